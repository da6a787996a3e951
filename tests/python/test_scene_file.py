"""Scenes from a file (sphsolid run) and quantities with units.

The scene file is not one of the paper's: a block on a fixed base pulled
upward by a piston (examples/scene_file/pull.toml).  The tensile wave it
launches is checked against the plane-strain wave of 1D strain: it reaches
a probe at depth d after d / c_p, and behind its front the block carries
sigma_yy = rho0 c_p v (tension) and a von Mises stress 2 mu v / c_p.
"""
from __future__ import annotations

import math
import os
import subprocess
import sys
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest

import sphsolid
from sphsolid import units
from sphsolid.scenefile import SceneFileError, load

REPOSITORY = Path(__file__).resolve().parents[2]
PULL = REPOSITORY / "examples" / "scene_file" / "pull.toml"
K, MU, RHO0 = 12.2e9, 2.67e9, 2300.0
C_P = math.sqrt((K + 4 * MU / 3) / RHO0)
SPEED = 0.1          # m/s, the piston's in pull.toml
TOP = 0.060          # m, the block's top


def cli(*args, cwd=None):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(Path(sphsolid.__file__).resolve().parents[1])]
        + [p for p in [env.get("PYTHONPATH")] if p])
    return subprocess.run([sys.executable, "-m", "sphsolid", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=600, env=env)


@pytest.fixture(scope="module")
def pulled(tmp_path_factory):
    out = tmp_path_factory.mktemp("pull")
    done = cli("run", str(PULL), "--out", str(out), "--no-progress")
    assert done.returncode == 0, done.stdout + done.stderr
    return out


def test_scene_file_runs_from_the_cli_and_writes_its_outputs(pulled):
    for name in ("pull.h5", "pull.xmf", "pull_probes.csv", "pull_probes.png",
                 "pull_von_mises.png"):
        assert (pulled / name).is_file(), name


def test_output_opens_in_h5py_and_ends_at_the_end_time(pulled):
    with h5py.File(pulled / "pull.h5", "r") as f:
        times = f["particles/all/position/time"][:]
        n = f["particles/all/position/value"].shape[1]
        names = f["observables/probes"].attrs["names"]
        names = (names.decode() if isinstance(names, bytes) else names).split()
        probe_times = f["observables/probes/time"][:]
        bodies = sorted(f["parameters/bodies"])
    assert n == 600 + 60 + 60                       # block 20 x 30, 3 layers of 20 twice
    assert bodies == ["base", "block", "puller"]
    assert names == ["top", "middle"]
    # frames every 10 us rounded to whole steps (19 of 0.52 us) and the
    # final state at exactly 40 us, written on close
    assert times[0] == 0.0 and times[-1] == pytest.approx(40e-6, rel=1e-12)
    every = np.diff(times[:-1])
    np.testing.assert_allclose(every, every[0], rtol=1e-9)
    assert abs(every[0] - 10e-6) < 0.6e-6
    assert times[-2] < times[-1] and len(times) == 6
    assert probe_times[-1] == pytest.approx(40e-6, rel=1e-12)


def test_output_opens_as_xdmf(pulled):
    root = ET.parse(pulled / "pull.xmf").getroot()
    grids = root.findall("./Domain/Grid/Grid")
    with h5py.File(pulled / "pull.h5", "r") as f:
        times = f["particles/all/position/time"][:]
        assert len(grids) == len(times)
        for grid, t in zip(grids, times):
            assert float(grid.find("Time").get("Value")) == t
            for item in grid.iter("DataItem"):
                if item.get("Format") == "HDF":
                    file, dataset = item.text.strip().split(":")
                    assert file == "pull.h5" and dataset in f


def test_sphsolid_xdmf_rewrites_the_companion(pulled, tmp_path):
    (tmp_path / "pull.h5").write_bytes((pulled / "pull.h5").read_bytes())
    done = cli("xdmf", str(tmp_path / "pull.h5"))
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "pull.xmf").read_text() == (pulled / "pull.xmf").read_text()
    done = cli("xdmf", str(tmp_path / "missing.h5"))
    assert done.returncode == 2 and "missing.h5" in done.stderr


def test_tensile_wave_of_the_pull_arrives_at_the_wave_speed(pulled):
    data = np.genfromtxt(pulled / "pull_probes.csv", delimiter=",", names=True)
    t = data["time_s"]
    for probe, y in (("top", 0.050), ("middle", 0.030)):
        vm = data[f"{probe}_von_mises_Pa"]
        plateau = 2 * MU * SPEED / C_P                    # 204 kPa
        arrival = t[np.argmax(vm > 0.5 * plateau)]
        expected = (TOP - y) / C_P                        # 3.8 us, 11.5 us
        # the half-height point of a front smeared over ~2h = 4.8 mm
        assert abs(arrival - expected) < 2.4e-3 / C_P + 2 * (t[1] - t[0]), (
            probe, arrival, expected)
    # behind the front (middle probe, after arrival and before the release
    # from the free sides, 20 mm away, has spread): the von Mises stress of
    # 1D strain, 2 mu v / c_p
    behind = (t > 30e-3 / C_P + 3e-6) & (t < 30e-3 / C_P + 7e-6)
    vm = data["middle_von_mises_Pa"][behind]
    np.testing.assert_allclose(vm.mean(), 2 * MU * SPEED / C_P, rtol=0.2)
    # tension, bounded by the 1D-strain value rho0 c_p v (602 kPa) until the
    # reflection from the base returns (lateral release only lowers it; the
    # smeared front reaches ~80 % before the release does)
    before = t < (TOP + 30e-3) / C_P
    peak = data["middle_sigma_yy_Pa"][before].max()
    assert 0.6 * RHO0 * C_P * SPEED < peak < 1.02 * RHO0 * C_P * SPEED, peak


