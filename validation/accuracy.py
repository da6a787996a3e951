# Over 600 lines: the honesty checks' scenes, runs and report share one record format.
"""Honesty checks of the planner and of the per-run error estimate
(docs/accuracy.md).

    python -m validation.accuracy [--quick] [--out docs] [--threads 1]
        [--report validation/reports/accuracy/quick.md]

The data (FE series, results.json) stay in ``--out``/accuracy; the
generated report goes to ``--report`` and docs/accuracy.md quotes it.

For three scenes with a trusted answer -- the paper's piston test against
the finite-element reference (:mod:`validation.fe_reference`), the
laterally periodic strip hit by the piston (exact: a plane front carrying
-rho0 c_p v) and the gravity column's section means (exact at rest:
-rho0 g (H - y)) -- and requests of 10, 5, 3 and 2 % in both norms:

- the planner's answer is run and its error measured against the answer:
  at most the request (or the planner refused);
- its predicted wall time against the measured one (within +-30 %);
- an exhaustive sweep (every candidate setting at a list of spacings)
  gives the cheapest setting that met the request: the chosen one may
  cost at most 1.5 times that;
- the per-run error estimate (shadow runs at 2 dx and 4 dx) against the
  actual error of each probe over each window: within a factor [1, 3] in
  at least 90 % of the cases.

Every run is the library's; this module compares and writes. Runs use one
thread by default: on a shared 2-core machine two spinning OpenMP threads
were measured up to 40x slower. Timings depend on the machine's load.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time as wallclock
from pathlib import Path

import numpy as np

# before the library (and its OpenMP runtime) is loaded: threads that
# wait at a barrier sleep rather than spin on the shared machine
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

from sphsolid import metrics, scenes  # noqa: E402
from sphsolid import planner  # noqa: E402
from sphsolid.planner import record as record_module  # noqa: E402
from sphsolid.probes import PAPER_PROBES  # noqa: E402

REQUESTS = (0.10, 0.05, 0.03, 0.02)
#: The scenes of the checks, in the document's order (held-out ones are
#: marked by their results' "held_out")
SCENE_ORDER = ("piston", "strip", "gravity", "strip_tension", "piston_nu045",
               "piston_squat", "piston_slender", "cylinder")
NORMS = ("max", "rms")


# ------------------------------------------------------------ references
def fe_reference(out: Path, until: float, sizes=(2e-3, 1e-3), log=print):
    """The FE von Mises series at A, B, C on a 0.1 us grid, per element
    size, computed once and kept in ``out/fe_piston_<size>mm.npz`` (delete
    them to recompute). Returns {"grid", "sizes", "fe<size>mm_<probe>",
    "fe<size>mm_wall"}."""
    from validation import fe_reference as fe
    grid = np.linspace(0.0, until, int(round(until / 1e-7)) + 1)
    rock = scenes.paper_material()
    arrays = {"grid": grid, "sizes": np.array(sizes)}
    for size in sizes:
        tag = f"fe{size * 1e3:g}mm"
        path = out / f"fe_piston_{size * 1e3:g}mm.npz"
        data = np.load(path) if path.exists() else None
        if data is None or float(data["grid"][-1]) < until - 1e-12:
            log(f"finite elements {size * 1e3:g} mm ...")
            r = fe.piston_fe(size, until, 0.25e-6 * size / 2e-3, grid,
                             PAPER_PROBES, rock.K, rock.mu, rock.rho0,
                             scenes.PISTON_SPEED)
            np.savez_compressed(path, grid=grid, wall=r["wall"],
                                **{n: r["vm"][n] for n in "ABC"})
            data = np.load(path)
        for n in "ABC":
            arrays[f"{tag}_{n}"] = np.interp(grid, data["grid"], data[n])
        arrays[f"{tag}_wall"] = float(data["wall"])
    return arrays


class Scene:
    """A scene of the checks: its planner spec and its reference."""

    def __init__(self, name, spec, reference, sweep, window=None,
                 until=None, note="", quick_rows=None):
        self.name, self.spec = name, spec
        self.quick_rows = quick_rows        # the quick mode's sample, if
        #                                     not QUICK_ROWS
        self.reference = reference          # grid -> {probe: series}
        self.sweep = sweep                  # spacings of the sweep
        self.until = until or spec.until
        self.window = window or (0.0, self.until)
        self.note = note

    def error(self, run: planner.LadderRun, norm: str,
              window=None) -> float:
        t0, t1 = window or self.window
        grid = metrics.time_grid(t0, t1)
        ref = self.reference(grid)
        series = {n: metrics.on_grid(run.times, run.series[n], grid)
                  for n in ref}
        return metrics.worst_deviation(series, ref, grid, norm)


#: Where the repository keeps the FE series (the held-out scenes' are
#: read from there too, validation/record.py).
KEPT_FE = Path(__file__).resolve().parent.parent / "docs" / "accuracy"


def piston_scene(out, quick, log) -> Scene:
    until = 0.3e-3
    # the fine FE series take hours: the finest kept one is the reference
    # (0.5 mm, else 1 mm; quick mode without either: 2 mm), the next
    # coarser one shows its convergence. An --out without them reads the
    # repository's: the 2 mm mesh differs from the 0.5 mm one by 2.35 %
    # (max), as much as a 2.5 % request, and measured against it the
    # planner's 0.31 mm plan for max 2.5 % (1.98 % from the 0.5 mm mesh)
    # erred 2.9 %
    if (not (out / "fe_piston_0.5mm.npz").exists()
            and (KEPT_FE / "fe_piston_0.5mm.npz").exists()):
        log(f"FE reference: {out} has no fe_piston_0.5mm.npz; reading the "
            f"kept series of {KEPT_FE}")
        out = KEPT_FE
    if (out / "fe_piston_0.5mm.npz").exists():
        sizes = (1e-3, 0.5e-3)
    elif quick and not (out / "fe_piston_1mm.npz").exists():
        sizes = (4e-3, 2e-3)
    else:
        sizes = (2e-3, 1e-3)
    data = fe_reference(out, until, sizes=sizes, log=log)
    grid0 = data["grid"]
    finest = f"fe{min(data['sizes']) * 1e3:g}mm"

    def reference(grid):
        return {n: np.interp(grid, grid0, data[f"{finest}_{n}"])
                for n in "ABC"}
    spec = planner.project_scenes()["piston"]
    coarse = f"fe{max(data['sizes']) * 1e3:g}mm"
    g = data["grid"]
    own = {norm: metrics.worst_deviation(
        {n: data[f"{coarse}_{n}"] for n in "ABC"},
        {n: data[f"{finest}_{n}"] for n in "ABC"}, g, norm)
        for norm in NORMS}
    note = (f"Reference: the finite-element solution of "
            f"validation/fe_reference.py (9-node quadratic quads, "
            f"{min(data['sizes']) * 1e3:g} mm elements, implicit Newmark), "
            f"kept in docs/accuracy/fe_piston_*.npz. Its own convergence: "
            f"the {max(data['sizes']) * 1e3:g} mm mesh differs from it by "
            f"{own['max'] * 100:.2f} % (max) and {own['rms'] * 100:.2f} % "
            "(RMS) in the metric below, so errors much below that are not "
            "resolved by this reference. Metric of the accuracy front: "
            "both series smoothed with a 1 us Gaussian; max deviation over "
            "the reference's peak, or RMS deviation over its RMS; worst "
            "of A, B, C.")
    sweep = (3e-3, 2e-3, 1.5e-3, 1e-3, 0.75e-3) if quick else (
        3e-3, 2e-3, 1.5e-3, 1e-3, 0.75e-3, 0.5e-3)
    return Scene("piston", spec, reference, sweep, until=until, note=note)


def strip_scene(out, quick, log, pulled: bool = False) -> Scene:
    """The strip hit by the piston (``strip``), or pulled by it
    (``strip_tension``: the front's stress jump changes sign)."""
    name = "strip_tension" if pulled else "strip"
    spec = planner.project_scenes()[name]
    rock = scenes.paper_material()
    jump = (1.0 if pulled else -1.0) * rock.rho0 * rock.c_p * scenes.PISTON_SPEED

    def reference(grid):
        # the front leaves the piston face at t = 0 at c_p (exact)
        return {n: np.where(grid > (planner.STRIP_HEIGHT - y) / rock.c_p,
                            jump, 0.0)
                for n, (_, y) in planner.STRIP_PROBES.items()}
    sweep = (2e-3, 1.4e-3, 1e-3, 0.7e-3, 0.5e-3, 0.35e-3, 0.25e-3)
    return Scene(name, spec, reference, sweep)


def gravity_scene(out, quick, log) -> Scene:
    spec = planner.project_scenes()["gravity"]
    rock = scenes.paper_material()
    H = scenes.SPECIMEN_Y[1]
    until = 2.5e-3

    def reference(grid):
        return {n: np.full_like(grid, -rock.rho0 * 9.81 * (H - y))
                for n, y in planner.GRAVITY_SECTIONS.items()}
    sweep = (8e-3, 6e-3, 4e-3, 3e-3, 2e-3)
    return Scene("gravity", spec, reference, sweep, until=until,
                 window=(0.5 * until, until),
                 note="section means of sigma_yy at y = 35, 70, 105 mm "
                 "over 1.25-2.5 ms (damped at c_p/L = 1.98e4 /s: every mode "
                 "has decayed by e^-12 at 1.25 ms, the series are flat). "
                 "The section mean at a height is the mean of the two "
                 "particle rows that meet at the cut, interpolated between "
                 "cuts (plan.gravity_sections): the static SPH field "
                 "alternates from row to row by 1-5 % of the weight (the "
                 "kernel-sum divergence does not see that mode), and "
                 "single-row means picked up a share of it that jumped "
                 "with where the height fell between rows (8.1, 1.2, 3.8, "
                 "0.8, 2.1 % at 8, 6, 4, 3, 2 mm with h/dx 1.5 instead of "
                 "a convergence).")


# --------------------------------------------------------------- checks
#: The rows of the checks: (norm, request, threads). Every row plans with
#: the CLI's own defaults (:data:`PLAN_DEFAULTS`: its default candidates,
#: no calibration budget, no time budget); the quick mode samples rows,
#: never a narrower candidate set.
ROWS = tuple((norm, request, threads) for threads in (1, 2)
             for norm in NORMS for request in REQUESTS) + (
    ("rms", 0.01, 1), ("max", 0.025, 1), ("max", 0.025, 2))
QUICK_ROWS = (("max", 0.05, 1), ("max", 0.03, 1), ("rms", 0.03, 1),
              ("max", 0.025, 1), ("rms", 0.10, 1), ("max", 0.03, 2))
#: The quick mode's sample on the 3D cylinder: 10, 5 and 3 % (its
#: sweep's finest level, 3 mm, errs 5 %, a 15 CPU s run with the
#: leapfrog; a 3 % plan runs at about 2 mm, 5x that).
QUICK_ROWS_3D = (("rms", 0.10, 1), ("max", 0.10, 1), ("max", 0.05, 1),
                 ("max", 0.05, 2), ("max", 0.03, 1), ("rms", 0.03, 1))
#: The keyword arguments of :func:`sphsolid.planner.plan` that decide what
#: is planned, as ``sphsolid plan`` passes them (tests/python/
#: test_accuracy_checks.py checks that the CLI passes the same).
PLAN_DEFAULTS = {"options": None, "candidates": None, "detect": True,
                 "calibration_seconds": None, "max_seconds": None,
                 "record": True}


#: A planned run shorter than this (CPU seconds) is timed as the median
#: of three runs (:func:`timed`).
SHORT_RUN_SECONDS = 1.0


def timed(run, again, repeats: int = 3) -> tuple[float, float]:
    """(wall, CPU) seconds of a planned run: its own, or for a run shorter
    than :data:`SHORT_RUN_SECONDS` of CPU the medians of ``repeats`` runs
    (``again()`` runs it once more). On the shared 2-core machine five
    runs of one 0.25 s strip run took 0.24-0.29 CPU s, and single runs of
    it in the checks up to 0.33 s: one timing of a run that short says
    more about the machine than about the prediction."""
    if run.failed or not run.cpu < SHORT_RUN_SECONDS:
        return run.wall, run.cpu
    runs = [run] + [again() for _ in range(repeats - 1)]
    runs = [r for r in runs if not r.failed]
    return (float(np.median([r.wall for r in runs])),
            float(np.median([r.cpu for r in runs])))


def run_checks(scene: Scene, rows_to_run, log) -> dict:
    """Plan each (norm, request, threads) row the way ``sphsolid plan``
    does, run the plan and measure its error against the scene's answer;
    then the exhaustive sweep of the candidates."""
    from sphsolid.planner.cache import RunCache
    spec = scene.spec
    # one cache per scene for the plans (a user's second request on a
    # scene reuses the first one's runs), kept in memory: every check
    # starts from nothing on disk; the sweep also reads the verification
    # record's runs (python -m validation.record) where they are kept
    cache = RunCache(scene.name, root=None)
    record_runs = RunCache(f"record:{scene.name}")
    rows, sweep_rows = [], []
    plans = {}
    for norm, request, threads in rows_to_run:
        log(f"{scene.name}: plan {norm} {request * 100:g} % on {threads} "
            "thread(s) ...")
        start = wallclock.perf_counter()
        p = planner.plan(spec.factory, error=request, until=scene.until,
                         probes=spec.probes, quantity=spec.quantity,
                         norm=norm, threads=threads, ladder=spec.ladder,
                         window=scene.window, cache=cache, scene=scene.name,
                         log=log, **PLAN_DEFAULTS)
        plans[(norm, request, threads)] = p
        row = {"norm": norm, "request": request, "threads": threads,
               "feasible": p.feasible,
               "plan_seconds": wallclock.perf_counter() - start}
        if p.feasible:
            def planned(p=p, threads=threads):
                return planner.ladder_run(spec.factory, p.dx, p.setting,
                                          scene.until, spec.probes,
                                          spec.quantity, threads)
            run = planned()
            wall, cpu = timed(run, planned)
            row.update(setting=p.setting.label(), dx=p.dx,
                       predicted_error=p.predicted_error,
                       error_upper=p.error_upper,
                       achieved=(scene.error(run, norm)
                                 if not run.failed else math.inf),
                       predicted_seconds=p.predicted_seconds,
                       measured_seconds=wall,
                       predicted_cpu=p.predicted_cpu_seconds,
                       measured_cpu=cpu,
                       particle_steps=run.particles * run.steps,
                       load=os.getloadavg()[0])
        else:
            row.update(reason=p.reason,
                       best_reachable=p.best_reachable_error)
        rows.append(row)
        log(f"  {row}")
    threads = 1
    # what planning cost: the calibration runs (shared by the requests
    # through the cache) and the wall time of the planner calls
    ladder_runs = [v for v in cache.values()
                   if isinstance(v, planner.LadderRun)]
    planning = {"runs": len(ladder_runs),
                "cpu": sum(r.cpu for r in ladder_runs
                           if math.isfinite(r.cpu)),
                "wall": sum(r["plan_seconds"] for r in rows)}
    # exhaustive sweep over the candidates the planner considered
    settings = []
    for p in plans.values():
        for c in p.candidates:
            if c.setting not in settings:
                settings.append(c.setting)
    for setting in settings:
        for dx in scene.sweep:
            key = (float(f"{dx:.6g}"), setting, float(scene.until),
                   spec.quantity, threads)
            run = cache.get(key) or record_runs.get(key)
            if run is not None:
                cache[key] = run
            if run is None:
                log(f"{scene.name}: sweep {setting.label()} dx = "
                    f"{dx * 1e3:g} mm ...")
                run = planner.ladder_run(spec.factory, dx, setting,
                                         scene.until, spec.probes,
                                         spec.quantity, threads)
                cache[key] = run
            if run.failed:
                continue
            sweep_rows.append({
                "setting": setting.label(),
                "family": record_module.family(setting), "dx": dx,
                "wall": run.wall,
                "cpu": run.cpu,
                "particle_steps": run.particles * run.steps,
                **{norm: scene.error(run, norm) for norm in NORMS}})
    self_certify(scene, settings, cache, sweep_rows, threads)
    # CPU seconds per particle-step of each setting (median over its sweep
    # runs of 10^5 particle-steps or more): the cost of a run in CPU time
    # is its particle-steps times its setting's rate
    rate = {}
    for s in sweep_rows:
        if s["particle_steps"] >= 1e5 and math.isfinite(s["cpu"]):
            rate.setdefault(s["setting"], []).append(
                s["cpu"] / s["particle_steps"])
    rate = {k: float(np.median(v)) for k, v in rate.items()}
    for s in sweep_rows:
        s["cpu_cost"] = s["particle_steps"] * rate.get(s["setting"], math.nan)
    for row in rows:
        if row["feasible"]:
            row["cpu_cost"] = row["particle_steps"] * rate.get(row["setting"],
                                                               math.nan)
        meeting = [s for s in sweep_rows if s[row["norm"]] <= row["request"]]
        if meeting:
            best = min(meeting, key=lambda s: s["particle_steps"])
            fastest = min(meeting, key=lambda s: s["wall"])
            cheapest_cpu = min(meeting, key=lambda s: s["cpu_cost"])
            known = [w for w in meeting
                     if (w.get("certified") or {}).get(row["norm"]) is not None
                     and w["certified"][row["norm"]] <= row["request"]]
            if known:
                least = min(known, key=lambda w: w["particle_steps"])
                row.update(certified_cheapest=least["setting"],
                           certified_cheapest_dx=least["dx"],
                           certified_cheapest_particle_steps=least[
                               "particle_steps"])
            row.update(sweep_cheapest=best["setting"],
                       sweep_cheapest_dx=best["dx"],
                       sweep_cheapest_particle_steps=best["particle_steps"],
                       sweep_fastest_wall=fastest["wall"],
                       sweep_cheapest_cpu=cheapest_cpu["setting"],
                       sweep_cheapest_cpu_dx=cheapest_cpu["dx"],
                       sweep_cheapest_cpu_cost=cheapest_cpu["cpu_cost"])
    planning["sweep_cpu"] = sum(w["cpu"] for w in sweep_rows
                                if math.isfinite(w["cpu"]))
    planning["sweep_runs"] = len(sweep_rows)
    # every calibration the planner fitted (per norm, setting and ladder):
    # the per-run estimate of a setting uses the one nearest its run
    calibrations = []
    for (norm, *_), p in plans.items():
        for c in p.candidates:
            if c.model is None:
                continue
            entry = {"norm": norm, "setting": c.setting.label(),
                     "model": c.model.to_dict()}
            if entry not in calibrations:
                calibrations.append(entry)
    return {"rows": rows, "sweep": sweep_rows, "planning": planning,
            "calibrations": calibrations,
            "findings": [f.to_dict() for f in
                         next(iter(plans.values())).findings]}


def self_certify(scene: Scene, settings, cache, sweep_rows, threads) -> None:
    """What self-convergence alone certifies in the sweep: for each sweep
    run with three coarser sweep levels of its setting, the planner's
    error model (:func:`sphsolid.planner.fit_error_model`: Eça & Hoekstra,
    order at most 1, the differences of the four levels ending at it, on
    its own scale, over the checks' window) and its upper bound at that
    spacing, per norm, as ``certified`` in the sweep row (None where the
    sweep has fewer coarser levels or the levels do not differ). This is
    the most any planner that sees only the user's scene could promise for
    that run (without a floor from other settings); the sweep's errors
    against the trusted answer are what no planner sees."""
    spec = scene.spec
    t0, t1 = scene.window
    grid = metrics.time_grid(t0, t1)
    for setting in settings:
        levels = []
        for dx in scene.sweep:
            key = (float(f"{dx:.6g}"), setting, float(scene.until),
                   spec.quantity, threads)
            run = cache.get(key)
            if run is None or run.failed:
                continue
            levels.append((dx, {n: metrics.smooth(grid, metrics.on_grid(
                run.times, run.series[n], grid)) for n in run.series}))
        for row in sweep_rows:
            if row["setting"] != setting.label():
                continue
            row["certified"] = {norm: None for norm in NORMS}
            index = [i for i, (dx, _) in enumerate(levels)
                     if dx == row["dx"]]
            if not index or index[0] < 3:
                continue
            four = levels[index[0] - 3:index[0] + 1]
            for norm in NORMS:
                scales = {n: metrics.scale_of(v, norm)
                          for n, v in four[-1][1].items()}

                def distance(a, b):
                    return max(metrics.deviation(a[n], b[n], norm,
                                                 scales[n]) for n in a)
                series = [v for _, v in four]
                diffs = [distance(a, b) for a, b in zip(series, series[1:])]
                spread = max(distance(series[i], series[j])
                             for i in range(4) for j in range(i + 1, 4))
                try:
                    model = planner.fit_error_model(
                        [dx for dx, _ in four], diffs, 0.0, spread=spread,
                        max_order=planner.FORMAL_ORDER)
                except ValueError:
                    continue
                row["certified"][norm] = model.upper(row["dx"])


def nearest_calibration(calibrations, setting, norm, dx):
    """The error model the planner fitted for ``setting`` in ``norm`` that
    the estimate can use (:func:`sphsolid.planner.estimate.calibrated_order`: well
    determined, no floor) before one it cannot, then the one whose ladder
    reaches closest to the 2 dx shadow of a run at ``dx`` (its coarsest
    level nearest 2 dx, then its finest nearest dx), or None. The planner
    calibrates a setting on several ladders (a coarse one, and finer ones
    for the settings it refines, among them those whose coarse ladder did
    not determine an order); a run's estimate uses the one that determines
    the order, nearest its shadow."""
    from sphsolid.planner.estimate import calibrated_order
    label = setting.label()
    best = None
    for entry in calibrations or []:
        if entry["setting"] != label or entry["norm"] != norm:
            continue
        spacings = [level[0] for level in entry["model"]["levels"]]
        key = (calibrated_order(entry["model"]) is None,
               abs(math.log(max(spacings) / (2 * dx))),
               abs(math.log(min(spacings) / dx)))
        if best is None or key < best[0]:
            best = (key, entry["model"])
    return None if best is None else best[1]


def estimate_checks(scene: Scene, settings, spacings, windows, threads,
                    log, calibrations=None) -> list:
    """Per-run estimate against the actual error, per probe and window.
    The estimate of each norm uses the planner's calibration of the setting
    in that norm (:func:`nearest_calibration`; its order when well
    determined, else the two-grid rule), from the same shadow runs."""
    from sphsolid import Probes
    from sphsolid.planner.estimate import ErrorEstimate
    spec = scene.spec
    cases = []
    for setting in settings:
        for dx in spacings:
            log(f"{scene.name}: estimate {setting.label()} dx = "
                f"{dx * 1e3:g} mm ...")
            built = planner.build_scene(spec.factory, dx, setting, threads)
            probes = Probes(built, spec.probes)
            dyn = planner.make_dynamics(built, setting.integrator,
                                        progress=False)
            dyn.attach(probes, interval=max(1, int(2.5e-7 / dyn.dt)))
            start = wallclock.perf_counter()
            dyn.run(until=scene.until)
            wall = wallclock.perf_counter() - start
            shadows: dict = {}
            estimates = {}
            for norm in NORMS:
                estimates[norm] = ErrorEstimate(
                    probes, threads=threads, integrator=setting.integrator,
                    scene_factory=lambda d, s=setting: planner.build_scene(
                        spec.factory, d, s, threads),
                    calibration=nearest_calibration(calibrations, setting,
                                                    norm, dx),
                    shadows=shadows).compute()
            for t0, t1 in windows:
                grid = metrics.time_grid(t0, t1)
                ref = scene.reference(grid)
                for name in probes.names:
                    values = probes[name][spec.quantity]
                    run = metrics.smooth(grid, np.interp(grid, probes.times,
                                                         values))
                    exact = metrics.smooth(grid, ref[name])
                    for norm in NORMS:
                        est = estimates[norm]
                        band = np.interp(grid, probes.times,
                                         est.bands[name][spec.quantity])
                        scale = metrics.scale_of(exact, norm)
                        if scale <= 0:      # nothing arrived in the window
                            continue
                        actual = metrics.deviation(run, exact, norm)
                        if norm == "max":
                            estimated = float(np.max(band)) / scale
                        else:
                            estimated = float(np.sqrt(np.mean(band ** 2))
                                              ) / scale
                        cases.append({
                            "setting": setting.label(), "dx": dx,
                            "probe": name, "window": [t0, t1], "norm": norm,
                            "actual": actual, "estimated": estimated,
                            "ratio": estimated / actual if actual else
                            math.inf,
                            "order": est.order[spec.quantity],
                            "observed_order":
                                est.observed_order[spec.quantity],
                            "safety": est.safety[spec.quantity],
                            "oscillatory": bool(
                                est.oscillatory[spec.quantity]),
                            "calibrated_order": est.calibrated,
                            "shadow_seconds":
                                estimates[NORMS[0]].shadow_seconds,
                            "run_seconds": wall})
    return cases


# ------------------------------------------------------------ document
def _power_law(x0, x1, x, y0, y1):
    """y at x on the power law through (x0, y0) and (x1, y1): error and
    cost are both taken as powers of dx between two sweep levels."""
    t = math.log(x / x0) / math.log(x1 / x0)
    return math.exp((1 - t) * math.log(y0) + t * math.log(y1))


def _levels(sweep, setting, keys):
    """The sweep rows of ``setting`` from the coarsest spacing, or None
    when one of them lacks a finite positive value of one of ``keys``."""
    rows = sorted((w for w in sweep if w["setting"] == setting),
                  key=lambda w: -w["dx"])
    if not all(math.isfinite(w.get(key, math.nan)) and w[key] > 0
               for w in rows for key in keys):
        return None
    return rows


def margin_cost(sweep, norm, request, safety=planner.SAFETY_GOOD,
                cost="particle_steps"):
    """What the safety factor alone costs: the particle-steps a planner
    would need if its central prediction were each setting's error
    against the trusted answer (known only to the sweep) and it kept the
    margin ``safety`` (Eça & Hoekstra's least, 1.25). Per setting, walking
    from its coarsest sweep level, the first spacing where ``safety x
    error <= request``: that level's particle-steps if it is the coarsest,
    else the power law through the two levels that bracket it (in error
    and in particle-steps). Returns (particle-steps, setting), the
    cheapest over the settings, or None when no level of any setting has
    the margin (the request lies beyond the sweep).

    ``safety`` may instead map setting labels to their margins (a setting
    it leaves out is not considered), and ``cost`` names the sweep rows'
    cost to compare ("particle_steps" or "cpu_cost")."""
    best = None
    for setting in dict.fromkeys(w["setting"] for w in sweep):
        margin_of = (safety.get(setting) if isinstance(safety, dict)
                     else safety)
        if margin_of is None:
            continue
        rows = _levels(sweep, setting, (cost,))
        if rows is None:
            continue
        margin = [margin_of * w[norm] for w in rows]
        for k, w in enumerate(rows):
            if margin[k] > request:
                continue
            value = float(w[cost])
            if k > 0:
                value = _power_law(margin[k - 1], margin[k], request,
                                   rows[k - 1][cost], w[cost])
            if best is None or value < best[0]:
                best = (value, setting)
            break
    return best


def record_margin_cost(sweep, norm, request, record=None):
    """Issue 32's item 5 measure: the CPU cost at which the cheapest
    setting the verification record lets the planner choose for this
    request (verified in ``norm``, ratio at most 1, bias below the
    request) meets it with the record's margin, its factor times its true
    error at most the request (:func:`margin_cost` with each setting's
    factor). Returns (CPU seconds, setting) or None (no such setting in
    the sweep, or sweep rows without their record family)."""
    record = record if record is not None else record_module.shipped()
    if record is None:
        return None
    return margin_cost(sweep, norm, request,
                       record_factors(sweep, norm, request, record),
                       cost="cpu_cost")


def record_factors(sweep, norm, request, record=None) -> dict:
    """The record's factor of each sweep setting the planner may choose
    for this request (verified in ``norm``, not refused by
    :func:`sphsolid.planner.record.refusal`), by setting label."""
    record = record if record is not None else record_module.shipped()
    factors = {}
    for w in sweep if record is not None else ():
        verdict = (record.verdict(w["family"], norm) if w.get("family")
                   else None)
        if verdict and record_module.refusal(verdict, request) is None:
            factors[w["setting"]] = verdict["factor"]
    return factors


def two_x_bound(sweep, norm, request, factors, within=2.0,
                cost="cpu_cost"):
    """Issue 32's item 5 set against the planner's honesty: the largest
    ratio of a plan's error bound to its true error with which a plan can
    cost at most ``within`` times the cheapest the record allows
    (:func:`margin_cost` at the record's ``factors``) and still meet the
    request. Per setting the planner may choose, the spacing whose cost
    is ``within`` times that cheapest (power laws in dx between the
    sweep's levels, as :func:`margin_cost` interpolates), its true error
    e there, and request / (factor x e): a plan of that setting within
    the cost keeps its promise only if its bound over its true error is
    at most that. When the cost lies past the setting's finest level,
    that level's error is used (its ratio is then a lower bound). Returns
    (the largest ratio over the settings, its setting, whether it is only
    a lower bound), or None when the record allows no setting of the sweep
    that meets the request."""
    cheapest = margin_cost(sweep, norm, request, factors, cost=cost)
    if cheapest is None:
        return None
    budget = within * cheapest[0]
    best = None
    for setting, factor in factors.items():
        rows = _levels(sweep, setting, (cost, norm))
        inside = [k for k, w in enumerate(rows or []) if w[cost] <= budget]
        if not inside:
            continue
        k = inside[-1]
        error, past = rows[k][norm], k + 1 == len(rows)
        if not past:
            error = _power_law(rows[k][cost], rows[k + 1][cost], budget,
                               rows[k][norm], rows[k + 1][norm])
        ratio = request / (factor * error)
        if best is None or ratio > best[0]:
            best = (ratio, setting, past)
    return best


def central_spread(results) -> dict:
    """Per (planned setting, norm): the true error over the planner's
    central prediction in every planned row of ``results`` (all scenes),
    as (smallest, largest, rows)."""
    spread = {}
    for result in results.values():
        for r in result.get("rows", []):
            if not (r.get("feasible") and r.get("predicted_error")
                    and r.get("achieved") is not None):
                continue
            ratio = r["achieved"] / r["predicted_error"]
            lo, hi, n = spread.get((r["setting"], r["norm"]),
                                   (math.inf, 0.0, 0))
            spread[(r["setting"], r["norm"])] = (min(lo, ratio),
                                                 max(hi, ratio), n + 1)
    return spread


def item5_text(results) -> str:
    """The rows whose plans cost more than 2x the cheapest the record
    allows (or are refused though that setting meets them), each with
    :func:`two_x_bound` and the spread of the planned setting's central
    prediction (:func:`central_spread`)."""
    spread = central_spread(results)
    rows = []
    for name in SCENE_ORDER:
        result = results.get(name) or {}
        sweep = result.get("sweep") or []
        for r in result.get("rows", []):
            allowed = _allowed_ratio(r, sweep)
            if allowed is None or (allowed[0] is not None
                                   and allowed[0] <= 2.0):
                continue
            factors = record_factors(sweep, r["norm"], r["request"])
            bound = two_x_bound(sweep, r["norm"], r["request"], factors)
            lo, hi, n = spread.get((r.get("setting"), r["norm"]),
                                   (None, None, 0))
            rows.append([
                name + (" (held out)" if result.get("held_out") else ""),
                r["norm"], f"{r['request'] * 100:g} %",
                str(r.get("threads", "-")),
                "refused" if allowed[0] is None else f"{allowed[0]:.2f}",
                allowed[1],
                "-" if bound is None else ("at least " if bound[2] else "")
                + f"{bound[0]:.3f} ({bound[1]})",
                "-" if not n else f"{r['setting']}: {lo:.3f}-{hi:.3f} "
                f"({n} rows; {hi / lo:.2f}x)"])
    if not rows:
        return ""
    return (ITEM5_NOTE + "\n" + _table(
        ["scene", "norm", "request", "threads",
         "CPU cost / cheapest the record "
         "allows", "that setting", "bound / true error a plan within 2x "
         "may keep (its setting)", "planned setting: true / central "
         "prediction over every planned row of its norm (spread)"], rows))


ITEM5_NOTE = """## Item 5 against honesty

The rows whose plan costs more than twice the cheapest setting the
record allows (at its record factor times its true error, known only to
the sweep), or is refused though that setting meets it. *Bound / true
error a plan within 2x may keep*: a plan that costs at most twice that
cheapest runs at a spacing where the setting's true error is e (the
sweep's levels, power laws between them); it meets the request only if
its promised bound, the record factor times the planner's upper
prediction, is at most request / e, that is at most this ratio times its
true error (`two_x_bound`; "at least" where twice the cost lies past the
sweep's finest level, whose error is then used). The planner's upper prediction is its central
one times a safety factor of at least 1.25 (Eça & Hoekstra); the last
column shows how far the central prediction itself wandered about the
true error over every row that planned the same setting in the same norm:
a bound that is honest on each of those rows is, on the row where the
central prediction over-stated most, at least the spread's ratio times
the true error.
"""


def _pct(x):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) \
        else f"{x * 100:.2f} %"


