"""MPI ranks and restarts do not change the result.

* mpirun -np 2 against one rank: the piston deck's probe histories, and a
  spinning, drifting block whose atoms cross from one rank to the other
  many times (exchange, ghost forward communication, re-neighbouring).
* write_restart / read_restart: a run continued from a restart file ends
  where the uninterrupted run ends.
"""
from __future__ import annotations

import re
import sys
import textwrap

import numpy as np
import pytest

from conftest import (ATOMS_2D, PISTON_DECK, REPOSITORY, read_probes, run_deck, run_on_one_and_two_ranks,
                      sphsolid_lammps)


@pytest.mark.parametrize("load,tolerance", [({}, 1e-12),
                                            ({"speed": 0.0, "pressure": 1.0e6}, 1e-10),
                                            ({"integrator": "leapfrog"}, 1e-12)],
                         ids=["moving_piston", "pressure_piston", "leapfrog"])
def test_two_ranks_reproduce_serial_probe_histories(tmp_path, plugin, load, tolerance):
    # The pressure piston's acceleration is a sum over its ~130 atoms added
    # over the ranks in another order: a round-off difference in the
    # piston's velocity that the 1 MPa load carries into every later state
    # (measured 2.4e-12 of the peak); a missing rank's share would be ~50 %.
    variables = {"dx": 0.002, "t_end": 1.0e-4, "every": 10, **load}
    serial, parallel = tmp_path / "serial", tmp_path / "parallel"
    serial.mkdir()
    parallel.mkdir()
    run_deck(PISTON_DECK, serial, dict(variables, probes="p.txt"), plugin, ranks=1)
    run_deck(PISTON_DECK, parallel, dict(variables, probes="p.txt"), plugin, ranks=2)
    log = (parallel / "log.lammps").read_text()
    assert "2 by 1 by 1 MPI processor grid" in log or "1 by 2 by 1 MPI processor grid" in log
    a, b = read_probes(serial / "p.txt"), read_probes(parallel / "p.txt")
    # (the leapfrog's default step is twice Improved Euler's)
    assert a.shape == b.shape and len(a) == (10 if load.get("integrator") == "leapfrog" else 20)
    # Only the order of sums differs between 1 and 2 ranks (force sums over
    # neighbours, probe sums added over the ranks), so the histories agree
    # to round-off relative to each probe's peak over its six values (a
    # column that is zero by symmetry, sigma_xy on the axis, carries only
    # round-off of that peak).  A missing ghost or stale state shows at 1e-3.
    for p in range(3):
        cols = slice(2 + 6 * p, 8 + 6 * p)
        peak = np.abs(a[:, cols]).max()
        assert peak > 0.0
        assert np.abs(a[:, cols] - b[:, cols]).max() / peak < tolerance


PAIRS_LINE = re.compile(r"pair sphsolid: (\d+) pairs computed, per rank (\S+) ave (\d+) max "
                        r"(\d+) min .*; (\d+) of them with a ghost atom")


