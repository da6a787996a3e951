"""The damage effect through LAMMPS (pair sphsolid ... damage).

A small specimen (40 x 60 mm at dx = 2 mm) is compressed by a piston fast
enough that flaws activate and damage grows within a few hundred steps.
Its atoms' IDs are sorted by position (reset_atoms id sort yes), specimen
first, so that each atom's flaws (drawn from its ID) are the same on any
number of ranks and are those of the library's particle of index ID - 1.

* 1 and 2 MPI ranks give bitwise the same damage field (Improved Euler
  and the leapfrog);
* a run continued from a restart file gives bitwise the straight run's
  damage field (D and the flaws travel in the restart file);
* the library (the Python front end on the same particles) gives the
  same damage field, bitwise: D grows by a fixed amount per step once a
  flaw is active, so only the step at which a flaw activates could
  differ, and it does not; the other state agrees to round-off (the
  order of the sums differs);
* with the effect on but no flaw active the probe series is bitwise that
  of the effect off, and the effect off gives bitwise the series the
  plugin gave before the effect existed (tests/data/piston_probes_4mm.txt,
  written by the plugin of commit 441ff53) on the pair loop's baseline
  path (SPHSOLID_RATE_PATH=baseline) when dv/dt goes through f as it did
  then (a fix adding zero forces); with the pair's forces alone, and on
  the widest path the CPU has (which fuses multiplies and adds), the same
  series to 1e-12 and 1e-10 of each probe's largest value
  (docs/performance.md).
"""
from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

from conftest import ATOMS_2D, PISTON_DECK, read_probes, run_deck, run_on_one_and_two_ranks, sphsolid_lammps

DATA = Path(__file__).resolve().parents[1] / "data"

DX = 0.002
SPEED = 0.5           # piston speed [m/s]
WEIBULL_K = 1e30      # flaws [m^-3]: the first activate near 0.1 % strain
WEIBULL_M = 9.0
STEPS = 700

SETUP = textwrap.dedent("""\
    plugin load ${plugin}
""") + ATOMS_2D + textwrap.dedent("""\
    processors ${px} 1 1
    region box block -0.03 0.03 -0.01 0.075 -0.001 0.001 units box
    create_box 3 box
    lattice sq 0.002 origin 0.5 0.5 0.0
    region specimen block -0.02 0.02 0.0 0.06 -0.001 0.001 units box
    region plate block -0.02 0.02 -0.006 0.0 -0.001 0.001 units box
    region piston block -0.02 0.02 0.06 0.066 -0.001 0.001 units box
    create_atoms 1 region specimen
    mass * $(2300.0*0.002*0.002)
    reset_atoms id sort yes
    create_atoms 2 region plate
    create_atoms 3 region piston
    group specimen type 1
    group plate type 2
    group piston type 3
    velocity piston set 0.0 -{speed} 0.0 units box
    write_dump all custom initial.txt id type x y modify sort id format float %.17g
    """)

MODEL = textwrap.dedent("""\
    pair_style sphsolid 0.002 artificial_viscosity alpha 1.0 beta 0.0 damage seed 5
    pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0 weibull_k ${weibull_k} weibull_m {m}
    neighbor 0.0006 bin
    neigh_modify every 1 delay 0 check yes
    fix integrate specimen sphsolid/${fix}
    fix piston piston move linear 0.0 -{speed} 0.0 units box
    compute rho all sphsolid/density/atom
    compute stress all sphsolid/stress/atom
    thermo 100
    """)

DUMP = ("write_dump all custom {path} id type x y vx vy c_rho c_stress[*]{extra} "
        "modify sort id format float %.17g\n")

DAMAGE_OUT = " c_D c_flaws c_strain c_active c_F"
DAMAGE_COMPUTES = textwrap.dedent("""\
    compute D all sphsolid/atom damage
    compute flaws all sphsolid/atom flaws
    compute strain all sphsolid/atom flaw_strain
    compute active all sphsolid/atom active_flaws
    compute F specimen sphsolid/atom fragment
    """)