def _cpu_error(r):
    """Measured over predicted CPU seconds minus one (None if either is
    missing)."""
    p, m = r.get("predicted_cpu"), r.get("measured_cpu")
    if not p or m is None or not math.isfinite(m):
        return None
    return m / p - 1


def _table(header, rows) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def _margin_ratio(row, sweep):
    """:func:`margin_cost` over the sweep's cheapest that met the request
    (None when either is missing)."""
    if not sweep or not row.get("sweep_cheapest_particle_steps"):
        return None
    cost = margin_cost(sweep, row["norm"], row["request"])
    return (None if cost is None
            else cost[0] / row["sweep_cheapest_particle_steps"])


def _allowed_ratio(row, sweep, record=None):
    """(planned CPU cost over :func:`record_margin_cost`, that setting),
    (None, setting) for a refusal that setting would have met, or None
    when the record allows no setting of the sweep that meets the
    request at its margin."""
    if not any("family" in w for w in sweep):
        return None
    cheapest = record_margin_cost(sweep, row["norm"], row["request"],
                                  record)
    if cheapest is None:
        return None
    if not row["feasible"]:
        return (None, cheapest[1])
    cost = row.get("cpu_cost")
    if cost is None or not math.isfinite(cost):
        return None
    return (cost / cheapest[0], cheapest[1])