def test_pairs_with_ghosts_follow_the_newton_setting(tmp_path, plugin):
    # A pair of an owned and a ghost atom is listed on both ranks (a half
    # list built with newton off).  With newton off each rank computes it
    # and adds only its own atom's terms; with newton on one rank computes
    # it (a hash of the two IDs picks which) and the ghost's sums are sent
    # back (reverse communication).  A pair of owned atoms is computed
    # once.  So the pairs of the 2-rank run, counting a pair with a ghost as
    # half with newton off and as one with newton on, are exactly the
    # serial run's (a pair with a ghost dropped on one side, kept on both
    # with newton on, or a pair of owned atoms listed twice, changes the
    # count); the two halves of the piston deck have the same work; and the
    # probe histories equal one rank's to round-off (a ghost's terms added
    # to its copy and not sent back, a stale ghost or sums sent back twice
    # show at the 1e-3 level).
    variables = {"dx": 0.002, "t_end": 5.0e-5, "every": 10, "probes": "p.txt"}
    runs, pairs = {}, {}
    for name, newton, ranks in [("serial", "on", 1), ("on", "on", 2), ("off", "off", 2)]:
        work = tmp_path / name
        work.mkdir()
        run_deck(PISTON_DECK, work, dict(variables, newton=newton), plugin, ranks=ranks)
        log = (work / "log.lammps").read_text()
        assert "attributes: half, newton off" in log
        assert f"newton          {newton}" in log
        total, average, largest, least, ghosts = PAIRS_LINE.search(log).groups()
        pairs[name] = (int(total), float(average), int(largest), int(least), int(ghosts))
        runs[name] = read_probes(work / "p.txt")
    serial_total, _, _, _, serial_ghosts = pairs["serial"]
    assert serial_total > 30000 and serial_ghosts == 0
    for name in ("on", "off"):
        total, average, largest, least, ghosts = pairs[name]
        assert ghosts > 0, name
        if name == "off":
            assert ghosts % 2 == 0 and total - ghosts // 2 == serial_total, name
        else:
            assert total == serial_total, name
        assert largest + least == total and largest / average < 1.002, name
    # both ranks list the same pairs across the cut: newton on computes half
    assert abs(2 * pairs["on"][4] - pairs["off"][4]) < 0.05 * pairs["off"][4]
    a = runs["serial"]
    assert len(a) == 10
    for name in ("on", "off"):
        b = runs[name]
        for p in range(3):
            cols = slice(2 + 6 * p, 8 + 6 * p)
            peak = np.abs(a[:, cols]).max()
            assert peak > 0.0
            assert np.abs(a[:, cols] - b[:, cols]).max() / peak < 1e-12, name


@pytest.mark.parametrize("integrator,ranks", [("improved_euler", 1), ("leapfrog", 2)])
def test_end_of_run_line_says_where_the_plugin_spends_its_time(tmp_path, plugin, integrator,
                                                                ranks):
    # bench/bench_lammps.py reads pair sphsolid's timers from this line (its
    # PLUGIN_PARTS) to split LAMMPS's Pair and Modify sections between the
    # library's work, the ghost exchanges and the plugin's own copies.
    # Every step of either integrator calls the library's pair pass and its
    # stages and copies f/m before a stage, so those parts took some time;
    # none is negative.
    sys.path.insert(0, str(REPOSITORY / "bench"))
    import bench_lammps
    variables = {"dx": 0.002, "t_end": 5.0e-5, "every": 10, "probes": "p.txt",
                 "integrator": integrator}
    run_deck(PISTON_DECK, tmp_path, variables, plugin, ranks=ranks)
    found = bench_lammps.PLUGIN_PARTS.search((tmp_path / "log.lammps").read_text())
    assert found, "no end-of-run line of pair sphsolid's timers"
    parts = dict(zip(bench_lammps.PART_NAMES, map(float, found.groups())))
    assert min(parts.values()) >= 0.0, parts
    assert parts["rates"] > 0.0 and parts["stages"] > 0.0 and parts["copies"] > 0.0, parts


SPINNING_BLOCK = textwrap.dedent("""\
    # A free 24 x 24 block of spacing 1 mm drifting at 60 m/s across the
    # processor boundary at x = 0 while spinning at 2000 rad/s.
    plugin load ${plugin}
""") + ATOMS_2D + textwrap.dedent("""\
    processors ${px} 1 1
    region box block -0.04 0.04 -0.03 0.03 -0.001 0.001 units box
    create_box 1 box
    lattice sq 0.001 origin 0.5 0.5 0.0
    region block block -0.032 -0.008 -0.012 0.012 -0.001 0.001 units box
    create_atoms 1 region block
    mass 1 $(2300.0*0.001*0.001)
    pair_style sphsolid 0.001 artificial_viscosity alpha 1.0 beta 0.0
    pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0
    neighbor 0.0003 bin
    neigh_modify every 1 delay 0 check yes
    variable vx atom 60.0-2000.0*y
    variable vy atom 2000.0*(x+0.02)
    velocity all set v_vx v_vy 0.0 units box
    fix integrate all sphsolid/${fix}
    compute rho all sphsolid/density/atom
    compute stress all sphsolid/stress/atom
    thermo 100
    run 600
    write_dump all custom final.txt id x y vx vy c_rho c_stress[*] &
        modify sort id format float %.17g
    """)


