"""Probes: stress at fixed points as time series.

The values are the library's Shepard-normalised kernel interpolation at the
point (``sph_probe_sample``): von Mises stress, pressure and the full Cauchy
stress components.
"""
from __future__ import annotations

import csv
import ctypes
from typing import Mapping, Sequence

import numpy as np

from . import _lib
from ._lib import lib
from .units import lengths as _lengths

__all__ = ["Probes", "PAPER_PROBES", "value_names"]

#: The paper's monitoring points A, B, C [m] (its Figure 5).
PAPER_PROBES = {"A": (0.0, 0.070), "B": (0.0215, 0.1035),
                "C": (0.0215, 0.070)}


def value_names(dimension: int) -> list[str]:
    """Names of the values a probe reports, in the library's order."""
    stress = (["sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy"]
              if dimension == 2 else
              ["sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "sigma_xz",
               "sigma_yz"])
    return ["von_mises", "pressure"] + stress


class Probes:
    """Points where the stress is sampled, and the series recorded there.

    Attach it to a dynamics object to record a sample on a schedule::

        probes = Probes(scene, PAPER_PROBES)
        dyn.attach(probes, interval=10)
        ...
        probes.times, probes["A"]["von_mises"]

    Probes registered here are also written by a :class:`Trajectory`
    opened afterwards with ``probe_interval``.

    Parameters
    ----------
    scene : Scene
    points : mapping of name to point [m], optional
    outside : "error" or "nan"
        A probe with no particle within 2h (outside every body) raises
        :class:`SimulationError` naming it (``"error"``, the default, as in
        the C library and the LAMMPS compute), or records NaN (``"nan"``).
        The setting belongs to the scene, so a Trajectory's probe samples
        follow it too.
    """

    def __init__(self, scene, points: Mapping[str, Sequence[float]] = None,
                 outside: str = "error"):
        if outside not in ("error", "nan"):
            raise ValueError(f"Probes: outside must be 'error' or 'nan', got "
                             f"{outside!r}")
        _lib.check(lib.sph_set_probe_outside(scene.handle,
                                             int(outside == "nan")),
                   scene.handle, "Probes")
        self.outside = outside
        self.scene = scene
        self.names: list[str] = []
        #: {name: point [m]} of every probe
        self.points: dict[str, tuple] = {}
        self._index: dict[str, int] = {}
        self.values = value_names(scene.dimension)
        self._times: list[float] = []
        self._steps: list[int] = []
        self._samples: list[np.ndarray] = []
        for name, point in (points or {}).items():
            self.add(name, point)

    def add(self, name: str, point: Sequence[float]) -> None:
        """Add a probe at ``point`` [m]."""
        if not isinstance(name, str):
            raise ValueError(f"probe name must be a string, got {name!r}")
        if self._samples:
            raise RuntimeError("cannot add a probe after samples were taken")
        dim = self.scene.dimension
        coords = _lib.as_doubles(          # (0, "50mm") too
            _lengths(point, f"probe {name!r} point", dim), dim,
            f"probe {name!r} point")
        index = ctypes.c_int()
        _lib.check(lib.sph_add_probe(self.scene.handle, name.encode(), coords,
                                     ctypes.byref(index)),
                   self.scene.handle, f"probe {name!r}")
        self._index[name] = index.value
        self.names.append(name)
        self.points[name] = tuple(coords[:])

    def sample(self) -> dict[str, dict[str, float]]:
        """Values at every probe now: {name: {value name: value [Pa]}}."""
        array = self._sample_array()
        return {name: dict(zip(self.values, array[i]))
                for i, name in enumerate(self.names)}

    def _sample_array(self) -> np.ndarray:
        handle = self.scene.handle
        out = np.empty((len(self.names), len(self.values)))
        buffer = (ctypes.c_double * len(self.values))()
        for row, name in enumerate(self.names):
            _lib.check(lib.sph_probe_sample(handle, self._index[name], buffer),
                       handle, f"probe {name!r}")
            out[row] = buffer[:]
        return out

    def record(self) -> None:
        """Append a sample at the current time to the series."""
        self.scene.calc.sync()
        self._times.append(self.scene.time)
        self._steps.append(self.scene.step)
        self._samples.append(self._sample_array())

    __call__ = record

    def record_final(self) -> None:
        """Record the current state unless the last sample is of this step:
        after a run, the series then ends at its end time."""
        if not self._steps or self._steps[-1] != self.scene.step:
            self.record()

    def load(self, series, interval: int | None = None,
             final: bool = False) -> None:
        """Take the samples of these probes recorded by the library into a
        trajectory file (:attr:`Trajectory.probes`, a ``ProbeSeries``),
        replacing any recorded here.

        A run that writes a trajectory with ``probe_interval`` gets its
        series this way without a Python observer: the library samples
        the same points with the same function (``sph_probe_sample``), so
        the series are those :meth:`record` takes at those steps, and the
        steps run without returning to Python between samples.  With
        ``interval`` only the samples at multiples of it are taken (a
        trajectory also samples the state it is closed at): those an
        observer attached with that interval records; ``final`` keeps the
        file's last sample too (the state the file was closed at).
        """
        if list(series.names) != self.names:
            raise ValueError(f"the file's probes {list(series.names)} are not"
                             f" these probes {self.names}")
        if list(series.columns) != self.values:
            raise ValueError(f"the file's probe columns {list(series.columns)}"
                             f" are not {self.values}")
        final = _lib.flag(final, "final")
        last = len(series.steps) - 1
        keep = [k for k, step in enumerate(series.steps)
                if interval is None or int(step) % interval == 0
                or (final and k == last)]
        self._times = [float(series.times[k]) for k in keep]
        self._steps = [int(series.steps[k]) for k in keep]
        self._samples = [np.array(series.values[k]) for k in keep]

    @property
    def times(self) -> np.ndarray:
        """Times of the recorded samples [s]."""
        return np.array(self._times)

    @property
    def steps(self) -> np.ndarray:
        return np.array(self._steps, dtype=int)

    def series(self, name: str) -> dict[str, np.ndarray]:
        """Recorded series of one probe: {value name: array [Pa]}."""
        if name not in self._index:
            raise KeyError(f"no probe {name!r}; probes: {self.names}")
        row = self.names.index(name)
        data = (np.array([s[row] for s in self._samples])
                if self._samples else np.empty((0, len(self.values))))
        return {value: data[:, k] for k, value in enumerate(self.values)}

    def __getitem__(self, name: str) -> dict[str, np.ndarray]:
        return self.series(name)

    def __len__(self) -> int:
        return len(self.names)

    def __repr__(self):
        span = (f", t = {self._times[0]:.6g} .. {self._times[-1]:.6g} s"
                if self._times else "")
        return (f"Probes([{', '.join(self.names)}], {len(self._times)} "
                f"samples{span})")

    def to_pandas(self):
        """The series as a pandas DataFrame indexed by time [s], with a
        ``step`` column and columns ``(probe, value)`` [Pa] (a two-level
        column index: ``df["A"]["von_mises"]``). Needs pandas."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Probes.to_pandas needs pandas (pip install "
                              "pandas)") from None
        data = (np.array(self._samples) if self._samples
                else np.empty((0, len(self.names), len(self.values))))
        columns = pd.MultiIndex.from_product([self.names, self.values],
                                             names=["probe", "value"])
        frame = pd.DataFrame(data.reshape(len(data), -1), columns=columns,
                             index=pd.Index(self.times, name="time_s"))
        frame.insert(0, ("step", ""), self.steps)
        return frame

    def write_csv(self, path) -> None:
        """Write the series as CSV: time [s], step, then
        ``<probe>_<value>`` [Pa] columns."""
        with open(path, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(["time_s", "step"] + [
                f"{name}_{value}_Pa" for name in self.names
                for value in self.values])
            for t, step, sample in zip(self._times, self._steps,
                                       self._samples):
                writer.writerow([repr(float(t)), int(step)] +
                                [repr(float(v)) for v in sample.ravel()])
