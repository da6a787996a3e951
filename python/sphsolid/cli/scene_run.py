"""Running a project scene from the command line (``sphsolid piston``,
``sphsolid gravity``): the scene's setting from the options (or a plan),
the run, its HDF5 file, probe CSV and figures."""
from __future__ import annotations

import os
import sys
import time as wallclock
from dataclasses import dataclass

from .options import output_folder

__all__ = ["Resolved", "resolve", "scene_setting", "planned_scene",
           "run_scene"]

_MIN_ACROSS = 4   # particles across the specimen, at least


@dataclass
class Resolved:
    """What a scene command runs, from its options and its plan (if any):
    spacing, end time, integrator, the number of von Mises maps and the
    plan."""
    name: str
    dx: float
    until: float
    integrator: str
    frames: int
    plan: object = None


def resolve(args, name: str, dx: float, until: float,
            frames: int) -> Resolved:
    """The spacing, end time and integrator of the options, else the
    plan's, else the preset's and the command's defaults."""
    from .. import planner
    from ..presets import preset
    chosen = preset(args.preset or "paper")
    loaded = None
    if args.plan is not None:
        loaded = planner.Plan.load(args.plan)
        if not loaded.feasible:
            raise ValueError(f"{args.plan}: the plan was refused: "
                             f"{loaded.reason}")
        if loaded.scene and loaded.scene != name:
            raise ValueError(f"{args.plan} plans the {loaded.scene!r} "
                             f"scene, not {name!r}")
        dx = loaded.dx
        requested = loaded.request.get("until")
        if requested is not None:
            from ..units import time
            until = time(requested, f"{args.plan}: request.until")
        integrator = loaded.setting.integrator
    else:
        integrator = args.integrator or chosen.integrator
    if args.until is not None:
        until = args.until
    return Resolved(name, dx, until, integrator, frames, loaded)


def check_spacing(dx: float) -> None:
    """The paper's specimen needs a few particles across at dx."""
    from .. import scenes
    spans = [hi - lo for lo, hi in (scenes.SPECIMEN_X, scenes.SPECIMEN_Y)]
    shape = [int(round(s / dx)) for s in spans]
    if min(shape) < _MIN_ACROSS:
        raise ValueError(
            f"--dx {dx * 1e3:g}mm leaves the specimen "
            f"{' x '.join(map(str, shape))} particles; the kernel needs at "
            f"least {_MIN_ACROSS} across: use --dx "
            f"{min(spans) / _MIN_ACROSS * 1e3:.3g}mm or less")


def scene_setting(args) -> dict:
    """The scene builders' keyword arguments of the preset and the
    options that override it."""
    from ..presets import preset
    chosen = preset(args.preset or "paper")
    viscosity = (chosen.viscosity if args.viscosity is None else
                 {"alpha": args.viscosity, "beta": 0.0}
                 if args.viscosity > 0 else None)
    return {"preset": chosen.name, "viscosity": viscosity,
            "kernel": args.kernel, "smoothing_ratio": args.smoothing_ratio,
            "inset": args.inset}


def planned_scene(args, run: Resolved, factory):
    """The scene of ``--plan plan.json`` (its spacing, h/dx, kernel,
    integrator and effects) built with ``factory(dx, **kw)``; ``--threads``
    overrides."""
    loaded = run.plan
    scene = loaded.build(factory, threads=args.threads,
                         calculator=args.backend == "c")
    print(f"plan {args.plan}: {loaded.setting.label()}, dx = "
          f"{loaded.dx * 1e3:.4g} mm; predicted error "
          f"{loaded.predicted_error * 100:.2f} % (at most "
          f"{loaded.error_upper * 100:.2f} %), predicted wall time "
          f"{loaded.predicted_seconds:.3g} s")
    return scene


def _dynamics(args, scene, run: Resolved, dt=None):
    """The run's Dynamics: --dt (else ``dt``: a checkpoint's), else a
    plan's step (its integrator's default times the plan's ``step``), else
    the preset's step when the preset's integrator runs, else the
    integrator's default."""
    from ..dynamics import dynamics_for
    from ..presets import dynamics as preset_dynamics
    dt = args.dt if args.dt is not None else dt
    if run.plan is not None:
        # the plan's integrator at the plan's step
        return run.plan.setting.dynamics(scene, dt=dt,
                                         progress=args.progress)
    chosen = getattr(scene, "preset", None)
    if (dt is None and chosen is not None
            and chosen.integrator == run.integrator):
        return preset_dynamics(scene, chosen, progress=args.progress)
    return dynamics_for(run.integrator)(scene, dt=dt, progress=args.progress)