def _allowed_text(allowed) -> str:
    if allowed is None:
        return "-"
    ratio, setting = allowed
    if ratio is None:
        return f"refused, **met by** {setting}"
    return f"{ratio:.2f}" + ("" if ratio <= 2.0 else " **") + f" ({setting})"


def scene_text(name, result) -> str:
    rows = []
    for r in result["rows"]:
        if r["feasible"]:
            ok = "yes" if r["achieved"] <= r["request"] else "**no**"
            wall = r["measured_seconds"] / r["predicted_seconds"] - 1
            cpu = _cpu_error(r)
            cost = (r["particle_steps"] / r["sweep_cheapest_particle_steps"]
                    if "sweep_cheapest_particle_steps" in r else None)
            cost_cpu = (r["cpu_cost"] / r["sweep_cheapest_cpu_cost"]
                        if r.get("sweep_cheapest_cpu_cost") else None)
            known = (r["particle_steps"]
                     / r["certified_cheapest_particle_steps"]
                     if r.get("certified_cheapest_particle_steps") else None)
            margin = _margin_ratio(r, result.get("sweep") or [])
            allowed = _allowed_ratio(r, result.get("sweep") or [])
            rows.append([
                r["norm"], f"{r['request'] * 100:g} %",
                str(r.get("threads", "-")),
                f"{r.get('plan_seconds', math.nan):.0f}", r["setting"],
                f"{r['dx'] * 1e3:.3g}", _pct(r["predicted_error"]),
                _pct(r["error_upper"]), _pct(r["achieved"]), ok,
                f"{r['predicted_seconds']:.3g}",
                f"{r['measured_seconds']:.3g}",
                f"{wall * 100:+.0f} %" + ("" if abs(wall) <= 0.3 else " **"),
                "-" if cpu is None else
                f"{r['predicted_cpu']:.3g} / {r['measured_cpu']:.3g} "
                f"({cpu * 100:+.0f} %" + (")" if abs(cpu) <= 0.3
                                          else ") **"),
                "-" if cost is None else
                f"{cost:.2f}" + ("" if cost <= 1.5 else " **"),
                "-" if cost_cpu is None else
                f"{cost_cpu:.2f}" + ("" if cost_cpu <= 1.5 else " **"),
                "-" if "sweep_cheapest" not in r else
                f"{r['sweep_cheapest']} @ {r['sweep_cheapest_dx'] * 1e3:g}",
                "-" if known is None else f"{known:.2f} ("
                f"{r['certified_cheapest']} @ "
                f"{r['certified_cheapest_dx'] * 1e3:g})",
                "-" if margin is None else f"{margin:.2f}"
                + ("" if margin <= 1.5 else " **"),
                _allowed_text(allowed)])
        else:
            rows.append([r["norm"], f"{r['request'] * 100:g} %",
                         str(r.get("threads", "-")),
                         f"{r.get('plan_seconds', math.nan):.0f}",
                         "refused: " + r["reason"].replace("|", "/"),
                         "-", "-", _pct(r.get("best_reachable")), "-",
                         "refused", "-", "-", "-", "-", "-", "-",
                         "-" if "sweep_cheapest" not in r else
                         f"{r['sweep_cheapest']} @ "
                         f"{r['sweep_cheapest_dx'] * 1e3:g}",
                         "-" if "certified_cheapest" not in r else
                         f"({r['certified_cheapest']} @ "
                         f"{r['certified_cheapest_dx'] * 1e3:g})", "-",
                         _allowed_text(_allowed_ratio(
                             r, result.get("sweep") or []))])
    text = _table(["norm", "request", "threads", "planning [s]",
                   "planned setting", "dx [mm]",
                   "predicted", "upper", "achieved", "<= request",
                   "predicted wall [s]", "measured wall [s]", "wall error",
                   "CPU predicted / measured [s]",
                   "particle-steps / cheapest", "CPU cost / cheapest",
                   "cheapest in the sweep (dx mm)",
                   "particle-steps / cheapest self-certified (setting @ dx "
                   "mm)", "exact prediction with Fs 1.25: particle-steps / "
                   "cheapest", "CPU cost / cheapest the record allows, at "
                   "its margin (setting)"], rows)
    sweep = result.get("sweep") or []
    if sweep:
        text += ("\nThe exhaustive sweep (every setting the planner "
                 "considered at the sweep's spacings; errors against the "
                 "trusted answer):\n\n" + _table(
                     ["setting", "dx [mm]", "particle-steps", "CPU [s]",
                      "max", "RMS", "self-certified bound max",
                      "self-certified bound RMS"],
                     [[w["setting"], f"{w['dx'] * 1e3:g}",
                       f"{w['particle_steps']:.3g}",
                       f"{w['cpu']:.3g}" if w.get("cpu") is not None
                       and math.isfinite(w["cpu"]) else "-",
                       _pct(w["max"]), _pct(w["rms"]),
                       _pct((w.get("certified") or {}).get("max")),
                       _pct((w.get("certified") or {}).get("rms"))]
                      for w in sweep]))
    cost = result.get("planning")
    if cost:
        text += (f"\nWhat planning cost (all {len(result['rows'])} requests "
                 f"together, sharing their calibration runs): "
                 f"{cost['wall']:.0f} s wall in the planner (effect "
                 f"detection, {cost['runs']} calibration runs of "
                 f"{cost['cpu']:.1f} CPU s, timing checks); the exhaustive "
                 f"sweep: {cost['sweep_runs']} runs of "
                 f"{cost['sweep_cpu']:.1f} CPU s.\n")
    found = result["findings"]
    effects = ("; ".join(f"{f['effect'] or '-'} ({f['reason']}; "
                         f"{f['measured']})" for f in found) or "none")
    return (f"## {name}\n\n{result.get('note', '')}\n\nEffects found: "
            f"{effects}\n\nWall time of these checks: "
            + (f"{result['wall']:.0f} s" if result.get("wall") else "-")
            + (" (load average {:.1f} at the start, {:.1f} at the end, on "
               "{} cores)".format(*result["load"], os.cpu_count())
               if result.get("load") else "")
            + "\n\n" + text)