def fill(text: str) -> str:
    """The test's constants into a deck text ({speed}, {m})."""
    return text.replace("{speed}", repr(SPEED)).replace("{m}", repr(WEIBULL_M))


def deck(steps: int = STEPS, restart_at: int | None = None) -> str:
    text = fill(SETUP + MODEL) + DAMAGE_COMPUTES
    if restart_at is None:
        text += f"run {steps}\n"
    else:
        text += f"run {restart_at}\nwrite_restart state.restart\nrun {steps - restart_at}\n"
    return text + DUMP.format(path="final.txt", extra=DAMAGE_OUT)


VARIABLES = {"weibull_k": WEIBULL_K, "fix": "improved_euler"}


def final(path: Path) -> np.ndarray:
    """Rows by atom ID: id type x y vx vy rho sxx syy szz sxy [D flaws strain active
    fragment]."""
    return np.loadtxt(path, skiprows=9)


def specimen(rows: np.ndarray) -> np.ndarray:
    return rows[rows[:, 1] == 1]


def check_damaged(rows: np.ndarray) -> None:
    """A field worth comparing: tens of specimen atoms damaged, tens whole;
    the platens have no flaws and stay whole."""
    spec = specimen(rows)
    damaged = (spec[:, 11] > 0).sum()
    assert 20 < damaged < len(spec) - 20, damaged
    assert (spec[:, 12] >= 1).all()              # every specimen atom has flaws
    platens = rows[rows[:, 1] != 1]
    assert (platens[:, 11] == 0).all() and (platens[:, 12] == 0).all()
    assert np.isinf(platens[:, 13]).all()
    # fragments: the least ID of each, -1 at D = 1, 0 outside the group
    assert (platens[:, 15] == 0).all()
    assert ((spec[:, 15] == -1) == (spec[:, 11] == 1)).all()
    assert (spec[spec[:, 15] > 0, 15] <= spec[spec[:, 15] > 0, 0]).all()


@pytest.mark.parametrize("fix", ["improved_euler", "leapfrog"])
def test_two_ranks_give_bitwise_the_damage_field_of_one(tmp_path, plugin, fix):
    one, two, builds = run_on_one_and_two_ranks(tmp_path, deck(), dict(VARIABLES, fix=fix),
                                                plugin)
    a, b = final(one / "final.txt"), final(two / "final.txt")
    assert "1 by 1 by 1" in (one / "log.lammps").read_text()
    assert "2 by 1 by 1" in (two / "log.lammps").read_text()
    check_damaged(a)
    # the specimen's IDs are the same atoms on 1 and 2 ranks (sorted by
    # position); the platens' IDs follow the creation order of each rank
    sa, sb = specimen(a), specimen(b)
    np.testing.assert_allclose(sb[:, 2:4], sa[:, 2:4], rtol=0, atol=1e-15)
    # D, flaw count, weakest strain, active flaws, fragments: bitwise
    np.testing.assert_array_equal(sa[:, 11:16], sb[:, 11:16])
    # the rest of the state to round-off (sums over ranks in another order)
    for col in range(4, 11):
        scale = np.abs(sa[:, col]).max()
        assert np.abs(sa[:, col] - sb[:, col]).max() <= 1e-9 * scale, col


RESTARTED = textwrap.dedent("""\
    plugin load ${plugin}
    read_restart state.restart
    comm_modify vel yes
    """) + fill(MODEL) + DAMAGE_COMPUTES


