#!/usr/bin/env python3
"""A run past a million particles through LAMMPS on 2 MPI ranks.

The laboratory cylinder (examples/uniaxial_cylinder/in.uniaxial_cylinder)
at the spacing that gives at least --particles particles (default 1 M:
dx = 0.65 mm, 1.17 M with the platens), --steps Improved Euler steps (default
200) under ``mpirun -np 2 lmp``.  Prints the particle count, the loop time,
particle-steps/s per core, LAMMPS's memory per rank ("Per MPI rank memory
allocation", LAMMPS's own arrays) and the peak resident memory of the
largest process (os.wait4 over mpirun's tree: plugin and library included),
and the timing breakdown (Pair, Neigh, Comm, Modify, Output, Other) with
the Comm share.  Run it niced on a shared machine:

    nice -n 10 .venv/bin/python bench/bench_million.py [--dx 0.00065] [--steps 200]
"""
from __future__ import annotations

import argparse
import json
import math
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import bench_lammps as common  # noqa: E402

DECK = HERE.parent / "examples" / "uniaxial_cylinder" / "in.uniaxial_cylinder"
MEMORY = re.compile(r"Per MPI rank memory allocation \(min/avg/max\) = ([0-9.]+) \| ([0-9.]+) \| ([0-9.]+) Mbytes")


def expected_particles(dx: float, D: float = 0.054, L: float = 0.135) -> int:
    """Particles of the cylinder and its platens at spacing dx (the
    library's lattice rule: the lattice points inside the circle, counted
    in integers, times the layers, plus two square platens of
    ceil(2h/dy) layers)."""
    n, ny = round(D / dx), round(L / dx)
    inside = sum(1 for i in range(n) for k in range(n)
                 if (2 * i + 1 - n) ** 2 + (2 * k + 1 - n) ** 2 < n * n)
    layers = math.ceil(2 * 1.2 * dx / (L / ny) - 1e-9)
    return inside * ny + 2 * n * n * layers


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dx", type=float, default=0.00065)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--plugin", type=Path, default=None)
    parser.add_argument("--work", type=Path, default=Path("/tmp/sphsolid-million"))
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    plugin = (args.plugin or common.default_plugin()).resolve()
    print(f"cylinder at dx = {args.dx * 1e3:g} mm: {expected_particles(args.dx)} particles "
          f"expected; {args.steps} steps on {args.ranks} ranks", flush=True)
    machine = common.machine()
    print(f"load average at the start: {machine['load_average']}", flush=True)
    import sphsolid_lammps
    bindir = Path(sys.executable).parent
    mpirun = (sphsolid_lammps.mpi_bin_dir() or bindir) / "mpirun"
    cmd = [str(mpirun), "-np", str(args.ranks), str(bindir / "lmp"), "-in", str(DECK),
           "-log", "log.lammps", "-screen", "none", "-nocite", "-var", "plugin", str(plugin),
           "-var", "dx", repr(args.dx), "-var", "steps", str(args.steps),
           "-var", "every", "50", "-var", "thermo_every", "50"]
    args.work.mkdir(parents=True, exist_ok=True)
    _, figures = common.run_process(cmd, args.work)
    log = args.work / "log.lammps"
    figures.update(common.lammps_figures(log))
    memory = MEMORY.findall(log.read_text())
    figures["lammps_memory_mb_min_avg_max"] = [float(v) for v in memory[-1]] if memory else None
    sections = figures["sections_seconds"]
    total = sum(sections.values())
    n, steps, loop = figures["particles"], figures["steps"], figures["loop_seconds"]
    print(f"particles {n}, steps {steps}, loop {loop:.1f} s, process wall "
          f"{figures['wall_seconds']:.1f} s")
    print(f"particle-steps/s per core: {n * steps / loop / args.ranks / 1e6:.3f} M")
    if memory:
        lo, avg, hi = figures["lammps_memory_mb_min_avg_max"]
        print(f"LAMMPS memory per rank (min/avg/max): {lo:.0f} / {avg:.0f} / {hi:.0f} MB")
    print(f"peak RSS of the largest process: {figures['peak_rss_mb']:.0f} MB "
          f"({figures['peak_rss_mb'] * 2 ** 20 / (n / args.ranks):.0f} B per particle of a rank)")
    print("timing breakdown (average over ranks): " + ", ".join(
        f"{k} {v:.1f} s ({v / total:.1%})" for k, v in sections.items()))
    print(f"comm share: {sections.get('comm', 0.0) / total:.1%}")
    print(f"load average at the end: {common.machine()['load_average']}")
    if args.json:
        args.json.write_text(json.dumps({"command": " ".join(cmd), "dx": args.dx,
                                         "machine_start": machine, **figures}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
