"""Accuracy on demand: ask for an error, get the settings, the time and the
evidence.

:func:`plan` takes a scene factory ``scene_factory(dx, smoothing_ratio=...,
kernel=...)`` that builds the user's scene (bodies, materials, loads) at a
particle spacing ``dx``, and a request (an error on probe time series over
``[0, until]``), and returns a :class:`Plan`: the cheapest settings (dx,
h/dx, kernel, integrator, effects) predicted to meet the request, the
predicted error with its uncertainty, the predicted wall time and the runs
it is based on, or an honest refusal naming the best reachable error.

How (orchestration only; every run is the C library's):

1. **Options** are asked from the library at run time: kernels
   (:func:`kernel_names`), integrators (:func:`integrator_names`) and
   effects (:func:`sphsolid.effect_names`); a missing option is left out.
2. **Effects the scene calls for** (:func:`detect_effects`): one run at
   the coarsest spacing with no optional effect, for as many steps as the
   finest run the plan may choose (so a growth that only shows after many
   steps is seen), per integrator. Sustained tension -> artificial stress;
   large rotation -> kernel correction; a constant load on a body at rest
   that keeps ringing -> damping; a blow-up or rough probe series ->
   artificial viscosity; near-incompressible material is reported (the
   hard-case suite needs nothing extra for it). Each finding carries its
   reason and its measured cost per step.
3. **Calibration ladder**: every candidate setting at the spacings of
   ``ladder`` (coarse; 3 or more), to ``until`` (or a shorter
   ``calibration_until`` when the user knows that is sound).
4. **Error model** per setting (:class:`ErrorModel`): the probe series are
   smoothed (Gaussian, 1 µs) and put on one grid; the norms of the
   differences between consecutive levels are fitted by least squares to
   ``C (dx_i^q - dx_{i+1}^q)`` over every level (Eça & Hoekstra's
   least-squares order, written on differences: no extrapolated limit
   series, which for a sharpening front is itself 10-16 % off the exact
   one on the strip), giving ``E(dx) = C dx^q``. Predictions carry the
   safety factor of Eça & Hoekstra (1.25 for an order in [0.5, 2.1] with
   a good fit, 3 otherwise), because the request must be met, not just
   met on average. Self-convergence cannot see a bias that does not go
   away with dx (the lattice moment at fixed h/dx, a dissipation floor):
   where two settings differ by an amount that does not shrink with
   refinement, or by more than their own predicted errors explain, the
   difference is a **floor** added to the prediction
   (:func:`consistency_floors`).
5. **Cost model** per setting (:class:`CostModel`): process CPU seconds
   per step against particles, fitted on the ladder's own runs at the
   requested thread count (CPU time, because wall time on a loaded
   machine is mostly the load), with the wall/CPU ratio of the same runs
   for the wall-time prediction; a spacing finer than the ladder's is
   checked by timing steps there and at the finest calibrated spacing
   (cache effects make large scenes dearer per particle; within the
   ladder's sizes its whole runs are the better measurement). Settings
   are ranked by predicted CPU seconds.
6. The cheapest setting whose predicted upper error is within the request
   and whose predicted time is within ``max_seconds`` is returned.

The planner never extrapolates more than ``max_refinement`` (default 2)
times below the finest calibrated spacing: it calibrates finer levels for
the most promising settings, and for those whose ladder determines no
order (within ``calibration_seconds``), or says so.
"""
from __future__ import annotations

import ctypes
import inspect
import itertools
import json
import math
import time as wallclock
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable, Mapping, Sequence

import numpy as np

from . import _lib, metrics
from ._lib import SimulationError, UnsupportedError, lib

__all__ = ["plan", "Plan", "Setting", "ErrorModel", "CostModel", "Finding",
           "LadderRun", "fit_error_model", "fit_order", "repeating_factor",
           "consistency_floors", "kernel_names",
           "integrator_names", "detect_effects", "build_scene",
           "make_dynamics", "run_scene", "DEFAULT_INTEGRATOR"]

DEFAULT_INTEGRATOR = "improved_euler"
#: h/dx values tried: the library's default and the wider support that the
#: validation study found more accurate.
SMOOTHING_RATIOS = (1.2, 1.5)
#: Kernels accurate at their own h/dx, with the end placement matched to
#: it: candidates only at that setting (kernel -> (h/dx, inset)). cubic_o4
#: at h/dx 1.65 with the static platen inset is the validation study's
#: most accurate setting per CPU second on the piston test (the "waves"
#: preset; its lattice moment vanishes, so its error converges at a higher
#: order than the cubic spline's).
OWN_SETTING = {"cubic_o4": (1.65, "static")}
#: The representative of the other kernels in the effect detection.
STANDARD = ("cubic_spline", 1.2, 0.0)
#: Effects the planner decides (switched off in the factory's scene first).
MANAGED_EFFECTS = ("artificial_viscosity", "artificial_stress",
                   "kernel_correction", "damping", "xsph")
#: GCI safety factors (Roache 1998): consistent observed order / otherwise.
SAFETY_GOOD, SAFETY_POOR = 1.25, 3.0


# ------------------------------------------------------------ options
def _optional_function(name, restype, argtypes):
    """A library function that may not exist in this build (None then)."""
    try:
        library_path = _lib.library_path()  # loads the library
    except OSError:
        return None
    cdll = lib._cdll
    function = getattr(cdll, name, None) if cdll is not None else None
    if function is None:
        return None
    function.restype, function.argtypes = restype, argtypes
    del library_path
    return function


def kernel_names() -> list[str]:
    """Kernels the library offers, from its own registry
    (``sph_kernel_names``, else ``sph_kernel_name`` per number), else the
    default kernel alone."""
    listed = getattr(_lib, "kernel_names", None)
    if callable(listed):
        try:
            names = list(listed())
            if names:
                return names
        except (UnsupportedError, AttributeError):
            pass
    named = _optional_function("sph_kernel_name", ctypes.c_char_p,
                               [ctypes.c_int])
    names = []
    if named is not None:
        for index in range(64):
            value = named(index)
            if not value:
                break
            names.append(value.decode())
    return names or list(getattr(_lib, "KERNELS", {"cubic_spline": 0}))


def integrator_names() -> list[str]:
    """Integrators the library offers (``sph_integrator_names`` when it is
    exported), the default first."""
    from . import dynamics
    listed = getattr(dynamics, "integrator_names", None)
    if callable(listed):
        names = list(listed())
    else:
        function = _optional_function("sph_integrator_names", ctypes.c_char_p,
                                      [])
        names = function().decode().split() if function is not None else []
        if not names:
            names = [DEFAULT_INTEGRATOR]
    names = list(dict.fromkeys([DEFAULT_INTEGRATOR] + names))
    return names


def _effect_available(name: str) -> bool:
    return name in _lib.effect_names()


# ------------------------------------------------------------ settings
def _freeze(effects: Mapping[str, Mapping[str, float]] | None) -> tuple:
    return tuple(sorted((str(name), tuple(sorted((str(k), float(v))
                                                 for k, v in
                                                 (params or {}).items())))
                        for name, params in (effects or {}).items()))


@dataclass(frozen=True)
class Setting:
    """What the planner chooses besides dx: h/dx, kernel, integrator and
    the effects with their parameters."""
    smoothing_ratio: float = 1.2
    kernel: str = "cubic_spline"
    integrator: str = DEFAULT_INTEGRATOR
    effects: tuple = ()
    #: end placement of plates and pistons (lattice steps, or "static":
    #: see :func:`sphsolid.build.plate`); 0 puts their faces on the body
    inset: float | str = 0.0

    @classmethod
    def make(cls, smoothing_ratio=1.2, kernel="cubic_spline",
             integrator=DEFAULT_INTEGRATOR, effects=None,
             inset=0.0) -> "Setting":
        return cls(float(smoothing_ratio), str(kernel), str(integrator),
                   _freeze(effects),
                   inset if isinstance(inset, str) else float(inset))

    @property
    def effect_dict(self) -> dict:
        return {name: dict(params) for name, params in self.effects}

    def with_effects(self, effects: Mapping) -> "Setting":
        return Setting(self.smoothing_ratio, self.kernel, self.integrator,
                       _freeze(effects), self.inset)

    def label(self) -> str:
        short = {"artificial_viscosity": "visc", "artificial_stress": "AS",
                 "kernel_correction": "KC", "damping": "damp",
                 "xsph": "XSPH"}
        parts = []
        for name, params in self.effects:
            p = ",".join(f"{k}={v:g}" for k, v in params
                         if k in ("alpha", "rate", "epsilon"))
            parts.append(short.get(name, name) + (f"({p})" if p else ""))
        inset = ("" if self.inset in (0, 0.0) else
                 f" inset={self.inset}" if isinstance(self.inset, str)
                 else f" inset={self.inset:g}")
        return (f"{self.kernel} h/dx={self.smoothing_ratio:g}{inset} "
                f"{self.integrator}" + (" + " + " + ".join(parts)
                                        if parts else ""))

    def to_dict(self) -> dict:
        return {"smoothing_ratio": self.smoothing_ratio,
                "kernel": self.kernel, "integrator": self.integrator,
                "effects": self.effect_dict, "inset": self.inset}

    @classmethod
    def from_dict(cls, data: Mapping) -> "Setting":
        return cls.make(data.get("smoothing_ratio", 1.2),
                        data.get("kernel", "cubic_spline"),
                        data.get("integrator", DEFAULT_INTEGRATOR),
                        data.get("effects") or {}, data.get("inset", 0.0))


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
    from .calculators import CLibrary
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
    from . import dynamics
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
    from .probes import Probes
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
              sample_every: float | None = None, clocks: dict | None = None):
    """Advance ``scene`` to ``until`` [s] sampling ``probes`` every
    ``sample_every`` [s] (default: 0.5 µs or 1/2000 of the run); returns
    (times, {probe: values}, dynamics, wall seconds of stepping). The
    process CPU seconds of the stepping go to ``clocks["cpu"]`` when
    ``clocks`` is given."""
    sample = _observer(scene, probes, quantity)
    dyn = make_dynamics(scene, integrator, progress=False)
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
                                             clocks=clocks)
    except SimulationError as error:
        return LadderRun(setting, dx, len(scene), int(scene.step),
                         float(scene.calc.dt), math.nan, until,
                         failed=str(error), threads=threads)
    return LadderRun(setting, dx, len(scene), dyn.nsteps, dyn.dt, wall, until,
                     times, series, cpu=clocks.get("cpu", math.nan),
                     threads=threads)


