"""``sphsolid run SCENE.toml``: build and run the scene a TOML file
describes (docs/python.md, "Scene files")."""
from __future__ import annotations

import argparse
from pathlib import Path

from .options import (add_allow_large_option, add_checkpoint_options,
                      add_integrator_options, positive_time, threads,
                      whole)

help = "build and run a scene file (TOML)"
description = ("Build and run the scene a TOML file describes "
               "(docs/python.md, 'Scene files').")


def add_arguments(parser) -> None:
    parser.add_argument("scene", type=Path)
    parser.add_argument("--out", type=Path, default=None,
                        help="output folder (default: the scene file's)")
    parser.add_argument("--until", type=positive_time, default=None,
                        help="end time, overriding the file's")
    parser.add_argument("--threads", type=threads, default=None,
                        help="OpenMP threads (default: the file's threads, "
                        "else OpenMP's)")
    add_integrator_options(parser, preset_default=(
        "the file's preset key, else none: the file and the library's "
        "defaults"))
    add_checkpoint_options(parser)
    add_allow_large_option(parser)
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction,
                        default=None)
    parser.add_argument("--probe-interval", type=whole(1), default=None,
                        help="steps between probe samples, overriding the "
                        "file's [output] probe_interval (default: every "
                        "step within 0.25 us, a quarter of the accuracy "
                        "metric's smoothing)")
    parser.add_argument("--plan", type=Path, default=None,
                        help="run with the settings of a plan.json from "
                        "'sphsolid plan SCENE.toml' (spacing, h/dx, kernel, "
                        "integrator, effects)")


def run(args) -> int:
    from ..io.scenefile import run_file
    run_file(args.scene, out=args.out, until=args.until,
             progress=args.progress, log=lambda m: print(m, flush=True),
             threads=args.threads, integrator=args.integrator,
             preset=args.preset, checkpoint_every=args.checkpoint_every,
             resume=args.resume, dt=args.dt, plan=args.plan,
             probe_interval=args.probe_interval)
    return 0
