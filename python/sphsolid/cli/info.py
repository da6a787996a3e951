"""``sphsolid info FILE.h5``: describe an HDF5 output file."""
from __future__ import annotations

from pathlib import Path

help = "describe an HDF5 output file"


def add_arguments(parser) -> None:
    parser.add_argument("file", type=Path)


def run(args) -> int:
    from ..trajectory import Trajectory
    with Trajectory(args.file) as traj:
        print(traj.describe())
    return 0
