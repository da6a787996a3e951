"""The cost model of a setting: CPU and wall seconds per step against
particles, fitted on its calibration runs."""
from __future__ import annotations

import math
import time as wallclock
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .calibration import LadderRun, build_scene


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
    dyn = setting.dynamics(scene, progress=False)
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
    itself (the library's default step of the integrator times the
    setting's step)."""
    scene = build_scene(scene_factory, dx, setting, 1)
    dyn = setting.dynamics(scene, progress=False)
    return len(scene), int(math.ceil(until / dyn.dt - 1e-9))
