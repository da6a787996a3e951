"""The price of a confident strength (sphsolid.planner.strength, ``sphsolid
plan ucs --quantity strength``): the planner's arithmetic on ensembles of
known mean, scatter and cost (the runs are replaced by their summaries),
Student's quantile, the plan file, bad input."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from sphsolid.ensemble import Ensemble
from sphsolid.planner import strength
from sphsolid.planner.strength import plan_strength, student_quantile

MU, A, REL_STD = 20e6, 10.0, 0.03    # mean(dx) = MU (1 + A dx)


def _fake_ensemble(test, members, out, dx=None, jobs=1, seed=1,
                   figure=True, **kw):
    """Members whose mean is exactly MU (1 + A dx), their std REL_STD of
    the converged mean, their CPU cost 1e-6 dx^-3 s."""
    mean = MU * (1 + A * dx)
    values = mean + REL_STD * MU * np.linspace(-1, 1, members) \
        / np.std(np.linspace(-1, 1, members), ddof=1)
    cpu = 1e-6 * dx ** -3
    summary = {"mean": float(values.mean()),
               "std": float(values.std(ddof=1)),
               "ci95_low": 0.0, "ci95_high": 0.0, "members": members,
               "member_cpu_s": [cpu] * members}
    return Ensemble(summary=summary, members=[], ran=[])


@pytest.fixture
def fake(monkeypatch):
    import sphsolid.ensemble as module
    monkeypatch.setattr(module._module if hasattr(module, "_module")
                        else module, "ensemble", _fake_ensemble)


def test_student_quantile_is_the_t_distributions_quantile():
    """The CDF of Student's t (its density integrated numerically) at the
    quantile is p."""
    for dof in (5, 9, 29):
        q = student_quantile(0.975, dof)
        t = np.linspace(-60, q, 400001)
        pdf = (math.gamma((dof + 1) / 2)
               / (math.sqrt(dof * math.pi) * math.gamma(dof / 2))
               * (1 + t ** 2 / dof) ** (-(dof + 1) / 2))
        cdf = float(np.sum((pdf[1:] + pdf[:-1]) / 2 * np.diff(t)))
        assert cdf == pytest.approx(0.975, abs=3e-4), dof


def test_plan_meets_the_request_on_ensembles_of_known_error(fake, tmp_path):
    """Means MU (1 + A dx): the ladder's differences give order 1 and the
    discretisation error A dx / (1 + A dx_finest) (times the safety
    factor 1.25); the seeds make t s/sqrt(N) fill the rest; the plan is
    the cheapest such pair, and finer or fewer would break the request."""
    error = 0.05
    plan = plan_strength("ucs", error, pilot=40, work=tmp_path)
    assert plan.feasible and plan.ladder_resolved
    assert plan.model["order"] == pytest.approx(1.0, abs=0.01)
    finest = plan.ladder[-1]["mean"]
    expected_d = 1.25 * MU * A * plan.dx / finest
    assert plan.discretisation_error == pytest.approx(expected_d, rel=0.02)
    s_rel = plan.ladder[-1]["std"] / finest
    n = plan.seeds
    t = student_quantile(0.975, n - 1)
    assert plan.statistical_error == pytest.approx(t * s_rel / math.sqrt(n))
    assert plan.predicted_error <= error
    # one seed fewer would miss the request (unless at the floor of 10)
    if n > strength.MIN_MEMBERS:
        fewer = student_quantile(0.975, n - 2) * s_rel / math.sqrt(n - 1)
        assert plan.discretisation_error + fewer > error
    assert plan.predicted_seconds == pytest.approx(n * 1e-6 * plan.dx ** -3,
                                                   rel=1e-6)
    # a halved request costs more
    tighter = plan_strength("ucs", error / 2, pilot=40, work=tmp_path)
    assert tighter.predicted_seconds > plan.predicted_seconds


def test_sphsolid_plan_strength_writes_the_plan(fake, tmp_path, capsys):
    from sphsolid.cli import main
    out = tmp_path / "plan.json"
    assert main(["plan", "ucs", "--quantity", "strength", "--error", "6%",
                 "--confidence", "0.95", "--out", str(out)]) == 0
    plan = json.loads(out.read_text())
    for key in ("seeds", "predicted_seconds", "predicted_error"):
        assert plan[key] > 0, key
    assert plan["settings"]["dx"] > 0
    assert plan["command"].startswith("sphsolid ensemble ucs --dx")
    assert main(["plan", "piston", "--quantity", "strength", "--error", "2%",
                 "--out", str(out)]) == 2
    assert "'piston'" in capsys.readouterr().err


def test_bad_strength_requests_are_named(tmp_path):
    with pytest.raises(ValueError, match="error=1.5"):
        plan_strength("ucs", 1.5, work=tmp_path)
    with pytest.raises(ValueError, match="'tensile'"):
        plan_strength("tensile", 0.02, work=tmp_path)
    with pytest.raises(ValueError, match="ladder"):
        plan_strength("ucs", 0.02, ladder=[4e-3, 2e-3], work=tmp_path)


def test_a_ladder_within_its_noise_is_reported_unresolved(fake, monkeypatch,
                                                         tmp_path):
    """Scatter 30 % of the mean: the ladder's differences of means (0.02
    of it) lie within their noise, and the plan says so."""
    monkeypatch.setitem(globals(), "REL_STD", 0.3)
    plan = plan_strength("ucs", 0.5, work=tmp_path)
    assert not plan.ladder_resolved
    assert plan.model["order"] <= 1.0
    assert "not resolved" in plan.summary()


def test_a_refusal_says_what_the_request_would_cost(fake, tmp_path):
    """Means MU (1 + A dx), ladder 8, 6, 4 mm: at the finest spacing the
    ladder allows (2 mm) the discretisation error alone, 1.25 A dx /
    (1 + 4 mm A), exceeds 2 %, so the plan is refused; below it the same
    law and the cost 1e-6 dx^-3 s per member give the cheapest (dx, N)
    that meets the request, which the refusal reports with its CPU
    seconds and a pilot ladder reaching it."""
    error = 0.02
    plan = plan_strength("ucs", error, pilot=40, work=tmp_path)
    assert not plan.feasible
    finest = plan.ladder[-1]["mean"]
    assert 1.25 * MU * A * 2e-3 / finest > error
    b = plan.beyond
    assert b["dx"] < 2e-3
    assert b["discretisation_error"] == pytest.approx(
        1.25 * MU * A * b["dx"] / finest, rel=0.02)
    s_rel = plan.ladder[-1]["std"] / finest
    n = b["seeds"]
    assert b["statistical_error"] == pytest.approx(
        student_quantile(0.975, n - 1) * s_rel / math.sqrt(n))
    assert b["discretisation_error"] + b["statistical_error"] <= error
    assert b["predicted_seconds"] == pytest.approx(n * 1e-6 * b["dx"] ** -3,
                                                   rel=1e-6)
    # the fewest seeds: one fewer misses the request
    fewer = student_quantile(0.975, n - 2) * s_rel / math.sqrt(n - 1)
    assert b["discretisation_error"] + fewer > error
    # the cheapest spacing: with E_d = a dx and N ~ (z s / (E - a dx))^2,
    # N dx^-3 is least where 3 (E - a dx) = 2 a dx, dx = 3 E / (5 a)
    # (the search's grid steps by 5 % in dx)
    a = 1.25 * MU * A / finest
    assert b["dx"] == pytest.approx(3 * error / (5 * a), rel=0.05)
    # the pilot ladder reaches the planned dx (finest = dx x refinement 2)
    assert b["pilot_ladder"][-1] == pytest.approx(2 * b["dx"])
    assert b["pilot_seconds"] == pytest.approx(
        40 * sum(1e-6 * d ** -3 for d in b["pilot_ladder"]), rel=1e-6)
    assert f"{b['predicted_seconds']:.3g} CPU s" in plan.reason
    # the statistical error alone at the finest allowed spacing (2 mm):
    # the fewest N with t s_rel / sqrt(N) <= 2 %, and their cost
    alone = b["statistics_alone"]
    n = alone["seeds"]
    assert alone["dx"] == pytest.approx(2e-3)
    assert student_quantile(0.975, n - 1) * s_rel / math.sqrt(n) <= error
    assert student_quantile(0.975, n - 2) * s_rel / math.sqrt(n - 1) > error
    assert alone["predicted_seconds"] == pytest.approx(n * 1e-6 * 2e-3 ** -3,
                                                       rel=1e-6)
    assert f"{n} seeds at dx = 2 mm" in plan.reason
    assert plan.to_dict()["beyond"] == b


def test_the_effect_options_reach_the_pilots_and_the_command(
        monkeypatch, tmp_path, capsys):
    """--cohesion and --artificial-stress reach every pilot ensemble's
    scene options (sphsolid ensemble's) and the planned command, which
    asks for the same scenes; a plan without them is as before."""
    import shlex
    import sys

    from sphsolid.cli import build_parser, main
    from sphsolid.cli.fracture import scene_options
    pilots = []

    def recording(*args, scene_options=None, **kw):
        pilots.append(scene_options)
        return _fake_ensemble(*args, **kw)
    # (sphsolid.ensemble is the function; the module is in sys.modules)
    monkeypatch.setattr(sys.modules["sphsolid.ensemble"], "ensemble",
                        recording)
    out = tmp_path / "plan.json"
    assert main(["plan", "ucs", "--quantity", "strength", "--error", "6%",
                 "--cohesion", "2MPa", "--artificial-stress", "0.3",
                 "--no-cache", "--out", str(out)]) == 0
    options = {"plasticity": {"cohesion": 2e6, "friction_angle": 30.0},
               "artificial_stress": {"epsilon": 0.3}}
    assert pilots == [options] * 3
    plan = json.loads(out.read_text())
    assert plan["scene_options"] == options
    assert plan["command"].endswith("--cohesion 2MPa --friction-angle 30 "
                                    "--artificial-stress 0.3 --out DIR")
    args = build_parser().parse_args(shlex.split(plan["command"])[1:])
    assert scene_options(args) == options
    pilots.clear()
    assert main(["plan", "ucs", "--quantity", "strength", "--error", "6%",
                 "--no-cache", "--out", str(out)]) == 0
    assert pilots == [{}] * 3
    assert "scene_options" not in json.loads(out.read_text())
    pilots.clear()
    capsys.readouterr()
    # refused: without --cohesion, and for the wave planner's scenes
    assert main(["plan", "ucs", "--quantity", "strength", "--error", "6%",
                 "--friction-angle", "30", "--out", str(out)]) == 2
    assert ("--friction-angle 30 applies only with --cohesion"
            in capsys.readouterr().err)
    assert main(["plan", "piston", "--error", "3%", "--cohesion", "2MPa",
                 "--out", str(out)]) == 2
    assert ("--cohesion applies only to the strength plans"
            in capsys.readouterr().err)
    assert pilots == []
