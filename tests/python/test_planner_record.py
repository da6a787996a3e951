# Over 600 lines: the verification record's tests share its fake ladders and fixtures.
"""The planner's verification record (sphsolid.planner.record), its use in
the search, the on-disk run cache, the progress bar and plan files as
input."""
import inspect
import json
import math
from pathlib import Path

import numpy as np
import pytest

from sphsolid import planner
from sphsolid.planner import record as record_module
from sphsolid.planner.cache import RunCache
from sphsolid.planner.error_model import ErrorModel
from sphsolid.planner.search import Progress

ROOT = Path(__file__).resolve().parents[2]
RAW = ROOT / "docs" / "accuracy" / "record_raw.json"


# ------------------------------------------------ the checks' candidates
class _Planned(Exception):
    """Raised by the recorder in place of planning."""


def _record_plan_calls(monkeypatch):
    calls = []

    def recorder(*args, **kwargs):
        bound = inspect.signature(planner.search.plan).bind(*args, **kwargs)
        bound.apply_defaults()
        calls.append(dict(bound.arguments))
        raise _Planned()
    monkeypatch.setattr(planner, "plan", recorder)
    return calls


def test_the_accuracy_checks_plan_with_the_clis_candidates(monkeypatch,
                                                          tmp_path):
    from sphsolid.cli import main
    from validation import accuracy
    calls = _record_plan_calls(monkeypatch)
    with pytest.raises(_Planned):
        main(["plan", "strip", "--error", "3%", "--no-cache",
              "--out", str(tmp_path / "p.json")])
    spec = planner.project_scenes()["strip"]
    scene = accuracy.Scene("strip", spec, reference=None, sweep=())
    with pytest.raises(_Planned):
        accuracy.run_checks(scene, [("max", 0.03, 1)], print)
    cli, checks = calls
    # everything that decides which settings are calibrated and chosen
    # (the request itself, the log and the cache aside) is the CLI's
    request = {"scene_factory", "error", "until", "probes", "quantity",
               "norm", "threads", "ladder", "window", "scene", "log",
               "cache"}
    for name in set(cli) - request:
        assert checks[name] == cli[name], name
    assert cli["options"] is None and cli["candidates"] is None
    assert cli["record"] is True


# ------------------------------------------------------ the record data
def _shipped_and_raw():
    record = record_module.shipped()
    if record is None or not RAW.exists():
        pytest.skip("no verification record in this tree")
    return record, json.loads(RAW.read_text())


def test_every_fitted_prediction_times_its_factor_bounds_the_true_error():
    # the record's factor of each setting covers every prediction of the
    # fitted scenes (true error <= factor x upper prediction): the record
    # agrees with its own evidence, margin included
    record, raw = _shipped_and_raw()
    checked = 0
    for name in record.data["fitted"]:
        for family, entry in raw.get(name, {}).items():
            for norm in ("max", "rms"):
                verdict = record.settings.get(family, {}).get(norm)
                if verdict is None:
                    continue
                factor = max(1.0, record.margin * verdict["ratio"])
                for pair in entry[norm]["pairs"]:
                    bound = max(factor * pair["upper"], verdict["bias"])
                    # the margin is kept too: 1/MARGIN of the bound at most
                    assert pair["true"] <= bound / record.margin * (
                        1 + 1e-9) or pair["true"] <= verdict["bias"], (
                        name, family, norm, pair)
                    checked += 1
    assert checked > 100


def test_held_out_scenes_never_enter_the_factors():
    record, raw = _shipped_and_raw()
    fitted, held = record.data["fitted"], record.data["held_out"]
    assert not set(fitted) & set(held)
    for family, entry in record.settings.items():
        for norm in ("max", "rms"):
            if norm not in entry:
                continue
            ratios = [raw[s][family][norm]["ratio"] for s in fitted
                      if family in raw.get(s, {})
                      and raw[s][family][norm]["ratio"] is not None]
            assert entry[norm]["ratio"] == pytest.approx(max(ratios))