# ----------------------------------------------------------- error model
def fit_order(spacings: Sequence[float], differences: Sequence[float],
              orders=np.arange(0.1, 6.001, 0.005)):
    """Observed order q and coefficient C of ``E(dx) = C dx^q`` from the
    norms of the differences between consecutive levels,
    ``D_i = |f(dx_i) - f(dx_{i+1})| = C (dx_i^q - dx_{i+1}^q)`` (for
    ``f = f* + C dx^q g`` with |g| = 1), by least squares in log D over a
    scan of q (for each q, log C is the mean residual in closed form).
    This is the Eça-Hoekstra least-squares estimate written on the
    differences, so no extrapolated limit series is needed. Returns
    (q, C, RMS log-residual)."""
    h = np.asarray(spacings, float)
    d = np.asarray(differences, float)
    if len(d) != len(h) - 1 or len(d) < 2:
        raise ValueError(f"need 3 or more spacings and one difference per "
                         f"consecutive pair, got {len(h)} and {len(d)}")
    if np.any(~np.isfinite(d)) or np.any(d <= 0):
        raise ValueError(f"differences must be positive and finite, got "
                         f"{list(d)}")
    if np.any(np.diff(h) >= 0):
        raise ValueError(f"spacings must decrease, got {list(h)}")
    best = None
    for q in orders:
        basis = np.log(h[:-1] ** q - h[1:] ** q)
        logc = float(np.mean(np.log(d) - basis))
        resid = np.log(d) - basis - logc
        score = float(np.sum(resid ** 2))
        if best is None or score < best[0] - 1e-12:
            best = (score, float(q), logc)
    score, q, logc = best
    return q, math.exp(logc), math.sqrt(score / len(d))


@dataclass
class ErrorModel:
    """E(dx) = C dx^order (+ floor): the predicted error of one setting.

    ``levels`` are (dx, estimated error C dx^order) of the ladder and
    ``differences`` the measured norms between consecutive levels;
    ``safety`` is the factor applied to the power law in :meth:`upper`;
    ``floor`` a bias the settings' disagreement shows; ``spread`` the
    largest deviation between any two calibrated levels (Eça &
    Hoekstra's data range Delta_M).
    """
    order: float
    coefficient: float
    safety: float
    floor: float
    residual: float
    levels: list
    differences: list
    finest: float
    max_refinement: float = 4.0
    spread: float | None = None
    anomalous: bool = False
    observed_order: float | None = None
    #: the share of the power law that repeats from level to level
    #: (:func:`repeating_factor`; 1: all of it)
    repeating: float = 1.0

    @property
    def data_range(self) -> float:
        """Delta_M: the largest deviation between two calibrated levels
        (when not measured, the sum of the consecutive differences, which
        bounds it)."""
        if self.spread is not None:
            return float(self.spread)
        return float(sum(self.differences))

    @property
    def range_bound(self) -> bool:
        """True when the differences follow no power law (Eça & Hoekstra's
        anomalous data: even the fixed-order fits scatter by more than
        :data:`ANOMALOUS_RESIDUAL`): at the calibrated spacings and below
        the error is bounded by 3 Delta_M instead (Eça & Hoekstra 2014)."""
        return self.anomalous

    @property
    def coarsest(self) -> float:
        return max(dx for dx, _ in self.levels)

    def power(self, dx: float) -> float:
        """Central estimate of the error that refinement removes, at dx
        (anomalous data: the data range, at every spacing)."""
        if self.anomalous:
            return self.data_range
        return self.repeating * self.coefficient * dx ** self.order

    def predict(self, dx: float) -> float:
        """Central prediction of the error at ``dx``."""
        return self.power(dx) + self.floor

    def upper(self, dx: float) -> float:
        """Conservative prediction: safety x power law + floor, or
        3 Delta_M + floor where that bound applies and is smaller."""
        if self.anomalous:
            return SAFETY_POOR * self.data_range + self.floor
        return self.safety * self.power(dx) + self.floor

    def spacing_for(self, error: float) -> float | None:
        """Largest dx whose :meth:`upper` is within ``error`` (None if the
        floor, or for anomalous data the bound 3 Delta_M, is already at or
        above it; anomalous data give the coarsest calibrated spacing,
        where the bound holds)."""
        room = error - self.floor
        if room <= 0:
            return None
        if self.anomalous:
            return (self.coarsest if SAFETY_POOR * self.data_range <= room
                    else None)
        return (room / (self.safety * self.repeating * self.coefficient)
                ) ** (1.0 / self.order)

    @property
    def smallest_dx(self) -> float:
        return self.finest / self.max_refinement

    def to_dict(self) -> dict:
        return {"order": self.order, "observed_order": self.observed_order,
                "coefficient": self.coefficient,
                "safety": self.safety, "floor": self.floor,
                "anomalous": self.anomalous,
                "repeating": self.repeating,
                "data_range": self.data_range,
                "range_bound": self.range_bound,
                "log_residual": self.residual,
                "levels": [list(level) for level in self.levels],
                "differences": list(self.differences)}


#: Largest RMS log-residual of the order fit for the small safety factor:
#: differences scattered by more than ~10 % about the power law are not
#: in the asymptotic range.
GOOD_RESIDUAL = 0.1
#: RMS log-residual above which even the best fixed-order fit (order 1 or
#: 2) does not describe the differences (a scatter of more than ~30 %):
#: no convergence is observed, the data range bounds the error.
ANOMALOUS_RESIDUAL = 0.25
#: Observed order below which the differences are taken not to shrink
#: (less than 13 % per halving of dx): no convergence is observed.
NO_CONVERGENCE = 0.2


#: Order of convergence the planner's predictions use at most: SPH with
#: free surfaces, plates and artificial viscosity is first-order
#: consistent there, and a front smoothed over a fixed time is not in its
#: asymptotic range while the kernel support is comparable to the
#: smoothing length (2.6 mm at c_p for 1 us).
FORMAL_ORDER = 1.0


def fit_error_model(spacings: Sequence[float], differences: Sequence[float],
                    floor: float = 0.0, max_refinement: float = 4.0,
                    spread: float | None = None,
                    max_order: float | None = None) -> ErrorModel:
    """:func:`fit_order` over every level plus the safety factor of Eça &
    Hoekstra (2014): 1.25 when the observed order is in [0.5, 2.1] and,
    with three or more differences, the fit is good (RMS log-residual
    below :data:`GOOD_RESIDUAL`); 3 otherwise (an order outside the range
    or scattered data make the power law a poor guide; an order below 0.5
    is kept, with Fs = 3). Differences that do not shrink (order below
    :data:`NO_CONVERGENCE`), or that neither the free fit nor a fit of
    fixed order 1 or 2 describes (RMS log-residual above
    :data:`ANOMALOUS_RESIDUAL`) are anomalous and the error of the
    calibrated levels is bounded by 3 Delta_M (``spread``: the largest
    deviation between two levels; default the sum of the differences,
    which bounds it).

    The order is the least-squares fit over all levels: on the project's
    scenes the order of the finest three levels alone swings with the
    scatter of two differences (0.2-0.9 where the full ladder and the
    exact solution agree on 0.6), so it is not used to lower the order.

    An observed order above ``max_order`` is not used: the coefficient is
    fitted again at ``max_order`` (Eça & Hoekstra use the theoretical
    order where the observed one exceeds it). On the strip, cubic_o4's
    differences fell at order 1.8 over 1.4-0.47 mm while its error against
    the exact front fell at 0.8-1.1; the order-1.8 prediction was 1.5x
    below the error (a 10 % plan achieved 11.7 %)."""
    h = np.asarray(spacings, float)
    q, c, resid = fit_order(h, differences)
    observed = q
    good = 0.5 <= q <= 2.1 and (len(differences) < 3
                                or resid < GOOD_RESIDUAL)
    # data that neither the free fit nor a fixed order (1 or 2, Eça &
    # Hoekstra's alternatives) describes are anomalous: the data range
    # bounds the error. An order below 0.5 that the data do follow is kept
    # (with Fs = 3): the project's fronts converge at 0.4-0.6 for real,
    # and the order-1 fit Eça & Hoekstra use instead predicted a third of
    # the strip's error two refinements down.
    # Differences that do not shrink (order below NO_CONVERGENCE) show no
    # convergence at all.
    anomalous = q < NO_CONVERGENCE or (
        len(differences) >= 3 and resid > ANOMALOUS_RESIDUAL
        and min(fit_order(h, differences, orders=[p])[2]
                for p in (1.0, 2.0)) > ANOMALOUS_RESIDUAL)
    if max_order is not None and q > max_order:
        q, c, _ = fit_order(h, differences, orders=[float(max_order)])
    return ErrorModel(q, c, SAFETY_GOOD if good else SAFETY_POOR,
                      float(floor), resid,
                      [(float(d), float(c * d ** q)) for d in h],
                      [float(x) for x in differences], float(h.min()),
                      max_refinement, spread, anomalous, float(observed))


