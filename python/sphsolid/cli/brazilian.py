"""``sphsolid brazilian``: the Brazilian disc to failure
(docs/fracture.md; the shared code is in fracture.py)."""
from __future__ import annotations

from . import fracture

help = ("Brazilian disc (D = 50 mm, 2D) between flat platens to splitting")


def add_arguments(parser) -> None:
    fracture.add_arguments(parser, "brazilian")


def run(args) -> int:
    return fracture.run(args, "brazilian")
