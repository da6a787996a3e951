# Over 600 lines: the order study: one function per candidate cause over shared runs.
"""What limits the observed order of the piston test's error
(docs/validation.md, section "What limits the observed order").

    python -m validation.order --experiments strip specimen sweep \
        --out docs/validation/order
    (--dx 2e-3 1e-3 5e-4 by default; --only LABEL ... runs some again and
    merges them into DIR/order.json; --series keeps the probe series in
    --series-dir, and --rescore scores the kept series again against the
    FE series of --fe, e.g. after a finer one was computed with
    ``python -m validation.fe_reference``; ``--experiments sweep`` runs
    the specimen at the nine spacings of SWEEP_DX, 2 to 0.5 mm, for the
    least-squares order over many spacings)

The error of the issue's metric (von Mises at the probes, both series
smoothed with a 1 us Gaussian, worst probe's RMS deviation over the
reference's RMS, 0-0.3 ms) falls at about first order from 2 to 1 to
0.5 mm. Each experiment here changes one candidate cause alone:

- *time stepping*: the same runs with the step halved and quartered;
- *free surfaces*: the laterally periodic strip (no free surface, no
  corner, exact answer) against the specimen (against finite elements);
- *the loaded ends*: plate and piston at the static inset against the
  paper's placement;
- *the front's steepness against the 1 us smoothing*: the same strip with
  the piston's speed ramped up smoothly over a time T (a C2 quintic ramp;
  the exact answer is then a staircase of smooth fronts, below) and the
  same runs measured with a wider smoothing (post-processing only);
- *the reference's own resolution*: the specimen against the 2, 1 and
  0.5 mm finite-element series, and those series' own convergence (their
  differences, observed order and Richardson estimate of the finest one's
  error, ``fe_self``).

The specimen runs that reach 1 ms are also scored over 0-1 ms, the
metric's second window. Each row gives the orders between successive
spacings and the least-squares slope over all of them.

Exact answer of the strip (linear acoustics, uniaxial strain): the piston
moving down at V(t) sends a front down; the fixed plate and the piston
(a prescribed velocity) both reflect it with the same sign, so at height y

    sigma_yy(y, t) = -rho0 c_p sum_k [V(t - t_k-(y)) + V(t - t_k+(y))],
    t_k-(y) = (2kH + H - y)/c_p,  t_k+(y) = (2kH + H + y)/c_p,

and von Mises is |sigma_yy - sigma_xx| = 2 mu/(rho0 c_p) |sigma_yy| = 2 mu
V/c_p per passage. With V a step this is ``decomposition.strip_exact``.
The runs are the library's; the ramp is applied by setting the piston's
prescribed velocity to V(t + dt/2) before each step (the midpoint rule:
the piston's position is second order in dt).
"""
from __future__ import annotations

import argparse
import json
import os
import time as wallclock
from pathlib import Path

import numpy as np

from sphsolid import _lib, metrics, presets, scenes
from sphsolid._lib import lib
from sphsolid.calculators import CLibrary
from sphsolid.dynamics import dynamics_for
from sphsolid.probes import PAPER_PROBES, Probes

from . import decomposition, end_placement

WINDOW = decomposition.WINDOW
#: the metric's long window (0-1 ms), scored for the runs that reach it
LONG = 1e-3
STRIP_PROBES = decomposition.STRIP_PROBES


ramp = decomposition.ramp
strip_exact = decomposition.strip_exact


def _ramp_piston(scene, dyn, rise):
    """An observer setting the piston's velocity to V(t + dt/2)."""
    piston = scene._body_index("piston")
    speed = scenes.PISTON_SPEED

    def update():
        v = -speed * float(ramp(dyn.time + 0.5 * dyn.dt, rise))
        scene._check(lib.sph_set_motion(
            scene.handle, piston, _lib.MOTION_VELOCITY,
            _lib.as_doubles((0.0, v), 2, "piston velocity")), "ramp")
    return update


