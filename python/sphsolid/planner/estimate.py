"""Per-run error estimate: an error band on every probe series.

After a run, :class:`ErrorEstimate` re-runs the same scene at 2 dx and
4 dx (shadow runs: in 2D they cost 1/8 and 1/64 of the run, about 14 %
together; in 3D 1/16 and 1/256), samples the same probes at the same
times, and estimates the error of the run's series with Roache's grid
convergence index (GCI):

    q_obs = log2(D(2dx, 4dx) / D(dx, 2dx)),
    e(t)  = Fs |f_dx(t) - f_2dx(t)| / (2^p - 1),
    Fs = 3,  p = q_obs bounded to [1, 2],

with D the largest difference of the (1 µs Gaussian-smoothed) series over
all probes. The shadows are coarser than the run, so the triplet is not
in the asymptotic range (a 4 dx shadow of a 3 mm piston run has seven
particles across the specimen): its observed order scatters from 0.04 to
0.9 on the project's scenes, which made a Richardson estimate with
Fs = 1.25 and that order 2-4x too large or up to 2x too small. Roache
prescribes Fs = 3 for such two-grid estimates, with the scheme's formal
order: 1 here (the artificial viscosity and the kernel sums at the free
surface are first order); an observed order above it (up to 2) is used
when the shadows show it. Fs = 3 with p = 1 covers true orders down to
about 0.42 (3 / (2^1 - 1) >= 1 / (2^0.42 - 1)), and is 3-6x the error of
a setting that converges at order 1 or faster (cubic_o4 on the project's
scenes).

A calibration (``calibration=``: the error model a plan fitted for the
run's setting, from a ladder of four or more levels; or ``order=``, a
calibrated order) replaces the two-grid rule when it is well determined
in Eça & Hoekstra's sense (observed order in [0.5, 2.1], a good fit:
safety factor 1.25 in the model, and convergence observed) and carries no
floor. Then

    Fs = 1.25,  p = min(q_cal, q_obs, 1) bounded below by 0.5,

the three-grid GCI with the calibrated order, lowered to the shadows'
observed order where they show slower convergence (their triplet reaches
coarser than the ladder) and to the formal order 1 that the planner's
predictions use as well (cubic_o4's differences on the strip fall at
order 1.8 over 1.4-0.47 mm while its error falls at 0.8-1.1), and not
below 0.5, the lower end of the range over which the calibration was
accepted (at p = 0.5 the factor Fs / (2^p - 1) is 3.0, the two-grid
rule's).

The shadows' order lowers the calibrated one unless the triplet
converges **oscillatorily** with an order outside [0.5, 2.1]. The
triplet oscillates when the run's difference from its 2 dx shadow and the
2 dx shadow's difference from the 4 dx one point in opposite directions
(their inner product over all probes and samples is negative: Celik et
al. 2008's convergence ratio eps21 / eps32 < 0). That happens when a part
of each level's error does not repeat from one spacing to the next
(differences of independent parts anti-correlate), and then the ratio of
the norms of two differences is no convergence order: one outside the
range where an order is accepted is not in the asymptotic range and says
nothing against a well-determined calibration. cubic_o4 on the piston:
consecutive differences anti-correlated (-0.34 to -0.45 for the shadow
triplets at 3, 2, 1.5 and 1 mm; its errors at consecutive ladder levels
correlate by only 0.5-0.6, the cubic spline's by 0.97-0.99), at 3 mm the
triplet's order 0.2 from a 4 dx shadow 7 particles wide, and the run and
its 2 dx shadow differ by 0.9-1.9 times the run's error (the cubic
spline's by 0.4-0.9 times), since the difference carries both levels'
non-repeating parts. A monotone triplet's order is used whatever it is
(down to 0.5).

A calibration with a **floor** (the plan saw a bias that refinement does
not remove: two settings whose difference does not shrink, see
:func:`sphsolid.planner.consistency_floors`) is not used: the shadows'
difference does not contain that bias, so the small safety factor would
not cover it (the cubic spline on the piston, floor 3.7 % max, 1.8 % RMS:
with its calibrated order 0.85 and Fs 1.25 the band came to 0.98 of its
error against the finite-element solution); the two-grid rule's Fs = 3
does. A calibration that is not well determined (an order outside
[0.5, 2.1], scattered or anomalous levels) is not used either. The
estimate sees the error that shrinks with dx; a bias that does not (see
:mod:`sphsolid.planner`, the floor) is covered only by the large factor.

The shadow scenes are the run's scene rebuilt with every block body at the
coarser spacing (same extents, materials, motions, effects, h/dx, kernel,
domain); plates and pistons keep their layer count and their face on the
body they touch. Scenes with bodies given as point sets need a
``scene_factory(dx)`` instead.
"""
from __future__ import annotations

