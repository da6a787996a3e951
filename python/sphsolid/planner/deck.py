"""The planner for LAMMPS input decks (``sphsolid plan --deck in.deck``).

A deck that declares its spacing and end time as variables (``variable dx
index 0.001``, ``variable t_end index 0.0003``) and its probes as
``compute ID all sphsolid/probe x y`` is planned like a Python scene: the
deck is run through the plugin with ``lmp -var dx ... -var t_end ...`` at
a ladder of spacings and for every combination of the other variables
given with ``--set NAME=V1,V2`` (e.g. ``alpha=0.5,1``); the probes'
von Mises column (``c_ID[1]``) is recorded by a ``fix ave/time`` the
planner adds before the deck's first ``run``; the run's own ``Loop time``
and atom count (from the LAMMPS log) feed the cost model. The error and
cost models and the choice are :mod:`sphsolid.planner`'s. Nothing else in
the deck is changed.
"""
from __future__ import annotations

import itertools
import math
import re
import subprocess
import sys
import tempfile
import time as wallclock
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import metrics
from . import error_model, search
from .calibration import LadderRun
from .search import Candidate, Plan

__all__ = ["plan_deck", "DeckSetting", "run_deck", "deck_variables"]


@dataclass(frozen=True)
class DeckSetting:
    """Values of the deck's own variables (besides the spacing)."""
    variables: tuple = ()
    integrator: str = "deck"
    effects: tuple = ()

    def label(self) -> str:
        return " ".join(f"{k}={v}" for k, v in self.variables) or "deck"

    def to_dict(self) -> dict:
        return {"variables": dict(self.variables)}

    @property
    def effect_dict(self) -> dict:
        return {}


def deck_variables(text: str) -> dict:
    """{name: default} of the deck's ``variable NAME index|equal ...``
    lines (the first value)."""
    out = {}
    for line in text.splitlines():
        match = re.match(r"\s*variable\s+(\S+)\s+(index|string|equal)\s+(\S+)",
                         line)
        if match and match.group(1) not in out:
            out[match.group(1)] = match.group(3)
    return out


def _probe_computes(text: str) -> list[str]:
    return re.findall(r"^\s*compute\s+(\S+)\s+\S+\s+sphsolid/probe\b", text,
                      re.M)


