"""``sphsolid xdmf FILE.h5``: rewrite the ParaView companion FILE.xmf,
after reading every dataset of FILE.h5 back (as ``sphsolid info``): the
companion of a damaged file is not written."""
from __future__ import annotations

import argparse
from pathlib import Path

help = ("write the XDMF companion of an HDF5 output file (FILE.h5 -> "
        "FILE.xmf) for ParaView")


def add_arguments(parser) -> None:
    parser.add_argument("file", type=Path)
    parser.add_argument("--verify", action=argparse.BooleanOptionalAction,
                        default=True,
                        help="read every dataset back first; a damaged one "
                        "fails naming it and no companion is written "
                        "(default: on)")


def run(args) -> int:
    from ..io.trajectory import verify, write_xdmf
    if args.verify and args.file.is_file() and _is_hdf5(args.file):
        verify(args.file)
    print(f"wrote {write_xdmf(args.file)}")
    return 0


def _is_hdf5(path: Path) -> bool:
    import h5py
    try:
        return bool(h5py.is_hdf5(path))
    except OSError:
        return False