def summary_text(results, titles) -> str:
    """One line per scene: how many checks held."""
    lines = ["## Summary\n",
             "| scene | planned | achieved <= request | refused "
             "(sweep also missed) | wall within +-30 % | CPU within "
             "+-30 % | particle-steps <= 1.5x cheapest | CPU cost <= 1.5x "
             "cheapest | particle-steps <= 1.5x cheapest self-certified "
             "| exact prediction with Fs 1.25 <= 1.5x cheapest "
             "| CPU cost <= 2x cheapest the record allows (issue 32, item 5) "
             "| estimate ratio in [1, 3] | planning [s] (median, max) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name in SCENE_ORDER:
        if name not in results:
            continue
        rows = results[name]["rows"]
        planned = [r for r in rows if r["feasible"]]
        refused = [r for r in rows if not r["feasible"]]
        met = sum(r["achieved"] <= r["request"] for r in planned)
        justified = sum("sweep_cheapest" not in r for r in refused)
        wall = sum(abs(r["measured_seconds"] / r["predicted_seconds"] - 1)
                   <= 0.3 for r in planned)
        cost = sum(r.get("sweep_cheapest_particle_steps") is not None
                   and r["particle_steps"]
                   <= 1.5 * r["sweep_cheapest_particle_steps"]
                   for r in planned)
        cpu = sum(_cpu_error(r) is not None and abs(_cpu_error(r)) <= 0.3
                  for r in planned)
        cost_cpu = sum(bool(r.get("sweep_cheapest_cpu_cost"))
                       and r["cpu_cost"] <= 1.5 * r["sweep_cheapest_cpu_cost"]
                       for r in planned)
        compared = sum(r.get("sweep_cheapest_particle_steps") is not None
                       for r in planned)
        margins = [m for m in (_margin_ratio(r, results[name].get("sweep"))
                               for r in rows) if m is not None]
        certified = [r for r in planned
                     if r.get("certified_cheapest_particle_steps")]
        known = sum(r["particle_steps"]
                    <= 1.5 * r["certified_cheapest_particle_steps"]
                    for r in certified)
        allowed = [a for a in (_allowed_ratio(r, results[name].get("sweep")
                                              or []) for r in rows)
                   if a is not None]
        within = sum(a[0] is not None and a[0] <= 2.0 for a in allowed)
        cases = results[name].get("estimate") or []
        inside = sum(1 <= c["ratio"] <= 3 for c in cases)
        # per setting: how many inside, how many above 3 (too cautious)
        # and how many below 1 (the band missed the error)
        per = {}
        for c in cases:
            k = per.setdefault(c["setting"].split(" ")[0] + " h/dx="
                               + c["setting"].split("h/dx=")[1].split(" ")[0],
                               [0, 0, 0, 0])
            k[0] += 1
            k[1] += 1 <= c["ratio"] <= 3
            k[2] += c["ratio"] > 3
            k[3] += c["ratio"] < 1
        detail = "; ".join(f"{k}: {v[1]} of {v[0]} (above 3: {v[2]}, "
                           f"below 1: {v[3]})" for k, v in per.items())
        plan_times = [r["plan_seconds"] for r in rows if "plan_seconds" in r]
        timing = (f"{np.median(plan_times):.0f}, {max(plan_times):.0f}"
                  if plan_times else "-")
        label = name + (" (held out)" if results[name].get("held_out")
                        else "")
        lines.append(
            f"| {label} | {len(planned)} of {len(rows)} | {met} of "
            f"{len(planned)} | {len(refused)} ({justified}) | {wall} of "
            f"{len(planned)} | {cpu} of {len(planned)} | {cost} of "
            f"{compared} | {cost_cpu} of {compared} | {known} of "
            f"{len(certified)} | {sum(m <= 1.5 for m in margins)} of "
            f"{len(margins)} | "
            + (f"{within} of {len(allowed)} | " if allowed else "not "
               "measured (sweep of an earlier version) | ")
            + (f"{inside} of {len(cases)} ({100 * inside / len(cases):.0f} "
               f"%; {detail})" if cases else "not run (section means are not point "
               "probes)" if name == "gravity" else "not run") + f" | {timing} |")
    return "\n".join(lines) + "\n"


def estimate_text(cases) -> str:
    if not cases:
        return ""
    inside = [1 <= c["ratio"] <= 3 for c in cases]
    rows = [[c["setting"], f"{c['dx'] * 1e3:g}", c["probe"],
             f"{c['window'][0] * 1e3:.3g}-{c['window'][1] * 1e3:.3g}",
             c["norm"], _pct(c["actual"]), _pct(c["estimated"]),
             f"{c['ratio']:.2f}" + ("" if 1 <= c["ratio"] <= 3 else " **"),
             f"{c.get('observed_order', math.nan):.2f}"
             + (" (osc.)" if c.get("oscillatory") else ""),
             ("-" if c.get("calibrated_order") is None
              else f"{c['calibrated_order']:.2f}"),
             f"{c['order']:.2f}", f"{c.get('safety', math.nan):g}"]
            for c in cases]
    return (f"{sum(inside)} of {len(cases)} cases "
            f"({100 * sum(inside) / len(cases):.0f} %) within [1, 3] "
            "(target: 90 %).\n\n"
            + _table(["setting", "dx [mm]", "probe", "window [ms]", "norm",
                      "actual", "estimated", "ratio", "observed order",
                      "calibrated order", "order used", "Fs"], rows))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m validation.accuracy",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("docs"))
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--quick", action="store_true",
                      help="the bounded checks (QUICK_NOTE in the module: "
                      "about 6 minutes wall and 6 of CPU on one thread of "
                      "the idle 2-core machine)")
    mode.add_argument("--full", action="store_true",
                      help="every candidate, no time budget, finer sweeps "
                      "(the default; hours)")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--scenes",
                        default="strip,gravity,strip_tension,piston,"
                        "piston_nu045,"
                        "piston_squat,piston_slender,cylinder")
    parser.add_argument("--report", type=Path, default=None,
                        help="the generated report (default: "
                        "validation/reports/accuracy/quick.md with --quick, "
                        "else full.md there); docs/accuracy.md quotes it")
    parser.add_argument("--document-only", action="store_true",
                        help="rewrite the report from accuracy/results.json")
    parser.add_argument("--estimate-only", action="store_true",
                        help="keep the planner checks of results.json, run "
                        "the per-run estimate checks again")
    args = parser.parse_args(argv)
    if args.report is None:
        args.report = REPORTS / ("quick.md" if args.quick else "full.md")
    args.report.parent.mkdir(parents=True, exist_ok=True)
    data = args.out / "accuracy"
    data.mkdir(parents=True, exist_ok=True)
    clock = wallclock.perf_counter()

    def log(message):
        print(f"[{wallclock.perf_counter() - clock:7.1f} s] {message}",
              flush=True)
    results_path = data / "results.json"
    results = (json.loads(results_path.read_text())
               if results_path.exists() else {})
    from validation.record import HELD_OUT, reference_scene
    if args.document_only:
        write_document(args.report, results, args)
        return 0
    visc = {"artificial_viscosity": {"alpha": 1.0, "beta": 0.0}}
    for name in args.scenes.split(","):
        load_start = os.getloadavg()[0]
        scene_start = wallclock.perf_counter()
        scene_cpu = wallclock.process_time()
        scene = reference_scene(name, data, log, quick=args.quick)
        if args.estimate_only and name in results:
            result = results[name]
        else:
            result = run_checks(
                scene, (scene.quick_rows or QUICK_ROWS) if args.quick
                else ROWS, log)
            result["held_out"] = name in HELD_OUT
            result["note"] = scene.note
            results[name] = result
            results_path.write_text(json.dumps(results, indent=1,
                                               default=float))
        # the paper's scheme at both h/dx, and cubic_o4 at its own setting,
        # with the integrator of the planner's candidates (the settings it
        # calibrates, so that each estimate has its calibration)
        o4 = planner.Setting.make(1.65, "cubic_o4", "leapfrog", None,
                                  "static")
        lf = "leapfrog"
        if name == "piston":
            settings = [planner.Setting.make(1.2, integrator=lf,
                                             effects=visc),
                        planner.Setting.make(1.5, integrator=lf,
                                             effects=visc), o4]
            result["estimate"] = estimate_checks(
                scene, settings,
                (3e-3, 2e-3) if args.quick else (2e-3, 1.5e-3, 1e-3),
                [(0.0, 0.15e-3), (0.0, 0.3e-3)], args.threads, log,
                result.get("calibrations"))
        elif name == "strip":
            settings = [planner.Setting.make(1.2, integrator=lf,
                                             effects=visc),
                        planner.Setting.make(1.5, integrator=lf,
                                             effects=visc), o4]
            result["estimate"] = estimate_checks(
                scene, settings, (1e-3, 0.5e-3),
                [(0.0, 0.5 * scene.until), (0.0, scene.until)],
                args.threads, log, result.get("calibrations"))
        if not args.estimate_only:
            result["wall"] = wallclock.perf_counter() - scene_start
            result["elapsed"] = wallclock.perf_counter() - clock
            result["cpu_elapsed"] = wallclock.process_time()
            result["cpu"] = wallclock.process_time() - scene_cpu
            result["load"] = [load_start, os.getloadavg()[0]]
        results[name] = result
        results_path.write_text(json.dumps(results, indent=1, default=float))
        write_document(args.report, results, args)
    log(f"done; wrote {args.report}")
    return 0