def _instrumented(text: str, probes, path: Path) -> str:
    """The deck with a fix ave/time of the probes' von Mises before its
    first ``run``."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if re.match(r"\s*run\s+", line):
            columns = " ".join(f"c_{p}[1]" for p in probes)
            extra = ["variable plan_time equal time",
                     f"fix plan_probes all ave/time 1 1 1 v_plan_time "
                     f"{columns} file {path} format \" %.17g\""]
            return "\n".join(lines[:i] + extra + lines[i:]) + "\n"
    raise ValueError("the deck has no 'run' command")


def _lmp() -> str:
    candidate = Path(sys.executable).parent / "lmp"
    return str(candidate) if candidate.exists() else "lmp"


def run_deck(deck: Path, dx: float, until: float, probes, variable: str,
             time_variable: str, values: dict, threads=None,
             workdir: Path | None = None) -> LadderRun:
    """One run of the deck; returns a LadderRun (times, {probe: von
    Mises}, atoms, steps, the deck's own Loop time)."""
    from ..lammps import find_plugin
    deck = Path(deck).resolve()
    text = deck.read_text()
    declared = deck_variables(text)
    work = Path(workdir or tempfile.mkdtemp(prefix="sphsolid-deck-"))
    series_path = work / f"probes_{dx:.6g}.txt"
    log_path = work / f"log_{dx:.6g}.lammps"
    script = work / f"in.plan_{dx:.6g}"
    script.write_text(_instrumented(text, probes, series_path))
    args = [_lmp(), "-in", str(script), "-log", str(log_path), "-screen",
            "none", "-var", variable, repr(float(dx)), "-var",
            time_variable, repr(float(until))]
    if "plugin" in declared or "${plugin}" in text:
        args += ["-var", "plugin", str(find_plugin())]
    for key, value in values:
        args += ["-var", key, str(value)]
    env = None
    if threads:
        import os
        env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    start = wallclock.perf_counter()
    done = subprocess.run(args, cwd=work, env=env,
                          capture_output=True, text=True)
    elapsed = wallclock.perf_counter() - start
    setting = DeckSetting(tuple(values))
    log = log_path.read_text() if log_path.exists() else done.stdout
    if done.returncode != 0:
        message = next((line for line in log.splitlines()[::-1]
                        if "ERROR" in line), f"lmp exit {done.returncode}")
        return LadderRun(setting, dx, 0, 0, math.nan, math.nan,
                                 until, failed=message.strip())
    loop = re.findall(r"Loop time of (\S+) on \d+ procs for (\d+) steps "
                      r"with (\d+) atoms", log)
    wall, steps, atoms = (float(loop[-1][0]), int(loop[-1][1]),
                          int(loop[-1][2])) if loop else (elapsed, 0, 0)
    data = np.loadtxt(series_path, comments="#", ndmin=2)
    times = data[:, 1]
    series = {p: data[:, 2 + k] for k, p in enumerate(probes)}
    return LadderRun(setting, dx, atoms, steps,
                             until / max(steps, 1), wall, until, times,
                             series)


def plan_deck(deck, error: float, until: float | None = None, probes=(),
              variable: str = "dx", time_variable: str = "t_end",
              norm: str = "max", threads=None, max_seconds=None,
              ladder=None, choices=(), max_refinement: float = 2.0,
              log=None) -> Plan:
    """Plan a LAMMPS deck: see the module docstring. ``choices`` are
    ``NAME=V1,V2`` strings; ``ladder`` defaults to 3, 2 and 1.5 times the
    deck's own spacing."""
    say = log or (lambda message: None)
    deck = Path(deck)
    if not deck.is_file():
        raise ValueError(f"--deck {deck}: no such file")
    text = deck.read_text()
    declared = deck_variables(text)
    for name in (variable, time_variable):
        if name not in declared:
            raise ValueError(f"{deck} declares no variable {name!r} "
                             f"(it declares {', '.join(declared)})")
    computes = _probe_computes(text)
    probes = list(probes) or computes
    unknown = [p for p in probes if p not in computes]
    if unknown or not probes:
        raise ValueError(f"--probe {', '.join(unknown) or '(none)'}: not a "
                         f"sphsolid/probe compute of {deck} (it has "
                         f"{', '.join(computes) or 'none'})")
    until = float(until if until is not None else declared[time_variable])
    if ladder is None:
        base = float(declared[variable])
        ladder = [3 * base, 2 * base, 1.5 * base]
    search._check_request(error, until, norm, max_seconds, ladder)
    ladder = sorted(ladder, reverse=True)
    options = []
    for choice in choices:
        name, _, values = choice.partition("=")
        if name not in declared or not values:
            raise ValueError(f"--set {choice!r}: expected NAME=V1,V2 with a "
                             f"variable the deck declares")
        options.append([(name, v) for v in values.split(",") if v])
    combos = [tuple(c) for c in itertools.product(*options)] or [()]
    clock = wallclock.perf_counter()
    request = {"error": error, "until": until, "norm": norm,
               "quantity": "von_mises", "probes": probes,
               "threads": threads, "max_seconds": max_seconds,
               "window": [0.0, until], "ladder": ladder,
               "smoothing_s": metrics.SMOOTHING, "deck": str(deck)}
    grid = metrics.time_grid(0.0, until)
    cands = []
    with tempfile.TemporaryDirectory(prefix="sphsolid-deck-") as work:
        for k, values in enumerate(combos):
            cand = Candidate(DeckSetting(values), [])
            for dx in ladder:
                say(f"[{k * len(ladder) + len(cand.runs) + 1}/"
                    f"{len(combos) * len(ladder)}] {cand.setting.label()}, "
                    f"{variable} = {dx:g} ...")
                run = run_deck(deck, dx, until, probes, variable,
                               time_variable, values, threads, Path(work))
                cand.runs.append(run)
                if run.failed:
                    cand.note = f"failed: {run.failed}"[:80]
                    say(f"  {cand.note}")
                    break
                say(f"  {run.particles} atoms, {run.steps} steps, "
                    f"{run.wall:.2f} s")
            cands.append(cand)
    usable = [c for c in cands if not c.note]
    for cand in usable:
        cand.smoothed = [search._smoothed(r, grid) for r in cand.runs]
        search._fit_candidate(cand, norm, max_refinement, threads)
    floors = error_model.consistency_floors([c.model for c in usable],
                                        [c.smoothed for c in usable], norm,
                                        ladder)
    for cand, floor in zip(usable, floors):
        cand.model.floor = floor
        dx = cand.model.spacing_for(error)
        if dx is None:
            cand.note = f"floor {floor * 100:.2f} % >= request"
            continue
        dx = float(f"{min(dx, ladder[0]):.3g}")
        while cand.model.upper(dx) > error:
            dx *= 0.99
        if dx < cand.model.smallest_dx:
            cand.note = (f"needs {variable} {dx:.3g}, below the finest "
                         f"calibrated / {max_refinement:g}")
            continue
        cand.dx = dx
        cand.particles, cand.steps = search._size_at(cand.runs, dx)
        cand.seconds = cand.cost.predict(cand.particles, cand.steps)
    priced = sorted((c for c in usable if c.seconds is not None),
                    key=lambda c: c.seconds)
    affordable = [c for c in priced
                  if max_seconds is None or c.seconds <= max_seconds]
    result = Plan(request=request, feasible=bool(affordable),
                          threads=threads, candidates=cands,
                          scene=f"deck {deck.name}",
                          effects_examined=False)
    if affordable:
        result.adopt(affordable[0])
    elif usable:
        best = min(usable, key=lambda c: c.model.reachable()[0])
        result.best_reachable_error, at = best.model.reachable()
        result.reason = (f"no variable setting meets {error * 100:g} %"
                         + (f" within {max_seconds:g} s" if max_seconds
                            else "") + f"; best reachable: "
                         f"{result.best_reachable_error * 100:.2f} % with "
                         f"{best.setting.label()} at {variable} = "
                         f"{at:.3g}")
    else:
        result.reason = "every deck run failed"
    result.calibration_seconds = wallclock.perf_counter() - clock
    return result
