"""The damage effect from Python: material keys, fields, files, restarts,
and the fracture scenes (docs/fracture.md)."""
import json

import numpy as np
import pytest

from sphsolid import Material, Scene, Trajectory
from sphsolid.build import rectangle
from sphsolid.dynamics import ImprovedEuler

ROCK = dict(K=12.2e9, mu=2.67e9, rho0=2300.0)


def tension_block(seed=11, k=1e22):
    """A free 2D block released from a uniform tension eps = 2e-3: about
    half its particles' weakest flaws lie below that strain."""
    rock = Material(**ROCK, weibull_k=k, weibull_m=6.0)
    block = rectangle((-0.02, 0.02), (-0.02, 0.02), 1e-3, rock, "block")
    scene = Scene(2, [block], effects={"damage": {"seed": seed},
                                       "artificial_viscosity": {}})
    scene.freeze()
    # P = c0^2 (rho - rho0) = -3 K eps
    scene.density[:] = 2300.0 * (1.0 - 3.0 * 2e-3)
    return scene


def test_weibull_keys_reach_the_library_and_bad_ones_are_named():
    rock = Material(**ROCK, weibull_k=1e20, weibull_m=6.0)
    assert (rock.weibull_k, rock.weibull_m) == (1e20, 6.0)
    with pytest.raises(ValueError, match="weibull_k"):
        Material(**ROCK, weibull_k=-1.0)
    with pytest.raises(ValueError, match="weibull_m"):
        Material(**ROCK, weibull_m=float("nan"))


def test_damage_fields_exist_only_with_the_effect():
    block = rectangle((0, 0.01), (0, 0.01), 1e-3, Material(**ROCK), "block")
    scene = Scene(2, [block])
    with pytest.raises(RuntimeError, match="effect damage is on"):
        _ = scene.damage


def test_damage_grows_and_is_written_to_hdf5_and_xdmf(tmp_path):
    scene = tension_block()
    dyn = ImprovedEuler(scene)
    with Trajectory(tmp_path / "t.h5", "w", scene) as traj:
        dyn.run(steps=100)
        traj.write()
        D, fragments = scene.damage, scene.fragments
    assert 0 < (D > 0).sum() < len(D)         # a field worth writing
    frame = Trajectory(tmp_path / "t.h5")[-1]
    assert np.array_equal(frame.damage, D)
    assert np.array_equal(frame.fragment, fragments)
    xmf = (tmp_path / "t.xmf").read_text()
    assert 'Attribute Name="damage"' in xmf
    assert 'Attribute Name="fragment"' in xmf


def test_restart_from_a_checkpoint_gives_bitwise_the_same_damage(tmp_path):
    first = tension_block()
    ImprovedEuler(first).run(steps=40)
    first.write_checkpoint(tmp_path / "c.h5")
    ImprovedEuler(first).run(steps=60)
    again = tension_block()
    again.read_checkpoint(tmp_path / "c.h5")
    ImprovedEuler(again).run(steps=60)
    grown = first.damage
    assert grown.max() > 0 and (grown > 0).sum() > 10
    assert np.array_equal(again.damage, grown)
    assert np.array_equal(again.positions, first.positions)


def test_the_seed_changes_the_draw_and_only_it():
    a, b, c = tension_block(1), tension_block(1), tension_block(2)
    assert np.array_equal(a.flaw_strain, b.flaw_strain)
    assert not np.array_equal(a.flaw_strain, c.flaw_strain)
    assert np.array_equal(a.flaws, b.flaws)



def test_the_scenes_are_in_the_scenes_module():
    from sphsolid import fracture, scenes
    assert scenes.ucs is fracture.ucs
    assert scenes.brazilian_disc is fracture.brazilian_disc


def test_ucs_runs_past_its_peak_and_reports_the_strength():
    from sphsolid import fracture
    scene = fracture.ucs(4e-3)
    run = fracture.load_to_break(scene, max_strain=0.008, drop=0.5)
    # the strength is the peak load over the loaded width (1 m deep)
    assert run.strength_Pa == pytest.approx(run.peak_load_N / 0.086)
    assert run.peak_load_N == pytest.approx(run.load.max())
    # past the peak: stopped by the drop, damage began before the peak
    assert run.post_peak_ratio < 0.5
    assert run.strain[-1] < 0.008
    assert run.damage_onset_s is not None
    assert run.damage_onset_s <= run.peak_time
    # the strain is the piston's travel over the specimen's height
    assert run.strain_at_peak == pytest.approx(run.peak_time * 1.0, rel=1e-9)
    assert run.fragments >= 1
    assert set(run.summary()) >= {"peak_load_N", "strength_Pa",
                                  "strain_at_peak", "fragments",
                                  "damage_onset_s"}


