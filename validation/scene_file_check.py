"""The planner on a user's own scene file, the way a user runs it, against
a finite-element answer of the same problem (docs/planner.md, "A scene
file checked").

    python -m validation.scene_file_check SCENE.toml [--probe A ...]
        [--requests max:10,max:5,rms:5] [--threads 1] [--fe-size 0.25mm]
        [--sweep paper,waves,fronts [--spacings 2mm,1mm,0.5mm]] [--out DIR]

For each request, in the order given and with one planner cache (as a
user's successive requests share it): ``sphsolid plan SCENE.toml --error
E% --norm N --probe ...`` and, when planned, ``sphsolid run SCENE.toml
--plan``, each as its own process, timed. What the user receives (the
run's probe CSV, von Mises columns, interpolated on the FE's 0.05 us grid)
is scored with :func:`sphsolid.metrics.worst_deviation` against the FE
series at ``--fe-size`` and, to show the reference's own convergence, the
FE series at twice that size against it.  ``--sweep`` runs the file
besides with each named preset at each of ``--spacings`` (its first
body's ``dx`` set, the others' scaled alike), unplanned, scored alike:
what a refused request could have had.  ``--requests ""`` runs the sweep alone.

The FE answer (:func:`validation.fe_reference.piston_fe`: plane strain,
quadratic quadrilaterals, Newmark) covers the scenes it can state: 2D, one
rectangular block (``shape = "block"``) between a fixed plate under it and
a piston over it that moves at a constant vertical velocity, one elastic
material; any other file is refused with the reason. The planner never
sees this answer: the scene is one it was not tuned on.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import re
import subprocess
import sys
import time as wallclock
from pathlib import Path

import numpy as np

from sphsolid import metrics, scenefile
from sphsolid.units import length, quantity

#: the FE series' grid step [s]
GRID_STEP = 0.05e-6


def fe_problem(path: Path) -> dict:
    """The FE statement of a scene file: material, the block's extent, the
    piston's upward speed, the probes and the end time; a ValueError says
    why a file is not such a scene."""
    loaded = scenefile.SceneFile(path)
    scene = loaded.scene
    if scene.dimension != 2:
        raise ValueError(f"{path}: the FE answer is plane strain (2D); the "
                         f"file is {scene.dimension}D")
    shapes = {b.name: b.shape for b in scene.bodies}
    blocks = [b for b in scene.bodies if b.shape == "block"]
    plates = [b for b in scene.bodies if b.shape == "plate"]
    pistons = [b for b in scene.bodies if b.shape == "piston"]
    if len(blocks) != 1 or len(plates) != 1 or len(pistons) != 1 \
            or len(scene.bodies) != 3:
        raise ValueError(f"{path}: the FE answer covers one block between a "
                         f"plate and a piston; the file has {shapes}")
    block, piston = blocks[0], pistons[0]
    motion = piston.motion
    velocity = getattr(motion, "velocity", None)
    if type(motion).__name__ != "Velocity" or velocity is None:
        raise ValueError(f"{path}: the piston {piston.name!r} must move at a "
                         f"constant velocity, got {motion}")
    vx, vy = (quantity(v, "velocity", "piston velocity")
              for v in velocity[:2])
    if vx != 0.0:
        raise ValueError(f"{path}: the FE answer moves the piston "
                         f"vertically; its velocity has x = {vx:g} m/s")
    rock = block.material
    if piston.material is not rock or plates[0].material is not rock:
        raise ValueError(f"{path}: the FE answer has one material")
    (x0, y0), (x1, y1) = (tuple(length(v, "block corner") for v in block.lo),
                          tuple(length(v, "block corner") for v in block.hi))
    if loaded.until is None or not loaded.probe_points:
        raise ValueError(f"{path}: needs until and [probes]")
    return {"K": rock.K, "mu": rock.mu, "rho0": rock.rho0,
            "extent": ((x0, x1), (y0, y1)), "speed": -vy,
            "probes": dict(loaded.probe_points), "until": loaded.until}


def fe_series(problem: dict, size: float, out: Path, log=print) -> dict:
    """The FE series at element ``size`` [m] (kept in ``out``, reused)."""
    from validation import fe_reference
    path = out / f"fe_{size * 1e3:g}mm.npz"
    if not path.exists():
        until = problem["until"]
        grid = np.arange(0.0, until + 0.5 * GRID_STEP, GRID_STEP)
        # the time step the project's FE references take (fe_reference)
        dt = 0.25e-6 * size / 2e-3
        start = wallclock.perf_counter()
        result = fe_reference.piston_fe(
            size, until, dt, grid, problem["probes"], problem["K"],
            problem["mu"], problem["rho0"], speed=problem["speed"],
            extent=problem["extent"])
        fe_reference.save_series(path, grid, result)
        log(f"FE at {size * 1e3:g} mm: {result['dofs']} dofs, "
            f"{wallclock.perf_counter() - start:.1f} s")
    data = np.load(path)
    return {"grid": data["grid"],
            **{n: data[n] for n in problem["probes"]}}


def written_series(csv_path: Path, names, grid) -> dict:
    """The von Mises columns of a run's probe CSV on ``grid`` (linear
    interpolation, as a user would read them)."""
    with open(csv_path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    t = np.array([float(r["time_s"]) for r in rows])
    return {n: np.interp(grid, t, [float(r[f"{n}_von_mises_Pa"])
                                   for r in rows]) for n in names}


def score(series: dict, reference: dict, names) -> dict:
    g = reference["grid"]
    return {norm: metrics.worst_deviation(
        {n: series[n] for n in names}, {n: reference[n] for n in names},
        g, norm) for norm in ("max", "rms")}


def _cli(args, log_path: Path) -> tuple[int, float]:
    start = wallclock.perf_counter()
    with open(log_path, "w") as log:
        code = subprocess.call([sys.executable, "-m", "sphsolid", *args],
                               stdout=log, stderr=subprocess.STDOUT)
    return code, wallclock.perf_counter() - start


def check(path: Path, requests, probes, threads: int, fe_size: float,
          out: Path, log=print, presets=(), spacings=()) -> list[dict]:
    problem = fe_problem(path)
    names = list(probes or problem["probes"])
    out.mkdir(parents=True, exist_ok=True)
    fine = fe_series(problem, fe_size, out, log)
    coarse = fe_series(problem, 2 * fe_size, out, log)
    own = score({n: np.interp(fine["grid"], coarse["grid"], coarse[n])
                 for n in names}, fine, names)
    log(f"FE {2 * fe_size * 1e3:g} mm against {fe_size * 1e3:g} mm: "
        f"{own['max'] * 100:.2f} % max, {own['rms'] * 100:.2f} % RMS")
    rows = []
    for norm, error in requests:
        tag = f"{norm}{error:g}"
        plan = out / f"plan_{tag}.json"
        probe_args = [a for n in names for a in ("--probe", n)]
        code, planning = _cli(
            ["plan", str(path), "--error", f"{error:g}%", "--norm", norm,
             *probe_args, "--threads", str(threads), "--out", str(plan)],
            out / f"plan_{tag}.log")
        # a refusal exits non-zero and still writes the plan file
        if not plan.exists() or plan.stat().st_mtime < wallclock.time() \
                - planning - 1:
            raise RuntimeError(f"sphsolid plan failed (exit {code}): "
                               f"{out}/plan_{tag}.log")
        planned = json.loads(plan.read_text())
        row = {"norm": norm, "request": error / 100, "planning_s": planning,
               "feasible": planned["feasible"]}
        if planned["feasible"]:
            run = out / f"run_{tag}"
            code, seconds = _cli(
                ["run", str(path), "--plan", str(plan), "--threads",
                 str(threads), "--out", str(run)], out / f"run_{tag}.log")
            if code != 0:
                raise RuntimeError(f"sphsolid run failed: {out}/run_{tag}.log")
            csv_path = next(run.glob("*_probes.csv"))
            achieved = score(written_series(csv_path, names, fine["grid"]),
                             fine, names)
            chosen = planned["settings"]
            row.update(setting=f"{chosen['kernel']} h/dx="
                       f"{chosen['smoothing_ratio']:g} {chosen['integrator']}"
                       + "".join(f" + {e}" for e in chosen["effects"]),
                       dx=chosen["dx"],
                       error_upper=planned["error_upper"],
                       run_s=seconds, achieved=achieved[norm],
                       achieved_other=achieved)
        else:
            row["reason"] = planned.get("reason", "")
        rows.append(row)
        log(_line(row))
    if presets and spacings:
        log("| preset | dx | max | RMS | run |")
        log("|---|---|---|---|---|")
    swept = [sweep_row(path, preset, dx, names, fine, threads, out, log)
             for preset in presets for dx in spacings]
    (out / "results.json").write_text(json.dumps(
        {"scene": str(path), "fe_size": fe_size, "fe_own": own,
         "threads": threads, "rows": rows, "sweep": swept}, indent=1))
    return rows


#: a body's spacing line of a scene file: dx = "2mm" or dx = 0.002
DX_LINE = r'(?m)^(\s*dx\s*=\s*)("[^"\n]*"|[-+0-9.eE]+)(\s*(?:#.*)?)$'


def respaced(text: str, dx: float, where: str = "scene file") -> str:
    """The scene file ``text`` with its first body's spacing set to ``dx``
    [m] and every other body's scaled by the same factor."""
    found = [length(m.group(2).strip('"'), f"{where}: dx")
             for m in re.finditer(DX_LINE, text)]
    if not found:
        raise ValueError(f"{where}: no dx = \"...\" line to set the spacing")
    factor = dx / found[0]
    scaled = iter(found)
    return re.sub(DX_LINE, lambda m: (
        f'{m.group(1)}"{next(scaled) * factor * 1e3:.12g}mm"{m.group(3)}'),
        text)


