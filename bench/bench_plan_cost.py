"""The planner's cost model against measured runs (a benchmark, not a test).

    .venv/bin/python bench/bench_plan_cost.py [--scene piston|strip|gravity]
        [--error 0.1] [--norm rms] [--threads 1] [--repeats 3]

Plans a request, then runs the planned setting ``--repeats`` times (and the
other priced candidates once each) and prints predicted and measured wall
times side by side, with medians, so the figures can be re-measured on a
quiet machine. Timings on a shared machine are noisy: say so when quoting.
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))

from sphsolid import plan as planner  # noqa: E402


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
    print(f"{'setting':<60} {'dx [mm]':>8} {'particles':>9} {'steps':>6} "
          f"{'predicted [s]':>13} {'measured [s] (median)':>22} "
          f"{'error':>7}")
    for cand in result.candidates:
        if cand.seconds is None:
            continue
        chosen = cand.setting == result.setting
        walls = []
        for _ in range(args.repeats if chosen else 1):
            run = planner.ladder_run(spec.factory, cand.dx, cand.setting,
                                     spec.until, spec.probes, spec.quantity,
                                     args.threads)
            walls.append(run.wall)
        median = statistics.median(walls)
        print(f"{cand.setting.label():<60} {cand.dx * 1e3:8.3g} "
              f"{cand.particles:9d} {cand.steps:6d} {cand.seconds:13.3g} "
              f"{median:22.3g} {(median / cand.seconds - 1) * 100:+6.0f}%"
              + ("  <- planned" if chosen else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
