"""The FE statement validation.scene_file_check reads from a scene file."""
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
