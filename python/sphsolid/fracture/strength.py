"""The price of a confident strength: dx and the number of flaw draws
chosen together (``sphsolid plan ucs|brazilian --quantity strength``,
docs/ensembles.md).

A strength from an ensemble of N draws at spacing dx misses the converged
mean by a discretisation error E_d(dx) plus a statistical error, the
half-width of the interval of the mean, t_c s / sqrt(N) (s the members'
standard deviation).  :func:`plan_strength`

1. runs a pilot ensemble (``pilot`` members, sphsolid.ensemble) at each
   spacing of a coarse ladder, keeping the runs on disk (a second plan of
   the same test reuses them);
2. fits the discretisation error to the differences of the ensemble means
   between consecutive levels, as the wave planner fits its probe series
   (:func:`~sphsolid.planner.error_model.fit_error_model`: E_d(dx) =
   C dx^q with Eça & Hoekstra's safety factor), relative to the finest
   mean;
3. takes the relative scatter s / mean of the finest level and the CPU
   seconds per member against dx (a power law over the ladder);
4. over spacings from the coarsest level down to ``max_refinement`` times
   below the finest, picks the (dx, N) of least predicted CPU time with
   E_d(dx) + t_c s_rel / sqrt(N) <= error, N the fewest members that
   meet it.

A request no spacing within that reach meets is refused, and the refusal
says what it would take if the error model held further down (``beyond``:
the cheapest (dx, N) down to 16 times below the reach, its CPU seconds,
and a pilot ladder that would reach it), or that the model predicts no
spacing meets it.

Differences of means that are not larger than their own noise (t_c times
the standard error of the difference) do not resolve a discretisation
error: the plan says so (``ladder_resolved``), fits them with an order of
at most 1 (the wave planner's FORMAL_ORDER: a steep order fitted to noise
would promise a vanishing error), and the prediction then rests on
noise.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from statistics import NormalDist

import numpy as np

from ..planner.error_model import FORMAL_ORDER, fit_error_model

__all__ = ["plan_strength", "StrengthPlan", "student_quantile", "LADDERS"]

#: The coarse ladders of the two tests [m] (their default spacings are
#: 2 mm and 1 mm).
LADDERS = {"ucs": (8e-3, 6e-3, 4e-3), "brazilian": (4e-3, 3e-3, 2e-3)}
#: Fewest members a plan asks for: the bootstrap-t interval keeps its
#: coverage from about 10 members on (sphsolid.ensemble).
MIN_MEMBERS = 10


def student_quantile(p: float, dof: int) -> float:
    """Student's t quantile by the Cornish-Fisher expansion in 1/dof
    (Abramowitz & Stegun 26.7.5; 4 terms: within 0.3 % of the exact value
    for dof >= 5 at p = 0.975)."""
    if dof < 1:
        raise ValueError(f"dof={dof!r} must be >= 1")
    z = NormalDist().inv_cdf(p)
    g1 = (z ** 3 + z) / 4
    g2 = (5 * z ** 5 + 16 * z ** 3 + 3 * z) / 96
    g3 = (3 * z ** 7 + 19 * z ** 5 + 17 * z ** 3 - 15 * z) / 384
    g4 = (79 * z ** 9 + 776 * z ** 7 + 1482 * z ** 5 - 1920 * z ** 3
          - 945 * z) / 92160
    n = float(dof)
    return z + g1 / n + g2 / n ** 2 + g3 / n ** 3 + g4 / n ** 4


@dataclass
class StrengthPlan:
    """A plan for a confident strength (plan.json's contents)."""

    scene: str
    error: float
    confidence: float
    dx: float | None
    seeds: int | None
    predicted_seconds: float | None
    predicted_error: float | None
    discretisation_error: float | None
    statistical_error: float | None
    feasible: bool
    ladder: list = field(default_factory=list)
    model: dict = field(default_factory=dict)
    cost: dict = field(default_factory=dict)
    reason: str = ""
    ladder_resolved: bool = False
    ladder_seconds: float = 0.0
    #: for a refused request: what the error and cost models predict it
    #: would take below the finest spacing the ladder allows (dx, seeds,
    #: CPU s of the ensemble and of a pilot ladder reaching that dx), or
    #: empty when no spacing is predicted to meet it
    beyond: dict = field(default_factory=dict)
    #: the pilot ensembles' scene options (sphsolid.ensemble's), e.g. the
    #: drucker_prager effect's ``plasticity``; the planned ensemble's too
    scene_options: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        extra = ({"scene_options": self.scene_options}
                 if self.scene_options else {})
        return {"kind": "strength", "scene": self.scene,
                "quantity": "strength", "error": self.error,
                "confidence": self.confidence,
                "settings": {"dx": self.dx}, "seeds": self.seeds,
                "predicted_seconds": self.predicted_seconds,
                "predicted_error": self.predicted_error,
                "discretisation_error": self.discretisation_error,
                "statistical_error": self.statistical_error,
                "feasible": self.feasible, "reason": self.reason,
                "ladder_resolved": self.ladder_resolved,
                "ladder_seconds": self.ladder_seconds,
                "beyond": self.beyond,
                "ladder": self.ladder, "error_model": self.model,
                "cost_model": self.cost,
                "command": (f"sphsolid ensemble {self.scene} --dx "
                            f"{self.dx * 1e3:.4g}mm --seeds {self.seeds} "
                            + _options_text(self.scene_options)
                            + "--out DIR" if self.feasible else None),
                **extra}

    def save(self, path) -> None:
        Path(path).write_text(json.dumps(self.to_dict(), indent=2))

    def summary(self) -> str:
        lines = [f"strength of {self.scene} within "
                 f"{self.error:.3g} at confidence {self.confidence:g}:"]
        for level in self.ladder:
            lines.append(
                f"  ladder dx = {level['dx'] * 1e3:g} mm: mean "
                f"{level['mean'] / 1e6:.4g} MPa, std "
                f"{level['std'] / 1e6:.3g} MPa over {level['members']} "
                f"members, {level['cpu_s']:.3g} CPU s per member")
        if not self.feasible:
            lines.append(f"  no plan: {self.reason}")
            return "\n".join(lines)
        lines.append(
            f"  dx = {self.dx * 1e3:.4g} mm, {self.seeds} seeds: predicted "
            f"error {self.predicted_error:.3g} (discretisation "
            f"{self.discretisation_error:.3g} + statistical "
            f"{self.statistical_error:.3g}), {self.predicted_seconds:.4g} "
            "CPU s")
        if not self.ladder_resolved:
            lines.append("  (the ladder's differences of means are within "
                         "their noise: the discretisation error is not "
                         "resolved)")
        return "\n".join(lines)


def _options_text(options: dict) -> str:
    """The ``sphsolid ensemble`` options of the scene options ``options``
    (plasticity, artificial_stress), each followed by a space."""
    words = []
    if "plasticity" in options:
        dp = options["plasticity"]
        words.append(f"--cohesion {dp['cohesion'] / 1e6:.15g}MPa")
        if "friction_angle" in dp:
            words.append(f"--friction-angle {dp['friction_angle']:.15g}")
    if "artificial_stress" in options:
        words.append("--artificial-stress "
                     f"{options['artificial_stress']['epsilon']:.15g}")
    return "".join(word + " " for word in words)


def _work_dir(scene: str, root, scene_options: dict | None = None) -> Path:
    from ..planner.cache import _digest, _library_digest, cache_root
    from .._lib import version
    base = Path(root) if root is not None else cache_root()
    scope = f"strength|{scene}|{version()}|{_library_digest()}"
    if scene_options:
        # pilots with other effects are other ensembles (the plain ones
        # keep their folder)
        scope += "|" + json.dumps(scene_options, sort_keys=True)
    return base / "strength" / _digest(scope)


def plan_strength(scene: str, error: float, confidence: float = 0.95,
                  ladder=None, pilot: int = 10, seed: int = 1,
                  jobs: int = 1, max_refinement: float = 2.0,
                  max_seconds: float | None = None, work=None,
                  log=None, scene_options: dict | None = None
                  ) -> StrengthPlan:
    """Plans the strength of test ``scene`` (ucs, brazilian) within the
    relative ``error`` at ``confidence``: the spacing and the number of
    seeds of least predicted CPU time (module text).  ``work``: where the
    pilot ensembles are kept (default under the planner's cache);
    ``scene_options``: the pilot members' scene options (as
    sphsolid.ensemble's, e.g. ``plasticity``), which the plan and its
    command carry."""
    from .ensemble import ensemble
    if scene not in LADDERS:
        raise ValueError(f"scene {scene!r}: the strength is planned for "
                         f"{', '.join(LADDERS)}")
    if not (isinstance(error, float | int) and 0 < error < 1):
        raise ValueError(f"error={error!r} must be in (0, 1)")
    if not 0 < confidence < 1:
        raise ValueError(f"confidence={confidence!r} must be in (0, 1)")
    if isinstance(pilot, bool) or not isinstance(pilot, int) or pilot < 3:
        raise ValueError(f"pilot={pilot!r} must be an integer >= 3")
    ladder = sorted((float(d) for d in (ladder or LADDERS[scene])),
                    reverse=True)
    if len(ladder) < 3 or len(set(ladder)) != len(ladder):
        raise ValueError(f"ladder={ladder!r}: needs 3 or more distinct "
                         "spacings")
    scene_options = dict(scene_options or {})
    folder = _work_dir(scene, work, scene_options)
    levels = []
    for dx in ladder:
        if log:
            log(f"pilot ensemble: {scene}, dx = {dx * 1e3:g} mm, "
                f"{pilot} members")
        result = ensemble(scene, pilot, folder / f"dx_{dx * 1e3:g}mm",
                          dx=dx, jobs=jobs, seed=seed, figure=False,
                          scene_options=scene_options)
        s = result.summary
        cpu = float(np.mean(s["member_cpu_s"]))
        levels.append({"dx": dx, "members": s["members"], "mean": s["mean"],
                       "std": s["std"], "ci95_low": s["ci95_low"],
                       "ci95_high": s["ci95_high"], "cpu_s": cpu,
                       "ran": len(result.ran)})
    ladder_seconds = sum(level["cpu_s"] * level["members"]
                         for level in levels)
    means = np.array([level["mean"] for level in levels])
    stds = np.array([level["std"] for level in levels])
    counts = np.array([level["members"] for level in levels])
    finest = levels[-1]
    reference = abs(finest["mean"])
    diffs = np.abs(np.diff(means)) / reference
    tq = student_quantile(0.5 + confidence / 2, pilot - 1)
    noise = tq * np.sqrt(stds[:-1] ** 2 / counts[:-1]
                         + stds[1:] ** 2 / counts[1:]) / reference
    resolved = bool(np.all(diffs > noise))
    # a difference of exactly zero carries no order; a ladder within its
    # noise carries none either: its order is taken at most FORMAL_ORDER,
    # as the wave planner predicts
    model = fit_error_model(ladder, np.maximum(diffs, 1e-12),
                            max_refinement=max_refinement,
                            spread=float(np.ptp(means)) / reference,
                            max_order=None if resolved else FORMAL_ORDER)
    s_rel = finest["std"] / reference
    # CPU seconds per member: a power law in dx over the ladder
    slope, intercept = np.polyfit(np.log(ladder),
                                  np.log([lv["cpu_s"] for lv in levels]), 1)

    def cost(dx: float) -> float:
        return float(math.exp(intercept + slope * math.log(dx)))

    z = NormalDist().inv_cdf(0.5 + confidence / 2)

    def statistical(n: int) -> float:
        return student_quantile(0.5 + confidence / 2, n - 1) * s_rel \
            / math.sqrt(n)

    def seeds_for(room: float) -> int | None:
        """The fewest members whose statistical error is within room:
        from the normal quantile's count (t exceeds z, so never too
        many) up one at a time (None beyond 100,000)."""
        n = max(MIN_MEMBERS, math.ceil((z * s_rel / room) ** 2))
        if n > 100000:
            return None
        while statistical(n) > room:
            n += 1
        return n

    def cheapest(spacings, limit):
        best = None
        for dx in spacings:
            e_d = model.upper(float(dx))
            room = error - e_d
            if room <= 0:
                continue
            n = seeds_for(room)
            if n is None:
                continue
            e_s = statistical(n)
            seconds = n * cost(float(dx))
            if limit is not None and seconds > limit:
                continue
            if best is None or seconds < best[0]:
                best = (seconds, float(dx), n, e_d, e_s)
        return best

    smallest = ladder[-1] / max_refinement
    best = cheapest(np.geomspace(ladder[0], smallest, 60), max_seconds)
    common = dict(scene=scene, error=float(error), confidence=confidence,
                  ladder=levels, model=model.to_dict(),
                  cost={"cpu_s_per_member": "exp(a) dx^b", "a": intercept,
                        "b": slope},
                  ladder_resolved=resolved, ladder_seconds=ladder_seconds,
                  scene_options=scene_options)
    if best is None:
        floor = model.upper(smallest)
        beyond = _beyond(cheapest, seeds_for, error, smallest, ladder,
                         pilot, cost, max_refinement)
        return StrengthPlan(
            beyond=beyond, dx=None, seeds=None, predicted_seconds=None,
            predicted_error=None, discretisation_error=None,
            statistical_error=None, feasible=False,
            reason=(f"the discretisation error alone is {floor:.3g} at dx "
                    f"= {smallest * 1e3:.3g} mm (the finest the ladder "
                    "allows)" + ("" if max_seconds is None else
                                 f", or the time exceeds max_seconds="
                                 f"{max_seconds:g}")
                    + ("" if resolved else "; the ladder's differences are "
                       "within their noise: more --pilot members or "
                       "another --ladder may resolve them")
                    + _beyond_text(beyond, pilot)),
            **common)
    seconds, dx, n, e_d, e_s = best
    return StrengthPlan(dx=dx, seeds=n, predicted_seconds=seconds,
                        predicted_error=e_d + e_s, discretisation_error=e_d,
                        statistical_error=e_s, feasible=True, **common)


#: How far below the ladder's reach a refusal looks for the spacing that
#: the error model predicts would meet the request (a factor on dx).
BEYOND_REFINEMENT = 16.0


def _beyond(cheapest, seeds_for, error, smallest, ladder, pilot, cost,
            max_refinement) -> dict:
    """What a refused request would take if the ladder's error model held
    below the finest spacing it allows: the cheapest (dx, seeds) down to
    ``smallest / BEYOND_REFINEMENT`` and its CPU seconds, and those of a
    pilot ladder that reaches it (three levels at the ladder's last ratio,
    the finest ``dx * max_refinement``, ``pilot`` members each).  Empty
    when no spacing is predicted to meet the request (an error model that
    does not shrink with dx).  Either way ``statistics_alone``: the seeds
    and CPU seconds that the statistical error alone needs at the finest
    spacing the ladder allows (a lower bound on any plan's cost there)."""
    alone = {"dx": smallest, "seeds": seeds_for(error),
             "cpu_s_per_member": cost(smallest)}
    alone["predicted_seconds"] = alone["seeds"] * alone["cpu_s_per_member"]
    best = cheapest(np.geomspace(smallest, smallest / BEYOND_REFINEMENT, 60),
                    None)
    if best is None:
        return {"statistics_alone": alone}
    seconds, dx, n, e_d, e_s = best
    ratio = ladder[-2] / ladder[-1]
    finest = dx * max_refinement
    pilots = [finest * ratio ** 2, finest * ratio, finest]
    return {"dx": dx, "seeds": n, "discretisation_error": e_d,
            "statistical_error": e_s, "predicted_seconds": seconds,
            "cpu_s_per_member": cost(dx), "pilot_ladder": pilots,
            "pilot_seconds": float(sum(pilot * cost(d) for d in pilots)),
            "statistics_alone": alone}


def _beyond_text(beyond: dict, pilot: int) -> str:
    alone = beyond["statistics_alone"]
    text = (f"; the statistical error alone needs {alone['seeds']} seeds at "
            f"dx = {alone['dx'] * 1e3:.3g} mm "
            f"({alone['cpu_s_per_member']:.3g} CPU s per member, "
            f"{alone['predicted_seconds']:.3g} CPU s)")
    if "dx" not in beyond:
        return text + ("; no finer spacing is predicted to meet the request "
                       "(the error model does not shrink with dx)")
    return text + (f"; if the error model held below the ladder, dx = "
            f"{beyond['dx'] * 1e3:.3g} mm with {beyond['seeds']} seeds would "
            f"meet it (discretisation {beyond['discretisation_error']:.3g} "
            f"+ statistical {beyond['statistical_error']:.3g}) for about "
            f"{beyond['predicted_seconds']:.3g} CPU s "
            f"({beyond['cpu_s_per_member']:.3g} per member), after a pilot "
            f"ladder --ladder "
            + ",".join(f"{d * 1e3:.3g}mm" for d in beyond["pilot_ladder"])
            + f" of {pilot} members each ({beyond['pilot_seconds']:.3g} CPU "
            "s) to check it")
