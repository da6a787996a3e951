"""``sphsolid run`` as complete as the Python API and ``sphsolid piston``:
threads, integrator and preset, checkpoints and resuming, and outputs that
end at the end time."""
import csv

import numpy as np
import pytest

import sphsolid
from sphsolid.cli import main
from sphsolid.presets import PRESETS

from scene_texts import block_toml

DAMPED = """
[effects]
damping = { rate = 100 }
"""


def scene_file(tmp_path, extra=""):
    path = tmp_path / "block.toml"
    path.write_text(block_toml(12, "3mm", until="20us", platens=True,
                               top=extra, tail=DAMPED, probe_interval=4))
    return path


def csv_rows(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(x) for x in r] for r in rows[1:]])


def test_run_help_lists_the_new_options_and_every_preset(capsys):
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for option in ("--threads", "--checkpoint-every", "--resume",
                   "--integrator", "--preset", "--dt"):
        assert option in text
    for name in PRESETS:
        assert f"{name}: " in text


def test_run_takes_threads_integrator_and_preset(tmp_path):
    path = scene_file(tmp_path, 'threads = 1')
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--threads", "1",
                 "--preset", "waves", "--no-progress"]) == 0
    with sphsolid.Trajectory(out / "block.h5") as traj:
        text = traj.describe()
    # the file gives no kernel, integrator or viscosity: the preset's
    assert "kernel cubic_o4" in text and "leapfrog" in text
    assert "artificial_viscosity" not in text
    # the command line's integrator beats the preset's
    assert main(["run", str(path), "--out", str(out), "--preset", "waves",
                 "--integrator", "improved_euler", "--no-progress"]) == 0
    with sphsolid.Trajectory(out / "block.h5") as traj:
        assert "improved_euler" in traj.describe()


def test_run_checkpoints_and_resumes_bit_for_bit(tmp_path):
    path = scene_file(tmp_path)
    whole, first, second = (tmp_path / n for n in ("whole", "a", "b"))
    assert main(["run", str(path), "--out", str(whole), "--checkpoint-every",
                 "10us", "--no-progress"]) == 0
    assert main(["run", str(path), "--out", str(first), "--until", "10us",
                 "--checkpoint-every", "10us", "--no-progress"]) == 0
    assert (first / "block_checkpoint.h5").is_file()
    assert main(["run", str(path), "--out", str(second), "--resume",
                 str(first / "block_checkpoint.h5"), "--no-progress"]) == 0
    _, straight = csv_rows(whole / "block_probes.csv")
    _, resumed = csv_rows(second / "block_probes.csv")
    assert resumed[0, 0] >= 10e-6 and 1 < len(resumed) < len(straight)
    # the samples after the checkpoint are the straight run's, bitwise
    np.testing.assert_array_equal(resumed, straight[-len(resumed):])


def test_resume_with_another_integrator_is_refused(tmp_path, capsys):
    path = scene_file(tmp_path)
    assert main(["run", str(path), "--out", str(tmp_path), "--until", "5us",
                 "--checkpoint-every", "5us", "--no-progress"]) == 0
    assert main(["run", str(path), "--out", str(tmp_path), "--integrator",
                 "leapfrog", "--resume",
                 str(tmp_path / "block_checkpoint.h5")]) == 2
    assert ("was written by the 'improved_euler' integrator; this run uses "
            "'leapfrog'") in capsys.readouterr().err


@pytest.mark.parametrize("command", ["run", "piston"])
def test_probe_csv_ends_with_the_final_state(command, tmp_path):
    out = tmp_path / "out"
    if command == "run":
        argv = ["run", str(scene_file(tmp_path)), "--out", str(out)]
        name, until, interval = "block", 20e-6, 4
    else:
        argv = ["piston", "--dx", "8mm", "--until", "0.025ms", "--out",
                str(out), "--times", "0.025ms"]
        name, until, interval = "piston", 25e-6, 10
    assert main(argv + ["--no-progress"]) == 0
    _, rows = csv_rows(out / f"{name}_probes.csv")
    with sphsolid.Trajectory(out / f"{name}.h5") as traj:
        series, final = traj.probes, traj.times[-1]
    assert rows[-1, 0] == final == pytest.approx(until, rel=1e-12)
    # the last step is not one of the probe interval's
    assert rows[-1, 1] % interval != 0
    # the CSV's last row is the file's last probe sample
    np.testing.assert_allclose(rows[-1, 2:], np.ravel(series.values[-1]),
                               rtol=1e-12)


def test_piston_checkpoints_and_resumes_bit_for_bit(tmp_path):
    common = ["piston", "--dx", "8mm", "--no-progress"]
    assert main(common + ["--until", "0.02ms", "--times", "0.01ms,0.02ms",
                          "--checkpoint-every", "0.01ms", "--out",
                          str(tmp_path / "whole")]) == 0
    assert main(common + ["--until", "0.01ms", "--times", "0.01ms",
                          "--checkpoint-every", "0.01ms", "--out",
                          str(tmp_path / "a")]) == 0
    assert main(common + ["--until", "0.02ms", "--times", "0.02ms",
                          "--resume", str(tmp_path / "a" /
                                          "piston_checkpoint.h5"),
                          "--out", str(tmp_path / "b")]) == 0
    _, straight = csv_rows(tmp_path / "whole" / "piston_probes.csv")
    _, resumed = csv_rows(tmp_path / "b" / "piston_probes.csv")
    np.testing.assert_array_equal(resumed[-1], straight[-1])


def test_info_lists_effects_without_a_trailing_separator(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["run", str(scene_file(tmp_path)), "--out", str(out),
                 "--until", "2us", "--no-progress"]) == 0
    capsys.readouterr()
    assert main(["info", str(out / "block.h5")]) == 0
    lines = capsys.readouterr().out.splitlines()
    effects = [line for line in lines if line.strip().startswith("effects:")]
    assert effects and "damping" in effects[0]
    assert not any(line.rstrip().endswith(";") for line in lines), lines


def test_a_plans_end_time_that_is_not_a_time_names_the_key(tmp_path,
                                                           capsys):
    from sphsolid import planner
    fake = planner.Plan(request={"until": "abc"}, feasible=True,
                        setting=planner.Setting.make(), dx=8e-3, threads=1,
                        predicted_error=0.1, error_upper=0.12,
                        predicted_seconds=1.0, scene="piston")
    path = fake.save(tmp_path / "plan.json")
    assert main(["piston", "--plan", str(path), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}: " in err and "request.until" in err and "'abc'" in err
    assert "could not convert" not in err and "Traceback" not in err
