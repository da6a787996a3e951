"""The verification record of the planner's settings
(:mod:`sphsolid.planner.record`; docs/accuracy.md, "Verification record";
the whole table in validation/reports/accuracy/quick.md).

    python -m validation.record [--scenes piston,strip,...] [--threads 1]
                                [--only 'step=0.5']

For every reference scene with a trusted answer, every setting the CLI's
default path plans with (:func:`sphsolid.planner.search.candidate_settings`:
effect detection, then the default candidates) is run at the scene's
calibration ladder and the finer levels a plan refines to. Per setting and
norm, for every window of four (or the ladder's three) consecutive levels,
the planner's own fit (:func:`~sphsolid.planner.search._fit_candidate`, the
consistency floors of the ladder) predicts the error at each finer level
within the planner's largest extrapolation (2x); the true error there is
measured against the scene's answer. The record keeps, per setting and norm,
the largest ratio of true to predicted (upper) error and the bias that
refinement does not remove, over the **fitted** scenes; the **held-out**
scenes are run and reported the same way and never enter the factors.

Declared before any factor was fitted (docs/accuracy.md):
- fitted: piston (FE, 0.5 mm), strip (exact plane front), gravity (exact
  static section means);
- held out: piston_nu045 (the piston with a nearly incompressible
  material, nu = 0.45, FE at 1 mm) and the elastic Brazilian disc (not yet
  a reference scene of this module: reported as missing);
- held out, declared before the consistency floors were charged by the
  record (after piston_nu045 had shown the majority vote's failure, so
  that the change is judged on a scene it was not made on):
  piston_squat (a 100 mm square specimen of a softer rock, E = 10 GPa,
  nu = 0.25, under a piston at twice the speed, probes D, E, F; FE at
  0.5 mm);
- held out, declared after the squat specimen had shown a broken promise
  and the refinement rules had changed, before any rule was judged on it:
  piston_slender (a 40 mm x 120 mm specimen of a stiff rock, E = 50 GPa,
  nu = 0.2, under a slower piston, probes G, H, I near the free sides; FE
  at 0.5 mm);
- fitted, added after the user's block in tension
  (examples/scene_file/pull.toml, checked by validation.scene_file_check)
  showed that no record scene called for artificial stress, so no
  setting with it was verified and the planner refused requests the
  library met there: strip_tension (the strip pulled by the piston, exact
  plane front in tension). pull.toml stays held out: nothing is fitted on
  it, and its checks are reported as before;
- held out, declared before its runs: cylinder (the 3D laboratory
  cylinder's centre slope of sigma_yy from 0.75 to 1.5 ms against the FE
  quasi-static slope, levels 9 to 3 mm). The Brazilian disc stays out:
  its trusted answer is a band 0.8-3.2 % wide (docs/accuracy.md).

Calibration runs go through the planner's on-disk cache
(:class:`sphsolid.planner.cache.RunCache`), so a second generation, or a
plan of the same scene afterwards, reuses them.
"""
from __future__ import annotations

import argparse
import json
import sys
import time as wallclock
from pathlib import Path

import numpy as np

from sphsolid import metrics, planner
from sphsolid.planner import record as record_module
from sphsolid.planner.cache import RunCache
from sphsolid.planner.search import Candidate, _fit_candidate, _smoothed

from . import accuracy

NORMS = ("max", "rms")
FITTED = ("piston", "strip", "gravity", "strip_tension")
HELD_OUT = ("piston_nu045", "piston_squat", "piston_slender", "cylinder",
            "brazilian")
#: the levels of each scene: its planner ladder and the finer spacings a
#: plan refines to (the finest the answer resolves)
LEVELS = {
    "piston": (3e-3, 2e-3, 1.5e-3, 1e-3, 0.75e-3),
    "piston_nu045": (3e-3, 2e-3, 1.5e-3, 1e-3, 0.75e-3),
    "piston_squat": (3e-3, 2e-3, 1.5e-3, 1e-3, 0.75e-3),
    "piston_slender": (3e-3, 2e-3, 1.5e-3, 1e-3, 0.75e-3),
    "strip": (2e-3, 1.4e-3, 1e-3, 0.7e-3, 0.5e-3, 0.35e-3),
    "strip_tension": (2e-3, 1.4e-3, 1e-3, 0.7e-3, 0.5e-3, 0.35e-3),
    "gravity": (8e-3, 6e-3, 4e-3, 3e-3, 2e-3),
    "cylinder": (9e-3, 6e-3, 4.5e-3, 3e-3),
}
#: the planner's largest extrapolation below its finest level
MAX_REFINEMENT = 2.0
NU045_FE = Path(__file__).resolve().parent.parent / "docs" / "accuracy"