def sweep_row(path: Path, preset: str, dx: float, names, fine: dict,
              threads: int, out: Path, log=print) -> dict:
    """The file run as a user would without a plan, ``sphsolid run FILE
    --preset PRESET``, with its first body's spacing set to ``dx`` and
    every other body's scaled by the same factor (as the planner scales a
    file's spacings), scored as the planned runs are: what a refused
    request could have had."""
    spaced = respaced(path.read_text(), dx, str(path))
    tag = f"{preset}_{dx * 1e3:g}mm"
    copy = out / f"sweep_{tag}.toml"
    copy.write_text(spaced)
    code, seconds = _cli(["run", str(copy), "--preset", preset, "--threads",
                          str(threads), "--out", str(out / f"sweep_{tag}"),
                          "--no-progress"], out / f"sweep_{tag}.log")
    row = {"preset": preset, "dx": dx, "run_s": seconds}
    if code != 0:
        row["failed"] = f"{out}/sweep_{tag}.log"
    else:
        csv_path = next((out / f"sweep_{tag}").glob("*_probes.csv"))
        row.update(score(written_series(csv_path, names, fine["grid"]),
                         fine, names))
    log(f"| {preset} | {dx * 1e3:g} mm | " + (
        "failed | - |" if "failed" in row else
        f"{row['max'] * 100:.2f} % | {row['rms'] * 100:.2f} % |")
        + f" {seconds:.1f} s |")
    return row


