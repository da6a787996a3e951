"""Accuracy versus cost of the piston test over the scheme's options
(docs/validation.md, section 4, "The accuracy front"; the generated table
and figure: docs/validation/front.md, docs/validation/front/front.png).

    python -m validation.front                         # whole study + doc
    python -m validation.front --dx 5e-4 --options waves --no-doc   # part
    sphsolid study front                               # the same command

Axes: the integrator (Improved Euler, leapfrog), the kernel and h/dx
(cubic spline at 1.2 and 1.25, the fourth-order cubic_o4 at 1.65), the
artificial viscosity, the platen placement (the paper's, the static
inset), the time step and the named presets (``sphsolid.presets``:
paper, waves, fronts), each at dx = 2, 1
and 0.5 mm. Metric: the issue's, von Mises at A, B, C over 0-0.3 ms
against the 1 mm finite-element series
(``docs/accuracy/fe_piston_1mm.npz``), both smoothed with a 1 us
Gaussian, worst probe's largest deviation over the reference's peak and
RMS deviation over its RMS (``sphsolid.metrics``). Cost: CPU seconds of
the run (one thread; the load-independent measure on a shared machine),
particle-steps, and the wall time (which depends on the load).

Every run is saved in ``--runs`` (one JSON file per option and spacing:
errors and costs) and reused: the study can be run in parts (``--dx``,
``--options``, ``--no-doc``), in parallel processes, and the last call
without ``--no-doc`` draws the figure and writes the section between the
markers ``<!-- front:begin -->`` and ``<!-- front:end -->`` of
``--doc`` from all saved runs; ``--rerun`` runs the selected ones again.
"""
from __future__ import annotations

import argparse
import json
import os
import re
from pathlib import Path

import numpy as np

from sphsolid import presets, scenes
from sphsolid.calculators import CLibrary
from sphsolid.dynamics import dynamics_for
from sphsolid.probes import PAPER_PROBES

from . import decomposition

WINDOW = decomposition.WINDOW
DXS = (2e-3, 1e-3, 5e-4)
FE = Path("docs/accuracy/fe_piston_1mm.npz")
RUNS = Path("docs/validation/front")
DOC = Path("docs/validation/front.md")
FIGURE = "front.png"
BEGIN, END = "<!-- front:begin -->", "<!-- front:end -->"

#: label -> (key, preset, integrator or None for the preset's,
#:           overrides of scenes.uniaxial_piston, factor on the default step)
OPTIONS = {
    "paper": ("paper", "paper", None, {}, 1.0),
    "paper, leapfrog": ("paper-leapfrog", "paper", "leapfrog", {}, 1.0),
    "paper, static inset": ("paper-inset", "paper", None,
                            {"inset": "static"}, 1.0),
    "paper, h/dx 1.25": ("paper-h1.25", "paper", None,
                         {"smoothing_ratio": 1.25}, 1.0),
    "cubic_o4, Improved Euler, alpha 0.25": (
        "o4-ie", "waves", "improved_euler",
        {"inset": 0.0, "viscosity": {"alpha": 0.25, "beta": 0.0}}, 1.0),
    "cubic_o4, Improved Euler, alpha 0.25, step 0.3 h/c0": (
        "o4-ie-0.3", "waves", "improved_euler",
        {"inset": 0.0, "viscosity": {"alpha": 0.25, "beta": 0.0}}, 0.9),
    "cubic_o4, leapfrog, no viscosity (waves, inset 0)": (
        "o4-lf", "waves", None, {"inset": 0.0}, 1.0),
    "waves (cubic_o4, leapfrog, static inset)": ("waves", "waves", None, {},
                                                 1.0),
    "waves, half step": ("waves-dt2", "waves", None, {}, 0.5),
    "fronts (cubic_o4 at M = 1, leapfrog at half step, static inset)": (
        "fronts", "fronts", None, {}, 1.0),
    "fronts, kernel correction, quarter step": (
        "fronts-kc-dt2", "fronts", None,
        {"effects": {"kernel_correction": {}}}, 0.5),
}
KEYS = {v[0]: k for k, v in OPTIONS.items()}
#: a run whose RMS deviation exceeds this has gone unstable (its stress
#: grows): listed, left off the figure and the Pareto fronts
UNSTABLE = 1.0


