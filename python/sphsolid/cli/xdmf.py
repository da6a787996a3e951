"""``sphsolid xdmf FILE.h5``: rewrite the ParaView companion FILE.xmf."""
from __future__ import annotations

from pathlib import Path

help = ("write the XDMF companion of an HDF5 output file (FILE.h5 -> "
        "FILE.xmf) for ParaView")


def add_arguments(parser) -> None:
    parser.add_argument("file", type=Path)


def run(args) -> int:
    from ..trajectory import write_xdmf
    print(f"wrote {write_xdmf(args.file)}")
    return 0
