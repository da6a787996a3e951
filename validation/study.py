# Over 600 lines: the paper study's steps (references, runs, tables, figures) share records.
"""Validation study: the paper reproduced, convergence, accuracy versus cost.

``sphsolid study paper --out docs/validation/ [--quick]`` runs everything
and writes PNG figures, ``results.json`` and ``tables.md`` into ``--out``.
Each section is a function here, usable on its own:

- :func:`standing_wave` — a doubly periodic strip carrying a plane P-wave
  standing wave, against its exact solution (derived below);
- :func:`strip_front` — a laterally periodic strip hit by the piston:
  the stress jump behind the front against rho0 c_p v;
- :func:`piston_runs` / :func:`richardson` — the paper's piston test at
  several spacings and the Richardson-extrapolated reference;
- :func:`effect_costs` — time per step with each effect on alone;
- :func:`gravity_column` — the gravity scene against the static column.

No physics is computed here: the runs are the library's; this module only
derives exact solutions, compares and plots.
"""
from __future__ import annotations

import json
import math
import time as wallclock
from pathlib import Path

import numpy as np

from sphsolid import build, kernel_values, scenes
from sphsolid.calculators import CLibrary
from sphsolid.dynamics import ImprovedEuler, dynamics_for
from sphsolid.probes import Probes
from sphsolid.scene import Scene
from sphsolid.trajectory import Frame

__all__ = ["lattice_gradient_moment", "standing_wave", "strip_front",
           "piston_scene", "piston_run", "richardson", "arrival_times",
           "agreement_time", "steady_shape", "pareto", "plot_accuracy_cost", "fe_section", "effect_costs", "gravity_column", "run_paper"]

RHO_V_NOTE = "stress jump behind a piston front: rho0 c_p v"
#: Options compared in the accuracy-versus-cost study.
OPTIONS = {
    "default (cubic, h/dx 1.2, alpha 1)": {},
    "h/dx 1.5": {"ratio": 1.5},
    "Wendland C2, h/dx 1.5": {"ratio": 1.5, "kernel": "wendland_c2"},
    "alpha 0.5": {"alpha": 0.5},
    "alpha 2": {"alpha": 2.0},
    # the integrator axis: the symplectic leapfrog at its default step h/c0
    "leapfrog (alpha 1)": {"integrator": "leapfrog"},
    "leapfrog, alpha 0.2": {"integrator": "leapfrog", "alpha": 0.2},
    # end placement: plate and piston at the static inset (0.396 steps)
    "static inset (alpha 1)": {"inset": "static"},
    # the "waves" preset: cubic_o4 at h/dx 1.65, leapfrog, no viscosity,
    # static inset (0.227 steps)
    "waves preset": {"preset": "waves", "integrator": "leapfrog"},
}


# ------------------------------------------------------------ kernels
def _dW_dq(q: np.ndarray, kernel: str) -> np.ndarray:
    """dW/dq of the library's 2D kernel times h^2 (support 2h):
    ``sph_kernel_values``, so the study uses the kernel the runs use."""
    return kernel_values(kernel, q, dimension=2)[1]


def lattice_gradient_moment(ratio: float, kernel: str = "cubic_spline") -> float:
    """M = -sum_b V_b y_ab^2 W'(r_ab)/r_ab on a square 2D lattice.

    The SPH gradient of a linear field on the lattice is M times the exact
    gradient. M depends on h/dx only, not on dx: both the velocity gradient
    and the stress divergence carry it, so plane waves travel at M c_p in
    the SPH continuum at fixed h/dx. (The continuous integral gives 1.)
    """
    n = int(math.ceil(2 * ratio)) + 1
    i, j = np.meshgrid(np.arange(-n, n + 1), np.arange(-n, n + 1))
    r = np.hypot(i, j)
    keep = r > 0
    q = r[keep] / ratio
    dW_dr = _dW_dq(q, kernel) / ratio ** 3
    return float(-np.sum(j[keep] ** 2 * dW_dr / r[keep]))


# ---------------------------------------------------- exact: strip
def standing_wave(dx: float, ratio: float = 1.2, kernel: str = "cubic_spline",
                  alpha: float = 0.0, wavelength: float = 0.08,
                  amplitude: float = 0.01, periods: float = 1.25,
                  lattice_speed: bool = False, threads: int = 1) -> dict:
    """A plane P-wave standing in a doubly periodic strip.

    Exact solution (plane strain, uniaxial strain, linear):
    v_y = V sin(k y) cos(w t), sigma_yy = rho0 c V cos(k y) sin(w t), with
    w = c k and c = c_p = sqrt((K + 4 mu/3)/rho0): from rho0 dv/dt =
    d sigma/dy and d sigma/dt = rho0 c^2 dv/dy. The run starts from v_y at
    t = 0 and no stress; sigma_yy is compared at t = ``periods`` periods
    (1.25: stress at its peak after a full period).

    With ``lattice_speed`` the reference speed is M c_p
    (:func:`lattice_gradient_moment`), the speed of the SPH continuum at
    this h/dx; its amplitude is still rho0 c_p V.

    Returns the relative RMS error of sigma_yy (over rho0 c_p V), wall time
    [s], steps and particles.
    """
    rock = scenes.paper_material()
    width = 8 * dx
    strip = build.rectangle((-width / 2, width / 2), (0.0, wavelength), dx,
                            rock, name="strip")
    effects = ({"artificial_viscosity": {"alpha": alpha, "beta": 0.0}}
               if alpha else {})
    scene = Scene(2, [strip], effects=effects,
                  domain=((-width / 2, 0.0), (width / 2, wavelength)),
                  periodic=(True, True), smoothing_ratio=ratio, kernel=kernel)
    scene.calc = CLibrary(threads=threads)
    scene.freeze()
    k = 2 * np.pi / wavelength
    c = rock.c_p * (lattice_gradient_moment(ratio, kernel)
                    if lattice_speed else 1.0)
    omega = c * k
    y0 = scene.positions[:, 1].copy()
    scene.velocities[:, 1] = amplitude * np.sin(k * y0)
    dyn = ImprovedEuler(scene, progress=False)
    start = wallclock.perf_counter()
    dyn.run(until=periods * 2 * np.pi / omega)
    wall = wallclock.perf_counter() - start
    scale = rock.rho0 * rock.c_p * amplitude
    exact = scale * np.cos(k * y0) * np.sin(omega * scene.time)
    error = float(np.sqrt(np.mean((scene.stress[:, 1] - exact) ** 2)) / scale)
    return {"dx": dx, "error": error, "wall": wall, "steps": dyn.nsteps,
            "particles": len(scene)}