def final_state(path):
    return np.loadtxt(path, skiprows=9)


@pytest.mark.parametrize("fix", ["improved_euler", "leapfrog"])
def test_atoms_crossing_ranks_keep_their_state(tmp_path, plugin, fix):
    # With the leapfrog the half step's density and stress rates, which
    # predict the next half step, travel with the atoms too (a lost or
    # misplaced one shows at 1e-6 and above).
    work1, work2, builds = run_on_one_and_two_ranks(tmp_path, SPINNING_BLOCK, {"fix": fix}, plugin)
    assert builds > 10  # atoms really moved across bins and ranks
    one, two = final_state(work1 / "final.txt"), final_state(work2 / "final.txt")
    assert one.shape == two.shape == (576, 10)
    np.testing.assert_array_equal(one[:, 0], two[:, 0])
    # the block crossed x = 0: it started at x < -0.008 m, drifted 0.02 m
    assert one[:, 1].max() > 0.0
    scale = np.abs(one).max(axis=0)
    assert (np.abs(one - two) / scale).max() < 1e-10


RESTARTED = textwrap.dedent("""\
    read_restart {restart}
    comm_modify vel yes
    pair_style sphsolid {dx} artificial_viscosity alpha 1.0 beta 0.0
    pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0
    neighbor {skin} bin
    neigh_modify every 1 delay 0 check yes
    fix integrate specimen sphsolid/improved_euler
    fix piston piston move linear 0.0 -0.0015 0.0 units box
    compute rho all sphsolid/density/atom
    compute stress all sphsolid/stress/atom
    """)


def test_restart_continues_to_the_uninterrupted_result(tmp_path, plugin):
    dx = 0.002
    dump = ("write_dump all custom {path} id x y vx vy c_rho c_stress[*] "
            "modify sort id format float %.17g")
    # uninterrupted: 100 steps, write_restart, 100 more
    lmp = sphsolid_lammps.open_lammps(
        ["-log", "none", "-screen", "none", "-nocite", "-var", "plugin", str(plugin),
         "-var", "dx", str(dx), "-var", "t_end", "0.0", "-var", "probes",
         str(tmp_path / "p0.txt")], plugin=plugin)
    try:
        lmp.file(str(PISTON_DECK))
        lmp.command("compute rho all sphsolid/density/atom")
        lmp.command("compute stress all sphsolid/stress/atom")
        lmp.command("run 100")
        lmp.command(f"write_restart {tmp_path / 'state.restart'}")
        lmp.command("run 100")
        lmp.command(dump.format(path=tmp_path / "straight.txt"))
        dt = lmp.extract_global("dt")
    finally:
        lmp.close()

    lmp = sphsolid_lammps.open_lammps(plugin=plugin)
    try:
        for line in RESTARTED.format(restart=tmp_path / "state.restart", dx=dx,
                                     skin=0.3 * dx).splitlines():
            lmp.command(line)
        assert lmp.extract_global("ntimestep") == 100
        assert lmp.extract_global("dt") == dt
        lmp.command("run 100")
        lmp.command(dump.format(path=tmp_path / "restarted.txt"))
    finally:
        lmp.close()

    straight = final_state(tmp_path / "straight.txt")
    restarted = final_state(tmp_path / "restarted.txt")
    np.testing.assert_array_equal(straight[:, 0], restarted[:, 0])
    # positions and densities to round-off of their own size; velocities and
    # stresses relative to their largest value in the scene
    np.testing.assert_allclose(restarted[:, 1:3], straight[:, 1:3], rtol=1e-14, atol=0)
    np.testing.assert_allclose(restarted[:, 5], straight[:, 5], rtol=1e-14, atol=0)
    for col in (3, 4, 6, 7, 8, 9):
        scale = np.abs(straight[:, col]).max()
        assert scale > 0
        assert np.abs(restarted[:, col] - straight[:, col]).max() / scale < 1e-9, col
