#!/usr/bin/env bash
# Prints a digest of the sources that go into the Python package and its
# wheel: setup.sh reinstalls the package, and test_wheel.sh reuses the
# wheel setup.sh built, only while it is unchanged.
set -euo pipefail
cd "$(dirname "$0")/.."
(cat pyproject.toml CMakeLists.txt; find python libsphsolid lammps_plugin -type f \
    \( -name '*.py' -o -name '*.c' -o -name '*.h' -o -name '*.cpp' -o -name '*.txt' \
       -o -name '*.in' -o -name '*.map' -o -name '*.sh' \) -not -path '*/__pycache__/*' \
    -print0 | sort -z | xargs -0 cat) | sha1sum | cut -d' ' -f1
