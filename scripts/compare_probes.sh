#!/usr/bin/env bash
# Compares the probe series of this tree with those of another commit, bit
# for bit: builds bench/probe_series.c against both libraries (the commit's
# sources exported to a temporary folder) and compares the outputs.
#
#   bash scripts/compare_probes.sh [COMMIT] [-- CMAKE_ARGS...]
#
# COMMIT defaults to f631483.  Extra CMake arguments apply to both builds,
# e.g. -DCMAKE_C_FLAGS=-DSPHSOLID_NO_CLONES for the baseline path only.  The
# series run on 1 thread, then on 3 threads for this tree (which must give
# the same bits).  Exit status 0 when all agree.
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:-f631483}
shift || true
[ "${1:-}" = "--" ] && shift
extra=("$@")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/base"
git archive "$base" | tar -x -C "$tmp/base"
cp bench/probe_series.c "$tmp/base/bench/"
grep -q probe_series "$tmp/base/bench/CMakeLists.txt" ||
    printf 'add_executable(probe_series probe_series.c)\ntarget_link_libraries(probe_series PRIVATE sphsolid_static)\n' \
        >>"$tmp/base/bench/CMakeLists.txt"
build() { # source folder, build folder
    cmake -S "$1" -B "$2" -DCMAKE_BUILD_TYPE=Release -DSPHSOLID_LAMMPS_PLUGIN=OFF \
        -DSPHSOLID_TESTS=OFF -DSPHSOLID_EXAMPLES=OFF ${extra[@]+"${extra[@]}"} >/dev/null
    cmake --build "$2" -j2 --target probe_series >/dev/null
}
build "$tmp/base" "$tmp/build-base"
build . "$tmp/build-head"
"$tmp/build-base/bench/probe_series" --threads 1 >"$tmp/base.txt"
"$tmp/build-head/bench/probe_series" --threads 1 >"$tmp/head.txt"
"$tmp/build-head/bench/probe_series" --threads 3 >"$tmp/head3.txt"
status=0
if cmp -s "$tmp/base.txt" "$tmp/head.txt"; then
    echo "compare_probes: $(wc -l <"$tmp/head.txt") series lines bitwise equal to $base"
else
    echo "compare_probes: series differ from $base:"
    diff "$tmp/base.txt" "$tmp/head.txt" | head -20
    status=1
fi
if cmp -s "$tmp/head.txt" "$tmp/head3.txt"; then
    echo "compare_probes: 1 and 3 threads bitwise equal"
else
    echo "compare_probes: 1 and 3 threads differ"
    status=1
fi
exit $status
