"""One version: project(VERSION) in CMakeLists.txt is what the header,
sph_version(), pkg-config, the CMake package and the Python package say."""
import re
from pathlib import Path

import sphsolid

ROOT = Path(__file__).resolve().parents[2]


def _project_version() -> str:
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(sphsolid VERSION ([0-9.]+)", text).group(1)


def test_python_and_library_report_the_project_version():
    version = _project_version()
    assert sphsolid.version().split()[0] == version
    assert sphsolid.__version__ == version


def test_generated_build_files_carry_the_project_version():
    version = _project_version()
    build = ROOT / "build" / "libsphsolid"
    if not build.is_dir():
        return   # no CMake build tree next to this checkout
    header = (build / "include" / "sphsolid_version.h").read_text()
    major, minor, patch = version.split(".")
    assert f"#define SPHSOLID_VERSION_MAJOR {major}" in header
    assert f"#define SPHSOLID_VERSION_MINOR {minor}" in header
    assert f"#define SPHSOLID_VERSION_PATCH {patch}" in header
    assert f'#define SPHSOLID_VERSION_STRING "{version}"' in header
    assert f"Version: {version}" in (build / "sphsolid.pc").read_text()
    assert f'set(PACKAGE_VERSION "{version}")' in \
        (build / "sphsolidConfigVersion.cmake").read_text()