import csv
import dataclasses
import math
import time as wallclock

import numpy as np

from .. import metrics
from .._lib import UnsupportedError

__all__ = ["ErrorEstimate", "coarsened", "SAFETY", "SAFETY_TWO_GRID",
           "gci_factor", "calibrated_order", "oscillates"]


def gci_factor(observed: float | None, calibrated: float | None = None,
               oscillatory: bool = False) -> tuple[float, float]:
    """(safety factor, order used) of the per-run estimate: ``observed``
    is the shadows' observed order (nan or None when unknown),
    ``calibrated`` a well-determined calibrated order (see
    :func:`calibrated_order`) or None, ``oscillatory`` whether the
    shadows' triplet converges oscillatorily (:func:`oscillates`); see the
    module docstring."""
    known = observed is not None and math.isfinite(observed)
    if calibrated is not None:
        q = min(float(calibrated), FORMAL_ORDER)
        if known and not (oscillatory and not LOW_ORDER <= float(observed)
                          <= HIGH_ORDER):
            q = min(q, float(observed))
        return SAFETY, max(q, LOW_ORDER)
    if not known:
        return SAFETY_TWO_GRID, FORMAL_ORDER
    return SAFETY_TWO_GRID, float(np.clip(observed, FORMAL_ORDER, MAX_ORDER))


def oscillates(fine: dict, middle: dict, coarse: dict) -> bool:
    """True when the triplet converges oscillatorily: the differences
    fine - middle and middle - coarse (series per probe on one grid) have
    a negative inner product over all probes and samples (Celik et al.
    2008: the convergence ratio eps21 / eps32 < 0)."""
    dot = sum(float(np.dot(fine[n] - middle[n], middle[n] - coarse[n]))
              for n in fine)
    return dot < 0.0


def calibrated_order(calibration=None, order: float | None = None
                     ) -> float | None:
    """The calibrated order when it is well determined, else None.

    ``calibration`` is a plan's error model for the run's setting (a
    :class:`sphsolid.planner.ErrorModel` or its ``to_dict()``, as in the
    ``error_model`` of plan.json): well determined when its observed order
    is in [0.5, 2.1], its safety factor is 1.25 (a good fit, Eça &
    Hoekstra), it is not anomalous (convergence observed) and it carries
    no floor (no bias that refinement does not remove). ``order``
    is a calibrated order given by hand: well determined when in
    [0.5, 2.1]."""
    if calibration is not None:
        get = (calibration.get if isinstance(calibration, dict)
               else lambda key, default=None: getattr(calibration, key,
                                                      default))
        q = get("observed_order")
        if q is None:
            q = get("order")
        if (q is None or not math.isfinite(float(q))
                or get("anomalous", False)
                or float(get("floor", 0.0) or 0.0) > 0.0
                or float(get("safety", SAFETY_TWO_GRID)) > SAFETY
                or not LOW_ORDER <= float(q) <= HIGH_ORDER):
            return None
        return float(q)
    if order is not None and math.isfinite(order) \
            and LOW_ORDER <= order <= HIGH_ORDER:
        return float(order)
    return None

#: GCI safety factors (Roache 1998): three or more grids in the
#: asymptotic range / two grids or grids outside it.
SAFETY, SAFETY_TWO_GRID = 1.25, 3.0
#: Formal order of the scheme (first-order artificial viscosity and free
#: surface kernel sums) and the highest order the estimate uses.
FORMAL_ORDER, MAX_ORDER = 1.0, 2.0
#: Range of calibrated orders with the small safety factor (Eça &
#: Hoekstra 2014, for a scheme of formal order up to 2).
LOW_ORDER, HIGH_ORDER = 0.5, 2.1


def _coarse_body(body, factor: float):
    dx = body.dx * factor
    if body.lo is None:
        raise UnsupportedError(f"body {body.name!r} is a point set: give "
                               "ErrorEstimate a scene_factory(dx) to build "
                               "its shadow runs")
    lo, hi = list(body.lo), list(body.hi)
    if body.role in ("plate", "piston") and body.layers:
        axis = len(lo) - 1           # layered along the last axis
        if body.role == "plate":
            lo[axis] = hi[axis] - body.layers * dx
        else:
            hi[axis] = lo[axis] + body.layers * dx
    return dataclasses.replace(body, dx=dx, lo=tuple(lo), hi=tuple(hi))


def coarsened(scene, factor: float = 2.0):
    """The scene rebuilt at ``factor`` times its spacing (a new Scene with
    a calculator like the original's: C library, same threads)."""
    from ..calculators import CLibrary
    from ..scene import Scene
    domain = None
    if scene.domain is not None:
        domain = scene.domain
    shadow = Scene(scene.dimension, [_coarse_body(b, factor)
                                     for b in scene.bodies],
                   effects=scene.effects, domain=domain,
                   periodic=scene.periodic if domain is not None else None,
                   smoothing_ratio=scene.smoothing_ratio,
                   kernel=scene.kernel)
    threads = getattr(scene.calc, "threads", None)
    shadow.calc = CLibrary(threads=threads)
    return shadow