#: Correlations from level to level that :func:`repeating_factor` scans.
_CORRELATIONS = np.linspace(0.0, 1.0, 201)


def _decorrelating_gram(a: np.ndarray, pairs) -> np.ndarray:
    """Gram entries ``<d_i, d_j>`` of the differences of consecutive
    levels, per unit ``E^2``, for level errors ``e_k`` of RMS size ``E
    a_k`` whose correlation falls as ``rho^|k - l|`` from level ``k`` to
    level ``l``: one row per scanned ``rho`` (:data:`_CORRELATIONS`), one
    column per pair ``(i, j)``."""
    def inner(k, l, rho):
        return a[k] * a[l] * rho ** abs(k - l)
    return np.array([[inner(i, j, rho) - inner(i, j + 1, rho)
                      - inner(i + 1, j, rho) + inner(i + 1, j + 1, rho)
                      for i, j in pairs] for rho in _CORRELATIONS])


def repeating_factor(spacings: Sequence[float], levels: Sequence[Mapping],
                     order: float, norm: str = "rms") -> tuple[float, dict]:
    """How much of the error the differences of consecutive levels imply
    is really there, when each level's error is only partly the same as
    the next level's.

    :func:`fit_order` reads every difference as the change of one error
    shape, ``e_i = E h_i^q s``, so the differences ``d_i = e_i - e_{i+1}``
    are ``E (a_i - a_{i+1})`` with ``a_i = h_i^q``: a quarter to a half of
    the error for ladder ratios 1.33-2. If the shape itself changes from
    level to level (a particle lattice that changes with dx moves the
    error's details), the differences are nearly as large as the errors
    themselves. Model: errors of RMS size ``E a_k`` whose correlation
    falls as ``rho^|k - l|`` between levels k and l (``rho = 1``: one
    shape, the power law; ``rho = 0``: each level's error its own). Then

        <d_i, d_j> = E^2 (c_ij - c_i(j+1) - c_(i+1)j + c_(i+1)(j+1)),
        c_kl = a_k a_l rho^|k - l|,

    for every entry of the Gram matrix of the differences (RMS over the
    window, each probe on the finest level's RMS scale): ``E^2`` follows
    by least squares for each ``rho`` of a scan over [0, 1], and the pair
    with the least misfit is kept. The factor is ``E`` over the power law
    :func:`fit_order` fits to the same differences' sizes at ``order``,
    for the probe where it is largest (every probe's error is covered), at
    most 1; a probe whose consecutive differences do not anti-correlate
    on average gives 1 (a shape that repeats dominates them: the power law
    stands).

    ``norm="max"``: the factor is sqrt(2) times the RMS one (at most 1).
    The max norm has no inner product: the part a level shares with the
    next and its own part may peak at one point, where their sizes add,
    and ``|p| + |q| <= sqrt(2) sqrt(p^2 + q^2)``.

    Returns (factor, {probe: factor in the RMS norm}); 1 with fewer than
    four levels (three differences, six Gram entries for two unknowns).
    On the piston, cubic_o4's level errors against the finite-element
    solution correlate by 0.4-0.7 from one level to the next and by
    0.1-0.2 from 3 to 0.5 mm, and its consecutive differences
    anti-correlate (-0.04 to -0.45): on ladders of four levels from 3 to
    0.5 mm the fit gives ``rho`` 0.04-0.57 and factors 0.25-0.40 per
    probe, and the actual RMS error of every level from 3 to 0.5 mm is
    0.8-1.5 times ``E h^q``. A model of two parts, one shape shared by
    every level and a part of each level's own, gave 0.35-0.51 (actual
    errors 0.7-1.0 times its prediction): it reads what neighbouring
    levels share as one shape for all of them. The cubic spline's
    differences correlate (0.82-0.97): 1."""
    if norm not in ("rms", "max"):
        raise ValueError(f"repeating_factor: norm must be 'rms' or 'max', "
                         f"got {norm!r}")
    h = np.asarray(spacings, float)
    if len(levels) < 4 or len(levels) != len(h):
        return 1.0, {}
    a = h ** order
    pairs = list(itertools.combinations_with_replacement(range(len(h) - 1),
                                                         2))
    model = _decorrelating_gram(a, pairs)
    weight = np.einsum("ij,ij->i", model, model)
    per_probe = {}
    for name in levels[-1]:
        scale = metrics.scale_of(levels[-1][name], "rms")
        if not scale > 0:
            continue
        d = np.array([(x[name] - y[name]) / scale
                      for x, y in zip(levels, levels[1:])])
        gram = d @ d.T / d.shape[1]
        sizes = np.sqrt(np.maximum(np.diag(gram), 0.0))
        if sizes.min() <= 0:
            continue
        # only where consecutive differences anti-correlate do the data
        # show errors that do not repeat (a repeating shape makes them
        # correlate, and the power law stands)
        correlation = np.mean([gram[i, i + 1] / (sizes[i] * sizes[i + 1])
                               for i in range(len(h) - 2)])
        if correlation >= 0:
            per_probe[name] = 1.0
            continue
        g = np.array([gram[i, j] for i, j in pairs])
        size2 = np.maximum(model @ g, 0.0) / weight
        misfit = np.sum((model * size2[:, None] - g) ** 2, axis=1)
        # the power law of the differences alone, as fit_order fits it
        law = fit_order(h, sizes, orders=[float(order)])[1]
        per_probe[name] = (math.sqrt(float(size2[int(np.argmin(misfit))]))
                           / law)
    if not per_probe:
        return 1.0, {}
    factor = max(per_probe.values()) * (math.sqrt(2.0) if norm == "max"
                                        else 1.0)
    return min(1.0, factor), per_probe


