"""The house's layout holds: the library's folders include one another as
libsphsolid/src/README.md's table allows, no library file names the LAMMPS
plugin, and the public C symbols and Python names are the stored ones
(tests/data/exported_symbols.txt, tests/data/python_all.txt): moving code
between files and folders changes neither."""
import re
import shutil
import subprocess
from pathlib import Path

import pytest

import sphsolid
from sphsolid import _lib

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "libsphsolid" / "src"
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
