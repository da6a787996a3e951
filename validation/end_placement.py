"""End placement and presets on the paper's piston test (docs/validation.md,
section "End placement and presets").

    python -m validation.end_placement [--dx 2e-3 1e-3 5e-4] [--slopes]
                                       [--threads 2] [--out DIR]

For each setting (a preset, with or without the platen inset) and spacing:

- the specimen against the 1 mm finite-element series over 0-0.3 ms
  (``docs/accuracy/fe_piston_1mm.npz``), the issue's metric: both series
  smoothed with a 1 us Gaussian, worst probe's max deviation over the
  reference's peak and RMS deviation over its RMS (sphsolid.metrics);
- the laterally periodic strip against its exact staircase
  (validation.decomposition) and the delay of each front;
- with ``--slopes``, the run to 5 ms at the first spacing and the slope of
  each probe's von Mises over 3.5-5 ms against the quasi-static FE slope
  (``validation.fe_reference.static_pattern`` at 1 mm: von Mises per
  metre of compression times the piston speed).

The scenes are the users' (``scenes.uniaxial_piston(dx, preset=...,
inset=...)``), run with the preset's integrator; CPU seconds (the
process's, all threads) and wall seconds are recorded for each run.
"""
from __future__ import annotations

import argparse
import json
import time as wallclock
from pathlib import Path

import numpy as np

from sphsolid import build, presets, scenes
from sphsolid.calculators import CLibrary
from sphsolid.probes import PAPER_PROBES, Probes
from sphsolid.scene import Scene

from . import decomposition

#: label -> (preset, overrides of uniaxial_piston)
SETTINGS = {
    "paper": ("paper", {}),
    "paper, static inset": ("paper", {"inset": "static"}),
    "waves, inset 0": ("waves", {"inset": 0.0}),
    "waves (static inset)": ("waves", {}),
}
SLOPE_WINDOW = (3.5e-3, 5e-3)


def specimen_run(dx, preset, until=decomposition.WINDOW, threads=1,
                 interval=1, **overrides) -> dict:
    """Probe series of the paper scene built from a preset."""
    scene = scenes.uniaxial_piston(dx, preset=preset, **overrides)
    scene.calc = CLibrary(threads=threads)
    dyn = presets.dynamics(scene, progress=False)
    result = decomposition.probe_series(scene, dyn, PAPER_PROBES, until, interval)
    result["inset"] = scene.bodies[1].hi[1] / (scene.bodies[0].hi[1]
                                               / scene.bodies[0].lattice_shape[1])
    return result


def strip_scene(dx, preset, **overrides) -> Scene:
    """The laterally periodic strip (8 dx wide) between plate and piston,
    with the preset's kernel, h/dx, viscosity and inset."""
    chosen = presets.preset(preset)
    setting = chosen.to_dict()
    setting.update(overrides)
    rock = scenes.paper_material()
    H = scenes.SPECIMEN_Y[1]
    x = (-4 * dx, 4 * dx)
    effects = ({} if setting["viscosity"] is None
               else {"artificial_viscosity": dict(setting["viscosity"])})
    scene = Scene(2, [], effects=effects, kernel=setting["kernel"],
                  smoothing_ratio=setting["smoothing_ratio"],
                  domain=((x[0], -0.02), (x[1], H + 0.03)),
                  periodic=(True, False))
    strip = build.rectangle(x, (0.0, H), dx, rock, "specimen")
    scene.add(strip)
    scene.add(build.plate(under=strip, inset=setting["inset"]))
    scene.add(build.piston(over=strip, velocity=(0.0, -scenes.PISTON_SPEED),
                           inset=setting["inset"]))
    scene.preset = chosen
    return scene


def strip_run(dx, preset, **overrides) -> dict:
    scene = strip_scene(dx, preset, **overrides)
    scene.calc = CLibrary(threads=1)
    dyn = presets.dynamics(scene, progress=False)
    probes = Probes(scene, decomposition.STRIP_PROBES)
    dyn.attach(probes, interval=1)
    cpu = wallclock.process_time()
    dyn.run(until=decomposition.WINDOW)
    return {"times": np.asarray(probes.times),
            "vm": {n: np.asarray(probes[n]["von_mises"]) for n in probes.names},
            "cpu": wallclock.process_time() - cpu}


def static_slopes(element_size=1e-3,
                  stored=Path("docs/validation/results.json")) -> dict:
    """Quasi-static FE slope of each probe's von Mises [Pa/s] (without
    scikit-fem: the study's stored values, same mesh)."""
    from . import fe_reference
    if not fe_reference.available():
        return dict(json.loads(stored.read_text())["fe"]["static_slopes"])
    rock = scenes.paper_material()
    compression = 1e-6
    static = fe_reference.static_pattern(element_size, PAPER_PROBES, rock.K,
                                         rock.mu, compression)
    return {n: v / compression * scenes.PISTON_SPEED
            for n, v in static.items()}


def steady_slopes(result, window=SLOPE_WINDOW) -> dict:
    t = result["times"]
    keep = (t >= window[0]) & (t <= window[1])
    return {n: float(np.polyfit(t[keep], v[keep], 1)[0])
            for n, v in result["vm"].items()}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path("/tmp/end_placement"))
    parser.add_argument("--dx", type=float, nargs="+",
                        default=[2e-3, 1e-3, 5e-4])
    parser.add_argument("--settings", nargs="+", default=list(SETTINGS),
                        choices=list(SETTINGS))
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--fe", type=Path,
                        default=Path("docs/accuracy/fe_piston_1mm.npz"))
    parser.add_argument("--slopes", action="store_true",
                        help="also run to 5 ms at the first --dx")
    parser.add_argument("--no-strip", action="store_true")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    reference = decomposition.fe_reference(args.fe)

    def strip_ref(grid):
        return {n: decomposition.strip_exact(grid, p[1])
                for n, p in decomposition.STRIP_PROBES.items()}

    rows = []
    if args.slopes:
        fe = static_slopes()
        print(json.dumps({"static_fe_slopes_kPa_per_ms":
                          {n: v / 1e6 for n, v in fe.items()}}), flush=True)
    for label in args.settings:
        preset, overrides = SETTINGS[label]
        for dx in args.dx:
            row = {"setting": label, "dx": dx}
            r = specimen_run(dx, preset, threads=args.threads, **overrides)
            row["specimen"] = decomposition.error(r, reference)
            row.update(cpu=r["cpu"], wall=r["wall"], steps=r["steps"],
                       particles=r["particles"], inset=r["inset"],
                       threads=args.threads)
            if not args.no_strip:
                s = strip_run(dx, preset, **overrides)
                row["strip"] = decomposition.error(s, strip_ref)
                row["delays_us"] = {n: [round(d * 1e6, 2) for d in v]
                                    for n, v in decomposition.front_delays(
                                        s).items()}
            rows.append(row)
            print(json.dumps(row), flush=True)
        if args.slopes:
            dx = args.dx[0]
            r = specimen_run(dx, preset, until=SLOPE_WINDOW[1],
                             threads=args.threads, interval=10, **overrides)
            slopes = steady_slopes(r)
            row = {"setting": label, "dx": dx, "until": SLOPE_WINDOW[1],
                   "slopes_kPa_per_ms": {n: v / 1e6 for n, v in slopes.items()},
                   "vs_fe_percent": {n: 100 * (slopes[n] / fe[n] - 1)
                                     for n in slopes},
                   "cpu": r["cpu"], "wall": r["wall"]}
            rows.append(row)
            print(json.dumps(row), flush=True)
    (args.out / "end_placement.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
