"""Settings that differ between MPI ranks stop every rank with one message.

A deck whose pair_style or pair_coeff values come from a variable that
depends on the rank (here the environment's PMI_RANK, set by mpirun) gives
each rank another model; the ranks would then exchange messages of other
sizes or sums of another model.  pair sphsolid compares its settings over
the communicator when a run starts and stops all ranks with an error that
names the keyword that differs.
"""
from __future__ import annotations

import os
import subprocess
import textwrap

import pytest

from conftest import ATOMS_2D, lmp_command

DECK = textwrap.dedent("""\
    plugin load ${{plugin}}
    variable rank getenv PMI_RANK
""") + ATOMS_2D + textwrap.dedent("""\
    processors 2 1 1
    region box block -0.01 0.01 -0.01 0.01 -0.001 0.001 units box
    create_box 1 box
    lattice sq 0.001 origin 0.5 0.5 0.0
    region block block -0.006 0.006 -0.004 0.004 -0.001 0.001 units box
    create_atoms 1 region block
    mass 1 0.0023
    pair_style {pair_style}
    pair_coeff {pair_coeff}
    fix integrate all sphsolid/{fix}
    timestep {timestep}
    run 5
    """)
PAIR_STYLE = "sphsolid 0.001 artificial_viscosity alpha 1.0 beta 0.0"
PAIR_COEFF = "* * K 12.2e9 mu 2.67e9 rho0 2300.0"


def run_two_ranks(tmp_path, plugin, **settings):
    values = dict(pair_style=PAIR_STYLE, pair_coeff=PAIR_COEFF, fix="improved_euler", timestep="1e-7")
    values.update(settings)
    deck = tmp_path / "in.deck"
    deck.write_text(DECK.format(**values))
    cmd = lmp_command(2) + ["-in", str(deck), "-log", "log.lammps", "-nocite",
                            "-var", "plugin", str(plugin)]
    done = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, OMP_NUM_THREADS="1"))
    log = (tmp_path / "log.lammps").read_text() if (tmp_path / "log.lammps").exists() else ""
    return done, done.stdout + done.stderr + log


@pytest.mark.parametrize("fix", ["improved_euler", "leapfrog"])
def test_same_settings_on_both_ranks_run(tmp_path, plugin, fix):
    done, text = run_two_ranks(tmp_path, plugin, fix=fix)
    assert done.returncode == 0, text
    assert "differs between MPI ranks" not in text


@pytest.mark.parametrize("settings, keyword", [
    ({"pair_style": "sphsolid $(0.001*(1+v_rank))"}, "dx"),
    ({"pair_style": "sphsolid 0.001 h_over_dx $(1.2+0.1*v_rank)"}, "h_over_dx"),
    ({"pair_style": "sphsolid 0.001 artificial_viscosity alpha $(1+v_rank) beta 0.0"},
     "artificial_viscosity"),
    ({"pair_coeff": "* * K $(12.2e9*(1+v_rank)) mu 2.67e9 rho0 2300.0"}, "pair_coeff 1 1"),
    # a key of the library's material registry is part of the type's setting
    ({"pair_coeff": "* * K 12.2e9 mu 2.67e9 rho0 2300.0 weibull_m $(9+v_rank)"},
     "pair_coeff 1 1"),
    ({"timestep": "$(1e-7*(1+v_rank))"}, "timestep"),
])
def test_a_setting_that_differs_between_ranks_is_named(tmp_path, plugin, settings, keyword):
    done, text = run_two_ranks(tmp_path, plugin, **settings)
    assert done.returncode != 0, text
    assert f"pair sphsolid: {keyword} differs between MPI ranks" in text, text
    # one message: the error is raised on all ranks together, printed once
    assert text.count("differs between MPI ranks") <= 2, text  # screen and log


# ----------------------------------------- a bad value on one rank alone
#: K negative on rank 1 only: the library refuses it in pair_coeff there.
BAD_ON_RANK_1 = {"pair_coeff": "* * K $(12.2e9*(1-2*v_rank)) mu 2.67e9 rho0 2300.0"}
LIBRARY_MESSAGE = ("ERROR on proc 1: pair sphsolid: pair_coeff * *: bulk modulus "
                   "K=-1.22e+10: must be finite and > 0")


@pytest.mark.parametrize("screen", [[], ["-screen", "none"]], ids=["screen", "no screen"])
def test_a_bad_value_on_one_rank_prints_the_librarys_message(tmp_path, plugin, screen):
    """The rank that refuses a value prints the library's message before the
    job stops (error->one; error->all on that rank alone printed nothing and
    the job died in a barrier abort, status 15), with or without a screen."""
    values = dict(pair_style=PAIR_STYLE, fix="improved_euler", timestep="1e-7")
    values.update(BAD_ON_RANK_1)
    deck = tmp_path / "in.deck"
    deck.write_text(DECK.format(**values))
    cmd = lmp_command(2) + ["-in", str(deck), "-log", "log.lammps", "-nocite",
                            "-var", "plugin", str(plugin)] + screen
    done = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=120,
                          env=dict(os.environ, OMP_NUM_THREADS="1"))
    assert done.returncode != 0
    assert LIBRARY_MESSAGE in done.stdout + done.stderr, done.stdout + done.stderr


def test_a_bad_value_on_one_rank_reaches_the_user_through_open_lammps(tmp_path, plugin):
    """The same deck fed by Python on two ranks through open_lammps (no screen,
    no log): rank 1 prints the library's message and the job stops."""
    import sys
    values = dict(pair_style=PAIR_STYLE, fix="improved_euler", timestep="1e-7")
    values.update(BAD_ON_RANK_1)
    text = DECK.format(**values).replace("plugin load ${plugin}\n", "")
    (tmp_path / "in.deck").write_text(text)
    script = tmp_path / "feed.py"
    script.write_text(textwrap.dedent(f"""\
        from pathlib import Path
        from sphsolid.lammps import open_lammps, preload_mpi
        preload_mpi()
        lmp = open_lammps(plugin={str(plugin)!r})
        lmp.commands_string(Path("in.deck").read_text())
        """))
    mpirun = lmp_command(2)[:-1]
    done = subprocess.run(mpirun + [sys.executable, str(script)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120,
                          env=dict(os.environ, OMP_NUM_THREADS="1"))
    assert done.returncode != 0
    assert LIBRARY_MESSAGE in done.stderr, done.stdout + done.stderr
