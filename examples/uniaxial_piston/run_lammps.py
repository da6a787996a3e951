#!/usr/bin/env python3
"""The paper's uniaxial piston test through LAMMPS's Python module.

Runs ``in.uniaxial_piston`` (this folder) with the libsphsolid LAMMPS plugin
and plots the von Mises stress at probes A, B and C against time, as the
paper's figures do.

    .venv/bin/python examples/uniaxial_piston/run_lammps.py --dx 0.002 --t-end 3e-4
    .venv/bin/mpirun -np 2 .venv/bin/python examples/uniaxial_piston/run_lammps.py

Writes ``probes_lammps.txt`` (fix ave/time: step, time [s], then for A, B, C
von Mises, pressure, sigma xx yy zz xy [Pa]) and ``probes_lammps.png`` into
--out.  The plugin is found as in lammps_plugin/python/sphsolid_lammps.py
(``SPHSOLID_LAMMPS_PLUGIN`` or the repository's build-lammps/ or build/).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "lammps_plugin" / "python"))

import sphsolid_lammps  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dx", type=float, default=0.002, help="particle spacing [m] (paper: 0.001)")
    parser.add_argument("--t-end", type=float, default=3e-4, help="simulated time [s]")
    parser.add_argument("--alpha", type=float, default=1.0,
                        help="artificial viscosity alpha (beta = 0)")
    parser.add_argument("--every", type=int, default=10, help="steps between probe samples")
    parser.add_argument("--out", type=Path, default=Path("."), help="output folder")
    args = parser.parse_args(argv)

    args.out.mkdir(parents=True, exist_ok=True)
    probes = (args.out / "probes_lammps.txt").resolve()
    plugin = sphsolid_lammps.plugin_path()
    variables = {"plugin": plugin, "dx": args.dx, "t_end": args.t_end, "alpha": args.alpha,
                 "every": args.every, "probes": probes, "thermo_every": 1000}
    cmdargs = ["-log", str((args.out / "log.lammps").resolve()), "-screen", "none", "-nocite"]
    for name, value in variables.items():
        cmdargs += ["-var", name, str(value)]

    lmp = sphsolid_lammps.open_lammps(cmdargs, plugin=plugin)
    rank = lmp.extract_setting("world_rank")
    start = time.perf_counter()
    lmp.file(str(HERE / "in.uniaxial_piston"))
    wall = time.perf_counter() - start
    steps = lmp.extract_global("ntimestep")
    natoms = lmp.get_natoms()
    nranks = lmp.extract_setting("world_size")
    if rank == 0:
        plot(args, probes, natoms, steps, nranks, wall)
    # collective: every rank waits here until rank 0 has plotted
    lmp.finalize()
    return 0


def plot(args, probes: Path, natoms: int, steps: int, nranks: int, wall: float) -> None:

    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = np.loadtxt(probes, ndmin=2)
    t_ms = data[:, 1] * 1e3
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for k, name in enumerate("ABC"):
        ax.plot(t_ms, data[:, 2 + 6 * k] / 1e3, label=f"probe {name}")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("von Mises stress [kPa]")
    ax.set_title(f"Uniaxial piston, LAMMPS plugin, dx = {args.dx * 1e3:g} mm")
    ax.legend()
    fig.tight_layout()
    png = args.out / "probes_lammps.png"
    fig.savefig(png, dpi=120)
    print(f"{natoms} particles, {steps} steps on {nranks} rank(s) in {wall:.2f} s "
          f"({natoms * steps / wall / 1e6:.2f} million particle-steps/s)")
    print("final von Mises A, B, C: "
          + ", ".join(f"{data[-1, 2 + 6 * k]:.6g} Pa" for k in range(3)))
    print(f"wrote {probes} and {png}")


if __name__ == "__main__":
    sys.exit(main())
