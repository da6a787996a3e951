"""The cibuildwheel configuration (pyproject.toml [tool.cibuildwheel])
builds the cluster wheel in the manylinux_2_28 container, once (the wheel
is py3-none), with HDF5, and tests it; the README names the glibc it
needs.  cibuildwheel itself runs only where a container runtime is; where
it is installed, it must accept the configuration."""
from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]


def config() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["cibuildwheel"]


def test_the_wheel_is_built_for_glibc_2_28():
    cibw = config()
    assert cibw["manylinux-x86_64-image"] == "manylinux_2_28"
    assert cibw["manylinux-aarch64-image"] == "manylinux_2_28"
    # one build: the wheel is py3-none, and no musllinux
    assert cibw["build"].endswith("-manylinux_*") and "*" not in cibw["build"].split("-")[0]
    assert "hdf5-devel" in cibw["linux"]["before-all"]
    assert "sphsolid piston" in cibw["test-command"]


def test_the_readme_names_the_glibc():
    readme = (ROOT / "README.md").read_text()
    assert "glibc\n>= 2.28" in readme or "glibc >= 2.28" in readme
    assert "cibuildwheel" in readme


@pytest.mark.skipif(shutil.which("cibuildwheel") is None,
                    reason="cibuildwheel is not installed")
def test_cibuildwheel_accepts_the_configuration():
    done = subprocess.run(["cibuildwheel", "--print-build-identifiers", "--platform",
                           "linux", str(ROOT)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["cp311-manylinux_x86_64"] or \
        all(i.startswith("cp311-manylinux_") for i in done.stdout.split())
