"""Effect detection: which optional effects the scene calls for, from a
run at the coarsest spacing with none."""
from __future__ import annotations

import ctypes
import math
from dataclasses import asdict, dataclass

import numpy as np

from .. import _lib
from .._lib import SimulationError, UnsupportedError, lib
from .calibration import _observer, build_scene, make_dynamics
from .cost_model import time_steps
from .settings import DEFAULT_INTEGRATOR, Setting, _effect_available


# ------------------------------------------------------- effect detection
@dataclass
class Finding:
    """An effect the scene calls for (or a property reported without one)."""
    effect: str | None
    parameters: dict
    reason: str
    measured: str
    cost: float | None = None       # relative extra time per step
    #: False when found from a sign (roughness, a tension share) rather
    #: than a failure: settings that are stable without it try both
    required: bool = True

    def to_dict(self) -> dict:
        return asdict(self)



def _defaults(effect: str) -> dict:
    """The library's default parameters of an effect (its registry)."""
    return {key: p["default"] for key, p in
            _lib.effect_registry()[effect]["parameters"].items()
            if p["default"] is not None}

def _roughness(values) -> float:
    """Mean |second difference| over mean |first difference| of a series
    (0 smooth, 2 alternating; the dissipation study's measure)."""
    v = np.asarray(values, float)
    if len(v) < 3:
        return 0.0
    first = np.mean(np.abs(np.diff(v)))
    return float(np.mean(np.abs(np.diff(v, 2))) / first) if first > 0 else 0.0


def _rotation_angle(x0: np.ndarray, x1: np.ndarray) -> float:
    """Best-fit rigid rotation angle [rad] (2D Kabsch) between two particle
    sets, or for 3D the angle of the best-fit rotation matrix."""
    a = x0 - x0.mean(axis=0)
    b = x1 - x1.mean(axis=0)
    u, _, vt = np.linalg.svd(a.T @ b)
    d = np.sign(np.linalg.det(u @ vt))
    corr = np.eye(a.shape[1])
    corr[-1, -1] = d
    rot = (u @ corr @ vt).T
    cosine = (np.trace(rot) - (a.shape[1] - 2)) / 2.0
    return float(np.arccos(np.clip(cosine, -1.0, 1.0)))


def _principal_max(stress: np.ndarray, dim: int) -> np.ndarray:
    """Largest principal value of the in-plane (2D) or full (3D) Cauchy
    stress rows in the library's order (xx yy zz xy [xz yz])."""
    if dim == 2:
        xx, yy, xy = stress[:, 0], stress[:, 1], stress[:, 3]
        mean, radius = 0.5 * (xx + yy), np.hypot(0.5 * (xx - yy), xy)
        return np.maximum(mean + radius, stress[:, 2])
    m = np.zeros((len(stress), 3, 3))
    for k in range(3):
        m[:, k, k] = stress[:, k]
    m[:, 0, 1] = m[:, 1, 0] = stress[:, 3]
    m[:, 0, 2] = m[:, 2, 0] = stress[:, 4]
    m[:, 1, 2] = m[:, 2, 1] = stress[:, 5]
    return np.linalg.eigvalsh(m)[:, -1]


def _effect_cost(scene_factory, dx, setting, effect, params, threads,
                 steps=20, repeats=3) -> float:
    """Relative extra seconds per step of ``effect`` on top of ``setting``
    (medians of ``repeats`` timings of ``steps`` steps, alternating)."""
    effects = setting.effect_dict
    effects[effect] = params
    on = setting.with_effects(effects)
    without, with_it = [], []
    for _ in range(repeats):
        without.append(time_steps(scene_factory, dx, setting, threads,
                                  steps)[2])
        with_it.append(time_steps(scene_factory, dx, on, threads, steps)[2])
    return float(np.median(with_it) / np.median(without) - 1.0)