def series(scene, dyn, points, until=WINDOW, rise=0.0) -> dict:
    """Run ``dyn`` to ``until`` with the piston ramped over ``rise``,
    sampling von Mises at ``points`` every step; CPU and wall time, steps
    and particle-steps."""
    if rise > 0:
        dyn.attach(_ramp_piston(scene, dyn, rise), interval=1)
    probes = Probes(scene, points)
    dyn.attach(probes, interval=1)
    wall, cpu = wallclock.perf_counter(), wallclock.process_time()
    dyn.run(until=until)
    return {"times": np.asarray(probes.times),
            "vm": {n: np.asarray(probes[n]["von_mises"]) for n in probes.names},
            "syy": {n: np.asarray(probes[n]["sigma_yy"])
                    for n in probes.names},
            "wall": wallclock.perf_counter() - wall,
            "cpu": wallclock.process_time() - cpu,
            "steps": dyn.nsteps, "particles": len(scene)}


def _dynamics(scene, integrator, dt_factor):
    """The preset's (or ``integrator``'s) Dynamics at ``dt_factor`` times
    its default step."""
    dyn = (presets.dynamics(scene, progress=False) if integrator is None
           else dynamics_for(integrator)(scene, progress=False))
    kind = type(dyn)
    if dt_factor != 1.0:
        dyn = kind(scene, dt=dyn.dt * dt_factor, progress=False)
    return dyn


def strip_run(dx, preset="waves", rise=0.0, dt_factor=1.0, until=WINDOW,
              integrator=None, effects=None, **overrides) -> dict:
    """The laterally periodic strip (``end_placement.strip_scene``) run
    with the preset's integrator (or ``integrator``) at ``dt_factor``
    times its default step, with ``effects`` (name -> parameters) on
    top of the preset's."""
    scene = decomposition.with_effects(
        end_placement.strip_scene(dx, preset, **overrides), effects)
    scene.calc = CLibrary(threads=1)
    return series(scene, _dynamics(scene, integrator, dt_factor),
                  STRIP_PROBES, until, rise)


def specimen_run(dx, preset="waves", rise=0.0, dt_factor=1.0, until=WINDOW,
                 integrator=None, threads=1, effects=None,
                 **overrides) -> dict:
    """The paper's specimen built from a preset, as :func:`strip_run`."""
    scene = decomposition.with_effects(
        scenes.uniaxial_piston(dx, preset=preset, **overrides), effects)
    scene.calc = CLibrary(threads=threads)
    return series(scene, _dynamics(scene, integrator, dt_factor),
                  PAPER_PROBES, until, rise)


def deviation(result, reference, norm="rms", sigma=metrics.SMOOTHING,
              window=WINDOW) -> float:
    """The worst probe's smoothed deviation of ``result`` against
    ``reference`` (a function of the time grid returning {probe: series})
    over [0, window]."""
    grid = metrics.time_grid(0.0, window)
    ref = reference(grid)
    got = {n: metrics.on_grid(result["times"], result["vm"][n], grid)
           for n in ref}
    return metrics.worst_deviation(got, ref, grid, norm, sigma)


def front_delays(result, rise, fronts=1, level=0.5) -> dict:
    """Per strip probe, the delay [s] of the first ``fronts`` fronts'
    crossings of ``level`` times the jump against the exact series'
    crossings (for the quintic ramp the half level is crossed at
    t_k + rise/2)."""
    jump = decomposition.front_jump()
    out = {}
    for name, (_, y) in STRIP_PROBES.items():
        t = result["times"]
        pair = (result["vm"][name] / jump, strip_exact(t, y, rise) / jump)
        delays = []
        for i, start in enumerate(decomposition.arrivals(y)[:fronts]):
            when = []
            for series in pair:
                j = np.nonzero((t > start - 0.5 * rise - 5e-6)
                               & (series > i + level))[0]
                if not len(j) or j[0] == 0:
                    raise ValueError(f"front {i + 1} does not reach probe "
                                     f"{name} before t = {t[-1]:g} s")
                j = j[0]
                when.append(t[j - 1] + (i + level - series[j - 1])
                            * (t[j] - t[j - 1]) / (series[j] - series[j - 1]))
            delays.append(float(when[0] - when[1]))
        out[name] = delays
    return out