def strip_front(dx: float, ratio: float = 1.2, alpha: float = 1.0,
                height: float = 0.1, speed: float = 1.5e-3,
                threads: int = 1) -> dict:
    """A laterally periodic strip under the piston, stopped when the front
    is half way down. Exact (linear acoustics): behind the front sigma_yy =
    -rho0 c_p v; ahead of it zero; the front at y = H - c_p t. Returns the
    relative error of the plateau (mean sigma_yy between 5 h behind the
    front and 4 h below the piston) and of the front position (where
    sigma_yy crosses half the jump, lateral mean)."""
    rock = scenes.paper_material()
    width = 8 * dx
    strip = build.rectangle((-width / 2, width / 2), (0.0, height), dx, rock,
                            name="strip")
    # plate and piston: the least layers one kernel support thick (the
    # library's sph_support_layers)
    scene = Scene(2, [strip, build.plate(under=strip),
                      build.piston(over=strip, velocity=(0.0, -speed))],
                  effects={"artificial_viscosity": {"alpha": alpha,
                                                    "beta": 0.0}},
                  domain=((-width / 2, -0.02), (width / 2, height + 0.03)),
                  periodic=(True, False), smoothing_ratio=ratio)
    scene.calc = CLibrary(threads=threads)
    dyn = ImprovedEuler(scene, progress=False)
    start = wallclock.perf_counter()
    dyn.run(until=0.5 * height / rock.c_p)
    wall = wallclock.perf_counter() - start
    part = scene.body_slice("strip")
    y = scene.positions[part, 1]
    s_yy = scene.stress[part, 1]
    jump = rock.rho0 * rock.c_p * speed
    front = height - rock.c_p * scene.time
    behind = (y > front + 5 * scene.h) & (y < height - 4 * scene.h)
    plateau = -float(s_yy[behind].mean()) / jump - 1.0
    # lateral means per row, then the half-jump crossing by interpolation
    rows = np.round(y / dx).astype(int)
    order = np.unique(rows)
    ym = np.array([y[rows == r].mean() for r in order])
    sm = np.array([-s_yy[rows == r].mean() / jump for r in order])
    above = np.nonzero(sm > 0.5)[0]
    i = above[0] if len(above) else len(sm) - 1
    y_front = (ym[i - 1] + (0.5 - sm[i - 1]) * (ym[i] - ym[i - 1])
               / (sm[i] - sm[i - 1])) if i > 0 else ym[0]
    return {"dx": dx, "plateau_error": plateau,
            "front_error": float((y_front - front) / (height - front)),
            "wall": wall, "steps": dyn.nsteps, "particles": len(scene)}


def fit_order(dxs, errors) -> float:
    """Least-squares slope of log(error) against log(dx)."""
    dxs, errors = np.asarray(dxs, float), np.abs(np.asarray(errors, float))
    return float(np.polyfit(np.log(dxs), np.log(errors), 1)[0])


# ------------------------------------------------------ paper piston
def piston_scene(dx: float, ratio: float = 1.2, kernel: str = "cubic_spline",
                 alpha: float = 1.0, threads: int = 1, preset: str | None = None,
                 inset=None) -> Scene:
    """The paper's piston scene with the options of the study (``preset``
    and ``inset``: scenes.uniaxial_piston's, the preset's viscosity)."""
    if preset is not None or inset is not None:
        scene = scenes.uniaxial_piston(dx, preset=preset, inset=inset)
    elif ratio == 1.2 and kernel == "cubic_spline":
        scene = scenes.uniaxial_piston(dx, viscosity={"alpha": alpha,
                                                      "beta": 0.0})
    else:
        rock = scenes.paper_material()
        specimen = build.rectangle(scenes.SPECIMEN_X, scenes.SPECIMEN_Y, dx,
                                   rock, "specimen")
        scene = Scene(2, [specimen, build.plate(under=specimen),
                          build.piston(over=specimen,
                                       velocity=(0.0, -scenes.PISTON_SPEED))],
                      effects={"artificial_viscosity": {"alpha": alpha,
                                                        "beta": 0.0}},
                      smoothing_ratio=ratio, kernel=kernel)
    scene.calc = CLibrary(threads=threads)
    return scene


def piston_run(dx: float, until: float, map_times=(), samples: int = 400,
               threads: int = 1, integrator: str = "improved_euler",
               **options) -> dict:
    """Run the piston scene to ``until`` [s]; probes A, B, C sampled about
    ``samples`` times; field frames at ``map_times``. The wall clock is
    recorded at every sample so the cost up to any time can be read off."""
    scene = piston_scene(dx, threads=threads, **options)
    probes = Probes(scene, scenes.PAPER_PROBES)
    dyn = dynamics_for(integrator)(scene, progress=False)
    interval = max(1, int(round(until / dyn.dt / samples)))
    walls = []
    start = wallclock.perf_counter()

    def sample():
        probes.record()
        walls.append(wallclock.perf_counter() - start)
    dyn.attach(sample, interval=interval)
    frames = []
    for t in sorted(t for t in map_times if t <= until):
        dyn.run(until=t)
        frames.append(Frame.from_scene(scene, len(frames)))
    if dyn.time < until:
        dyn.run(until=until)
    sample()
    return {"dx": dx, "options": options, "integrator": integrator,
            "times": probes.times,
            "walls": np.array(walls), "dt": dyn.dt, "particles": len(scene),
            "steps": dyn.nsteps, "wall": walls[-1],
            "vm": {n: probes[n]["von_mises"] for n in "ABC"},
            "frames": frames,
            "specimen": [b.name for b in scene.bodies].index("specimen")}


def on_grid(run: dict, grid: np.ndarray) -> dict:
    """Probe von Mises series interpolated onto ``grid`` [s]."""
    return {n: np.interp(grid, run["times"], run["vm"][n]) for n in "ABC"}