def run_scene(args, scene, run: Resolved) -> int:
    """Run the scene to ``run.until``, write its HDF5 file (C backend),
    probe CSV and figures into ``--out``; 130 when interrupted."""
    from .. import Probes, scenes
    from ..io.checkpoint import marks, resume
    from ..io.figures import probe_curves, von_mises_map
    from ..metrics import probe_interval_for
    from ..io.trajectory import Frame, Trajectory

    name, dx, until = run.name, run.dx, run.until
    output_folder(args.out)
    if args.backend == "lammps":
        from ..lammps import Lammps
        scene.calc = Lammps(threads=args.threads)
    elif args.threads is not None and not scene.has_calculator:
        from ..calculators import CLibrary
        scene.calc = CLibrary(threads=args.threads)
    probes = Probes(scene, scenes.PAPER_PROBES if scene.dimension == 2
                    else scenes.CYLINDER_PROBES)
    resumed_dt = None
    if args.resume is not None:
        if args.backend != "c":
            raise ValueError("--resume: a checkpoint is read into the C "
                             "library's state (--backend c)")
        resumed_dt = resume(scene, args.resume, run.integrator)
    dyn = _dynamics(args, scene, run, resumed_dt)
    probe_interval = (args.probe_interval if args.probe_interval is not None
                      else probe_interval_for(dyn.dt))
    late = [t for t in (args.times or []) if t > until]
    if late:
        raise ValueError(f"--times {', '.join(f'{t * 1e3:g}ms' for t in late)}"
                         f" beyond --until {until * 1e3:g}ms")
    times = args.times or [until * (i + 1) / run.frames
                           for i in range(run.frames)]
    times = sorted(t for t in times if 0 < t <= until)
    stops = marks(args.checkpoint_every, dyn.time, until)
    checkpoint = args.out / f"{name}_checkpoint.h5"
    counts = scene.body_counts()
    print(f"{name}: dx = {dx * 1e3:g} mm, "
          + ", ".join(f"{k} {v}" for k, v in counts.items())
          + f" particles, {run.integrator}, dt = {dyn.dt * 1e6:.4g} us, "
          f"until {until * 1e3:g} ms ({args.backend} backend)")
    # The library writes the HDF5 file with its own clock, which only the C
    # backend advances; with LAMMPS the field maps come from copies.
    h5 = args.out / f"{name}.h5" if args.backend == "c" else None
    traj = (Trajectory(h5, "w", scene, probe_interval=probe_interval)
            if h5 is not None else None)
    frames = []
    if traj is None:
        dyn.attach(probes, interval=probe_interval)
    # else the library records the probes into the file as it steps (the
    # same samples), so the steps between frames run in one library call
    start, cpu_start = wallclock.perf_counter(), wallclock.process_time()
    interrupted = False
    try:
        for t in sorted(set(times) | set(stops) | {until}):
            if t > dyn.time:
                dyn.run(until=t)
                if t in times:
                    if traj is not None:
                        traj.write()
                    else:
                        frames.append(Frame.from_scene(scene, len(frames)))
                if t in stops:
                    scene.write_checkpoint(checkpoint)
        if traj is None:
            probes.record_final()      # the state at the end time
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
                probes.load(series, interval=probe_interval, final=True)
    print(f"{dyn.nsteps} steps to t = {dyn.time * 1e3:.6g} ms in {wall:.2f} s"
          f" ({len(scene) * dyn.nsteps / max(wall, 1e-9) / 1e6:.3g} M "
          "particle-steps/s)")
    # CPU over wall: ~the threads asked for when they had the cores to
    # themselves; fewer when other jobs took them (then the wall time is
    # not this run's alone)
    print(f"loop CPU time {cpu:.2f} s ({cpu / max(wall, 1e-9):.2f} cores busy"
          f" on average); load average {os.getloadavg()[0]:.2f} at the end")
    planned = run.plan
    if planned is not None and planned.predicted_seconds:
        print(f"the plan predicted {planned.predicted_seconds:.3g} s for this"
              f" run: measured {wall:.3g} s "
              f"({(wall / planned.predicted_seconds - 1) * 100:+.0f} %)"
              + (f"; CPU predicted {planned.predicted_cpu_seconds:.3g} s, "
                 f"measured {cpu:.3g} s ("
                 f"{(cpu / planned.predicted_cpu_seconds - 1) * 100:+.0f} %)"
                 if planned.predicted_cpu_seconds else ""))
    csv = args.out / f"{name}_probes.csv"
    estimate = (None if interrupted or not args.error_estimate
                else _error_estimate(args, probes, planned))
    if estimate is not None:
        estimate.write_csv(csv)
        if h5 is not None:
            estimate.write_hdf5(h5)
    else:
        probes.write_csv(csv)
    outputs = ([h5, traj.xdmf_path] if traj is not None else []) + [csv]
    if stops:
        outputs.append(checkpoint)
    if len(probes.times):
        outputs.append(args.out / f"{name}_probes.png")
        probe_curves(
            probes.times, {n: probes[n]["von_mises"] for n in probes.names},
            outputs[-1],
            title=f"{name}: von Mises stress at probes, dx = "
                  f"{dx * 1e3:g} mm ({args.backend})",
            bands=None if estimate is None else
            {n: estimate.bands[n]["von_mises"] for n in probes.names})
    if traj is not None:
        with Trajectory(h5) as reader:
            frames = [frame for frame in reader if frame.time > 0]
    if frames:
        outputs.append(args.out / f"{name}_von_mises.png")
        von_mises_map(
            frames, outputs[-1], mask=_specimen_mask(scene, dx),
            title=f"{name}: von Mises stress"
                  + (" (mid-plane z = 0)" if scene.dimension == 3 else "")
                  + f", dx = {dx * 1e3:g} mm ({args.backend})")
    for path in outputs:
        print(f"wrote {path}")
    return 130 if interrupted else 0


def _specimen_mask(scene, dx: float):
    """The particles the von Mises maps draw: the specimen's, in 3D those
    of its mid-plane (the lattice layer of least z >= 0)."""
    specimen = [b.name for b in scene.bodies].index("specimen")
    if scene.dimension == 2:
        return lambda f: f.body_ids == specimen
    import numpy as np
    z = scene.positions[scene.body_slice("specimen"), 2]
    z0 = z[z >= -1e-12].min()
    return lambda f: (f.body_ids == specimen) & (
        np.abs(f.positions[:, 2] - z0) < 0.25 * dx)


def _error_estimate(args, probes, planned):
    """``--error-estimate``: shadow runs at 2dx (and 4dx for the order)."""
    if len(probes.times) < 2:
        return None
    from ..planner.estimate import ErrorEstimate
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

