"""``sphsolid gravity``: the specimen settling under gravity on the
plate."""
from __future__ import annotations

import math

from .options import add_scene_options, finite

help = "the specimen settling under gravity on the plate"

_DX = 2e-3
_UNTIL = 20e-3
_FRAMES = 3


def add_arguments(parser) -> None:
    add_scene_options(parser, _DX, _UNTIL, _FRAMES)
    parser.add_argument("--damping", type=finite(0.0, "must be finite "
                        "and >= 0 1/s", "rate"), default=None,
                        help="damping rate [1/s] (default: the scene's)")
    parser.add_argument("--g", type=finite(-math.inf, "must be finite",
                                           "acceleration"),
                        default=9.81,
                        help="gravitational acceleration [m/s^2]")


def run(args) -> int:
    from .. import planner
    from .. import scenes
    from .scene_run import (check_spacing, planned_scene, resolve,
                            run_scene, scene_setting)
    check_spacing(args.dx)
    job = resolve(args, "gravity", args.dx, _UNTIL, _FRAMES)
    if job.plan is not None:
        scene = planned_scene(args, job, lambda dx, **kw:
                              planner.gravity_factory(dx, g=args.g, **kw))
    else:
        kwargs = {} if args.damping is None else {"damping": args.damping}
        scene = scenes.gravity(args.dx, g=args.g, **scene_setting(args),
                               **kwargs)
    return run_scene(args, scene, job)
