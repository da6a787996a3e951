"""Checkpoints of command-line and scene-file runs: when to write them and
how to continue from one (``sphsolid run/piston --checkpoint-every``,
``--resume``).  The library writes and reads them
(``Scene.write_checkpoint``, ``Scene.read_checkpoint``)."""
from __future__ import annotations

import math
from pathlib import Path

from ..units import time as _time

__all__ = ["marks", "resume"]


def marks(every, start: float, until: float) -> list[float]:
    """The times k * every (k = 1, 2, ...) after ``start`` and up to
    ``until`` [s] at which a run writes its checkpoint (``every`` a
    number or a string such as "0.1ms"; None: none)."""
    if every is None:
        return []
    every = _time(every, "checkpoint_every")
    if not (math.isfinite(every) and every > 0):
        raise ValueError(f"checkpoint_every must be finite and > 0 s, got "
                         f"{every!r}")
    first = math.floor(start / every) + 1
    last = math.floor(until / every * (1 + 1e-12))
    if last < 1:
        raise ValueError(f"checkpoint_every={every:g} s is longer than the run "
                         f"(to {until:g} s): no checkpoint would be written; "
                         "give an interval up to the end time")
    if last - first > 100_000:
        raise ValueError(f"checkpoint_every={every!r} s writes "
                         f"{last - first + 1} checkpoints up to {until!r} s;"
                         " give a longer interval")
    return [k * every for k in range(first, last + 1)]


def resume(scene, path, integrator: str) -> float:
    """Read the checkpoint ``path`` into ``scene`` (built as the run that
    wrote it, on the C library) and return its time step; the checkpoint
    must have been written by ``integrator``'s run (its carried state is
    that integrator's)."""
    path = Path(path)
    scene.read_checkpoint(path)
    written_by = scene.integrator
    if written_by != integrator:
        raise ValueError(f"checkpoint {str(path)!r} was written by the "
                         f"{written_by!r} integrator; this run uses "
                         f"{integrator!r} (give --integrator {written_by} to "
                         "continue it)")
    return scene.calc.dt
