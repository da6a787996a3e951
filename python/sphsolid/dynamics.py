"""Dynamics: advance a scene in time with observers on a schedule (ASE's
``Dynamics`` shape: ``attach(function, interval)`` then ``run(...)``)."""
from __future__ import annotations

import math
import signal
import threading
from typing import Callable

from . import _lib
from ._lib import StoppedError, SimulationError
from .units import time as _time

__all__ = ["Dynamics", "ImprovedEuler", "Leapfrog", "dynamics_for"]


class _Observer:
    __slots__ = ("function", "interval", "args", "kwargs", "last_step")

    def __init__(self, function, interval, args, kwargs):
        self.function = function
        self.interval = interval
        self.args = args
        self.kwargs = kwargs
        self.last_step = None

    def next_step(self, step: int) -> int:
        return (step // self.interval + 1) * self.interval


class Dynamics:
    """Time stepping of a scene by one of the library's integrators.

    The integrator (:attr:`integrator`, a library name) is selected on the
    scene's calculator, which takes the steps where the state lives (the C
    library, or LAMMPS). Use :class:`ImprovedEuler` or :class:`Leapfrog`.

    Parameters
    ----------
    scene : Scene
        Its calculator (``scene.calc``, default the C library) does the
        steps.
    dt : float, optional
        Time step [s]. Default: the integrator's default step in the library
        (:func:`sph_default_dt`).
    allow_unstable : bool
        Accept a ``dt`` above the integrator's stability limit.
    progress : bool or None
        Show a tqdm progress bar: True always, False never, None (default)
        for runs of at least ``progress_threshold`` steps on a terminal.
    progress_threshold : int
        Steps from which a run counts as long.
    """

    integrator = None

    def __init__(self, scene, dt: float | None = None,
                 allow_unstable: bool = False, progress: bool | None = None,
                 progress_threshold: int = 2000):
        if self.integrator is None:
            raise TypeError("Dynamics is the base class: use ImprovedEuler or "
                            "Leapfrog")
        self.scene = scene
        self.calc = scene.calc
        try:
            self.calc.set_integrator(self.integrator)
        except RuntimeError as error:
            if "exceeds its stability limit" not in str(error):
                raise
            # a step set for the previous integrator is above this one's
            # limit: step within both, then this dynamics sets its own below
            self.calc.set_dt(0.5 * self.calc.stable_dt())
            self.calc.set_integrator(self.integrator)
        if dt is None:
            dt = self.calc.default_dt()
        else:
            dt = _time(dt, "dt")                # 1e-7 or "0.1us"
        self.calc.set_dt(dt, allow_unstable)
        self.observers: list[_Observer] = []
        self.progress = (None if progress is None
                         else _lib.flag(progress, "progress"))
        self.progress_threshold = progress_threshold
        self._interrupted = False

    # ------------------------------------------------------------ state
    @property
    def dt(self) -> float:
        """Time step [s]."""
        return self.calc.dt

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self.calc.time

    @property
    def nsteps(self) -> int:
        """Steps taken so far (the scene's step count)."""
        return self.calc.step

    # -------------------------------------------------------- observers
    def attach(self, function: Callable, interval: int = 1, *args,
               **kwargs) -> None:
        """Call ``function(*args, **kwargs)`` every ``interval`` steps.

        It is called when the step count is a multiple of ``interval``,
        including at the start of a run (step 0), once per step. An object
        with a ``write`` method (a Trajectory) has it called.
        """
        if (not isinstance(interval, int) or isinstance(interval, bool)
                or interval < 1):
            raise ValueError(f"interval must be a positive integer number of "
                             f"steps, got {interval!r}")
        if not callable(function):
            write = getattr(function, "write", None)
            if not callable(write):
                raise ValueError(f"observer must be callable, got "
                                 f"{function!r}")
            function = write
        self.observers.append(_Observer(function, interval, args, kwargs))

    def _call_observers(self) -> None:
        step = self.calc.step
        due = [o for o in self.observers
               if step % o.interval == 0 and o.last_step != step]
        if not due:
            return
        self.calc.sync()
        for observer in due:
            observer.last_step = step
            observer.function(*observer.args, **observer.kwargs)

    def _flush_observers(self) -> None:
        seen = set()
        for observer in self.observers:
            target = getattr(observer.function, "__self__", observer.function)
            flush = getattr(target, "flush", None)
            if callable(flush) and id(target) not in seen:
                seen.add(id(target))
                flush()

    def _next_event(self, step: int) -> float:
        if not self.observers:
            return math.inf
        return min(o.next_step(step) for o in self.observers)

    # -------------------------------------------------------------- run
    def run(self, steps: int | None = None, until: float | None = None) -> int:
        """Advance by ``steps`` steps or until time ``until`` [s].

        ``run(until=t)`` ends exactly at ``t`` (the library shortens the
        last step). Ctrl-C stops after a completed step: observers with a
        ``flush`` method (trajectories) are flushed and KeyboardInterrupt
        is raised. A non-finite value raises
        :class:`sphsolid.SimulationError` naming step, particle and
        quantity, after flushing too.

        Returns
        -------
        int
            Steps taken by this call.
        """
        if (steps is None) == (until is None):
            raise ValueError("give exactly one of steps= or until=")
        current = self.scene.integrator
        if current != self.integrator:
            raise RuntimeError(
                f"{type(self).__name__} drives the {self.integrator!r} "
                f"integrator, but the scene now runs {current!r} (selected "
                "by another Dynamics object on it, or by a checkpoint read): "
                f"make a {dynamics_for(current).__name__}(scene) to run it, "
                f"or a new {type(self).__name__}(scene) to switch back")
        calc = self.calc
        start = calc.step
        if steps is not None:
            if (not isinstance(steps, int) or isinstance(steps, bool)
                    or steps < 0):
                raise ValueError(f"steps must be a non-negative integer, got "
                                 f"{steps!r}")
            total = steps
        else:
            until = _time(until, "until")       # 3e-4 or "0.3ms"
            if not math.isfinite(until) or until < calc.time:
                raise ValueError(f"until must be a finite time not before the "
                                 f"current time {calc.time!r} s, got "
                                 f"{until!r}")
            whole, last = calc.steps_until(until)
            total = whole + (last > 0.0)
        bar = self._progress_bar(total)
        shown = [start]          # the step the bar shows

        def progress(step: int) -> bool:
            if bar is not None:
                bar.update(step - shown[0])
                shown[0] = step
            return self._interrupted

        self._interrupted = False
        previous = self._install_sigint()
        try:
            self._call_observers()
            if steps is not None:
                target = start + steps
                while calc.step < target and not self._interrupted:
                    stop = min(self._next_event(calc.step), target)
                    calc.advance(int(stop - calc.step), progress)
                    self._call_observers()
            else:
                while calc.time < until and not self._interrupted:
                    # whole steps up to the next observer, leaving the final
                    # (possibly shortened) step to the library's run_until
                    whole, last = calc.steps_until(until)
                    if whole == 0 and last == 0.0:
                        break
                    event = self._next_event(calc.step) - calc.step
                    chunk = min(event, whole)
                    if chunk >= 1:
                        calc.advance(int(chunk), progress)
                    else:
                        calc.advance_until(until, progress)
                    self._call_observers()
            if self._interrupted:
                raise StoppedError("interrupted")
        except StoppedError:
            if bar is not None:
                bar.close()
                bar = None
            self._flush_observers()
            if self._interrupted:
                raise KeyboardInterrupt(
                    f"run stopped by Ctrl-C at step {calc.step}, "
                    f"t = {calc.time:.6g} s; output flushed") from None
            raise
        except SimulationError:
            self._flush_observers()
            raise
        finally:
            if bar is not None:
                bar.update(calc.step - shown[0])
                bar.close()
            self._restore_sigint(previous)
        return calc.step - start

    def _progress_bar(self, total: int):
        show = self.progress
        if show is False or (show is None and total < self.progress_threshold):
            return None
        notebook = _in_notebook()
        if notebook:
            try:                      # a widget bar (needs ipywidgets)
                import ipywidgets  # noqa: F401
            except ImportError:
                pass
            else:
                from tqdm.notebook import tqdm
                return tqdm(total=total, unit="step")
        from tqdm.std import tqdm
        # on a terminal or in a notebook by default; not in logs and pipes
        # (in a kernel without widgets: a text bar of fixed width, as the
        # kernel's stderr has no terminal size)
        return tqdm(total=total, unit="step", dynamic_ncols=not notebook,
                    disable=None if show is None and not notebook else False)

    def _install_sigint(self):
        if threading.current_thread() is not threading.main_thread():
            return None

        def handler(signum, frame):
            if self._interrupted:  # a second Ctrl-C does not wait
                raise KeyboardInterrupt
            self._interrupted = True

        try:
            return signal.signal(signal.SIGINT, handler)
        except ValueError:
            return None

    @staticmethod
    def _restore_sigint(previous) -> None:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)


