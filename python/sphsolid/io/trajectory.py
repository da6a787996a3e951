"""Trajectories: HDF5 files in libsphsolid's layout, with an XDMF sidecar.

Writing goes through the library (``sph_output_open``/``_snapshot``/
``_close``), so a file written from Python is the same as one written by a C
program; reading uses h5py. The layout (docs/hdf5_layout.md) follows H5MD:
``/particles/all/<field>/{step,time,value}`` for position, velocity,
density, pressure, deviatoric_stress and von_mises, static ``mass``,
``body`` and ``material`` arrays, ``/parameters`` (bodies, materials,
effects) and ``/observables/probes``.

The library writes an XDMF file beside it on close (``piston.h5`` ->
``piston.xmf``) that lets ParaView open the particles and fields over time
directly; :func:`write_xdmf` (``sphsolid xdmf FILE.h5``) rewrites it.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np

from .. import _lib
from .._lib import lib
from ..units import time as _time

__all__ = ["Trajectory", "Frame", "ProbeSeries", "write_xdmf", "verify"]

_SERIES = ("position", "velocity", "density", "pressure", "deviatoric_stress",
           "von_mises")


@dataclass
class Frame:
    """One snapshot read from a trajectory (SI units)."""

    index: int
    time: float                      # [s]
    step: int
    positions: np.ndarray            # [m] (n, dim)
    velocities: np.ndarray           # [m/s] (n, dim)
    density: np.ndarray              # [kg/m^3] (n,)
    pressure: np.ndarray             # [Pa] (n,)
    deviatoric_stress: np.ndarray    # [Pa] (n, ncomp)
    von_mises: np.ndarray            # [Pa] (n,)
    masses: np.ndarray               # [kg] (n,)
    body_ids: np.ndarray             # (n,) int
    spacing: float = 0.0             # [m] nominal particle spacing
    damage: np.ndarray | None = None     # (n,) D, runs with effect damage
    fragment: np.ndarray | None = None   # (n,) fragment id (-1: none)

    def __repr__(self):
        top = float(self.von_mises.max()) if len(self.von_mises) else 0.0
        return (f"Frame({self.index}, t={self.time:.6g} s, step {self.step}, "
                f"{len(self.positions):,} particles, max von Mises "
                f"{top:.4g} Pa)")

    @classmethod
    def from_scene(cls, scene, index: int = 0) -> "Frame":
        """A copy of the scene's current state as a frame (no file)."""
        return cls(index=index, time=scene.time, step=scene.step,
                   positions=scene.positions.copy(),
                   velocities=scene.velocities.copy(),
                   density=scene.density.copy(), pressure=scene.pressure,
                   deviatoric_stress=scene.deviatoric_stress.copy(),
                   von_mises=scene.von_mises, masses=scene.masses.copy(),
                   body_ids=scene.body_ids,
                   spacing=scene.bodies[0].dx if scene.bodies else 0.0)


@dataclass
class ProbeSeries:
    """Probe samples stored in a trajectory file."""

    names: list
    columns: list
    points: np.ndarray   # [m] (nprobes, dim)
    steps: np.ndarray
    times: np.ndarray    # [s]
    values: np.ndarray   # [Pa] (frames, nprobes, ncolumns)

    def __getitem__(self, name: str) -> dict:
        """{column: array over time} for one probe."""
        if name not in self.names:
            raise KeyError(f"no probe {name!r}; probes: {self.names}")
        k = self.names.index(name)
        return {c: self.values[:, k, j] for j, c in enumerate(self.columns)}