def test_until_on_the_command_line_overrides_the_file(tmp_path):
    done = cli("run", str(PULL), "--out", str(tmp_path), "--until", "5us",
               "--no-progress")
    assert done.returncode == 0, done.stderr
    with h5py.File(tmp_path / "pull.h5", "r") as f:
        assert f["particles/all/position/time"][-1] == pytest.approx(5e-6)


@pytest.mark.parametrize("text, message", [
    ('until = "1ms"\n[[bodies]]\nname = "b"\nshape = "blob"\n', "shape must be one of"),
    ('until = "1ms"\ncolour = "red"\n[[bodies]]\nname = "b"\nshape = "block"\n',
     "unknown key(s) colour"),
    ('until = "1ms"\n[[bodies]]\nname = "b"\nshape = "block"\nlo = [0, 0]\n'
     'hi = ["1mm", "1mm"]\ndx = "0.5mm"\nmaterial = "steel"\n', "no material 'steel'"),
    ('until = "1ms"\n[materials.m]\nK = "1GPa"\nmu = "1GPa"\nrho0 = 1000\n'
     '[[bodies]]\nname = "b"\nshape = "block"\nlo = [0, 0]\nhi = ["1mm", "1mm"]\n'
     'dx = "0.5ms"\nmaterial = "m"\n', "dx is a length, but '0.5ms' is a time"),
    ('until = "1ms"\n[materials.m]\nK = "1GPa"\nmu = "1GPa"\nrho0 = 1000\n'
     '[[bodies]]\nname = "p"\nshape = "piston"\nover = "nothing"\n',
     "over must name a body defined before it"),
])
def test_bad_scene_files_are_errors_naming_the_key(tmp_path, text, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(SceneFileError) as error:
        load(path)
    assert message in str(error.value)
    assert str(path) in str(error.value)
    done = cli("run", str(path))
    assert done.returncode == 2 and message in done.stderr


def test_units_in_builders_and_dynamics():
    rock = sphsolid.Material(K=K, mu=MU, rho0=RHO0)
    a = sphsolid.block(("-2mm", "0mm"), ("2mm", "3mm"), "1mm", rock)
    b = sphsolid.block((-0.002, 0.0), (0.002, 0.003), 0.001, rock)
    assert a.lo == b.lo and a.hi == b.hi and a.dx == b.dx
    assert units.quantity("1.5mm/s") == pytest.approx(1.5e-3)
    assert units.quantity("12.2GPa") == pytest.approx(12.2e9)
    assert units.time("0.3ms") == pytest.approx(3e-4)
    assert units.length(" 2 mm ") == pytest.approx(2e-3)
    with pytest.raises(ValueError, match="dx is a length, but '1ms' is a time"):
        sphsolid.block((0, 0), (1, 1), "1ms", rock)
    with pytest.raises(ValueError, match="unknown unit 'furlong'"):
        units.length("3furlong")
    scene = sphsolid.Scene(2, [a])
    dyn = sphsolid.ImprovedEuler(scene, dt="0.1us")
    assert dyn.dt == pytest.approx(1e-7)
    dyn.run(until="0.5us")
    assert scene.time == pytest.approx(5e-7)
    piston = sphsolid.piston(a, velocity=(0, "-1.5mm/s"))
    assert piston.motion.vector(piston, 2) == [0.0, pytest.approx(-1.5e-3)]


def test_implausible_scale_warns_with_the_numbers():
    rock = sphsolid.Material(K=K, mu=MU, rho0=RHO0)
    # 50 "mm" given as metres, with dx = 2 (metres): 625 particles over 50 m
    with pytest.warns(units.ScaleWarning) as record:
        sphsolid.Scene(2, [sphsolid.block((0, 0), (50, 50), 2, rock)])
    text = str(record[0].message)
    assert "50 m across" in text and "dx = 2 m" in text and "625 particles" in text
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # a normal scene: no warning
        sphsolid.Scene(2, [sphsolid.block((0, 0), ("50mm", "50mm"), "2mm", rock)])


def test_version_option():
    done = cli("--version")
    assert done.returncode == 0
    assert done.stdout.startswith(f"sphsolid {sphsolid.__version__} (libsphsolid ")


CYLINDER = REPOSITORY / "examples" / "scene_file" / "cylinder.toml"


def test_cylinder_scene_file_is_the_cylinder_scene():
    """examples/scene_file/cylinder.toml builds scenes.uniaxial_cylinder at
    4.5 mm with the static inset particle for particle (shapes cylinder,
    plate and piston with their inset)."""
    from sphsolid import scenes
    spec = load(CYLINDER)
    mine = spec.scene
    theirs = scenes.uniaxial_cylinder(4.5e-3, inset="static")
    assert mine.dimension == 3
    assert mine.body_counts() == theirs.body_counts()
    np.testing.assert_array_equal(mine.positions, theirs.positions)
    np.testing.assert_array_equal(mine.body_ids, theirs.body_ids)
    np.testing.assert_allclose(mine.masses, theirs.masses, rtol=1e-15)


def test_cylinder_scene_file_runs_and_the_front_is_between_its_probes(tmp_path):
    """Run from the CLI to 16 us: the P-wave from the piston, at
    L - c_p t = 93 mm, has passed D (101.25 mm, 13 us) and not reached the
    centre A (67.5 mm, 26 us, more than 2h ahead of the front): D is
    compressed by a good part of rho0 c_p v, A is still at rest.  On the
    axis the lattice is symmetric under x <-> z: sigma_xx = sigma_zz."""
    import csv
    done = cli("run", str(CYLINDER), "--out", str(tmp_path), "--no-progress")
    assert done.returncode == 0, done.stdout + done.stderr
    for name in ("cylinder.h5", "cylinder.xmf", "cylinder_probes.csv"):
        assert (tmp_path / name).is_file(), name
    with open(tmp_path / "cylinder_probes.csv") as handle:
        last = list(csv.DictReader(handle))[-1]
    assert float(last["time_s"]) == pytest.approx(16e-6, rel=1e-9)
    jump = RHO0 * C_P * 1.5e-3
    assert abs(float(last["A_sigma_yy_Pa"])) < 0.02 * jump
    assert float(last["D_sigma_yy_Pa"]) < -0.1 * jump
    for probe in ("A", "D"):
        xx, zz = float(last[f"{probe}_sigma_xx_Pa"]), float(last[f"{probe}_sigma_zz_Pa"])
        assert abs(xx - zz) <= 1e-9 * jump, probe


#: the held-out scene files of docs/planner.md: material (K, mu, rho0),
#: piston speed, block top and the probe deepest under the piston (name, y)
PRESSED = {
    "press.toml": (30e9, 20e9, 2650.0, 0.5, 0.050, "low", 0.010),
    "soft.toml": (8e9, 4e9, 2200.0, 0.2, 0.030, "low", 0.006),
}


@pytest.mark.parametrize("name", sorted(PRESSED))
def test_compressive_front_of_a_scene_file_arrives_at_its_wave_speed(tmp_path, name):
    """The piston's compressive front reaches the deepest probe (depth d
    below the top, 24-40 mm) after d / c_p, c_p = sqrt((K + 4 mu / 3) /
    rho0) of the file's material (the half height of 2 mu v / c_p, the von
    Mises stress of 1D strain), and the probe is in compression behind it
    until the reflection from the base returns."""
    K_, mu, rho0, speed, top, probe, y = PRESSED[name]
    c_p = math.sqrt((K_ + 4 * mu / 3) / rho0)
    done = cli("run", str(REPOSITORY / "examples" / "scene_file" / name),
               "--out", str(tmp_path), "--no-progress")
    assert done.returncode == 0, done.stdout + done.stderr
    stem = Path(name).stem
    data = np.genfromtxt(tmp_path / f"{stem}_probes.csv", delimiter=",", names=True)
    t, vm = data["time_s"], data[f"{probe}_von_mises_Pa"]
    plateau = 2 * mu * speed / c_p
    arrival = t[np.argmax(vm > 0.5 * plateau)]
    expected = (top - y) / c_p
    # the half-height point of a front smeared over ~2h = 4.8 mm (2 mm)
    assert abs(arrival - expected) < 2.4e-3 / c_p + 2 * (t[1] - t[0]), (
        arrival, expected)
    behind = (t > arrival) & (t < (top + y) / c_p)
    assert np.all(data[f"{probe}_sigma_yy_Pa"][behind] < 0.0)


def test_waves_preset_keeps_the_files_viscosity_and_runs_to_the_end(tmp_path):
    """pull.toml keeps its artificial viscosity (alpha 1) under --preset
    waves: cubic_o4 with the leapfrog, whose stable step viscosity shortens
    for this kernel (docs/stability.md, "Artificial viscosity and the
    leapfrog's step").  At the leapfrog's step without that limit,
    h/(1.5 c0), the watchdog stopped this run at step 21; at the default
    step it reaches the file's end time with every density in bounds."""
    done = cli("run", str(PULL), "--preset", "waves", "--out", str(tmp_path),
               "--no-progress")
    assert done.returncode == 0, done.stdout + done.stderr
    data = np.genfromtxt(tmp_path / "pull_probes.csv", delimiter=",", names=True)
    assert data["time_s"][-1] == pytest.approx(40e-6, rel=1e-9)