#: Where the generated reports go (the quick one and the full mode's, one
#: per scene set); docs/accuracy.md is the hand-written reference.
REPORTS = Path("validation/reports/accuracy")

RECORD_HEADER = """## Verification record

Which settings the planner may choose, and what their predictions are
worth (`python -m validation.record`; the data ships as
`python/sphsolid/planner/record.json`, every prediction and error in
`docs/accuracy/record_raw.json`). Declared before the factors were fitted:
**fitted** on the piston (FE 0.5 mm), the strip (exact) and gravity
(exact at rest); **held out** the piston with nu = 0.45 (FE 1 mm) and the
elastic Brazilian disc (see below); **held out**, declared
after the piston with nu = 0.45 had shown the floors' majority vote to
fail and before that rule changed, a squat specimen (100 mm x 100 mm,
E = 10 GPa, nu = 0.25, the piston at 3 mm/s, probes D, E, F; FE 0.5 mm);
**held out**, declared after the squat specimen had shown a broken
promise and the refinement rules had changed, a slender specimen (40 mm
x 120 mm, E = 50 GPa, nu = 0.2, the piston at 1 mm/s, probes G, H, I
near the free sides; FE 0.5 mm); **held out**, declared before its runs,
the 3D laboratory cylinder (54 x 135 mm, the piston at 1.5 mm/s; the
least-squares slope of sigma_yy at its centre from 0.75 to 1.5 ms,
against the FE quasi-static slope of docs/validation/cylinder_3d; levels
9 to 3 mm). The elastic Brazilian disc is not a reference scene: its
trusted answer is a band, the centre stress of a load spread over its
contact between a rigid punch's and a uniform pressure's, 0.8 % wide for
a contact of 5 degrees and 3.2 % for 10 degrees (docs/fracture.md), too
wide to measure errors of 1-5 % against. **Fitted**, added after a
user's block pulled into tension (`examples/scene_file/pull.toml`,
docs/planner.md) showed that no record scene called for artificial
stress, so that no setting with it was verified: the strip pulled by the
piston (`strip_tension`: the exact front in tension, the strip's mirror).
pull.toml stays held out (nothing is fitted on it). The block in tension
shows what the record then says of artificial stress: with the cubic
spline and Wendland kernels it moves the front, a bias of 23-63 % (RMS)
that refinement does not remove, and with cubic_o4 (whose kernel is
negative past q = 0.91 and a quarter of its peak at one spacing, so that
f^4 = (W/W(dx))^4 reaches 248 for close pairs) the runs are meaningless;
none of them is planned for a request under its bias. The library now
refuses artificial stress with a kernel that changes sign, so the
planner's detection no longer offers it with cubic_o4: the two cubic_o4
families with artificial stress below are what was measured before, and
are no longer candidates.
For each setting of
the CLI's default candidates, at the spacings a plan uses, each window of
consecutive levels predicts the error at every finer level within 2x, and
the true error there is measured; a scene's column is the largest ratio of
true to predicted (upper) error. The planner multiplies the setting's
upper prediction by *factor* = max(1, 1.2 x the largest fitted ratio) and
never plans it at or below *bias* (the error refinement did not remove); a
setting whose largest fitted ratio exceeds 1 is not planned at all (its
prediction under-stated its true error on a fitted scene; a margin fitted
there did not carry to the held-out slender specimen).
A held-out ratio above the factor would be a promise broken on a scene the
factors never saw.

"""


