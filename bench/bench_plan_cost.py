"""The planner's cost model against measured runs (a benchmark, not a test).

    .venv/bin/python bench/bench_plan_cost.py [--scene piston|strip|gravity]
        [--error 0.2] [--norm rms] [--threads 1] [--repeats 3]

Plans a request, then runs the planned setting ``--repeats`` times (and the
other priced candidates once each) and prints, side by side, the predicted
and measured **process CPU seconds** (the cost model's own clock: it is
calibrated on the CPU time of the calibration runs, which a loaded machine
disturbs far less than wall time) and wall seconds, with medians, plus each
setting's calibrated throughput (particle-steps per CPU second), so the
figures can be re-measured on a quiet machine. The load average is printed
before and after: on a shared machine wall-time predictions hold only at
the load the calibration saw.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))

from sphsolid import planner  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default="strip",
                        choices=("piston", "strip", "gravity"))
    parser.add_argument("--error", type=float, default=0.2)
    parser.add_argument("--norm", default="rms", choices=("max", "rms"))
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    spec = planner.project_scenes()[args.scene]
    window = spec.window(spec.until) if spec.window else None
    result = planner.plan(spec.factory, error=args.error, until=spec.until,
                          probes=spec.probes, quantity=spec.quantity,
                          norm=args.norm, threads=args.threads,
                          ladder=spec.ladder, window=window,
                          scene=args.scene)
    print(result.summary())
    print()
    print(f"load average before the runs: {os.getloadavg()[0]:.1f} "
          f"({os.cpu_count()} cores)")
    print(f"{'setting':<56} {'dx [mm]':>7} {'particles':>9} {'steps':>6} "
          f"{'Mps/s':>6} {'CPU pred':>8} {'CPU meas':>8} {'err':>5} "
          f"{'wall pred':>9} {'wall meas':>9} {'err':>5}")
    for cand in result.candidates:
        if cand.seconds is None:
            continue
        chosen = cand.setting == result.setting
        cpus, walls = [], []
        for _ in range(args.repeats if chosen else 1):
            run = planner.ladder_run(spec.factory, cand.dx, cand.setting,
                                     spec.until, spec.probes, spec.quantity,
                                     args.threads)
            cpus.append(run.cpu)
            walls.append(run.wall)
        cpu, wall = statistics.median(cpus), statistics.median(walls)
        print(f"{cand.setting.label():<56} {cand.dx * 1e3:7.3g} "
              f"{cand.particles:9d} {cand.steps:6d} "
              f"{cand.cost.particle_steps_per_second / 1e6:6.2f} "
              f"{cand.cpu_seconds:8.3g} {cpu:8.3g} "
              f"{(cpu / cand.cpu_seconds - 1) * 100:+4.0f}% "
              f"{cand.seconds:9.3g} {wall:9.3g} "
              f"{(wall / cand.seconds - 1) * 100:+4.0f}%"
              + ("  <- planned" if chosen else ""))
    print(f"load average after the runs: {os.getloadavg()[0]:.1f}")
    print("(CPU: process CPU seconds of the stepping, median of "
          f"{args.repeats} runs for the planned setting; Mps/s: calibrated "
          "million particle-steps per CPU second)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
