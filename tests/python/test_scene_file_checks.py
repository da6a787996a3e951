"""Scene files that do not describe a run are refused with the file and
the key named: no silent acceptance, no traceback."""
import pytest

from sphsolid.cli import main
from sphsolid.scenefile import SceneFileError, load

from scene_texts import block_toml

BASE = block_toml(6, "3mm")


def with_output(lines):
    return BASE.replace("figures = false", "figures = false\n" + lines)


CASES = [
    (BASE.replace('until = "2us"', "until = 0"),
     "until must be a finite time > 0, got 0"),
    (BASE.replace('until = "2us"', 'until = "-1us"'),
     "until must be a finite time > 0, got '-1us'"),
    (with_output('snapshot_every = "-1us"'),
     "output.snapshot_every must be a finite time > 0, got '-1us'"),
    (with_output("snapshot_interval = 0"),
     "output.snapshot_interval must be a whole number >= 1, got 0"),
    (with_output('snapshot_interval = "x"'),
     "output.snapshot_interval must be a whole number >= 1, got 'x'"),
    (with_output("probe_interval = 2.5"),
     "output.probe_interval must be a whole number >= 1, got 2.5"),
    (with_output('probe_interval = "x"'),
     "output.probe_interval must be a whole number >= 1, got 'x'"),
    (with_output('snapshot_every = "1us"\nsnapshot_interval = 2'),
     "gives both snapshot_every and snapshot_interval"),
    (with_output("file = 5"), "output.file must be a non-empty string, got 5"),
    (BASE.replace("figures = false", 'figures = "no"'),
     "output.figures must be true or false, got 'no'"),
    (with_output('probes_csv = "x.csv"'), "unknown key(s) probes_csv"),
    ("smoothing_ratio = -1\n" + BASE,
     "smoothing ratio h/dx=-1: must be in"),
    ('smoothing_ratio = "abc"\n' + BASE,
     "smoothing_ratio must be a number, got 'abc'"),
    ("integrator = 5\n" + BASE, "integrator must be one of"),
    ('dt = "abc"\n' + BASE, "dt: 'abc' is not a number"),
    ("threads = 0\n" + BASE, "threads must be a whole number >= 1, got 0"),
    ('preset = "fast"\n' + BASE, "preset 'fast': known presets are"),
    ("title = 5\n" + BASE, "title must be a non-empty string, got 5"),
    (BASE.replace("dimension = 2", "dimension = 2\ndomain = {lo = [-1, -1], "
                  "hi = [1, 1], periodic = [\"x\", true]}"),
     "domain.periodic[0] must be true or false, got 'x'"),
    (BASE.replace('material = "rock"', 'material = "rock"\nmotion = '
                  '{pressure = "1MPa", direction = ["a", 0]}'),
     "Pressure.direction[0]: 'a' is not a number"),
]


@pytest.mark.parametrize("text, message", CASES,
                         ids=[c[1][:40] for c in CASES])
def test_a_bad_scene_file_names_the_file_and_the_key(text, message,
                                                     tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(SceneFileError) as info:
        load(path)
    assert str(info.value).startswith(str(path))
    assert message in str(info.value)


@pytest.mark.parametrize("content, message", [
    ("\ufeffdimension = 2\n".encode("utf-16"),
     "not a UTF-8 text file (byte 0: b'\\xff'; it looks like UTF-16 text)"),
    (bytes(range(256)), "not a UTF-8 text file"),
    (b"dimension = 2\x00\x00", "not a text file (a NUL byte at 13)"),
])
def test_binary_and_utf16_scene_files_name_the_file(content, message,
                                                    tmp_path, capsys):
    path = tmp_path / "scene.toml"
    path.write_bytes(content)
    assert main(["run", str(path), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}: {message}" in err and "Traceback" not in err


def test_a_directory_as_scene_file_says_so(tmp_path, capsys):
    assert main(["run", str(tmp_path), "--out", str(tmp_path)]) == 2
    assert f"scene file {str(tmp_path)!r} is a directory" in \
        capsys.readouterr().err


def test_until_zero_on_the_command_line_is_refused(tmp_path, capsys):
    path = tmp_path / "ok.toml"
    path.write_text(BASE)
    with pytest.raises(SystemExit):
        main(["run", str(path), "--until", "0"])
    assert "--until: '0': must be finite and > 0" in capsys.readouterr().err