class ImprovedEuler(Dynamics):
    """Improved Euler (Heun), the library's "improved_euler", the paper's
    scheme and the default.

    Two rate evaluations per step: ``y* = y_n + dt f(y_n)``,
    ``y_{n+1} = y_n + dt/2 (f(y_n) + f(y*))``. Default step 0.5 h / c0
    (0.261 us for the paper's scene at dx = 1 mm); wave problems need
    artificial viscosity. Parameters as for :class:`Dynamics`.

    Examples
    --------
    >>> dyn = ImprovedEuler(scene)
    >>> dyn.attach(probes, interval=10)
    >>> dyn.attach(trajectory, interval=1000)
    >>> dyn.run(until=1e-3)
    """

    integrator = "improved_euler"


class Leapfrog(Dynamics):
    """Kick-drift-kick leapfrog (velocity Verlet), the library's
    "leapfrog": density and deviatoric stress are advanced with the
    velocity gradient of the half-step velocity that moves the positions,
    so the scheme is symplectic (no drift of the total energy of an
    undamped vibration) and stable without viscosity up to
    1.75 h / (c_p + |v|). One rate evaluation's pair work per step (the
    density and stress rates at the half step, the acceleration at the
    end), default step h / c0 (twice Improved Euler's). Parameters as for :class:`Dynamics`.

    Examples
    --------
    >>> Leapfrog(scene).run(until=1e-3)
    """

    integrator = "leapfrog"


def dynamics_for(name: str) -> type:
    """The Dynamics class of the library integrator ``name``."""
    classes = {cls.integrator: cls for cls in Dynamics.__subclasses__()}
    if name not in classes:
        raise ValueError(f"integrator {name!r}: no Dynamics class; known: "
                         f"{', '.join(classes)}")
    return classes[name]


def _in_notebook() -> bool:
    """True inside a Jupyter kernel (where stderr is not a terminal but a
    progress bar is wanted, as tqdm.auto decides)."""
    import sys
    shell = sys.modules.get("IPython")
    if shell is None or "ipykernel" not in sys.modules:
        return False
    try:
        ip = shell.get_ipython()
    except AttributeError:
        return False
    return ip is not None and "IPKernelApp" in getattr(ip, "config", {})