def test_family_ignores_effect_parameters_but_not_effects():
    a = planner.Setting.make(1.2, effects={"artificial_viscosity":
                                           {"alpha": 1.0}})
    b = planner.Setting.make(1.2, effects={"artificial_viscosity":
                                           {"alpha": 0.5}})
    c = planner.Setting.make(1.2)
    assert record_module.family(a) == record_module.family(b)
    assert record_module.family(a) != record_module.family(c)


def test_a_record_with_bad_values_names_the_key(tmp_path):
    path = tmp_path / "record.json"
    path.write_text(json.dumps({"format": 1, "settings": {
        "k": {"max": {"ratio": -1, "bias": 0}}}}))
    with pytest.raises(ValueError, match=r"\['k'\]\['max'\]\['ratio'\]"):
        record_module.Record.load(path)
    path.write_text("[1, 2")
    with pytest.raises(ValueError, match="record.json"):
        record_module.Record.load(path)


# ------------------------------------------------- the record's effect
UNTIL = 20e-6
TIMES = np.linspace(0.0, UNTIL, 201)


def _fake_strip_run(dx, setting, ran=None):
    """A calibration run of the strip whose probe series converge at order
    1 (30 dx of relative error), sized like the strip at dx."""
    if ran is not None:
        ran.append(setting)
    spec = planner.project_scenes()["strip"]
    series = {n: 1e6 * (1 + 30 * dx * np.sin(2e5 * TIMES))
              for n in spec.probes}
    n, steps = int(0.8 / dx), int(UNTIL / (0.1 * dx / 3000.0))
    return planner.LadderRun(setting, dx, n, steps, UNTIL / steps, 1.0,
                             UNTIL, TIMES, series, cpu=n * steps * 1e-8,
                             threads=1)


def _model(**kw):
    return ErrorModel(order=1.0, coefficient=10.0, safety=1.25, floor=0.0,
                      residual=0.0, levels=[], differences=[], finest=1e-3,
                      **kw)


def test_upper_is_scaled_by_the_record_and_never_below_its_bias():
    plain, verified = _model(), _model(verified=2.0, bias=0.004)
    assert verified.upper(1e-3) == pytest.approx(2 * plain.upper(1e-3))
    # the spacing for a request is where the scaled bound meets it
    dx = verified.spacing_for(0.01)
    assert verified.upper(dx) == pytest.approx(0.01)
    assert dx == pytest.approx(plain.spacing_for(0.005))
    # at or below the bias, refinement cannot reach the request
    assert verified.spacing_for(0.004) is None
    assert verified.upper(1e-9) == pytest.approx(0.004)


def test_the_planner_calibrates_only_what_the_record_verifies(monkeypatch):
    spec = planner.project_scenes()["strip"]
    kept = planner.Setting.make(1.2, "cubic_spline", "leapfrog")
    unverified = planner.Setting.make(1.5, "cubic_spline", "leapfrog")
    biased = planner.Setting.make(1.2, "wendland_c2", "leapfrog")
    # its prediction under-stated its true error on a fitted scene
    under = planner.Setting.make(1.5, "wendland_c2", "leapfrog")
    record = record_module.Record({"format": 1, "settings": {
        record_module.family(kept): {"max": {"ratio": 0.95, "bias": 0.0}},
        record_module.family(biased): {"max": {"ratio": 0.5,
                                               "bias": 0.05}},
        record_module.family(under): {"max": {"ratio": 1.05,
                                              "bias": 0.0}}}})
    monkeypatch.setattr(planner.search, "candidate_settings",
                        lambda *a, **k: ([kept, unverified, biased, under],
                                         []))
    until = UNTIL
    ran = []
    monkeypatch.setattr(planner.search, "ladder_run",
                        lambda factory, dx, setting, *args:
                        _fake_strip_run(dx, setting, ran))
    plan = planner.plan(spec.factory, error=0.03, until=until,
                        probes=spec.probes, quantity=spec.quantity,
                        norm="max", threads=1, ladder=(2e-3, 1.4e-3, 1e-3),
                        timing_checks=0, scene="strip", record=record)
    assert set(ran) == {kept}
    by = {c.setting: c for c in plan.candidates}
    assert "not verified" in by[unverified].note
    assert "bias" in by[biased].note
    assert "under-stated its true error 1.05x" in by[under].note
    # the kept setting's bound carries the record's factor (0.95 x 1.2)
    assert by[kept].model.verified == pytest.approx(1.14)
    if plan.feasible:
        assert plan.error_upper <= 0.03 + 1e-12