def front_share(result, rise=0.0, sigma=metrics.SMOOTHING, window=WINDOW,
                near=3e-6, ahead=12e-6) -> dict:
    """Where the squared smoothed deviation of a strip run sits (worst
    probe): within ``near`` of an exact front's arrival (its middle, for
    a ramp), up to ``ahead`` before it (a precursor: short waves running
    fast), or elsewhere (behind the fronts)."""
    grid = metrics.time_grid(0.0, window)
    worst, out = -1.0, {}
    for name, (_, y) in STRIP_PROBES.items():
        got = metrics.smooth(grid, metrics.on_grid(result["times"],
                                                    result["vm"][name], grid),
                             sigma)
        ref = metrics.smooth(grid, strip_exact(grid, y, rise), sigma)
        d2 = (got - ref) ** 2
        middle = [t + 0.5 * rise for t in decomposition.arrivals(y)]
        close = np.zeros(len(grid), bool)
        before = np.zeros(len(grid), bool)
        for t in middle:
            close |= np.abs(grid - t) <= near
            before |= (grid > t - ahead) & (grid < t - near)
        before &= ~close
        total = float(d2.sum())
        if total > worst:
            worst = total
            out = {"near": float(d2[close].sum() / total),
                   "ahead": float(d2[before].sum() / total),
                   "behind": float(d2[~close & ~before].sum() / total)}
    return out


def _signed(reference):
    """The exact sigma_yy of the strip from its von Mises: in uniaxial
    strain sigma_yy = -(rho0 c_p^2 / 2 mu) x von Mises."""
    rock = scenes.paper_material()
    factor = -rock.rho0 * rock.c_p ** 2 / (2 * rock.mu)
    return lambda grid: {n: factor * v for n, v in reference(grid).items()}


def fe_series(path):
    """An FE series of ``fe_reference.main`` (or ``accuracy.fe_reference``):
    (reference function of the time grid, the time it reaches [s])."""
    data = np.load(path)
    grid = data["grid"]
    series = {n: data[n] for n in "ABC"}
    return (lambda g: {n: np.interp(g, grid, v) for n, v in series.items()},
            float(grid[-1]))


def _stem(path) -> str:
    """fe_piston_0.5mm from .../fe_piston_0.5mm.npz (Path.stem would cut
    at the size's decimal point of an already stripped name)."""
    name = Path(path).name
    return name[:-4] if name.endswith(".npz") else name


def _size(path) -> float:
    """Element size [mm] from fe_piston_<size>mm[.npz]."""
    return float(str(path).split("fe_piston_")[-1].split("mm")[0])


def fe_self(paths, extra=()) -> dict:
    """The FE series against each other in the metric (worst probe), over
    0-0.3 ms and, where both reach it, 0-1 ms: successive sizes, each
    against the finest, and the ``extra`` pairs (label, path, path) (e.g.
    a series at half the step against the same mesh); the observed order
    of the RMS deviation between successive sizes and the Richardson
    estimate of the finest series' own RMS deviation from the converged
    answer, d / (2^p - 1) with d and p its last difference and order."""
    series = {_stem(p): fe_series(p) for p in paths if Path(p).exists()}
    names = sorted(series, key=lambda n: -_size(n))
    pairs = [(f"{a} vs {b}", a, b) for a, b in zip(names, names[1:])]
    pairs += [(f"{a} vs {names[-1]}", a, names[-1]) for a in names[:-2]]
    for label, a, b in extra:
        if Path(a).exists() and Path(b).exists():
            series[_stem(a)] = fe_series(a)
            series[_stem(b)] = fe_series(b)
            pairs.append((label, _stem(a), _stem(b)))
    out = {"pairs": [], "windows": {}, "ringing": {}}
    for name in names:
        # what the 1 us smoothing removes from the series (the undamped
        # Newmark ringing and anything shorter than the smoothing), worst
        # probe, as a share of the smoothed series' RMS
        data = np.load(paths[[_stem(p) for p in paths].index(name)])
        keep = data["grid"] <= WINDOW * (1 + 1e-9)
        g = data["grid"][keep]
        shares = []
        for n in "ABC":
            raw = data[n][keep]
            smooth = metrics.smooth(g, raw)
            shares.append(float(np.sqrt(np.mean((raw - smooth) ** 2))
                                / np.sqrt(np.mean(smooth ** 2))))
        out["ringing"][name] = max(shares)
    for label, a, b in pairs:
        row = {"pair": label}
        for window in (WINDOW, LONG):
            if min(series[a][1], series[b][1]) < window * (1 - 1e-9):
                continue
            grid = metrics.time_grid(0.0, window)
            tag = "" if window == WINDOW else " 1ms"
            for norm in ("max", "rms"):
                row[norm + tag] = metrics.worst_deviation(
                    series[a][0](grid), series[b][0](grid), grid, norm)
        out["pairs"].append(row)
    for tag in ("", " 1ms"):
        steps = [r.get("rms" + tag) for r in out["pairs"][:len(names) - 1]]
        sizes = [_size(n) for n in names]
        if len(steps) < 2 or None in steps:
            continue
        p = [float(np.log2(steps[i] / steps[i + 1]))
             for i in range(len(steps) - 1)]
        sizes_used = [sizes[i + 1] for i in range(len(steps))]
        out["windows"][tag or " 0.3ms"] = {
            "orders": p, "finest": names[-1],
            "richardson": float(steps[-1] / (2 ** p[-1] - 1)),
            "richardson_previous": float(steps[-1] * 2 ** p[-1]
                                         / (2 ** p[-1] - 1)),
            "sizes": sizes_used}
    return out


