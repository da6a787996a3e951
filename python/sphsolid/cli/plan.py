"""``sphsolid plan``: the cheapest settings for a requested error, on a
project scene or a LAMMPS deck (calibration runs, error and cost models);
writes plan.json."""
from __future__ import annotations

from pathlib import Path

from .options import finite, fraction, length_list, positive_time, whole

help = ("cheapest settings for a requested error (calibration runs, error "
        "and cost models); writes plan.json")


def add_arguments(parser) -> None:
    parser.add_argument("scene", nargs="?", choices=("piston", "gravity",
                                                     "strip"),
                        help="project scene (or --deck)")
    parser.add_argument("--error", type=fraction, required=True,
                        help="requested error, e.g. 3%% or 0.03")
    parser.add_argument("--until", type=positive_time, default=None,
                        help="end time (default: the scene's)")
    parser.add_argument("--norm", choices=("max", "rms"), default="max",
                        help="max: largest deviation over the reference's "
                        "peak; rms: RMS deviation over its RMS (default max)")
    parser.add_argument("--threads", type=whole(1), default=None,
                        help="threads of the planned run (and the "
                        "calibration)")
    parser.add_argument("--max-seconds", type=finite(0.0, "must be finite "
                        "and >= 0 s"), default=None,
                        help="wall-time budget of the planned run [s]")
    parser.add_argument("--ladder", type=length_list, default=None,
                        help="calibration spacings, e.g. 4mm,3mm,2mm")
    parser.add_argument("--out", type=Path, default=Path("plan.json"))
    deck = parser.add_argument_group("LAMMPS decks")
    deck.add_argument("--deck", type=Path, default=None,
                      help="plan a LAMMPS input deck through the plugin")
    deck.add_argument("--var", default="dx",
                      help="the deck's spacing variable (default dx)")
    deck.add_argument("--time-var", default="t_end",
                      help="the deck's end-time variable (default t_end)")
    deck.add_argument("--probe", action="append", default=[],
                      help="a sphsolid/probe compute of the deck (repeat)")
    deck.add_argument("--set", action="append", default=[],
                      metavar="NAME=V1,V2",
                      help="another deck variable to choose from (repeat)")


def run(args) -> int:
    from .. import plan as planner
    log = lambda message: print(message, flush=True)  # noqa: E731
    if args.deck is not None:
        from ..plan_deck import plan_deck
        result = plan_deck(args.deck, error=args.error, until=args.until,
                           probes=args.probe, variable=args.var,
                           time_variable=args.time_var, norm=args.norm,
                           threads=args.threads, max_seconds=args.max_seconds,
                           ladder=args.ladder, choices=args.set, log=log)
    else:
        if args.scene is None:
            raise ValueError("sphsolid plan: name a scene (piston, gravity, "
                             "strip) or give --deck")
        spec = planner.project_scenes()[args.scene]
        until = args.until or spec.until
        result = planner.plan(
            spec.factory, error=args.error, until=until, probes=spec.probes,
            quantity=spec.quantity, norm=args.norm, threads=args.threads,
            max_seconds=args.max_seconds,
            ladder=args.ladder or spec.ladder,
            window=spec.window(until) if spec.window else None,
            scene=args.scene, log=log)
    print()
    print(result.summary())
    result.save(args.out)
    print(f"wrote {args.out}")
    return 0 if result.feasible else 3