# ---------------------------------------------------------- run cache
def test_run_cache_keeps_runs_per_scene_on_disk(tmp_path):
    setting = planner.Setting.make()
    run = planner.LadderRun(setting, 1e-3, 10, 5, 1e-7, 0.1, 5e-7,
                            np.arange(3.0), {"A": np.ones(3)})
    key = (1e-3, setting, 5e-7, "von_mises", 1)
    RunCache("piston", tmp_path)[key] = run
    again = RunCache("piston", tmp_path)
    assert key in again and again[key].series["A"].tolist() == [1, 1, 1]
    assert key not in RunCache("strip", tmp_path)
    # an entry that cannot be read is a miss, and is written again
    for entry in tmp_path.rglob("*.pkl"):
        entry.write_bytes(b"\x80\x04truncated")
    fresh = RunCache("piston", tmp_path)
    assert key not in fresh
    fresh[key] = run
    assert key in RunCache("piston", tmp_path)
    assert key not in RunCache("piston", None)


def test_progress_bar_counts_and_estimates_the_time_left():
    setting = planner.Setting.make()
    progress = Progress(2e-3)
    progress.plan([2e-3, 1e-3, 2e-3, 1e-3])

    def run(dx, wall):
        n = int(1e-3 / dx * 100)
        return planner.LadderRun(setting, dx, n * n, int(100 * 1e-3 / dx),
                                 1e-7, wall, 1e-5)
    progress.done(run(2e-3, 1.0), cached=False)
    progress.done(run(1e-3, 8.0), cached=False)
    text = progress.bar(3, 4)
    # the coarse run costs 1/8 of the fine one (dx^-3): 9 s of work left
    assert text.startswith("[##########") and "3/4" in text
    left = float(text.split(", ")[1].split(" s left")[0])
    assert left == pytest.approx(9.0, rel=0.05)


# ------------------------------------------------------- plan files
def _plan_dict():
    return {"format": "sphsolid-plan 1", "scene": "piston",
            "request": {"error": 0.03, "until": 3e-4, "norm": "max"},
            "feasible": True,
            "settings": {"dx": 1e-3, "smoothing_ratio": 1.2,
                         "kernel": "cubic_spline",
                         "integrator": "improved_euler",
                         "effects": {"artificial_viscosity": {"alpha": 1.0}},
                         "inset": 0.0, "threads": 1},
            "predicted_error": 0.02, "error_upper": 0.03,
            "predicted_seconds": 1.0, "effects": []}


@pytest.mark.parametrize("change, key", [
    (lambda d: d.pop("settings"), "settings"),
    (lambda d: d["settings"].pop("dx"), "settings.dx"),
    (lambda d: d["settings"].update(dx="1mm"), "settings.dx"),
    (lambda d: d["settings"].update(effects=["artificial_viscosity"]),
     "settings.effects"),
    (lambda d: d.update(settings="cubic_spline"), "settings"),
    (lambda d: d.update(feasible="no"), "feasible"),
    (lambda d: d.update(format="sphsolid-plan 9"), "format"),
    (lambda d: d["settings"].update(threads=1.5), "settings.threads"),
    (lambda d: d["settings"]["effects"]["artificial_viscosity"].update(
        alpha="one"), "settings.effects.artificial_viscosity.alpha"),
    (lambda d: d.update(effects={"a": 1}), "effects"),
    (lambda d: d.update(request=[1]), "request"),
])
def test_a_tampered_plan_file_names_the_key(tmp_path, change, key):
    data = _plan_dict()
    change(data)
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError) as error:
        planner.Plan.load(path)
    assert key in str(error.value) and str(path) in str(error.value)


