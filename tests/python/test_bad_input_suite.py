"""The bad-input suite of the Python front end, the ``sphsolid`` command and
the example program: each case fails cleanly (an exception, or an exit
status with a message) naming the bad value; none crashes or is silently
accepted.  Files that fail mid-write keep what was written before
(tests/c/test_faults.c covers the faults in depth)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

import sphsolid
import sphsolid.lammps
from sphsolid import build, scenes

ROOT = Path(__file__).resolve().parents[2]


def rock():
    return scenes.paper_material()


def small(dx=1e-3, **kwargs):
    return build.rectangle((0, 0.01), (0, 0.01), dx, rock(), **kwargs)


def small_scene(**kwargs):
    return sphsolid.Scene(2, [small()], **kwargs)


# --------------------------------------------------------------- Python API
def _energy_account_no():
    small_scene().energy_account("no")


def _energy_all_bodies_string():
    small_scene().energy(all_bodies="yes")


def _periodic_strings():
    sphsolid.Scene(2, [small()], domain=((-1, -1), (1, 1)),
                   periodic=("no", "no"))


def _allow_large_string():
    small_scene(allow_large="false")


def _allowing_large_none():
    with sphsolid.allowing_large(None):
        pass


def _set_dt_allow_unstable_string():
    scene = small_scene()
    sphsolid.ImprovedEuler(scene, allow_unstable="no")


def _material_bool():
    sphsolid.Material(K=True, mu=1e9, rho0=1000)


def _material_overflow():
    sphsolid.Material(K=1e300, mu=1e300, rho0=1000)


def _material_string():
    sphsolid.Material(K="12e9", mu=1e9, rho0=1000)


def _material_nan_density():
    sphsolid.Material(K=1e9, mu=1e9, rho0=float("nan"))


def _rectangle_three_x():
    build.rectangle((0, 1, 2), (0, 1), 0.1, rock())


def _rectangle_string_x():
    build.rectangle("ab", (0, 1), 0.1, rock())


def _rectangle_string_entry():
    build.rectangle((0, "one"), (0, 1), 0.1, rock())


def _block_bool_corner():
    build.block((0, False), (1, 1), 0.1, rock())


def _force_string():
    build.Force("abc")


def _velocity_string():
    build.Velocity("fast")


def _disc_below_spacing():
    build.disc((0, 0), 1e-4, 1e-3, rock())


def _disc_string_centre():
    build.disc("origin", 0.01, 1e-3, rock())


def _ring_radius_string():
    build.ring((0, 0), "a", 0.01, 1e-3, rock())


def _effects_string():
    small_scene(effects="artificial_viscosity")


def _effects_list():
    small_scene(effects=["artificial_viscosity"])


def _effect_parameters_string():
    small_scene(effects={"artificial_viscosity": "alpha=1 alpha=2"})


def _effect_nan_alpha():
    small_scene(effects={"artificial_viscosity": {"alpha": float("nan")}})


def _effect_negative_alpha():
    small_scene(effects={"artificial_viscosity": {"alpha": -1.0}})


def _probe_point_string():
    sphsolid.Probes(small_scene(), {"A": "0.005,0.005"})


def _probe_point_bool():
    sphsolid.Probes(small_scene(), {"A": (True, 0.005)})


def _probe_outside_every_body():
    sphsolid.Probes(small_scene(), {"far": (1.0, 1.0)}).sample()


def _probes_outside_mode():
    sphsolid.Probes(small_scene(), {"A": (0.005, 0.005)}, outside="ignore")


def _lammps_negative_threads():
    from sphsolid.lammps import Lammps
    Lammps(threads=-1)


def _lammps_bool_threads():
    from sphsolid.lammps import Lammps
    Lammps(threads=True)


def _lammps_missing_plugin(tmp_path):
    from sphsolid.lammps import Lammps
    Lammps(plugin=tmp_path / "no_such_plugin.so")


def _builder_that_cannot_fit():
    # 1.6e10 points of a disc at dx = 1 um: refused before numpy allocates
    build.disc((0, 0), 0.07, 1e-6, rock())


def _scene_that_cannot_fit():
    sphsolid.Scene(2, [build.rectangle((-0.043, 0.043), (0, 0.14), 3e-6,
                                       rock())])


def _far_apart_3d():
    a = build.box((0, 0.003), (0, 0.003), (0, 0.003), 1e-3, rock(), name="a")
    b = build.box((1.1e7, 1.1e7 + 0.003), (1.1e7, 1.1e7 + 0.003),
                  (1.1e7, 1.1e7 + 0.003), 1e-3, rock(), name="b")
    sphsolid.Scene(3, [a, b])       # b beyond 1e6 spacings from the origin


def _trajectory_of_old_format(tmp_path):
    path = tmp_path / "old.h5"
    with h5py.File(path, "w") as f:            # format 1 (no version), cut short
        f.create_group("h5md")
        f.create_dataset("particles/all/position/value", data=np.zeros((1, 2, 2)))
    sphsolid.Trajectory(path)


def _trajectory_probes_without_probes(tmp_path):
    sphsolid.Trajectory(tmp_path / "run.h5", "w", small_scene(), probe_interval=5)


def _trajectory_of_old_checkpoint(tmp_path):
    path = tmp_path / "old.h5"
    with h5py.File(path, "w") as f:            # a format-1 checkpoint
        f.create_group("checkpoint")
    sphsolid.Trajectory(path)


def _trajectory_of_newer_format(tmp_path):
    path = tmp_path / "new.h5"
    with h5py.File(path, "w") as f:
        f.attrs["sphsolid_format"] = 7
    sphsolid.Trajectory(path)


def _trajectory_of_a_checkpoint(tmp_path):
    scene = small_scene()
    scene.write_checkpoint(tmp_path / "state.h5")
    sphsolid.Trajectory(tmp_path / "state.h5")


def _damaged_trajectory_frame(tmp_path):
    path = tmp_path / "run.h5"
    scene = small_scene()
    dyn = sphsolid.ImprovedEuler(scene)
    with sphsolid.Trajectory(path, "w", scene) as traj:
        dyn.run(2)
        traj.write()
    # a byte inside the stored chunk of the last frame's positions (the
    # same value may also be stored in earlier frames, elsewhere)
    import h5py
    with h5py.File(path, "r") as f:
        value = f["/particles/all/position/value"]
        chunk = value.id.get_chunk_info_by_coord((value.shape[0] - 1, 0, 0))
    marker = scene.positions[37, 1].tobytes()
    data = bytearray(path.read_bytes())
    at = data.find(marker, chunk.byte_offset,
                   chunk.byte_offset + chunk.size)
    assert at >= 0
    data[at + 6] ^= 0x5F
    path.write_bytes(bytes(data))
    with sphsolid.Trajectory(path) as traj:
        traj[-1]


def _xdmf_of_damaged_times(tmp_path):
    # the XDMF companion lists each frame's time: a damaged time series
    # fails its checksum and no companion is written from it
    path = tmp_path / "run.h5"
    scene = small_scene()
    with sphsolid.Trajectory(path, "w", scene) as traj:
        sphsolid.ImprovedEuler(scene).run(2)
        traj.write()
    with h5py.File(path, "r") as f:
        times = f["/particles/all/position/time"]
        chunk = times.id.get_chunk_info(0)
        stored = times[-1].tobytes()
    data = bytearray(path.read_bytes())
    at = data.find(stored, chunk.byte_offset, chunk.byte_offset + chunk.size)
    assert at >= 0
    data[at + 3] ^= 0x5F
    path.write_bytes(bytes(data))
    sphsolid.trajectory.write_xdmf(path)


def _load_frame_into_another_shape(tmp_path):
    path = tmp_path / "run.h5"
    scene = sphsolid.Scene(2, [build.rectangle((0, 0.02), (0, 0.01), 1e-3, rock())])
    with sphsolid.Trajectory(path, "w", scene):
        pass
    other = sphsolid.Scene(2, [build.rectangle((0, 0.01), (0, 0.02), 1e-3, rock())])
    sphsolid.Trajectory(path).load_into(other)


def _checkpoint_of_another_material(tmp_path):
    small_scene().write_checkpoint(tmp_path / "state.h5")
    other = sphsolid.Scene(2, [build.rectangle(
        (0, 0.01), (0, 0.01), 1e-3, sphsolid.Material(K=1e9, mu=1e9, rho0=2300),
        name="specimen")])
    other.read_checkpoint(tmp_path / "state.h5")


def _checkpoint_of_another_motion(tmp_path):
    small_scene().write_checkpoint(tmp_path / "state.h5")
    other = sphsolid.Scene(2, [small(motion="fixed")])
    other.read_checkpoint(tmp_path / "state.h5")


def _checkpoint_in_missing_directory(tmp_path):
    small_scene().write_checkpoint(tmp_path / "no" / "such" / "state.h5")


PYTHON_CASES = [
    (_material_bool, ValueError, r"K must be a number, got True"),
    (_material_overflow, ValueError, r"E=inf"),
    (_material_string, ValueError, r"K must be a number, got '12e9'"),
    (_material_nan_density, ValueError, r"Material: reference density rho0=nan: must be finite and > 0"),
    (_rectangle_three_x, ValueError, r"rectangle x \(x0, x1\) must have 2 entries, got 3"),
    (_rectangle_string_x, ValueError, r"rectangle x \(x0, x1\) must be a sequence of numbers or quantities such as '1mm', got 'ab'"),
    (_rectangle_string_entry, ValueError, r"rectangle x \(x0, x1\)\[1\]: 'one' is not a number with an optional unit"),
    (_block_bool_corner, ValueError, r"lo\[1\] must be a number or a quantity such as '1mm', got False"),
    (_force_string, ValueError, r"Force.force.*'abc'"),
    (_velocity_string, ValueError, r"Velocity.velocity.*'fast'"),
    (_disc_below_spacing, ValueError, r"disc 'disc' of radius 0.0001 m .*extent 0.0002 along x is less than half of dx=0.001"),
    (_disc_string_centre, ValueError, r"center.*'origin'"),
    (_ring_radius_string, ValueError, r"r_inner.*'a'"),
    (_effects_string, ValueError, r"effects must be a mapping .* got str 'artificial_viscosity'"),
    (_effects_list, ValueError, r"effects must be a mapping .* got list"),
    (_effect_parameters_string, ValueError, r"parameters of effect 'artificial_viscosity' must be a mapping .* 'alpha=1 alpha=2'"),
    (_effect_nan_alpha, ValueError, r"alpha"),
    (_effect_negative_alpha, ValueError, r"alpha=-1"),
    (_probe_point_string, ValueError, r"probe 'A' point must be a sequence of numbers or quantities such as '1mm', got '0.005,0.005'"),
    (_probe_point_bool, ValueError, r"probe 'A' point\[0\] must be a number or a quantity such as '1mm', got True"),
    (_probe_outside_every_body, sphsolid.SimulationError, r"probe 'far' at \(1, 1\) m is outside every body"),
    (_probes_outside_mode, ValueError, r"outside must be 'error' or 'nan', got 'ignore'"),
    (_lammps_negative_threads, ValueError, r"threads must be a positive integer, got -1"),
    (_lammps_bool_threads, ValueError, r"threads must be a positive integer, got True"),
    (_lammps_missing_plugin, OSError, r"plugin '.*no_such_plugin.so' does not exist"),
    (_builder_that_cannot_fit, MemoryError, r"radius 0.07 m .*dx=1e-06 m.*are available"),
    (_scene_that_cannot_fit, MemoryError, r"block 'specimen' \(dx=3e-06 m\).*need about .* are available"),
    (_far_apart_3d, ValueError, r"body 'b': particle 0 at x=1.1e\+07 m lies 1.1e\+10 spacings"),
    (_trajectory_of_old_format, OSError,
     r"old.h5' is a libsphsolid output of file format 1 without /parameters"),
    (_energy_account_no, ValueError, r"energy_account: on must be True or False, got 'no'"),
    (_energy_all_bodies_string, ValueError, r"all_bodies must be True or False, got 'yes'"),
    (_periodic_strings, ValueError, r"periodic\[0\] must be True or False, got 'no'"),
    (_allow_large_string, ValueError, r"allow_large must be True or False, got 'false'"),
    (_allowing_large_none, ValueError, r"allow must be True or False, got None"),
    (_set_dt_allow_unstable_string, ValueError, r"allow_unstable must be True or False, got 'no'"),
    (_trajectory_probes_without_probes, ValueError,
     r"probe interval 5, but there are no probes to sample"),
    (_trajectory_of_old_checkpoint, OSError,
     r"old.h5' is a checkpoint in libsphsolid file format 1 .*not an output"),
    (_trajectory_of_newer_format, OSError, r"new.h5' has libsphsolid file format 7"),
    (_trajectory_of_a_checkpoint, OSError, r"is a libsphsolid checkpoint file, not an output file"),
    (_damaged_trajectory_frame, OSError, r"run.h5' is damaged: /particles/all/position/value fails its checksum"),
    (_xdmf_of_damaged_times, OSError, r"frame times of .*run.h5.: data error detected by Fletcher32 checksum"),
    (_load_frame_into_another_shape, ValueError, r"body 'specimen' spans x in \[.*\] m in the file, \[.*\] m here"),
    (_checkpoint_of_another_material, ValueError, r"material 0 has bulk modulus K = 12200000000 in the file, 1000000000 here"),
    (_checkpoint_of_another_motion, ValueError, r"body 'specimen' has motion 'free' in the file, motion 'fixed' here"),
    (_checkpoint_in_missing_directory, OSError, r"no/such/state.h5.*No such file or directory"),
]


@pytest.mark.parametrize("case, error, message", PYTHON_CASES,
                         ids=[c[0].__name__.strip("_") for c in PYTHON_CASES])
def test_python_bad_input_is_refused_naming_the_value(case, error, message,
                                                      tmp_path):
    import inspect
    if "lammps" in case.__name__ and not sphsolid.lammps.available():
        pytest.skip("LAMMPS is not installed")
    args = (tmp_path,) if inspect.signature(case).parameters else ()
    with pytest.raises(error, match=message):
        case(*args)


def test_probe_outside_can_record_nan_instead():
    probes = sphsolid.Probes(small_scene(), {"far": (1.0, 1.0)}, outside="nan")
    values = probes.sample()["far"]
    assert all(np.isnan(v) for v in values.values())


# ------------------------------------------------------ the sphsolid command
CLI_CASES = [
    (["piston", "--viscosity", "nan"], "--viscosity: 'nan': must be finite and >= 0"),
    (["piston", "--viscosity", "-1"], "--viscosity: '-1': must be finite and >= 0"),
    (["piston", "--speed", "-1"], "--speed: '-1': must be finite and >= 0"),
    (["piston", "--speed", "inf"], "--speed: 'inf': must be finite"),
    (["piston", "--until", "-1ms"], "--until: '-1ms': must be finite and > 0"),
    (["piston", "--until", "0"], "--until: '0': must be finite and > 0"),
    (["piston", "--dx", "nanmm"], "'nanmm'"),
    (["piston", "--dx", "nan"], "--dx: 'nan': must be finite and > 0"),
    (["piston", "--dx", "0.1"], "--dx 100mm leaves the specimen 1 x 1 particles; the kernel needs at least 4 across: use --dx 21.5mm or less"),
    (["piston", "--dx", "3um"], "block 'specimen' (dx=3e-06 m): 1.338e+09 particles"),
    (["piston", "--times", "1ms", "--until", "0.3ms"], "--times 1ms beyond --until 0.3ms"),
    (["piston", "--times", "-1ms"], "--times: '-1ms': must be finite and > 0"),
    (["piston", "--threads", "-1"], "--threads: '-1': must be >= 1"),
    (["piston", "--threads", "100000"], "--threads: '100000': must be <= "),
    (["ucs", "--threads", "100000"], "core"),
    (["ucs", "--seed", "-1"], "--seed: '-1': must be >= 0"),
    (["ucs", "--seed", str(2**53)], "seeds are below 2^53"),
    (["ucs", "--seed", "1e3"], "--seed: '1e3': not a whole number"),
    (["ucs", "--dx", "x" * 5000], "xxx...(5002 characters) is not a number"),
    (["ensemble", "ucs", "--seeds", "3", "--jobs", "100000"], "--jobs: '100000': must be <= "),
    (["piston", "--probe-interval", "0"], "--probe-interval: '0': must be >= 1"),
    (["piston", "--dt", "-1us"], "--dt: '-1us': must be finite and > 0"),
    (["gravity", "--damping", "-5"], "--damping: '-5': must be finite and >= 0"),
    (["info", "no_such_file.h5"], "no_such_file.h5"),
]


@pytest.mark.parametrize("argv, message", CLI_CASES,
                         ids=[" ".join(c[0])[:60] for c in CLI_CASES])
def test_cli_bad_input_exits_naming_the_value(argv, message, tmp_path,
                                              capsys):
    from sphsolid.cli import main
    out = ["--out", str(tmp_path)] if argv[0] != "info" else []
    try:
        code = main(argv + out)
    except SystemExit as exited:          # argparse: status 2
        code = exited.code
    assert code not in (0, None)
    err = capsys.readouterr().err
    assert message in err, err
    assert "Traceback" not in err
    assert not list(tmp_path.glob("*.h5"))      # nothing half written


# ------------- errors while the parser, a scene or a handle is built
#: SPHSOLID_RATE_PATH values sph_create refuses: each reaches the user as
#: one line through the command's handler (it was a traceback: the
#: parser's help asks the library's registries for a handle).
RATE_PATHS = ["sse9", "avx2 ", "x" * 5000, "avx512\nbaseline"]


@pytest.mark.parametrize("value", RATE_PATHS,
                         ids=["sse9", "trailing space", "5000 characters",
                              "line break"])
def test_bad_rate_path_is_one_line_through_the_handler(value, tmp_path,
                                                       capsys, monkeypatch):
    from sphsolid.cli import main
    monkeypatch.setenv("SPHSOLID_RATE_PATH", value)
    code = main(["ucs", "--dx", "4mm", "--max-strain", "0.1%",
                 "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith("sphsolid: error: SPHSOLID_RATE_PATH=") and \
        err.count("\n") == 1, err
    assert len(err) < 300, err          # not echoed in full
    assert not list(tmp_path.glob("*.h5"))


def test_errors_of_the_library_while_running_are_one_line(capsys):
    """Any error of the library (its status as an exception) and an
    unexpected one leave the command as one line with status 2, never a
    traceback."""
    from sphsolid import _lib
    from sphsolid.cli import main, one_line

    def state_error(args):
        _lib.check(_lib.SPH_ERR_STATE, None, "sph_run")

    def bug(args):
        raise TypeError("unsupported operand")

    for run, text in ((state_error, "sphsolid: error: sph_run: "
                       "SPH_ERR_STATE"),
                      (bug, "sphsolid: error: TypeError: unsupported "
                       "operand (an internal "
                       "error; SPHSOLID_TRACEBACK=1 shows where)")):
        import sphsolid.cli.info as info
        original = info.run
        info.run = run
        try:
            assert main(["info", "x.h5"]) == 2
        finally:
            info.run = original
        err = capsys.readouterr().err
        assert err.startswith(text) and err.count("\n") == 1, err
    assert one_line("a\n  b\n" + "y" * 500) == \
        "a b " + "y" * 120 + "...(500 characters)"


def test_bad_rate_path_from_the_shell_has_no_traceback(tmp_path):
    env = dict(os.environ, SPHSOLID_RATE_PATH="sse9")
    run = subprocess.run([sys.executable, "-m", "sphsolid", "ucs", "--dx",
                          "4mm", "--out", str(tmp_path)], env=env,
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, run
    assert run.stderr.count("\n") == 1 and "Traceback" not in run.stderr
    assert "SPHSOLID_RATE_PATH='sse9'" in run.stderr


# --------------------------- the sphsolid command on files and large scenes
PULL = str(ROOT / "examples" / "scene_file" / "pull.toml")
#: files the cases below name as @NAME (made in the test's folder)
FILES = {
    "text.h5": b"not an HDF5 file\n",
    "binary.toml": b"\x00\x01\x02binary",
    "utf16.toml": "dimension = 2\n".encode("utf-16"),
    "zero.toml": b"until = 0\n",
    "both.toml": (ROOT / "examples" / "scene_file" / "pull.toml").read_bytes()
    + b"snapshot_interval = 5\n",
    "array.json": b"[1, 2]",
    "truncated.json": b'{"format": "sphsolid-plan 1", "settings": {"dx": 0.001',
    "old_format.json": b'{"format": 1, "settings": "cubic_spline"}',
}

FILE_CLI_CASES = [
    (["run", "@folder"], "scene file '@folder' is a directory, not a TOML file"),
    (["run", "@missing.toml"], "scene file '@missing.toml': no such file"),
    (["run", "@zero.toml"], "until must be a finite time > 0, got 0"),
    (["run", "@utf16.toml"], "it looks like UTF-16 text"),
    (["run", "@binary.toml"], "binary.toml: not a text file (a NUL byte at 0)"),
    (["run", "@both.toml"], "gives both snapshot_every and snapshot_interval"),
    (["run", PULL, "--threads", "0"], "--threads: '0': must be >= 1"),
    (["run", PULL, "--checkpoint-every", "1ms"],
     "checkpoint_every=0.001 s is longer than the run (to 4e-05 s)"),
    (["run", PULL, "--resume", "@missing.h5"], "No such file or directory"),
    (["run", PULL, "--resume", "@text.h5"], "as an HDF5 file: file signature not found"),
    (["run", PULL, "--plan", "@array.json"], "a plan file holds a JSON object, got a list"),
    (["run", PULL, "--out", "@text.h5"], "output folder '@text.h5': is a file, not a folder"),
    (["piston", "--plan", "@truncated.json"], "truncated.json: not a JSON plan file"),
    (["piston", "--plan", "@missing.json"], "cannot read the plan file"),
    (["piston", "--plan", "@old_format.json"], "'format' is 1; this version reads"),
    (["piston", "--resume", "@text.h5"], "as an HDF5 file: file signature not found"),
    (["piston", "--out", "@text.h5"], "--out @text.h5: is a file, not a folder"),
    (["piston", "--until", "1ms", "--checkpoint-every", "2ms"],
     "checkpoint_every=0.002 s is longer than the run (to 0.001 s)"),
    (["piston", "--dim", "3", "--dx", "10um"], "3.092e+11 particles"),
    (["piston", "--h-over-dx", "-1"], "smoothing ratio h/dx=-1"),
    (["piston", "--integrator", "heun"], "--integrator: invalid choice: 'heun'"),
    (["piston", "--preset", "nosuch"], "--preset: invalid choice: 'nosuch'"),
    (["gravity", "--g", "nan"], "--g: 'nan': must be finite"),
    (["ucs", "--dx", "0"], "--dx: '0': must be finite and > 0"),
    (["brazilian", "--out", "@text.h5"], "--out @text.h5: is a file, not a folder"),
    (["xdmf", "@folder"], "'@folder' is a directory, not an HDF5 output file"),
    (["xdmf", "@text.h5"], "cannot open HDF5 file '@text.h5'"),
    (["info", "@folder"], "cannot read '@folder': it is a directory"),
    (["info", "@text.h5"], "file signature not found"),
]


@pytest.mark.parametrize("argv, message", FILE_CLI_CASES,
                         ids=[" ".join(c[0]).replace(PULL, "pull.toml")
                              for c in FILE_CLI_CASES])
def test_cli_refuses_bad_files_naming_them(argv, message, tmp_path, capsys,
                                           monkeypatch):
    from sphsolid.cli import main
    monkeypatch.chdir(tmp_path)
    (tmp_path / "folder").mkdir()
    for name, content in FILES.items():
        (tmp_path / name).write_bytes(content)
    words = [w.replace("@", "") if w.startswith("@") else w for w in argv]
    if words[0] in ("run", "piston", "gravity", "ucs", "brazilian") and "--out" not in words:
        words += ["--out", "out"]
    try:
        code = main(words)
    except SystemExit as exited:          # argparse: status 2
        code = exited.code
    assert code not in (0, None)
    err = capsys.readouterr().err
    assert message.replace("@", "") in err, err
    assert "Traceback" not in err
    assert not list((tmp_path / "out").glob("*.h5")) if (tmp_path / "out").is_dir() else True


# ---------------------------------------------------- the example program
def _example():
    for candidate in (ROOT / "build" / "examples" / "uniaxial_piston",
                      ROOT / "build" / "examples" / "uniaxial_piston" / "uniaxial_piston"):
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return candidate
    return None


EXAMPLE_CASES = [
    (["--snapshots", "-5"], "--snapshots expects a whole number in [0, 1000000], got '-5'"),
    (["--snapshots", "2.5"], "--snapshots expects a whole number"),
    (["--alpha", "nan"], "--alpha expects a finite number, got 'nan'"),
    (["--alpha", "-1"], "--alpha -1 must be >= 0"),
    (["--threads", "-2"], "--threads expects a whole number in [0, 4096], got '-2'"),
    (["--dx", "abc"], "--dx expects a finite number, got 'abc'"),
    (["--dx", "0"], "--dx 0 mm and --until 0.3 ms must be > 0"),
    (["--until", "inf"], "--until expects a finite number, got 'inf'"),
    (["--dx", "0.003"], "block 'specimen'"),
    (["--out", "no/such/dir/run.h5"], "no/such/dir/run.h5"),
    (["--dx"], "unknown or incomplete option '--dx'"),
    (["--bogus", "1"], "unknown option '--bogus'"),
]


@pytest.mark.parametrize("argv, message", EXAMPLE_CASES,
                         ids=[" ".join(c[0]) for c in EXAMPLE_CASES])
def test_example_program_bad_input_exits_naming_the_value(argv, message,
                                                          tmp_path):
    program = _example()
    if program is None:
        pytest.skip("the example program is not built (build/examples)")
    run = subprocess.run([str(program), *argv, "--quiet"] if argv[-1] != "--dx" else [str(program), *argv],
                         cwd=tmp_path, capture_output=True, text=True,
                         timeout=120)
    assert run.returncode not in (0,) and run.returncode > 0, run
    assert message in run.stderr, run.stderr


# ------------------------------------------------ the LAMMPS backend's state
def test_lammps_backend_refuses_edits_it_would_drop():
    if not sphsolid.lammps.available():
        pytest.skip("LAMMPS is not installed")
    from sphsolid.lammps import Lammps
    scene = small_scene()
    scene.calc = Lammps()
    dyn = sphsolid.ImprovedEuler(scene)
    dyn.run(2)
    scene.velocities[3] = (1.0, 0.0)        # LAMMPS holds the state
    with pytest.raises(ValueError, match=r"cannot take edits of "
                       r"scene.velocities"):
        dyn.run(2)