def _fe_scene(name: str, what: str, sizes=("1", "2")) -> accuracy.Scene:
    """A planner scene against its FE solution on the first of ``sizes``
    [mm] (the second shows its convergence), read from the files
    fe_<name>_<size>mm.npz of docs/accuracy."""
    spec = planner.project_scenes()[name]
    fine_size, coarse_size = sizes
    data = {s: np.load(NU045_FE / f"fe_{name}_{s}mm.npz") for s in sizes}
    fine = data[fine_size]
    names = list(spec.probes)

    def reference(grid):
        return {n: np.interp(grid, fine["grid"], fine[n]) for n in names}
    g = fine["grid"]
    own = {norm: metrics.worst_deviation(
        {n: np.interp(g, data[coarse_size]["grid"], data[coarse_size][n])
         for n in names},
        {n: fine[n] for n in names}, g, norm) for norm in NORMS}
    note = (f"{what}; FE at {fine_size} mm, which the {coarse_size} mm mesh "
            f"differs from by {own['max'] * 100:.2f} % (max) and "
            f"{own['rms'] * 100:.2f} % (RMS)")
    return accuracy.Scene(name, spec, reference, LEVELS[name],
                          until=spec.until, note=note)


def nu045_scene(out: Path, quick: bool, log) -> accuracy.Scene:
    """The piston with nu = 0.45 (mu of the paper's rock, K from nu),
    against its FE solution at 1 mm (the 2 mm one shows its convergence)."""
    return _fe_scene("piston_nu045", "piston with nu = 0.45")


def squat_scene(out: Path, quick: bool, log) -> accuracy.Scene:
    """The squat specimen (100 mm x 100 mm, E = 10 GPa, nu = 0.25, the
    piston at 3 mm/s, probes D, E, F) against its FE solution at 0.5 mm
    (the 1 mm one differs by 1.4 % in the max norm)."""
    return _fe_scene("piston_squat", "squat specimen of a softer rock "
                     "under a faster piston", sizes=("0.5", "1"))


def slender_scene(out: Path, quick: bool, log) -> accuracy.Scene:
    """The slender specimen (40 mm x 120 mm, E = 50 GPa, nu = 0.2, the
    piston at 1 mm/s, probes G, H, I) against its FE solution at 0.5 mm
    (the 1 mm one shows its convergence)."""
    return _fe_scene("piston_slender", "slender specimen of a stiff rock "
                     "under a slower piston", sizes=("0.5", "1"))


def cylinder_scene(out: Path, quick: bool, log) -> accuracy.Scene:
    """The 3D cylinder's centre slope (planner scene ``cylinder``)
    against the finite-element quasi-static slope of the 3D validation
    (docs/validation/cylinder_3d/results_3d.json: graded meshes
    extrapolated, confirmed by an independent solver to 0.015 %)."""
    spec = planner.project_scenes()["cylinder"]
    results = json.loads((NU045_FE.parent / "validation" / "cylinder_3d"
                          / "results_3d.json").read_text())
    slope = float(results["slope_fe"])

    def reference(grid):
        return {"slope": np.full_like(grid, slope)}
    return accuracy.Scene("cylinder", spec, reference, LEVELS["cylinder"],
                          until=spec.until, window=spec.window(spec.until),
                          note=f"slope of sigma_yy at the centre from "
                          f"0.75 ms on against the FE's {slope / 1e6:.4g} "
                          "MPa/s", quick_rows=accuracy.QUICK_ROWS_3D)


def reference_scene(name: str, out: Path, log,
                    quick: bool = False) -> accuracy.Scene:
    makers = {"piston": accuracy.piston_scene,
              "strip": accuracy.strip_scene,
              "strip_tension": lambda out, quick, log: accuracy.strip_scene(
                  out, quick, log, pulled=True),
              "gravity": accuracy.gravity_scene,
              "piston_nu045": nu045_scene,
              "piston_squat": squat_scene,
              "piston_slender": slender_scene,
              "cylinder": cylinder_scene}
    if name not in makers:
        raise ValueError(f"no reference scene {name!r} (have "
                         f"{', '.join(makers)})")
    return makers[name](out, quick, log)