def test_plan_files_that_are_not_plans_name_the_file(tmp_path):
    good = tmp_path / "good.json"
    good.write_text(json.dumps(_plan_dict()))
    loaded = planner.Plan.load(good)
    assert loaded.dx == 1e-3 and loaded.feasible is True
    for name, content in [("array.json", "[1, 2]"),
                          ("cut.json", json.dumps(_plan_dict())[:40]),
                          ("utf16.json", None)]:
        path = tmp_path / name
        if content is None:
            path.write_bytes(json.dumps(_plan_dict()).encode("utf-16"))
        else:
            path.write_text(content)
        with pytest.raises(ValueError, match=name):
            planner.Plan.load(path)
    with pytest.raises(ValueError, match="directory"):
        planner.Plan.load(tmp_path)
    assert math.isfinite(loaded.predicted_seconds)


# --------------------------------------------- what a run writes
def test_default_probe_interval_keeps_the_metric_of_a_wave_series():
    from sphsolid import metrics
    assert metrics.probe_interval_for(0.26e-6) == 1
    assert metrics.probe_interval_for(0.05e-6) == 5
    with pytest.raises(ValueError, match="dt"):
        metrics.probe_interval_for(0.0)
    # a front that rises over 2 us (a wave at the piston's resolution),
    # stepped at 0.1 us: sampled at the default interval and interpolated
    # it stays within 0.1 % of its every-step series in the metric, where
    # sampling every 62 steps (the former 10 steps at 0.62 us) does not
    dt, until = 0.1e-6, 100e-6
    times = np.arange(0.0, until + dt / 2, dt)
    series = 1e7 * (1 + np.tanh((times - 40e-6) / 1e-6)) \
        + 2e6 * np.sin(2 * np.pi * times / 7e-6)
    grid = metrics.time_grid(0.0, until)
    full = metrics.smooth(grid, metrics.on_grid(times, series, grid))

    def sampled(every):
        return metrics.smooth(grid, metrics.on_grid(
            times[::every], series[::every], grid))
    fine = metrics.deviation(sampled(metrics.probe_interval_for(dt)), full)
    coarse = metrics.deviation(sampled(62), full)
    assert fine < 1e-3 < coarse


def test_finer_levels_of_earlier_plans_enter_the_fit(monkeypatch, tmp_path):
    # one verdict per setting: a level an earlier plan of the scene
    # calibrated is part of every later fit of that setting
    spec = planner.project_scenes()["strip"]
    setting = planner.Setting.make(1.2, "cubic_spline", "leapfrog")
    until = UNTIL
    monkeypatch.setattr(planner.search, "ladder_run",
                        lambda factory, dx, setting_, *args:
                        _fake_strip_run(dx, setting_))
    cache = RunCache("strip-test", tmp_path)
    key = (0.5e-3, setting, until, spec.quantity, 1)
    cache[key] = _fake_strip_run(0.5e-3, setting)
    plan = planner.plan(spec.factory, error=0.03, until=until,
                        probes=spec.probes, quantity=spec.quantity,
                        norm="max", threads=1, ladder=(2e-3, 1.4e-3, 1e-3),
                        candidates=[setting], timing_checks=0, refinements=0,
                        cache=RunCache("strip-test", tmp_path), record=None)
    (cand,) = plan.candidates
    assert [r.dx for r in cand.runs] == [2e-3, 1.4e-3, 1e-3, 0.5e-3]
    assert cand.model.finest == pytest.approx(0.5e-3)


def test_a_scene_file_is_planned_at_the_spacing_asked_for():
    example = ROOT / "examples" / "scene_file" / "pull.toml"
    spec = planner.scenes.scene_file(example, probes=["top"])
    assert list(spec.probes) == ["top"]
    assert spec.ladder[-1] == pytest.approx(2e-3)
    coarse, fine = spec.factory(4e-3), spec.factory(2e-3)
    # the block is 40 x 60 mm: halving dx gives four times its particles
    assert fine.body_counts()["block"] == 4 * coarse.body_counts()["block"]
    with pytest.raises(ValueError, match="no probe nowhere"):
        planner.scenes.scene_file(example, probes=["nowhere"])