def _record_section() -> str:
    from validation.record import record_text
    from sphsolid.planner.record import RECORD_FILE
    raw_path = Path(__file__).resolve().parent.parent / "docs" / \
        "accuracy" / "record_raw.json"
    if not (RECORD_FILE.exists() and raw_path.exists()):
        return "Not generated yet (`python -m validation.record`).\n"
    return record_text(json.loads(RECORD_FILE.read_text()),
                       json.loads(raw_path.read_text()))


def write_document(path: Path, results: dict, args) -> None:
    titles = {"piston_nu045": "Held out: the piston with nu = 0.45 against "
              "its finite-element reference (von Mises at A, B, C, "
              "0-0.3 ms)",
              "piston_squat": "Held out: a squat specimen of a softer rock "
              "under a faster piston against its finite-element reference "
              "(von Mises at D, E, F, 0-0.25 ms)",
              "piston_slender": "Held out: a slender specimen of a stiff "
              "rock under a slower piston against its finite-element "
              "reference (von Mises at G, H, I, 0-0.2 ms)",
              "piston": "Paper scene against the finite-element reference "
              "(von Mises at A, B, C, 0-0.3 ms)",
              "strip": "Laterally periodic strip hit by the piston (exact "
              "front, sigma_yy at y = 75, 50, 25 mm)",
              "gravity": "Gravity column, section means (exact at rest)",
              "strip_tension": "The strip pulled by the piston (exact "
              "front in tension, sigma_yy at y = 75, 50, 25 mm)",
              "cylinder": "Held out: the 3D laboratory cylinder, the slope "
              "of sigma_yy at its centre from 0.75 to 1.5 ms against the "
              "finite-element quasi-static slope"}
    parts = [HEADER.format(command="python -m validation.accuracy"
                           + (" --quick" if args.quick else ""),
                           threads=args.threads)]
    if args.quick:
        ran = [results[n] for n in SCENE_ORDER
               if n in results and results[n].get("wall")]
        loads = [x for r in ran for x in r.get("load", [])]
        # each scene's own wall and CPU time (the scenes may have run in
        # separate invocations, --scenes)
        cpu = (sum(r["cpu"] for r in ran) if all("cpu" in r for r in ran)
               else max((r.get("cpu_elapsed", 0.0) for r in ran),
                        default=0.0))
        elapsed = ("{:.1f} minutes wall for the three scenes (each "
                   "scene's own time, summed), one thread, "
                   "at load average {:.0f}-{:.0f} on {} cores from other "
                   "jobs{}".format(sum(r["wall"] for r in ran) / 60,
                                   min(loads), max(loads), os.cpu_count(),
                                   f", {cpu:.0f} s of CPU" if cpu else "")
                   if len(ran) == 3 and loads else
                   "its run time is given per scene below")
        parts.append(QUICK_NOTE.format(elapsed=elapsed,
                                       full_strip=FULL_STRIP))
    parts.append(summary_text(results, titles))
    parts.append(item5_text(results))
    parts.append(RECORD_HEADER + _record_section())
    parts.append(READING)
    for name in SCENE_ORDER:
        if name not in results:
            continue
        parts.append(scene_text(titles[name], results[name]))
        if results[name].get("estimate"):
            parts.append("\n### Per-run error estimate against the actual "
                         "error\n\n" + estimate_text(
                             results[name]["estimate"]))
    path.write_text("\n".join(parts))