def test_restart_gives_bitwise_the_straight_damage_field(tmp_path, plugin):
    # damage starts before the restart (step 400) and grows after it
    straight, restarted = tmp_path / "straight", tmp_path / "restarted"
    straight.mkdir()
    restarted.mkdir()
    (straight / "in.deck").write_text(deck(restart_at=400))
    variables = dict(VARIABLES, px=1)
    run_deck(straight / "in.deck", straight, variables, plugin)
    (restarted / "in.deck").write_text(
        RESTARTED + f"run {STEPS - 400}\n" + DUMP.format(path="final.txt", extra=DAMAGE_OUT))
    (restarted / "state.restart").write_bytes((straight / "state.restart").read_bytes())
    run_deck(restarted / "in.deck", restarted, variables, plugin)
    a, b = final(straight / "final.txt"), final(restarted / "final.txt")
    check_damaged(a)
    np.testing.assert_array_equal(a[:, :2], b[:, :2])
    np.testing.assert_array_equal(a[:, 11:16], b[:, 11:16])
    for col in range(2, 11):
        scale = np.abs(a[:, col]).max()
        assert np.abs(a[:, col] - b[:, col]).max() <= 1e-9 * scale, col
    # and the damage at the restart was not zero: D came through the file
    log = (straight / "log.lammps").read_text()
    assert "write_restart" in log


def test_restart_file_carries_the_damage(tmp_path, plugin):
    # read back without running: the computes see the file's D and flaws
    (tmp_path / "in.deck").write_text(deck(restart_at=STEPS))
    run_deck(tmp_path / "in.deck", tmp_path, dict(VARIABLES, px=1), plugin)
    lmp = sphsolid_lammps.open_lammps(plugin=plugin)
    try:
        lmp.command(f"read_restart {tmp_path / 'state.restart'}")
        lmp.command("comm_modify vel yes")
        for line in fill(MODEL).replace("${weibull_k}", repr(WEIBULL_K)).replace(
                "${fix}", "improved_euler").splitlines():
            lmp.command(line)
        lmp.commands_string(DAMAGE_COMPUTES)
        lmp.command("run 0")
        lmp.command(DUMP.format(path=tmp_path / "read.txt", extra=DAMAGE_OUT).strip())
    finally:
        lmp.close()
    a, b = final(tmp_path / "final.txt"), final(tmp_path / "read.txt")
    check_damaged(b)
    np.testing.assert_array_equal(a[:, 11:14], b[:, 11:14])


def library_run(initial: np.ndarray, steps: int, dt: float, integrator: str = "improved_euler",
                extra: dict | None = None, scene_out: list | None = None):
    """The same particles in the library (Python front end): specimen in ID
    order (library index = ID - 1), fixed plate, piston at SPEED; `extra`
    effects on top, the scene appended to `scene_out`."""
    from sphsolid import Scene
    from sphsolid.build import Velocity, particles
    from sphsolid.dynamics import dynamics_for
    from sphsolid.material import Material

    rock = Material(K=12.2e9, mu=2.67e9, rho0=2300.0, weibull_k=WEIBULL_K,
                    weibull_m=WEIBULL_M)
    spec = initial[initial[:, 1] == 1]
    assert (spec[:, 0] == np.arange(1, len(spec) + 1)).all()
    scene = Scene(2, [particles(spec[:, 2:4], DX, rock, name="specimen")],
                  effects={"damage": {"seed": 5},
                           "artificial_viscosity": {"alpha": 1.0, "beta": 0.0},
                           **(extra or {})})
    scene.add(particles(initial[initial[:, 1] == 2][:, 2:4], DX, rock, name="plate",
                        motion="fixed"))
    scene.add(particles(initial[initial[:, 1] == 3][:, 2:4], DX, rock, name="piston",
                        motion=Velocity((0.0, -SPEED))))
    dyn = dynamics_for(integrator)(scene, progress=False)
    assert dyn.dt == dt
    # the deck's mass, (rho0 dx) dx, not the library's rho0 (dx dx): they
    # differ in the last bit, and so would the flaws (k m / rho0)
    scene.masses[:] = 2300.0 * DX * DX
    dyn.run(steps=steps)
    if scene_out is not None:
        scene_out.append(scene)
    n = len(spec)
    return (scene.damage[:n].copy(), scene.positions[:n].copy(), scene.flaws[:n].copy(),
            scene.flaw_strain[:n].copy(), scene.fragments[:n].copy())


