"""``sphsolid plan``: the cheapest settings for a requested error, on a
project scene or a LAMMPS deck (calibration runs, error and cost models);
writes plan.json.

    sphsolid plan ucs|brazilian --quantity strength --error 2% \
                  [--confidence 0.95] [--pilot 10] [--jobs J] --out plan.json
                  [--cohesion 5MPa [--friction-angle 30]]
                  [--artificial-stress 0.3]

plans a confident strength instead: dx and the number of flaw draws
together (sphsolid.planner.strength, docs/ensembles.md), with the optional
effects of ``sphsolid ensemble`` in every pilot member."""
from __future__ import annotations

from pathlib import Path

from .fracture import add_effect_arguments, scene_options
from .options import (finite, fraction, jobs, length_list, positive_time,
                      threads, whole)

help = ("cheapest settings for a requested error (calibration runs, error "
        "and cost models); writes plan.json")


def add_arguments(parser) -> None:
    parser.add_argument("scene", nargs="?",
                        help="a project scene (piston, gravity, strip, "
                        "piston_nu045, piston_squat, piston_slender), a "
                        "scene file "
                        "(SCENE.toml, with --probe), or --deck; with "
                        "--quantity strength: ucs or brazilian")
    parser.add_argument("--error", type=fraction, required=True,
                        help="requested error, e.g. 3%% or 0.03")
    parser.add_argument("--until", type=positive_time, default=None,
                        help="end time (default: the scene's)")
    parser.add_argument("--norm", choices=("max", "rms"), default="max",
                        help="max: largest deviation over the reference's "
                        "peak; rms: RMS deviation over its RMS (default max)")
    parser.add_argument("--threads", type=threads, default=None,
                        help="threads of the planned run (and the "
                        "calibration)")
    parser.add_argument("--max-seconds", type=finite(0.0, "must be finite "
                        "and >= 0 s", "time"), default=None,
                        help="wall-time budget of the planned run [s]")
    parser.add_argument("--ladder", type=length_list, default=None,
                        help="calibration spacings, e.g. 4mm,3mm,2mm")
    parser.add_argument("--out", type=Path, default=Path("plan.json"))
    strength = parser.add_argument_group(
        "a confident strength (ucs, brazilian; docs/ensembles.md)")
    strength.add_argument("--quantity", choices=("strength",), default=None,
                          help="plan the mean strength of an ensemble of "
                          "flaw draws: dx and the number of seeds")
    strength.add_argument("--confidence", type=_confidence, default=0.95,
                          help="confidence of the interval of the mean "
                          "(default 0.95)")
    strength.add_argument("--pilot", type=whole(3), default=10,
                          help="members of each ladder level's pilot "
                          "ensemble (default 10)")
    strength.add_argument("--jobs", type=jobs, default=1,
                          help="processes running the pilot members "
                          "(default 1)")
    add_effect_arguments(strength)
    parser.add_argument("--no-cache", action="store_true",
                        help="calibrate anew and keep no runs on disk (by "
                        "default calibration runs are kept in "
                        "$SPHSOLID_CACHE, else ~/.cache/sphsolid/plan, and "
                        "reused by later plans of the same scene)")
    parser.add_argument("--no-record", action="store_true",
                        help="plan without the verification record: every "
                        "default candidate, chosen by self-convergence "
                        "alone, with no verified margin (for scenes whose "
                        "effects the record does not verify)")
    deck = parser.add_argument_group("LAMMPS decks")
    deck.add_argument("--deck", type=Path, default=None,
                      help="plan a LAMMPS input deck through the plugin")
    deck.add_argument("--var", default="dx",
                      help="the deck's spacing variable (default dx)")
    deck.add_argument("--time-var", default="t_end",
                      help="the deck's end-time variable (default t_end)")
    deck.add_argument("--probe", action="append", default=[],
                      help="where the error is measured: a probe of the "
                      "scene file's [probes] or a sphsolid/probe compute of "
                      "the deck (repeat; default for a scene file: all its "
                      "probes)")
    deck.add_argument("--set", action="append", default=[],
                      metavar="NAME=V1,V2",
                      help="another deck variable to choose from (repeat)")


