"""Calculators: the backends that evaluate a scene and run its integrator.

All backends share one interface (:class:`Calculator`), so a script
switches backend with one line (``scene.calc = ...``). As in ASE, a
calculator evaluates (:meth:`Calculator.get_forces`,
:meth:`Calculator.get_stress`, rates on demand) and a dynamics object
(:mod:`sphsolid.dynamics`) integrates; the steps themselves are the C
library's integrators, which the dynamics object selects by name and the
calculator runs where the state lives (``sph_run``/``sph_run_until`` for
:class:`CLibrary`, LAMMPS's ``run`` for :class:`~sphsolid.lammps.Lammps`).

:class:`CLibrary` advances the scene's own libsphsolid handle.

A LAMMPS backend (:class:`Lammps`, in :mod:`sphsolid.lammps`) advances
the same scene through the ``lammps`` Python module and the plugin in
``lammps_plugin/``, then copies the state back into the scene's arrays
so probes, trajectories and figures work unchanged.
"""
from __future__ import annotations

import ctypes
from abc import ABC, abstractmethod
from typing import Callable, Optional

import numpy as np

from . import _lib
from ._lib import lib
from .units import time as _time

__all__ = ["Calculator", "CLibrary"]

#: A progress function gets the step count and returns True to stop.
Progress = Optional[Callable[[int], bool]]


class Calculator(ABC):
    """What every backend provides to the dynamics.

    Methods
    -------
    bind(scene)
        Take charge of a scene (called by ``scene.calc = calculator``).
    default_dt(), stable_dt()
        The default step 0.5 h / c0 and the stability limit [s].
    set_dt(dt, allow_unstable=False)
        Set the step [s]; above the stability limit only when allowed.
    set_integrator(name), integrator
        Select the library integrator ("improved_euler", "leapfrog") by
        name; its name.
    steps_until(t)
        Whole steps and the length of the last, shortened one that land on
        time ``t`` (asked of the library, which takes them).
    get_forces(), get_accelerations(), get_stress()
        Evaluate at the current state: m dv/dt [N, per unit depth in 2D],
        dv/dt [m/s^2] and the per-particle Cauchy stress [Pa].
    advance(steps, progress=None, interval=...)
        Take ``steps`` steps of the integrator. ``progress(step)`` is called
        every ``interval`` steps; if it returns True the run stops after a
        completed step and :class:`sphsolid.StoppedError` is raised.
    advance_until(t, progress=None, interval=...)
        Advance until time ``t`` [s] exactly (last step shortened).
    sync()
        Make the scene's arrays hold the backend's current state.
    dt, time, step
        Current step [s], simulated time [s] and step count.
    """

    name = "abstract"

    @abstractmethod
    def bind(self, scene) -> None:
        """Take charge of ``scene``."""

    @abstractmethod
    def default_dt(self) -> float:
        """0.5 h / c0 [s]."""

    @abstractmethod
    def stable_dt(self) -> float:
        """h / max(c_p + |v|) [s]."""

    @abstractmethod
    def set_dt(self, dt: float, allow_unstable: bool = False) -> None:
        """Set the time step [s]."""

    @abstractmethod
    def set_integrator(self, name: str) -> None:
        """Select the library integrator ``name``."""

    @property
    def integrator(self) -> str:
        """Name of the integrator in use."""
        return lib.sph_integrator_name(self.scene.handle).decode()

    def steps_until(self, t: float) -> tuple[int, float]:
        """Whole steps of dt to time ``t``, then the length of one
        shortened step landing on ``t`` (0: none), as the run takes them."""
        self.sync()
        return _lib.steps_until(self.scene.handle, _time(t, "t"))

    # -------------------------------------------------- evaluation (ASE)
    def get_accelerations(self) -> np.ndarray:
        """dv/dt at the current state [m/s^2], (n, dim): the integrator's
        rates of this state, else evaluated now by the library."""
        self.sync()
        return self.scene.accelerations

    def get_forces(self) -> np.ndarray:
        """m dv/dt at the current state [N; N per metre of depth in 2D],
        (n, dim)."""
        return self.scene.masses[:, None] * self.get_accelerations()

    def get_stress(self) -> np.ndarray:
        """Per-particle Cauchy stress -P I + S [Pa], (n, ncomp), components
        (xx, yy, zz, xy[, xz, yz]) (ASE's get_stress is one virial stress
        of the whole system in Voigt order: see docs/python.md)."""
        self.sync()
        return self.scene.stress

    @abstractmethod
    def advance(self, steps: int, progress: Progress = None,
                interval: int = 10) -> None:
        """Take ``steps`` steps of the integrator."""

    @abstractmethod
    def advance_until(self, t: float, progress: Progress = None,
                      interval: int = 10) -> None:
        """Advance to time ``t`` [s] exactly."""

    @property
    @abstractmethod
    def dt(self) -> float:
        """Time step [s]."""

    @property
    @abstractmethod
    def time(self) -> float:
        """Simulated time [s]."""

    @property
    @abstractmethod
    def step(self) -> int:
        """Steps taken."""

    def sync(self) -> None:  # noqa: B027 (optional hook, empty by default)
        """Nothing to do for backends that work on the scene's arrays."""