def run(dx: float, label: str, window: float = WINDOW, threads: int = 1,
        reference: Path = FE) -> dict:
    """One option at one spacing: the metric against the FE series and the
    costs."""
    key, preset, integrator, overrides, factor = OPTIONS[label]
    overrides = dict(overrides)
    effects = overrides.pop("effects", None)
    scene = decomposition.with_effects(
        scenes.uniaxial_piston(dx, preset=preset, **overrides), effects)
    scene.calc = CLibrary(threads=threads)
    dyn = (presets.dynamics(scene, progress=False) if integrator is None
           else dynamics_for(integrator)(scene, progress=False))
    kind = type(dyn)
    if factor != 1.0:
        dyn = kind(scene, dt=dyn.dt * factor, progress=False)
    r = decomposition.probe_series(scene, dyn, PAPER_PROBES, window)
    err = decomposition.error(r, decomposition.fe_reference(reference))
    return {"option": label, "key": key, "dx": dx, "window": window,
            "max": err["max"], "rms": err["rms"], "cpu": r["cpu"],
            "wall": r["wall"], "steps": r["steps"],
            "particles": r["particles"],
            "particle_steps": r["steps"] * r["particles"],
            "threads": threads, "integrator": type(dyn).__name__,
            "dt": dyn.dt,
            "kernel": scene.kernel, "h_over_dx": scene.smoothing_ratio,
            "effects": scene.effects, "load": os.getloadavg()[0]}


def pareto(points, cost, error="rms") -> list:
    """Whether no other point is both no more costly and more accurate."""
    return [not any(o[cost] <= q[cost] and o[error] < q[error]
                    for o in points if o is not q) for q in points]


def observed_orders(points) -> dict:
    """Per option, the observed order of the RMS and max deviations
    between successive spacings present."""
    out = {}
    for label in OPTIONS:
        qs = sorted((q for q in points if q["option"] == label),
                    key=lambda q: -q["dx"])
        if len(qs) < 2:
            continue
        out[label] = {norm: [float(np.log(a[norm] / b[norm])
                                   / np.log(a["dx"] / b["dx"]))
                             for a, b in zip(qs, qs[1:])]
                      for norm in ("rms", "max")}
        out[label]["dx"] = [q["dx"] for q in qs]
    return out


def plot(points, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6), constrained_layout=True)
    for ax, cost, name in ((axes[0], "cpu", "CPU time [s], one thread"),
                           (axes[1], "particle_steps", "particle-steps")):
        for label in OPTIONS:
            qs = sorted((q for q in points if q["option"] == label),
                        key=lambda q: q[cost])
            if qs:
                ax.loglog([q[cost] for q in qs],
                          [100 * q["rms"] for q in qs], "o-", label=label)
        front = sorted((q for q, on in zip(points, pareto(points, cost))
                        if on), key=lambda q: q[cost])
        ax.loglog([q[cost] for q in front], [100 * q["rms"] for q in front],
                  "k--", lw=1.5, label="Pareto front")
        ax.set_xlabel(name)
        ax.set_ylabel("worst-probe RMS deviation vs FE [%]")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("Piston test, von Mises at A, B, C over 0-0.3 ms, against "
                 "the 1 mm FE (1 us smoothing); each line dx = 2, 1, 0.5 mm "
                 "from left to right")
    fig.savefig(path, dpi=100)
    plt.close(fig)


