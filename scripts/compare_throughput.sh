#!/usr/bin/env bash
# One-thread pair throughput of this tree against another commit, side by
# side: builds bench/bench_piston.c against both libraries (the commit's
# sources exported to a folder kept for reuse) and runs `bench_piston
# --throughput --repeats 1` alternately, REPEATS times each, so that load
# on a shared machine falls on both alike.  Prints each case's median pair
# interactions per CPU second of the process (less sensitive to other load
# than wall seconds) and the ratio head / base, with the range of the
# per-repeat ratios (each head run over the base run beside it).
#
#   bash scripts/compare_throughput.sh [COMMIT] [REPEATS] [-- CMAKE_ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:-f631483}
repeats=${2:-5}
shift $(($# < 2 ? $# : 2))
[ "${1:-}" = "--" ] && shift
extra=("$@")
work=${TMPDIR:-/tmp}/sphsolid-throughput-$(git rev-parse --short "$base")
. scripts/build_beside.sh
build_beside "$base" "$work" bench_piston ${extra[@]+"${extra[@]}"}
: >"$work/runs.txt"
for ((r = 0; r < repeats; ++r)); do
    for side in base head; do
        "$work/build-$side/bench/bench_piston" --throughput --repeats 1 |
            grep "pair interactions/s" | sed "s/^/$side /" >>"$work/runs.txt"
    done
done
head -1 <("$work/build-head/bench/bench_piston" --throughput --repeats 1 | head -1)
awk -v base="$base" '
    { side = $1; key = $2 " " $4 }
    { for (i = 1; i <= NF; ++i) if ($(i) == "(CPU:") { v = $(i + 1); sub(/\)/, "", v) } }
    { n[side, key]++; val[side, key, n[side, key]] = v; keys[key] = 1 }
    function median(side, key,    m, i, j, t, a) {
        m = n[side, key]
        for (i = 1; i <= m; ++i) a[i] = val[side, key, i]
        for (i = 1; i <= m; ++i) for (j = i + 1; j <= m; ++j) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
        return m % 2 ? a[(m + 1) / 2] : 0.5 * (a[m / 2] + a[m / 2 + 1])
    }
    END {
        printf "%-26s %14s %14s %7s %13s     (pair interactions per CPU second, medians of %d)\n", "case", base, "head", "ratio", "per repeat", n["head", "paper improved_euler"]
        for (key in keys) {
            b = median("base", key); h = median("head", key)
            lo = hi = ""
            for (i = 1; i <= n["head", key] && i <= n["base", key]; ++i) {
                r = val["head", key, i] / val["base", key, i]
                if (lo == "" || r < lo) lo = r
                if (hi == "" || r > hi) hi = r
            }
            printf "%-26s %14.4g %14.4g %7.3f %6.2f-%-6.2f\n", key, b, h, h / b, lo, hi
        }
    }' "$work/runs.txt" | sort
