"""The 3D cylinder deck (region cylinder + create_atoms) against the library.

examples/uniaxial_cylinder/in.uniaxial_cylinder builds the laboratory
cylinder with LAMMPS's own region and lattice; it must hold the particles
of sph_add_cylinder / sph_add_plate / sph_add_piston
(sphsolid.scenes.uniaxial_cylinder), give the same state on 1 and 2 MPI
ranks, and advance like the library.  Coarse (6 mm: 2,073 particles).
Tolerances as in test_three_dimensions: positions to 1e-15 m, density to a
few ulps, stress to 64 ulps of rho times c0^2 (summation order differs
between LAMMPS's neighbour lists and the library's).
"""
from __future__ import annotations

import numpy as np

import textwrap

from conftest import REPOSITORY, read_probes, run_deck, sphsolid_lammps

DECK = REPOSITORY / "examples" / "uniaxial_cylinder" / "in.uniaxial_cylinder"


def lattice_order(x: np.ndarray, step: float) -> np.ndarray:
    cells = np.round(x / (0.25 * step)).astype(np.int64)
    return np.lexsort((cells[:, 0], cells[:, 1], cells[:, 2]))


def test_cylinder_deck_holds_the_library_cylinder_and_agrees_on_1_and_2_ranks(tmp_path, plugin):
    import sphsolid
    from sphsolid import scenes
    from sphsolid.calculators import CLibrary

    dx, steps = 0.006, 30
    runs = {}
    for ranks in (1, 2):
        work = tmp_path / f"np{ranks}"
        work.mkdir()
        run_deck(DECK, work, {"dx": dx, "steps": steps, "dump": 1, "every": 10}, plugin,
                 ranks=ranks)
        runs[ranks] = np.loadtxt(work / "cylinder_final.txt", skiprows=9)
    # the probe histories (A, B, C, D: 8 values each in 3D) agree to
    # round-off relative to each probe's peak
    a, b = (read_probes(tmp_path / f"np{r}" / "cylinder_probes.txt") for r in (1, 2))
    assert a.shape == b.shape == (steps // 10 + 1, 2 + 4 * 8)
    for p in range(4):
        cols = slice(2 + 8 * p, 10 + 8 * p)
        peak = np.abs(a[:, cols]).max()
        assert peak > 0.0
        assert np.abs(a[:, cols] - b[:, cols]).max() / peak < 1e-10
    # columns: id type x y z vx vy vz rho sigma xx yy zz xy xz yz; atom ids
    # depend on the decomposition (create_atoms numbers per rank): compare
    # particles by their lattice site
    one = runs[1][lattice_order(runs[1][:, 2:5], dx)]
    two = runs[2][lattice_order(runs[2][:, 2:5], dx)]
    one[:, 0] = two[:, 0] = 0
    np.testing.assert_array_equal(one[:, 1], two[:, 1])
    scale = np.abs(one).max(axis=0)
    scale[scale == 0.0] = 1.0
    assert (np.abs(one - two) / scale).max() < 1e-10

    scene = scenes.uniaxial_cylinder(dx)
    scene.calc = CLibrary(threads=1)
    counts = scene.body_counts()
    assert len(one) == len(scene)
    for kind, name in ((1, "specimen"), (2, "plate"), (3, "piston")):
        assert (one[:, 1] == kind).sum() == counts[name]
    dyn = sphsolid.ImprovedEuler(scene)
    dyn.run(steps=steps)
    x = scene.positions
    mine, theirs = np.arange(len(one)), lattice_order(x, dx)
    np.testing.assert_array_equal(one[mine, 1] - 1, scene.body_ids[theirs])
    np.testing.assert_allclose(one[mine, 2:5], x[theirs], rtol=0, atol=1e-15)
    np.testing.assert_allclose(one[mine, 8], scene.density[theirs], rtol=1e-14)
    stress = scene.stress[theirs]
    c0_squared_ulp = 12.2e9 / 2300.0 * np.spacing(2300.0)
    assert np.abs(stress).max() > 1.0e3          # the piston loaded the specimen
    assert np.abs(one[mine, 9:] - stress).max() < 64 * c0_squared_ulp


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


def test_cylinder_restart_continues_to_the_uninterrupted_result(tmp_path, plugin):
    """write_restart / read_restart in 3D: the six stress components and
    the density travel in the restart file (fix sphsolid/state)."""
    dx = 0.006
    dump = ("write_dump all custom {path} id x y z vx vy vz c_rho c_stress[*] "
            "modify sort id format float %.17g")
    lmp = sphsolid_lammps.open_lammps(
        ["-log", "none", "-screen", "none", "-nocite", "-var", "plugin", str(plugin),
         "-var", "dx", str(dx), "-var", "steps", "20", "-var", "probes",
         str(tmp_path / "p0.txt")], plugin=plugin)
    try:
        lmp.file(str(DECK))
        lmp.command(f"write_restart {tmp_path / 'state.restart'}")
        lmp.command("run 20")
        lmp.command(dump.format(path=tmp_path / "straight.txt"))
        dt = lmp.extract_global("dt")
    finally:
        lmp.close()
    lmp = sphsolid_lammps.open_lammps(plugin=plugin)
    try:
        for line in RESTARTED.format(restart=tmp_path / "state.restart", dx=dx,
                                     skin=0.3 * dx).splitlines():
            lmp.command(line)
        assert lmp.extract_global("ntimestep") == 20
        assert lmp.extract_global("dt") == dt
        lmp.command("run 20")
        lmp.command(dump.format(path=tmp_path / "restarted.txt"))
    finally:
        lmp.close()
    straight = np.loadtxt(tmp_path / "straight.txt", skiprows=9)
    restarted = np.loadtxt(tmp_path / "restarted.txt", skiprows=9)
    np.testing.assert_array_equal(straight[:, 0], restarted[:, 0])
    np.testing.assert_allclose(restarted[:, 1:4], straight[:, 1:4], rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(restarted[:, 7], straight[:, 7], rtol=1e-14, atol=0)
    for col in (4, 5, 6, 8, 9, 10, 11, 12, 13):
        scale = np.abs(straight[:, col]).max()
        assert scale > 0, col
        assert np.abs(restarted[:, col] - straight[:, col]).max() / scale < 1e-9, col