def test_a_scene_files_static_inset_yields_to_the_settings_own():
    # the cylinder's file lays its platens at inset = "static", which has
    # no solution for the cubic spline at h/dx 1.5: the planner's setting
    # places the ends (there, on the lattice), as it sets kernel and h/dx
    example = ROOT / "examples" / "scene_file" / "cylinder.toml"
    spec = planner.scenes.scene_file(example, probes=["D"])
    lattice = spec.factory(9e-3, 1.5, "cubic_spline", 0.0)
    static = spec.factory(9e-3, 1.65, "cubic_o4", "static")
    top = {s: float(sc.positions[sc.body_slice("piston"), 1].min())
           for s, sc in (("lattice", lattice), ("static", static))}
    # set in by the static inset, the piston's rows start lower
    assert top["static"] < top["lattice"]


def test_a_scene_file_runs_with_the_settings_of_its_plan(tmp_path):
    from sphsolid.scenefile import run_file
    example = ROOT / "examples" / "scene_file" / "pull.toml"
    data = _plan_dict()
    data.update(scene="pull.toml", request={"until": 10e-6, "error": 0.1})
    data["settings"].update(dx=4e-3, integrator="leapfrog")
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(data))
    lines = []
    run_file(example, out=tmp_path, plan=path, log=lines.append)
    # the block of 40 x 60 mm at 4 mm: 10 x 15 particles
    assert any("block 150" in line for line in lines), lines
    assert any("until 0.01 ms" in line for line in lines), lines
    # the file samples its probes every 2 steps, more sparsely than the
    # planner's metric reads them at this step: the run says so, unless
    # the interval asked for is fine enough
    assert any(line.startswith("warning: probes sampled every 2 steps")
               for line in lines), lines
    # the user's thread count replaces the plan's (the CLI's --threads)
    lines.clear()
    run_file(example, out=tmp_path, plan=path, threads=1, probe_interval=1,
             log=lines.append)
    assert not any("warning" in line for line in lines), lines
    data["scene"] = "other.toml"
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="other.toml"):
        run_file(example, out=tmp_path, plan=path, log=lines.append)


def test_plan_refuses_an_unwritable_output_before_any_work(tmp_path,
                                                           capsys,
                                                           monkeypatch):
    from sphsolid.cli import main
    calls = _record_plan_calls(monkeypatch)
    assert main(["plan", "piston", "--error", "3%", "--out",
                 str(tmp_path / "missing" / "plan.json")]) != 0
    assert "missing does not exist" in capsys.readouterr().err
    assert calls == []


def test_dominance_needs_better_errors_everywhere_for_less_time():
    from validation.record import dominance

    def entry(errors, cpu):
        return {"cpu": cpu, "max": {"errors": errors},
                "rms": {"errors": [e / 2 for e in errors]}}
    raw = {"a": {"slow": entry([0.10, 0.05], [1.0, 8.0]),
                 "fast": entry([0.10, 0.05], [0.5, 4.0]),
                 "sharp": entry([0.08, 0.06], [0.2, 1.0])},
           "b": {"slow": entry([0.10, 0.05], [1.0, 8.0]),
                 "fast": entry([0.104, 0.05], [0.5, 4.0])}}
    out = dominance(raw, ("a", "b"))
    # "fast" is as good (within 5 %) on both scenes for half the time;
    # "sharp" is worse at one level and absent from scene b
    assert out == {"slow": ["fast"]}
    raw["b"]["fast"] = entry([0.11, 0.05], [0.5, 4.0])
    assert dominance(raw, ("a", "b")) == {}


def test_a_dominated_candidate_is_not_calibrated(monkeypatch):
    spec = planner.project_scenes()["strip"]
    fast = planner.Setting.make(1.2, "cubic_spline", "leapfrog")
    slow = planner.Setting.make(1.2, "cubic_spline", "improved_euler")
    verdict = {"max": {"ratio": 0.5, "bias": 0.0}}
    record = record_module.Record({
        "format": 1, "settings": {record_module.family(fast): verdict,
                                  record_module.family(slow): verdict},
        "dominated_by": {record_module.family(slow):
                         [record_module.family(fast)]}})
    monkeypatch.setattr(planner.search, "candidate_settings",
                        lambda *a, **k: ([slow, fast], []))
    ran = []

    def fake_run(factory, dx, setting, *args):
        ran.append(setting)
        times = np.linspace(0.0, 20e-6, 201)
        series = {n: 1e6 * (1 + 30 * dx * np.sin(2e5 * times))
                  for n in spec.probes}
        return planner.LadderRun(setting, dx, 100, 100, 2e-7, 1.0, 20e-6,
                                 times, series, cpu=0.1, threads=1)
    monkeypatch.setattr(planner.search, "ladder_run", fake_run)
    plan = planner.plan(spec.factory, error=0.05, until=20e-6,
                        probes=spec.probes, quantity=spec.quantity,
                        threads=1, ladder=(2e-3, 1.4e-3, 1e-3),
                        timing_checks=0, refinements=0, record=record)
    assert set(ran) == {fast}
    by = {c.setting: c for c in plan.candidates}
    assert "dominated by" in by[slow].note


