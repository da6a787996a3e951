"""``sphsolid run SCENE.toml``: build and run the scene a TOML file
describes (docs/python.md, "Scene files")."""
from __future__ import annotations

import argparse
from pathlib import Path

from .options import positive_time

help = "build and run a scene file (TOML)"
description = ("Build and run the scene a TOML file describes "
               "(docs/python.md, 'Scene files').")


def add_arguments(parser) -> None:
    parser.add_argument("scene", type=Path)
    parser.add_argument("--out", type=Path, default=None,
                        help="output folder (default: the scene file's)")
    parser.add_argument("--until", type=positive_time, default=None,
                        help="end time, overriding the file's")
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction,
                        default=None)


def run(args) -> int:
    from ..scenefile import run_file
    run_file(args.scene, out=args.out, until=args.until,
             progress=args.progress, log=lambda m: print(m, flush=True))
    return 0