def richardson(h: list, f: list):
    """Richardson extrapolation from three spacings h1 > h2 > h3 with the
    series f_i (arrays on one grid): f(h) = f* + C h^p with one order p
    for the whole series, p from ||f1 - f2|| / ||f2 - f3||, solved by
    bisection. Returns (f*, p)."""
    h1, h2, h3 = h
    d12 = np.linalg.norm(f[0] - f[1])
    d23 = np.linalg.norm(f[1] - f[2])
    target = d12 / max(d23, 1e-300)

    def ratio(p):
        return (h1 ** p - h2 ** p) / (h2 ** p - h3 ** p)
    lo, hi = 0.05, 6.0
    if not ratio(lo) <= target <= ratio(hi):
        p = lo if target < ratio(lo) else hi
    else:
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if ratio(mid) < target else (lo, mid)
        p = 0.5 * (lo + hi)
    ref = f[2] + (f[2] - f[1]) * h3 ** p / (h2 ** p - h3 ** p)
    return ref, float(p)


def arrival_times(times, vm: dict, threshold: float) -> dict:
    """First time each series exceeds ``threshold`` [Pa] (linear
    interpolation between samples)."""
    out = {}
    for name, v in vm.items():
        above = np.nonzero(np.asarray(v) > threshold)[0]
        if not len(above) or above[0] == 0:
            out[name] = float("nan")
            continue
        i = above[0]
        out[name] = float(times[i - 1] + (threshold - v[i - 1])
                          * (times[i] - times[i - 1]) / (v[i] - v[i - 1]))
    return out


def agreement_time(times, vm: dict, tolerance: float = 0.02):
    """The time after which A, B and C stay within ``tolerance`` of their
    mean, and the slope [Pa/s] of the mean fitted after it (nan, nan if
    they are not within it at the end)."""
    stack = np.vstack([vm[n] for n in "ABC"])
    mean = stack.mean(axis=0)
    spread = np.abs(stack - mean).max(axis=0) / np.maximum(np.abs(mean),
                                                           1e-300)
    bad = np.nonzero(spread > tolerance)[0]
    if len(bad) and bad[-1] == len(times) - 1:
        return float("nan"), float("nan")
    i = bad[-1] + 1 if len(bad) else 0
    t_agree = float(times[i])
    slope = float(np.polyfit(times[i:], mean[i:], 1)[0]) \
        if len(times) - i > 2 else float("nan")
    return t_agree, slope


def steady_shape(times, vm: dict, tolerance: float = 0.02) -> dict:
    """The steady state as the paper describes it (stresses growing
    linearly with a fixed pattern): the time after which each probe's
    ratio to the mean of A, B, C stays within ``tolerance`` of its final
    value, those final ratios, and each probe's slope [Pa/s] fitted from
    that time on."""
    stack = np.vstack([vm[n] for n in "ABC"])
    mean = np.maximum(stack.mean(axis=0), 1e-300)
    ratios = stack / mean
    final = ratios[:, -1:]
    bad = np.nonzero((np.abs(ratios - final) > tolerance).any(axis=0))[0]
    i = bad[-1] + 1 if len(bad) else 0
    i = min(i, len(times) - 3)
    return {"settled_after": float(times[i]),
            "ratios": {n: float(final[k, 0]) for k, n in enumerate("ABC")},
            "slopes": {n: float(np.polyfit(times[i:], stack[k, i:], 1)[0])
                       for k, n in enumerate("ABC")}}


# --------------------------------------------------------- effect cost
def effect_costs(dx: float = 1e-3, steps: int = 100, repeats: int = 3,
                 threads: int = 1, workdir: Path | None = None) -> list:
    """Wall time per step of the paper scene with each effect on alone
    (median of ``repeats``), after one warm-up step."""
    from sphsolid.trajectory import Trajectory
    cases = [("none", {}, None),
             ("artificial_viscosity", {"alpha": 1.0, "beta": 0.0}, None),
             ("artificial_stress", {"epsilon": 0.3, "n": 4}, None),
             ("xsph", {"epsilon": 0.5}, None),
             ("kernel_correction", {}, None),
             ("gravity", {"gx": 0.0, "gy": -9.81}, None),
             ("damping", {"rate": 1000.0}, None),
             ("probes (A, B, C every step)", None, "probes"),
             ("HDF5 snapshot every 10 steps", None, "output")]
    rows = []
    for label, params, extra in cases:
        times = []
        for _ in range(repeats):
            scene = scenes.uniaxial_piston(dx, viscosity=None)
            if params is not None and label != "none":
                scene.effect(label, **params)
            scene.calc = CLibrary(threads=threads)
            dyn = ImprovedEuler(scene, progress=False)
            traj = None
            if extra == "probes":
                dyn.attach(Probes(scene, scenes.PAPER_PROBES), interval=1)
            elif extra == "output":
                path = Path(workdir or ".") / "_effect_cost.h5"
                traj = Trajectory(path, "w", scene, xdmf=False)
                dyn.attach(traj, interval=10)
            dyn.run(steps=1)
            start = wallclock.perf_counter()
            dyn.run(steps=steps)
            times.append((wallclock.perf_counter() - start) / steps)
            if traj is not None:
                traj.close()
                path.unlink(missing_ok=True)
        rows.append({"effect": label, "per_step": float(np.median(times)),
                     "particles": len(scene)})
    base = rows[0]["per_step"]
    for row in rows:
        row["relative"] = row["per_step"] / base
    return rows