def detect_effects(scene_factory, dx: float, until: float, probes,
                   quantity: str = "von_mises",
                   integrator: str = DEFAULT_INTEGRATOR,
                   threads: int | None = None, steps: int | None = None,
                   log=None, kernel: str = "cubic_spline",
                   smoothing_ratio: float = 1.2,
                   inset: float | str = 0.0,
                   priced=frozenset()) -> list[Finding]:
    """What the scene calls for, measured on one run at ``dx`` with no
    optional effect, ``integrator``, ``kernel``, ``smoothing_ratio`` and
    end placement ``inset``, for ``steps`` steps (default: to ``until``).
    A finding's extra cost per step is timed unless its (effect, reason)
    is in ``priced`` (already timed by an earlier detection run of the
    same plan).

    Criteria (from the hard-case suite, docs/stability.md):

    - artificial viscosity: the run blows up or a probe series is rough
      (mean |second difference| / mean |first difference| > 0.3; smooth
      runs measure 0.03-0.2 on coarse probe series, undamped Improved
      Euler 0.5-1);
    - artificial stress: at each of t = until/3, 2 until/3 and until more
      than 10 % of the free particles are in tension above 10 % of the
      largest stress magnitude then (sustained, not a passing reflection);
    - kernel correction: a body rotates by more than 0.1 rad (free bodies,
      best-fit rotation) or has a prescribed rotation;
    - damping: no body is driven by a prescribed motion, a constant load
      acts (gravity, or a force-driven body), and the free bodies still
      ring at the end (kinetic energy over the last quarter above 5 % of
      its peak): the answer wanted is the static one. Rate c_p / L (L the
      largest extent of the free bodies): damping ratio ~0.3 for the
      fundamental, so it settles in a few periods;
    - near-incompressible material (Poisson ratio > 0.45): reported; the
      suite measured it stable and smooth with nothing extra.
    """
    say = log or (lambda message: None)
    setting = Setting.make(smoothing_ratio, kernel, integrator, inset=inset)
    scene = build_scene(scene_factory, dx, setting, threads)
    free = np.zeros(len(scene), bool)
    driven, forced, rotating = [], [], []
    for body in scene.bodies:
        part = scene.body_slice(body.name)
        kind = getattr(body.motion, "kind", "free")
        if kind in ("free", "force", "pressure"):
            free[part] = True
        if kind == "velocity" or (kind == "free" and body.velocity is not None
                                  and any(body.velocity)):
            driven.append(body.name)
        if kind in ("force", "pressure"):
            forced.append(body.name)
        if kind == "rotation":
            rotating.append(body.name)
    gravity = "gravity" in scene.effects
    x0 = scene.positions[free].copy()
    sample = _observer(scene, probes, quantity)
    dyn = make_dynamics(scene, integrator, progress=False)
    total = steps or max(1, int(math.ceil(until / dyn.dt)))
    at_until = max(1, min(total, int(math.ceil(until / dyn.dt))))
    interval = max(1, total // 400)
    values, kinetic = [], []
    checks = sorted({max(1, int(at_until * k / 3)) for k in (1, 2, 3)})
    snapshots = []

    def record():
        values.append(sample())
        kinetic.append(scene.energy()["kinetic"])

    def snapshot():
        scene.calc.sync()
        snapshots.append((scene.stress[free].copy(),
                          scene.positions[free].copy()))
    dyn.attach(record, interval=interval)
    failure = None
    try:
        for check in checks:
            dyn.run(steps=check - dyn.nsteps)
            snapshot()
        if total > at_until:
            dyn.run(steps=total - at_until)
    except SimulationError as error:
        failure = error
    if not snapshots:
        snapshot()
    findings = []
    names = list(values[0]) if values else []
    rough = max((_roughness([v[n] for v in values]) for n in names),
                default=0.0)
    where = (f"dx = {dx * 1e3:g} mm, {setting.label()}, no optional effect, "
             f"{total} steps (t = {total * dyn.dt * 1e3:.3g} ms)")
    if driven:
        why = f"waves from the velocity step of {', '.join(driven)}"
    elif gravity or forced:
        why = "waves from the suddenly applied load"
    else:
        why = "waves"
    if _effect_available("artificial_viscosity") and (
            failure is not None or rough > 0.3):
        findings.append(Finding(
            "artificial_viscosity", {"alpha": 1.0, "beta": 0.0},
            f"{why}: undamped high-frequency modes grow",
            (f"blew up: {failure}" if failure is not None
             else f"probe roughness {rough:.3f} > 0.3") + f" ({where})",
            required=failure is not None))
    if not driven and not rotating and (gravity or forced) and kinetic:
        k = np.asarray(kinetic)
        tail = float(k[3 * len(k) // 4:].mean()) / max(float(k.max()), 1e-300)
        if (tail > 0.05 or failure is not None) and _effect_available(
                "damping"):
            c_p = max(_material_cp(scene, m) for m in _material_indices(scene))
            extent = float(np.max(np.ptp(x0, axis=0))) if len(x0) else dx
            rate = c_p / extent
            findings.append(Finding(
                "damping", {"rate": round(rate, -1)},
                "quasi-static loading: constant loads on a body at rest, the "
                "static field is the answer",
                f"kinetic energy over the last quarter {tail * 100:.0f} % of "
                f"its peak; rate c_p/L = {rate:.3g} /s"))
    # tension and rotation are judged on a run with the dissipation just
    # found: a ringing or blowing-up undamped run swings into tension
    dissipation = {f.effect: f.parameters for f in findings}
    stage = ""
    if dissipation:
        stage = " (run with " + ", ".join(dissipation) + ")"
        damped = build_scene(scene_factory, dx,
                             setting.with_effects(dissipation), threads)
        damped_dyn = make_dynamics(damped, integrator, progress=False)
        snapshots = []
        try:
            for check in checks:
                damped_dyn.run(steps=check - damped_dyn.nsteps)
                damped.calc.sync()
                snapshots.append((damped.stress[free].copy(),
                                  damped.positions[free].copy()))
        except SimulationError:
            pass
        if not snapshots:
            damped.calc.sync()
            snapshots.append((damped.stress[free].copy(),
                              damped.positions[free].copy()))
    if len(x0):
        shares = []
        for stress, _ in snapshots:
            top = float(np.max(np.abs(stress))) or 1.0
            shares.append(float(np.mean(
                _principal_max(stress, scene.dimension) > 0.1 * top)))
        share = min(shares)
        negative = _lib.kernel_negative_from(kernel, scene.dimension)
        if share > 0.1 and negative > 0.0:
            findings.append(Finding(
                None, {}, "sustained tension, but artificial_stress needs a "
                f"non-negative kernel ({kernel} is negative from q = "
                f"{negative:.3g}; the library refuses the pair)",
                f"{min(shares) * 100:.0f} % of the free particles in "
                "tension above 10 % of the peak stress" + stage))
        elif share > 0.1 and _effect_available("artificial_stress"):
            findings.append(Finding(
                "artificial_stress", _defaults("artificial_stress"),
                "sustained tension (tensile instability: clumping, "
                "numerical fracture)",
                "at t = " + ", ".join(f"{c * dyn.dt * 1e3:.3g}"
                                      for c in checks)
                + " ms, " + ", ".join(f"{x * 100:.0f}" for x in shares)
                + " % of the free particles in tension above 10 % of the "
                "peak stress" + stage, required=False))
        angle = _rotation_angle(x0, snapshots[-1][1]) if len(x0) > 2 else 0.0
        if (rotating or angle > 0.1) and _effect_available(
                "kernel_correction"):
            findings.append(Finding(
                "kernel_correction", {},
                "large rotation (uncorrected gradients give stress from "
                "rigid rotation)",
                (f"prescribed rotation of {', '.join(rotating)}" if rotating
                 else f"free bodies rotate by {angle:.2f} rad{stage}")))
    nu = max((_material_nu(scene, m) for m in _material_indices(scene)),
             default=0.0)
    if nu > 0.45:
        findings.append(Finding(
            None, {}, f"near-incompressible material (nu = {nu:.3f}): "
            "nothing extra at the default step (hard-case suite)",
            f"probe roughness {rough:.3f}"))
    for finding in findings:
        if (finding.effect is not None
                and (finding.effect, finding.reason) not in priced):
            try:
                finding.cost = _effect_cost(scene_factory, dx, setting,
                                            finding.effect,
                                            finding.parameters, threads)
            except (SimulationError, UnsupportedError):
                finding.cost = None
        say(f"  needs {finding.effect or '(nothing)'}: {finding.reason}; "
            f"{finding.measured}")
    return findings


def _material_indices(scene) -> list[int]:
    return sorted({index for _, index in scene._materials.values()})


def _material_info(scene, index):
    info = _lib.MaterialInfo()
    _lib.check(lib.sph_material_info_get(scene.handle, index,
                                         ctypes.byref(info)), scene.handle,
               "material")
    return info


def _material_cp(scene, index) -> float:
    return _material_info(scene, index).c_p


def _material_nu(scene, index) -> float:
    return _material_info(scene, index).poisson_ratio
