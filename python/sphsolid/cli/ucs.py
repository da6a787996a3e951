"""``sphsolid ucs``: the uniaxial compression test to failure
(docs/fracture.md; the shared code is in fracture.py)."""
from __future__ import annotations

from . import fracture

help = ("uniaxial compression test to failure (2D plane strain, the paper's 86 x 140 mm specimen)")


def add_arguments(parser) -> None:
    fracture.add_arguments(parser, "ucs")


def run(args) -> int:
    return fracture.run(args, "ucs")