#: What the quick document says of the full mode: where it was run with
#: the record's planner, its time and its verdict (measured figures).
FULL_STRIP = ("run with this record's planner on the strip and the "
              "pulled strip (`python -m validation.accuracy --full --scenes "
              "strip,strip_tension --out DIR --report "
              "validation/reports/accuracy/full_strip.md`, 100 s on one "
              "thread) and on gravity (`--scenes gravity`, "
              "24 minutes: full_gravity.md), the machine's other "
              "core busy: on each strip 12 of the 19 rows planned and met, "
              "the 7 refused missed by the exhaustive sweep too; on gravity "
              "19 of 19 planned and met. On the piston (`--scenes "
              "piston`, 37 minutes, sweep to 0.5 mm: "
              "full_piston.md) 19 of 19 planned and met, RMS 1 % and max "
              "2 % included; on the held-out scenes, each with another run "
              "beside it: the slender specimen (10 minutes: "
              "full_slender.md) 12 of 19 planned and met, the 7 refused "
              "missed by the sweep too; the squat specimen (5 minutes: "
              "full_squat.md) 6 of 19 planned and met, the 13 "
              "refused missed by the sweep too; the piston with nu = 0.45 "
              "(12 minutes: full_nu045.md) 15 of 19 planned and "
              "13 met: **RMS 2 % achieved 2.02 % against a bound of "
              "1.98 %** on 1 and 2 threads (true over central prediction "
              "1.27, above the safety factor 1.25; the FE reference's own "
              "1 mm and 2 mm meshes differ by 0.52 % RMS), and max 2.5 % "
              "refused where the sweep's cubic_o4 + leapfrog meets it. "
              "Not run on the cylinder (hours)")
QUICK_NOTE = """**Quick mode** (`--quick`: {elapsed}). The rows of
`QUICK_ROWS` (a sample of norm, request and thread count), each planned
exactly as `sphsolid plan` plans it: the CLI's default candidates (every
kernel at h/dx 1.2 and 1.5 with both integrators and the kernel-correction
variants, cubic_o4 at its own setting), pruned only by the verification
record (unverified, biased above the request, or dominated on every
fitted scene), no calibration or run-time budget. Finite-element
reference at 0.5 mm for the piston and 1 mm for the held-out piston with
nu = 0.45 (kept in docs/accuracy); sweeps: the record's levels (piston
3-0.75 mm, strip 2-0.35 mm, gravity 8-2 mm) and the checks' own (piston
0.5 mm, strip 0.25 mm) where a row needs them; on the 3D cylinder the
sample is 10, 5 and 3 % (`QUICK_ROWS_3D`). **Full mode** (`--full`):
every row of `ROWS` (10, 5, 3, 2 % in both norms on 1 and 2 threads, 2.5 %
max and 1 % RMS); {full_strip}.
"""

READING = """How to read the tables. *refused (sweep also missed)*: the
refusals for which no setting of the exhaustive sweep met the request
either (within the sweep's spacings). *particle-steps / cheapest*:
particle-steps of the planned run over those of the cheapest sweep
setting that met the request; *CPU cost / cheapest*: the same with every
run priced at its setting's measured CPU seconds per particle-step (`-`:
no sweep setting met the request, so there is nothing to compare).
*particle-steps / cheapest self-certified*: the same against the
cheapest sweep run that met the request *and* whose error self-convergence
alone bounds within the request: the planner's error model (Eça &
Hoekstra, order at most 1, no floor) fitted to the four sweep levels of
its setting that end at it (column *self-certified bound* of the sweep
table; `-` where the sweep has fewer than three coarser levels). That is
what a planner that sees only the user's scene could know from the
sweep's own runs; the criterion of the issue stays the comparison with
the sweep's cheapest, which uses the trusted answer no planner has. *wall
error*: measured over predicted wall time minus one; *CPU predicted /
measured*: process CPU seconds of the planned run's stepping, the cost
model's own clock.

Known limits of the method, visible here (docs/planner.md explains
them). *Cost against the sweep.* The safety factor the planner keeps
(1.25 from Eça & Hoekstra for orders in [0.5, 2.1] and a good fit, 3
otherwise) costs Fs^(d/q) in run time even when the central prediction
is exact (run cost ~ dx^-d, d = 3 in 2D, 2 for the strip): 1.25^(2/1) =
1.6x on the strip at order 1. On the strip, where the calibration shows
cubic_o4 converging at order 1 and the plan uses it, the planned runs
cost 1.1-1.3x the sweep's cheapest sufficient setting for the coarser
requests and about 2x for RMS 3 and 2 % (the sweep's cheapest, cubic_o4
at 0.5 and 0.35 mm, is 2.6 and 2.0 % RMS; self-convergence bounds it by
4.1 and 2.4 %, so it is not certified for those requests: the plans cost
0.9-1.1x the cheapest self-certified sweep run). *Piston*: the sweep's
cheapest sufficient setting is cubic_o4 at coarse spacings (at 3 mm
7.6 % max and 4.1 % RMS from the FE solution). Its calibration is
determined (a setting whose ladder determines no order gets finer levels:
in the max norm its differences at 3, 2, 1.5, 1 mm, 8.3, 6.7, 7.0 %,
show no convergence, the largest of 3 and 2 mm being a feature of A at
238 us and those of the finer levels one at 280-290 us; from 2 to
0.67 mm they fall at order 1.26 with a good fit). Its consecutive level
differences are as large as its errors (6.6, 6.9, 3.7 % max between 2,
1.5, 1, 0.67 mm, errors 6.2, 4.4, 3.9, 3.1 %): the shape of its error
changes from one spacing to the next (the errors of consecutive levels
correlate by 0.4-0.7, those of 3 and 0.5 mm by 0.1-0.2; the cubic
spline's by 0.97-0.99), and a power law fitted to the differences reads
that change as error still to converge (2-4x the error). The
differences themselves anti-correlate (-0.04 to -0.45 from one to the
next), which the planner's repeating factor reads (docs/planner.md,
step 4: a fit of their inner products with errors whose shapes
decorrelate from level to level gives 0.34 in the RMS norm here, on
levels from 3 to 1 mm, and 0.46 in the max norm, on levels from 2 to
0.67 mm, sqrt(2) times that ladder's RMS factor; the cubic spline's
differences correlate, 1). Every planned request uses cubic_o4 and is met (achieved
4.0, 3.1, 2.1 % for max 10, 5, 3 %; 4.1, 2.8, 1.5, 1.2 % for RMS 10, 5,
3, 2 %), at 1.1-10x the sweep's cheapest: RMS 5, 3, 2 % at 1.9, 3.5 and
1.8x and max 10, 5, 3 % at 9.5, 10 and 5.9x, where the former model
(one shape for every level plus an independent part per level, at least
0.5) had 7.2, 13, 7.1x and 12, 13, 7.7x. The central predictions are
still 1.1-2x the errors in the max norm (order 1 where the differences
fall at 1.26, and the max norm's sqrt(2)) and 1.2-1.6x in the RMS norm,
and the sweep's cheapest sits just below each request by the luck of
its spacings: at order 1 in 2D the run cost grows as the cube of the
error's margin. *What the margin alone costs* (column *exact prediction
with Fs 1.25*): a planner whose central prediction were each setting's
error against the trusted answer, interpolated between the sweep's
levels, and which kept the least safety factor (1.25) would need more
than 1.5x the sweep's cheapest in 2 of the piston's 6 comparable rows
(max 5 %: 2.5x, RMS 3 %: 2.1x) and 1 of the strip's 5 (max 5 %: 1.9x);
in the other rows the planner's excess is its prediction, which sees
only the scene's own runs (column *self-certified*).
*Order at most 1*: an observed order above 1 is fitted again at 1
(cubic_o4 on the strip: level differences falling at order 1.8 over
1.4-0.47 mm, errors at 0.8-1.1; the order-1.8 plan for 10 % max achieved
11.7 %). *Floors*: two settings whose difference does not shrink (h/dx
1.2 and 1.5 on the piston and on the strip) both carry it as a floor
unless a setting that agrees more closely with one of them says
otherwise; without it a 5 % max plan with h/dx 1.2 on the piston achieved
8.9 %. *Gravity column*: every request is planned with Wendland C2 and
met (h/dx 1.2 at 8 mm for 10 %, h/dx 1.5 at 6.8-2.7 mm below; achieved
7.2, 4.1, 2.4, 1.6 % max for 10, 5, 3, 2 %), 1.2-1.6x the sweep's
cheapest for 10 and 5 % and 4.2-7.3x for 3 and 2 %. There the sweep's
cheapest is cubic_o4 at 8 and 6 mm (2.5 and 0.4 %), whose errors follow
no power law (2.5, 0.4, 0.3, 0.8, 0.2 % from 8 to 2 mm): its refined
ladder (6, 4, 3, 2 mm) is bounded by 3x its data range, 3.5 %, and no
self-convergence of its own certifies it (bounds 8.3 and 3.5 % at 3 and
2 mm). Wendland C2 at h/dx 1.5 converges with a good fit, and its central
predictions are within 4 % of its errors (3.96, 2.40, 1.59 % predicted,
4.06, 2.43, 1.64 % achieved); at h/dx 1.2 its 10 % plan predicted 6.2 %
(bound 7.0 %) for 7.2 % achieved: its errors fall slowly (5.3, 5.0,
4.5 % at 4, 3, 2 mm), a floor that only the comparison of settings
shows (the sweep's own levels bound it by 1.4-2.2 %, below its
errors). Without Wendland C2 among
the quick candidates (the quick checks before) the 3 and 2 % plans used
the cubic spline at 3 and 1.19 mm, 15-86x the sweep's cheapest, and the
gravity part took 7 minutes instead of 2 (cubic_o4's ladder refined to
0.887 mm, 100 s, where it determines no order). The repeating factor
changes none of the strip's and gravity's plans (their consecutive
differences correlate or show no power law).
*Wall and CPU predictions*: in the tables here (regenerated on the idle
machine, load average 1, one thread) every row meets +-30 %: the
piston's 7 within -2 to +3 % (CPU), the strip's 6 within -13 to +10 %,
gravity's 8 within -6 to +6 %. Five changes to the cost model and its
check did it. (1) The line a + b x particles is fitted in relative residuals:
the unweighted line followed the largest runs and missed small ones by
up to 40 % (the piston's 3 mm plan, 0.129 CPU s predicted, 0.176 s
measured; gravity's 0.1 s runs, 0.168 and 0.156 s measured against
0.097 s predicted). (2) A timing check steps for 0.25 s of CPU at each
size: five steps of the strip at 0.362 mm, a few milliseconds, had set
the RMS 2 % plan's prediction at 0.79 s for a run of 0.46 s. (3) Beyond
the ladder the prediction is the finest calibration run's own cost per
step plus the timed difference of the two sizes; a ratio had scaled
the strip's probe sampling (every step) with the scene, 14-29 % over.
(4) That calibration run, when shorter than 1 CPU s, is run again and
the faster of the two counts (other work only slows a run): a 0.17 s
run of the strip at 0.467 mm had taken 1.04 ms per step, where its
repeats take 0.73-0.74, and set two plans 31-52 % high. (5) A planned
run shorter than 1 CPU s is timed here as the median of three: five
runs of the strip's 0.25 s plan took 0.24-0.29 CPU s, and one timed
alone in a previous pass 0.33 s (+54 %).
In an earlier pass gravity missed in 4 of 8 rows:
cubic_o4's three gravity runs took 23-36 % less than predicted (0.462
predicted, 0.357 and 0.295 s measured; 3.65 predicted, 2.39 s), the
straight line through its calibration sizes over-predicting the runs
between them, as on the piston below. In an earlier
pass the misses were runs of 0.03-0.3 s and one of
14 s measured under load 2 on 2 cores, where the CPU time of one run
varies from repeat to repeat by more than 30 %: the cubic_o4 run planned
for gravity's 5 % took 0.542 CPU s in the max-norm row and 0.318 s in the
RMS one, and five repeats of the 0.1 s gravity run at 8 mm took 0.099 to
0.172 s. The planner times a few steps only for scenes larger than its
largest calibration run; a few timed steps of a small scene had been
noise (two plans of the 8 mm gravity run predicted 0.148 and 0.111 CPU s
after their timing checks). Tried and not kept: taking the cost within
the calibrated sizes from the calibration runs themselves (interpolated
between the two that bracket the size) instead of the straight line
through all of them. It follows the step in cubic_o4's cost per
particle-step on the piston (3.9-4.1e-7 CPU s up to 12 700 particles,
5.0-5.1e-7 from 28 000, where the unweighted line over-predicted the
smaller runs by 20-26 %; the line is now fitted in relative residuals),
but passes each small run's own noise straight through (the
first, cold calibration run of the gravity column at 8 mm took
0.174 CPU s, the planned run 0.097-0.105 s): 4 of 8 gravity CPU
predictions within 30 % at load 4.5-6, where the line had 7 of 8 at
load 2.
*Per-run estimate*: on the piston within [1, 3] in all 72 cases
(1.13-2.72x, none below 1; 50 of 72 before). cubic_o4's shadow triplets
converge oscillatorily (the run's difference from its 2 dx shadow and
the shadow's from the 4 dx one anti-correlate, -0.34 and -0.43 at 3 and
2 mm): its run and 2 dx shadow differ by 0.9-1.9 times its error, the
triplet's observed order is no convergence order, and at 3 mm (0.20,
outside [0.5, 2.1]) it does not lower the calibrated one; the band is
the three-grid GCI (Fs 1.25) at the calibrated order (max 1.26 used at
1, RMS 0.86), lowered to 0.88 at 2 mm by the shadows (1.2-2.6x; with the
two-grid rule it was 2.8-5.0x). The cubic spline's calibrations carry
floors (3.65 % max, 1.81 % RMS: the bias of the limit that its ladder
cannot see), so its band keeps the two-grid rule, Fs 3 (1.1-2.7x; with
Fs 1.25 at its calibrated order 0.85 it would fall to 0.98x). On the
strip the estimate is unchanged (45 of 48): cubic_o4's 0.5 mm triplet is
monotone with order 0.57, which lowers the order used to 0.57 (2.4-5.3x
in three cases). At finer piston spacings (1.5 and 1 mm, the full mode's)
the same rule puts 57 of 72 cases within [1, 3] and two below 1 (the
cubic spline at 0.97-0.98: there its floor is the larger part of its
error), the previous rule 41 with 11 below 1 (computed from the same
shadow runs, not part of the quick checks).
"""