# ------------------------------------- refinement ordered by the record
def _record_with_errors(finest_errors):
    """A record verifying each setting in the max norm, with the given
    error at the finest level of two fitted scenes."""
    settings = {}
    for setting, (a, b) in finest_errors.items():
        settings[record_module.family(setting)] = {
            "max": {"ratio": 0.5, "bias": 0.0},
            "scenes": {"a": {"max": {"errors": [3 * a, a]}},
                       "b": {"max": {"errors": [3 * b, b]}},
                       "held": {"max": {"errors": [1e-9]}}}}
    return record_module.Record({"format": 1, "fitted": ["a", "b"],
                                 "held_out": ["held"],
                                 "settings": settings})


def test_promise_is_the_mean_log_distance_to_the_best_fitted_error():
    best = planner.Setting.make(1.2, "cubic_spline", "leapfrog")
    other = planner.Setting.make(1.5, "cubic_spline", "leapfrog")
    record = _record_with_errors({best: (0.01, 0.02), other: (0.04, 0.02)})
    assert record.promise(best, "max") == pytest.approx(0.0)
    # 4x worse on a, as good on b; the held-out scene never counts
    assert record.promise(other, "max") == pytest.approx(math.log(4) / 2)
    assert record.promise(best, "rms") is None


def _refine_three(monkeypatch, errors, scaling, **options):
    """Plan the strip with three settings of the record ``errors`` whose
    calibration runs show no order (noise that refinement does not
    reduce); the runs' size scales as dx^-3 when ``scaling`` (else fixed).
    Returns the settings refined, in order, and the log."""
    spec = planner.project_scenes()["strip"]
    record = _record_with_errors(errors)
    monkeypatch.setattr(planner.search, "candidate_settings",
                        lambda *a_, **k: (list(errors), []))
    ran, said = [], []

    def noisy_run(factory, dx, setting, *args):
        ran.append((setting, dx))
        times = np.linspace(0.0, 20e-6, 201)
        rng = np.random.default_rng(int(dx * 1e7))
        series = {n: 1e6 * (1 + 0.2 * rng.standard_normal(times.size))
                  for n in spec.probes}
        particles, steps = ((int(0.1 / dx ** 2), int(0.1 / dx)) if scaling
                            else (100, 100))
        cpu = 1e-7 * particles * steps
        return planner.LadderRun(setting, dx, particles, steps, 2e-7, cpu,
                                 20e-6, times, series, cpu=cpu, threads=1)
    monkeypatch.setattr(planner.search, "ladder_run", noisy_run)
    ladder = (2e-3, 1.4e-3, 1e-3)
    options.setdefault("record", record)
    planner.plan(spec.factory, error=0.03, until=20e-6, probes=spec.probes,
                 quantity=spec.quantity, threads=1, ladder=ladder,
                 timing_checks=0, refinements=1, log=said.append, **options)
    return [s for s, dx in ran if dx < ladder[-1] * (1 - 1e-6)], said


def test_settings_without_an_order_are_refined_in_the_records_order(
        monkeypatch):
    a = planner.Setting.make(1.2, "cubic_spline", "leapfrog")
    b = planner.Setting.make(1.5, "cubic_spline", "leapfrog")
    c = planner.Setting.make(1.2, "wendland_c2", "leapfrog")
    # c came closest to the best setting on the fitted scenes, then a
    refined, _ = _refine_three(monkeypatch, {a: (0.02, 0.02),
                                             b: (0.08, 0.08),
                                             c: (0.01, 0.01)},
                               scaling=False, refine_best=2)
    assert refined == [c, a]


