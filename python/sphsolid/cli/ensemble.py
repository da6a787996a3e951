"""``sphsolid ensemble``: a fracture test over flaw draws, its strength
with error bars (docs/ensembles.md; the runs are sphsolid.ensemble's).

    sphsolid ensemble {ucs,brazilian,tensile} --seeds N [--dx D] [--jobs J]
                      [--seed BASE] [--quantity strength] --out DIR
                      [--cohesion 5MPa [--friction-angle 30]]
                      [--artificial-stress 0.3]

Runs members 0 .. N-1 (member i's flaws drawn from hash(BASE, i)) in J
processes with a progress bar; a rerun into DIR keeps the finished
members.  ``--cohesion``, ``--friction-angle`` and ``--artificial-stress``
switch on the drucker_prager and artificial_stress effects in every
member, as for ``sphsolid ucs`` (DIR/ensemble.json records them among its
scene_options, each member's summary.json its ``effects``).  Writes
DIR/member_XXXX/{load.csv,summary.json}, DIR/summary.json (quantity,
members, mean, std, ci95_low, ci95_high in SI units, the members' values)
and DIR/histogram.png.
"""
from __future__ import annotations

import sys
from pathlib import Path

from .fracture import (_optional_effects_text, _strain, add_effect_arguments,
                       scene_options)
from .options import (jobs, positive, positive_length, positive_time,
                      seed, whole)

help = "an ensemble of flaw draws of a fracture test: mean and 95% interval"


def add_arguments(parser) -> None:
    from ..fracture.ensemble import QUANTITIES
    from ..fracture import TESTS
    parser.add_argument("test", choices=sorted(TESTS),
                        help="the fracture test (as sphsolid ucs, brazilian, "
                             "tensile)")
    parser.add_argument("--seeds", type=whole(2), required=True,
                        help="members of the ensemble (flaw draws), >= 2")
    parser.add_argument("--dx", type=positive_length, default=None,
                        help="particle spacing (default: the test's, 2mm "
                             "or 1mm for brazilian)")
    parser.add_argument("--jobs", type=jobs, default=1,
                        help="processes running members at once (default 1; "
                             "each member runs on one thread)")
    parser.add_argument("--seed", type=seed, default=1,
                        help="base seed: member i draws from hash(seed, i) "
                             "(default 1; member 0 is the single run "
                             "'sphsolid TEST --seed SEED')")
    parser.add_argument("--quantity", choices=sorted(QUANTITIES),
                        default="strength",
                        help="the quantity summarised (default strength: "
                             "UCS, 2P/(pi D t) or the bar's strength)")
    parser.add_argument("--max-strain", type=_strain, default=None,
                        help="stop a member at this nominal strain if its "
                             "load has not dropped (default: the test's)")
    parser.add_argument("--strain-rate", type=positive, default=None,
                        help="strain rate [1/s] of ucs and tensile "
                             "(default: the test's, 1/s)")
    parser.add_argument("--out", type=Path, required=True,
                        help="output directory (a rerun resumes it)")
    parser.add_argument("--max-time", type=positive_time, default=24 * 3600.0,
                        metavar="TIME",
                        help="refuse an ensemble estimated to take longer "
                        "than this wall time (default 24h; e.g. 30min)")
    add_effect_arguments(parser)


def run(args) -> int:
    import sphsolid

    options = scene_options(args)
    if args.strain_rate is not None:
        if args.test == "brazilian":
            raise SystemExit("sphsolid ensemble: --strain-rate applies to "
                             "ucs and tensile, not brazilian")
        options["strain_rate"] = args.strain_rate
    _check_cost(args, options)
    result = sphsolid.ensemble(args.test, args.seeds, args.out, dx=args.dx,
                               jobs=args.jobs, seed=args.seed,
                               quantity=args.quantity,
                               max_strain=args.max_strain,
                               progress=True, scene_options=options,
                               log=lambda m: print(f"sphsolid ensemble: {m}",
                                                   file=sys.stderr))
    s = result.summary
    scale, unit = (1e-6, "MPa") if s["unit"] == "Pa" else (1.0, s["unit"])
    kept = s["members"] - len(result.ran)
    print(f"{args.test}: {s['members']} members ({kept} kept from an earlier "
          f"run), dx = {s['dx_m'] * 1e3:g} mm, seed {args.seed}; optional "
          "effects: " + _optional_effects_text(_effects(options)))
    print(f"{s['quantity']}: mean {s['mean'] * scale:.5g} {unit}, std "
          f"{s['std'] * scale:.4g} {unit}, 95% interval of the mean "
          f"[{s['ci95_low'] * scale:.5g}, {s['ci95_high'] * scale:.5g}] "
          f"{unit}")
    for name in ("summary.json", "histogram.png"):
        print(f"wrote {args.out / name}")
    return 0


def _duration(seconds: float) -> str:
    for unit, size in (("d", 86400), ("h", 3600), ("min", 60)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


def _check_cost(args, options) -> None:
    """Print the estimate of :func:`sphsolid.ensemble.cost` before the
    members start (stderr); refuse an ensemble the disk cannot hold or
    that would take longer than --max-time, with the figures."""
    from ..fracture.ensemble import cost
    c = cost(args.test, args.seeds, args.out, dx=args.dx, jobs=args.jobs,
             seed=args.seed, max_strain=args.max_strain,
             scene_options=options)
    what = (f"{c['to_run']} member(s) to run of {c['particles']} particles "
            f"and at most {c['steps']} steps at {c['step_s'] * 1e3:.3g} ms "
            f"a step: at most {_duration(c['seconds'])} on {args.jobs} "
            f"process(es), {c['bytes'] / 1e6:.3g} MB")
    print(f"sphsolid ensemble: estimate: {what}", file=sys.stderr)
    if c["free_bytes"] is not None and c["bytes"] > c["free_bytes"]:
        raise ValueError(f"--seeds {args.seeds}: {what}, but {args.out} has "
                         f"{c['free_bytes'] / 1e6:.3g} MB free; use fewer "
                         "--seeds or another --out")
    if c["seconds"] > args.max_time:
        raise ValueError(f"--seeds {args.seeds}: {what}, longer than "
                         f"--max-time {_duration(args.max_time)}; use fewer "
                         "--seeds, more --jobs, a coarser --dx or a larger "
                         "--max-time")


def _effects(options: dict) -> dict:
    """The optional effects the scene options switch on, named as in the
    scene's ``effects``."""
    from ..fracture import OPTIONAL_EFFECTS
    return {OPTIONAL_EFFECTS[key]: value for key, value in options.items()
            if key in OPTIONAL_EFFECTS}
