#!/usr/bin/env python3
"""3D benchmark: the laboratory cylinder (D = 54 mm, L = 135 mm) at 2 mm and
1 mm, library vs plugin (1 and 2 ranks) vs MACHDYN smd/ulsph, side by side.

For each spacing, one invocation runs each of

  library   libsphsolid alone (sph_add_cylinder, sph_add_plate,
            sph_add_piston, its own neighbour search and Improved Euler), 1
            OpenMP thread, probes A-D sampled every 10 steps;
  plugin-1  examples/uniaxial_cylinder/in.uniaxial_cylinder in ``lmp``, 1 rank;
  plugin-2  the same deck under ``mpirun -np 2``;
  library-leapfrog, plugin-1-leapfrog
            the library and the deck (``-var integrator leapfrog``, 1 rank)
            with the leapfrog at its default step h/c0;
  smd       bench/in.smd_ulsph_cylinder: smd/ulsph on the same particles,
            time step and piston, ``lmp`` on 1 rank;

each in its own process with OMP_NUM_THREADS=1, the cases interleaved within
each repeat.  It prints per case: particle-steps/s per core (all particles
times steps over the loop time, divided by the ranks), pair interactions/s
per core (the library's neighbour pairs within 2h, counted once, times two
rate evaluations per step; smd/ulsph evaluates once per step, so its count
is half), loop and process times, peak resident memory, and bytes per
particle: the library's own sph_memory_bytes(), and for every case the
marginal peak RSS between the two spacings, (RSS_1mm - RSS_2mm) /
(N_1mm - N_2mm), which removes the fixed cost of the interpreter and
LAMMPS.  Medians over --repeats.  For each plugin case on one rank, where
its loop goes (pair sphsolid's timers, as in bench_lammps.py) against the
library case with the same integrator.

    .venv/bin/python bench/bench_cylinder3d.py [--fine] [--dxs 0.002] [--steps 20]
        [--repeats 3] [--skip smd] [--json out.json]

The default run times every case at 2 mm (a few minutes on a free
machine) and reports the library's bytes per particle at 2 mm and 1 mm
(sph_memory_parts, from a 2-step run at 1 mm); --fine also times every
case at 1 mm and adds the marginal peak RSS between the spacings.  It
prints the command it was run with.
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import bench_lammps as common  # noqa: E402

REPOSITORY = HERE.parent
DECK = REPOSITORY / "examples" / "uniaxial_cylinder" / "in.uniaxial_cylinder"
SMD_DECK = HERE / "in.smd_ulsph_cylinder"
CASES = ("library", "plugin-1", "plugin-2", "smd", "library-leapfrog", "plugin-1-leapfrog")
PROBE_EVERY = 10


def library_worker(library: Path, dx: float, steps: int,
                   integrator: str = "improved_euler") -> dict:
    """The cylinder scene on the library alone, in this process."""
    import ctypes
    from ctypes import POINTER, byref, c_char_p, c_double, c_int, c_long, c_void_p
    lib = ctypes.CDLL(str(library))
    lib.sph_create.argtypes = [c_int, POINTER(c_void_p)]
    lib.sph_set_threads.argtypes = [c_void_p, c_int]
    lib.sph_add_material_K_mu.argtypes = [c_void_p, c_double, c_double, c_double, POINTER(c_int)]
    lib.sph_add_cylinder.argtypes = [c_void_p, c_char_p, c_int, POINTER(c_double), c_double,
                                     c_double, c_double, POINTER(c_int)]
    lib.sph_add_plate.argtypes = [c_void_p, c_char_p, c_int, c_int, c_int, POINTER(c_int)]
    lib.sph_add_piston.argtypes = [c_void_p, c_char_p, c_int, c_int, c_int, c_double,
                                   POINTER(c_int)]
    lib.sph_add_probe.argtypes = [c_void_p, c_char_p, POINTER(c_double), POINTER(c_int)]
    lib.sph_effect.argtypes = [c_void_p, c_char_p, c_char_p]
    lib.sph_set_integrator.argtypes = [c_void_p, c_char_p]
    lib.sph_run.argtypes = [c_void_p, c_long]
    lib.sph_probe_sample.argtypes = [c_void_p, c_int, POINTER(c_double)]
    lib.sph_particle_count.argtypes = [c_void_p]
    lib.sph_particle_count.restype = ctypes.c_size_t
    lib.sph_memory_bytes.argtypes = [c_void_p]
    lib.sph_memory_bytes.restype = ctypes.c_size_t
    lib.sph_field.argtypes = [c_void_p, c_int, POINTER(POINTER(c_double)),
                              POINTER(ctypes.c_size_t), POINTER(ctypes.c_size_t)]
    lib.sph_smoothing_length.argtypes = [c_void_p]
    lib.sph_smoothing_length.restype = c_double
    lib.sph_errmsg.argtypes = [c_void_p]
    lib.sph_errmsg.restype = c_char_p
    lib.sph_memory_parts.argtypes = [c_void_p, POINTER(c_char_p), POINTER(ctypes.c_size_t),
                                     c_int]
    sim = c_void_p()

    def check(status):
        if status != 0:
            raise RuntimeError(lib.sph_errmsg(sim).decode())

    check(lib.sph_create(3, byref(sim)))
    check(lib.sph_set_threads(sim, 1))
    rock, specimen, plate, piston = c_int(), c_int(), c_int(), c_int()
    check(lib.sph_add_material_K_mu(sim, 12.2e9, 2.67e9, 2300.0, byref(rock)))
    base = (c_double * 3)(0.0, 0.0, 0.0)
    D, L = 0.054, 0.135
    check(lib.sph_add_cylinder(sim, b"specimen", rock, base, D / 2, L, dx, byref(specimen)))
    check(lib.sph_add_plate(sim, b"plate", -1, specimen, 0, byref(plate)))
    check(lib.sph_add_piston(sim, b"piston", -1, specimen, 0, 1.5e-3, byref(piston)))
    check(lib.sph_effect(sim, b"artificial_viscosity", b"alpha=1 beta=0"))
    check(lib.sph_set_integrator(sim, integrator.encode()))
    points = [(0, L / 2, 0), (D / 4, 0.75 * L, 0), (D / 4, L / 2, 0), (0, 0.75 * L, 0)]
    for k, p in enumerate(points):
        check(lib.sph_add_probe(sim, f"{'ABCD'[k]}".encode(), (c_double * 3)(*p), None))
    n = int(lib.sph_particle_count(sim))
    values = (c_double * 8)()
    start, start_cpu = time.perf_counter(), time.process_time()
    done = 0
    while done < steps:
        chunk = min(PROBE_EVERY, steps - done)
        check(lib.sph_run(sim, chunk))
        done += chunk
        if done % PROBE_EVERY == 0:
            for k in range(4):
                check(lib.sph_probe_sample(sim, k, values))
    loop, loop_cpu = time.perf_counter() - start, time.process_time() - start_cpu
    # pairs within the support 2h at the end (what the rate loop evaluates)
    data = POINTER(c_double)()
    check(lib.sph_field(sim, 0, byref(data), None, None))
    import numpy as np
    x = np.ctypeslib.as_array(data, shape=(n, 3)).copy()
    pairs = count_pairs(x, 2.0 * lib.sph_smoothing_length(sim))
    names, sizes = (c_char_p * 16)(), (ctypes.c_size_t * 16)()
    parts = lib.sph_memory_parts(sim, names, sizes, 16)
    return {"loop_seconds": loop, "loop_cpu_seconds": loop_cpu, "steps": steps,
            "particles": n, "memory_bytes": int(lib.sph_memory_bytes(sim)), "pairs": pairs,
            "memory_parts": {names[k].decode(): int(sizes[k]) for k in range(parts)}}


def count_pairs(x, cutoff: float) -> int:
    """Unordered pairs closer than `cutoff` (scipy's k-d tree if there is
    one, else cell lists in numpy)."""
    import numpy as np
    try:
        from scipy.spatial import cKDTree
        tree = cKDTree(x)
        return int((tree.count_neighbors(tree, cutoff * (1 - 1e-12)) - len(x)) // 2)
    except ImportError:
        pass
    cells = np.floor((x - x.min(axis=0)) / cutoff).astype(np.int64)
    keys = {}
    for i, c in enumerate(map(tuple, cells)):
        keys.setdefault(c, []).append(i)
    total = 0
    offsets = [(a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)]
    for c, members in keys.items():
        mine = x[members]
        for o in offsets:
            other = keys.get((c[0] + o[0], c[1] + o[1], c[2] + o[2]))
            if other is None:
                continue
            d = mine[:, None, :] - x[other][None, :, :]
            total += int(((d ** 2).sum(axis=2) < cutoff * cutoff).sum())
    return (total - len(x)) // 2


def run_case(case: str, dx: float, args, work: Path) -> dict:
    work.mkdir(parents=True, exist_ok=True)
    bindir = Path(sys.executable).parent
    lmp = [str(bindir / "lmp"), "-log", "log.lammps", "-screen", "none", "-nocite"]
    variables = ["-var", "dx", repr(dx), "-var", "steps", str(args.steps)]
    integrator = "leapfrog" if case.endswith("leapfrog") else "improved_euler"
    if case.startswith("library"):
        cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", "--library",
               str(args.library), "--dxs", repr(dx), "--steps", str(args.steps),
               "--integrator", integrator]
        _, figures = common.run_process(cmd, work)
        figures.update(json.loads((work / "stdout.txt").read_text().strip().splitlines()[-1]))
        figures["ranks"] = 1
        return figures
    if case.startswith("plugin"):
        ranks = 2 if case == "plugin-2" else 1
        cmd = lmp + ["-in", str(DECK), "-var", "plugin", str(args.plugin),
                     "-var", "probes", "probes.txt", "-var", "integrator", integrator] + variables
        if ranks > 1:
            import sphsolid_lammps
            mpirun = (sphsolid_lammps.mpi_bin_dir() or bindir) / "mpirun"
            cmd = [str(mpirun), "-np", str(ranks)] + cmd
    else:
        cmd = lmp + ["-in", str(SMD_DECK)] + variables
    _, figures = common.run_process(cmd, work)
    figures.update(common.lammps_figures(work / "log.lammps"))
    return figures


LABELS = {"library": "library, 1 thread", "plugin-1": "plugin, 1 rank",
          "plugin-2": "plugin, mpirun -np 2", "smd": "smd/ulsph, 1 rank",
          "library-leapfrog": "library leapfrog", "plugin-1-leapfrog": "plugin leapfrog, 1 r."}


def report(summary: dict, pairs: dict, memory: dict, args) -> str:
    lines = [f"3D cylinder D = 54 mm, L = 135 mm, {args.steps} steps; medians of "
             f"{args.repeats} repeats; OMP_NUM_THREADS=1",
             f"{'dx [mm]':>7} {'case':<22}{'particles':>10}{'Mpart-steps/s/core':>20}"
             f"{'Mpairs/s/core':>15}{'per CPU-s':>11}{'loop [s]':>10}{'wall [s]':>10}"
             f"{'peak RSS [MB]':>15}",
             "  (per CPU-s: million particle-steps per second of the loop's CPU time,"
             " all ranks; the figure to read on a loaded machine)"]
    for dx in args.dxs:
        for case in CASES:
            s = summary.get((dx, case))
            if not s:
                continue
            ranks = s.get("ranks", 1)
            # the leapfrog's two passes make one evaluation's pair terms
            evaluations = 1 if case == "smd" or case.endswith("leapfrog") else 2
            per_core = s["particles"] * s["steps"] / s["loop_seconds"] / ranks
            pair_rate = pairs.get(dx, float("nan")) * evaluations * s["steps"] / s["loop_seconds"] / ranks
            per_cpu = s["particles"] * s["steps"] / (s["loop_cpu_seconds"] * ranks)
            lines.append(f"{dx * 1e3:>7g} {LABELS[case]:<22}{s['particles']:>10d}"
                         f"{per_core / 1e6:>20.3f}{pair_rate / 1e6:>15.2f}{per_cpu / 1e6:>11.3f}"
                         f"{s['loop_seconds']:>10.2f}{s['wall_seconds']:>10.2f}"
                         f"{s['peak_rss_mb']:>15.1f}")
    lines.append("ratios (loop times):")
    for dx in args.dxs:
        def get(case):
            return summary.get((dx, case), {}).get("loop_seconds")
        lib, p1, p2, smd, lib_lf, p1_lf = (get(c) for c in CASES)
        if lib and p1:
            lines.append(f"  {dx * 1e3:g} mm  plugin 1 rank / library       {p1 / lib:6.3f}")
        for name, plugin, alone in (("", "plugin-1", "library"),
                                    (" leapfrog", "plugin-1-leapfrog", "library-leapfrog")):
            a, b = summary.get((dx, plugin)), summary.get((dx, alone))
            if a and b:
                lines.append(f"  {dx * 1e3:g} mm  plugin{name} 1 rank / library{name} (loop CPU) "
                             f"{a['loop_cpu_seconds'] / b['loop_cpu_seconds']:6.3f}"
                             "   (target <= 1.05)")
        if p1 and p2:
            lines.append(f"  {dx * 1e3:g} mm  plugin 1 rank / 2 ranks       {p1 / p2:6.3f}"
                         "   (target >= 1.8)")
        if smd and p1:
            lines.append(f"  {dx * 1e3:g} mm  smd/ulsph / plugin 1 rank     {smd / p1:6.3f}")
    for dx in args.dxs:
        by_case = {case: s for (d, case), s in summary.items() if d == dx}
        parts = common.plugin_parts(by_case, 2, LABELS)
        if len(parts) > 1:
            lines += [f"{dx * 1e3:g} mm, " + parts[0]] + parts[1:]
    lines.append("bytes per particle (library, sph_memory_parts / particles, after the "
                 "first steps):")
    for dx in sorted(memory, reverse=True):
        m = memory[dx]
        n = m["particles"]
        parts = ", ".join(f"{k} {v / n:.0f}" for k, v in m["memory_parts"].items())
        lines.append(f"  {dx * 1e3:g} mm  {m['memory_bytes'] / n:.0f}   (target <= 600)   "
                     f"[{parts}]")
    if len(args.dxs) >= 2:
        a, b = sorted(args.dxs)[-1], sorted(args.dxs)[0]
        for case in CASES:
            sa, sb = summary.get((a, case)), summary.get((b, case))
            if sa and sb and sb["particles"] != sa["particles"]:
                marginal = ((sb["peak_rss_mb"] - sa["peak_rss_mb"]) * 2 ** 20
                            / (sb["particles"] - sa["particles"]))
                note = " (largest rank; x2 for both ranks)" if case == "plugin-2" else ""
                lines.append(f"  {LABELS[case]:<22} marginal peak RSS {a * 1e3:g} -> "
                             f"{b * 1e3:g} mm: {marginal:.0f} B/particle{note}")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dxs", type=float, nargs="+", default=[0.002],
                        help="spacings timed side by side [m] (default 2 mm)")
    parser.add_argument("--fine", action="store_true",
                        help="also time every case at 1 mm (about 330,000 particles; "
                        "some 10 minutes more on a free machine)")
    parser.add_argument("--memory-dxs", type=float, nargs="+", default=[0.002, 0.001],
                        help="spacings whose library memory per particle is reported "
                        "(a 2-step library run where a spacing is not timed)")
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--plugin", type=Path, default=None)
    parser.add_argument("--library", type=Path, default=None)
    parser.add_argument("--skip", action="append", default=[], choices=CASES)
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--keep", type=Path, default=None)
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--integrator", default="improved_euler", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        print(json.dumps(library_worker(args.library, args.dxs[0], args.steps,
                                        args.integrator)))
        return 0
    if args.fine and 0.001 not in args.dxs:
        args.dxs.append(0.001)
    command = " ".join([Path(sys.executable).name, "bench/bench_cylinder3d.py"]
                       + (argv if argv is not None else sys.argv[1:]))
    print(f"command: {command}", flush=True)
    args.plugin = (args.plugin or common.default_plugin()).resolve()
    if args.library is None:
        args.library = args.plugin.parent.parent / "libsphsolid" / "libsphsolid.so"
    cases = [c for c in CASES if c not in args.skip]
    start_machine = common.machine()
    print(f"machine: {start_machine['cpu']}, {start_machine['cores']} cores, load average "
          f"{', '.join(f'{x:.2f}' for x in start_machine['load_average'])} (shared)", flush=True)
    results = {(dx, c): [] for dx in args.dxs for c in cases}
    with tempfile.TemporaryDirectory(prefix="bench_cyl3d_") as tmp:
        root = args.keep or Path(tmp)
        for r in range(args.repeats):
            for dx in args.dxs:
                for case in cases:
                    figures = run_case(case, dx, args, root / f"{dx}-{case}-{r}")
                    results[(dx, case)].append(figures)
                    print(f"  repeat {r + 1}/{args.repeats} {dx * 1e3:g} mm {case:<9} loop "
                          f"{figures['loop_seconds']:7.2f} s  loop CPU "
                          f"{figures['loop_cpu_seconds']:7.2f} s  peak RSS "
                          f"{figures['peak_rss_mb']:7.1f} MB", flush=True)
    summary = {}
    for key, rows in results.items():
        if not rows:
            continue
        s = {k: statistics.median(r[k] for r in rows) for k in
             ("loop_seconds", "loop_cpu_seconds", "wall_seconds", "cpu_seconds",
              "peak_rss_mb")}
        for k in ("steps", "particles", "ranks", "memory_bytes", "pairs"):
            if k in rows[0]:
                s[k] = rows[0][k]
        if "sections_seconds" in rows[0]:
            s["sections_seconds"] = {name: statistics.median(r["sections_seconds"][name]
                                                             for r in rows)
                                     for name in rows[0]["sections_seconds"]}
        if rows[0].get("plugin_parts_seconds"):
            s["plugin_parts_seconds"] = {
                name: statistics.median(r["plugin_parts_seconds"][name] for r in rows)
                for name in common.PART_NAMES}
        summary[key] = s
    pairs = {dx: summary[(dx, "library")]["pairs"] for dx in args.dxs
             if (dx, "library") in summary}
    memory = {dx: results[(dx, "library")][0] for dx in args.dxs
              if results.get((dx, "library"))}
    with tempfile.TemporaryDirectory(prefix="bench_cyl3d_mem_") as tmp:
        for dx in args.memory_dxs:
            if dx not in memory:
                work = Path(tmp) / f"{dx}"
                work.mkdir()
                cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", "--library",
                       str(args.library), "--dxs", repr(dx), "--steps", "2"]
                common.run_process(cmd, work)
                memory[dx] = json.loads((work / "stdout.txt").read_text().strip().splitlines()[-1])
    text = report(summary, pairs, memory, args)
    print(text)
    print(f"command: {command}")
    end_machine = common.machine()
    print(f"load average at the end: {', '.join(f'{x:.2f}' for x in end_machine['load_average'])}")
    if args.json:
        args.json.write_text(json.dumps({
            "command": command,
            "memory": {str(dx): m for dx, m in memory.items()},
            "machine_start": start_machine, "machine_end": end_machine,
            "summary": {f"{dx}/{case}": s for (dx, case), s in summary.items()},
            "results": {f"{dx}/{case}": r for (dx, case), r in results.items()}}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