def _bias(spacings, errors, order) -> float:
    """b of the non-negative least-squares fit e = a dx^q + b (relative
    residuals, a >= 0, b >= 0), 0 with fewer than three levels."""
    if len(errors) < 3:
        return 0.0
    h = np.asarray(spacings, float)
    e = np.asarray(errors, float)
    w = 1.0 / e ** 2                 # relative residuals
    x = (h / h.max()) ** order

    def fit(with_a: bool, with_b: bool):
        if with_a and with_b:
            design = np.column_stack([x, np.ones_like(x)]) * np.sqrt(w)[:, None]
            return np.linalg.lstsq(design, e * np.sqrt(w), rcond=None)[0]
        if with_a:
            return np.array([np.sum(w * x * e) / np.sum(w * x * x), 0.0])
        return np.array([0.0, np.sum(w * e) / np.sum(w)])
    a, b = fit(True, True)
    if a >= 0 and b >= 0:
        return float(b)
    # the optimum lies on a bound: the better of the two one-term fits
    candidates = [fit(True, False), fit(False, True)]
    costs = [np.sum(w * (e - c[0] * x - c[1]) ** 2) for c in candidates]
    return float(candidates[int(np.argmin(costs))][1])


def viscous_variants(settings) -> list:
    """Each setting without artificial viscosity, with it (the wave
    viscosity the effect detection switches on): another scene may call
    for it where the reference scenes do not (the squat piston: cubic_o4
    with the leapfrog blew up without it in the detection run), and a
    setting the record does not verify is never planned."""
    from sphsolid.scenes import WAVE_VISCOSITY
    viscous = next((dict(s.effect_dict["artificial_viscosity"])
                    for s in settings
                    if "artificial_viscosity" in s.effect_dict),
                   dict(WAVE_VISCOSITY))
    out = []
    for setting in settings:
        effects = setting.effect_dict
        if "artificial_viscosity" in effects:
            continue
        variant = setting.with_effects({**effects,
                                        "artificial_viscosity": viscous})
        if variant not in settings and variant not in out:
            out.append(variant)
    return out


def verify_scene(scene: accuracy.Scene, threads: int, log,
                 only: str | None = None) -> dict:
    """Per setting family and norm: the pairs (fit window, target level,
    true error, upper prediction), the largest ratio and the bias. With
    ``only``, the families whose key contains it: every setting still runs
    the ladder levels (the consistency floors compare them all, as a plan
    does), only those run the finer levels and are returned."""
    spec = scene.spec
    cache = RunCache(f"record:{scene.name}")
    ladder = sorted(spec.ladder, reverse=True)
    settings, _ = planner.search.candidate_settings(
        spec.factory, scene.until, spec.probes, spec.quantity, threads,
        ladder, cache=cache, log=log)
    planned = set(settings)
    settings = settings + viscous_variants(settings)
    levels = LEVELS[scene.name]
    t0, t1 = scene.window
    grid = metrics.time_grid(t0, t1)
    cands = []
    for setting in settings:
        cand = Candidate(setting, [])
        chosen = only is None or only in record_module.family(setting)
        for dx in levels if chosen else levels[:len(ladder)]:
            key = (float(f"{dx:.6g}"), setting, float(scene.until),
                   spec.quantity, threads)
            if key in cache:
                run = cache[key]
            else:
                log(f"{scene.name}: {setting.label()}, dx = {dx * 1e3:g} mm")
                run = planner.ladder_run(spec.factory, dx, setting,
                                         scene.until, spec.probes,
                                         spec.quantity, threads)
                cache[key] = run
            if run.failed:
                cand.note = f"failed at {dx * 1e3:g} mm: {run.failed[:120]}"
                break
            cand.runs.append(run)
        cand.smoothed = [_smoothed(r, grid) for r in cand.runs]
        cands.append(cand)
    out = {}
    shipped = record_module.shipped()
    for norm in NORMS:
        complete = [c for c in cands if len(c.runs) >= len(ladder)]
        # consistency floors from the ladder levels, as a plan makes them
        for cand in complete:
            cand.runs, runs = cand.runs[:len(ladder)], cand.runs
            smoothed = cand.smoothed
            cand.smoothed = smoothed[:len(ladder)]
            _fit_candidate(cand, norm, MAX_REFINEMENT, threads)
            cand.runs, cand.smoothed = runs, smoothed
        # charged as a plan charges them: by the shipped record's errors
        # (true errors at its finest levels, which this generation
        # measures again)
        def floors_among(group):
            return dict(zip((id(c) for c in group), planner.consistency_floors(
                [c.model for c in group],
                [c.smoothed[:len(ladder)] for c in group], norm, ladder,
                trust=[shipped.promise(c.setting, norm) if shipped else None
                       for c in group])))
        # a plan of this scene compares the settings it calibrates; a
        # variant the scene does not call for is compared with them all
        floor_of = floors_among(complete)
        floor_of.update(floors_among(
            [c for c in complete if c.setting in planned]))
        for cand in cands:
            key = record_module.family(cand.setting)
            if only is not None and only not in key:
                continue
            entry = out.setdefault(key, {"label": cand.setting.label()})
            errors = [scene.error(r, norm) for r in cand.runs]
            spacings = [r.dx for r in cand.runs]
            pairs = []
            for k in range(len(ladder) - 1, len(cand.runs) - 1):
                runs, smoothed = cand.runs, cand.smoothed
                cand.runs, cand.smoothed = runs[:k + 1], smoothed[:k + 1]
                _fit_candidate(cand, norm, MAX_REFINEMENT, threads)
                cand.model.floor = floor_of.get(id(cand), 0.0)
                cand.runs, cand.smoothed = runs, smoothed
                for j in range(k + 1, len(runs)):
                    if spacings[k] / spacings[j] > MAX_REFINEMENT + 1e-9:
                        break
                    upper = cand.model.upper(spacings[j])
                    pairs.append({"fit_to": spacings[k],
                                  "dx": spacings[j],
                                  "true": errors[j], "upper": upper,
                                  "predicted": cand.model.predict(
                                      spacings[j])})
            order = 1.0
            if len(cand.runs) >= len(ladder):
                _fit_candidate(cand, norm, MAX_REFINEMENT, threads)
                order = (1.0 if cand.model.anomalous
                         else max(0.5, min(cand.model.order, 2.0)))
            ratios = [p["true"] / p["upper"] for p in pairs
                      if p["upper"] > 0]
            entry["cpu"] = [r.cpu for r in cand.runs]
            entry[norm] = {
                "spacings": spacings, "errors": errors, "pairs": pairs,
                "ratio": max(ratios) if ratios else None,
                "bias": _bias(spacings, errors, order),
                "failed": cand.note or None}
    return out


