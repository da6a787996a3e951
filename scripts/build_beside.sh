# Sourced by compare_probes.sh and compare_throughput.sh.
#
#   build_beside COMMIT WORKDIR TARGET [CMAKE_ARGS...]
#
# Exports COMMIT's sources to WORKDIR/base (once), copies this tree's bench/
# into them (the benchmark programs use the public API only) and builds
# TARGET there (WORKDIR/build-base) and in this tree (WORKDIR/build-head),
# both Release, with CMAKE_ARGS.
build_beside() {
    local base=$1 work=$2 target=$3 side src
    shift 3
    mkdir -p "$work/base"
    [ -f "$work/base/CMakeLists.txt" ] || git archive "$base" | tar -x -C "$work/base"
    cp bench/*.c bench/*.h bench/CMakeLists.txt "$work/base/bench/"
    for side in base head; do
        src=$work/base
        [ "$side" = head ] && src=.
        cmake -S "$src" -B "$work/build-$side" -DCMAKE_BUILD_TYPE=Release \
            -DSPHSOLID_LAMMPS_PLUGIN=OFF -DSPHSOLID_TESTS=OFF -DSPHSOLID_EXAMPLES=OFF \
            -DSPHSOLID_BENCH=ON "$@" >/dev/null
        cmake --build "$work/build-$side" -j2 --target "$target" >/dev/null
    done
}