class Trajectory:
    """An HDF5 trajectory, opened for reading (``'r'``) or writing (``'w'``).

    Writing (the scene's library handle writes the file)::

        traj = Trajectory("piston.h5", "w", scene, probe_interval=10)
        dyn.attach(traj, interval=500)   # snapshot every 500 steps
        dyn.run(until=1e-3)
        traj.close()                     # also writes piston.xmf

    Frame 0 (the state when opened) is written at once; closing writes the
    state at that moment as a last frame unless it is already the last one,
    so the file always ends with the final state. Probes registered
    in the scene before opening are sampled every ``probe_interval`` steps
    into ``/observables/probes``.

    Reading::

        with Trajectory("piston.h5") as traj:
            len(traj), traj[-1].von_mises, traj[::10], traj.probes["A"]

    Parameters
    ----------
    path : str or Path
    mode : {"r", "w"}
    scene : Scene
        Needed for writing.
    snapshot_interval : int
        Steps between automatic snapshots written by the library during a
        run (0: only those asked for with :meth:`write`).
    probe_interval : int
        Steps between probe samples (0: none).
    xdmf : bool
        Keep the XDMF companion the library writes on close (default True;
        False removes it).
    """

    def __init__(self, path, mode: str = "r", scene=None,
                 snapshot_interval: int = 0, probe_interval: int = 0,
                 xdmf: bool = True):
        self.path = Path(os.fspath(path))
        self.mode = mode
        self.scene = scene
        self._file = None
        self._closed = False
        self.xdmf = _lib.flag(xdmf, "xdmf")
        if mode == "r":
            self._open_read()
        elif mode == "w":
            if scene is None:
                raise ValueError("Trajectory: mode 'w' needs the scene to "
                                 "write")
            for name, value in (("snapshot_interval", snapshot_interval),
                                ("probe_interval", probe_interval)):
                if (not isinstance(value, int) or isinstance(value, bool)
                        or value < 0):
                    raise ValueError(f"Trajectory: {name} must be a "
                                     f"non-negative integer, got {value!r}")
            _require_library_clock(scene)
            scene.calc.sync()
            _lib.check(lib.sph_output_open(
                scene.handle, _lib.encode_path(self.path),
                snapshot_interval, probe_interval), scene.handle,
                f"Trajectory {str(self.path)!r}")
        else:
            raise ValueError(f"Trajectory: mode must be 'r' or 'w', got "
                             f"{mode!r}")

    # ------------------------------------------------------------ writing
    @property
    def xdmf_path(self) -> Path:
        """The XDMF sidecar's path (same name, suffix .xmf)."""
        return self.path.with_suffix(".xmf")

    def write(self) -> None:
        """Write a snapshot of the scene's current state (once per step)."""
        self._writable()
        _require_library_clock(self.scene)
        self.scene.calc.sync()
        _lib.check(lib.sph_output_snapshot(self.scene.handle),
                   self.scene.handle, f"Trajectory {str(self.path)!r}")

    __call__ = write

    def _writable(self):
        if self.mode != "w":
            raise ValueError(f"Trajectory {str(self.path)!r} is open for "
                             "reading")
        if self._closed:
            raise ValueError(f"Trajectory {str(self.path)!r} is closed")

    def flush(self) -> None:
        """Write the current state as a snapshot; the library flushes the
        file to disk with it. Called by the dynamics when a run is
        interrupted, so the file ends with the state where it stopped. (The
        XDMF sidecar is written by :meth:`close`: the library holds the
        file's lock until then.)"""
        if self.mode == "w" and not self._closed:
            self.write()

    def close(self) -> None:
        """Close the file; when writing, the library first adds the current
        state as a last frame (if not already written) and then writes the
        XDMF companion."""
        if self._closed:
            return
        self._closed = True
        if self.mode == "w":
            _require_library_clock(self.scene)
            self.scene.calc.sync()
            _lib.check(lib.sph_output_close(self.scene.handle),
                       self.scene.handle, f"Trajectory {str(self.path)!r}")
            if not self.xdmf:
                self.xdmf_path.unlink(missing_ok=True)
        elif self._file is not None:
            self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # ------------------------------------------------------------ reading
    def _open_read(self):
        import h5py
        if self.path.is_dir():
            raise OSError(f"Trajectory: cannot read {str(self.path)!r}: it "
                          "is a directory, not an HDF5 file")
        if not self.path.is_file():
            raise OSError(f"Trajectory: cannot read {str(self.path)!r}: no "
                          "such file")
        try:
            self._file = h5py.File(self.path, "r")
        except OSError as error:
            raise OSError(f"Trajectory: cannot read {str(self.path)!r} as "
                          f"HDF5: {error}") from None
        problem = _format_problem(self._file)
        if problem:
            self._file.close()
            raise OSError(f"Trajectory: {str(self.path)!r} {problem}")
        self._all = self._file["particles/all"]
        #: the file format (1: libsphsolid 0.1.0 and 0.2.0, before the
        #: version was recorded; then sph_output_format_version())
        version = self._file.attrs.get("sphsolid_format")
        self.format = 1 if version is None else int(np.ravel(version)[0])

    def _readable(self):
        if self.mode != "r":
            raise ValueError("Trajectory: open the file with mode 'r' to "
                             "read it")
        if self._closed:
            raise ValueError(f"Trajectory {str(self.path)!r} is closed")

    def __bool__(self) -> bool:
        return True       # an open trajectory is truthy, even when empty

    def __repr__(self):
        state = "closed" if self._closed else f"mode {self.mode!r}"
        if self.mode == "r" and not self._closed:
            times = self.times
            span = (f", {len(times)} frames, t = {times[0]:.6g} .. "
                    f"{times[-1]:.6g} s" if len(times) else ", no frames")
            state += f"{span}, {self._all['position/value'].shape[1]:,} particles"
        return f"Trajectory({str(self.path)!r}, {state})"

    def __len__(self) -> int:
        # frames count once the library has flushed them (complete_frames);
        # a frame being written when the writer stopped is not counted
        self._readable()
        if "complete_frames" in self._all.attrs:
            return min(int(self._all.attrs["complete_frames"]),
                       self._all["position/value"].shape[0])
        # format 1 recorded no count: the frames every series holds
        return min(self._all[f"{name}/{part}"].shape[0]
                   for name in _SERIES if name in self._all
                   for part in ("step", "time", "value"))

    @property
    def times(self) -> np.ndarray:
        """Times of the frames [s]."""
        self._readable()
        return self._read(self._all["position/time"], slice(0, len(self)))

    @property
    def steps(self) -> np.ndarray:
        self._readable()
        return self._read(self._all["position/step"], slice(0, len(self)))

    def _read(self, dataset, index):
        """dataset[index], naming the file when a checksum fails."""
        try:
            return dataset[index]
        except OSError as error:
            raise OSError(f"Trajectory: {str(self.path)!r} is damaged: "
                          f"{dataset.name} fails its checksum ({error})"
                          ) from None

    @property
    def dimension(self) -> int:
        self._readable()
        return int(self._file["parameters"].attrs["dimension"])

    @property
    def body_names(self) -> list:
        """Body names in index order."""
        self._readable()
        bodies = self._file["parameters/bodies"]
        return sorted(bodies, key=lambda b: int(bodies[b].attrs["index"]))

    @property
    def parameters(self) -> dict:
        """The /parameters attributes (dimension, h, dt, effects, ...)."""
        self._readable()
        return {k: _attr(v) for k, v in
                self._file["parameters"].attrs.items()}

    def frame(self, index: int) -> Frame:
        """Frame ``index`` (negative counts from the end)."""
        self._readable()
        n = len(self)
        if not isinstance(index, (int, np.integer)):
            raise ValueError(f"Trajectory: frame index must be an integer, "
                             f"got {index!r}")
        if index < 0:
            index += n
        if not 0 <= index < n:
            raise IndexError(f"Trajectory: frame {index} out of range "
                             f"({n} frames)")
        a = self._all
        r = self._read
        return Frame(
            index=int(index), time=float(r(a["position/time"], index)),
            step=int(r(a["position/step"], index)),
            positions=r(a["position/value"], index),
            velocities=r(a["velocity/value"], index),
            density=r(a["density/value"], index),
            pressure=r(a["pressure/value"], index),
            deviatoric_stress=r(a["deviatoric_stress/value"], index),
            von_mises=r(a["von_mises/value"], index),
            masses=r(a["mass"], slice(None)),
            body_ids=r(a["body"], slice(None)),
            spacing=float(np.ravel(
                self._file["parameters"].attrs["spacing"])[0]),
            damage=r(a["damage/value"], index) if "damage" in a else None,
            fragment=(r(a["fragment/value"], index).astype(np.int64)
                      if "fragment" in a else None))

    def __getitem__(self, key):
        if isinstance(key, slice):
            return [self.frame(i) for i in range(*key.indices(len(self)))]
        return self.frame(key)

    def __iter__(self) -> Iterator[Frame]:
        for i in range(len(self)):
            yield self.frame(i)

    def nearest(self, time: float) -> Frame:
        """The frame closest to ``time`` [s] (or a string such as
        ``"0.2ms"``)."""
        t = _time(time, "time")
        return self.frame(int(np.argmin(np.abs(self.times - t))))

    @property
    def probes(self) -> ProbeSeries | None:
        """Probe samples in the file, or None if it has none."""
        self._readable()
        if "observables/probes" not in self._file:
            return None
        g = self._file["observables/probes"]
        if "complete_samples" in g.attrs:
            done = slice(0, int(g.attrs["complete_samples"]))
        else:       # format 1: the samples every series holds
            done = slice(0, min(g[k].shape[0] for k in ("step", "time", "value")))
        return ProbeSeries(names=_attr(g.attrs["names"]).split(),
                           columns=_attr(g.attrs["columns"]).split(),
                           points=self._read(g["points"], slice(None)),
                           steps=self._read(g["step"], done),
                           times=self._read(g["time"], done),
                           values=self._read(g["value"], done))

    def load_into(self, scene, index: int = -1) -> None:
        """Load frame ``index`` into a scene built like the one that wrote
        the file (positions, velocities, density, stress, time, step) with
        the library's ``sph_read_frame``."""
        _lib.check(lib.sph_read_frame(scene.handle,
                                      _lib.encode_path(self.path), index),
                   scene.handle, f"Trajectory {str(self.path)!r}")

    def verify(self) -> dict:
        """Read every object of the file back (:func:`verify`)."""
        self._readable()
        return verify(self.path)

    def describe(self) -> str:
        """A summary for people (``sphsolid info``)."""
        self._readable()
        p = self.parameters
        times = self.times
        lines = [f"{self.path}: libsphsolid output "
                 f"({_attr(self._file['h5md/creator'].attrs.get('version', b'?'))})",
                 f"  dimension {p.get('dimension')}, kernel {p.get('kernel')},"
                 f" integrator {_attr(p.get('integrator', 'unknown'))},"
                 f" h = {float(np.ravel(p['smoothing_length'])[0]) * 1e3:.4g}"
                 f" mm, dt = {float(np.ravel(p['dt'])[0]) * 1e6:.4g} us",
                 f"  effects: {_effect_list(p.get('effects'))}"]
        bodies = self._file["parameters/bodies"]
        total = 0
        for name in self.body_names:
            a = bodies[name].attrs
            total += int(a["count"])
            lines.append(f"  body {name}: {int(a['count'])} particles, "
                         f"motion {_attr(a['motion'])}, spacing "
                         f"{float(np.ravel(a['spacing'])[0]) * 1e3:.4g} mm")
        lines.append(f"  particles: {total}")
        if len(times):
            lines.append(f"  frames: {len(times)}, t = {times[0] * 1e3:.6g} "
                         f"to {times[-1] * 1e3:.6g} ms")
        probes = self.probes
        if probes is not None:
            lines.append(
                f"  probes: {' '.join(probes.names)}, {len(probes.times)} "
                "samples" + (f" to t = {probes.times[-1] * 1e3:.6g} ms"
                             if len(probes.times) else ""))
            if len(probes.times):
                last = probes.values[-1]
                for k, name in enumerate(probes.names):
                    point = ", ".join(f"{c:g}" for c in probes.points[k])
                    lines.append(f"    {name} at ({point}) m:"
                                 f" von Mises {last[k, 0]:.6g} Pa at the end")
        return "\n".join(lines)