def _confidence(text: str) -> float:
    value = fraction(text)
    if not 0 < value < 1:
        import argparse
        raise argparse.ArgumentTypeError(f"{text!r}: must be in (0, 1)")
    return value


def writable(path: Path, option: str = "--out") -> None:
    """Refuse an output path that cannot be written, before any work."""
    import tempfile
    folder = path.parent
    if path.is_dir():
        raise ValueError(f"{option} {path}: is a directory; give a file name")
    if not folder.is_dir():
        raise ValueError(f"{option} {path}: the folder {folder} does not "
                         "exist")
    try:
        with tempfile.NamedTemporaryFile(dir=folder):
            pass
    except OSError as error:
        raise ValueError(f"{option} {path}: cannot write in {folder} "
                         f"({error.strerror})") from None


def run(args) -> int:
    from .. import planner
    from ..planner.cache import RunCache
    log = lambda message: print(message, flush=True)  # noqa: E731
    writable(args.out)
    if args.quantity == "strength" or args.scene in ("ucs", "brazilian"):
        return _plan_strength(args, log)
    given = [option for option, value in (
        ("--cohesion", args.cohesion),
        ("--friction-angle", args.friction_angle),
        ("--artificial-stress", args.artificial_stress)) if value is not None]
    if given:
        raise ValueError(f"sphsolid plan: {', '.join(given)} applies only "
                         "to the strength plans (ucs, brazilian --quantity "
                         "strength)")
    if args.deck is not None:
        from ..planner.deck import plan_deck
        result = plan_deck(args.deck, error=args.error, until=args.until,
                           probes=args.probe, variable=args.var,
                           time_variable=args.time_var, norm=args.norm,
                           threads=args.threads, max_seconds=args.max_seconds,
                           ladder=args.ladder, choices=args.set, log=log)
    else:
        if args.scene is None:
            raise ValueError("sphsolid plan: name a scene (piston, gravity, "
                             "strip, piston_nu045, piston_squat), a scene "
                             "file or give --deck")
        projects = planner.project_scenes()
        if args.scene in projects:
            spec, key = projects[args.scene], args.scene
        elif args.scene.endswith(".toml") or Path(args.scene).exists():
            import hashlib
            spec = planner.scenes.scene_file(args.scene, args.probe or None)
            # runs are kept per file contents: an edited file is a new scene
            digest = hashlib.sha256(Path(args.scene).read_bytes()).hexdigest()
            key = f"file:{digest[:16]}"
        else:
            raise ValueError(f"sphsolid plan: {args.scene!r} is neither a "
                             f"project scene ({', '.join(projects)}) nor a "
                             "scene file")
        until = args.until or spec.until
        cache = RunCache(key, root=None if args.no_cache else "default")
        result = planner.plan(
            spec.factory, error=args.error, until=until, probes=spec.probes,
            quantity=spec.quantity, norm=args.norm, threads=args.threads,
            max_seconds=args.max_seconds,
            ladder=args.ladder or spec.ladder,
            window=spec.window(until) if spec.window else None,
            scene=(args.scene if args.scene in projects
                   else Path(args.scene).name),
            log=log, cache=cache,
            record=None if args.no_record else True)
    print()
    print(result.summary())
    result.save(args.out)
    print(f"wrote {args.out}")
    return 0 if result.feasible else 3


def _plan_strength(args, log) -> int:
    import tempfile

    from ..fracture.strength import LADDERS, plan_strength
    options = scene_options(args)
    if args.scene not in LADDERS or args.quantity != "strength":
        raise ValueError(f"sphsolid plan {args.scene}: the strength is "
                         f"planned with --quantity strength for "
                         f"{' or '.join(LADDERS)}, got scene "
                         f"{args.scene!r} and --quantity {args.quantity}")
    with tempfile.TemporaryDirectory() as scratch:
        result = plan_strength(args.scene, args.error,
                               confidence=args.confidence,
                               ladder=args.ladder, pilot=args.pilot,
                               jobs=args.jobs, max_seconds=args.max_seconds,
                               work=scratch if args.no_cache else None,
                               log=log, scene_options=options)
    print()
    print(result.summary())
    result.save(args.out)
    print(f"wrote {args.out}")
    return 0 if result.feasible else 3