def strip_reference(rise=0.0):
    return lambda grid: {n: strip_exact(grid, p[1], rise)
                         for n, p in STRIP_PROBES.items()}


def orders(dxs, errors) -> list:
    """Observed order between successive spacings."""
    return [float(np.log(errors[i] / errors[i + 1])
                  / np.log(dxs[i] / dxs[i + 1])) for i in range(len(dxs) - 1)]


def fitted_order(dxs, errors) -> float:
    """Least-squares slope of log(error) against log(dx)."""
    return float(np.polyfit(np.log(dxs), np.log(errors), 1)[0])


#: Strip experiments: label -> (preset, options of strip_run)
STRIP = {
    "waves": ("waves", {}),
    "waves, dt/2": ("waves", {"dt_factor": 0.5}),
    "waves, dt/4": ("waves", {"dt_factor": 0.25}),
    "waves, inset 0": ("waves", {"inset": 0.0}),
    "waves, h/dx 1.6525 (M = 1)": ("waves", {"smoothing_ratio": 1.6525}),
    "waves, M = 1, dt/2": ("waves", {"smoothing_ratio": 1.6525,
                                     "dt_factor": 0.5}),
    "waves, M = 1, dt/4": ("waves", {"smoothing_ratio": 1.6525,
                                     "dt_factor": 0.25}),
    "waves, ramp 10 us": ("waves", {"rise": 10e-6}),
    "waves, ramp 20 us": ("waves", {"rise": 20e-6}),
    "waves, M = 1, dt/2, ramp 10 us": ("waves", {"smoothing_ratio": 1.6525,
                                                 "dt_factor": 0.5,
                                                 "rise": 10e-6}),
    "waves, M = 1, dt/4, ramp 10 us": ("waves", {"smoothing_ratio": 1.6525,
                                                 "dt_factor": 0.25,
                                                 "rise": 10e-6}),
    "waves, M = 1, dt/4, kernel correction": (
        "waves", {"smoothing_ratio": 1.6525, "dt_factor": 0.25,
                  "effects": {"kernel_correction": {}}}),
    "paper": ("paper", {}),
    "paper, dt/2": ("paper", {"dt_factor": 0.5}),
    "paper, static inset": ("paper", {"inset": "static"}),
    "paper, ramp 10 us": ("paper", {"rise": 10e-6}),
}
#: Specimen experiments (against FE): label -> (preset, options)
SPECIMEN = {
    "waves": ("waves", {}),
    "waves, dt/2": ("waves", {"dt_factor": 0.5}),
    "waves, dt/4": ("waves", {"dt_factor": 0.25}),
    "paper, dt/2": ("paper", {"dt_factor": 0.5}),
    "fronts": ("fronts", {"until": LONG}),
    "fronts, step 1/4": ("fronts", {"dt_factor": 0.5}),
    "fronts, kernel correction": (
        "fronts", {"effects": {"kernel_correction": {}}}),
    "fronts, kernel correction, step 1/4": (
        "fronts", {"dt_factor": 0.5, "effects": {"kernel_correction": {}}}),
}
#: Spacing sweeps of the specimen (against the finest FE series): label ->
#: (preset, options, spacings).  The order between two spacings scatters
#: with where each falls against the fronts' ringing; the least-squares
#: slope over many spacings is the steadier measure.
SWEEP_DX = (2e-3, 1.75e-3, 1.5e-3, 1.25e-3, 1e-3, 8.75e-4, 7.5e-4,
            6.25e-4, 5e-4)
