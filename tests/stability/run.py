"""Run the stability suite and print its summary table.

    .venv/bin/python tests/stability/run.py            # fast subset (~1 min)
    .venv/bin/python tests/stability/run.py --full     # finer and longer
    .venv/bin/python tests/stability/run.py rings tension   # chosen cases

Exit status 1 if any row fails. ``--markdown`` prints the table as
Markdown (as in docs/stability.md).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from stability_cases import CASES  # noqa: E402


def table(rows, markdown=False) -> str:
    header = ("case", "effects", "steps", "criterion", "measured", "result")
    body = [(r.case, r.effects, str(r.steps), r.criterion, r.measured,
             ("pass" if r.passed else "FAIL") + f" ({r.wall:.1f} s)")
            for r in rows]
    if markdown:
        lines = ["| " + " | ".join(header) + " |",
                 "|" + "---|" * len(header)]
        lines += ["| " + " | ".join(c.replace("|", "\\|") for c in cells)
                  + " |" for cells in body]
        return "\n".join(lines)
    return "\n\n".join("\n".join(f"{h:>9}: {c}" for h, c in zip(header, cells))
                       for cells in body)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", choices=[[]] + list(CASES),
                        help="cases to run (default: all)")
    parser.add_argument("--full", action="store_true",
                        help="finer resolutions and longer runs")
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--h-over-dx", type=float, default=None,
                        help="smoothing ratio of every case (default 1.2)")
    parser.add_argument("--kernel", default=None,
                        help="kernel of every case (default cubic_spline)")
    parser.add_argument("--integrator", default=None,
                        help="library integrator of every case that does "
                             "not name its own (default improved_euler)")
    parser.add_argument("--inset", type=float, default=None,
                        help="platen inset of every plate and piston in "
                             "lattice steps (default 0)")
    parser.add_argument("--alpha", type=float, default=None,
                        help="artificial viscosity alpha of the cases that "
                             "use it (default 1)")
    parser.add_argument("--effect", action="append", default=[],
                        metavar="NAME",
                        help="an effect switched on in every case on top of "
                             "its own, with the library's default parameters "
                             "(repeatable; e.g. kernel_correction)")
    args = parser.parse_args(argv)
    if args.effect:
        import stability_cases
        stability_cases.EXTRA_EFFECTS[:] = args.effect
    if args.alpha is not None:
        import stability_cases
        stability_cases.VISCOSITY["alpha"] = args.alpha
    if args.inset is not None:
        import stability_cases
        stability_cases.INSET = args.inset
    if args.integrator is not None:
        import stability_cases
        stability_cases.INTEGRATOR = args.integrator
    if args.kernel is not None:
        import stability_cases
        stability_cases.KERNEL = args.kernel
    if args.h_over_dx is not None:
        import stability_cases
        stability_cases.H_OVER_DX = args.h_over_dx
    rows = []
    start = time.time()
    for name in args.cases or CASES:
        case_start = time.time()
        new = CASES[name](full=args.full)
        rows += new
        print(f"[{name}: {len(new)} rows, {time.time() - case_start:.1f} s]",
              file=sys.stderr, flush=True)
    print(table(rows, args.markdown))
    failed = [r.case for r in rows if not r.passed]
    print(f"\n{len(rows) - len(failed)}/{len(rows)} passed in "
          f"{time.time() - start:.0f} s" + (f"; FAILED: {', '.join(failed)}"
                                             if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