#: Tolerances of dominance: B dominates A when its errors are at most
#: 1.05 times A's at every level of every fitted scene both ran, in both
#: norms, and its CPU time over those levels is at most 0.8 times A's.
DOMINANCE_ERROR, DOMINANCE_CPU = 1.05, 0.8


def dominance(per_scene: dict, fitted) -> dict:
    """{family: [families that dominate it]}: a setting is dominated when
    another does at least as well at every level of every fitted scene
    that verified it, for clearly less CPU time (:data:`DOMINANCE_ERROR`,
    :data:`DOMINANCE_CPU`), and ran on every one of those scenes."""
    families = sorted({k for s in fitted for k in per_scene.get(s, {})})
    out = {}
    for a in families:
        scenes = [s for s in fitted if a in per_scene.get(s, {})
                  and per_scene[s][a]["max"]["errors"]]
        if not scenes:
            continue
        for b in families:
            if b == a:
                continue
            better = True
            for s in scenes:
                ea, eb = per_scene[s][a], per_scene[s].get(b)
                if eb is None or len(eb["max"]["errors"]) < len(
                        ea["max"]["errors"]):
                    better = False
                    break
                n = len(ea["max"]["errors"])
                for norm in NORMS:
                    if any(y > DOMINANCE_ERROR * x for x, y in zip(
                            ea[norm]["errors"][:n], eb[norm]["errors"][:n])):
                        better = False
                cpu_a, cpu_b = sum(ea["cpu"][:n]), sum(eb["cpu"][:n])
                if not cpu_b <= DOMINANCE_CPU * cpu_a:
                    better = False
                if not better:
                    break
            if better:
                out.setdefault(a, []).append(b)
    return out


