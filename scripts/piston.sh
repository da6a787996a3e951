#!/usr/bin/env bash
# The main job: the paper's uniaxial piston test at a quick default
# resolution (dx = 2 mm, to 0.3 ms), writing the HDF5 file (+ XDMF for
# ParaView), the probe series (CSV) and the figures (PNG) to out/piston/.
# Extra arguments go to `sphsolid piston` (e.g. --dx 1mm --until 5ms).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
.venv/bin/sphsolid piston --dx 2mm --until 0.3ms --out out/piston "$@"
ls -l out/piston
