"""SPH runs of the 3D laboratory cylinder for the 3D validation.

Each run is sphsolid.scenes.uniaxial_cylinder at one spacing, sampled at
probes on the axis (the P-wave arrival, the centre's axial stress) and off
it, saved as an .npz that cylinder_3d.py reads (a run is reused when its
file exists with the same parameters).

    python validation/cylinder_3d_runs.py --dx 2mm --until 4ms --out DIR
"""
from __future__ import annotations

import argparse
import json
import time as wallclock
from pathlib import Path

import numpy as np

#: Depths below the piston face of the axis probes [m].
AXIS_DEPTHS = (0.010, 0.020, 0.030, 0.040, 0.050, 0.0675)


def probe_points(length: float, diameter: float) -> dict:
    points = {f"axis_{round(d * 1e3):g}mm": (0.0, length - d, 0.0)
              for d in AXIS_DEPTHS}
    points["centre"] = (0.0, length / 2, 0.0)
    points["off_axis_mid"] = (diameter / 4, length / 2, 0.0)
    points["off_axis_upper"] = (diameter / 4, 0.75 * length, 0.0)
    return points


def run_file(out: Path, dx: float, until: float, corrected: bool = False,
             inset=0.0, integrator: str = "improved_euler") -> Path:
    tag = "_kc" if corrected else ""
    if inset != 0.0:
        tag += f"_inset{inset}" if isinstance(inset, str) else f"_inset{inset:g}"
    if integrator != "improved_euler":
        tag += f"_{integrator}"
    return Path(out) / f"cylinder_dx{dx * 1e3:g}mm_{until * 1e3:g}ms{tag}.npz"


def run(dx: float, until: float, out: Path, every: int = 5,
        threads: int = 1, log=print, corrected: bool = False,
        inset=0.0, integrator: str = "improved_euler") -> Path:
    """Run the cylinder at spacing dx to time `until`; returns the .npz.
    ``corrected`` switches the kernel-gradient correction effect on;
    ``inset`` lays plate and piston that many lattice steps closer to the
    specimen ("static": the library's static inset,
    sph_static_platen_inset); ``integrator`` is a library integrator name."""
    from sphsolid import Probes, scenes
    from sphsolid.calculators import CLibrary
    from sphsolid.dynamics import dynamics_for

    path = run_file(out, dx, until, corrected, inset, integrator)
    if path.exists():
        return path
    scene = scenes.uniaxial_cylinder(dx, inset=inset)
    inset_steps = scene.static_platen_inset()[0] if inset == "static" else float(inset)
    if corrected:
        scene.effect("kernel_correction")
    scene.calc = CLibrary(threads=threads)
    points = probe_points(scenes.CYLINDER_LENGTH, scenes.CYLINDER_DIAMETER)
    probes = Probes(scene, points)
    dyn = dynamics_for(integrator)(scene)
    dyn.attach(probes, interval=every)
    start = wallclock.perf_counter()
    log(f"cylinder dx = {dx * 1e3:g} mm: {len(scene)} particles, dt = "
        f"{dyn.dt * 1e6:.4g} us, until {until * 1e3:g} ms")
    dyn.run(until=until)
    wall = wallclock.perf_counter() - start
    if not len(probes.times) or probes.steps[-1] != dyn.nsteps:
        probes.record()
    names = list(points)
    sigma_yy = np.array([probes[n]["sigma_yy"] for n in names])
    von_mises = np.array([probes[n]["von_mises"] for n in names])
    Path(out).mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, times=np.asarray(probes.times), names=np.array(names),
             points=np.array([points[n] for n in names]),
             sigma_yy=sigma_yy, von_mises=von_mises,
             meta=json.dumps({"dx": dx, "until": until, "particles": len(scene),
                              "counts": scene.body_counts(), "dt": dyn.dt,
                              "steps": dyn.nsteps, "wall_s": wall,
                              "h": scene.h, "effects": scene.effects,
                              "inset": inset, "integrator": integrator,
                              "inset_steps": inset_steps}))
    tmp.replace(path)
    log(f"  {dyn.nsteps} steps in {wall:.0f} s -> {path}")
    return path


def main(argv=None):
    from sphsolid.cli.options import quantity
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dx", type=quantity, required=True)
    parser.add_argument("--until", type=quantity, default=4e-3)
    parser.add_argument("--out", type=Path, default=Path("docs/validation/cylinder_3d"))
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--kernel-correction", action="store_true")
    parser.add_argument("--inset", default="0",
                        help="platen inset in lattice steps, or 'static'")
    parser.add_argument("--integrator", default="improved_euler")
    args = parser.parse_args(argv)
    inset = args.inset if args.inset == "static" else float(args.inset)
    run(args.dx, args.until, args.out, threads=args.threads,
        corrected=args.kernel_correction, inset=inset, integrator=args.integrator)


if __name__ == "__main__":
    main()