def combine(per_scene: dict, fitted, held_out) -> dict:
    """The record: per family and norm the largest ratio and bias over the
    fitted scenes (a family no fitted scene verified is left out), with
    every scene's figures kept beside them."""
    families = sorted({k for s in per_scene.values() for k in s})
    settings = {}
    for key in families:
        entry = {"scenes": {}}
        for norm in NORMS:
            ratios, biases = [], []
            for name in fitted:
                verdict = per_scene.get(name, {}).get(key, {}).get(norm)
                if verdict and verdict["ratio"] is not None:
                    ratios.append(verdict["ratio"])
                    biases.append(verdict["bias"])
            if ratios:
                entry[norm] = {"ratio": max(ratios), "bias": max(biases),
                               "scenes": len(ratios)}
        for name, results in per_scene.items():
            if key in results:
                entry["scenes"][name] = {
                    "label": results[key]["label"],
                    **{norm: {k: results[key][norm][k] for k in
                              ("ratio", "bias", "spacings", "errors",
                               "failed")}
                       for norm in NORMS if norm in results[key]}}
        if any(norm in entry for norm in NORMS):
            settings[key] = entry
    return {"format": record_module.RECORD_FORMAT,
            "margin": record_module.MARGIN,
            "fitted": list(fitted), "held_out": list(held_out),
            "library": planner.calibration._lib.version(),
            "settings": settings,
            "dominated_by": dominance(per_scene, fitted)}


def record_text(record: dict, raw: dict) -> str:
    """The table of the verification record (validation/reports/
    accuracy/quick.md): per setting
    and norm the factor and bias the planner uses, and each scene's
    largest ratio of true to predicted error (held-out scenes marked, with
    whether the factor covers them)."""
    scenes = [s for s in FITTED + HELD_OUT if s in raw]
    held = set(record.get("held_out", HELD_OUT))
    header = (["setting", "norm", "factor", "bias"]
              + [f"{s} (held out)" if s in held else s for s in scenes])
    lines = ["| " + " | ".join(header) + " |",
             "|" + "---|" * len(header)]
    margin = record.get("margin", record_module.MARGIN)
    for family, entry in sorted(record["settings"].items()):
        for norm in NORMS:
            if norm not in entry:
                continue
            ratio = entry[norm]["ratio"]
            factor = max(1.0, margin * ratio)
            cells = [family, norm,
                     f"{factor:.2f}" if ratio <= 1.0 else
                     f"not planned ({ratio:.2f} > 1)",
                     f"{entry[norm]['bias'] * 100:.2f} %"]
            for name in scenes:
                verdict = raw.get(name, {}).get(family, {}).get(norm)
                if not verdict or verdict["ratio"] is None:
                    cells.append("failed" if verdict and verdict["failed"]
                                 else "-")
                    continue
                mark = ""
                if name in held:
                    mark = (" (covered)" if verdict["ratio"] <= factor
                            else " **not covered**")
                cells.append(f"{verdict['ratio']:.2f}{mark}")
            lines.append("| " + " | ".join(cells) + " |")
    unverified = sorted({k for s in raw.values() for k in s}
                        - set(record["settings"]))
    text = "\n".join(lines) + "\n"
    if unverified:
        text += ("\nNot verified (failed on every fitted scene, or never "
                 "reached a fitted level; never planned): "
                 + "; ".join(unverified) + ".\n")
    return text


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m validation.record",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--scenes", default=",".join(FITTED + HELD_OUT[:3]))
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--out", type=Path,
                        default=record_module.RECORD_FILE)
    parser.add_argument("--only", default=None,
                        help="verify only the families whose key contains "
                        "this text (e.g. 'step=0.5'), keeping the other "
                        "families' results of the raw file")
    parser.add_argument("--raw", type=Path,
                        default=Path("docs/accuracy/record_raw.json"),
                        help="every pair (window, level, true, upper)")
    args = parser.parse_args(argv)
    log = lambda message: print(message, flush=True)  # noqa: E731
    per_scene = {}
    if args.raw.exists():
        per_scene = json.loads(args.raw.read_text())
    start = wallclock.perf_counter()
    for name in filter(None, args.scenes.split(",")):
        scene = reference_scene(name, Path("docs/accuracy"), log)
        result = verify_scene(scene, args.threads, log, args.only)
        if args.only is not None:
            result = {**{k: v for k, v in per_scene.get(name, {}).items()
                         if args.only not in k}, **result}
        per_scene[name] = result
        args.raw.write_text(json.dumps(per_scene, indent=1))
        log(f"{name}: done at {wallclock.perf_counter() - start:.0f} s")
    record = combine(per_scene, FITTED, HELD_OUT)
    args.out.write_text(json.dumps(record, indent=1) + "\n")
    log(f"wrote {args.out} ({len(record['settings'])} settings)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