def test_the_record_prunes_settings_it_prices_far_above_the_best(
        monkeypatch):
    a = planner.Setting.make(1.2, "cubic_spline", "leapfrog")
    b = planner.Setting.make(1.5, "cubic_spline", "leapfrog")
    c = planner.Setting.make(1.2, "wendland_c2", "leapfrog")
    # a is the best; b's error 1.2x a's costs 1.2^3 = 1.7x a's work at
    # order 1 in 2D (particles x steps ~ dx^-3); c's 2x costs 8x
    errors = {a: (0.01, 0.01), b: (0.012, 0.012), c: (0.02, 0.02)}
    refined, said = _refine_three(monkeypatch, errors, scaling=True,
                                  refine_best=3)
    assert refined == [a, b]
    assert any(line.startswith(f"not refining {c.label()}") and "8x" in line
               for line in said)
    # without the record every undetermined setting gets its level
    refined, _ = _refine_three(monkeypatch, errors, scaling=True,
                               refine_best=3, record=None)
    assert set(refined) == {a, b, c}


def test_a_scene_whose_effects_the_record_lacks_is_refused_by_name(
        monkeypatch, tmp_path):
    # the record verifies the plain setting; the scene calls for
    # artificial stress, which no setting of the record has
    spec = planner.project_scenes()["strip"]
    plain = planner.Setting.make(1.2, "cubic_spline", "leapfrog")
    stressed = planner.Setting.make(
        1.2, "cubic_spline", "leapfrog",
        effects={"artificial_stress": {"epsilon": 0.3}})
    record = record_module.Record({"format": 1, "settings": {
        record_module.family(plain): {"max": {"ratio": 0.5, "bias": 0.0}}}})
    monkeypatch.setattr(planner.search, "candidate_settings",
                        lambda *a, **k: ([stressed], []))
    plan = planner.plan(spec.factory, error=0.05, until=20e-6,
                        probes=spec.probes, quantity=spec.quantity,
                        threads=1, ladder=(2e-3, 1.4e-3, 1e-3),
                        timing_checks=0, record=record)
    assert not plan.feasible
    assert "no setting with artificial_stress" in plan.reason
    assert "--no-record" in plan.reason and "record=None" in plan.reason


def test_the_cli_plans_without_the_record_when_asked(monkeypatch, tmp_path):
    from sphsolid.cli import main
    calls = _record_plan_calls(monkeypatch)
    for extra in ([], ["--no-record"]):
        with pytest.raises(_Planned):
            main(["plan", "strip", "--error", "3%", "--no-cache",
                  "--out", str(tmp_path / "p.json")] + extra)
    assert calls[0]["record"] is True and calls[1]["record"] is None


def test_levels_of_earlier_plans_count_toward_the_refinement_depth(
        monkeypatch, tmp_path):
    # a setting whose levels show no order is refined while no plan is in
    # reach, but never below `refinements` levels under its ladder: with
    # the levels of earlier plans cached, each later request would
    # otherwise go 3.4x deeper in cost (a pulled block's max-norm
    # requests: levels of 0.26, 0.18, 0.12 mm for 10 %, then 0.078 mm)
    spec = planner.project_scenes()["strip"]
    setting = planner.Setting.make(1.2, "cubic_spline", "leapfrog")
    monkeypatch.setattr(planner.search, "candidate_settings",
                        lambda *a_, **k: ([setting], []))
    ran, said = [], []

    def noisy_run(factory, dx, setting_, *args):
        ran.append(dx)
        times = np.linspace(0.0, 20e-6, 201)
        rng = np.random.default_rng(int(dx * 1e7))
        series = {n: 1e6 * (1 + 0.2 * rng.standard_normal(times.size))
                  for n in spec.probes}
        return planner.LadderRun(setting_, dx, 100, 100, 2e-7, 1e-3, 20e-6,
                                 times, series, cpu=1e-3, threads=1)
    monkeypatch.setattr(planner.search, "ladder_run", noisy_run)
    ladder = (2e-3, 1.4e-3, 1e-3)

    def plan_once():
        ran.clear()
        planner.plan(spec.factory, error=0.03, until=20e-6,
                     probes=spec.probes, quantity=spec.quantity, threads=1,
                     ladder=ladder, timing_checks=0, refinements=2,
                     record=None, log=said.append,
                     cache=RunCache("strip-depth", tmp_path))
        return [dx for dx in ran if dx < ladder[-1] * (1 - 1e-6)]
    # a first plan refines twice; a second one, with those levels cached,
    # adds none, and says why
    assert plan_once() == pytest.approx([0.667e-3, 0.445e-3])
    assert plan_once() == []
    assert any("2 level(s) below its ladder" in line for line in said)


