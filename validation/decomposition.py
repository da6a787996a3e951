"""Error decomposition of the piston test (docs/validation.md, section
"What limits the error").

    python -m validation.decomposition [--out DIR] [--dx 1e-3 ...]

Each experiment switches one error source off or changes it alone:

- the laterally periodic strip (the specimen's height, plate and piston,
  no free surfaces, no corners) against its exact solution: a staircase
  of plane fronts, von Mises 2 mu v/c_p higher after each passage;
- the same strip with the time step halved (time stepping), with
  artificial viscosity 1, 0.5, 0.25 (dissipation), at h/dx = 1.25 where
  the cubic spline's lattice gradient moment is 1 (lattice speed), with
  the fourth-order kernel cubic_o4 (lattice dispersion), with Leapfrog
  and no viscosity, and with the plate and piston moved towards the
  specimen by a fraction of dx (loaded ends);
- the arrival of each front at the probes against (2kH +- y)/c_p: the
  delay per passage separates a speed error (grows with the distance
  travelled) from an end error (grows with the number of reflections);
- the paper's specimen against the finite-element reference of
  ``docs/accuracy/fe_piston_1mm.npz`` (validation/accuracy.py keeps it).

Metric: both series smoothed with a 1 us Gaussian (sphsolid.metrics),
largest deviation over the reference's peak and RMS deviation over the
reference's RMS, worst probe, 0-0.3 ms. Every run is the library's.
"""
from __future__ import annotations

import argparse
import json
import time as wallclock
from pathlib import Path

import numpy as np

from sphsolid import build, metrics, scenes
from sphsolid.build import Velocity
from sphsolid.calculators import CLibrary
from sphsolid.dynamics import dynamics_for
from sphsolid.probes import PAPER_PROBES, Probes
from sphsolid.scene import Scene

WINDOW = 3e-4
STRIP_PROBES = {"A": (0.0, 0.070), "B": (0.0, 0.1035)}

#: Variants: label -> options of :func:`run`.
VARIANTS = {
    "paper (cubic 1.2, alpha 1, Improved Euler)": {},
    "dt / 2": {"dt_factor": 0.5},
    "alpha 0.5": {"alpha": 0.5},
    "alpha 0.25": {"alpha": 0.25},
    "h/dx 1.25 (M = 1.001)": {"ratio": 1.25},
    "kernel correction": {"correction": True},
    "cubic_o4 1.65, alpha 0.25": {"ratio": 1.65, "kernel": "cubic_o4",
                                  "alpha": 0.25},
    "cubic_o4 1.65, Leapfrog, no viscosity": {
        "ratio": 1.65, "kernel": "cubic_o4", "alpha": 0.0,
        "integrator": "leapfrog"},
    "cubic_o4 1.65, Leapfrog, no viscosity, ends 0.25 dx in": {
        "ratio": 1.65, "kernel": "cubic_o4", "alpha": 0.0,
        "integrator": "leapfrog", "ends_in": 0.25},
}


def scene(dx, strip=False, ratio=1.2, kernel="cubic_spline", alpha=1.0,
          correction=False, ends_in=0.0) -> Scene:
    """The specimen (or a laterally periodic strip of it, 8 dx wide)
    between plate and piston; ``ends_in`` moves plate and piston towards
    the specimen by that fraction of dx."""
    rock = scenes.paper_material()
    H = scenes.SPECIMEN_Y[1]
    x = (-4 * dx, 4 * dx) if strip else scenes.SPECIMEN_X
    specimen = build.rectangle(x, (0.0, H), dx, rock, "specimen")
    effects = {}
    if alpha:
        effects["artificial_viscosity"] = {"alpha": alpha, "beta": 0.0}
    if correction:
        effects["kernel_correction"] = {}
    extra = ({"domain": ((x[0], -0.02), (x[1], H + 0.03)),
              "periodic": (True, False)} if strip else {})
    scene = Scene(2, [specimen], effects=effects, smoothing_ratio=ratio,
                  kernel=kernel, **extra)
    # plate and piston one kernel support thick (sph_support_layers)
    layers = scene.support_layers(dx)
    d = ends_in * dx
    scene.add(build.block((x[0], -layers * dx + d), (x[1], d), dx, rock,
                          "plate", "fixed", role="plate"))
    scene.add(build.block((x[0], H - d), (x[1], H - d + layers * dx), dx,
                          rock, "piston", Velocity((0.0, -scenes.PISTON_SPEED)),
                          role="piston"))
    return scene


def run(dx, strip=False, until=WINDOW, dt_factor=1.0,
        integrator="improved_euler", **options) -> dict:
    """Probe series (every step) of one run; wall and CPU time."""
    s = scene(dx, strip=strip, **options)
    s.calc = CLibrary(threads=1)
    dynamics = dynamics_for(integrator)
    dyn = dynamics(s, progress=False)
    dyn = dynamics(s, dt=dyn.dt * dt_factor, progress=False)
    return probe_series(s, dyn, STRIP_PROBES if strip else PAPER_PROBES, until)


def with_effects(scene, effects):
    """Switch on ``effects`` (name -> parameters) on top of the scene's
    own; the scene, for chaining."""
    for name, parameters in (effects or {}).items():
        scene.effect(name, **parameters)
    return scene


