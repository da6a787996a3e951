"""3D: the plugin's per-atom state travels with atoms, ghosts and restarts.

* A free 3D block drifting across the processor boundary at x = 0 while
  spinning: on 2 ranks its atoms cross from one rank to the other (exchange,
  ghost forward communication, re-neighbouring) and end in the state of the
  1-rank run, all six stress components and the density; a probe it sweeps
  past records the same history.  Rigid rotation leaves an unstressed body
  unstressed (the Jaumann rate is objective): the stress stays a small
  fraction of the stress a strain of v dt / dx would give.
* The 3D cylinder on 2 ranks: write_restart, then read_restart on 2 ranks
  and continue: the same atoms, state and probe histories as the
  uninterrupted 2-rank run.
"""
from __future__ import annotations

import textwrap

import numpy as np

from conftest import REPOSITORY, read_probes, run_deck, run_on_one_and_two_ranks

CYLINDER = REPOSITORY / "examples" / "uniaxial_cylinder" / "in.uniaxial_cylinder"

SPINNING_BLOCK_3D = textwrap.dedent("""\
    # A free 10 x 10 x 10 block of spacing 1 mm drifting at 60 m/s across
    # the processor boundary at x = 0 while spinning at 2000 rad/s about
    # its own axis (parallel to z).
    plugin load ${plugin}
    units si
    dimension 3
    boundary f f f
    atom_style atomic
    atom_modify map array
    comm_modify vel yes
    processors ${px} 1 1
    region box block -0.03 0.03 -0.02 0.02 -0.01 0.01 units box
    create_box 1 box
    lattice sc 0.001 origin 0.5 0.5 0.5
    region block block -0.012 -0.002 -0.005 0.005 -0.005 0.005 units box
    create_atoms 1 region block
    mass 1 $(2300.0*0.001^3)
    pair_style sphsolid 0.001 artificial_viscosity alpha 1.0 beta 0.0
    pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0
    neighbor 0.0003 bin
    neigh_modify every 1 delay 0 check yes
    variable vx atom 60.0-2000.0*y
    variable vy atom 2000.0*(x+0.007)
    velocity all set v_vx v_vy 0.0 units box
    fix integrate all sphsolid/improved_euler
    compute rho all sphsolid/density/atom
    compute stress all sphsolid/stress/atom
    compute P all sphsolid/probe 0.0 0.0 0.0 outside nan
    fix probes all ave/time 20 1 20 c_P[*] file probes.txt format " %.17g"
    thermo 100
    run 700
    write_dump all custom final.txt id x y z vx vy vz c_rho c_stress[*] &
        modify sort id format float %.17g
    """)


def test_3d_atoms_crossing_ranks_keep_their_state(tmp_path, plugin):
    work1, work2, builds = run_on_one_and_two_ranks(tmp_path, SPINNING_BLOCK_3D, {}, plugin)
    assert builds > 10  # atoms really moved across bins and ranks
    one, two = (np.loadtxt(w / "final.txt", skiprows=9) for w in (work1, work2))
    probes = {1: read_probes(work1 / "probes.txt"), 2: read_probes(work2 / "probes.txt")}
    assert one.shape == two.shape == (1000, 14)
    np.testing.assert_array_equal(one[:, 0], two[:, 0])
    # the block's centre drifted from x = -0.007 m across x = 0
    assert one[:, 1].mean() > 0.0
    scale = np.abs(one).max(axis=0)
    scale[scale == 0.0] = 1.0
    assert (np.abs(one - two) / scale).max() < 1e-10
    # a free body keeps its momentum (pair forces are equal and opposite):
    # mean velocity (60, 0, 0) m/s, as set
    velocity = one[:, 4:7].mean(axis=0)
    np.testing.assert_allclose(velocity, [60.0, 0.0, 0.0], rtol=0, atol=1e-9)
    # the probe at the origin: outside (NaN) before the block arrives,
    # inside it later, and the same history on both
    a, b = probes[1][:, 1:], probes[2][:, 1:]
    assert a.shape == b.shape
    np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
    assert np.isnan(a[0]).all() and not np.isnan(a[-1]).any()
    seen = np.nanmax(np.abs(a))
    assert seen > 0.0
    assert np.nanmax(np.abs(a - b)) < 1e-10 * seen


