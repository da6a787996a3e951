"""The planner on a LAMMPS deck (sphsolid plan --deck): the deck's runs
are the library's physics, and bad requests are named."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import PISTON_DECK

from sphsolid import planner
from sphsolid.planner import deck as plan_deck


def test_deck_run_records_the_library_series(tmp_path, plugin):
    # the deck at 4 mm, alpha 1, to 40 us: its probe series (recorded by
    # the fix the planner adds) equal the library's run of the same scene
    run = plan_deck.run_deck(PISTON_DECK, 4e-3, 40e-6, ["A", "B", "C"], "dx",
                             "t_end", [("alpha", "1.0")], threads=1,
                             workdir=tmp_path)
    assert run.failed is None
    setting = planner.Setting.make(effects={"artificial_viscosity":
                                            {"alpha": 1.0, "beta": 0.0}})
    ref = planner.ladder_run(planner.piston_factory, 4e-3, setting, 40e-6,
                             planner.project_scenes()["piston"].probes,
                             "von_mises", 1)
    # the deck takes round(t_end/dt) whole steps, the library lands on
    # t_end with a shortened last one
    assert run.particles == ref.particles
    assert abs(run.steps - ref.steps) <= 1
    common = ref.times <= run.times[-1] + 1e-12
    for name in "ABC":
        mine = np.interp(ref.times[common], run.times, run.series[name])
        peak = np.max(np.abs(ref.series[name]))
        assert np.max(np.abs(mine - ref.series[name][common])) <= 1e-6 * peak


def test_deck_plan_names_unknown_probes_and_variables(tmp_path):
    with pytest.raises(ValueError, match="Z: not a sphsolid/probe compute"):
        plan_deck.plan_deck(PISTON_DECK, 0.1, probes=["Z"])
    with pytest.raises(ValueError, match="declares no variable 'h'"):
        plan_deck.plan_deck(PISTON_DECK, 0.1, variable="h", probes=["A"])
    with pytest.raises(ValueError, match="--set 'nope=1'"):
        plan_deck.plan_deck(PISTON_DECK, 0.1, probes=["A"],
                            choices=["nope=1"])