SWEEP = {
    "fronts": ("fronts", {}, SWEEP_DX),
    "fronts, step 1/4": ("fronts", {"dt_factor": 0.5}, SWEEP_DX),
    "fronts, kernel correction": (
        "fronts", {"effects": {"kernel_correction": {}}}, SWEEP_DX),
    "fronts, kernel correction, step 1/4": (
        "fronts", {"dt_factor": 0.5, "effects": {"kernel_correction": {}}},
        SWEEP_DX),
}
#: the FE series the specimen is scored against, finest first
FE_SERIES = tuple(Path(f"docs/accuracy/fe_piston_{s}mm.npz")
                  for s in ("0.5", "1", "2"))
FE_NAMES = tuple(f"fe_piston_{s}mm" for s in ("0.5", "1", "2"))
SIGMAS = (1e-6, 2e-6, 4e-6)


def score(kind, run, refs, rise=0.0) -> dict:
    """The errors of one run: per reference (name -> (function of the time
    grid, the time it reaches)), smoothing and norm over 0-0.3 ms, and
    with the 1 us smoothing over 0-1 ms where the run and the reference
    reach it (keys ending in " 1ms"); for the strip also the RMS
    deviation of the signed sigma_yy."""
    e = {}
    if kind == "strip" and "syy" in run:
        e["exact-syy rms 1us"] = deviation(
            {"times": run["times"], "vm": run["syy"]},
            _signed(strip_reference(rise)), "rms")
    for rname, (ref, end) in refs.items():
        for sigma in SIGMAS:
            for norm in ("max", "rms"):
                e[f"{rname} {norm} {sigma * 1e6:g}us"] = deviation(
                    run, ref, norm, sigma)
        if min(end, float(run["times"][-1])) >= LONG - 1e-6:
            for norm in ("max", "rms"):
                e[f"{rname} {norm} 1us 1ms"] = deviation(
                    run, ref, norm, window=LONG)
    return e


def series_path(directory: Path, kind, label, dx) -> Path:
    """Where ``--series`` keeps a run's probe series."""
    return directory / (f"{kind}_{label.replace(' ', '_')}"
                        f"_{dx * 1e3:g}mm.npz".replace("/", ""))


def _fe_refs(paths) -> dict:
    return {_stem(p): fe_series(p) for p in paths if Path(p).exists()}


def _fmt_orders(values) -> str:
    return ", ".join(f"{v:.2f}" for v in values)


def sweep_table(rows, ref=FE_NAMES[0]) -> str:
    """The spacing sweeps: worst-probe RMS (1 us smoothing) against
    ``ref`` per spacing, the orders between successive spacings and the
    least-squares slopes over all spacings, over 2-1 mm and over 1-0.5 mm."""
    chosen = [r for r in rows if r["kind"] == "sweep"]
    if not chosen:
        return ""
    lines = ["| sweep (specimen) | reference | spacings [mm] | RMS % | "
             "orders between successive spacings | least squares: all / "
             "2-1 mm / 1-0.5 mm | CPU s |", "|---|---|---|---|---|---|---|"]
    for r in chosen:
        dxs = [x["dx"] for x in r["runs"]]
        rms = [x["errors"].get(f"{ref} rms 1us") for x in r["runs"]]
        if None in rms:
            continue
        fits = []
        for lo, hi in ((0.0, np.inf), (1e-3, 2e-3), (5e-4, 1e-3)):
            pick = [i for i, d in enumerate(dxs)
                    if lo - 1e-12 <= d <= hi + 1e-12]
            if len(pick) < 2:
                fits.append("")
                continue
            slope = fitted_order([dxs[i] for i in pick],
                                 [rms[i] for i in pick])
            fits.append(f"{slope:.2f} ({len(pick)})")
        lines.append(
            f"| {r['label']} | {ref} | "
            + " / ".join(f"{d * 1e3:g}" for d in dxs) + " | "
            + " / ".join(f"{100 * v:.3g}" for v in rms) + " | "
            + _fmt_orders(orders(dxs, rms)) + " | " + " / ".join(fits)
            + " | " + " / ".join(f"{x['cpu']:.0f}" for x in r["runs"]) + " |")
    return "\n".join(lines + [""])