def test_the_cylinders_centre_slope_is_the_least_squares_slope():
    # the probe of the planner scene "cylinder" keeps running sums; its
    # value after each sample is the least-squares slope of sigma_yy at
    # the centre over the samples from its start, as numpy fits it
    from sphsolid import Probes, scenes
    from sphsolid.dynamics import Leapfrog
    scene = planner.scenes.cylinder_factory(9e-3)
    slope = planner.scenes.CentreSlope(start=0.1e-3)
    probes = Probes(scene, {"c": (0.0, 0.5 * scenes.CYLINDER_LENGTH, 0.0)})
    times, values, seen = [], [], []

    def sample():
        seen.append(slope(scene)["slope"])
        times.append(scene.time)
        values.append(probes._sample_array()[0,
                                             probes.values.index("sigma_yy")])
    dyn = Leapfrog(scene, progress=False)
    dyn.attach(sample, interval=1)
    dyn.run(until=0.3e-3)
    t, v = np.array(times), np.array(values)
    late = t >= 0.1e-3
    assert late.sum() > 10 and (~late).sum() > 2
    assert seen[-1] == pytest.approx(np.polyfit(t[late], v[late], 1)[0],
                                     rel=1e-9)
    assert seen[0] == 0.0                      # before its start
    # the stress at the centre falls as the piston loads it
    assert seen[-1] < 0


# ------------------------------------------------- the scene in tension
def test_the_pulled_strip_mirrors_the_pushed_one():
    # linear elasticity in uniaxial strain: pulling the strip at v gives
    # the stress of pushing it at v with the sign changed, but for the
    # geometric terms: the piston moves 5e-8 m by the end, 2.7e-5 of the
    # spacing, and the kernel sums at its face change by that share (the
    # runs differ by 1.4e-5 of the jump).  Without
    # artificial viscosity, which acts on approaching pairs only, the
    # runs mirror each other; the record's exact reference of
    # strip_tension is that mirror of the strip's
    from validation import accuracy
    scenes = planner.project_scenes()
    setting = planner.Setting.make(1.65, "cubic_o4", "leapfrog", None,
                                   "static")
    pushed, pulled = (planner.ladder_run(
        scenes[name].factory, 2e-3, setting, scenes[name].until,
        scenes[name].probes, scenes[name].quantity, 1)
        for name in ("strip", "strip_tension"))
    assert pushed.failed is None and pulled.failed is None
    for name in pushed.series:
        push, pull = np.asarray(pushed.series[name]), np.asarray(
            pulled.series[name])
        scale = np.max(np.abs(push))
        assert scale > 0
        assert np.max(np.abs(pull + push)) <= 1e-4 * scale, name
    exact = {name: accuracy.strip_scene(None, True, print, pulled=pulled_)
             for name, pulled_ in (("strip", False), ("tension", True))}
    grid = np.linspace(0.0, scenes["strip"].until, 50)
    for probe in planner.STRIP_PROBES:
        assert np.array_equal(exact["tension"].reference(grid)[probe],
                              -exact["strip"].reference(grid)[probe])
        assert exact["tension"].reference(grid)[probe].max() > 0


def test_the_record_verifies_settings_with_artificial_stress():
    # a scene in tension among the fitted ones: a setting with artificial
    # stress can be verified (planned where its factor and bias allow)
    record, _ = _shipped_and_raw()
    assert "strip_tension" in record.data["fitted"]
    assert any("artificial_stress" in family
               for family in record.settings)