def verify(path) -> dict:
    """Read every object of an HDF5 file back, every dataset whole (chunk
    by chunk), so that HDF5 checks each chunk's Fletcher32 checksum and
    each object header's metadata checksum: the proof that a file is
    whole that ``sphsolid info`` (``--verify``, the default) and
    ``sphsolid xdmf`` give.

    Returns ``datasets`` (how many), ``bytes`` (of data read),
    ``checksummed`` (datasets with the Fletcher32 filter) and
    ``unchecked`` (names of non-empty datasets without it: files of format
    1, or written by other programs).  Raises OSError naming the file and
    every object that cannot be read back (a failed checksum, a damaged
    header), and how many of them."""
    import h5py
    path = Path(os.fspath(path))
    failed, unchecked = [], []
    counts = {"datasets": 0, "bytes": 0, "checksummed": 0}

    def read(obj):
        try:
            for name in obj.attrs:
                obj.attrs[name]
        except (OSError, KeyError, RuntimeError) as error:
            failed.append(f"the attributes of {obj.name} ({_reason(error)})")
            return
        if isinstance(obj, h5py.Dataset):
            counts["datasets"] += 1
            try:
                if obj.chunks is not None and obj.size:
                    for block in obj.iter_chunks():
                        counts["bytes"] += obj[block].nbytes
                else:
                    counts["bytes"] += np.asarray(obj[()]).nbytes
            except (OSError, RuntimeError, ValueError) as error:
                failed.append(f"dataset {obj.name} ({_reason(error)})")
                return
            if obj.fletcher32:
                counts["checksummed"] += 1
            elif obj.size:
                unchecked.append(obj.name)
            return
        try:
            names = list(obj)
        except (OSError, RuntimeError) as error:
            failed.append(f"group {obj.name} ({_reason(error)})")
            return
        for name in names:
            try:
                child = obj[name]
            except (OSError, KeyError, RuntimeError) as error:
                failed.append(f"{obj.name.rstrip('/')}/{name} "
                              f"({_reason(error)})")
                continue
            read(child)

    try:
        f = h5py.File(path, "r")
    except OSError as error:
        raise OSError(f"verify: cannot read {str(path)!r} as HDF5: "
                      f"{_reason(error)}") from None
    with f:
        read(f)
    if failed:
        raise OSError(f"{path}: damaged: {'; '.join(failed[:4])}"
                      + (f"; and {len(failed) - 4} more" if len(failed) > 4
                         else "")
                      + f" ({len(failed)} object(s) of the file cannot be "
                      "read back)")
    return dict(counts, unchecked=unchecked)