@pytest.mark.parametrize("fix", ["improved_euler", "leapfrog"])
def test_library_gives_the_same_damage_field(tmp_path, plugin, fix):
    # with the leapfrog, a step in which D grew evaluates both passes again
    # at its end state (the library's leapfrog then carries no rates)
    (tmp_path / "in.deck").write_text(deck() + 'print "dt $(dt:%.17g)"\n')
    run_deck(tmp_path / "in.deck", tmp_path, dict(VARIABLES, px=1, fix=fix), plugin)
    dt = float((tmp_path / "log.lammps").read_text().split("\ndt ")[1].split()[0])
    initial = np.loadtxt(tmp_path / "initial.txt", skiprows=9)
    rows = final(tmp_path / "final.txt")
    check_damaged(rows)
    D, x, flaws, strain, fragment = library_run(initial, STEPS, dt, fix)
    spec = specimen(rows)
    # the library numbers fragments 0, 1, ... in the order of their first
    # particle; the plugin gives each the least ID of its atoms
    first = {f: i for i, f in reversed(list(enumerate(fragment))) if f >= 0}
    np.testing.assert_array_equal(
        spec[:, 15], [first[f] + 1 if f >= 0 else -1 for f in fragment])
    np.testing.assert_array_equal(spec[:, 12], flaws)
    np.testing.assert_array_equal(spec[:, 13], strain)
    np.testing.assert_array_equal(spec[:, 11], D)
    np.testing.assert_allclose(spec[:, 2:4], x, rtol=0, atol=1e-12)


COHESION, FRICTION = 2e6, 30.0     # a cone the compressed specimen reaches


@pytest.mark.parametrize("fix", ["improved_euler", "leapfrog"])
def test_drucker_prager_returns_the_stress_as_the_library_does(tmp_path, plugin, fix):
    """pair_style ... drucker_prager: the plugin returns the deviators of
    the atoms its integrator moves onto the cone after each step, as the
    library does: the same damage field and positions to round-off, with
    tens of specimen particles on the cone (sqrt(J2) of the damaged stress
    = A + B P_d) and the platens' stress not limited."""
    dp = f"drucker_prager cohesion {COHESION!r} friction_angle {FRICTION!r}"
    text = deck().replace("damage seed 5", "damage seed 5 " + dp)
    (tmp_path / "in.deck").write_text(text + 'print "dt $(dt:%.17g)"\n')
    run_deck(tmp_path / "in.deck", tmp_path, dict(VARIABLES, px=1, fix=fix), plugin)
    dt = float((tmp_path / "log.lammps").read_text().split("\ndt ")[1].split()[0])
    initial = np.loadtxt(tmp_path / "initial.txt", skiprows=9)
    spec = specimen(final(tmp_path / "final.txt"))
    scenes = []
    D, x, *_ = library_run(initial, STEPS, dt, fix,
                           {"drucker_prager": {"cohesion": COHESION,
                                               "friction_angle": FRICTION}}, scenes)
    scene = scenes[0]
    n = len(spec)
    phi = np.radians(FRICTION)
    A = 6 * COHESION * np.cos(phi) / (np.sqrt(3) * (3 - np.sin(phi)))
    B = 6 * np.sin(phi) / (np.sqrt(3) * (3 - np.sin(phi)))
    S = scene.deviatoric_stress
    j2 = np.sqrt(0.5 * (S[:, 0] ** 2 + S[:, 1] ** 2 + S[:, 2] ** 2 + 2 * S[:, 3] ** 2))
    P = scene.pressure
    Dall = scene.damage
    Pd = np.where(P < 0, (1 - Dall) * P, P)
    on_cone = np.abs((1 - Dall) * j2 - (A + B * Pd)) < 1e-9 * A
    assert 20 < on_cone[:n].sum() < n
    assert not on_cone[n:].any()          # the platens are not limited
    assert ((1 - Dall[:n]) * j2[:n] <= (A + B * Pd[:n]) * (1 + 1e-9) + 1e-9 * A).all()
    np.testing.assert_array_equal(spec[:, 11], D)
    np.testing.assert_allclose(spec[:, 2:4], x, rtol=0, atol=1e-12)


