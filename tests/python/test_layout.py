"""The house's layout holds: the library's folders include one another as
libsphsolid/src/README.md's table allows, no library file names the LAMMPS
plugin, and the public C symbols and Python names are the stored ones
(tests/data/exported_symbols.txt, tests/data/python_all.txt): moving code
between files and folders changes neither.  The Python package's
subpackages hold what their docstrings say, its moved module paths still
import, and a Python file over 600 lines says why at its top."""
import importlib
import re
import sys
import shutil
import subprocess
from pathlib import Path

import pytest

import sphsolid
from sphsolid import _lib

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "libsphsolid" / "src"
PACKAGE = Path(sphsolid.__file__).resolve().parent
LONG = 600
DATA = Path(__file__).resolve().parents[1] / "data"

needs_tree = pytest.mark.skipif(not SRC.is_dir(), reason="no source tree")


def allowed_includes() -> dict:
    """{folder: set of folders or headers it may include}, from the README."""
    text = (SRC / "README.md").read_text()
    table = text[text.index("| folder | may include |"):]
    allowed = {}
    for row in re.findall(r"^\| `(\w+)` \| (.*) \|$", table, re.M):
        folder, cells = row
        allowed[folder] = set(re.findall(r"`([\w/.]+)`", cells))
    return allowed


@needs_tree
def test_folders_include_only_what_the_readme_allows():
    allowed = allowed_includes()
    folders = sorted(p.name for p in SRC.iterdir() if p.is_dir())
    assert sorted(allowed) == folders
    wrong = []
    for folder in folders:
        for path in sorted((SRC / folder).glob("*.[ch]")):
            for header in re.findall(r'^#include "(\w+)/([\w.]+)"',
                                     path.read_text(), re.M):
                target, name = header
                if target == folder or target == "sphsolid":
                    continue
                ok = allowed[folder]
                if target not in ok and f"{target}/{name}" not in ok:
                    wrong.append(f"{path.relative_to(SRC)} includes "
                                 f"{target}/{name}")
    assert not wrong, wrong


@needs_tree
def test_no_library_file_names_the_plugin():
    plugin = ROOT / "lammps_plugin"
    names = set()
    for header in plugin.glob("*.h"):
        names |= set(re.findall(r"^class (\w+)", header.read_text(), re.M))
    names |= {p.stem for p in plugin.glob("*.cpp")}
    assert names
    found = []
    for path in SRC.rglob("*.[ch]"):
        text = path.read_text()
        found += [f"{path.relative_to(SRC)}: {n}" for n in sorted(names)
                  if re.search(rf"\b{n}\b", text)]
    assert not found, found


def test_exported_c_symbols_are_the_stored_list():
    nm = shutil.which("nm")
    if nm is None:
        pytest.skip("no nm")
    out = subprocess.run([nm, "-D", "--defined-only", str(_lib.library_path())],
                         capture_output=True, text=True, check=True).stdout
    symbols = sorted(line.split()[-1] for line in out.splitlines()
                     if line.split() and line.split()[-1].startswith("sph_"))
    stored = (DATA / "exported_symbols.txt").read_text().split()
    assert symbols == stored


def test_python_public_names_are_the_stored_list():
    stored = (DATA / "python_all.txt").read_text().split()
    assert sorted(sphsolid.__all__) == stored
    for name in stored:
        assert hasattr(sphsolid, name), name


def _modules(folder: Path) -> set:
    return {p.stem for p in folder.glob("*.py") if p.stem != "__init__"}


@pytest.mark.parametrize("name", ["io", "fracture", "planner"])
def test_each_subpackage_holds_the_modules_its_docstring_names(name):
    package = importlib.import_module(f"sphsolid.{name}")
    named = set(re.findall(r":mod:`\.(\w+)`", package.__doc__))
    assert named == _modules(PACKAGE / name), (
        f"sphsolid.{name}: named but absent {sorted(named - _modules(PACKAGE / name))}, "
        f"present but not named {sorted(_modules(PACKAGE / name) - named)}")


def test_the_cli_holds_its_commands_and_the_helpers_it_names():
    from sphsolid import cli
    commands = {m.__name__.rsplit(".", 1)[-1] for m in cli.COMMANDS}
    helpers = set(re.findall(r"``(\w+)\.py``", cli.__doc__))
    assert commands | helpers == _modules(PACKAGE / "cli")
    assert not commands & helpers


def test_the_top_level_is_the_core_front_end():
    # what moved to io/ and fracture/ is not at the top again
    top = _modules(PACKAGE)
    for name in ("io", "fracture"):
        assert not top & _modules(PACKAGE / name), name
    assert {"scene", "material", "builders", "calculators", "dynamics",
            "units", "_lib"} <= top


def test_old_module_paths_import_the_moved_modules():
    from sphsolid import _moved
    for old, new in _moved.MOVED.items():
        relative = old.split(".")[1:]
        assert not (PACKAGE.joinpath(*relative[:-1]) / f"{relative[-1]}.py").exists(), old
        module = importlib.import_module(old)
        assert module is importlib.import_module(new) is sys.modules[old], old
        assert module.__name__ == new and module.__spec__.name == new, old
    # the names users reach through the old paths
    from sphsolid.build import block
    from sphsolid.trajectory import Trajectory
    assert block is sphsolid.block and Trajectory is sphsolid.Trajectory
    assert sphsolid.trajectory.Frame is sys.modules["sphsolid.io.trajectory"].Frame
    # sphsolid.ensemble stays the callable entry, its module importable
    importlib.import_module("sphsolid.ensemble")
    assert callable(sphsolid.ensemble) and not isinstance(sphsolid.ensemble,
                                                         type(sys))
    assert sphsolid.fracture.load_to_break is sphsolid.fracture.specimens.load_to_break


def _tracked_python_files():
    try:
        out = subprocess.run(["git", "ls-files", "*.py"], cwd=ROOT,
                             capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")
    return [ROOT / name for name in out.split()]


def test_a_python_file_over_600_lines_says_why_at_its_top():
    unexplained = []
    for path in _tracked_python_files():
        lines = path.read_text().splitlines()
        if len(lines) <= LONG:
            continue
        first = lines[0] if lines else ""
        reason = first.removeprefix(f"# Over {LONG} lines:").strip()
        if first == reason or len(reason) < 20:
            unexplained.append(f"{path.relative_to(ROOT)} ({len(lines)} lines)")
    assert not unexplained, unexplained
