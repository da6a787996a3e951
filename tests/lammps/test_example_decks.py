"""Every example deck (examples/*/in.*) follows the conventions of
examples/README.md and runs with every integrator of the library.

The conventions: the shared variables dx, t_end, integrator, threads and
output; the integrating fix named by ${integrator}, never written out; the
plugin loaded once (-var plugin FILE in place of the one lmp loaded by
itself, no "Open of file ... failed" after the automatic load); the files
written named ${output}_*.  Each deck runs at 4 times its default spacing
for 20 us of simulated time (a few steps each).  A deck that runs another
deck (examples/ensemble/in.ensemble) names it in its variable `deck`, a
path relative to its own folder, which the test passes resolved.
"""
from __future__ import annotations

import os
import re
import subprocess
from importlib import metadata
from pathlib import Path

import pytest

from conftest import REPOSITORY, lmp_command

from sphsolid._lib import integrator_names
from sphsolid.planner.deck import deck_variables

DECKS = sorted(REPOSITORY.glob("examples/*/in.*"))
SHARED = ("dx", "t_end", "integrator", "threads", "output")
COARSE = 4.0            # times the deck's default spacing
T_END = 2e-5            # [s]


def deck_id(deck: Path) -> str:
    return deck.name


def run(deck: Path, work: Path, variables: dict, plugin: Path | None = None,
        threads: str = "1") -> tuple[subprocess.CompletedProcess, str]:
    """lmp on the deck in `work` (OMP_NUM_THREADS=threads); returns the
    process and its log."""
    work.mkdir(parents=True, exist_ok=True)
    cmd = lmp_command(1) + ["-in", str(deck), "-log", "log.lammps", "-nocite"]
    if plugin is not None:
        cmd += ["-var", "plugin", str(plugin)]
    for key, value in variables.items():
        cmd += ["-var", key, str(value)]
    done = subprocess.run(cmd, cwd=work, capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, OMP_NUM_THREADS=threads))
    log = work / "log.lammps"
    return done, log.read_text() if log.exists() else ""


def coarse(deck: Path, integrator: str, output: str = "run") -> dict:
    declared = deck_variables(deck.read_text())
    dx = float(declared["dx"]) * COARSE
    variables = {"dx": repr(dx), "t_end": T_END, "integrator": integrator, "threads": 1,
                 "output": output}
    if "deck" in declared:
        variables["deck"] = str((deck.parent / declared["deck"]).resolve())
    return variables


#: LAMMPS's own file: the counter of a uloop variable (in.ensemble)
LAMMPS_FILES = {"log.lammps", "tmp.lammps.variable"}


def test_there_are_decks():
    assert {d.parent.name for d in DECKS} >= {"uniaxial_piston", "gravity",
                                               "uniaxial_cylinder"}


@pytest.mark.parametrize("deck", DECKS, ids=deck_id)
def test_deck_follows_the_conventions(deck):
    text = deck.read_text()
    declared = deck_variables(text)
    missing = [name for name in SHARED if name not in declared]
    assert not missing, f"{deck.name} declares no variable {missing}"
    assert declared["integrator"] == "improved_euler"
    assert declared["threads"] == "0"
    # the integrating fix follows ${integrator}
    written = re.findall(r"^\s*fix\s+\S+\s+\S+\s+sphsolid/(improved_euler|leapfrog|heun)\b",
                         text, re.M)
    assert not written, f"{deck.name} writes out fix sphsolid/{written}"
    assert re.search(r"sphsolid/\$\{integrator\}", text)
    # no unconditional plugin load (it fails after lmp's automatic load)
    assert not re.search(r"^\s*plugin\s+load", text, re.M)


@pytest.mark.parametrize("integrator", integrator_names())
@pytest.mark.parametrize("deck", DECKS, ids=deck_id)
def test_deck_runs_with_every_integrator(deck, integrator, tmp_path, plugin):
    done, log = run(deck, tmp_path, coarse(deck, integrator), plugin)
    assert done.returncode == 0, f"{deck.name}: {done.stdout[-3000:]}{done.stderr[-2000:]}"
    screen = done.stdout + done.stderr
    assert "Open of file" not in screen and "ERROR" not in screen
    assert "Ignoring load" not in log
    # loaded once, from the file given: one "Loading plugin" per style
    assert log.count("Loading plugin: SPH elastic solid") == 1
    assert re.search(rf"^fix\s+\S+\s+\S+\s+sphsolid/{integrator}\b", log, re.M), \
        f"{deck.name} did not run fix sphsolid/{integrator}"
    steps = [int(s) for s in re.findall(r"Loop time of \S+ on \d+ procs for (\d+) steps", log)]
    assert steps and steps[-1] > 0
    assert "1 MPI tasks x 1 OpenMP threads" in log
    written = sorted(p.name for p in tmp_path.iterdir() if p.name not in LAMMPS_FILES)
    assert written and all(name.startswith("run_") for name in written), written
    assert all((tmp_path / name).stat().st_size > 0 for name in written)


def test_threads_sets_the_openmp_threads(tmp_path, plugin):
    deck = REPOSITORY / "examples" / "gravity" / "in.gravity"
    variables = dict(coarse(deck, "improved_euler"), threads=2)
    done, log = run(deck, tmp_path, variables, plugin, threads="1")
    assert done.returncode == 0, done.stdout[-3000:]
    assert "1 MPI tasks x 2 OpenMP threads" in log


def test_a_missing_plugin_file_stops_the_deck(tmp_path):
    deck = REPOSITORY / "examples" / "uniaxial_piston" / "in.uniaxial_piston"
    done, _ = run(deck, tmp_path, coarse(deck, "improved_euler"),
                  plugin=tmp_path / "no_such_plugin.so")
    assert done.returncode == 1
    assert "-var plugin " + str(tmp_path / "no_such_plugin.so") + ": no such file" in done.stdout


def _entry_point_installed() -> bool:
    return any(ep.name == "sphsolid"
               for ep in metadata.entry_points(group="lammps.plugins"))


@pytest.mark.skipif(not _entry_point_installed(),
                    reason="lmp loads no plugin by itself (sphsolid build-plugin)")
def test_deck_runs_quietly_on_the_automatic_plugin(tmp_path):
    deck = REPOSITORY / "examples" / "uniaxial_piston" / "in.uniaxial_piston"
    done, log = run(deck, tmp_path, coarse(deck, "leapfrog"))
    assert done.returncode == 0, done.stdout[-3000:]
    assert "Open of file" not in done.stdout + done.stderr
    assert "Loading plugin" not in log and "Unloading" not in log
    assert (tmp_path / "run_probes.txt").stat().st_size > 0