# ------------------------------------------------------------ gravity
def gravity_column(dx: float, until: float, threads: int = 1) -> dict:
    """The paper's gravity scene to ``until``; sigma_yy along the centre
    line and the section mean against the static column
    sigma_yy = -rho0 g (H - y) (the section mean is exact for any base:
    the section carries the weight above it)."""
    scene = scenes.gravity(dx)
    scene.calc = CLibrary(threads=threads)
    probes = Probes(scene, {"A": scenes.PAPER_PROBES["A"]})
    dyn = ImprovedEuler(scene, progress=False)
    dyn.attach(probes, interval=max(1, int(until / dyn.dt / 300)))
    start = wallclock.perf_counter()
    dyn.run(until=until)
    wall = wallclock.perf_counter() - start
    part = scene.body_slice("specimen")
    x, y = scene.positions[part, 0], scene.positions[part, 1]
    s_yy = scene.stress[part, 1]
    rows = np.round(y / dx).astype(int)
    levels = np.unique(rows)
    y_row = np.array([y[rows == r].mean() for r in levels])
    centre = np.array([s_yy[rows == r][np.argsort(np.abs(x[rows == r]))[:2]]
                       .mean() for r in levels])
    section = np.array([s_yy[rows == r].mean() for r in levels])
    rock = scenes.paper_material()
    H = scenes.SPECIMEN_Y[1]
    exact = -rock.rho0 * 9.81 * (H - y_row)
    inner = (y_row > 0.1 * H) & (y_row < 0.9 * H)
    return {"dx": dx, "until": until, "wall": wall, "y": y_row,
            "centre": centre, "section": section, "exact": exact,
            "section_error": float(np.max(np.abs(section - exact)[inner])
                                   / np.max(np.abs(exact))),
            "centre_error": float(np.max(np.abs(centre - exact)[inner])
                                  / np.max(np.abs(exact))),
            "probe_times": probes.times, "probe_syy": probes["A"]["sigma_yy"],
            "frame": Frame.from_scene(scene),
            "specimen": [b.name for b in scene.bodies].index("specimen")}


# ------------------------------------------------------------- driver
def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _fmt(x, digits=3):
    return f"{x:.{digits}g}" if isinstance(x, float) else str(x)