def _reason(error) -> str:
    """HDF5's reason, without the error stack's noise."""
    text = str(error).strip().splitlines()[0] if str(error).strip() else ""
    text = text.strip("'\"") or type(error).__name__
    if "filter returned failure" in text:
        return f"fails its Fletcher32 checksum; HDF5: {text}"
    return text


def file_format() -> int:
    """The output file format the library writes, which this module reads
    (``sph_output_format_version``)."""
    return int(lib.sph_output_format_version())


#: what every format-1 output holds (the reader's minimum)
_FORMAT_1_NEEDS = ("parameters", "particles/all/mass", "particles/all/body",
                   *(f"particles/all/{name}/{part}" for name in _SERIES
                     for part in ("step", "time", "value")))


def _format_problem(f) -> str:
    """Why an open h5py file is not a libsphsolid output file this
    version reads ('' when it is one)."""
    version = f.attrs.get("sphsolid_format")
    if version is None:
        # format 1 (libsphsolid 0.1.0 and 0.2.0) recorded no version: an
        # output has the H5MD group and the position series
        if "h5md" in f and "particles/all/position/value" in f:
            missing = [k for k in _FORMAT_1_NEEDS if k not in f]
            return (f"is a libsphsolid output of file format 1 without "
                    f"{', '.join('/' + k for k in missing)}" if missing else "")
        if "checkpoint" in f:
            return ("is a checkpoint in libsphsolid file format 1 (written "
                    "before the format was versioned), not an output file")
        return "is not a libsphsolid file (no sphsolid_format attribute)"
    if int(np.ravel(version)[0]) != file_format():
        return (f"has libsphsolid file format {int(np.ravel(version)[0])}; "
                f"this version reads format {file_format()}")
    content = _attr(f.attrs.get("sphsolid_content", b""))
    if content != "output":
        return f"is a libsphsolid {content or '(unknown)'} file, not an output file"
    return ""