RESTART_STRAIGHT = textwrap.dedent("""\
    include {deck}
    write_restart state.restart
    run 20
    write_dump all custom straight.txt id type x y z vx vy vz c_rho c_stress[*] &
        modify sort id format float %.17g
    """)

RESTART_CONTINUED = textwrap.dedent("""\
    plugin load ${{plugin}}
    read_restart {restart}
    comm_modify vel yes
    pair_style sphsolid {dx} artificial_viscosity alpha 1.0 beta 0.0
    pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0
    neighbor {skin} bin
    neigh_modify every 1 delay 0 check yes
    fix integrate specimen sphsolid/improved_euler
    fix piston piston move linear 0.0 -0.0015 0.0 units box
    compute A all sphsolid/probe 0.0 $(0.5*0.135) 0.0
    compute B all sphsolid/probe $(0.25*0.054) $(0.75*0.135) 0.0
    compute C all sphsolid/probe $(0.25*0.054) $(0.5*0.135) 0.0
    compute D all sphsolid/probe 0.0 $(0.75*0.135) 0.0
    compute rho all sphsolid/density/atom
    compute stress all sphsolid/stress/atom
    variable time equal time
    fix probes all ave/time 10 1 10 v_time c_A[*] c_B[*] c_C[*] c_D[*] &
        file continued_probes.txt format " %.17g"
    run 20
    write_dump all custom restarted.txt id type x y z vx vy vz c_rho c_stress[*] &
        modify sort id format float %.17g
    """)


def test_3d_cylinder_restart_on_two_ranks_continues_to_the_uninterrupted_result(
        tmp_path, plugin):
    """write_restart on 2 ranks, read_restart on 2 ranks: per-atom density
    and all six stress components travel in the restart file with the atoms
    of each rank (fix sphsolid/state), and the run goes on unchanged."""
    dx = 0.006
    straight = tmp_path / "in.straight"
    straight.write_text(RESTART_STRAIGHT.format(deck=CYLINDER))
    run_deck(straight, tmp_path, {"dx": dx, "steps": 20, "every": 10,
                                  "probes": "straight_probes.txt"}, plugin, ranks=2)
    continued = tmp_path / "in.continued"
    continued.write_text(RESTART_CONTINUED.format(restart="state.restart", dx=dx,
                                                  skin=0.3 * dx))
    run_deck(continued, tmp_path, {}, plugin, ranks=2)
    a = np.loadtxt(tmp_path / "straight.txt", skiprows=9)
    b = np.loadtxt(tmp_path / "restarted.txt", skiprows=9)
    np.testing.assert_array_equal(a[:, :2], b[:, :2])
    assert len(a) == 1587 + 2 * 243  # specimen, plate, piston at 6 mm
    np.testing.assert_allclose(b[:, 2:5], a[:, 2:5], rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(b[:, 8], a[:, 8], rtol=1e-14, atol=0)
    for col in (5, 6, 7, 9, 10, 11, 12, 13, 14):
        scale = np.abs(a[:, col]).max()
        assert scale > 0, col
        assert np.abs(b[:, col] - a[:, col]).max() / scale < 1e-9, col
    # the probe samples after the restart (steps 30 and 40) are those of the
    # uninterrupted run
    p = read_probes(tmp_path / "straight_probes.txt")
    q = read_probes(tmp_path / "continued_probes.txt")
    later = p[p[:, 0] > 20]
    assert len(later) == 2 and len(q) >= 2
    q = q[np.isin(q[:, 0], later[:, 0])]
    np.testing.assert_array_equal(q[:, 0], later[:, 0])
    peak = np.abs(later[:, 2:]).max()
    assert peak > 0.0
    assert np.abs(q[:, 2:] - later[:, 2:]).max() < 1e-9 * peak
