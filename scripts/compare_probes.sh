#!/usr/bin/env bash
# Compares the probe series of this tree with those of another commit, bit
# for bit: builds bench/probe_series.c against both libraries (the commit's
# sources exported to a temporary folder) and compares the outputs.
#
#   bash scripts/compare_probes.sh [COMMIT] [--bound X] [-- CMAKE_ARGS...]
#
# COMMIT defaults to f631483.  Extra CMake arguments apply to both builds,
# e.g. -DCMAKE_C_FLAGS=-DSPHSOLID_NO_CLONES for the baseline path only.  The
# series run on 1 thread, then on 3 threads for this tree (which must give
# the same bits).  With --bound X the two commits' series need only agree
# to X: every value within X of the largest magnitude its probe (or state
# checksum) reaches in the base's series, as when the two run different
# instruction-set paths of the pair loop (the wide paths fuse multiplies
# and adds).  Exit status 0 when all agree.
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:-f631483}
shift || true
bound=
if [ "${1:-}" = "--bound" ]; then
    bound=${2:?--bound needs a value}
    shift 2
fi
[ "${1:-}" = "--" ] && shift
extra=("$@")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. scripts/build_beside.sh
build_beside "$base" "$tmp" probe_series ${extra[@]+"${extra[@]}"}
"$tmp/build-base/bench/probe_series" --threads 1 >"$tmp/base.txt"
"$tmp/build-head/bench/probe_series" --threads 1 >"$tmp/head.txt"
"$tmp/build-head/bench/probe_series" --threads 3 >"$tmp/head3.txt"
# series of combinations this tree's library refuses before their first
# step (artificial_stress with a kernel that changes sign) have nothing to
# compare: left out of both sides, by label, and named
grep "stopped: effect artificial_stress needs a kernel" "$tmp/head.txt" |
    sed 's/ step [0-9]*: stopped.*//' | sort -u >"$tmp/refused.txt" || true
if [ -s "$tmp/refused.txt" ]; then
    echo "compare_probes: left out, refused by this tree: $(paste -sd ';' "$tmp/refused.txt")"
    for f in base head head3; do
        awk 'NR == FNR { skip[$0] = 1; next }
             { label = $0; sub(/ step [0-9]+:.*/, "", label) }
             !(label in skip)' "$tmp/refused.txt" "$tmp/$f.txt" >"$tmp/$f.kept"
        mv "$tmp/$f.kept" "$tmp/$f.txt"
    done
fi
status=0
if cmp -s "$tmp/base.txt" "$tmp/head.txt"; then
    echo "compare_probes: $(wc -l <"$tmp/head.txt") series lines bitwise equal to $base"
elif [ -n "$bound" ]; then
    python3 scripts/probe_series_bound.py "$tmp/base.txt" "$tmp/head.txt" "$bound" || status=1
else
    echo "compare_probes: series differ from $base:"
    diff "$tmp/base.txt" "$tmp/head.txt" | head -20 || true
    status=1
fi
if cmp -s "$tmp/head.txt" "$tmp/head3.txt"; then
    echo "compare_probes: 1 and 3 threads bitwise equal"
else
    echo "compare_probes: 1 and 3 threads differ"
    status=1
fi
exit $status