def _line(row) -> str:
    head = (f"| {row['norm']} {row['request'] * 100:g} % | "
            f"{row['planning_s']:.1f} s | ")
    if not row["feasible"]:
        return head + "refused | - | - | - |"
    met = "met" if row["achieved"] <= row["request"] else "**not met**"
    return (head + f"{row['setting']}, {row['dx'] * 1e3:.3g} mm, at most "
            f"{row['error_upper'] * 100:.2f} % | {row['run_s']:.1f} s | "
            f"{row['achieved'] * 100:.2f} % | {met} |")


def _requests(text: str):
    out = []
    for item in filter(None, text.split(",")):
        norm, _, value = item.partition(":")
        if norm not in ("max", "rms") or not value:
            raise argparse.ArgumentTypeError(
                f"{item!r}: a request is NORM:PERCENT, NORM max or rms")
        number = float(value)
        if not (math.isfinite(number) and number > 0):
            raise argparse.ArgumentTypeError(f"{item!r}: the percentage "
                                             "must be positive")
        out.append((norm, number))
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("--probe", action="append", default=None)
    parser.add_argument("--requests", type=_requests,
                        default=_requests("max:10,max:5,max:3,rms:10,"
                                          "rms:5,rms:3,rms:2,rms:1"))
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--fe-size", type=lambda v: length(v, "--fe-size"),
                        default=0.25e-3)
    parser.add_argument("--out", type=Path,
                        default=Path("scene_file_check"))
    parser.add_argument("--sweep", type=lambda v: list(filter(None, v.split(","))),
                        default=[], metavar="PRESET,...",
                        help="also run the file with these presets at "
                        "--spacings, unplanned, scored alike")
    parser.add_argument("--spacings", default=[2e-3, 1e-3, 0.5e-3],
                        type=lambda v: [length(x, "--spacings")
                                        for x in v.split(",")],
                        help="the block spacings of --sweep (default "
                        "2mm,1mm,0.5mm)")
    args = parser.parse_args(argv)
    print("| request | planning | plan | run | achieved vs FE | |")
    print("|---|---|---|---|---|---|")
    check(args.scene, args.requests, args.probe, args.threads,
          args.fe_size, args.out, presets=args.sweep, spacings=args.spacings)
    return 0


if __name__ == "__main__":
    sys.exit(main())