def section(points, figure) -> str:
    """The generated Markdown of the accuracy front."""
    grown = [q for q in points if q["rms"] > UNSTABLE]
    points = [q for q in points if q["rms"] <= UNSTABLE]
    cpu_front = pareto(points, "cpu")
    ps_front = pareto(points, "particle_steps")
    cpu_front_max = pareto(points, "cpu", "max")
    rows = sorted(zip(points, cpu_front, ps_front, cpu_front_max),
                  key=lambda z: (-z[0]["dx"], z[0]["cpu"]))
    loads = [q["load"] for q in points]
    lines = [
        "<!-- generated by python -m validation.front; do not edit -->",
        f"![accuracy front]({figure})", "",
        "Worst probe over A, B, C, 0-0.3 ms, against the 1 mm FE series, "
        "1 us smoothing; CPU seconds of the run on one thread; * = on the "
        "Pareto front of RMS deviation against CPU time (C), particle-steps "
        "(P), and of the max deviation against CPU time (M). Wall times "
        f"were taken under a load average of {min(loads):.1f}-"
        f"{max(loads):.1f} on 2 cores and are not a measure of the scheme.",
        "",
        "| option | dx [mm] | max % | RMS % | CPU s | wall s | steps | "
        "particle-steps | Pareto |",
        "|---|---|---|---|---|---|---|---|---|"]
    for q, c, p, m in rows:
        flags = "".join(f for f, on in (("C", c), ("P", p), ("M", m)) if on)
        lines.append(
            f"| {q['option']} | {q['dx'] * 1e3:g} | {100 * q['max']:.2f} | "
            f"{100 * q['rms']:.2f} | {q['cpu']:.1f} | {q['wall']:.1f} | "
            f"{q['steps']} | {q['particle_steps']:.3g} | {flags} |")
    for q in grown:
        lines.append(f"| {q['option']} | {q['dx'] * 1e3:g} | grows: "
                     f"{100 * q['max']:.3g} | {100 * q['rms']:.3g} | "
                     f"{q['cpu']:.1f} | {q['wall']:.1f} | {q['steps']} | "
                     f"{q['particle_steps']:.3g} | unstable |")
    lines += ["", "Observed order of the deviations between successive "
              "spacings (2 to 1 mm, 1 to 0.5 mm):", "",
              "| option | RMS | max |", "|---|---|---|"]
    for label, o in observed_orders(points).items():
        lines.append(f"| {label} | "
                     + ", ".join(f"{v:.2f}" for v in o["rms"]) + " | "
                     + ", ".join(f"{v:.2f}" for v in o["max"]) + " |")
    best = {}
    for q in points:
        if q["max"] <= 0.05 and (q["dx"] not in best
                                 or q["cpu"] < best[q["dx"]]["cpu"]):
            best[q["dx"]] = q
    cheapest = sorted(points, key=lambda q: q["cpu"])
    under = [q for q in cheapest if q["max"] <= 0.025 and q["rms"] <= 0.012]
    lines += ["", "Cheapest run with max <= 5 %: "
              + (f"{min(best.values(), key=lambda q: q['cpu'])['option']} at "
                 f"{min(best.values(), key=lambda q: q['cpu'])['dx'] * 1e3:g}"
                 " mm" if best else "none")
              + "; cheapest with max <= 2.5 % and RMS <= 1.2 %: "
              + (f"{under[0]['option']} at {under[0]['dx'] * 1e3:g} mm "
                 f"({under[0]['cpu']:.1f} CPU s)" if under else "none")
              + "."]
    return "\n".join(lines) + "\n"


def write_doc(doc: Path, text: str):
    body = doc.read_text()
    if BEGIN not in body or END not in body:
        raise SystemExit(f"{doc}: no {BEGIN} ... {END} markers to write "
                         "the accuracy front between")
    pattern = re.compile(re.escape(BEGIN) + ".*?" + re.escape(END), re.S)
    doc.write_text(pattern.sub(lambda _: BEGIN + "\n" + text + END, body))


def load(runs: Path) -> list:
    points = [json.loads(p.read_text()) for p in sorted(runs.glob("*.json"))]
    order = {label: i for i, label in enumerate(OPTIONS)}
    return sorted((q for q in points if q["option"] in order),
                  key=lambda q: (order[q["option"]], -q["dx"]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dx", type=float, nargs="+", default=list(DXS))
    parser.add_argument("--options", nargs="+", default=list(KEYS),
                        choices=list(KEYS), help="option keys")
    parser.add_argument("--runs", type=Path, default=RUNS)
    parser.add_argument("--doc", type=Path, default=DOC)
    parser.add_argument("--no-doc", action="store_true",
                        help="only run (and save) the selected runs")
    parser.add_argument("--rerun", action="store_true")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--fe", type=Path, default=FE)
    args = parser.parse_args(argv)
    args.runs.mkdir(parents=True, exist_ok=True)
    for key in args.options:
        for dx in args.dx:
            path = args.runs / f"{key}_{dx * 1e3:g}mm.json"
            if path.exists() and not args.rerun:
                continue
            point = run(dx, KEYS[key], threads=args.threads, reference=args.fe)
            path.write_text(json.dumps(point, indent=1))
            print(json.dumps({k: point[k] for k in ("option", "dx", "max",
                                                     "rms", "cpu", "wall")}),
                  flush=True)
    if args.no_doc:
        return
    points = load(args.runs)
    (args.doc.parent / args.doc.stem).mkdir(parents=True, exist_ok=True)
    plot([q for q in points if q["rms"] <= UNSTABLE],
         args.doc.parent / args.doc.stem / FIGURE)
    write_doc(args.doc, section(points, f"{args.doc.stem}/{FIGURE}"))
    print(f"wrote {args.doc} and {args.doc.stem}/{FIGURE} from "
          f"{len(points)} runs")


if __name__ == "__main__":
    main()
