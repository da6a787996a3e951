"""``sphsolid piston``: the paper's uniaxial piston test (2D plane strain,
or the laboratory cylinder in 3D)."""
from __future__ import annotations

from .options import add_scene_options, finite, positive_length

help = "the paper's uniaxial piston test"

_DX = {2: 1e-3, 3: 2e-3}
_UNTIL = 0.3e-3
_FRAMES = 4


def add_arguments(parser) -> None:
    parser.add_argument("--dx", type=positive_length, default=None,
                        help="particle spacing (default 1mm; 2mm with "
                             "--dim 3)")
    add_scene_options(parser, None, _UNTIL, _FRAMES)
    parser.add_argument("--speed", type=finite(0.0, "must be finite and "
                        ">= 0 m/s (the piston moves down)", "velocity"),
                        default=1.5e-3,
                        help="piston speed [m/s, or with a unit: 1.5mm/s] "
                        "(default 1.5e-3)")
    parser.add_argument("--dim", type=int, choices=(2, 3), default=2,
                        help="2: the paper's plane-strain specimen (default);"
                             " 3: the laboratory cylinder D = 54 mm, "
                             "L = 135 mm (--dx default 2mm)")


def run(args) -> int:
    from .. import planner
    from .. import scenes
    from .scene_run import (check_spacing, planned_scene, resolve,
                            run_scene, scene_setting)
    dx = args.dx if args.dx is not None else _DX[args.dim]
    check_spacing(dx)
    job = resolve(args, "piston", dx, _UNTIL, _FRAMES)
    if job.plan is not None:
        scene = planned_scene(args, job, lambda dx, **kw:
                              planner.piston_factory(dx, speed=args.speed,
                                                     **kw))
    elif args.dim == 3:
        scene = scenes.uniaxial_cylinder(dx, velocity=args.speed,
                                         **scene_setting(args))
    else:
        scene = scenes.uniaxial_piston(dx, velocity=args.speed,
                                       **scene_setting(args))
    return run_scene(args, scene, job)
