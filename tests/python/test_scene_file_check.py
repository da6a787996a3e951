"""The FE statement validation.scene_file_check reads from a scene file."""
import re
from pathlib import Path

import pytest

from validation import scene_file_check as check

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "scene_file"


def test_the_pulled_block_is_stated_as_the_fe_solves_it():
    problem = check.fe_problem(EXAMPLES / "pull.toml")
    (x0, x1), (y0, y1) = problem["extent"]
    assert (x0, x1, y0, y1) == pytest.approx((-0.02, 0.02, 0.0, 0.06))
    # the FE's speed is downward: the block is pulled up at 0.1 m/s
    assert problem["speed"] == pytest.approx(-0.1)
    assert problem["probes"] == {"top": (0.0, 0.05), "middle": (0.0, 0.03)}
    assert (problem["K"], problem["mu"], problem["rho0"]) == (
        12.2e9, 2.67e9, 2300.0)
    assert problem["until"] == pytest.approx(40e-6)


def test_a_scene_the_fe_cannot_state_is_refused_with_the_reason():
    with pytest.raises(ValueError, match="plane strain .* the file is 3D"):
        check.fe_problem(EXAMPLES / "cylinder.toml")


def test_requests_are_norm_and_percentage():
    assert check._requests("max:10,rms:2.5") == [("max", 10.0),
                                                 ("rms", 2.5)]
    for bad in ("mean:3", "max:", "max:-1", "rms:nan"):
        with pytest.raises(Exception, match="request|percentage"):
            check._requests(bad)


def test_a_sweep_run_is_the_file_at_the_spacing_and_preset_asked(tmp_path):
    """sweep_row runs the file with its block at the spacing given (the
    40 x 60 mm block at 4 mm: 10 x 15 particles) and the preset named, and
    scores what it writes as a planned run is scored: against the series
    of that same run the deviation is zero, against a reference off by a
    factor 2 it is 50 % in the max norm."""
    import numpy as np
    names = ["top", "middle"]
    grid = np.linspace(0.0, 40e-6, 801)
    zero = {"grid": grid, **{n: np.zeros_like(grid) for n in names}}
    row = check.sweep_row(EXAMPLES / "pull.toml", "waves", 4e-3, names, zero, 1, tmp_path)
    assert "failed" not in row, row
    log = (tmp_path / "sweep_waves_4mm.log").read_text()
    assert "block 150," in log and "leapfrog" in log, log
    csv_path = next((tmp_path / "sweep_waves_4mm").glob("*_probes.csv"))
    own = check.written_series(csv_path, names, grid)
    itself = {"grid": grid, **own}
    assert check.sweep_row(EXAMPLES / "pull.toml", "waves", 4e-3, names, itself, 1,
                           tmp_path)["max"] == 0.0
    double = {"grid": grid, **{n: 2 * own[n] for n in names}}
    assert check.sweep_row(EXAMPLES / "pull.toml", "waves", 4e-3, names, double, 1,
                           tmp_path)["max"] == pytest.approx(0.5)


def test_a_sweep_of_a_file_without_a_spacing_is_refused(tmp_path):
    bare = tmp_path / "bare.toml"
    bare.write_text((EXAMPLES / "pull.toml").read_text().replace('dx = "2mm"', ""))
    with pytest.raises(ValueError, match="no dx"):
        check.sweep_row(bare, "paper", 4e-3, ["top"], {}, 1, tmp_path)


def test_a_sweep_scales_every_body_by_the_first_ones_factor():
    # as the planner does: the first body's spacing becomes the sweep's,
    # every other body's keeps its ratio to it (given in any unit)
    text = ('[[bodies]]\ndx = "2mm"  # block\n[[bodies]]\n  dx = 0.003\n'
            '[[bodies]]\ndx = "1 mm"\n')
    out = check.respaced(text, 4e-3)
    assert re.findall(r'dx = "([^"]*)"', out) == ["4mm", "6mm", "2mm"]
    assert "# block" in out
    with pytest.raises(ValueError, match="dx"):
        check.respaced('dx = "fast"\n', 4e-3)
