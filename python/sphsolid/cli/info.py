"""``sphsolid info FILE.h5``: describe an HDF5 output file, after reading
every dataset back (``--verify``, the default: a dataset whose checksum
fails, or that cannot be read, makes it fail naming the dataset)."""
from __future__ import annotations

import argparse
from pathlib import Path

help = "describe an HDF5 output file (reading every dataset back)"


def add_arguments(parser) -> None:
    parser.add_argument("file", type=Path)
    parser.add_argument("--verify", action=argparse.BooleanOptionalAction,
                        default=True,
                        help="read every dataset and attribute back, so "
                        "that HDF5 checks each chunk's checksum; a damaged "
                        "one fails naming it (default: on)")


def run(args) -> int:
    from ..io.trajectory import Trajectory, verify
    from .xdmf import _is_hdf5
    checked = None
    if args.verify and args.file.is_file() and _is_hdf5(args.file):
        checked = verify(args.file)      # before anything reads the file
    with Trajectory(args.file) as traj:
        print(traj.describe())
    if checked is not None:
        print(verified_line(checked))
    return 0


def verified_line(checked: dict) -> str:
    """'  verified: 28 datasets (2.36 MB) read back, each checksum holds'
    (and those that carry none)."""
    line = (f"  verified: {checked['datasets']} datasets "
            f"({checked['bytes'] / 1e6:.3g} MB) read back")
    if checked["unchecked"]:
        names = ", ".join(checked["unchecked"][:3])
        more = len(checked["unchecked"]) - 3
        line += (f"; {checked['checksummed']} carry a checksum and hold it, "
                 f"{len(checked['unchecked'])} carry none ({names}"
                 + (f" and {more} more" if more > 0 else "") + ")")
    else:
        line += ", each checksum holds"
    return line
