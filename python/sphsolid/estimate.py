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
about 0.42 (3 / (2^1 - 1) >= 1 / (2^0.42 - 1)). A plan's fitted order
(``order=``, from a ladder of several levels) is used with Fs = 1.25 as
a three-grid GCI when it is in [0.5, 2.1], else with Fs = 3 bounded to
[0.5, 2]; then only the 2 dx shadow runs. The estimate sees the error
that shrinks with dx; a bias that does not (see :mod:`sphsolid.plan`,
the floor) is not in it.

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

from . import metrics
from ._lib import UnsupportedError

__all__ = ["ErrorEstimate", "coarsened", "SAFETY", "SAFETY_TWO_GRID",
           "gci_factor"]


def gci_factor(order: float | None, given: bool = False
               ) -> tuple[float, float]:
    """(safety factor, order used) of the per-run estimate for an
    observed order from the shadows (``given`` False) or a plan's fitted
    order (``given`` True); see the module docstring."""
    if given:
        if 0.5 <= order <= 2.1:
            return SAFETY, float(order)
        return SAFETY_TWO_GRID, float(np.clip(order, 0.5, MAX_ORDER))
    if order is None or not math.isfinite(order):
        return SAFETY_TWO_GRID, FORMAL_ORDER
    return SAFETY_TWO_GRID, float(np.clip(order, FORMAL_ORDER, MAX_ORDER))

#: GCI safety factors (Roache 1998): three or more grids in the
#: asymptotic range / two grids or grids outside it.
SAFETY, SAFETY_TWO_GRID = 1.25, 3.0
#: Formal order of the scheme (first-order artificial viscosity and free
#: surface kernel sums) and the highest order the estimate uses.
FORMAL_ORDER, MAX_ORDER = 1.0, 2.0


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
    from .calculators import CLibrary
    from .scene import Scene
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
    order : float, optional
        Observed order to use (e.g. a plan's); default: measured from a
        second shadow run at 4 dx.
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
                 integrator: str | None = None):
        self.probes = probes
        self.scene = probes.scene
        self.order_given = order
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
        from .probes import Probes
        if self.scene_factory is not None:
            shadow = self.scene_factory(self.dx * factor)
        else:
            shadow = coarsened(self.scene, factor)
        if self.threads is not None and getattr(shadow, "_calc",
                                                None) is None:
            from .calculators import CLibrary
            shadow.calc = CLibrary(threads=self.threads)
        from .plan import _set_integrator, make_dynamics
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
        observed, factors = {}, {}
        if self.order_given is None:
            f4 = smoothed(self._shadow(4.0))
            for v in self.probes.values:
                d1 = max(metrics.deviation(f1[n][v], f2[n][v], "max")
                         for n in f1)
                d2 = max(metrics.deviation(f2[n][v], f4[n][v], "max")
                         for n in f1)
                observed[v] = (math.log2(d2 / d1) if d1 > 0 and d2 > 0
                               else math.nan)
                factors[v] = gci_factor(observed[v])
        else:
            for v in self.probes.values:
                observed[v] = float(self.order_given)
                factors[v] = gci_factor(observed[v], given=True)
        #: observed order per value (nan when the shadows do not differ)
        self.observed_order = observed
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
            g.attrs["smoothing_s"] = metrics.SMOOTHING
            g.attrs["shadow_seconds"] = self.shadow_seconds
            g.create_dataset("step", data=p.steps.astype(np.int64))
            g.create_dataset("time", data=p.times)
            g.create_dataset("value", data=value)
