"""Figures like the paper's: von Mises field maps and probe time series.

Both return a :class:`matplotlib.figure.Figure` with units on the axes
(shown inline in Jupyter) and write it only when given a ``path``. They
never touch pyplot's state or the user's backend: the figure is made with
``matplotlib.figure.Figure`` directly. They take data, not a scene: frames
from a :class:`~sphsolid.Trajectory` (or anything with ``positions``,
``von_mises`` and ``time``) and probe series from
:class:`~sphsolid.Probes` or a trajectory file.
"""
from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

__all__ = ["von_mises_map", "probe_curves", "stress_unit", "time_unit"]

_STRESS_UNITS = (("MPa", 1e6), ("kPa", 1e3), ("Pa", 1.0))
_TIME_UNITS = (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6))


def stress_unit(max_value: float) -> tuple[str, float]:
    """A readable stress unit for values up to ``max_value`` [Pa]."""
    for name, scale in _STRESS_UNITS:
        if max_value >= scale:
            return name, scale
    return "Pa", 1.0


def time_unit(max_time: float) -> tuple[str, float]:
    """A readable time unit for times up to ``max_time`` [s]."""
    for name, scale in _TIME_UNITS:
        if max_time >= scale:
            return name, scale
    return "µs", 1e-6


def _figure(**kwargs):
    """A Figure outside pyplot (no backend selected, no global state)."""
    from matplotlib.figure import Figure
    return Figure(constrained_layout=True, **kwargs)


def _finish(fig, path):
    if path is not None:
        from pathlib import Path
        fig.savefig(Path(path), dpi=120)
    return fig


def _spacing(frame, positions: np.ndarray) -> float:
    """Particle spacing [m]: the frame's own, else sqrt(area / count)."""
    spacing = getattr(frame, "spacing", None)
    if spacing:
        return float(spacing)
    extent = np.ptp(positions[:, :2], axis=0)
    return float(np.sqrt(max(extent[0] * extent[1], 1e-300) / len(positions)))


def von_mises_map(frames, path=None, mask=None, vmax: float | None = None,
                  title: str | None = None, columns: int | None = None):
    """von Mises stress field maps (like the paper's Figs 2-4 and 12).

    Parameters
    ----------
    frames : frame or sequence of frames
        Each with ``positions`` [m] (n, 2 or 3; x and y are drawn),
        ``von_mises`` [Pa] (n,), ``time`` [s] and optionally ``spacing``
        [m] (the size of the square drawn per particle).
    path : str or Path, optional
        File to write (PNG, PDF, SVG: by its suffix); default none.
    mask : callable(frame) -> bool array, optional
        Particles to draw (e.g. only the specimen); default all.
    vmax : float, optional
        Top of the colour scale [Pa]; default the largest value shown.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import Normalize
    from matplotlib.collections import PolyCollection
    if not isinstance(frames, (list, tuple)):
        frames = [frames]
    if not frames:
        raise ValueError("von_mises_map: frames is empty")
    selected = []
    for frame in frames:
        keep = (np.ones(len(frame.von_mises), bool) if mask is None
                else np.asarray(mask(frame), bool))
        selected.append((frame, frame.positions[keep], frame.von_mises[keep]))
    top = vmax if vmax is not None else max(
        float(np.max(v)) if len(v) else 0.0 for _, _, v in selected)
    unit, scale = stress_unit(top)
    n = len(frames)
    columns = columns or min(n, 4)
    rows = -(-n // columns)
    fig = _figure(figsize=(3.2 * columns + 1.0, 4.6 * rows))
    axes = fig.subplots(rows, columns, squeeze=False)
    norm = Normalize(0.0, top / scale if top > 0 else 1.0)
    mappable = None
    for ax, (frame, x, vm) in zip(axes.ravel(), selected):
        spacing = _spacing(frame, x) * 1e3
        # squares a little wider than the nominal spacing: a lattice of
        # round(L/dx) sites is slightly looser than dx, and gaps would show
        # (one array of corners: a patch object per particle took seven
        # times as long to draw)
        side = 1.08 * spacing
        corners = 0.5 * side * np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]])
        squares = x[:, None, :2] * 1e3 + corners[None]
        patches = PolyCollection(squares, closed=True, cmap="jet", norm=norm,
                                 linewidths=0)
        patches.set_array(vm / scale)
        ax.add_collection(patches)
        mappable = patches
        ax.set_xlim(x[:, 0].min() * 1e3 - spacing / 2,
                    x[:, 0].max() * 1e3 + spacing / 2)
        ax.set_ylim(x[:, 1].min() * 1e3 - spacing / 2,
                    x[:, 1].max() * 1e3 + spacing / 2)
        ax.set_aspect("equal")
        tname, tscale = time_unit(frame.time)
        ax.set_title(f"t = {frame.time / tscale:.4g} {tname}")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
    for ax in axes.ravel()[n:]:
        ax.set_visible(False)
    fig.colorbar(mappable, ax=axes.ravel().tolist(), shrink=0.8,
                 label=f"von Mises stress [{unit}]")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def probe_curves(times: Sequence[float],
                 series: Mapping[str, Sequence[float]], path=None,
                 quantity: str = "von Mises stress",
                 title: str | None = None,
                 bands: Mapping[str, Sequence[float]] | None = None):
    """Probe time series (like the paper's Figs 6-9).

    Parameters
    ----------
    times : array [s]
    series : mapping of label to array [Pa], each as long as ``times``
    path : str or Path, optional
        File to write (by its suffix); default none.
    quantity : str
        Label of the y axis (its unit is added).
    bands : mapping of label to array [Pa], optional
        Half-widths of an error band per series (e.g. from
        :class:`sphsolid.planner.estimate.ErrorEstimate`), drawn shaded.

    Returns
    -------
    matplotlib.figure.Figure
    """
    times = np.asarray(times, dtype=float)
    if not series:
        raise ValueError("probe_curves: no series given")
    for label, values in series.items():
        if len(values) != len(times):
            raise ValueError(f"probe_curves: series {label!r} has "
                             f"{len(values)} values for {len(times)} times")
    top = max((float(np.max(np.abs(v))) for v in series.values() if len(v)),
              default=0.0)
    unit, scale = stress_unit(top)
    tname, tscale = time_unit(times.max() if len(times) else 0.0)
    fig = _figure(figsize=(6.4, 4.2))
    ax = fig.subplots()
    for label, values in series.items():
        line, = ax.plot(times / tscale, np.asarray(values) / scale,
                        label=label)
        if bands is not None and label in bands:
            half = np.asarray(bands[label], float)
            ax.fill_between(times / tscale, (np.asarray(values) - half) / scale,
                            (np.asarray(values) + half) / scale,
                            color=line.get_color(), alpha=0.25, linewidth=0,
                            label=f"{label} error band")
    ax.set_xlabel(f"time [{tname}]")
    ax.set_ylabel(f"{quantity} [{unit}]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    if title:
        ax.set_title(title)
    return _finish(fig, path)
