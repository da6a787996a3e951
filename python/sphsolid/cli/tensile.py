"""``sphsolid tensile``: the tensile bar to failure
(docs/fracture.md; the shared code is in fracture.py)."""
from __future__ import annotations

from . import fracture

help = ("tensile bar (20 x 80 mm, 2D) pulled apart by its bonded platens to failure")


def add_arguments(parser) -> None:
    fracture.add_arguments(parser, "tensile")


def run(args) -> int:
    return fracture.run(args, "tensile")