def test_a_load_lost_before_any_damage_is_not_taken_for_fracture(
        monkeypatch):
    # the reaction of a bar whose flaws never activate (D stays 0) rises
    # and then falls to a third of its peak: a loss of load the damage
    # model did not cause, flagged; the real run of the same bar keeps
    # its load and is not
    from sphsolid import fracture
    flawless = Material(**ROCK, weibull_k=1.0, weibull_m=9.0)
    scene = fracture.tensile_bar(5e-3, material=flawless)
    real = fracture.load_to_break(scene, max_strain=2e-5, drop=0.5)
    assert float(scene.damage.max()) == 0.0
    assert not real.load_lost_before_damage
    assert real.summary()["load_lost_before_damage"] is False
    loads = iter([1e5, 2e5, 3e5, 2e5, 1e5] + [1e5] * 1000)
    scene = fracture.tensile_bar(5e-3, material=flawless)
    monkeypatch.setattr(scene, "reaction",
                        lambda body: (0.0, -next(loads)))
    lost = fracture.load_to_break(scene, max_strain=2e-4, drop=0.5)
    assert lost.load_lost_before_damage and lost.damage_onset_s is None
    assert lost.peak_load_N == pytest.approx(3e5)



def test_the_old_names_of_a_break_warn_and_give_the_same_run():
    # load_to_failure and FailureRun (0.2) name a broken specimen as the
    # library names its numerical stop (sph_failure): they stay until
    # 0.3.0, load_to_failure with a DeprecationWarning, and the run is
    # load_to_break's to the bit
    from sphsolid import fracture
    new = fracture.load_to_break(fracture.tensile_bar(5e-3), max_strain=5e-5)
    with pytest.warns(DeprecationWarning, match="load_to_break"):
        old = fracture.load_to_failure(fracture.tensile_bar(5e-3),
                                       max_strain=5e-5)
    assert fracture.FailureRun is fracture.BreakRun
    assert isinstance(old, fracture.BreakRun)
    assert np.array_equal(old.load, new.load) and len(new.load) > 1
    assert old.summary() == new.summary()

