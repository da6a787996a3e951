"""Docs and comments point only at files that are in the repository: every
path they name under a top-level folder (docs/, scripts/, tests/, ...) and
every relative Markdown link exists."""
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TOPS = ("docs", "scripts", "tests", "examples", "bench", "validation",
        "libsphsolid", "lammps_plugin", "python")
PATH = re.compile(r"(?<![\w/.-])((?:%s)/[\w./-]*\w)" % "|".join(TOPS))
LINK = re.compile(r"\]\(([^)#\s]+)")
TEXT = re.compile(r"\.(md|rst|py|c|h|cpp|sh|txt|in|toml|cmake)$|(^|/)in\.[\w.]+$")


def _tracked():
    try:
        out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True,
                             text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")
    return out.split()


def _exists(name: str, here: Path, tracked: set) -> bool:
    for base in (ROOT, here):
        target = (base / name).resolve()
        if target.exists():
            return True
        prefix = target.relative_to(ROOT).as_posix() if target.is_relative_to(ROOT) else None
        if prefix and any(t.startswith(prefix) for t in tracked):
            return True
    return False


def test_named_files_exist():
    files = _tracked()
    tracked = set(files)
    missing = []
    for name in files:
        if not TEXT.search(name):
            continue
        path = ROOT / name
        try:
            text = path.read_text()
        except (OSError, UnicodeDecodeError):
            continue
        for match in PATH.finditer(text):
            ref = match.group(1).rstrip(".")
            # generated, globbed or placeholder paths, build trees
            if any(c in ref for c in "*{<$") or "/build" in ref:
                continue
            if not _exists(ref, path.parent, tracked):
                missing.append(f"{name}: {ref}")
        if name.endswith(".md"):
            for match in LINK.finditer(text):
                ref = match.group(1)
                if re.match(r"[a-z]+:", ref):
                    continue
                if not (path.parent / ref).exists():
                    missing.append(f"{name}: link {ref}")
    assert not missing, "references to files not in the repository:\n" + "\n".join(missing)
