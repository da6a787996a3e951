"""Probes see the paper's wave order; figures and the CLI write PNGs."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import sphsolid
from sphsolid import figures, scenes


def cli(*args, timeout=300):
    """Run ``python -m sphsolid`` with this test's sphsolid importable."""
    env = dict(os.environ)
    package_parent = str(Path(sphsolid.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join(
        [package_parent] + [p for p in [env.get("PYTHONPATH")] if p])
    return subprocess.run([sys.executable, "-m", "sphsolid", *args],
                          capture_output=True, text=True, timeout=timeout,
                          env=env)


def arrival(times, values, threshold):
    above = np.nonzero(values > threshold)[0]
    return times[above[0]] if len(above) else np.inf


def test_wave_reaches_probe_B_before_A_and_C():
    """B is 36.5 mm below the piston, A and C 70 mm: the front (speed
    c_p) reaches B first and A, C together (the paper's Fig. 6)."""
    scene = scenes.uniaxial_piston(2e-3)
    probes = sphsolid.Probes(scene, scenes.PAPER_PROBES)
    dyn = sphsolid.ImprovedEuler(scene)
    dyn.attach(probes, interval=1)
    material = scenes.paper_material()
    t_A = 0.070 / material.c_p             # front from the piston to A
    dyn.run(until=1.5 * t_A)
    # threshold: a fifth of the jump rho0 c_p v behind a plane front
    jump = material.rho0 * material.c_p * scenes.PISTON_SPEED
    a, b, c = (arrival(probes.times, probes[n]["von_mises"], 0.2 * jump)
               for n in "ABC")
    assert b < a and b < c
    assert abs(a - c) <= 4 * dyn.dt
    assert 0.5 * t_A < a < 1.5 * t_A


def test_figures_write_pngs_with_the_units(tmp_path):
    scene = scenes.uniaxial_piston(4e-3)
    probes = sphsolid.Probes(scene, scenes.PAPER_PROBES)
    dyn = sphsolid.ImprovedEuler(scene)
    path = tmp_path / "f.h5"
    traj = sphsolid.Trajectory(path, "w", scene)
    dyn.attach(probes, interval=5)
    dyn.attach(traj, interval=50)
    dyn.run(steps=100)
    traj.close()
    with sphsolid.Trajectory(path) as reader:
        frames = reader[1:]
        fig = figures.von_mises_map(frames, tmp_path / "map.png",
                                    mask=lambda f: f.body_ids == 0)
    curves = figures.probe_curves(
        probes.times, {n: probes[n]["von_mises"] for n in probes.names},
        tmp_path / "curves.png")
    for file in (tmp_path / "map.png", tmp_path / "curves.png"):
        assert file.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # Figures returned: one panel per frame (+ colour bar), one curve per
    # probe; nothing written without a path
    from matplotlib.figure import Figure
    assert isinstance(fig, Figure) and isinstance(curves, Figure)
    assert len(fig.axes) == len(frames) + 1
    # each specimen particle of a frame is one square centred on it [mm],
    # coloured by its own von Mises stress in the colour bar's unit
    unit, scale = figures.stress_unit(max(
        float(f.von_mises[f.body_ids == 0].max()) for f in frames))
    for ax, frame in zip(fig.axes, frames):
        keep = frame.body_ids == 0
        squares, = ax.collections
        centres = np.array([p.vertices[:4].mean(axis=0)
                            for p in squares.get_paths()])
        np.testing.assert_allclose(centres, frame.positions[keep, :2] * 1e3,
                                   rtol=0, atol=1e-9)
        np.testing.assert_allclose(squares.get_array(),
                                   frame.von_mises[keep] / scale)
    assert [line.get_label() for line in curves.axes[0].lines] == probes.names
    before = set(tmp_path.iterdir())
    figures.probe_curves(probes.times, {"A": probes["A"]["von_mises"]})
    assert set(tmp_path.iterdir()) == before
    assert figures.stress_unit(2.5e4) == ("kPa", 1e3)
    assert figures.time_unit(3e-4) == ("µs", 1e-6)
    with pytest.raises(ValueError, match="series 'A'"):
        figures.probe_curves([0.0, 1.0], {"A": [1.0]}, tmp_path / "x.png")


def test_figures_leave_the_users_backend_alone(tmp_path):
    # a user who chose a backend (here svg, through MPLBACKEND) keeps it,
    # and pyplot's list of open figures stays empty
    code = ("import matplotlib, numpy as np; from sphsolid import figures;"
            "fig = figures.probe_curves(np.arange(3.0), {'A': np.ones(3)});"
            "import matplotlib.pyplot as plt;"
            "print(matplotlib.get_backend(), len(plt.get_fignums()),"
            " type(fig).__name__)")
    env = dict(os.environ, MPLBACKEND="svg", PYTHONPATH=str(
        Path(sphsolid.__file__).resolve().parents[1]))
    done = subprocess.run([sys.executable, "-c", code], env=env,
                          capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["svg", "0", "Figure"]


def test_cli_piston_writes_its_outputs_and_info_reads_them(tmp_path):
    run = cli("piston", "--dx", "4mm", "--until", "0.04ms", "--out",
              str(tmp_path))
    assert run.returncode == 0, run.stderr
    # the library's lattice rule: round(L / dx) particles per side
    expected = round(0.086 / 4e-3) * round(0.140 / 4e-3)
    assert f"specimen {expected}," in run.stdout
    for name in ("piston.h5", "piston.xmf", "piston_probes.csv",
                 "piston_probes.png", "piston_von_mises.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    info = cli("info", str(tmp_path / "piston.h5"))
    assert info.returncode == 0, info.stderr
    assert "frames: 5" in info.stdout and "probes: A B C" in info.stdout


def test_cli_reports_bad_input_without_a_traceback(tmp_path):
    run = cli("piston", "--dx", "-1mm", "--out", str(tmp_path))
    assert run.returncode == 2
    assert "dx" in run.stderr and "Traceback" not in run.stderr
    run = cli("info", str(tmp_path / "none.h5"))
    assert run.returncode == 2 and "none.h5" in run.stderr


def test_cli_probe_series_is_the_observer_series(tmp_path):
    """The CLI takes its probe series from the library's trajectory file
    (no Python observer between samples): it must be the series a Probes
    observer records at the same steps of the same run, value for value."""
    run = cli("piston", "--dx", "4mm", "--until", "0.04ms",
              "--probe-interval", "3", "--out", str(tmp_path))
    assert run.returncode == 0, run.stderr
    scene = scenes.uniaxial_piston(4e-3)
    probes = sphsolid.Probes(scene, scenes.PAPER_PROBES)
    dyn = sphsolid.ImprovedEuler(scene, progress=False)
    dyn.attach(probes, interval=3)
    for k in range(1, 5):                 # the CLI's 4 frames to --until
        dyn.run(until=0.04e-3 * k / 4)
    probes.record_final()                 # the CLI's series ends at --until
    assert probes.times[-1] == 0.04e-3
    expected = tmp_path / "observer.csv"
    probes.write_csv(expected)
    written = (tmp_path / "piston_probes.csv").read_text()
    assert len(probes.times) > 10
    assert written == expected.read_text()


def test_probes_load_refuses_another_files_probes(tmp_path):
    scene = scenes.uniaxial_piston(4e-3)
    probes = sphsolid.Probes(scene, {"A": scenes.PAPER_PROBES["A"]})
    from sphsolid.trajectory import ProbeSeries
    other = ProbeSeries(names=["B"], columns=probes.values,
                        points=np.zeros((1, 2)), steps=np.zeros(0),
                        times=np.zeros(0), values=np.zeros((0, 1, 6)))
    with pytest.raises(ValueError, match="'B'"):
        probes.load(other)


def test_trajectory_probes_follow_particles_across_list_rebuilds(tmp_path):
    """The library's own probe samples (a Trajectory's, taken in the run
    from the particles near each point) equal sph_probe_sample's over all
    particles, sample for sample, while a vibrating block sweeps through
    the points and the neighbour list is rebuilt many times (it moves
    ~15 skins); points the block enters and leaves record NaN outside."""
    from sphsolid.build import block
    from sphsolid.trajectory import Trajectory
    dx = 1e-3
    body = block((0.0, 0.0), (0.02, 0.01), dx, scenes.paper_material(),
                 velocity=(30.0, 0.0))
    scene = sphsolid.Scene(2, [body])
    scene.freeze()
    x = scene.positions[:, 0].copy()
    scene.velocities[:, 0] += 2.0 * np.sin(np.pi * x / 0.02)  # vibrates
    points = {f"P{k}": (0.016 + 0.002 * k, 0.005 + 0.0004 * k)
              for k in range(5)}
    probes = sphsolid.Probes(scene, points, outside="nan")
    dyn = sphsolid.ImprovedEuler(scene, progress=False)
    dyn.attach(probes, interval=7)
    traj = Trajectory(tmp_path / "sweep.h5", "w", scene, probe_interval=7)
    dyn.run(steps=600)
    traj.close()
    assert scene.positions[:, 0].min() > 10 * 0.25 * 1.2 * dx   # moved
    with Trajectory(tmp_path / "sweep.h5") as reader:
        series = reader.probes
    steps = list(series.steps)
    assert steps[:-1] == list(probes.steps)       # + the closing sample
    values = np.array(probes._samples)
    assert np.isnan(values[:, -1, 0]).any() and not np.isnan(values).all()
    np.testing.assert_array_equal(series.values[:-1], values)
