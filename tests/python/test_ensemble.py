"""Ensembles of flaw draws (sphsolid.ensemble, ``sphsolid ensemble``):
the bootstrap interval's coverage, bitwise members alone / in the pool /
after a resume, the summary's keys, bad input.

The runs are tensile bars at dx = 5 mm (64 specimen particles, a fraction
of a second each)."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

import sphsolid
from sphsolid.cli import main as cli_main
from sphsolid.ensemble import bootstrap_mean_interval, run_member

DX = 5e-3
MEMBERS = 3


def _ensemble(out, members=MEMBERS, jobs=1, **kw):
    return sphsolid.ensemble("tensile", members, out, dx=DX, jobs=jobs,
                             seed=4, figure=False, **kw)


def _member_files(out, member):
    where = out / f"member_{member:04d}"
    summary = json.loads((where / "summary.json").read_text())
    summary.pop("wall_s")
    summary.pop("cpu_s")
    summary.pop("checksum")       # over the wall and CPU seconds
    return (where / "load.csv").read_bytes(), summary


@pytest.fixture(scope="module")
def fresh(tmp_path_factory):
    out = tmp_path_factory.mktemp("fresh")
    return out, _ensemble(out)


def test_bootstrap_interval_covers_the_mean_at_its_rate():
    """Over 600 samples of 12 values of a normal and of an exponential
    distribution, the 95 % interval of the mean contains the true mean in
    95 % of them, within three binomial standard deviations (0.027)."""
    rng = np.random.Generator(np.random.PCG64(7))
    repeats, n, mu = 600, 12, 3.0
    tolerance = 3.0 * np.sqrt(0.95 * 0.05 / repeats)
    for draw in (lambda: rng.normal(mu, 2.0, n),
                 lambda: rng.exponential(mu, n)):
        hits = 0
        for r in range(repeats):
            low, high = bootstrap_mean_interval(draw(), 0.95, resamples=1000,
                                                seed=r)
            hits += low <= mu <= high
        rate = hits / repeats
        assert abs(rate - 0.95) < tolerance, rate
    # and its width is that of the normal interval of the mean
    x = rng.normal(mu, 2.0, 400)
    low, high = bootstrap_mean_interval(x, 0.95)
    assert (high - low) == pytest.approx(2 * 1.96 * x.std(ddof=1) / 20,
                                         rel=0.1)


def test_summary_has_the_keys_and_its_statistics(fresh):
    out, result = fresh
    summary = json.loads((out / "summary.json").read_text())
    for key in ("quantity", "members", "mean", "std", "ci95_low",
                "ci95_high", "values"):
        assert key in summary, key
    assert summary["quantity"] == "strength" and summary["unit"] == "Pa"
    assert summary["members"] == MEMBERS
    values = [json.loads((out / f"member_{i:04d}" / "summary.json")
                         .read_text())["strength_Pa"] for i in range(MEMBERS)]
    assert summary["values"] == values
    assert summary["mean"] == pytest.approx(np.mean(values), rel=1e-12)
    assert summary["std"] == pytest.approx(np.std(values, ddof=1), rel=1e-12)
    assert summary["ci95_low"] < summary["mean"] < summary["ci95_high"]
    assert len(set(values)) == MEMBERS       # the members are other draws
    assert result.ran == list(range(MEMBERS))


def test_member_i_is_the_run_of_the_damage_member_i(fresh):
    """Member i's flaws are the damage effect's member i: member 0 is the
    single run of the seed (sphsolid.fracture with that seed, no member),
    member 2 that with member=2."""
    from sphsolid import fracture
    out, _ = fresh
    for member, options in ((0, {}), (2, {"member": 2})):
        scene = fracture.tensile_bar(DX, seed=4, **options)
        scene.calc = sphsolid.CLibrary(threads=1)
        run = fracture.load_to_break(scene, max_strain=0.01)
        _, summary = _member_files(out, member)
        assert run.strength_Pa == summary["strength_Pa"], member


def test_resume_keeps_finished_members_and_reruns_the_rest(fresh, tmp_path):
    """A killed ensemble (member 1 without its summary, a half-written
    temporary file) continues: members 0 and 2 are kept, member 1 runs
    again, and every member is bitwise that of a fresh run."""
    out, _ = fresh
    partial = tmp_path / "partial"
    first = _ensemble(partial, members=2)      # stopped after two members
    assert first.ran == [0, 1]
    (partial / "member_0001" / "summary.json").unlink()
    (partial / "member_0001" / "summary.json.tmp").write_text("{")
    (partial / "member_0001" / "load.csv").write_text("time_s,stra")
    resumed = _ensemble(partial)
    assert resumed.ran == [1, 2]
    for i in range(MEMBERS):
        assert _member_files(partial, i) == _member_files(out, i), i
    again = _ensemble(partial)
    assert again.ran == []
    assert again.summary["values"] == resumed.summary["values"]


def test_resume_reruns_a_member_whose_record_fails_its_checksum(fresh,
                                                                tmp_path):
    """A member summary that holds a JSON list, is truncated, had a value
    edited by hand, is another member's, or whose load.csv was edited is
    not taken: the resume names the file and the reason and runs the
    member again, bitwise as a fresh run; the others are kept."""
    out, _ = fresh
    tampered = tmp_path / "tampered"
    shutil.copytree(out, tampered)
    member = tampered / "member_000{}" / "summary.json"
    original = json.loads(Path(str(member).format(2)).read_text())
    edited = dict(original, strength_Pa=original["strength_Pa"] * 1.1)
    cases = {
        0: ("[1, 2]", "holds a JSON list, not a member's summary"),
        1: ('{"peak_load_N": 3', "not a complete JSON file"),
        2: (json.dumps(edited, indent=2), "fails its checksum"),
    }
    for i, (text, _) in cases.items():
        Path(str(member).format(i)).write_text(text)
    messages = []
    resumed = _ensemble(tampered, log=messages.append)
    assert resumed.ran == [0, 1, 2]
    for i, (_, reason) in cases.items():
        path = str(member).format(i)
        assert any(m.startswith(f"{path}: {reason}") and
                   m.endswith(f"member {i} runs again")
                   for m in messages), (i, messages)
        assert _member_files(tampered, i) == _member_files(out, i), i
    assert resumed.summary["values"] == json.loads(
        (out / "summary.json").read_text())["values"]
    # another member's record, a changed load.csv, no checksum at all
    shutil.copy(Path(str(member).format(0)), Path(str(member).format(1)))
    with open(tampered / "member_0002" / "load.csv", "a") as f:
        f.write("1,2,3\n")
    messages.clear()
    again = _ensemble(tampered, log=messages.append)
    assert sorted(again.rejected) == [1, 2], messages
    assert "is of member=0, this ensemble's member has member=1" in \
        again.rejected[1]
    assert "its load.csv fails the summary's checksum" in again.rejected[2]
    record = json.loads(Path(str(member).format(0)).read_text())
    record.pop("checksum")
    Path(str(member).format(0)).write_text(json.dumps(record))
    with pytest.warns(UserWarning, match="member_0000/summary.json: has no "
                      "checksum"):
        assert _ensemble(tampered).ran == [0]


def test_cli_ensemble_estimates_its_cost_and_refuses_what_cannot_be(
        tmp_path, capsys):
    """Before a member starts, the cost: particles, steps, time and disk;
    an ensemble beyond --max-time or the free disk is refused with the
    figures, nothing written."""
    out = tmp_path / "big"
    assert cli_main(["ensemble", "tensile", "--dx", "5mm", "--seeds",
                     "1000000", "--max-time", "1h", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "estimate: 1000000 member(s) to run of 88 particles" in err
    assert "longer than --max-time 1 h" in err
    assert not list(out.glob("member_*"))
    assert cli_main(["ensemble", "tensile", "--dx", "5mm", "--seeds",
                     str(10**12), "--out", str(out)]) == 2
    assert "MB free; use fewer --seeds" in capsys.readouterr().err


def test_a_member_in_the_pool_is_bitwise_the_member_alone(fresh, tmp_path):
    out, _ = fresh
    pool = tmp_path / "pool"
    result = _ensemble(pool, jobs=2)
    assert sorted(result.ran) == list(range(MEMBERS))
    alone = tmp_path / "alone"
    config = json.loads((pool / "ensemble.json").read_text())
    run_member(config, 2, alone)
    assert _member_files(pool, 2) == _member_files(alone, 2)
    assert _member_files(pool, 1) == _member_files(out, 1)


def test_an_ensemble_directory_refuses_another_ensemble(fresh, tmp_path):
    out, _ = fresh
    other = tmp_path / "other"
    shutil.copytree(out, other)
    with pytest.raises(ValueError, match="seed=4.*seed=5"):
        sphsolid.ensemble("tensile", MEMBERS, other, dx=DX, seed=5,
                          figure=False)
    with pytest.raises(ValueError, match="members=1"):
        sphsolid.ensemble("tensile", 1, tmp_path / "one", dx=DX)
    with pytest.raises(ValueError, match="'bend'"):
        sphsolid.ensemble("bend", 3, tmp_path / "bend")
    with pytest.raises(ValueError, match="jobs=0"):
        sphsolid.ensemble("ucs", 3, tmp_path / "jobs", jobs=0)
    with pytest.raises(ValueError, match="2 values, got 1"):
        bootstrap_mean_interval([1.0])


def test_cli_writes_summary_and_histogram(tmp_path, capsys):
    out = tmp_path / "cli"
    assert cli_main(["ensemble", "tensile", "--seeds", "2", "--dx", "5mm",
                     "--seed", "4", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["members"] == 2 and (out / "histogram.png").stat().st_size
    assert "95% interval of the mean" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        cli_main(["ensemble", "tensile", "--seeds", "1", "--out", str(out)])
    assert "'1': must be >= 2" in capsys.readouterr().err


# ----------------------------------- the optional effects (sphsolid ucs's)
def _cli_ensemble(capsys, argv, out):
    assert cli_main(["ensemble"] + argv + ["--seeds", "2", "--out",
                                           str(out)]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    config = json.loads((out / "ensemble.json").read_text())
    members = [json.loads((out / f"member_{i:04d}" / "summary.json")
                          .read_text()) for i in range(2)]
    return config, members, first


@pytest.fixture(scope="module")
def brittle_ucs(tmp_path_factory):
    """A 2-member UCS ensemble at 4 mm with the defaults: damage only
    (strengths 26.5 and 25.6 MPa, peaks at 0.31 % strain)."""
    out = tmp_path_factory.mktemp("brittle") / "ucs"
    assert cli_main(["ensemble", "ucs", "--dx", "4mm", "--seeds", "2",
                     "--out", str(out)]) == 0
    config = json.loads((out / "ensemble.json").read_text())
    members = [json.loads((out / f"member_{i:04d}" / "summary.json")
                          .read_text()) for i in range(2)]
    return config, members


def test_ensemble_defaults_record_the_options_as_before(brittle_ucs):
    config, members = brittle_ucs
    assert config == {"test": "ucs", "dx_m": 0.004, "seed": 1,
                      "max_strain": 0.008, "drop": 0.5,
                      "samples_per_strain": 20000.0, "scene_options": {}}
    for i, member in enumerate(members):
        assert member["effects"] == {
            "damage": {"seed": 1.0, "flaws": 10.0, "member": float(i)},
            "artificial_viscosity": {"alpha": 1.0, "beta": 0.0}}


def test_ensemble_cohesion_reaches_every_members_scene(brittle_ucs,
                                                       tmp_path, capsys):
    """--cohesion 2MPa caps each member at the plane-strain cone (12.7
    MPa at 4 mm, reached by 0.2 % strain: test_fracture_effects), about
    half the damage-only strengths."""
    _, brittle = brittle_ucs
    config, members, first = _cli_ensemble(
        capsys, ["ucs", "--dx", "4mm", "--max-strain", "0.2%",
                 "--cohesion", "2MPa"], tmp_path / "plastic")
    plasticity = {"cohesion": 2e6, "friction_angle": 30.0}
    assert config["scene_options"] == {"plasticity": plasticity}
    assert first.endswith("optional effects: drucker_prager (cohesion 2 "
                          "MPa, friction angle 30 deg)")
    weakest = min(m["strength_Pa"] for m in brittle)
    for i, member in enumerate(members):
        assert member["effects"]["drucker_prager"] == plasticity, i
        assert member["strength_Pa"] < 0.6 * weakest, i


def test_ensemble_effects_survive_a_resume_and_a_reread(tmp_path, capsys):
    out = tmp_path / "tensile"
    argv = ["tensile", "--dx", "5mm", "--seed", "4", "--max-strain",
            "0.02%", "--cohesion", "5e6", "--friction-angle", "40",
            "--artificial-stress", "0.3"]
    config, members, _ = _cli_ensemble(capsys, argv, out)
    effects = {"drucker_prager": {"cohesion": 5e6, "friction_angle": 40.0},
               "artificial_stress": {"epsilon": 0.3}}
    assert config["scene_options"] == {
        "plasticity": effects["drucker_prager"],
        "artificial_stress": effects["artificial_stress"]}
    for member in members:
        assert effects.items() <= member["effects"].items()
    # a member rerun from ensemble.json is bitwise the one in the ensemble
    _, again = _member_files(out, 1)
    rerun = run_member(config, 1)
    for key in ("wall_s", "cpu_s", "checksum"):
        rerun.pop(key)
    assert rerun == again
    # the same options resume it; others are another ensemble
    assert cli_main(["ensemble"] + argv + ["--seeds", "2", "--out",
                                           str(out)]) == 0
    assert "(2 kept from an earlier run)" in capsys.readouterr().out
    assert cli_main(["ensemble", "tensile", "--dx", "5mm", "--seed", "4",
                     "--max-strain", "0.02%", "--seeds", "2", "--out",
                     str(out)]) == 2
    assert "holds an ensemble with scene_options=" in capsys.readouterr().err


def test_ensemble_refuses_friction_angle_without_cohesion(tmp_path, capsys):
    out = tmp_path / "out"
    assert cli_main(["ensemble", "ucs", "--seeds", "2", "--dx", "4mm",
                     "--max-strain", "0.02%", "--friction-angle", "30",
                     "--out", str(out)]) == 2
    assert ("--friction-angle 30 applies only with --cohesion"
            in capsys.readouterr().err)
    assert not out.exists()            # refused before anything is made
    # the values are those of sphsolid ucs's parsers, with their messages
    for argv, message in (
            (["--cohesion", "-1MPa"], "--cohesion: '-1MPa': must be a "
             "finite stress >= 0"),
            (["--cohesion", "2MPa", "--friction-angle", "90"],
             "--friction-angle: '90': must be in [0, 90) degrees"),
            (["--artificial-stress", "1"], "--artificial-stress: '1': must "
             "be in (0, 1)")):
        with pytest.raises(SystemExit):
            cli_main(["ensemble", "ucs", "--seeds", "2", "--out", str(out)]
                     + argv)
        assert message in capsys.readouterr().err
