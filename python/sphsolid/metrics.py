"""Error metrics of probe time series (comparison only: no physics here).

The accuracy metric used by the planner, the per-run error estimate and the
validation studies: both series are put on one time grid and smoothed with a
Gaussian of standard deviation ``sigma`` (1 µs by default), then per probe

- ``"max"``: the largest deviation as a fraction of the reference's peak
  ``max |ref|``;
- ``"rms"``: the RMS deviation as a fraction of the reference's RMS;

and the worst probe counts.
"""
from __future__ import annotations

from typing import Mapping

import math

import numpy as np

__all__ = ["SMOOTHING", "time_grid", "smooth", "on_grid", "deviation",
           "scale_of",
           "probe_deviations", "worst_deviation", "PROBE_SPACING",
           "probe_interval_for"]

#: Standard deviation of the Gaussian both series are smoothed with [s].
SMOOTHING = 1e-6
#: The default time between probe samples [s]: a quarter of the metric's
#: smoothing, so that a series sampled at it and interpolated linearly
#: differs from the every-step series by far less than any error the
#: planner is asked for (a 6.2 us interval put a 1.6 % run at 2.9 % RMS).
PROBE_SPACING = SMOOTHING / 4


def probe_interval_for(dt: float, spacing: float = PROBE_SPACING) -> int:
    """Steps between probe samples for a step ``dt`` [s]: the most steps
    whose time is within ``spacing`` (at least 1)."""
    if not (dt > 0 and math.isfinite(dt)):
        raise ValueError(f"dt must be a time > 0 s, got {dt!r}")
    return max(1, int(math.floor(spacing / dt * (1 + 1e-9))))


def time_grid(start: float, stop: float, sigma: float = SMOOTHING,
              points_per_sigma: float = 4.0, max_points: int = 20000
              ) -> np.ndarray:
    """A uniform grid over [start, stop] [s] fine enough for ``sigma``."""
    if not stop > start:
        raise ValueError(f"time window must have stop > start, got "
                         f"[{start!r}, {stop!r}]")
    n = int(np.ceil((stop - start) / sigma * points_per_sigma)) + 1
    return np.linspace(start, stop, int(np.clip(n, 50, max_points)))


def on_grid(times, values, grid) -> np.ndarray:
    """``values`` sampled at ``times`` linearly interpolated onto ``grid``."""
    times = np.asarray(times, float)
    values = np.asarray(values, float)
    if times.ndim != 1 or len(times) != len(values) or len(times) < 2:
        raise ValueError(f"need at least two samples with one value each, "
                         f"got {len(times)} times and {len(values)} values")
    return np.interp(grid, times, values)


def smooth(grid, values, sigma: float = SMOOTHING) -> np.ndarray:
    """Gaussian smoothing (standard deviation ``sigma`` [s]) of a series on
    the uniform ``grid``, normalised at the ends (each output is a weighted
    mean of the samples inside the window, so a constant stays constant).
    ``sigma`` = 0 returns the series unchanged."""
    values = np.asarray(values, float)
    if sigma <= 0 or len(grid) < 2:
        return values.copy()
    step = float(grid[1] - grid[0])
    half = int(np.ceil(4 * sigma / step))
    if half < 1:
        return values.copy()
    offsets = np.arange(-half, half + 1) * step
    weights = np.exp(-0.5 * (offsets / sigma) ** 2)
    total = np.convolve(values, weights, mode="same")
    norm = np.convolve(np.ones_like(values), weights, mode="same")
    return total / norm


def scale_of(reference, norm: str = "max") -> float:
    """The normaliser of :func:`deviation`: max|ref| or rms(ref)."""
    reference = np.asarray(reference, float)
    if norm == "max":
        return float(np.max(np.abs(reference)))
    if norm == "rms":
        return float(np.sqrt(np.mean(reference ** 2)))
    raise ValueError(f"norm must be 'max' or 'rms', got {norm!r}")


def deviation(values, reference, norm: str = "max",
              scale: float | None = None) -> float:
    """Deviation of one (already smoothed) series from its reference on the
    same grid, as a fraction: ``"max"`` max|d| / max|ref|, ``"rms"``
    rms(d) / rms(ref); ``scale`` replaces the denominator (to compare
    differences between several series on one scale)."""
    values = np.asarray(values, float)
    reference = np.asarray(reference, float)
    d = values - reference
    if scale is None:
        scale = scale_of(reference, norm)
    if norm == "max":
        size = float(np.max(np.abs(d)))
    elif norm == "rms":
        size = float(np.sqrt(np.mean(d ** 2)))
    else:
        raise ValueError(f"norm must be 'max' or 'rms', got {norm!r}")
    if scale > 0:
        return size / float(scale)
    return 0.0 if size == 0 else float("inf")


def probe_deviations(series: Mapping[str, np.ndarray],
                     reference: Mapping[str, np.ndarray], grid,
                     norm: str = "max", sigma: float = SMOOTHING,
                     smoothed: bool = False) -> dict:
    """Per-probe :func:`deviation` of series on ``grid`` (smoothed here with
    ``sigma`` unless ``smoothed``)."""
    out = {}
    for name, ref in reference.items():
        if name not in series:
            raise KeyError(f"no series for probe {name!r}")
        a, b = series[name], ref
        if not smoothed:
            a, b = smooth(grid, a, sigma), smooth(grid, b, sigma)
        out[name] = deviation(a, b, norm)
    return out


def worst_deviation(series, reference, grid, norm: str = "max",
                    sigma: float = SMOOTHING, smoothed: bool = False) -> float:
    """The worst probe's :func:`deviation` (the metric of the planner)."""
    return max(probe_deviations(series, reference, grid, norm, sigma,
                                smoothed).values())