def consistency_floors(models: Sequence[ErrorModel], levels: Sequence[list],
                       norm: str = "max",
                       spacings: Sequence[float] | None = None) -> list[float]:
    """Floors from the settings' disagreement that refinement does not
    remove.

    A bias that refinement does not remove (the lattice moment at fixed
    h/dx, a dissipation floor) is invisible to each setting's own ladder,
    but not to a comparison of settings: the difference of two settings
    at the same spacing, ``d(dx)``, must shrink with refinement if both
    converge to one limit at the rates their ladders show. A pair's floor
    is its difference at the finest common level, ``d_ab``, when

    - ``d`` does not shrink over the ladder (least-squares slope of
      log d against log dx below :data:`NO_CONVERGENCE`): nothing in the
      data says the two limits are closer than d_ab; or
    - ``d_ab`` exceeds the sum of the two central predictions there,
      ``P_a + P_b`` (two settings with one limit differ by at most the sum
      of their errors);

    else 0. A setting's floor is the lower median of its pairs' floors (a
    setting that disagrees with most others carries the bias, one that
    agrees with most does not; with two settings both carry it), over the
    pairs that can tell: a pair without a floor whose difference at the
    finest level is larger than the setting's largest pair floor does not
    show that their limits are closer than that floor (a setting far from
    converged explains any difference), so it does not count. (On the
    piston h/dx 1.2 and 1.5 differ by 3.7 % in the max norm at 1.5 mm, a
    difference that grows with refinement; cubic_o4 differs from both by
    11-12 %, shrinking slowly: it excused the cubic spline's bias, and a
    5 % plan with h/dx 1.2 achieved 8.9 %.)

    The first rule is conservative by design: h/dx 1.2 and 1.5 sharpen the
    strip's front at different rates, so their difference grows from 4 to
    7 % (RMS) down to 0.25 mm although both converge to the exact front,
    and the rule takes it for a floor; on the piston the same pattern
    (1.1 to 1.8 % RMS from 3 to 1.5 mm) is the only sign in the
    calibration that h/dx 1.2 converges towards a limit 4-5 % (RMS) away
    from the finite-element solution, which its self-convergence (order
    0.85) does not show: without the floor a 5 % RMS plan achieved 5.9 %.
    The data of the two scenes cannot tell the cases apart; the planner
    keeps its promise. ``levels[i]`` holds setting i's smoothed series
    {probe: array} at each of ``spacings`` (default the spacings of the
    first model's levels)."""
    n = len(models)
    if n < 2:
        return [0.0] * n
    spacings = np.array(spacings if spacings is not None else
                        [dx for dx, _ in models[0].levels], float)
    finest = float(spacings[-1])
    floors = np.zeros((n, n))
    last = np.zeros((n, n))
    for i, j in itertools.combinations(range(n), 2):
        d = np.array([max(metrics.deviation(a[p], c[p], norm,
                                            metrics.scale_of(c[p], norm))
                          for p in a) for a, c in zip(levels[i], levels[j])])
        explained = models[i].power(finest) + models[j].power(finest)
        shrinking = True
        if len(d) >= 2:
            slope = np.polyfit(np.log(spacings[:len(d)]),
                               np.log(np.maximum(d, 1e-12)), 1)[0]
            shrinking = slope >= NO_CONVERGENCE
        last[i, j] = last[j, i] = float(d[-1])
        if not shrinking or d[-1] > explained:
            floors[i, j] = floors[j, i] = float(d[-1])
    out = []
    for i in range(n):
        others = [j for j in range(n) if j != i]
        top = max(floors[i, j] for j in others)
        telling = sorted(floors[i, j] for j in others
                         if floors[i, j] > 0 or last[i, j] < top)
        out.append(float(telling[(len(telling) - 1) // 2]) if telling
                   else 0.0)
    return out


# ------------------------------------------------------------ cost model
@dataclass
class CostModel:
    """Seconds per step = a + b x particles of one setting at one thread
    count, fitted on its calibration runs' own measurements (least
    squares in the relative residual).

    The fit is on **process CPU seconds** (all threads of the process):
    on a machine shared with other jobs the wall time of a run depends on
    the load, its CPU time much less. ``wall_per_cpu`` (the median wall /
    CPU ratio of the same runs) turns it into wall time as the machine
    behaved during the calibration (1 / threads on an idle machine with
    perfect scaling; more under load or when threads wait). ``measured``
    holds corrections of the fit at particle counts the plan considered:
    a few steps timed there over the same timing at the finest calibrated
    spacing, relative to the fit's ratio of the two (large scenes cost
    more per particle than small ones; timing both alike keeps what the
    few-step timing leaves out, such as probe sampling, in the fit). Runs
    without a CPU time (a LAMMPS deck's ``Loop time``) are fitted on wall
    time, with ``wall_per_cpu`` 1."""
    intercept: float
    per_particle: float
    threads: int | None
    measured: dict = field(default_factory=dict)
    wall_per_cpu: float = 1.0
    clock: str = "cpu"

    @classmethod
    def fit(cls, particles, seconds_per_step, threads=None,
            wall_per_cpu: float = 1.0, clock: str = "cpu") -> "CostModel":
        n = np.asarray(particles, float)
        t = np.asarray(seconds_per_step, float)
        # residuals relative to each run's time: the runs span 40x in
        # time, and an unweighted fit follows the largest, missing the
        # smallest by up to 40 % (left out of their ladder in turn, the 66
        # calibration runs of a piston plan were predicted within 5.0 % on
        # average and 23 % at most, against 6.1 % and 40 % unweighted)
        w = 1.0 / t if np.all(t > 0) else np.ones_like(t)
        if len(n) >= 2 and np.ptp(n) > 0:
            b, a = np.polyfit(n, t, 1, w=w)
            if a < 0 or b <= 0:
                # through the origin, in the same relative terms
                a, b = 0.0, float(np.sum(w * w * t * n)
                                  / np.sum(w * w * n * n))
        else:
            a, b = 0.0, float(t.mean() / n.mean())
        return cls(float(a), float(b), threads, {}, float(wall_per_cpu),
                   clock)

    @classmethod
    def from_runs(cls, runs, threads=None) -> "CostModel":
        """The model of a setting from its calibration runs (CPU time when
        every run has it, else wall time)."""
        good = [r for r in runs if not r.failed and r.steps > 0]
        cpu = [r.cpu for r in good]
        if good and all(math.isfinite(c) and c > 0 for c in cpu):
            ratio = float(np.median([r.wall / r.cpu for r in good]))
            return cls.fit([r.particles for r in good],
                           [r.cpu / r.steps for r in good], threads, ratio,
                           "cpu")
        return cls.fit([r.particles for r in good],
                       [r.wall / r.steps for r in good], threads, 1.0, "wall")

    @property
    def particle_steps_per_second(self) -> float:
        """Throughput of large scenes (1 / per-particle cost)."""
        return 1.0 / self.per_particle if self.per_particle > 0 else math.inf

    def fitted(self, particles: int) -> float:
        """The fit's seconds per step (no timing correction)."""
        return self.intercept + self.per_particle * particles

    def correct(self, particles: int, seconds: float, reference: int,
                reference_seconds: float,
                measured_reference: float | None = None) -> float:
        """Record a timing check: ``seconds`` per step at ``particles``
        and ``reference_seconds`` at ``reference`` particles (the finest
        calibrated spacing), timed alike. With ``measured_reference`` (the
        calibration run's own seconds per step there, probe sampling and
        all) the prediction at ``particles`` is that cost plus the timed
        difference of the two sizes: what a step costs beyond the
        stepping (sampling a point probe) stays what it was, where a
        ratio would scale it with the scene. Without it, the fit's cost at
        ``reference`` times the timed ratio. Returns the correction factor
        of the fit at ``particles``."""
        if measured_reference and measured_reference > 0:
            target = measured_reference + (seconds - reference_seconds)
        else:
            target = self.fitted(reference) * seconds / reference_seconds
        factor = target / self.fitted(particles)
        self.measured[int(particles)] = float(factor)
        return factor

    def seconds_per_step(self, particles: int) -> float:
        """CPU (or, for wall-clock models, wall) seconds per step: the fit,
        times the correction of the nearest timing check."""
        base = self.fitted(particles)
        if self.measured:
            n0 = min(self.measured, key=lambda n: abs(math.log(n / particles)))
            base *= self.measured[n0]
        return base

    def predict_cpu(self, particles: int, steps: int) -> float:
        """Predicted CPU seconds of a run (wall seconds for a wall-clock
        model)."""
        return steps * self.seconds_per_step(particles)

    def predict(self, particles: int, steps: int) -> float:
        """Predicted wall seconds of a run, at the load of the
        calibration."""
        return self.predict_cpu(particles, steps) * self.wall_per_cpu

    def to_dict(self) -> dict:
        return {"clock": self.clock, "intercept_s": self.intercept,
                "per_particle_step_s": self.per_particle,
                "particle_steps_per_s": self.particle_steps_per_second,
                "threads": self.threads, "wall_per_cpu": self.wall_per_cpu,
                "timing_correction": {str(k): v for k, v in
                                      self.measured.items()}}


def time_steps(scene_factory, dx, setting, threads, steps: int = 5,
               warmup: int = 2, clock: str = "cpu", min_seconds: float = 0.0
               ) -> tuple[int, float, float]:
    """(particles, dt, seconds per step) of a few steps at ``dx``: process
    CPU seconds (``clock="cpu"``) or wall seconds (``"wall"``), over blocks
    of ``steps`` steps until ``min_seconds`` have passed (at least one
    block)."""
    scene = build_scene(scene_factory, dx, setting, threads)
    dyn = make_dynamics(scene, setting.integrator, progress=False)
    dyn.run(steps=warmup)
    timer = (wallclock.process_time if clock == "cpu"
             else wallclock.perf_counter)
    start, done = timer(), 0
    while True:
        dyn.run(steps=steps)
        done += steps
        elapsed = timer() - start
        if elapsed >= min_seconds:
            return len(scene), dyn.dt, elapsed / done


#: Least duration of a timing check (seconds of its clock, at each of the
#: two sizes): five steps of the strip at 0.36 mm, a few milliseconds,
#: had set a plan's prediction 1.7x above its run.
TIMING_SECONDS = 0.25


#: A calibration run shorter than this (seconds of its clock) that
#: anchors a timing check is measured again (:func:`reference_cost`).
REFERENCE_REPEAT_SECONDS = 1.0


def reference_cost(run: LadderRun, clock: str,
                   again: Callable[[], LadderRun]) -> float | None:
    """Seconds per step of the calibration run that anchors a timing check
    (``clock``: "cpu" or "wall"). Other work on the machine only slows a
    run down, never speeds it up, so a run shorter than
    :data:`REFERENCE_REPEAT_SECONDS` is measured again (``again()``, the
    same run) and the faster of the two is its cost: a 0.17 s calibration
    run of the strip at 0.467 mm had taken 1.04 ms per step where its
    repeats take 0.73-0.74, and set two plans' predictions 31-52 % above
    their runs. None for a run without steps."""
    if not run.steps:
        return None

    def cost(r):
        return r.cpu if clock == "cpu" else r.wall
    spent = cost(run)
    if spent < REFERENCE_REPEAT_SECONDS:
        repeat = again()
        if not repeat.failed and repeat.steps == run.steps:
            spent = min(spent, cost(repeat))
    return spent / run.steps


def _steps_to(scene_factory, dx, setting, until) -> tuple[int, float]:
    """(particles, steps) of a run to ``until`` at ``dx``, from the scene
    itself (the library's default step of this setting)."""
    scene = build_scene(scene_factory, dx, setting, 1)
    dyn = make_dynamics(scene, setting.integrator, progress=False)
    return len(scene), int(math.ceil(until / dyn.dt - 1e-9))


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
                   inset: float | str = 0.0) -> list[Finding]:
    """What the scene calls for, measured on one run at ``dx`` with no
    optional effect, ``integrator``, ``kernel``, ``smoothing_ratio`` and
    end placement ``inset``, for ``steps`` steps (default: to ``until``).

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
        if share > 0.1 and _effect_available("artificial_stress"):
            findings.append(Finding(
                "artificial_stress", {"epsilon": 0.3, "n": 4.0},
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
        if finding.effect is not None:
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


# ------------------------------------------------------------------- plan
@dataclass
class Candidate:
    """A setting with its models and the spacing and cost it needs."""
    setting: Setting
    runs: list
    model: ErrorModel | None = None
    cost: CostModel | None = None
    limit: dict | None = None
    dx: float | None = None
    particles: int | None = None
    steps: int | None = None
    seconds: float | None = None
    cpu_seconds: float | None = None
    note: str = ""

    def to_dict(self) -> dict:
        return {"setting": self.setting.to_dict(),
                "label": self.setting.label(),
                "error_model": self.model.to_dict() if self.model else None,
                "cost_model": self.cost.to_dict() if self.cost else None,
                "dx": self.dx, "particles": self.particles,
                "steps": self.steps, "predicted_seconds": self.seconds,
                "predicted_cpu_seconds": self.cpu_seconds,
                "predicted_error": (self.model.predict(self.dx)
                                    if self.model and self.dx else None),
                "error_upper": (self.model.upper(self.dx)
                                if self.model and self.dx else None),
                "note": self.note,
                "runs": [r.summary() for r in self.runs]}


@dataclass
class Plan:
    """The planner's answer. ``feasible`` False means refused: ``reason``
    says why and ``best_reachable_error`` what can be had."""
    request: dict
    feasible: bool
    setting: Setting | None = None
    dx: float | None = None
    threads: int | None = None
    predicted_error: float | None = None
    error_upper: float | None = None
    predicted_seconds: float | None = None
    predicted_cpu_seconds: float | None = None
    particles: int | None = None
    steps: int | None = None
    reason: str = ""
    best_reachable_error: float | None = None
    findings: list = field(default_factory=list)
    candidates: list = field(default_factory=list)
    calibration_seconds: float = 0.0
    scene: str = ""
    effects_examined: bool = True
    #: the error model of the chosen setting (``ErrorModel.to_dict()``):
    #: the calibration a run's error estimate uses
    #: (:class:`sphsolid.estimate.ErrorEstimate`)
    calibration: dict | None = None

    # ------------------------------------------------------------ output
    def to_dict(self) -> dict:
        settings = None
        if self.setting is not None:
            settings = {"dx": self.dx, **self.setting.to_dict(),
                        "threads": self.threads}
        return {"format": "sphsolid-plan 1", "scene": self.scene,
                "request": self.request, "feasible": self.feasible,
                "settings": settings,
                "predicted_error": self.predicted_error,
                "error_uncertainty": (None if self.error_upper is None else
                                      self.error_upper - self.predicted_error),
                "error_upper": self.error_upper,
                "predicted_seconds": self.predicted_seconds,
                "predicted_cpu_seconds": self.predicted_cpu_seconds,
                "error_model": self.calibration,
                "particles": self.particles, "steps": self.steps,
                "reason": self.reason,
                "best_reachable_error": self.best_reachable_error,
                "effects": [f.to_dict() for f in self.findings],
                "calibration_seconds": self.calibration_seconds,
                "library": _lib.version(),
                "evidence": [c.to_dict() for c in self.candidates]}

    def save(self, path) -> Path:
        path = Path(path)
        path.write_text(json.dumps(self.to_dict(), indent=1, default=float))
        return path

    @classmethod
    def load(cls, path) -> "Plan":
        """Read a plan.json (the settings and predictions; the evidence
        stays in the file)."""
        data = json.loads(Path(path).read_text())
        if not str(data.get("format", "")).startswith("sphsolid-plan"):
            raise ValueError(f"{path}: not a plan file (no 'format': "
                             "'sphsolid-plan ...')")
        settings = data.get("settings")
        plan = cls(request=data.get("request", {}),
                   feasible=bool(data.get("feasible")),
                   reason=data.get("reason", ""),
                   best_reachable_error=data.get("best_reachable_error"),
                   predicted_error=data.get("predicted_error"),
                   error_upper=data.get("error_upper"),
                   predicted_seconds=data.get("predicted_seconds"),
                   predicted_cpu_seconds=data.get("predicted_cpu_seconds"),
                   particles=data.get("particles"), steps=data.get("steps"),
                   scene=data.get("scene", ""),
                   calibration=data.get("error_model"))
        plan.findings = [Finding(**f) for f in data.get("effects", [])]
        if settings:
            plan.setting = Setting.from_dict(settings)
            plan.dx = float(settings["dx"])
            plan.threads = settings.get("threads")
        return plan

    def build(self, scene_factory, threads: int | None = None,
              calculator: bool = True):
        """The planned scene (``threads`` overrides the plan's; with
        ``calculator`` False the caller attaches one)."""
        if not self.feasible or self.setting is None:
            raise ValueError(f"the plan was refused: {self.reason}")
        return build_scene(scene_factory, self.dx, self.setting,
                           self.threads if threads is None else threads,
                           calculator)

    def summary(self) -> str:
        """A table for people."""
        r = self.request
        norm = r.get("norm", "max")
        lines = [f"request: {norm} deviation of {r.get('quantity')} at "
                 f"{', '.join(r.get('probes', []))} <= "
                 f"{r.get('error', 0) * 100:g} % over 0-"
                 f"{r.get('until', 0) * 1e3:g} ms"
                 + (f" within {r['max_seconds']:g} s"
                    if r.get("max_seconds") else "")
                 + f", threads {r.get('threads') or 'default'}"]
        lines.append("effects the scene calls for:")
        if not self.effects_examined:
            lines.append("  not examined (the deck's own effects are kept)")
        elif not any(f.effect for f in self.findings):
            lines.append("  none")
        for f in self.findings:
            cost = ("" if f.cost is None else f"; cost {f.cost * 100:+.0f} % "
                    "per step")
            lines.append(f"  {f.effect or '-'}: {f.reason} ({f.measured}"
                         f"{cost})")
        lines.append("")
        header = (f"{'setting':<58} {'order':>5} {'Fs':>4} {'rep.':>4} "
                  f"{'floor':>6} "
                  f"{'dx [mm]':>8} {'error':>7} {'upper':>7} {'CPU [s]':>9} "
                  f"{'wall [s]':>9}")
        lines.append(header)
        lines.append("-" * len(header))
        for c in self.candidates:
            m = c.model
            if m is None:
                lines.append(f"{c.setting.label():<58} {c.note}")
                continue
            dx = f"{c.dx * 1e3:8.3g}" if c.dx else f"{'-':>8}"
            err = (f"{m.predict(c.dx) * 100:6.2f}%" if c.dx else f"{'-':>7}")
            up = (f"{m.upper(c.dx) * 100:6.2f}%" if c.dx else f"{'-':>7}")
            sec = f"{c.seconds:9.3g}" if c.seconds else f"{'-':>9}"
            cpu = (f"{c.cpu_seconds:9.3g}" if c.cpu_seconds
                   else f"{'-':>9}")
            mark = " <" if (self.setting == c.setting
                            and self.feasible) else ""
            lines.append(f"{c.setting.label():<58} {m.order:5.2f} "
                         f"{m.safety:4.2f} {m.repeating:4.2f} "
                         f"{m.floor * 100:5.2f}% {dx} {err} "
                         f"{up} {cpu} {sec}{mark}"
                         + (f"  {c.note}" if c.note else ""))
        lines.append("")
        if self.feasible:
            lines.append(
                f"plan: {self.setting.label()}, dx = {self.dx * 1e3:.4g} mm "
                f"({self.particles} particles, {self.steps} steps): predicted "
                f"error {self.predicted_error * 100:.2f} % (at most "
                f"{self.error_upper * 100:.2f} %), predicted wall time "
                f"{self.predicted_seconds:.3g} s"
                + (f" (CPU {self.predicted_cpu_seconds:.3g} s; wall at the "
                   "load of the calibration)"
                   if self.predicted_cpu_seconds else ""))
        else:
            lines.append(f"refused: {self.reason}")
        lines.append(f"calibration took {self.calibration_seconds:.1f} s")
        return "\n".join(lines)


def _check_request(error, until, norm, max_seconds, ladder):
    if not (isinstance(error, (int, float)) and 0 < error < 1):
        raise ValueError(f"error must be a fraction in (0, 1) (0.03 for 3 %),"
                         f" got {error!r}")
    if not (isinstance(until, (int, float)) and until > 0
            and math.isfinite(until)):
        raise ValueError(f"until must be a time > 0 s, got {until!r}")
    if norm not in ("max", "rms"):
        raise ValueError(f"norm must be 'max' or 'rms', got {norm!r}")
    if max_seconds is not None and not max_seconds > 0:
        raise ValueError(f"max_seconds must be > 0, got {max_seconds!r}")
    if ladder is None or len(ladder) < 3:
        raise ValueError(f"ladder must list 3 or more coarse spacings [m], "
                         f"got {ladder!r}")
    if any(not (d > 0) for d in ladder):
        raise ValueError(f"ladder spacings must be > 0, got {ladder!r}")


def detection_families(scene_factory, kernels: Sequence[str] | None = None,
                       own_settings: bool = True) -> list[tuple]:
    """(kernel, h/dx, inset) of the effect detection runs: the default
    kernel at h/dx 1.2 for the kernels tried at :data:`SMOOTHING_RATIOS`,
    and each kernel of :data:`OWN_SETTING` the library and the factory
    offer (and ``kernels`` names, when given) at its own setting (the
    static inset only when the factory takes ``inset``)."""
    accepted = factory_options(scene_factory)
    families = [STANDARD]
    if not (own_settings and accepted["kernel"]):
        return families
    offered = kernel_names()
    for kernel, (ratio, inset) in OWN_SETTING.items():
        if kernel in offered and (kernels is None or kernel in kernels):
            families.append((kernel, ratio if accepted["smoothing_ratio"]
                             else 1.2, inset if accepted["inset"] else 0.0))
    return families


def default_candidates(scene_factory, findings_by: dict,
                       extra_kernel_correction: bool = True,
                       kernels: Sequence[str] | None = None,
                       ratios: Sequence[float] | None = None,
                       own_settings: bool = True) -> list:
    """Every kernel x h/dx x integrator the library and the factory offer
    (or those of ``kernels`` and ``ratios`` among them), each with the
    effects found for its integrator (and, as an accuracy option, with
    kernel correction added); the kernels of :data:`OWN_SETTING` at their
    own h/dx and end placement, with the effects found for them.
    ``findings_by`` maps (integrator, family) to the findings of that
    detection run (:func:`detection_families`; a bare integrator key is
    the standard family)."""
    accepted = factory_options(scene_factory)
    offered = kernel_names() if accepted["kernel"] else ["cubic_spline"]
    default = [k for k in offered if k not in OWN_SETTING]
    standard = [k for k in (kernels or default)
                if k in offered and k not in OWN_SETTING]
    ratios = ((ratios or SMOOTHING_RATIOS) if accepted["smoothing_ratio"]
              else (1.2,))
    out = []
    for key, findings in findings_by.items():
        integrator, family = key if isinstance(key, tuple) else (key,
                                                                 STANDARD)
        effects = {f.effect: f.parameters for f in findings if f.effect}
        variants = [effects]
        if (extra_kernel_correction and "kernel_correction" not in effects
                and _effect_available("kernel_correction")):
            variants.append({**effects, "kernel_correction": {}})
        if family == STANDARD:
            for kernel, ratio, eff in itertools.product(standard, ratios,
                                                        variants):
                out.append(Setting.make(ratio, kernel, integrator, eff))
        elif own_settings:
            # these kernels run without dissipation on wave problems
            # (their rough raw series is their own high-frequency content,
            # not a growth): effects found from a sign rather than a
            # failure are tried both ways, the calibration decides (a
            # variant that fails there drops out)
            kernel, ratio, inset = family
            needed = {f.effect: f.parameters for f in findings
                      if f.effect and f.required}
            for eff in ([effects, needed] if needed != effects
                        else [effects]):
                out.append(Setting.make(ratio, kernel, integrator, eff,
                                        inset))
    return out


def plan(scene_factory: Callable, error: float = 0.03,
         until: float | None = None, probes=None,
         quantity: str = "von_mises", norm: str = "max",
         threads: int | None = None, max_seconds: float | None = None, *,
         ladder: Sequence[float] | None = None,
         window: tuple | None = None,
         candidates: Sequence | None = None, detect: bool = True,
         max_refinement: float = 2.0, max_order: float | None = FORMAL_ORDER,
         timing_checks: int = 3,
         refinements: int = 3, refine_best: int = 2,
         calibration_seconds: float | None = None,
         cache: dict | None = None, options: dict | None = None,
         scene: str = "", log: Callable[[str], None] | None = None) -> Plan:
    """The cheapest settings predicted to meet an error request.

    Parameters
    ----------
    scene_factory : callable
        ``scene_factory(dx, smoothing_ratio=..., kernel=...)`` returns the
        user's :class:`~sphsolid.Scene` at spacing ``dx`` [m] (the two
        keywords are optional: a factory without them is planned at its
        own h/dx and kernel). Effects the planner manages
        (``MANAGED_EFFECTS``) are replaced by the plan's.
    error : float
        Requested error as a fraction (0.03 = 3 %) of the reference's peak
        (``norm="max"``) or RMS (``"rms"``), worst probe.
    until : float
        End of the run [s].
    probes : mapping name -> point [m], or callable(scene) -> {name: value}
        Where the error is measured.
    quantity : str
        Probe column (``von_mises``, ``pressure``, ``sigma_yy``, ...).
    norm : {"max", "rms"}
    threads : int, optional
        Threads of the planned run (the calibration uses them too, so the
        cost model is this machine's at this thread count).
    max_seconds : float, optional
        Wall-time budget of the planned run.
    ladder : sequence of float
        Calibration spacings [m], coarse, 3 or more.
    window : (t0, t1), optional
        Part of [0, until] over which the error counts (default all).
    candidates : sequence of Setting or dict, optional
        Settings to choose from (default: every kernel x h/dx x integrator
        the library offers, with the effects the scene calls for).
    detect : bool
        Run the effect detection (else the candidates' effects are used
        as given).
    max_refinement : float
        How far below the finest calibrated spacing predictions may go
        (default 2: on the piston scene the self-convergence order of
        three coarse levels, 0.85, over-predicts the order the error
        keeps below them, about 0.5; a finer level shows it).
    max_order : float or None
        Largest order of convergence a prediction uses (default
        :data:`FORMAL_ORDER`, 1); a faster observed order is fitted again
        at it. None trusts any observed order.
    timing_checks : int
        How many of the cheapest candidates get a timing of a few steps at
        their planned spacing.
    refinements, refine_best : int
        Up to ``refinements`` rounds in which the ``refine_best`` cheapest
        settings that need a spacing below half their finest calibrated
        one, or below it with the large safety factor, get a finer level
        (finest / 1.5) and are fitted again.
    calibration_seconds : float, optional
        Budget of the calibration runs (default: no limit); a refinement
        that would exceed it is not run.
    options : dict, optional
        Narrows the default candidates: ``kernels``, ``ratios`` (h/dx),
        ``integrators``, ``extra_kernel_correction``
        (see :func:`default_candidates`).
    cache : dict, optional
        Calibration runs by (dx, setting, until, quantity, threads), reused
        and filled (several requests on one scene share their ladders; the
        same factory and probes are assumed).
    log : callable(str), optional
        Progress messages.

    Returns
    -------
    Plan
    """
    say = log or (lambda message: None)
    _check_request(error, until, norm, max_seconds, ladder)
    if probes is None:
        raise ValueError("probes must name where the error is measured "
                         "(mapping name -> point, or callable(scene))")
    ladder = sorted((float(d) for d in ladder), reverse=True)
    t0, t1 = window if window is not None else (0.0, float(until))
    probe_names = (list(probes) if isinstance(probes, Mapping) else [])
    request = {"error": float(error), "until": float(until), "norm": norm,
               "quantity": quantity, "probes": probe_names,
               "threads": threads, "max_seconds": max_seconds,
               "window": [t0, t1], "ladder": ladder,
               "smoothing_s": metrics.SMOOTHING}
    clock = wallclock.perf_counter()

    # 1. effects the scene calls for, per integrator -----------------
    findings_by = {}
    integrators = [i for i in integrator_names()
                   if i in ((options or {}).get("integrators")
                            or integrator_names())]
    if candidates is None:
        families = detection_families(
            scene_factory, (options or {}).get("kernels"),
            (options or {}).get("own_settings", True))
        for integrator, family in itertools.product(integrators, families):
            if not detect:
                findings_by[(integrator, family)] = []
                continue
            kernel, ratio, inset = family
            say(f"effects: detection run at dx = {ladder[0] * 1e3:g} mm with "
                f"{Setting.make(ratio, kernel, integrator, None, inset).label()}"
                " ...")
            # as many steps as a run at the smallest spacing the plan may
            # choose (growth per step does not depend on dx)
            steps = int(math.ceil(until / _default_dt(scene_factory,
                                                      ladder[0], integrator)
                                  * ladder[0] / ladder[-1] * max_refinement))
            key = ("detect", integrator, family, ladder[0], float(until),
                   steps)
            try:
                if cache is not None and key in cache:
                    findings_by[(integrator, family)] = cache[key]
                else:
                    findings_by[(integrator, family)] = detect_effects(
                        scene_factory, ladder[0], until, probes, quantity,
                        integrator, threads, steps=min(steps, 200000),
                        log=say, kernel=kernel, smoothing_ratio=ratio,
                        inset=inset)
                    if cache is not None:
                        cache[key] = findings_by[(integrator, family)]
            except UnsupportedError as unsupported:
                say(f"  {integrator} with {kernel} left out: {unsupported}")
        settings = default_candidates(
            scene_factory, findings_by,
            **{k: v for k, v in (options or {}).items()
               if k != "integrators"})
    else:
        settings = [c if isinstance(c, Setting) else Setting.from_dict(c)
                    for c in candidates]
    findings = []
    for items in findings_by.values():
        for f in items:
            if not any(f.effect == g.effect and f.reason == g.reason
                       for g in findings):
                findings.append(f)

    # 2. calibration ladder -----------------------------------------
    cands = [Candidate(setting, []) for setting in settings]
    total = len(settings) * len(ladder)
    counter = [0]

    def calibrate(cand, dx, total):
        counter[0] += 1
        say(f"[{counter[0]}/{total}] {cand.setting.label()}, dx = "
            f"{dx * 1e3:.3g} mm ...")
        key = (float(f"{dx:.6g}"), cand.setting, float(until), quantity,
               threads)
        try:
            if cache is not None and key in cache:
                run = cache[key]
            else:
                run = ladder_run(scene_factory, dx, cand.setting, until,
                                 probes, quantity, threads)
                if cache is not None:
                    cache[key] = run
        except UnsupportedError as unsupported:
            cand.note = f"left out: {unsupported}"
            say(f"  {cand.note}")
            return False
        cand.runs.append(run)
        if run.failed:
            say(f"  failed: {run.failed}")
            return False
        say(f"  {run.particles} particles, {run.steps} steps, "
            f"{run.wall:.2f} s")
        return True

    for cand in cands:
        for dx in ladder:
            if not calibrate(cand, dx, total):
                break
    grid = metrics.time_grid(t0, t1)
    usable = []
    for cand in cands:
        if (len(cand.runs) < len(ladder)
                or any(r.failed for r in cand.runs)):
            cand.note = cand.note or ("failed: " + next(
                (r.failed for r in cand.runs if r.failed), ""))[:80]
            continue
        cand.smoothed = [_smoothed(r, grid) for r in cand.runs]
        usable.append(cand)

    # 3. error models, floors, spacings and costs; refine the ladder of
    # the most promising settings while they need far extrapolation --
    def price(cand):
        cand.dx = cand.particles = cand.steps = cand.seconds = None
        cand.cpu_seconds = None
        cand.note = ""
        dx = cand.model.spacing_for(error)
        if dx is None:
            cand.note = (f"no convergence on the ladder: error bounded by "
                         f"3 x data range = {cand.model.upper(ladder[-1]) * 100:.2f} %"
                         if cand.model.anomalous else
                         f"floor {cand.model.floor * 100:.2f} % >= request")
            return None
        dx = float(f"{min(dx, ladder[0]):.3g}")
        while cand.model.upper(dx) > error:
            dx *= 0.99
        if dx < cand.model.smallest_dx:
            # never build a scene this fine: scale from the ladder
            n, steps = _size_at(cand.runs, dx)
            cand.note = (f"needs dx {dx * 1e3:.3g} mm, below the finest "
                         f"calibrated spacing / {max_refinement:g}")
            return dx, cand.cost.predict_cpu(n, steps)
        n, steps = _steps_to(scene_factory, dx, cand.setting, until)
        cand.dx, cand.particles, cand.steps = dx, n, steps
        cand.seconds = cand.cost.predict(n, steps)
        cand.cpu_seconds = cand.cost.predict_cpu(n, steps)
        return dx, cand.cpu_seconds

    def fit_all():
        for cand in usable:
            _fit_candidate(cand, norm, max_refinement, threads, max_order)
        floors = consistency_floors(
            [c.model for c in usable],
            [c.smoothed[:len(ladder)] for c in usable], norm, ladder)
        for cand, floor in zip(usable, floors):
            cand.model.floor = floor
        return {id(c): price(c) for c in usable}

    needs = fit_all()
    spent = sum(r.wall for c in cands for r in c.runs if not r.failed)
    budget = (calibration_seconds if calibration_seconds is not None
              else math.inf)
    for _ in range(refinements):
        # a setting that needs a spacing far below its ladder, or below
        # it with the large safety factor (a fit outside the asymptotic
        # range: a finer level may bring the small one, which costs
        # Fs^(d/q) less), gets a finer level
        wanted = sorted(
            (c for c in usable if needs[id(c)] is not None
             and (needs[id(c)][0] < c.model.finest / 2
                  or (c.model.safety > SAFETY_GOOD
                      and needs[id(c)][0] < c.model.finest))),
            key=lambda c: needs[id(c)][1])[:refine_best]
        # a setting whose ladder determines no order (no convergence
        # observed, or the large safety factor) has no trustworthy
        # prediction to rank it by: its levels may be outside the
        # asymptotic range (cubic_o4 on the piston in the max norm: the
        # largest difference of 3 and 2 mm is a feature at 238 us, those
        # of the finer levels one at 280-290 us; from 2 to 0.67 mm the
        # order is 1.26 with a good fit). It gets a finer level too, the
        # cheapest first, besides those ranked by their need, when that
        # level costs less CPU time than the cheapest run planned so far
        # (else running the plan is the cheaper way to the answer)
        next_size = {id(c): _size_at(c.runs, c.model.finest / 1.5)
                     for c in usable}
        next_cost = {id(c): c.cost.predict(*next_size[id(c)])
                     for c in usable}
        next_cpu = {id(c): c.cost.predict_cpu(*next_size[id(c)])
                    for c in usable}
        cheapest = min((needs[id(c)][1] for c in usable
                        if needs[id(c)] is not None), default=math.inf)
        undetermined = sorted(
            (c for c in usable if c not in wanted
             and (c.model.anomalous or c.model.safety > SAFETY_GOOD)
             and next_cpu[id(c)] <= cheapest),
            key=lambda c: next_cost[id(c)])[:refine_best]
        wanted = [c for c in wanted + undetermined
                  if next_cost[id(c)] + spent <= budget]
        if not wanted:
            break
        for cand in wanted:
            dx = float(f"{cand.model.finest / 1.5:.3g}")
            say(f"refining {cand.setting.label()}: "
                + (f"it needs dx {needs[id(cand)][0] * 1e3:.3g} mm"
                   if needs[id(cand)] is not None else
                   "its ladder determines no order"))
            if calibrate(cand, dx, counter[0] + 1):
                cand.smoothed.append(_smoothed(cand.runs[-1], grid))
                spent += cand.runs[-1].wall
            else:
                cand.runs.pop()
        needs = fit_all()

    # 4. timing of a few steps at the planned spacing ----------------
    # (the cheapest in CPU seconds: the measure that a loaded machine
    # disturbs least)
    priced = sorted((c for c in usable if c.cpu_seconds is not None),
                    key=lambda c: c.cpu_seconds)
    # within the calibrated sizes the calibration runs (whole runs, probe
    # sampling included) measure the cost; a few steps timed there only
    # add noise (on the gravity column at 8 mm, 0.1 s runs of 3200 steps,
    # two plans of the same run predicted 0.148 and 0.111 CPU s after
    # their five timed steps, the run took 0.096-0.101 s): the timing
    # checks are for scenes larger than the largest calibration run
    for cand in [c for c in priced if c.particles > max(
            r.particles for r in c.runs if not r.failed)][
            :max(0, timing_checks)]:
        say(f"timing a few steps of {cand.setting.label()} at dx = "
            f"{cand.dx * 1e3:.3g} mm ...")
        n, _, per_step = time_steps(scene_factory, cand.dx, cand.setting,
                                    threads, clock=cand.cost.clock,
                                    min_seconds=TIMING_SECONDS)
        finest = min(cand.runs, key=lambda r: r.dx)
        n0, _, per_step0 = time_steps(scene_factory, finest.dx, cand.setting,
                                      threads, clock=cand.cost.clock,
                                      min_seconds=TIMING_SECONDS)
        # anchored on the finest calibration run's own cost (the line
        # through all runs misses single sizes by several per cent)
        cand.cost.correct(n, per_step, n0, per_step0, reference_cost(
            finest, cand.cost.clock,
            lambda run=finest, setting=cand.setting: ladder_run(
                scene_factory, run.dx, setting, until, probes, quantity,
                threads)))
        cand.seconds = cand.cost.predict(cand.particles, cand.steps)
        cand.cpu_seconds = cand.cost.predict_cpu(cand.particles, cand.steps)
    priced.sort(key=lambda c: c.cpu_seconds)
    affordable = [c for c in priced
                  if max_seconds is None or c.seconds <= max_seconds]
    result = Plan(request=request, feasible=bool(affordable),
                  threads=threads, findings=findings, candidates=cands,
                  scene=scene)
    if affordable:
        best = affordable[0]
        result.setting, result.dx = best.setting, best.dx
        result.predicted_error = best.model.predict(best.dx)
        result.error_upper = best.model.upper(best.dx)
        result.predicted_seconds = best.seconds
        result.predicted_cpu_seconds = best.cpu_seconds
        result.particles, result.steps = best.particles, best.steps
        result.calibration = best.model.to_dict()
    else:
        result.best_reachable_error, result.reason = _refusal(
            usable, error, max_seconds, scene_factory, until)
    result.calibration_seconds = wallclock.perf_counter() - clock
    return result


def _size_at(runs: Sequence[LadderRun], dx: float) -> tuple[int, int]:
    """(particles, steps) at ``dx`` scaled from the ladder's runs by the
    power laws they follow (particles ~ dx^-dim, steps ~ dx^-1), without
    building the scene."""
    h = np.log([r.dx for r in runs])
    n = np.polyfit(h, np.log([r.particles for r in runs]), 1)
    k = np.polyfit(h, np.log([r.steps for r in runs]), 1)
    return (int(math.exp(np.polyval(n, math.log(dx)))),
            int(math.ceil(math.exp(np.polyval(k, math.log(dx))))))


def _smoothed(run: LadderRun, grid) -> dict:
    return {n: metrics.smooth(grid, metrics.on_grid(run.times, run.series[n],
                                                    grid))
            for n in run.series}


def _fit_candidate(cand, norm, max_refinement, threads,
                   max_order=FORMAL_ORDER) -> None:
    """Error model on the finest four levels (three differences: the
    coarsest levels of a long ladder are the least asymptotic), all on
    the finest level's scale; cost model on all its runs."""
    spacings = [r.dx for r in cand.runs][-4:]
    levels = cand.smoothed[-4:]
    scales = {n: metrics.scale_of(s, norm) for n, s in levels[-1].items()}

    def distance(a, b):
        return max(metrics.deviation(a[n], b[n], norm, scales[n]) for n in a)
    diffs = [distance(a, b) for a, b in zip(levels, levels[1:])]
    spread = max(distance(a, b) for a, b in
                 itertools.combinations(levels, 2))
    cand.model = fit_error_model(spacings, diffs, 0.0, max_refinement,
                                 spread, max_order)
    if not cand.model.anomalous:
        cand.model.repeating = repeating_factor(spacings, levels,
                                                cand.model.order, norm)[0]
        cand.model.levels = [(dx, cand.model.power(dx)) for dx in spacings]
    cand.cost = CostModel.from_runs(cand.runs, threads)


def _default_dt(scene_factory, dx, integrator) -> float:
    scene = build_scene(scene_factory, dx, Setting.make(integrator=integrator),
                        1)
    return make_dynamics(scene, integrator, progress=False).dt


def _refusal(modelled, error, max_seconds, scene_factory, until):
    """The best error any setting reaches (within max_seconds and the
    extrapolation limit) and the reason for refusing."""
    if not modelled:
        return None, ("no setting could be calibrated (every candidate "
                      "failed or was unavailable)")
    # the best error within the extrapolation limit alone: when it meets
    # the request, the time budget is what refuses
    unlimited = min(c.model.upper(c.model.smallest_dx) for c in modelled)
    best, where = math.inf, None
    for cand in modelled:
        dx = cand.model.smallest_dx
        if max_seconds is not None:
            # largest affordable refinement
            while dx < cand.model.finest * 4:
                if cand.cost.predict(*_size_at(cand.runs, dx)) <= max_seconds:
                    break
                dx *= 1.25
        reach = cand.model.upper(dx)
        if reach < best:
            best, where = reach, (cand, dx)
    floors = min(c.model.floor for c in modelled)
    cand, dx = where
    if cand.model.anomalous:
        dx = cand.model.coarsest
        reason = (f"no setting meets {error * 100:g} %: the calibration "
                  f"levels show no convergence (observed order "
                  f"{cand.model.observed_order:.2f}, fit residual "
                  f"{cand.model.residual:.2f}), so the error of each "
                  f"calibrated level is only bounded by 3 x their largest "
                  f"difference ({cand.model.data_range * 100:.2f} %; Eça & "
                  f"Hoekstra) and nothing finer can be promised")
    elif max_seconds is not None and unlimited <= error:
        reason = (f"no setting meets {error * 100:g} % within "
                  f"{max_seconds:g} s")
    elif floors >= error:
        reason = (f"the request {error * 100:g} % is below the observed error"
                  f" floor: the settings differ by {floors * 100:.2f} %, a "
                  f"difference that does not shrink with refinement or "
                  f"that their own predicted errors do not explain (a bias "
                  f"refinement does not remove)")
    else:
        reason = (f"no setting meets {error * 100:g} % within the "
                  f"extrapolation limit (dx >= finest ladder spacing / "
                  f"{cand.model.max_refinement:g})")
    reason += (f"; best reachable: {best * 100:.2f} % with "
               f"{cand.setting.label()} at dx = {dx * 1e3:.3g} mm")
    return float(best), reason


# ------------------------------------------------ the project's scenes
def _layers(smoothing_ratio: float) -> int:
    """Plate and piston layers: at least the kernel support 2h thick,
    with 1 % to spare for a lattice spacing round(L/dx) makes a little
    wider than dx (h follows the lattice)."""
    return int(math.ceil(2 * smoothing_ratio * 1.01))


def piston_factory(dx: float, smoothing_ratio: float = 1.2,
                   kernel: str = "cubic_spline",
                   speed: float | None = None, inset: float | str = 0.0):
    """The paper's piston scene (:func:`sphsolid.scenes.uniaxial_piston`)
    with the planner's h/dx, kernel and end placement (``inset``, see
    :func:`sphsolid.build.plate`) and no optional effect; plate and
    piston ``ceil(2 h/dx)`` layers thick."""
    from . import build, scenes
    from .scene import Scene
    rock = scenes.paper_material()
    specimen = build.rectangle(scenes.SPECIMEN_X, scenes.SPECIMEN_Y, dx, rock,
                               "specimen")
    layers = _layers(smoothing_ratio)
    v = scenes.PISTON_SPEED if speed is None else speed
    return Scene(2, [specimen, build.plate(under=specimen, layers=layers,
                                           inset=inset),
                     build.piston(over=specimen, layers=layers,
                                  velocity=(0.0, -v), inset=inset)],
                 smoothing_ratio=smoothing_ratio, kernel=kernel)


def gravity_factory(dx: float, smoothing_ratio: float = 1.2,
                    kernel: str = "cubic_spline", g: float = 9.81,
                    inset: float | str = 0.0):
    """The paper's gravity scene: the specimen on the fixed plate under
    gravity, with no optional effect (the planner finds what it needs)."""
    from . import build, scenes
    from .scene import Scene
    rock = scenes.paper_material()
    specimen = build.rectangle(scenes.SPECIMEN_X, scenes.SPECIMEN_Y, dx, rock,
                               "specimen")
    layers = _layers(smoothing_ratio)
    return Scene(2, [specimen, build.plate(under=specimen, layers=layers,
                                           inset=inset)],
                 effects={"gravity": {"gx": 0.0, "gy": -float(g)}},
                 smoothing_ratio=smoothing_ratio, kernel=kernel)


#: Laterally periodic strip under the piston: height [m] and width in dx.
STRIP_HEIGHT, STRIP_WIDTH_DX = 0.1, 8


def strip_factory(dx: float, smoothing_ratio: float = 1.2,
                  kernel: str = "cubic_spline", speed: float | None = None,
                  inset: float | str = 0.0):
    """A laterally periodic strip (the paper's material, 100 mm high, 8 dx
    wide) on a fixed plate, hit by the piston at t = 0: a plane P-wave with
    the exact stress jump -rho0 c_p v behind a front at y = H - c_p t."""
    from . import build, scenes
    from .scene import Scene
    rock = scenes.paper_material()
    width = STRIP_WIDTH_DX * dx
    strip = build.rectangle((-width / 2, width / 2), (0.0, STRIP_HEIGHT), dx,
                            rock, name="strip")
    layers = _layers(smoothing_ratio)
    v = scenes.PISTON_SPEED if speed is None else speed
    return Scene(2, [strip, build.plate(under=strip, layers=layers,
                                        inset=inset),
                     build.piston(over=strip, layers=layers,
                                  velocity=(0.0, -v), inset=inset)],
                 domain=((-width / 2, -layers * dx - 0.01),
                         (width / 2, STRIP_HEIGHT + layers * dx + 0.01)),
                 periodic=(True, False), smoothing_ratio=smoothing_ratio,
                 kernel=kernel)


#: Probe points of the strip [m] (on the axis, a quarter, half and three
#: quarters down).
STRIP_PROBES = {"y75": (0.0, 0.075), "y50": (0.0, 0.050),
                "y25": (0.0, 0.025)}
#: Heights [m] of the gravity column's section means.
GRAVITY_SECTIONS = {"y35": 0.035, "y70": 0.070, "y105": 0.105}


def gravity_sections(scene) -> dict:
    """Mean sigma_yy [Pa] over the specimen's section at each height of
    :data:`GRAVITY_SECTIONS` (the section carries the weight above it:
    exactly -rho0 g (H - y) at rest, whatever the base does).

    The section between two particle rows is represented by the mean of
    the two rows that meet there, interpolated linearly in y between the
    cuts that bracket the height. The static SPH field carries a row-to-row
    alternation of the row means (+-1 to 5 % of the weight at mid-height on
    the cubic spline at h/dx 1.2, growing towards the free top): the
    kernel-sum divergence of the stress does not see a mode that alternates
    from row to row, so equilibrium leaves it undetermined. The mean of two
    neighbouring rows cancels it, as the force carried across the cut (a
    sum over pairs with one particle on each side) does; the mean of one
    row, or an interpolation between single rows, picks up a share of it
    that jumps with where the height falls between rows (errors of 8, 1,
    4, 1, 3 % at 8, 6, 4, 3, 2 mm instead of a convergence)."""
    part = scene.body_slice("specimen")
    y = scene.positions[part, 1]
    s_yy = scene.stress[part, 1]
    tolerance = 1e-3 * (scene.h or 1.0)
    order = np.argsort(y)
    y, s_yy = y[order], s_yy[order]
    starts = np.concatenate(([0], np.nonzero(np.diff(y) > tolerance)[0] + 1))
    counts = np.diff(np.append(starts, len(y)))
    rows_y = np.add.reduceat(y, starts) / counts
    rows_s = np.add.reduceat(s_yy, starts) / counts
    cuts_y = 0.5 * (rows_y[1:] + rows_y[:-1])
    cuts_s = 0.5 * (rows_s[1:] + rows_s[:-1])
    return {name: float(np.interp(height, cuts_y, cuts_s))
            for name, height in GRAVITY_SECTIONS.items()}


@dataclass
class PlanScene:
    """A named scene for ``sphsolid plan NAME``: factory, probes, quantity,
    the default window, calibration ladder and end time."""
    factory: Callable
    probes: object
    quantity: str
    ladder: tuple
    until: float
    window: Callable | None = None     # until -> (t0, t1)
    description: str = ""


def project_scenes() -> dict:
    from .probes import PAPER_PROBES
    from .scenes import paper_material
    # the strip's window ends before the front reaches the plate
    strip_until = 0.95 * STRIP_HEIGHT / paper_material().c_p
    return {
        "piston": PlanScene(piston_factory, PAPER_PROBES, "von_mises",
                            (3e-3, 2e-3, 1.5e-3), 0.3e-3,
                            description="the paper's piston test, von Mises "
                            "at A, B, C"),
        "gravity": PlanScene(gravity_factory, gravity_sections, "sigma_yy",
                             (8e-3, 6e-3, 4e-3, 3e-3), 2.5e-3,
                             window=lambda until: (0.5 * until, until),
                             description="the specimen settling under "
                             "gravity: section means of sigma_yy at y = 35, "
                             "70, 105 mm over the second half of the run "
                             "(damped at c_p/L, the waves have decayed by "
                             "e^-12 at its start)"),
        "strip": PlanScene(strip_factory, STRIP_PROBES, "sigma_yy",
                           (2e-3, 1.4e-3, 1e-3, 0.7e-3), strip_until,
                           description="laterally periodic strip hit by the "
                           "piston, sigma_yy at y = 75, 50, 25 mm"),
    }


class _CallableModule(type(math)):
    """``sphsolid.plan(...)`` calls :func:`plan`; ``sphsolid.plan.Plan``
    and the rest of this module stay reachable."""

    def __call__(self, *args, **kwargs):
        return plan(*args, **kwargs)


import sys as _sys  # noqa: E402

_sys.modules[__name__].__class__ = _CallableModule