def probe_series(tmp_path: Path, plugin, name: str, pair_extra: str,
                 zero_force: bool = False) -> np.ndarray:
    """The piston deck at dx = 4 mm, 40 steps, probes every 4 steps
    (zero_force: with a fix adding zero forces, so that the integrating fix
    takes dv/dt = f/m of every force, not the pair's own)."""
    work = tmp_path / name
    work.mkdir()
    text = PISTON_DECK.read_text()
    if zero_force:
        text = text.replace("run             ${steps}",
                            "fix zero all addforce 0.0 0.0 0.0\nrun             ${steps}")
        assert "addforce" in text
    if pair_extra:
        text = text.replace("pair_coeff      * * K 12.2e9 mu 2.67e9 rho0 2300.0",
                            "pair_coeff      * * K 12.2e9 mu 2.67e9 rho0 2300.0 "
                            "weibull_k 1e-30 weibull_m 9")
        text = text.replace("artificial_viscosity alpha ${alpha} beta 0.0",
                            "artificial_viscosity alpha ${alpha} beta 0.0 " + pair_extra)
        assert pair_extra in text and "weibull_k" in text
    deck_path = work / "in.deck"
    deck_path.write_text(text)
    dt = 0.5 * 1.2 * 0.004 / np.sqrt(12.2e9 / 2300.0)
    run_deck(deck_path, work, {"dx": 0.004, "t_end": 40.2 * dt, "every": 4,
                               "probes": "p.txt"}, plugin)
    return read_probes(work / "p.txt")


def test_damage_off_leaves_the_series_bitwise(tmp_path, plugin, monkeypatch):
    # the reference rounds as every path did before the wide ones fused
    # multiplies and adds: the baseline path still does
    monkeypatch.setenv("SPHSOLID_RATE_PATH", "baseline")
    # the reference's plugin took dv/dt = f/m, as the integrating fix still
    # does when another fix adds forces (zero ones here)
    through_f = probe_series(tmp_path, plugin, "through_f", "", zero_force=True)
    reference = np.loadtxt(DATA / "piston_probes_4mm.txt", comments="#", ndmin=2)
    assert through_f.shape == reference.shape == (11, 20)
    np.testing.assert_array_equal(through_f, reference)
    # with pair sphsolid's forces alone it takes the pair's dv/dt, which
    # (m dv/dt) / m gives back to within one rounding: the same series to
    # round-off, each probe to 1e-12 of its largest value
    off = probe_series(tmp_path, plugin, "off", "")
    np.testing.assert_array_equal(off[:, :2], reference[:, :2])
    assert not np.array_equal(off, reference)    # the two paths were taken
    for probe in range(3):
        cols = slice(2 + 6 * probe, 8 + 6 * probe)
        scale = np.abs(reference[:, cols]).max()
        np.testing.assert_allclose(off[:, cols], reference[:, cols], rtol=0, atol=1e-12 * scale)
    # on, with flaws too rare to activate: the same series, bitwise
    on = probe_series(tmp_path, plugin, "on", "damage seed 3")
    np.testing.assert_array_equal(on, off)
    # the widest path: the same series, each probe (von Mises, pressure,
    # stresses: 6 columns) to 1e-10 of its largest value
    monkeypatch.delenv("SPHSOLID_RATE_PATH")
    wide = probe_series(tmp_path, plugin, "wide", "")
    np.testing.assert_array_equal(wide[:, :2], reference[:, :2])
    for probe in range(3):
        cols = slice(2 + 6 * probe, 8 + 6 * probe)
        scale = np.abs(reference[:, cols]).max()
        np.testing.assert_allclose(wide[:, cols], reference[:, cols], rtol=0,
                                   atol=1e-10 * scale)
