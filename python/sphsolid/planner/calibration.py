"""Calibration runs: a setting's scene built at a spacing and run to the
end time, its probe series recorded."""
from __future__ import annotations

import ctypes
import inspect
import math
import time as wallclock
from dataclasses import dataclass, field

import numpy as np

from .. import _lib, metrics
from .._lib import SimulationError, UnsupportedError
from .settings import DEFAULT_INTEGRATOR, MANAGED_EFFECTS, Setting, _optional_function, integrator_names


# ------------------------------------------------- building and running
def _accepts(function, name: str) -> bool:
    try:
        parameters = inspect.signature(function).parameters
    except (TypeError, ValueError):
        return False
    return name in parameters or any(
        p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values())


def factory_options(scene_factory) -> dict:
    """Which settings a factory accepts besides dx."""
    return {key: _accepts(scene_factory, key)
            for key in ("smoothing_ratio", "kernel", "inset")}


def _set_integrator(scene, name: str) -> None:
    if name == DEFAULT_INTEGRATOR and name not in integrator_names()[1:]:
        return
    setter = getattr(scene, "set_integrator", None)
    if callable(setter):
        setter(name)
        return
    function = _optional_function("sph_set_integrator", ctypes.c_int,
                                  [ctypes.c_void_p, ctypes.c_char_p])
    if function is None:
        if name == DEFAULT_INTEGRATOR:
            return
        raise UnsupportedError(f"integrator {name!r}: this library has no "
                               "sph_set_integrator")
    _lib.check(function(scene.handle, name.encode()), scene.handle,
               f"integrator {name!r}")


def build_scene(scene_factory, dx: float, setting: Setting,
                threads: int | None = None, calculator: bool = True):
    """The factory's scene at ``dx`` with ``setting`` applied: h/dx and
    kernel passed to the factory, the managed effects replaced by the
    setting's, the integrator set, and a C-library calculator with
    ``threads`` (unless ``calculator`` is False)."""
    from ..calculators import CLibrary
    accepted = factory_options(scene_factory)
    kwargs = {}
    for key, default in (("smoothing_ratio", 1.2), ("kernel", "cubic_spline"),
                         ("inset", 0.0)):
        value = getattr(setting, key)
        if accepted[key]:
            kwargs[key] = value
        elif not accepted[key] and value != default:
            raise UnsupportedError(f"the scene factory takes no {key}= "
                                   f"(needed for {key} = {value!r})")
    scene = scene_factory(dx, **kwargs)
    for name in MANAGED_EFFECTS:
        if name in scene.effects:
            scene.effect_off(name)
    for name, params in setting.effects:
        scene.effect(name, **dict(params))
    _set_integrator(scene, setting.integrator)
    if calculator:
        scene.calc = CLibrary(threads=threads)
    return scene


def make_dynamics(scene, integrator: str = DEFAULT_INTEGRATOR, **kwargs):
    """The dynamics object that advances ``scene`` with ``integrator``:
    the class of :mod:`sphsolid.dynamics` registered for it when there is
    one, else the library's run driver through :class:`ImprovedEuler`'s
    schedule (which steps with the handle's integrator)."""
    from .. import dynamics
    lookup = getattr(dynamics, "dynamics_for", None)
    if callable(lookup):
        return lookup(integrator)(scene, **kwargs)
    for name in dir(dynamics):
        cls = getattr(dynamics, name)
        if (isinstance(cls, type) and getattr(cls, "integrator", None)
                == integrator):
            return cls(scene, **kwargs)
    return dynamics.ImprovedEuler(scene, **kwargs)


def _observer(scene, probes, quantity: str):
    """A function returning {probe: value} now, for point probes (mapping)
    or a user callable(scene) -> mapping."""
    if callable(probes):
        return lambda: {k: float(v) for k, v in probes(scene).items()}
    from ..probes import Probes
    points = Probes(scene, probes)
    if quantity not in points.values:
        raise ValueError(f"quantity must be one of {points.values}, got "
                         f"{quantity!r}")
    column = points.values.index(quantity)

    def sample():
        values = points._sample_array()
        return {name: float(values[i, column])
                for i, name in enumerate(points.names)}
    return sample


@dataclass
class LadderRun:
    """One calibration run: what was run and what it cost."""
    setting: Setting
    dx: float
    particles: int
    steps: int
    dt: float
    wall: float                 # seconds stepping (probes included)
    until: float
    times: np.ndarray = field(repr=False, default=None)
    series: dict = field(repr=False, default=None)
    failed: str | None = None
    cpu: float = math.nan       # process CPU seconds stepping (all threads)
    threads: int | None = None

    @property
    def seconds_per_step(self) -> float:
        return self.wall / max(self.steps, 1)

    @property
    def particle_steps(self) -> int:
        return int(self.particles) * int(self.steps)

    def summary(self) -> dict:
        return {"setting": self.setting.label(), "dx": self.dx,
                "particles": self.particles, "steps": self.steps,
                "dt": self.dt, "wall": self.wall, "cpu": self.cpu,
                "threads": self.threads, "failed": self.failed}


def run_scene(scene, until: float, probes, quantity: str = "von_mises",
              integrator: str = DEFAULT_INTEGRATOR,
              sample_every: float | None = None, clocks: dict | None = None,
              setting=None):
    """Advance ``scene`` to ``until`` [s] sampling ``probes`` every
    ``sample_every`` [s] (default: 0.5 µs or 1/2000 of the run); returns
    (times, {probe: values}, dynamics, wall seconds of stepping). The
    process CPU seconds of the stepping go to ``clocks["cpu"]`` when
    ``clocks`` is given. With ``setting`` its integrator and step
    advance the scene (:meth:`Setting.dynamics`)."""
    sample = _observer(scene, probes, quantity)
    dyn = (setting.dynamics(scene, progress=False) if setting is not None
           else make_dynamics(scene, integrator, progress=False))
    every = sample_every or min(metrics.SMOOTHING / 2, until / 2000)
    interval = max(1, int(every / dyn.dt))
    times, values = [], []

    def record():
        scene.calc.sync()
        times.append(scene.time)
        values.append(sample())
    dyn.attach(record, interval=interval)
    start, cpu = wallclock.perf_counter(), wallclock.process_time()
    try:
        dyn.run(until=until)
    finally:
        if clocks is not None:
            clocks["cpu"] = wallclock.process_time() - cpu
    wall = wallclock.perf_counter() - start
    if not times or times[-1] < scene.time:
        record()
    names = list(values[0]) if values else []
    return (np.array(times), {n: np.array([v[n] for v in values])
                              for n in names}, dyn, wall)


def ladder_run(scene_factory, dx, setting, until, probes, quantity,
               threads) -> LadderRun:
    scene = build_scene(scene_factory, dx, setting, threads)
    clocks = {}
    try:
        times, series, dyn, wall = run_scene(scene, until, probes, quantity,
                                             setting.integrator,
                                             clocks=clocks, setting=setting)
    except SimulationError as error:
        return LadderRun(setting, dx, len(scene), int(scene.step),
                         float(scene.calc.dt), math.nan, until,
                         failed=str(error), threads=threads)
    return LadderRun(setting, dx, len(scene), dyn.nsteps, dyn.dt, wall, until,
                     times, series, cpu=clocks.get("cpu", math.nan),
                     threads=threads)
