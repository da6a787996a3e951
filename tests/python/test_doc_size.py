"""The user docs stay references: scripts/doc_size.sh holds docs/**/*.md
under 5000 lines together and refuses headings that carry a date, a time
of day or the word "issue"."""
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "doc_size.sh"

pytestmark = pytest.mark.skipif(shutil.which("bash") is None, reason="needs bash")


def _run(docs: Path | None = None):
    args = ["bash", str(SCRIPT)] + ([str(docs)] if docs else [])
    return subprocess.run(args, capture_output=True, text=True, timeout=60)


def test_docs_are_under_the_size_limit_with_clean_headings():
    result = _run()
    assert result.returncode == 0, result.stdout + result.stderr
    assert "largest:" in result.stdout


def test_the_script_refuses_a_dated_heading_and_a_long_tree(tmp_path):
    (tmp_path / "a.md").write_text("# Guide\n\n```\n# 2026-01-01 in code is fine\n```\n")
    assert _run(tmp_path).returncode == 0
    (tmp_path / "b.md").write_text("## Fixed in issue 7\n")
    result = _run(tmp_path)
    assert result.returncode == 1 and "b.md:1" in result.stderr
    (tmp_path / "b.md").write_text("line\n" * 5000)
    result = _run(tmp_path)
    assert result.returncode == 1 and "not under 5000" in result.stderr