class ErrorEstimate:
    """Error bands for the series of a :class:`~sphsolid.Probes` object.

    Parameters
    ----------
    probes : Probes
        The run's probes, attached to its dynamics (the run must be done
        before :meth:`compute`).
    calibration : ErrorModel or dict, optional
        The error model a plan fitted for the run's setting (``Plan``'s
        :attr:`~sphsolid.planner.Plan.calibration`, the ``error_model`` of
        plan.json): used when well determined (:func:`calibrated_order`).
    order : float, optional
        A calibrated order given by hand instead (used when in
        [0.5, 2.1]). Either way the shadows at 2 dx and 4 dx both run: the
        observed order of their triplet can lower the one used.
    scene_factory : callable(dx) -> Scene, optional
        Builds the shadow scenes; default :func:`coarsened`.
    threads : int, optional
        Threads of the shadow runs (default the run's).

    Examples
    --------
    >>> probes = Probes(scene, PAPER_PROBES)
    >>> dyn.attach(probes, interval=10)
    >>> dyn.run(until=0.3e-3)
    >>> est = ErrorEstimate(probes).compute()
    >>> est.bands["A"]["von_mises"]          # half-width [Pa] per sample
    """

    def __init__(self, probes, order: float | None = None,
                 scene_factory=None, threads: int | None = None,
                 integrator: str | None = None, calibration=None,
                 shadows: dict | None = None):
        self.probes = probes
        #: shadow series per coarsening factor ({2.0: ..., 4.0: ...}):
        #: pass another estimate's ``shadows`` of the same run to reuse
        #: its shadow runs with another calibration
        self.shadows = shadows if shadows is not None else {}
        self.scene = probes.scene
        self.order_given = order
        #: the well-determined calibrated order, or None (two-grid rule)
        self.calibrated = calibrated_order(calibration, order)
        self.scene_factory = scene_factory
        self.threads = threads
        self.integrator = integrator
        self.order = None
        self.bands = None
        self.shadow_seconds = 0.0
        self.shadow_particles = []
        self.dx = self.scene.bodies[0].dx if self.scene.bodies else None

    # ------------------------------------------------------------ runs
    def _shadow(self, factor: float) -> dict:
        if factor not in self.shadows:
            self.shadows[factor] = self._run_shadow(factor)
        return self.shadows[factor]

    def _run_shadow(self, factor: float) -> dict:
        from ..probes import Probes
        if self.scene_factory is not None:
            shadow = self.scene_factory(self.dx * factor)
        else:
            shadow = coarsened(self.scene, factor)
        if self.threads is not None and getattr(shadow, "_calc",
                                                None) is None:
            from ..calculators import CLibrary
            shadow.calc = CLibrary(threads=self.threads)
        from .calibration import _set_integrator, make_dynamics
        if self.integrator:
            _set_integrator(shadow, self.integrator)
        shadow_probes = Probes(shadow, dict(self.probes.points))
        dyn = make_dynamics(shadow, self.integrator or "improved_euler",
                            progress=False)
        times = self.probes.times
        start = wallclock.perf_counter()
        interval = max(1, int(np.median(np.diff(times)) / dyn.dt)
                       if len(times) > 1 else 1)
        dyn.attach(shadow_probes, interval=interval)
        dyn.run(until=float(times[-1]))
        if shadow_probes.times[-1] < shadow.time:
            shadow_probes.record()
        self.shadow_seconds += wallclock.perf_counter() - start
        self.shadow_particles.append(len(shadow))
        return {name: {value: np.interp(times, shadow_probes.times,
                                        shadow_probes[name][value])
                       for value in self.probes.values}
                for name in self.probes.names}

    def compute(self) -> "ErrorEstimate":
        """Run the shadow runs and fill :attr:`bands` and :attr:`order`."""
        times = self.probes.times
        if len(times) < 2:
            raise ValueError("ErrorEstimate needs a run with at least two "
                             "probe samples")
        fine = {n: self.probes[n] for n in self.probes.names}
        grid = metrics.time_grid(float(times[0]), float(times[-1]))

        def smoothed(series):
            return {n: {v: metrics.smooth(grid, np.interp(grid, times,
                                                          series[n][v]))
                        for v in self.probes.values} for n in series}
        f1 = smoothed(fine)
        f2 = smoothed(self._shadow(2.0))
        observed, factors, oscillatory = {}, {}, {}
        f4 = smoothed(self._shadow(4.0))
        for v in self.probes.values:
            d1 = max(metrics.deviation(f1[n][v], f2[n][v], "max")
                     for n in f1)
            d2 = max(metrics.deviation(f2[n][v], f4[n][v], "max")
                     for n in f1)
            observed[v] = (math.log2(d2 / d1) if d1 > 0 and d2 > 0
                           else math.nan)
            oscillatory[v] = oscillates(*({n: f[n][v] for n in f1}
                                          for f in (f1, f2, f4)))
            factors[v] = gci_factor(observed[v], self.calibrated,
                                    oscillatory[v])
        #: observed order per value (nan when the shadows do not differ)
        self.observed_order = observed
        #: whether the triplet (dx, 2dx, 4dx) converges oscillatorily
        self.oscillatory = oscillatory
        self.safety = {v: f for v, (f, _) in factors.items()}
        self.order = {v: q for v, (_, q) in factors.items()}
        self.bands = {
            n: {v: np.interp(times, grid, self.safety[v]
                             * np.abs(f1[n][v] - f2[n][v])
                             / (2.0 ** self.order[v] - 1.0))
                for v in self.probes.values} for n in f1}
        return self

    # --------------------------------------------------------- results
    def relative(self, name: str, value: str = "von_mises",
                 norm: str = "max") -> float:
        """The estimated error of one series in the metric of
        :mod:`sphsolid.metrics` (max band over the series' peak, or RMS
        band over its RMS)."""
        series = self.probes[name][value]
        band = self.bands[name][value]
        if norm == "max":
            return float(np.max(band) / np.max(np.abs(series)))
        return float(np.sqrt(np.mean(band ** 2))
                     / np.sqrt(np.mean(series ** 2)))

    @property
    def cost_fraction(self) -> float:
        """Shadow particle-steps over the run's (2D: about 1/8 + 1/64; the
        plate and piston layers make it a little more)."""
        n = len(self.scene)
        return sum(p / n / f for p, f in zip(self.shadow_particles,
                                              (2.0, 4.0)))

    def write_csv(self, path) -> None:
        """The probe CSV (time_s, step, ``<probe>_<value>_Pa`` columns as
        :meth:`Probes.write_csv`) followed by ``<probe>_<value>_error_Pa``
        columns: the half-width of the band at each sample."""
        if self.bands is None:
            raise RuntimeError("call compute() first")
        p = self.probes
        with open(path, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(
                ["time_s", "step"]
                + [f"{n}_{v}_Pa" for n in p.names for v in p.values]
                + [f"{n}_{v}_error_Pa" for n in p.names for v in p.values])
            for k, (t, step) in enumerate(zip(p.times, p.steps)):
                row = [repr(float(t)), int(step)]
                row += [repr(float(p[n][v][k])) for n in p.names
                        for v in p.values]
                row += [repr(float(self.bands[n][v][k])) for n in p.names
                        for v in p.values]
                writer.writerow(row)

    def write_hdf5(self, path) -> None:
        """Add ``/observables/probes_error`` (layout in
        docs/hdf5_layout.md) to an HDF5 file written by the run."""
        import h5py
        if self.bands is None:
            raise RuntimeError("call compute() first")
        p = self.probes
        value = np.stack([np.stack([self.bands[n][v] for v in p.values],
                                   axis=-1) for n in p.names], axis=1)
        with h5py.File(path, "a") as f:
            group = f.require_group("observables")
            if "probes_error" in group:
                del group["probes_error"]
            g = group.create_group("probes_error")
            g.attrs["names"] = " ".join(p.names)
            g.attrs["columns"] = " ".join(p.values)
            g.attrs["method"] = ("GCI from shadow runs at 2 dx (and 4 dx for "
                                 "the observed order), 1 us Gaussian "
                                 "smoothing: Fs |f_dx - f_2dx| / (2^p - 1)")
            g.attrs["order"] = np.array([self.order[v] for v in p.values])
            g.attrs["observed_order"] = np.array(
                [self.observed_order[v] for v in p.values])
            g.attrs["safety_factor"] = np.array(
                [self.safety[v] for v in p.values])
            g.attrs["oscillatory"] = np.array(
                [bool(self.oscillatory[v]) for v in p.values])
            g.attrs["calibrated_order"] = (math.nan if self.calibrated is None
                                           else self.calibrated)
            g.attrs["smoothing_s"] = metrics.SMOOTHING
            g.attrs["shadow_seconds"] = self.shadow_seconds
            # checksummed as the library's datasets (sphsolid info
            # --verify reads them back)
            for name, data in (("step", p.steps.astype(np.int64)),
                               ("time", np.asarray(p.times)),
                               ("value", value)):
                g.create_dataset(name, data=data,
                                 fletcher32=bool(np.size(data)))