class CLibrary(Calculator):
    """The C library backend: the scene's own handle, advanced in C.

    Parameters
    ----------
    threads : int, optional
        OpenMP threads (default: OpenMP's default). Results do not depend
        on it.
    """

    name = "c"

    def __init__(self, threads: int | None = None):
        if threads is not None and (not isinstance(threads, int)
                                    or isinstance(threads, bool)
                                    or threads < 0):
            raise ValueError(f"threads must be a non-negative integer, got "
                             f"{threads!r}")
        self.threads = threads
        self.scene = None

    def bind(self, scene) -> None:
        if self.scene is not None and self.scene is not scene:
            raise RuntimeError("this calculator already serves another scene")
        self.scene = scene
        if self.threads is not None:
            self._check(lib.sph_set_threads(scene.handle, self.threads),
                        "threads")

    def _check(self, status, what=""):
        _lib.check(status, self.scene.handle, what)

    @property
    def _handle(self):
        if self.scene is None:
            raise RuntimeError("calculator not attached to a scene")
        return self.scene.handle

    def default_dt(self) -> float:
        return lib.sph_default_dt(self._handle)

    def stable_dt(self) -> float:
        return lib.sph_stable_dt(self._handle)

    def set_integrator(self, name: str) -> None:
        self._check(lib.sph_set_integrator(self._handle,
                                           _lib.encode_name(name)),
                    "integrator")

    def set_dt(self, dt: float, allow_unstable: bool = False) -> None:
        value = _time(dt, "dt")          # 1e-7 or "0.1us"; the library judges
        allow_unstable = _lib.flag(allow_unstable, "allow_unstable")
        self._check(lib.sph_set_dt(self._handle, value, int(allow_unstable)),
                    "dt")

    @property
    def dt(self) -> float:
        return lib.sph_dt(self._handle)

    @property
    def time(self) -> float:
        return lib.sph_time(self._handle)

    @property
    def step(self) -> int:
        return int(lib.sph_step_count(self._handle))

    def _with_progress(self, run, progress: Progress, interval: int):
        self.scene._touch()   # the user may have written through the views
        if progress is None:
            return self._check(run(), "run")
        errors = []

        def callback(_sim, _user):
            try:
                return 1 if progress(self.step) else 0
            except BaseException as error:  # never unwind through C
                errors.append(error)
                return 1

        c_callback = _lib.PROGRESS_FN(callback)
        self._check(lib.sph_set_progress(self._handle, max(1, int(interval)),
                                         c_callback, None), "progress")
        try:
            status = run()
            if not errors:
                # before the reset below, which clears the library's message
                self._check(status, "run")
        finally:
            lib.sph_set_progress(self._handle, 0,
                                 ctypes.cast(None, _lib.PROGRESS_FN), None)
        if errors:
            raise errors[0]

    def advance(self, steps: int, progress: Progress = None,
                interval: int = 10) -> None:
        self._with_progress(lambda: lib.sph_run(self._handle, int(steps)),
                            progress, interval)

    def advance_until(self, t: float, progress: Progress = None,
                      interval: int = 10) -> None:
        t = _time(t, "t")
        self._with_progress(lambda: lib.sph_run_until(self._handle, t),
                            progress, interval)