def _table(header, rows) -> str:
    lines = ["| " + " | ".join(header) + " |",
             "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_fmt(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def pareto(points: list, cost: str) -> list:
    """For each point, whether no other point is both cheaper (``cost``)
    and more accurate (``error``)."""
    return [not any(o[cost] <= q[cost] and o["error"] < q["error"]
                    for o in points if o is not q) for q in points]


def plot_accuracy_cost(points: list, path, window: float):
    """Error against wall time and against particle-steps, one line per
    option, with the Pareto front of each axis."""
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    labels = list(dict.fromkeys(q["option"] for q in points))
    for ax, key in zip(axes, ("wall", "particle_steps")):
        for label in labels:
            qs = sorted((q for q in points if q["option"] == label),
                        key=lambda q: q[key])
            ax.loglog([q[key] for q in qs], [q["error"] for q in qs], "o-",
                      label=label)
        front = sorted((q for q, on in zip(points, pareto(points, key))
                        if on), key=lambda q: q[key])
        ax.loglog([q[key] for q in front], [q["error"] for q in front],
                  "k--", lw=1.5, label="Pareto front")
        ax.set_xlabel("wall time [s], 1 core" if key == "wall"
                      else "particle-steps")
        ax.set_ylabel("relative L2 error at A, B, C")
    axes[0].legend(fontsize=7)
    fig.suptitle(f"Accuracy versus cost, piston test 0-{window * 1e3:g} ms "
                 "(each line: dx = 4 mm top left to the finest bottom right)")
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return Path(path)


def _steady_text(t2, slope2, t5, slope5, shape) -> str:
    def when(t, slope, tol):
        if math.isnan(t):
            return f"A, B, C are not within {tol} % of their mean at the end"
        return (f"A, B, C stay within {tol} % of their mean from t = "
                f"{t * 1e3:.3g} ms; slope of the mean {slope / 1e6:.4g} "
                "kPa/ms")
    return (f"\n{when(t2, slope2, 2)}. {when(t5, slope5, 5)}. The pattern "
            f"settles (each probe's ratio to the mean within 2 % of its "
            f"final value) from t = {shape['settled_after'] * 1e3:.3g} ms; "
            "final ratios "
            + ", ".join(f"{n} {shape['ratios'][n]:.3f}" for n in "ABC")
            + "; slopes "
            + ", ".join(f"{n} {shape['slopes'][n] / 1e6:.4g}" for n in "ABC")
            + " kPa/ms.\n")


def run_paper(out: Path, quick: bool = False, log=print) -> dict:
    """Everything in docs/validation.md: figures, tables, results.json."""
    from sphsolid.figures import probe_curves, von_mises_map
    plt = _plt()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rock = scenes.paper_material()
    c_p, v = rock.c_p, scenes.PISTON_SPEED
    results: dict = {"quick": quick, "c_p": c_p}
    tables = [f"# Validation tables ({'quick' if quick else 'full'} mode)\n"]
    clock = wallclock.perf_counter()

    def save():
        (out / "results.json").write_text(json.dumps(results, indent=1))
        (out / "tables.md").write_text("\n".join(tables))

    # 1. standing wave in the periodic strip --------------------------
    log("standing wave (periodic strip) ...")
    strip_dx = [4e-3, 2e-3, 1e-3, 0.5e-3]
    variants = [("cubic, h/dx 1.2, no viscosity", dict()),
                ("cubic, h/dx 1.2, no viscosity, vs M c_p",
                 dict(lattice_speed=True)),
                ("cubic, h/dx 1.2, alpha 1", dict(alpha=1.0)),
                ("cubic, h/dx 1.5, no viscosity", dict(ratio=1.5)),
                ("Wendland, h/dx 1.5, no viscosity",
                 dict(ratio=1.5, kernel="wendland_c2")),
                ("Wendland, h/dx 1.5, no viscosity, vs M c_p",
                 dict(ratio=1.5, kernel="wendland_c2", lattice_speed=True))]
    wave = {}
    rows = []
    fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
    for label, kw in variants:
        runs = [standing_wave(dx, **kw) for dx in strip_dx]
        errs = [r["error"] for r in runs]
        p_all = fit_order(strip_dx, errs)
        p_fine = fit_order(strip_dx[1:], errs[1:])
        wave[label] = {"errors": errs, "order": p_all, "order_fine": p_fine,
                       "walls": [r["wall"] for r in runs]}
        rows.append([label] + [f"{e:.2e}" for e in errs]
                    + [f"{p_all:.2f}", f"{p_fine:.2f}"])
        ax.loglog(np.array(strip_dx) * 1e3, errs, "o-", label=label)
    ax.set_xlabel("dx [mm]")
    ax.set_ylabel("RMS error of sigma_yy / (rho0 c_p V)")
    ax.set_title("Standing P-wave, periodic strip, t = 1.25 periods")
    ax.legend(fontsize=7)
    fig.savefig(out / "strip_convergence.png", dpi=110)
    plt.close(fig)
    results["standing_wave"] = {"dx": strip_dx, **wave,
                                "M": {"cubic 1.2": lattice_gradient_moment(1.2),
                                      "cubic 1.5": lattice_gradient_moment(1.5),
                                      "wendland 1.5": lattice_gradient_moment(
                                          1.5, "wendland_c2")}}
    tables.append("## Standing wave in the periodic strip\n\n"
                  "Relative RMS error of sigma_yy at t = 1.25 periods "
                  "(wavelength 80 mm). 'vs M c_p': against the exact "
                  "solution travelling at the lattice speed M c_p.\n\n"
                  + _table(["variant"] + [f"{d * 1e3:g} mm" for d in strip_dx]
                           + ["order (all)", "order (2-0.5 mm)"], rows))

    # 2. piston front in the periodic strip ---------------------------
    log("piston front (periodic strip) ...")
    front = [strip_front(dx) for dx in strip_dx]
    results["strip_front"] = front
    tables.append("## Piston front in the laterally periodic strip "
                  "(alpha 1)\n\nPlateau: mean sigma_yy behind the front over "
                  "rho0 c_p v, minus 1 (exact 0; the lattice speed predicts "
                  f"M - 1 = {lattice_gradient_moment(1.2) - 1:+.4f}). Front: "
                  "position error over the distance travelled.\n\n"
                  + _table(["dx [mm]", "plateau error", "front error",
                            "wall [s]"],
                           [[f"{r['dx'] * 1e3:g}", f"{r['plateau_error']:+.4f}",
                             f"{r['front_error']:+.4f}", f"{r['wall']:.2f}"]
                            for r in front]))
    save()

    # 3. piston test: convergence and Richardson reference -------------
    window = 0.3e-3 if quick else 1e-3
    conv_dx = ([4e-3, 3e-3, 2e-3, 1.5e-3, 1e-3] if quick else
               [4e-3, 2e-3, 1.5e-3, 1e-3, 0.5e-3])
    long_dx = 2e-3 if quick else 1e-3
    long_until = 2e-3 if quick else 5e-3
    map_times = [0.04e-3, 0.08e-3, 0.11e-3, 0.12e-3, 0.24e-3]
    runs = {}
    for dx in conv_dx:
        log(f"piston dx = {dx * 1e3:g} mm ...")
        if abs(dx - long_dx) < 1e-12:
            runs[dx] = piston_run(dx, long_until, map_times=map_times,
                                  samples=2000)
        else:
            runs[dx] = piston_run(dx, window, samples=400)
    if long_dx not in runs:
        runs[long_dx] = piston_run(long_dx, long_until, map_times=map_times,
                                   samples=2000)
    grid = np.linspace(window / 200, window, 200)
    series = {dx: on_grid(r, grid) for dx, r in runs.items()}
    hs = sorted(conv_dx, reverse=True)
    stack = lambda dx: np.concatenate([series[dx][n] for n in "ABC"])  # noqa
    # reference from a chain of halvings; other triples check it
    ref_dx = [4e-3, 2e-3, 1e-3] if quick else [2e-3, 1e-3, 0.5e-3]
    check_dx = ([[3e-3, 2e-3, 1.5e-3]] if quick else
                [[4e-3, 2e-3, 1e-3], [1.5e-3, 1e-3, 0.5e-3]])
    ref, p_ref = richardson(ref_dx, [stack(d) for d in ref_dx])
    scale = np.linalg.norm(ref)
    checks = []
    for triple in check_dx:
        other, p_other = richardson(triple, [stack(d) for d in triple])
        checks.append({"dx": triple, "order": p_other,
                       "change": float(np.linalg.norm(other - ref) / scale)})
    np.savez_compressed(out / "piston_series.npz", grid=grid,
                        **{f"dx{d * 1e3:g}mm_{n}": series[d][n]
                           for d in hs for n in "ABC"})
    conv_rows = []
    errors = {}
    for dx in hs:
        e = {}
        for k, n in enumerate("ABC"):
            r = ref[k * len(grid):(k + 1) * len(grid)]
            e[n] = float(np.linalg.norm(series[dx][n] - r) / np.linalg.norm(r))
        e["all"] = float(np.linalg.norm(stack(dx) - ref) / scale)
        wall = float(np.interp(window, runs[dx]["times"], runs[dx]["walls"]))
        steps = int(math.ceil(window / runs[dx]["dt"]))
        e.update(wall=wall, particle_steps=steps * runs[dx]["particles"])
        errors[dx] = e
        conv_rows.append([f"{dx * 1e3:g}", runs[dx]["particles"], steps,
                          f"{e['A']:.2e}", f"{e['B']:.2e}", f"{e['C']:.2e}",
                          f"{e['all']:.2e}", f"{wall:.2f}"])
    fit_dx = hs[:-1]   # the finest defines the reference
    p_piston = fit_order(fit_dx, [errors[d]["all"] for d in fit_dx])
    results["piston_convergence"] = {
        "window": window, "dx": hs, "errors": {str(k): v for k, v in
                                               errors.items()},
        "reference_dx": ref_dx, "richardson_order": p_ref,
        "checks": checks, "observed_order": p_piston}
    mm = lambda ds: ", ".join(f"{d * 1e3:g}" for d in ds)  # noqa
    tables.append(
        f"## Piston test: error against the Richardson reference, 0 to "
        f"{window * 1e3:g} ms\n\nReference: Richardson extrapolation of "
        f"dx = {mm(ref_dx)} mm (fitted order p = {p_ref:.2f}). Checks: "
        + "; ".join(f"from {mm(c['dx'])} mm p = {c['order']:.2f}, differs "
                    f"by {c['change']:.2e}" for c in checks)
        + f" (relative L2). Observed order of the error (fit over "
        f"{mm(fit_dx)} mm): {p_piston:.2f}. Relative L2 error of von Mises "
        "over the window.\n\n"
        + _table(["dx [mm]", "particles", "steps", "A", "B", "C", "A+B+C",
                  "wall [s], 1 core"], conv_rows))
    # Fig 11-like deviation plot
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6), sharey=True,
                             constrained_layout=True)
    for k, n in enumerate("ABC"):
        r = ref[k * len(grid):(k + 1) * len(grid)]
        for dx in hs:
            axes[k].plot(grid * 1e3, (series[dx][n] - r) / np.abs(r).max()
                         * 100, label=f"{dx * 1e3:g} mm")
        axes[k].set_title(f"point {n}")
        axes[k].set_xlabel("t [ms]")
    axes[0].set_ylabel("(SPH - reference) / max|reference| [%]")
    axes[0].legend(fontsize=8)
    fig.savefig(out / "piston_deviation.png", dpi=100)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(5, 4), constrained_layout=True)
    for n in ("A", "B", "C", "all"):
        ax.loglog([d * 1e3 for d in hs[:-1]], [errors[d][n] for d in hs[:-1]],
                  "o-", label=n)
    ax.set_xlabel("dx [mm]")
    ax.set_ylabel("relative L2 error vs reference")
    ax.set_title(f"piston test, 0-{window * 1e3:g} ms, order {p_piston:.2f}")
    ax.legend()
    fig.savefig(out / "piston_convergence.png", dpi=110)
    plt.close(fig)
    save()

    # 4. accuracy versus cost over options ----------------------------
    log("accuracy versus cost ...")
    cost_dx = [4e-3, 2e-3] if quick else [4e-3, 2e-3, 1.5e-3, 1e-3]
    points = []
    point_series = {}
    for label, opts in OPTIONS.items():
        for dx in cost_dx:
            # short cases: median wall time of 3 repeats (shared machines)
            repeats = 3 if dx >= 2e-3 else 1
            if not opts and dx in runs and repeats == 1:
                tries = [runs[dx]]
            else:
                log(f"  {label}, dx = {dx * 1e3:g} mm")
                tries = [piston_run(dx, window, samples=400, **opts)
                         for _ in range(repeats)]
            r = tries[0]
            s = on_grid(r, grid)
            point_series[f"p{len(points)}"] = np.concatenate(
                [s[n] for n in "ABC"])
            err = float(np.linalg.norm(np.concatenate([s[n] for n in "ABC"])
                                       - ref) / scale)
            wall = float(np.median([np.interp(window, q["times"], q["walls"])
                                    for q in tries]))
            steps = int(math.ceil(window / r["dt"]))
            points.append({"option": label, "dx": dx, "error": err,
                           "wall": wall,
                           "particle_steps": steps * r["particles"]})
    order = sorted(points, key=lambda q: q["wall"])
    for q, on in zip(points, pareto(points, "wall")):
        q["pareto"] = on
    results["accuracy_cost"] = points
    np.savez_compressed(out / "accuracy_series.npz", grid=grid,
                        **point_series)
    plot_accuracy_cost(points, out / "accuracy_vs_cost.png", window)
    tables.append(
        "## Accuracy versus cost (piston test, error against the Richardson "
        "reference; * = on the Pareto front of wall time)\n\n"
        + _table(["option", "dx [mm]", "error", "wall [s]", "particle-steps",
                  "Pareto"],
                 [[q["option"], f"{q['dx'] * 1e3:g}", f"{q['error']:.2e}",
                   f"{q['wall']:.2f}", f"{q['particle_steps']:.3g}",
                   "*" if q["pareto"] else ""] for q in order]))
    save()

    # 5. the paper's figures from the long run -------------------------
    log("paper figures ...")
    long = runs[long_dx]
    dtag = f"{long_dx * 1e3:g} mm"
    specimen = long["specimen"]
    von_mises_map(long["frames"], out / "fig2_3_von_mises.png",
                  mask=lambda f: f.body_ids == specimen, columns=5,
                  title=f"von Mises stress (Figs 2-3), dx = {dtag}")
    t, vm = long["times"], long["vm"]
    early = t <= 0.1e-3
    probe_curves(t[early], {n: vm[n][early] for n in "ABC"},
                 out / "fig6_probes_0_0.1ms.png",
                 title=f"Fig 6: von Mises at A, B, C, dx = {dtag}")
    probe_curves(t, vm, out / "fig7_probes_long.png",
                 title=f"Fig 7: von Mises at A, B, C, dx = {dtag}")
    jump_vm = 2 * rock.mu * v / c_p      # uniaxial strain behind the front
    arrival = arrival_times(t, vm, 0.5 * jump_vm)
    H = scenes.SPECIMEN_Y[1]
    exact_arrival = {n: (H - scenes.PAPER_PROBES[n][1]) / c_p for n in "ABC"}
    t_agree, slope = agreement_time(t, vm)
    t_agree5, slope5 = agreement_time(t, vm, 0.05)
    shape = steady_shape(t, vm)
    E, nu = rock.E, rock.nu
    slope_estimate = (E / (1 - nu ** 2) * math.sqrt(1 - nu + nu ** 2)
                      * v / H)
    results["paper"] = {"dx": long_dx, "until": long_until,
                        "wall": long["wall"], "arrival": arrival,
                        "arrival_exact": exact_arrival,
                        "agree_2pct_after": t_agree, "slope": slope,
                        "agree_5pct_after": t_agree5, "slope_5pct": slope5,
                        "steady_shape": shape,
                        "slope_uniaxial_stress_estimate": slope_estimate}
    arrival_rows = [[n, f"{arrival[n] * 1e6:.2f}",
                     f"{exact_arrival[n] * 1e6:.2f}",
                     f"{(arrival[n] / exact_arrival[n] - 1) * 100:+.1f}"]
                    for n in "ABC"]
    tables.append(
        f"## Paper scene at dx = {dtag} to {long_until * 1e3:g} ms "
        f"({long['steps']} steps, {long['wall']:.1f} s on 1 core)\n\n"
        f"Arrival: von Mises first above half the plane-wave value 2 mu v / "
        f"c_p = {jump_vm:.0f} Pa; exact: distance from the piston face / c_p "
        f"(c_p = {c_p:.1f} m/s).\n\n"
        + _table(["probe", "arrival [us]", "(H - y)/c_p [us]",
                  "difference [%]"], arrival_rows)
        + _steady_text(t_agree, slope, t_agree5, slope5, shape)
        + f"Uniaxial-stress estimate of the slope E/(1-nu^2) "
        f"sqrt(1-nu+nu^2) v/H = {slope_estimate / 1e6:.4g} kPa/ms.\n")
    save()
    if not quick:
        log("steady state (Fig 4, Fig 8) at 2 mm to 20 ms ...")
        steady = piston_run(2e-3, 20e-3, map_times=[10e-3, 20e-3],
                            samples=2000)
        probe_curves(steady["times"], steady["vm"], out / "fig8_probes_20ms.png",
                     title="Fig 8: von Mises at A, B, C, dx = 2 mm")
        sp = steady["specimen"]
        von_mises_map(steady["frames"], out / "fig4_steady_von_mises.png",
                      mask=lambda f: f.body_ids == sp,
                      title="Steady state (Fig 4), dx = 2 mm")
        t2_agree, slope2 = agreement_time(steady["times"], steady["vm"])
        t2_agree5, slope25 = agreement_time(steady["times"], steady["vm"],
                                            0.05)
        shape2 = steady_shape(steady["times"], steady["vm"])
        results["steady"] = {"dx": 2e-3, "until": 20e-3,
                             "wall": steady["wall"],
                             "agree_2pct_after": t2_agree, "slope": slope2,
                             "agree_5pct_after": t2_agree5,
                             "slope_5pct": slope25, "steady_shape": shape2}
        tables.append(f"\n### Steady state: dx = 2 mm to 20 ms "
                      f"({steady['wall']:.1f} s)\n\n"
                      + _steady_text(t2_agree, slope2, t2_agree5, slope25,
                                     shape2))
        save()

    # 6. gravity --------------------------------------------------------
    g_dx, g_until = (4e-3, 20e-3) if quick else (2e-3, 60e-3)
    log(f"gravity dx = {g_dx * 1e3:g} mm to {g_until * 1e3:g} ms ...")
    grav = gravity_column(g_dx, g_until)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), constrained_layout=True)
    axes[0].plot(-grav["exact"] / 1e3, grav["y"] * 1e3, "k-",
                 label="static: rho0 g (H - y)")
    axes[0].plot(-grav["centre"] / 1e3, grav["y"] * 1e3, "o", ms=3,
                 label="SPH, centre line")
    axes[0].plot(-grav["section"] / 1e3, grav["y"] * 1e3, "x", ms=3,
                 label="SPH, section mean")
    axes[0].set_xlabel("-sigma_yy [kPa]")
    axes[0].set_ylabel("y [mm]")
    axes[0].legend(fontsize=8)
    axes[0].set_title(f"t = {g_until * 1e3:g} ms, dx = {g_dx * 1e3:g} mm")
    axes[1].plot(grav["probe_times"] * 1e3, -grav["probe_syy"] / 1e3)
    axes[1].axhline(rock.rho0 * 9.81 * (H - 0.070) / 1e3, color="k", ls="--",
                    label="static column at y = 70 mm")
    axes[1].set_xlabel("t [ms]")
    axes[1].set_ylabel("-sigma_yy at A [kPa]")
    axes[1].legend(fontsize=8)
    fig.savefig(out / "fig12_gravity_syy.png", dpi=100)
    plt.close(fig)
    gs = grav["specimen"]
    von_mises_map(grav["frame"], out / "fig12_gravity_von_mises.png",
                  mask=lambda f: f.body_ids == gs,
                  title=f"gravity, t = {g_until * 1e3:g} ms, "
                        f"dx = {g_dx * 1e3:g} mm")
    results["gravity"] = {k: grav[k] for k in ("dx", "until", "wall",
                                                "section_error",
                                                "centre_error")}
    tables.append(
        f"## Gravity column, dx = {g_dx * 1e3:g} mm, t = {g_until * 1e3:g} ms"
        f" ({grav['wall']:.1f} s)\n\nMax deviation from -rho0 g (H - y) "
        "between 10 % and 90 % of the height, over rho0 g H: section mean "
        f"{grav['section_error']:.2e}, centre line {grav['centre_error']:.2e}"
        ".\n")
    save()

    # 7. cost of each effect -------------------------------------------
    log("cost of each effect ...")
    eff_dx = 2e-3 if quick else 1e-3
    costs = effect_costs(eff_dx, steps=50 if quick else 100,
                         repeats=3, workdir=out)
    results["effect_costs"] = {"dx": eff_dx, "rows": costs}
    tables.append(
        f"## Cost of each effect (paper scene, dx = {eff_dx * 1e3:g} mm, "
        f"{costs[0]['particles']} particles, 1 thread, median of 3)\n\n"
        + _table(["effect alone", "ms per step", "relative to none"],
                 [[r["effect"], f"{r['per_step'] * 1e3:.2f}",
                   f"{r['relative']:.2f}"] for r in costs]))
    results["total_wall"] = wallclock.perf_counter() - clock
    save()
    results = fe_section(out, quick, log)
    log(f"done in {wallclock.perf_counter() - clock:.0f} s (SPH "
        f"{results['total_wall']:.0f} s); wrote {out}")
    return results


