"""The plugin's decks against the standalone library on the same scene.

Both sides run the paper's scene (Das & Cleary) with the same physics
(the same libsphsolid code) and the same time step; they differ only in who
owns the particles: LAMMPS (its lattice, neighbour lists, fix move, fix
gravity, ghost atoms) or the library (its blocks, cell lists, motions).
Summation order differs, so agreement is to round-off, not bit for bit.

Tolerance 1e-9 of the probe's largest value over the run: the pressure is
c0^2 (rho - rho0) with rho ~ 2300 kg/m^3 held in double precision, so one
unit in the last place of rho (4.5e-13 kg/m^3) is c0^2 * 4.5e-13 = 2.4e-6 Pa,
about 2e-10 of the few-kPa probe values of these short runs.  A few ulps of
density differing between two summation orders is the floor; a physics or
data-movement error (a missing ghost, a stale rate, a wrong stage) shows up
at 1e-3 or more.
"""
from __future__ import annotations

import numpy as np
import pytest

from conftest import GRAVITY_DECK, PISTON_DECK, read_probes, run_deck
from library_reference import PaperRun

TOLERANCE = 1e-9


def compare(lammps_rows: np.ndarray, library_rows: np.ndarray) -> list[float]:
    """Largest difference of each probe's 6 values relative to its peak."""
    assert lammps_rows.shape == library_rows.shape
    np.testing.assert_array_equal(lammps_rows[:, 0], library_rows[:, 0])  # same steps
    errors = []
    for p in range(3):
        cols = slice(2 + 6 * p, 8 + 6 * p)
        peak = np.abs(library_rows[:, cols]).max()
        assert peak > 0.0
        errors.append(np.abs(lammps_rows[:, cols] - library_rows[:, cols]).max() / peak)
    return errors


@pytest.mark.parametrize("fix, integrator", [("improved_euler", "improved_euler"),
                                             ("leapfrog", "leapfrog")])
def test_piston_deck_probes_match_standalone_library(tmp_path, plugin, library, fix,
                                                     integrator):
    """fix sphsolid/improved_euler or fix sphsolid/leapfrog (with fix move's piston)
    against the library's integrator of the same name."""
    dx, steps, every = 0.002, 200, 10
    reference = PaperRun(library, dx, effects={"artificial_viscosity": "alpha=1 beta=0"},
                         integrator=integrator)
    try:
        expected = reference.history(steps, every)
        dt = reference.dt
    finally:
        reference.close()
    # t_end lands on step `steps` (the deck rounds t_end/dt)
    run_deck(PISTON_DECK, tmp_path, {"dx": dx, "t_end": steps * dt, "every": every,
                                     "probes": "probes.txt", "integrator": fix}, plugin)
    got = read_probes(tmp_path / "probes.txt")
    np.testing.assert_allclose(got[:, 1], expected[:, 1], rtol=1e-12)  # same dt
    errors = compare(got, expected)
    assert max(errors) < TOLERANCE, errors


def test_pressure_piston_deck_matches_library_force_motion(tmp_path, plugin, library):
    # fix sphsolid/force against the library's SPH_MOTION_FORCE: the piston
    # starts at rest under 1 MPa on its face and accelerates into the
    # specimen; its atoms share one acceleration summed over the group.
    dx, steps, every, pressure = 0.002, 200, 10, 1.0e6
    reference = PaperRun(library, dx, speed=0.0, pressure=pressure,
                         effects={"artificial_viscosity": "alpha=1 beta=0"})
    try:
        expected = reference.history(steps, every)
        piston = reference.body_field("velocity", reference.scene.piston)
        dt = reference.dt
    finally:
        reference.close()
    deck = tmp_path / "in.deck"
    deck.write_text(PISTON_DECK.read_text() + PISTON_VELOCITY_DUMP)
    run_deck(deck, tmp_path, {"dx": dx, "t_end": steps * dt, "every": every, "speed": 0.0,
                              "pressure": pressure, "probes": "probes.txt"}, plugin)
    got = read_probes(tmp_path / "probes.txt")
    errors = compare(got, expected)
    assert max(errors) < TOLERANCE, errors
    # one rigid velocity for the whole piston, the library's
    vy = np.loadtxt(tmp_path / "piston_v.txt")
    assert np.ptp(vy) == 0.0
    assert np.ptp(piston[:, 1]) == 0.0
    assert vy[0] == pytest.approx(piston[0, 1], rel=1e-9)
    assert vy[0] < 0.0


# after the deck's run: the piston atoms' vy, one per line
PISTON_VELOCITY_DUMP = """
variable        pvy atom vy
write_dump      piston custom piston_v.txt v_pvy modify header no format float %.17g
"""


def test_gravity_deck_probes_match_standalone_library(tmp_path, plugin, library):
    dx, steps, every = 0.002, 200, 20
    reference = PaperRun(library, dx, gravity_only=True,
                         effects={"artificial_viscosity": "alpha=1 beta=0"})
    try:
        expected = reference.history(steps, every)
        dt = reference.dt
    finally:
        reference.close()
    run_deck(GRAVITY_DECK, tmp_path, {"dx": dx, "t_end": steps * dt, "every": every,
                                      "probes": "probes.txt"}, plugin)
    got = read_probes(tmp_path / "probes.txt")
    errors = compare(got, expected)
    assert max(errors) < TOLERANCE, errors


def test_paper_deck_has_12040_specimen_particles_and_paper_time_step(tmp_path, plugin):
    # 86 mm x 140 mm at dx = 1 mm: round(86) x round(140) lattice centres
    run_deck(PISTON_DECK, tmp_path, {"dx": 0.001, "t_end": 0.0}, plugin)
    log = (tmp_path / "log.lammps").read_text()
    count = next(line for line in log.splitlines() if line.startswith("specimen particles:"))
    assert int(count.split(":")[1]) == 86 * 140
    # dt = 0.5 h / c0 with h = 1.2 dx, c0 = sqrt(K / rho0): the paper's 0.261 us
    expected_dt = 0.5 * 1.2e-3 / np.sqrt(12.2e9 / 2300.0)
    line = next(line for line in log.splitlines() if line.startswith("time step:"))
    dt = float(line.split(":")[1].split()[0])
    assert dt == pytest.approx(expected_dt, rel=1e-12)
    assert round(dt * 1e6, 3) == 0.261