def table(rows) -> str:
    """Markdown tables of the saved experiments (``order.json``): RMS and
    max deviation (1 us smoothing) per spacing, the observed orders
    (between successive spacings, and the least-squares slope over all),
    CPU seconds, and for the strip where the error sits at the finest
    spacing; the 0-1 ms window for the runs that reach it; the FE series
    against each other."""
    lines = []
    fe_names = list(FE_NAMES)
    for kind, refs in (("strip", ("exact",)), ("specimen", fe_names)):
        chosen = [r for r in rows if r["kind"] == kind]
        if not chosen:
            continue
        dxs = chosen[0]["dx"]
        mm = " / ".join(f"{d * 1e3:g}" for d in dxs)
        head = (f"| {kind} | reference | RMS % ({mm} mm) | RMS orders | "
                f"RMS order, least squares | "
                f"RMS orders, 2 / 4 us smoothing | max % | max orders | "
                f"CPU s |")
        if kind == "strip":
            head += (" RMS % of signed sigma_yy | near / ahead of fronts, "
                     "per spacing |")
        lines += [head, "|" + "---|" * (head.count("|") - 1)]
        for r in chosen:
            for ref in refs:
                e = {n: [x["errors"].get(f"{ref} {n} 1us") for x in r["runs"]]
                     for n in ("rms", "max")}
                if None in e["rms"]:
                    continue
                o = {n: orders(r["dx"], e[n]) for n in e}
                wide = [_fmt_orders(orders(r["dx"], [
                    x["errors"][f"{ref} rms {w}us"] for x in r["runs"]]))
                    for w in (2, 4)]
                line = (f"| {r['label']} | {ref} | "
                        + " / ".join(f"{100 * v:.3g}" for v in e["rms"])
                        + " | " + _fmt_orders(o["rms"])
                        + f" | {fitted_order(r['dx'], e['rms']):.2f}"
                        + " | " + " / ".join(wide)
                        + " | " + " / ".join(f"{100 * v:.3g}" for v in e["max"])
                        + " | " + _fmt_orders(o["max"])
                        + " | " + " / ".join(f"{x['cpu']:.1f}"
                                             for x in r["runs"])
                        + (" (to 1 ms)" if all(x.get("until", 0) >= LONG - 1e-6
                                               for x in r["runs"]) else "")
                        + " |")
                if kind == "strip":
                    syy = [x["errors"].get("exact-syy rms 1us")
                           for x in r["runs"]]
                    line += (" " + (" / ".join(f"{100 * v:.3g}" for v in syy)
                                    if None not in syy else "") + " |")
                    line += " " + ", ".join(
                        f"{x['shares']['near']:.2f} / "
                        f"{x['shares']['ahead']:.2f}" for x in r["runs"]) + " |"
                lines.append(line)
        lines.append("")
    long_rows = []
    for r in (r for r in rows if r["kind"] == "specimen"):
        for ref in fe_names:
            e = {n: [x["errors"].get(f"{ref} {n} 1us 1ms") for x in r["runs"]]
                 for n in ("rms", "max")}
            if None in e["rms"]:
                continue
            mm = " / ".join(f"{d * 1e3:g}" for d in r["dx"])
            long_rows.append(
                f"| {r['label']} | {ref} | "
                + " / ".join(f"{100 * v:.3g}" for v in e["rms"])
                + " | " + _fmt_orders(orders(r["dx"], e["rms"]))
                + f" | {fitted_order(r['dx'], e['rms']):.2f}"
                + " | " + " / ".join(f"{100 * v:.3g}" for v in e["max"])
                + " | " + _fmt_orders(orders(r["dx"], e["max"])) + " |")
    if long_rows:
        lines += [f"| specimen, 0-1 ms | reference | RMS % ({mm} mm) | "
                  "RMS orders | RMS order, least squares | max % | "
                  "max orders |", "|---|---|---|---|---|---|---|"]
        lines += long_rows + [""]
    sweep = sweep_table(rows)
    if sweep:
        lines.append(sweep)
    fe = [r for r in rows if r["kind"] == "fe"]
    if fe:
        fe = fe[0]
        lines += ["| FE series against each other | max % (0-0.3 ms) | "
                  "RMS % (0-0.3 ms) | max % (0-1 ms) | RMS % (0-1 ms) |",
                  "|---|---|---|---|---|"]
        cell = lambda q, k: f"{100 * q[k]:.3g}" if k in q else ""  # noqa
        lines += [f"| {q['pair']} | {cell(q, 'max')} | {cell(q, 'rms')} | "
                  f"{cell(q, 'max 1ms')} | {cell(q, 'rms 1ms')} |"
                  for q in fe["pairs"]]
        lines.append("")
        if fe.get("ringing"):
            lines.append(
                "Part of each FE series that the 1 us smoothing removes "
                "(RMS of raw minus smoothed over the smoothed RMS, worst "
                "probe, 0-0.3 ms): " + ", ".join(
                    f"{n} {100 * v:.2g} %" for n, v in fe["ringing"].items())
                + ".")
        for window, w in fe.get("windows", {}).items():
            sizes = " / ".join(f"{s:g}" for s in w["sizes"])
            lines.append(
                f"FE over 0-{window.strip()}: observed RMS orders "
                f"{_fmt_orders(w['orders'])} (differences ending at "
                f"{sizes} mm); Richardson estimate of the RMS deviation "
                f"from the converged answer: {w['finest']} "
                f"{100 * w['richardson']:.2g} %, the next coarser "
                f"{100 * w['richardson_previous']:.2g} %.")
        lines.append("")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path("/tmp/accur-order"))
    parser.add_argument("--dx", type=float, nargs="+",
                        default=[2e-3, 1e-3, 5e-4])
    parser.add_argument("--experiments", nargs="+", default=["strip"],
                        choices=["strip", "specimen", "sweep"])
    parser.add_argument("--only", nargs="+", default=None,
                        help="labels of the experiments to run")
    parser.add_argument("--tables-only", action="store_true",
                        help="run nothing: the tables from DIR/order.json")
    parser.add_argument("--series", action="store_true",
                        help="also save each run's probe series (npz)")
    parser.add_argument("--series-dir", type=Path, default=None,
                        help="where --series keeps them (default: --out)")
    parser.add_argument("--rescore", action="store_true",
                        help="run nothing: score the specimen runs kept by "
                        "--series again against the FE series of --fe "
                        "(after a finer one was added)")
    parser.add_argument("--doc", type=Path, default=None,
                        help="also write the tables between <!-- order:begin "
                        "--> and <!-- order:end --> of this file "
                        "(docs/validation.md)")
    parser.add_argument("--fe", nargs="+", type=Path, default=list(FE_SERIES))
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    series_dir = args.series_dir or args.out
    series_dir.mkdir(parents=True, exist_ok=True)
    path = args.out / "order.json"
    fe_refs = _fe_refs(args.fe)
    if args.rescore:
        saved = json.loads(path.read_text()) if path.exists() else []
        for row in saved:
            if row["kind"] not in ("specimen", "sweep") or (args.only
                                             and row["label"] not in args.only):
                continue
            for r in row["runs"]:
                f = series_path(series_dir, row["kind"], row["label"], r["dx"])
                if not f.exists():
                    print(f"{f}: no series kept, {row['label']} at "
                          f"{r['dx'] * 1e3:g} mm not rescored", flush=True)
                    continue
                data = np.load(f)
                r["errors"] = score("specimen", {
                    "times": data["times"],
                    "vm": {n: data[n] for n in "ABC"}}, fe_refs)
            errs = {}
            for r in row["runs"]:
                for key, value in r["errors"].items():
                    errs.setdefault(key, []).append(value)
            row["orders"] = {k: orders(row["dx"], v) for k, v in errs.items()
                             if len(v) == len(row["dx"])}
        path.write_text(json.dumps(saved, indent=1))
    rows = []
    for kind in [] if args.tables_only or args.rescore else args.experiments:
        experiments = {"strip": STRIP, "specimen": SPECIMEN,
                       "sweep": SWEEP}[kind]
        for label, (preset, options, *spacings) in experiments.items():
            if args.only and label not in args.only:
                continue
            dxs = list(spacings[0]) if spacings else args.dx
            options = dict(options)
            rise = options.get("rise", 0.0)
            errs = {}
            row = {"kind": kind, "label": label, "dx": dxs, "runs": []}
            for dx in dxs:
                run = (strip_run if kind == "strip" else specimen_run)(
                    dx, preset, **options)
                if args.series:
                    np.savez_compressed(
                        series_path(series_dir, kind, label, dx),
                        times=run["times"], **run["vm"])
                shares = None
                if kind == "strip":
                    refs = {"exact": (strip_reference(rise), np.inf)}
                    shares = front_share(run, rise)
                else:
                    refs = fe_refs
                e = score(kind, run, refs, rise)
                row["runs"].append({"dx": dx, "cpu": run["cpu"],
                                    "shares": shares,
                                    "wall": run["wall"], "steps": run["steps"],
                                    "particle_steps": run["steps"]
                                    * run["particles"],
                                    "until": float(run["times"][-1]),
                                    "load": os.getloadavg()[0],
                                    "errors": e})
                for key, value in e.items():
                    errs.setdefault(key, []).append(value)
                print(json.dumps({"label": label, "dx": dx,
                                  "cpu": round(run["cpu"], 2),
                                  **{k: round(100 * v, 3)
                                     for k, v in e.items()
                                     if "1us" in k}}), flush=True)
            row["orders"] = {k: orders(dxs, v) for k, v in errs.items()}
            rows.append(row)
            print(json.dumps({"label": label, "orders": {
                k: [round(o, 2) for o in v] for k, v in row["orders"].items()
                if "rms" in k}}), flush=True)
            old = json.loads(path.read_text()) if path.exists() else []
            old = [r for r in old if not (r["kind"] == kind
                                          and r["label"] == label)]
            path.write_text(json.dumps(old + [row], indent=1))
    fe_paths = [Path(f"docs/accuracy/fe_piston_{s}mm.npz")
                for s in ("4", "2", "1", "0.5")]
    if all(p.exists() for p in fe_paths[:3]):
        old = json.loads(path.read_text()) if path.exists() else []
        old = [r for r in old if r["kind"] != "fe"]
        extra = [(f"fe_piston_{s}mm at half its step vs fe_piston_{s}mm",
                  Path(f"docs/accuracy/fe_piston_{s}mm_half_step.npz"),
                  Path(f"docs/accuracy/fe_piston_{s}mm.npz"))
                 for s in ("2", "1")]
        extra.append(("fe_piston_1mm at half its step vs fe_piston_0.5mm "
                      "(the same step)",
                      Path("docs/accuracy/fe_piston_1mm_half_step.npz"),
                      Path("docs/accuracy/fe_piston_0.5mm.npz")))
        path.write_text(json.dumps(old + [{"kind": "fe", "label": "fe",
                                           **fe_self(fe_paths, extra)}],
                                   indent=1))
    if path.exists():
        text = table(json.loads(path.read_text()))
        (args.out / "order.md").write_text(text)
        if args.doc is not None:
            body = args.doc.read_text()
            begin, end = "<!-- order:begin -->", "<!-- order:end -->"
            if begin not in body or end not in body:
                raise SystemExit(f"{args.doc}: no {begin} ... {end} markers")
            head, rest = body.split(begin, 1)
            args.doc.write_text(
                head + begin + "\n<!-- generated by python -m validation."
                "order; do not edit -->\n" + text + end
                + rest.split(end, 1)[1])


if __name__ == "__main__":
    main()