def probe_series(scene, dyn, points, until, interval=1) -> dict:
    """Run `dyn` on `scene` to `until`, sampling von Mises at `points`
    every `interval` steps; the series with the run's wall and CPU time."""
    probes = Probes(scene, points)
    dyn.attach(probes, interval=interval)
    wall, cpu = wallclock.perf_counter(), wallclock.process_time()
    dyn.run(until=until)
    return {"times": np.asarray(probes.times),
            "vm": {n: np.asarray(probes[n]["von_mises"]) for n in probes.names},
            "wall": wallclock.perf_counter() - wall,
            "cpu": wallclock.process_time() - cpu,
            "steps": dyn.nsteps, "particles": len(scene)}


def ramp(t, rise: float):
    """The piston's speed over its final speed: 0 before t = 0, the C2
    quintic 10 s^3 - 15 s^4 + 6 s^5 (s = t/rise) up to ``rise``, then 1;
    a step (1 from t = 0 on) when ``rise`` is 0."""
    t = np.asarray(t, float)
    if rise <= 0:
        return (t > 0).astype(float)
    s = np.clip(t / rise, 0.0, 1.0)
    return s ** 3 * (10 - 15 * s + 6 * s * s)


def arrivals(y, passages=4) -> list:
    """Exact arrival times of the strip's fronts at height y, in order:
    (2kH + H - y)/c_p and (2kH + H + y)/c_p."""
    c, H = scenes.paper_material().c_p, scenes.SPECIMEN_Y[1]
    return sorted([(2 * k * H + H - y) / c for k in range(passages)]
                  + [(2 * k * H + H + y) / c for k in range(passages)])


def front_jump() -> float:
    """Von Mises added by each front: 2 mu v/c_p [Pa]."""
    rock = scenes.paper_material()
    return 2 * rock.mu * scenes.PISTON_SPEED / rock.c_p


def strip_exact(times, y, rise=0.0):
    """Von Mises at height y of the strip: 2 mu (v/c_p) times the fronts
    passed, the fronts at (2kH + H - y)/c_p and (2kH + H + y)/c_p (bottom
    fixed, top moving at v from t = 0; with ``rise`` > 0 the piston's
    speed follows :func:`ramp` and so does each front: linear acoustics,
    both ends reflect with the same sign)."""
    c, H = scenes.paper_material().c_p, scenes.SPECIMEN_Y[1]
    times = np.asarray(times, float)
    passages = int(times[-1] * c / (2 * H)) + 2
    total = sum(ramp(times - t, rise) for t in arrivals(y, passages))
    return front_jump() * total


def front_delays(result) -> dict:
    """Per probe, the delay [s] of each front's half-step crossing against
    its exact arrival time."""
    jump = front_jump()
    out = {}
    for n, (_, y) in STRIP_PROBES.items():
        t, v = result["times"], result["vm"][n]
        delays = []
        for i, te in enumerate(a for a in arrivals(y) if a < t[-1] - 1e-5):
            level = (i + 0.5) * jump
            idx = np.nonzero((t > te - 8e-6) & (v > level))[0]
            if not len(idx) or idx[0] == 0:
                break
            j = idx[0]
            tc = t[j - 1] + (level - v[j - 1]) * (t[j] - t[j - 1]) / (v[j] - v[j - 1])
            delays.append(float(tc - te))
        out[n] = delays
    return out


def error(result, reference) -> dict:
    """Worst-probe smoothed max and RMS deviation against ``reference``
    (a function of the grid returning {probe: series})."""
    grid = metrics.time_grid(0.0, WINDOW)
    ref = reference(grid)
    series = {n: metrics.on_grid(result["times"], result["vm"][n], grid)
              for n in ref}
    return {norm: metrics.worst_deviation(series, ref, grid, norm)
            for norm in ("max", "rms")}


def fe_reference(path):
    data = np.load(path)
    return lambda grid: {n: np.interp(grid, data["grid"], data[n])
                         for n in "ABC"}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path("docs/validation"))
    parser.add_argument("--dx", type=float, nargs="+", default=[2e-3, 1e-3])
    parser.add_argument("--fe", type=Path,
                        default=Path("docs/accuracy/fe_piston_1mm.npz"))
    parser.add_argument("--specimen", action="store_true",
                        help="also the full specimen against the FE reference")
    args = parser.parse_args(argv)
    rows = []

    def strip_ref(grid):
        return {n: strip_exact(grid, p[1]) for n, p in STRIP_PROBES.items()}

    for label, options in VARIANTS.items():
        for dx in args.dx:
            row = {"variant": label, "dx": dx}
            try:
                r = run(dx, strip=True, **options)
            except Exception as exc:            # a blow-up is a result here
                row["strip"] = f"failed: {exc}"
            else:
                row["strip"] = error(r, strip_ref)
                row["delays"] = front_delays(r)
                row["strip_cpu"] = r["cpu"]
            if args.specimen and args.fe.exists():
                try:
                    r = run(dx, **options)
                except Exception as exc:
                    row["specimen"] = f"failed: {exc}"
                else:
                    row["specimen"] = error(r, fe_reference(args.fe))
                    row["specimen_cpu"] = r["cpu"]
                    row["particle_steps"] = r["particles"] * r["steps"]
            rows.append(row)
            print(json.dumps(row), flush=True)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "decomposition.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