# ------------------------------------------------- finite-element check
def fe_section(out: Path, quick: bool = False, log=print) -> dict:
    """An independent reference for the piston test: the finite-element
    solution (:mod:`sphsolid.fe_reference`, scikit-fem) at several element
    sizes on the grid of ``piston_series.npz``, against the SPH runs and
    the Richardson reference; and the quasi-static FE pattern against the
    SPH steady-state ratios. Appends to ``results.json`` and
    ``tables.md`` in ``out``."""
    from . import fe_reference
    out = Path(out)
    results = json.loads((out / "results.json").read_text())
    if not fe_reference.available():
        log("scikit-fem not installed: finite-element check skipped")
        return results
    data = np.load(out / "piston_series.npz")
    grid = data["grid"]
    conv = results["piston_convergence"]
    hs = conv["dx"]
    series = {d: {n: data[f"dx{d * 1e3:g}mm_{n}"] for n in "ABC"} for d in hs}
    stack = lambda d: np.concatenate([series[d][n] for n in "ABC"])  # noqa
    ref_dx = conv["reference_dx"]
    ref, _ = richardson(ref_dx, [stack(d) for d in ref_dx])
    rock = scenes.paper_material()
    sizes = [4e-3, 2e-3] if quick else [4e-3, 2e-3, 1e-3]
    fe = {}
    for size in sizes:
        log(f"finite elements, {size * 1e3:g} mm quadratic quads ...")
        fe[size] = fe_reference.piston_fe(
            size, grid[-1], 0.25e-6 * size / 2e-3, grid, scenes.PAPER_PROBES,
            rock.K, rock.mu, rock.rho0, scenes.PISTON_SPEED)
    fe_stack = lambda s: np.concatenate([fe[s]["vm"][n] for n in "ABC"])  # noqa
    best = fe_stack(sizes[-1])
    scale = np.linalg.norm(best)
    np.savez_compressed(out / "fe_series.npz", grid=grid,
                        **{f"fe{s * 1e3:g}mm": fe_stack(s) for s in sizes})
    extra = ""
    if (out / "accuracy_series.npz").exists():
        acc = np.load(out / "accuracy_series.npz")
        points = results["accuracy_cost"]
        for i, q in enumerate(points):
            q["error_fe"] = float(np.linalg.norm(acc[f"p{i}"] - best) / scale)
        fe_points = [dict(q, error=q["error_fe"]) for q in points]
        front = pareto(fe_points, "wall")
        plot_accuracy_cost(fe_points, out / "accuracy_vs_cost_fe.png",
                           grid[-1])
        order = sorted(range(len(points)), key=lambda i: points[i]["wall"])
        extra = ("\n## Accuracy versus cost against the FE reference "
                 f"({sizes[-1] * 1e3:g} mm; * = Pareto front of wall time)"
                 "\n\n" + _table(
                     ["option", "dx [mm]", "error vs FE",
                      "error vs Richardson", "wall [s]", "Pareto"],
                     [[points[i]["option"], f"{points[i]['dx'] * 1e3:g}",
                       f"{points[i]['error_fe']:.2e}",
                       f"{points[i]['error']:.2e}",
                       f"{points[i]['wall']:.2f}",
                       "*" if front[i] else ""] for i in order]))
    fe_rows = [[f"{s * 1e3:g}", fe[s]["dofs"], fe[s]["steps"],
                f"{fe[s]['dt'] * 1e6:g}",
                f"{np.linalg.norm(fe_stack(s) - best) / scale:.2e}"
                if s != sizes[-1] else "(reference)",
                f"{fe[s]['wall']:.1f}"] for s in sizes]
    sph_rows = []
    sph_err = {}
    for d in hs:
        sph_err[d] = float(np.linalg.norm(stack(d) - best) / scale)
        sph_rows.append([f"{d * 1e3:g}", f"{sph_err[d]:.2e}"])
    ref_vs_fe = float(np.linalg.norm(ref - best) / scale)
    p_fe = fit_order(hs, [sph_err[d] for d in hs])
    # quasi-static pattern
    static = fe_reference.static_pattern(sizes[-1], scenes.PAPER_PROBES,
                                         rock.K, rock.mu)
    mean = np.mean(list(static.values()))
    static_ratios = {n: static[n] / mean for n in "ABC"}
    # von Mises per metre of compression times the piston speed [Pa/s]
    static_slope = {n: static[n] / 1e-6 * scenes.PISTON_SPEED
                    for n in "ABC"}
    results["fe"] = {"sizes": sizes,
                     "walls": [fe[s]["wall"] for s in sizes],
                     "sph_error_vs_fe": {str(d): sph_err[d] for d in hs},
                     "observed_order_vs_fe": p_fe,
                     "richardson_vs_fe": ref_vs_fe,
                     "static_ratios": static_ratios,
                     "static_slopes": static_slope}
    plt = _plt()
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6), sharey=True,
                             constrained_layout=True)
    for k, n in enumerate("ABC"):
        axes[k].plot(grid * 1e3, fe[sizes[-1]]["vm"][n] / 1e3, "k-", lw=1,
                     label=f"FE {sizes[-1] * 1e3:g} mm Q2")
        axes[k].plot(grid * 1e3, ref[k * len(grid):(k + 1) * len(grid)] / 1e3,
                     "r--", lw=1, label="Richardson (SPH)")
        for d in hs[-2:]:
            axes[k].plot(grid * 1e3, series[d][n] / 1e3, lw=1,
                         label=f"SPH {d * 1e3:g} mm")
        axes[k].set_title(f"point {n}")
        axes[k].set_xlabel("t [ms]")
    axes[0].set_ylabel("von Mises [kPa]")
    axes[0].legend(fontsize=7)
    fig.savefig(out / "fe_comparison.png", dpi=100)
    plt.close(fig)
    text = ("\n## Finite-element reference (scikit-fem, 9-node quadratic "
            "quads, implicit Newmark average acceleration, consistent mass)"
            f"\n\nOwn convergence (relative L2 of von Mises at A, B, C over "
            f"0-{grid[-1] * 1e3:g} ms against the finest mesh):\n\n"
            + _table(["element [mm]", "DOFs", "steps", "dt [us]",
                      "vs finest", "wall [s]"], fe_rows)
            + f"\nSPH against FE {sizes[-1] * 1e3:g} mm (observed order "
            f"{p_fe:.2f}); the Richardson reference differs from it by "
            f"{ref_vs_fe:.2e}:\n\n"
            + _table(["SPH dx [mm]", "error vs FE"], sph_rows)
            + "\nQuasi-static FE pattern (top pushed down, bonded ends): "
            "ratios to the mean of A, B, C "
            + ", ".join(f"{n} {static_ratios[n]:.3f}" for n in "ABC")
            + "; slopes at 1.5 mm/s "
            + ", ".join(f"{n} {static_slope[n] / 1e6:.4g}" for n in "ABC")
            + " kPa/ms.\n" + extra)
    (out / "results.json").write_text(json.dumps(results, indent=1))
    with open(out / "tables.md", "a") as handle:
        handle.write(text)
    return results