HEADER = """# Accuracy on demand: the planner's honesty checks

Regenerate with `{command}` (from the repository root, with the
package installed by scripts/setup.sh; `--scenes
strip,gravity,piston,piston_nu045,piston_squat,piston_slender,cylinder` picks
scenes). Every row plans the way
`sphsolid plan` does, with its default candidates and no budget
(`PLAN_DEFAULTS`; a test checks that the CLI passes the same); the quick
mode samples rows (norm, request, threads), never a narrower candidate
set. The **held-out** scenes (piston_nu045, piston_squat,
piston_slender, cylinder) never entered the verification record's factors
(declared before they were fitted; piston_squat was declared after
piston_nu045 had shown a rule to fail and before that rule was changed,
piston_slender after piston_squat had shown a broken promise and the
refinement rules had changed, before any rule was judged on it, the 3D
cylinder before its runs; section "Verification record"). **Timings were taken on a shared 2-core machine under
load from other jobs (load averages below); wall times depend on that
load, CPU times much less: compare the CPU predictions.** Threads wait
passively at OpenMP barriers (`OMP_WAIT_POLICY=PASSIVE`, which this
module sets unless the environment sets a policy): on the shared
machine a spinning thread takes the core from the one it waits for
(docs/planner.md).

What is checked, per request (10, 5, 3, 2 %, in the max and the RMS norm,
on 1 and 2 threads; 2.5 % max and 1 % RMS besides):
the planner (`sphsolid.plan`, `sphsolid plan ...`) returns settings or
refuses; the settings are run and their error measured against the
scene's trusted answer (**achieved <= request**), the predicted wall time
is compared with the measured one (**within +-30 %**, marked `**` when
not; a run shorter than 1 CPU s is timed as the median of three), and
the chosen setting's particle-steps are compared with the
cheapest setting of an exhaustive sweep that met the request (**at most
1.5x**; particle-steps rather than seconds, because seconds on a loaded
machine are noise), and in CPU seconds. Issue 32's item 5 is its own
column: the chosen setting's CPU cost against the cheapest setting the
verification record lets the planner choose for that request (verified
in the norm, ratio at most 1, bias below the request), at the spacing
where its record factor times its true error meets the request
(`record_margin_cost`): **at most 2x**, and a refusal where such a
setting exists is marked "met by". The per-run error estimate
(`--error-estimate`, `sphsolid.planner.estimate.ErrorEstimate`: shadow runs at
2 dx and 4 dx, 1/8 + 1/64 of the run's particle-steps in 2D; Roache's GCI
with Fs = 3 and the observed order bounded to [1, 2], or, where the
planner's calibration of the setting in that norm is well determined
(observed order in [0.5, 2.1], good fit) and carries no floor, the
three-grid GCI with Fs = 1.25 and the calibrated order lowered to the
shadows' observed order (unless their triplet oscillates with an order
outside [0.5, 2.1]: column *observed order*, "osc.") and capped at 1, at
least 0.5; the calibration used is the planner's well-determined one for
that setting and norm whose ladder reaches closest to the run's 2 dx
shadow) is compared with the actual error per probe and window: **ratio
in [1, 3] in at least 90 % of the cases**. The estimate runs the
planner's candidate settings (the leapfrog), so each has its
calibration.

How the planner decides (python/sphsolid/planner/, docs/planner_method.md):
effects from one coarse run with none per integrator and kernel family;
a calibration ladder per candidate setting (kernels at h/dx 1.2 and 1.5,
cubic_o4 at its own h/dx 1.65 and static platen inset, integrators and
the effects found), refined for the most promising, for those that
extrapolate with the large safety factor and for those whose ladder
determines no order (when a finer level costs less than the cheapest
plan so far); error model E = C dx^q fitted
by least squares on the differences of consecutive levels (Eça &
Hoekstra), the order used at most 1, times the share that repeats
from level to level where consecutive differences anti-correlate (errors
whose shapes decorrelate as rho^k over k levels; sqrt(2) times that in
the max norm), with their safety factor (1.25 for
an observed order in [0.5, 2.1] and a good fit, else 3; data that show
no convergence bounded by 3x their range), at most 2x below the finest
calibrated spacing; a floor where two settings differ by an amount that
does not shrink with refinement or that their own predicted errors do
not explain (unless a setting closer to both says otherwise); cost from
the calibration runs' process CPU time (a line in particles fitted in
relative residuals, per setting, at the requested threads) and, at a
spacing finer than the ladder's, the finest calibration run's cost per
step plus the timed difference of the two sizes (0.25 s of stepping at
each), wall time
from the calibration's wall/CPU ratio. *CPU cost / cheapest* prices every run at its setting's
CPU seconds per particle-step measured in the sweep, so that a setting
with cheaper steps (the leapfrog's one evaluation per step) counts as
cheaper; *particle-steps / cheapest* ignores that.
"""


if __name__ == "__main__":
    sys.exit(main())