def test_sphsolid_ucs_writes_summary_and_files(tmp_path):
    from sphsolid.cli import main
    assert main(["ucs", "--dx", "4mm", "--threads", "1",
                 "--out", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    for key in ("peak_load_N", "strength_Pa", "strain_at_peak", "fragments",
                "damage_onset_s"):
        assert key in summary
    assert summary["strength_Pa"] == pytest.approx(
        summary["peak_load_N"] / 0.086)
    for name in ("ucs.h5", "ucs.xmf", "ucs_load.csv", "ucs_damage.png"):
        assert (tmp_path / name).stat().st_size > 0
    frames = list(Trajectory(tmp_path / "ucs.h5"))
    assert frames and frames[-1].damage is not None


def test_sphsolid_tensile_pulls_the_bar_apart(tmp_path):
    """The tensile bar: the load (the piston's reaction, pulled down) is a
    tension that rises until damage sets in, then drops below half its
    peak; strength = peak load / width; the bar breaks in two or more."""
    import numpy as np
    from sphsolid.cli import main
    assert main(["tensile", "--dx", "5mm", "--threads", "1",
                 "--out", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["strength_Pa"] == pytest.approx(
        summary["peak_load_N"] / 0.020)
    t, strain, load = np.loadtxt(tmp_path / "tensile_load.csv",
                                 delimiter=",", skiprows=1).T
    k = int(np.argmax(load))
    assert np.all(np.diff(load[:k + 1][t[:k + 1]
                                       < summary["damage_onset_s"]]) > 0)
    assert summary["damage_onset_s"] < t[k] and load[-1] < 0.5 * load[k]
    assert strain[k] == summary["strain_at_peak"]
    assert summary["fragments"] >= 2


def test_bad_fracture_arguments_are_named(tmp_path):
    from sphsolid import fracture
    from sphsolid.cli import main
    scene = fracture.ucs(4e-3)
    with pytest.raises(ValueError, match="drop"):
        fracture.load_to_break(scene, drop=1.5)
    with pytest.raises(ValueError, match="strain_rate=-1"):
        fracture.tensile_bar(5e-3, strain_rate=-1.0)
    with pytest.raises(ValueError, match="member=2.5"):
        fracture.tensile_bar(5e-3, member=2.5)
    with pytest.raises(SystemExit):
        main(["ucs", "--max-strain", "2", "--out", str(tmp_path)])


def _broken_bar(steps, energy_account=True, dt_factor=None):
    """The tensile bar at a coarse 4 mm (damage on, artificial viscosity
    alpha 1, no damping) run ``steps`` steps; it breaks near step 2500."""
    from sphsolid import fracture
    scene = fracture.tensile_bar(4e-3)
    scene.energy_account(energy_account)
    dyn = ImprovedEuler(scene, progress=False)
    if dt_factor is not None:
        dyn = ImprovedEuler(scene, dt=dt_factor * dyn.dt,
                            allow_unstable=True, progress=False)
    e0 = scene.energy(all_bodies=True)
    dyn.run(steps=steps)
    return scene, e0


def test_energy_balances_within_1_percent_past_failure():
    """Undamped (no damping effect): kinetic + elastic + the energy
    dissipated by damage and by artificial viscosity, less the work of the
    moving platens, stays at its initial value within 1 % of the work
    through the bar's failure; without the damage's share (the elastic
    energy released as stiffness is lost) it does not."""
    scene, e0 = _broken_bar(3200)
    e = scene.energy(all_bodies=True)
    assert scene.damage.max() == 1.0 and scene.fragments.max() >= 1
    initial = e0["kinetic"] + e0["elastic"]
    held = e["kinetic"] + e["elastic"]
    dissipated = e["dissipated_damage"] + e["dissipated_viscosity"]
    scale = max(e["work"], held + dissipated)
    assert e["work"] > 0 and e["dissipated_plastic"] == 0.0
    balance = held + dissipated - e["work"] - initial
    assert abs(balance) < 0.01 * scale
    without_damage = balance - e["dissipated_damage"]
    assert abs(without_damage) > 0.01 * scale
    # most of the work is gone from the elastic energy once it broke
    assert e["elastic"] < 0.05 * e["work"]


def test_energy_account_is_absent_while_off():
    """Never switched on, the account kept nothing: its terms are None,
    not the 0.0 the library's zeroed totals would say while the pistons
    did work; "no" is refused, not taken as true."""
    scene, _ = _broken_bar(20, energy_account=False)
    e = scene.energy(all_bodies=True)
    assert (e["work"], e["dissipated_damage"], e["dissipated_viscosity"],
            e["dissipated_plastic"]) == (None, None, None, None)
    assert e["kinetic"] > 0.0
    with pytest.raises(ValueError, match="on must be True or False, got "
                       "'no'"):
        scene.energy_account("no")
    assert scene.energy()["work"] is None


def test_watchdog_lets_fragments_fly_and_stops_a_blow_up():
    """Past failure the halves of the bar separate (fragments move at a
    small fraction of c_p) without tripping the watchdog; the same bar at
    20 times the stable step blows up and the run stops with the
    watchdog's or the non-finite report."""
    from sphsolid._lib import SimulationError
    scene, _ = _broken_bar(3200)
    assert scene.fragments.max() >= 1
    speed = np.linalg.norm(scene.velocities, axis=1).max()
    c_p = np.sqrt((12.2e9 + 4 / 3 * 2.67e9) / 2300.0)
    assert 0 < speed < 0.1 * c_p
    with pytest.raises(SimulationError) as failed:
        _broken_bar(400, dt_factor=20.0)
    assert ("watchdog" in str(failed.value)
            or "not finite" in str(failed.value)
            or "non-finite" in str(failed.value))


def _leapfrog_ucs_account(on_sample_every=None):
    """sphsolid.fracture.ucs(0.006) (damage on, artificial viscosity alpha
    1, no damping) with the energy account and the leapfrog, loaded to the
    stop as load_to_break samples it (every 5e-5 s: 16 steps); per
    sample: step, imbalance and the energy scale."""
    from sphsolid import Leapfrog, fracture
    scene = fracture.ucs(0.006)
    scene.energy_account(True)
    dyn = Leapfrog(scene, progress=False)
    e0 = scene.energy(all_bodies=True)
    start = e0["kinetic"] + e0["elastic"]
    rows = []

    def on_sample(scene, t, load, peak):
        e = scene.energy(all_bodies=True)
        held = e["kinetic"] + e["elastic"]
        dissipated = (e["dissipated_damage"] + e["dissipated_plastic"]
                      + e["dissipated_viscosity"])
        rows.append((round(t / dyn.dt), held + dissipated - e["work"] - start,
                     max(e["work"], held + dissipated), e["work"],
                     e["dissipated_damage"]))

    fracture.load_to_break(scene, dynamics=dyn, on_sample=on_sample)
    return scene, np.array(rows)


def test_leapfrog_energy_balances_within_1_percent_through_failure():
    """The leapfrog's step opens with the powers of the rates it starts
    from (kept from its last momentum pass, or of the rates evaluated
    again after damage grew) and closes with its momentum pass: the
    trapezoid.  Measured (16 steps a sample, 992 to the stop): |imbalance|
    at most 0.67 % of the energy from step 32 on, at most 0.09 % past
    5 J/m of work before damage, -1.90 of 465.2 J/m at the stop.  The
    first sample (step 16, 1.25 %) holds the scheme's start-up offset,
    +0.005 J/m set in the first 3 steps as the piston starts against the
    specimen at rest (artificial viscosity's heat at that impulsive start
    is under-resolved; 0.0013 J/m without viscosity), which no
    integration of the powers removes.  With the step's closing powers
    alone (its rectangle, the account before) the work runs half a step
    ahead: 0.96 % at step 64, 0.69 % before damage."""
    scene, rows = _leapfrog_ucs_account()
    step, imbalance, scale, work, damage = rows.T
    assert scene.damage.max() == 1.0 and work[-1] > 100.0
    assert damage[-1] > 0.1 * work[-1]
    ratio = np.abs(imbalance) / np.maximum(scale, 1e-3)
    later = step >= 32
    assert (ratio[later] <= 0.01).all(), (ratio.max(), step[ratio.argmax()])
    # the start-up offset, against which the first sample's energy is small
    assert step[0] == 16 and abs(imbalance[0]) < 0.006
    # before damage the balance holds to far better than 1 %
    elastic_phase = (damage == 0.0) & (work > 5.0)
    assert elastic_phase.sum() > 10
    assert (ratio[elastic_phase] <= 1e-3).all(), ratio[elastic_phase].max()


def test_leapfrog_account_resumes_from_a_checkpoint(tmp_path):
    """The checkpoint keeps the powers of the rates it carries
    (rate_powers): a resumed leapfrog run's account (its totals start
    again at the read) is the uninterrupted run's increase over the same
    steps, to round-off, through damage; split runs are one run bitwise."""
    from sphsolid import Leapfrog, fracture
    keys = ("work", "dissipated_damage", "dissipated_viscosity")

    def ucs():
        scene = fracture.ucs(0.006)
        scene.energy_account(True)
        return scene, Leapfrog(scene, progress=False)

    first, dyn = ucs()
    dyn.run(steps=720)                  # damage sets in at step 740
    first.write_checkpoint(tmp_path / "c.h5")
    before = first.energy(all_bodies=True)
    for _ in range(9):
        dyn.run(steps=30)
    after = first.energy(all_bodies=True)
    assert first.damage.max() > 0.0 and before["dissipated_damage"] == 0.0

    again, dyn = ucs()
    again.read_checkpoint(tmp_path / "c.h5")
    dyn.run(steps=270)
    resumed = again.energy(all_bodies=True)
    assert np.array_equal(again.positions, first.positions)
    assert (resumed["kinetic"], resumed["elastic"]) == (after["kinetic"],
                                                        after["elastic"])
    for key in keys:
        increase = after[key] - before[key]
        assert increase > 0.0
        assert resumed[key] == pytest.approx(increase, rel=0,
                                             abs=1e-12 * after["work"]), key

    whole, dyn = ucs()
    dyn.run(steps=990)
    e = whole.energy(all_bodies=True)
    assert all(e[key] == after[key] for key in keys + ("kinetic", "elastic"))