def _require_library_clock(scene) -> None:
    """The library writes its own time and step into the file; refuse to
    write when another backend advanced the scene without them."""
    calc = scene.calc
    if (calc.time != lib.sph_time(scene.handle)
            or calc.step != lib.sph_step_count(scene.handle)):
        raise _lib.UnsupportedError(
            f"Trajectory: the {calc.name!r} backend is at step {calc.step}, "
            f"t = {calc.time!r} s but the library's clock is at step "
            f"{lib.sph_step_count(scene.handle)}; writing a trajectory from "
            "this backend needs a library call to set the clock")


def _attr(value):
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.ndarray) and value.dtype.kind == "S":
        return [v.decode() for v in value]
    return value


def _effect_list(value) -> str:
    """The file's effects attribute ("name k=v; name k=v; ") as "name
    k=v; name k=v" ("none" without effects)."""
    parts = [part.strip() for part in _attr(value or "").split(";")]
    return "; ".join(part for part in parts if part) or "none"


def write_xdmf(h5_path) -> Path:
    """Write (or rewrite) the XDMF companion of a libsphsolid HDF5 file
    for ParaView: ``run.h5`` -> ``run.xmf`` (the library's
    ``sph_write_xdmf``, which ``sph_output_close`` also calls).

    One grid per frame (a temporal collection) of polyvertex cells, with
    velocity as a vector, density, pressure, von Mises stress and body as
    scalars, and each deviatoric stress component as a scalar
    (``S_xx``, ``S_yy``, ...); the data stay in the HDF5 file.
    """
    h5_path = Path(os.fspath(h5_path))
    if h5_path.is_dir():
        raise OSError(f"write_xdmf: {str(h5_path)!r} is a directory, not an "
                      "HDF5 output file")
    handle = _lib.new_handle(2)          # only carries the error message
    try:
        _lib.check(lib.sph_write_xdmf(handle, _lib.encode_path(h5_path)),
                   handle, "write_xdmf")
    finally:
        lib.sph_destroy(handle)
    return h5_path.with_suffix(".xmf")
