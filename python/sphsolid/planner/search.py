# Over 600 lines: plan() and its named steps, the Plan record and the plan-file checks.
"""The search: candidates, their calibration ladders, refinement and the
cheapest setting predicted to meet the request."""
from __future__ import annotations

import itertools
import json
import math
import time as wallclock
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable, Mapping, Sequence

import numpy as np

from .. import _lib, metrics
from .._lib import UnsupportedError
from .calibration import LadderRun, build_scene, factory_options, ladder_run, make_dynamics
from .cost_model import CostModel, TIMING_SECONDS, _steps_to, reference_cost, time_steps
from .detection import Finding, detect_effects
from .error_model import ErrorModel, FORMAL_ORDER, consistency_floors, fit_error_model, repeating_factor
from .record import Record, refusal
from .record import shipped as shipped_record
from .settings import OWN_SETTING, SAFETY_GOOD, SMOOTHING_RATIOS, STANDARD, Setting, _effect_available, integrator_names, kernel_names


# ------------------------------------------------------------------- plan
@dataclass
class Candidate:
    """A setting with its models and the spacing and cost it needs."""
    setting: Setting
    runs: list
    model: ErrorModel | None = None
    cost: CostModel | None = None
    limit: dict | None = None
    dx: float | None = None
    particles: int | None = None
    steps: int | None = None
    seconds: float | None = None
    cpu_seconds: float | None = None
    note: str = ""

    def to_dict(self) -> dict:
        return {"setting": self.setting.to_dict(),
                "label": self.setting.label(),
                "error_model": self.model.to_dict() if self.model else None,
                "cost_model": self.cost.to_dict() if self.cost else None,
                "dx": self.dx, "particles": self.particles,
                "steps": self.steps, "predicted_seconds": self.seconds,
                "predicted_cpu_seconds": self.cpu_seconds,
                "predicted_error": (self.model.predict(self.dx)
                                    if self.model and self.dx else None),
                "error_upper": (self.model.upper(self.dx)
                                if self.model and self.dx else None),
                "note": self.note,
                "runs": [r.summary() for r in self.runs]}


#: The plan file's format (its "format" key); files of this format are
#: read, others are refused with their format named.
PLAN_FORMAT = "sphsolid-plan 1"
#: A setting whose ladder determines no order is refined only while the
#: verification record prices the error it would reach at no more than
#: this many times the cost of the most promising setting in play (the
#: plan is meant to cost at most twice the cheapest sufficient setting).
RECORD_PRUNE = 2.0


def read_json(path: Path, what: str):
    """The JSON contents of ``path``; a ValueError names the file and says
    what is wrong (a directory, not UTF-8, unreadable, not JSON)."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{path}: is a directory, not a {what}")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a {what} (not UTF-8 text)") from None
    except OSError as error:
        raise ValueError(f"{path}: cannot read the {what} "
                         f"({error.strerror})") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as error:
        raise ValueError(f"{path}: not a JSON {what} ({error.msg} at line "
                         f"{error.lineno}, column {error.colno})") from None


def _number(value, where: str, positive: bool = False,
            optional: bool = True, integer: bool = False):
    if value is None and optional:
        return
    kind = int if integer else (int, float)
    if (isinstance(value, bool) or not isinstance(value, kind)
            or not math.isfinite(value) or (positive and not value > 0)):
        what = ("an integer" if integer else "a number") + (
            " > 0" if positive else "")
        raise ValueError(f"{where} must be {what}, got {value!r}")


def validate_plan_data(data, source: str = "plan") -> None:
    """Check a plan file's contents (what :meth:`Plan.load` reads); a
    ValueError names ``source`` and the key."""
    if not isinstance(data, dict):
        raise ValueError(f"{source}: a plan file holds a JSON object, got "
                         f"a {type(data).__name__}")
    if data.get("format") != PLAN_FORMAT:
        raise ValueError(f"{source}: 'format' is {data.get('format')!r}; "
                         f"this version reads {PLAN_FORMAT!r} plan files")
    if not isinstance(data.get("feasible"), bool):
        raise ValueError(f"{source}: 'feasible' must be true or false, got "
                         f"{data.get('feasible')!r}")
    for key in ("request", "error_model"):
        if data.get(key) is not None and not isinstance(data[key], dict):
            raise ValueError(f"{source}: {key!r} must be an object, got "
                             f"{data[key]!r}")
    request = data.get("request") or {}
    _number(request.get("until"), f"{source}: 'request.until'", True)
    _number(request.get("error"), f"{source}: 'request.error'", True)
    for key in ("predicted_error", "error_upper", "predicted_seconds",
                "predicted_cpu_seconds", "best_reachable_error"):
        _number(data.get(key), f"{source}: {key!r}")
    for key in ("particles", "steps"):
        _number(data.get(key), f"{source}: {key!r}", integer=True)
    for key in ("reason", "scene"):
        if data.get(key) is not None and not isinstance(data[key], str):
            raise ValueError(f"{source}: {key!r} must be a string, got "
                             f"{data[key]!r}")
    effects = data.get("effects")
    if effects is not None:
        if not isinstance(effects, list):
            raise ValueError(f"{source}: 'effects' must be a list of "
                             f"findings, got {effects!r}")
        names = set(Finding.__dataclass_fields__)
        for i, finding in enumerate(effects):
            if not isinstance(finding, dict) or not set(finding) <= names \
                    or not {"effect", "parameters", "reason",
                            "measured"} <= set(finding):
                raise ValueError(f"{source}: 'effects[{i}]' must be an "
                                 f"object with the keys {sorted(names)}, got "
                                 f"{finding!r}")
    settings = data.get("settings")
    if data["feasible"] and settings is None:
        raise ValueError(f"{source}: a feasible plan needs 'settings'")
    if settings is None:
        return
    if not isinstance(settings, dict):
        raise ValueError(f"{source}: 'settings' must be an object, got "
                         f"{settings!r}")
    where = f"{source}: 'settings."
    if "dx" not in settings:
        raise ValueError(f"{where}dx' is missing (the planned spacing [m])")
    _number(settings["dx"], f"{where}dx'", True, optional=False)
    if "smoothing_ratio" in settings:
        _number(settings["smoothing_ratio"], f"{where}smoothing_ratio'",
                True, optional=False)
    if "step" in settings:
        _number(settings["step"], f"{where}step'", True, optional=False)
    _number(settings.get("threads"), f"{where}threads'", True, integer=True)
    for key in ("kernel", "integrator"):
        if key in settings and not isinstance(settings[key], str):
            raise ValueError(f"{where}{key}' must be a name, got "
                             f"{settings[key]!r}")
    inset = settings.get("inset", 0.0)
    if not (inset == "static" or (isinstance(inset, (int, float))
                                  and not isinstance(inset, bool))):
        raise ValueError(f"{where}inset' must be a number of lattice steps "
                         f"or \"static\", got {inset!r}")
    effects = settings.get("effects") or {}
    if not isinstance(effects, dict):
        raise ValueError(f"{where}effects' must be an object (effect -> "
                         f"parameters), got {effects!r}")
    for name, params in effects.items():
        if not isinstance(params, dict):
            raise ValueError(f"{where}effects.{name}' must be an object of "
                             f"parameters, got {params!r}")
        for key, value in params.items():
            _number(value, f"{where}effects.{name}.{key}'", optional=False)


@dataclass
class Plan:
    """The planner's answer. ``feasible`` False means refused: ``reason``
    says why and ``best_reachable_error`` what can be had."""
    request: dict
    feasible: bool
    setting: Setting | None = None
    dx: float | None = None
    threads: int | None = None
    predicted_error: float | None = None
    error_upper: float | None = None
    predicted_seconds: float | None = None
    predicted_cpu_seconds: float | None = None
    particles: int | None = None
    steps: int | None = None
    reason: str = ""
    best_reachable_error: float | None = None
    findings: list = field(default_factory=list)
    candidates: list = field(default_factory=list)
    calibration_seconds: float = 0.0
    scene: str = ""
    effects_examined: bool = True
    #: the error model of the chosen setting (``ErrorModel.to_dict()``):
    #: the calibration a run's error estimate uses
    #: (:class:`sphsolid.planner.estimate.ErrorEstimate`)
    calibration: dict | None = None

    # ------------------------------------------------------------ output
    def to_dict(self) -> dict:
        settings = None
        if self.setting is not None:
            settings = {"dx": self.dx, **self.setting.to_dict(),
                        "threads": self.threads}
        return {"format": PLAN_FORMAT, "scene": self.scene,
                "request": self.request, "feasible": self.feasible,
                "settings": settings,
                "predicted_error": self.predicted_error,
                "error_uncertainty": (None if self.error_upper is None else
                                      self.error_upper - self.predicted_error),
                "error_upper": self.error_upper,
                "predicted_seconds": self.predicted_seconds,
                "predicted_cpu_seconds": self.predicted_cpu_seconds,
                "error_model": self.calibration,
                "particles": self.particles, "steps": self.steps,
                "reason": self.reason,
                "best_reachable_error": self.best_reachable_error,
                "effects": [f.to_dict() for f in self.findings],
                "calibration_seconds": self.calibration_seconds,
                "library": _lib.version(),
                "evidence": [c.to_dict() for c in self.candidates]}

    def save(self, path) -> Path:
        path = Path(path)
        path.write_text(json.dumps(self.to_dict(), indent=1, default=float))
        return path

    @classmethod
    def load(cls, path) -> "Plan":
        """Read a plan.json (the settings and predictions; the evidence
        stays in the file). A plan file is input: every key this reads is
        checked (:func:`validate_plan_data`), and an error names the file
        and the key."""
        path = Path(path)
        data = read_json(path, "plan file")
        validate_plan_data(data, str(path))
        settings = data.get("settings")
        plan = cls(request=data.get("request") or {},
                   feasible=data["feasible"],
                   reason=data.get("reason") or "",
                   best_reachable_error=data.get("best_reachable_error"),
                   predicted_error=data.get("predicted_error"),
                   error_upper=data.get("error_upper"),
                   predicted_seconds=data.get("predicted_seconds"),
                   predicted_cpu_seconds=data.get("predicted_cpu_seconds"),
                   particles=data.get("particles"), steps=data.get("steps"),
                   scene=data.get("scene") or "",
                   calibration=data.get("error_model"))
        plan.findings = [Finding(**f) for f in data.get("effects") or []]
        if settings:
            plan.setting = Setting.from_dict(settings)
            plan.dx = float(settings["dx"])
            plan.threads = settings.get("threads")
        return plan

    def adopt(self, best: Candidate) -> None:
        """Take ``best``'s setting, spacing and predictions as the plan's."""
        self.setting, self.dx = best.setting, best.dx
        self.predicted_error = best.model.predict(best.dx)
        self.error_upper = best.model.upper(best.dx)
        self.predicted_seconds = best.seconds
        self.predicted_cpu_seconds = best.cpu_seconds
        self.particles, self.steps = best.particles, best.steps
        self.calibration = best.model.to_dict()

    def build(self, scene_factory, threads: int | None = None,
              calculator: bool = True):
        """The planned scene (``threads`` overrides the plan's; with
        ``calculator`` False the caller attaches one)."""
        if not self.feasible or self.setting is None:
            raise ValueError(f"the plan was refused: {self.reason}")
        return build_scene(scene_factory, self.dx, self.setting,
                           self.threads if threads is None else threads,
                           calculator)

    def dynamics(self, scene, **kwargs):
        """The Dynamics of the planned run: the plan's integrator at its
        step (``kwargs`` go to it; an explicit ``dt`` wins)."""
        if not self.feasible or self.setting is None:
            raise ValueError(f"the plan was refused: {self.reason}")
        return self.setting.dynamics(scene, **kwargs)

    def summary(self) -> str:
        """A table for people."""
        r = self.request
        norm = r.get("norm", "max")
        lines = [f"request: {norm} deviation of {r.get('quantity')} at "
                 f"{', '.join(r.get('probes', []))} <= "
                 f"{r.get('error', 0) * 100:g} % over 0-"
                 f"{r.get('until', 0) * 1e3:g} ms"
                 + (f" within {r['max_seconds']:g} s"
                    if r.get("max_seconds") else "")
                 + f", threads {r.get('threads') or 'default'}"]
        lines.append("effects the scene calls for:")
        if not self.effects_examined:
            lines.append("  not examined (the deck's own effects are kept)")
        elif not any(f.effect for f in self.findings):
            lines.append("  none")
        for f in self.findings:
            cost = ("" if f.cost is None else f"; cost {f.cost * 100:+.0f} % "
                    "per step")
            lines.append(f"  {f.effect or '-'}: {f.reason} ({f.measured}"
                         f"{cost})")
        lines.append("")
        header = (f"{'setting':<58} {'order':>5} {'Fs':>4} {'rep.':>4} "
                  f"{'ver.':>4} {'floor':>6} "
                  f"{'dx [mm]':>8} {'error':>7} {'upper':>7} {'CPU [s]':>9} "
                  f"{'wall [s]':>9}")
        lines.append(header)
        lines.append("-" * len(header))
        for c in self.candidates:
            m = c.model
            if m is None:
                lines.append(f"{c.setting.label():<58} {c.note}")
                continue
            dx = f"{c.dx * 1e3:8.3g}" if c.dx else f"{'-':>8}"
            err = (f"{m.predict(c.dx) * 100:6.2f}%" if c.dx else f"{'-':>7}")
            up = (f"{m.upper(c.dx) * 100:6.2f}%" if c.dx else f"{'-':>7}")
            sec = f"{c.seconds:9.3g}" if c.seconds else f"{'-':>9}"
            cpu = (f"{c.cpu_seconds:9.3g}" if c.cpu_seconds
                   else f"{'-':>9}")
            mark = " <" if (self.setting == c.setting
                            and self.feasible) else ""
            lines.append(f"{c.setting.label():<58} {m.order:5.2f} "
                         f"{m.safety:4.2f} {m.repeating:4.2f} "
                         f"{m.verified:4.2f} "
                         f"{max(m.floor, m.bias) * 100:5.2f}% {dx} {err} "
                         f"{up} {cpu} {sec}{mark}"
                         + (f"  {c.note}" if c.note else ""))
        lines.append("")
        if self.feasible:
            lines.append(
                f"plan: {self.setting.label()}, dx = {self.dx * 1e3:.4g} mm "
                f"({self.particles} particles, {self.steps} steps): predicted "
                f"error {self.predicted_error * 100:.2f} % (at most "
                f"{self.error_upper * 100:.2f} %), predicted wall time "
                f"{self.predicted_seconds:.3g} s"
                + (f" (CPU {self.predicted_cpu_seconds:.3g} s; wall at the "
                   "load of the calibration)"
                   if self.predicted_cpu_seconds else ""))
        else:
            lines.append(f"refused: {self.reason}")
        lines.append(f"planning took {self.calibration_seconds:.1f} s"
                     + (f"; the planned run is predicted to take "
                        f"{self.predicted_seconds:.3g} s"
                        if self.feasible and self.predicted_seconds
                        else ""))
        return "\n".join(lines)


def _check_request(error, until, norm, max_seconds, ladder):
    if not (isinstance(error, (int, float)) and 0 < error < 1):
        raise ValueError(f"error must be a fraction in (0, 1) (0.03 for 3 %),"
                         f" got {error!r}")
    if not (isinstance(until, (int, float)) and until > 0
            and math.isfinite(until)):
        raise ValueError(f"until must be a time > 0 s, got {until!r}")
    if norm not in ("max", "rms"):
        raise ValueError(f"norm must be 'max' or 'rms', got {norm!r}")
    if max_seconds is not None and not max_seconds > 0:
        raise ValueError(f"max_seconds must be > 0, got {max_seconds!r}")
    if ladder is None or len(ladder) < 3:
        raise ValueError(f"ladder must list 3 or more coarse spacings [m], "
                         f"got {ladder!r}")
    if any(not (d > 0) for d in ladder):
        raise ValueError(f"ladder spacings must be > 0, got {ladder!r}")


def detection_families(scene_factory, kernels: Sequence[str] | None = None,
                       own_settings: bool = True) -> list[tuple]:
    """(kernel, h/dx, inset) of the effect detection runs: the default
    kernel at h/dx 1.2 for the kernels tried at :data:`SMOOTHING_RATIOS`,
    and each kernel of :data:`OWN_SETTING` the library and the factory
    offer (and ``kernels`` names, when given) at its own setting (the
    static inset only when the factory takes ``inset``)."""
    accepted = factory_options(scene_factory)
    families = [STANDARD]
    if not (own_settings and accepted["kernel"]):
        return families
    offered = kernel_names()
    for kernel, (ratio, inset) in OWN_SETTING.items():
        if kernel in offered and (kernels is None or kernel in kernels):
            families.append((kernel, ratio if accepted["smoothing_ratio"]
                             else 1.2, inset if accepted["inset"] else 0.0))
    return families


def default_candidates(scene_factory, findings_by: dict,
                       extra_kernel_correction: bool = True,
                       kernels: Sequence[str] | None = None,
                       ratios: Sequence[float] | None = None,
                       own_settings: bool = True) -> list:
    """Every kernel x h/dx x integrator the library and the factory offer
    (or those of ``kernels`` and ``ratios`` among them), each with the
    effects found for its integrator (and, as an accuracy option, with
    kernel correction added); the kernels of :data:`OWN_SETTING` at their
    own h/dx and end placement, with the effects found for them.
    ``findings_by`` maps (integrator, family) to the findings of that
    detection run (:func:`detection_families`; a bare integrator key is
    the standard family)."""
    accepted = factory_options(scene_factory)
    offered = kernel_names() if accepted["kernel"] else ["cubic_spline"]
    default = [k for k in offered if k not in OWN_SETTING]
    standard = [k for k in (kernels or default)
                if k in offered and k not in OWN_SETTING]
    ratios = ((ratios or SMOOTHING_RATIOS) if accepted["smoothing_ratio"]
              else (1.2,))
    out = []
    for key, findings in findings_by.items():
        integrator, family = key if isinstance(key, tuple) else (key,
                                                                 STANDARD)
        effects = {f.effect: f.parameters for f in findings if f.effect}
        variants = [effects]
        if (extra_kernel_correction and "kernel_correction" not in effects
                and _effect_available("kernel_correction")):
            variants.append({**effects, "kernel_correction": {}})
        if family == STANDARD:
            for kernel, ratio, eff in itertools.product(standard, ratios,
                                                        variants):
                out.append(Setting.make(ratio, kernel, integrator, eff))
        elif own_settings:
            # these kernels run without dissipation on wave problems
            # (their rough raw series is their own high-frequency content,
            # not a growth): effects found from a sign rather than a
            # failure are tried both ways, the calibration decides (a
            # variant that fails there drops out)
            kernel, ratio, inset = family
            needed = {f.effect: f.parameters for f in findings
                      if f.effect and f.required}
            for eff in ([effects, needed] if needed != effects
                        else [effects]):
                out.append(Setting.make(ratio, kernel, integrator, eff,
                                        inset))
    return out


def candidate_settings(scene_factory, until: float, probes, quantity: str,
                       threads, ladder: Sequence[float], *,
                       options: dict | None = None, detect: bool = True,
                       max_refinement: float = 2.0, cache=None,
                       log: Callable[[str], None] | None = None
                       ) -> tuple[list, list]:
    """The settings :func:`plan` calibrates by default, and the findings
    of the effect detection behind them: per integrator and detection
    family (:func:`detection_families`) one run at the coarsest spacing
    of ``ladder`` with no optional effect (:func:`detect_effects`), then
    :func:`default_candidates`. ``options`` narrows them as in
    :func:`plan`. The verification record (:mod:`.record`) is generated
    from exactly these settings, so it covers what the CLI plans with."""
    say = log or (lambda message: None)
    ladder = sorted((float(d) for d in ladder), reverse=True)
    findings_by = {}
    integrators = [i for i in integrator_names()
                   if i in ((options or {}).get("integrators")
                            or integrator_names())]
    families = detection_families(
        scene_factory, (options or {}).get("kernels"),
        (options or {}).get("own_settings", True))
    for integrator, family in itertools.product(integrators, families):
        if not detect:
            findings_by[(integrator, family)] = []
            continue
        kernel, ratio, inset = family
        say(f"effects: detection run at dx = {ladder[0] * 1e3:g} mm with "
            f"{Setting.make(ratio, kernel, integrator, None, inset).label()}"
            " ...")
        # as many steps as a run at the smallest spacing the plan may
        # choose (growth per step does not depend on dx)
        steps = int(math.ceil(until / _default_dt(scene_factory,
                                                  ladder[0], integrator)
                              * ladder[0] / ladder[-1] * max_refinement))
        key = ("detect", integrator, family, ladder[0], float(until),
               steps)
        try:
            if cache is not None and key in cache:
                findings_by[(integrator, family)] = cache[key]
            else:
                # an effect's cost is timed once per plan: the summary
                # shows each finding once
                priced = {(f.effect, f.reason)
                          for items in findings_by.values() for f in items
                          if f.cost is not None}
                findings_by[(integrator, family)] = detect_effects(
                    scene_factory, ladder[0], until, probes, quantity,
                    integrator, threads, steps=min(steps, 200000),
                    log=say, kernel=kernel, smoothing_ratio=ratio,
                    inset=inset, priced=priced)
                if cache is not None:
                    cache[key] = findings_by[(integrator, family)]
        except UnsupportedError as unsupported:
            say(f"  {integrator} with {kernel} left out: {unsupported}")
    settings = default_candidates(
        scene_factory, findings_by,
        **{k: v for k, v in (options or {}).items() if k != "integrators"})
    findings = []
    for items in findings_by.values():
        for f in items:
            same = [k for k, g in enumerate(findings)
                    if f.effect == g.effect and f.reason == g.reason]
            if not same:
                findings.append(f)
            elif findings[same[0]].cost is None and f.cost is not None:
                findings[same[0]] = f      # the one whose cost was timed
    return settings, findings


def cached_levels(cache, setting: Setting, until: float, quantity: str,
                  threads) -> list:
    """The successful calibration runs of ``setting`` in ``cache`` (to
    ``until``, of ``quantity``, on ``threads``), coarsest first."""
    if cache is None:
        return []
    if hasattr(cache, "runs_of"):
        runs = cache.runs_of(setting, until, quantity, threads)
    else:
        runs = [v for k, v in cache.items()
                if isinstance(k, tuple) and len(k) == 5 and k[1] == setting
                and k[2] == float(until) and k[3] == quantity
                and k[4] == threads and isinstance(v, LadderRun)]
    runs = [r for r in runs if not r.failed]
    unique = {float(f"{r.dx:.6g}"): r for r in runs}
    return [unique[dx] for dx in sorted(unique, reverse=True)]


class Progress:
    """A progress bar with the time left for the calibration runs: each
    run's work scales as dx^-p (p fitted on the particle-steps of the runs
    so far; 3 in 2D), the time per unit of work is measured on the runs
    that were not kept from an earlier plan."""

    WIDTH = 20

    def __init__(self, coarsest: float):
        self.coarsest = coarsest
        self.pending: list[float] = []
        self.sizes: list[tuple[float, int]] = []
        self.seconds = self.work = 0.0

    def plan(self, spacings) -> None:
        self.pending = list(spacings)

    def exponent(self) -> float:
        """Work (particle-steps) as dx^-p: p fitted on the runs so far."""
        if len({dx for dx, _ in self.sizes}) < 2:
            return 3.0
        x = np.log([dx for dx, _ in self.sizes])
        y = np.log([max(ps, 1) for _, ps in self.sizes])
        return float(np.clip(-np.polyfit(x, y, 1)[0], 1.0, 5.0))

    def _units(self, dx: float) -> float:
        return (self.coarsest / dx) ** self.exponent()

    def done(self, run, cached: bool) -> None:
        if self.pending:
            self.pending.pop(0)
        if run.failed:
            return
        self.sizes.append((run.dx, run.particle_steps))
        if not cached and math.isfinite(run.wall):
            self.seconds += run.wall
            self.work += self._units(run.dx)

    def skip(self, count: int) -> None:
        del self.pending[:max(0, count)]

    def bar(self, done: int, total: int) -> str:
        filled = int(round(self.WIDTH * (done - 1) / max(total, 1)))
        left = ""
        if self.work > 0:
            seconds = (self.seconds / self.work
                       * sum(self._units(dx) for dx in self.pending))
            left = f", {seconds:.0f} s left"
        return (f"[{'#' * filled}{'.' * (self.WIDTH - filled)}] "
                f"{done}/{total}{left}")


def plan(scene_factory: Callable, error: float = 0.03,
         until: float | None = None, probes=None,
         quantity: str = "von_mises", norm: str = "max",
         threads: int | None = None, max_seconds: float | None = None, *,
         ladder: Sequence[float] | None = None,
         window: tuple | None = None,
         candidates: Sequence | None = None, detect: bool = True,
         max_refinement: float = 2.0, max_order: float | None = FORMAL_ORDER,
         timing_checks: int = 3,
         refinements: int = 3, refine_best: int = 2,
         calibration_seconds: float | None = None,
         cache: dict | None = None, options: dict | None = None,
         scene: str = "", log: Callable[[str], None] | None = None,
         record: Record | bool | None = True) -> Plan:
    """The cheapest settings predicted to meet an error request.

    Parameters
    ----------
    scene_factory : callable
        ``scene_factory(dx, smoothing_ratio=..., kernel=...)`` returns the
        user's :class:`~sphsolid.Scene` at spacing ``dx`` [m] (the two
        keywords are optional: a factory without them is planned at its
        own h/dx and kernel). Effects the planner manages
        (``MANAGED_EFFECTS``) are replaced by the plan's.
    error : float
        Requested error as a fraction (0.03 = 3 %) of the reference's peak
        (``norm="max"``) or RMS (``"rms"``), worst probe.
    until : float
        End of the run [s].
    probes : mapping name -> point [m], or callable(scene) -> {name: value}
        Where the error is measured.
    quantity : str
        Probe column (``von_mises``, ``pressure``, ``sigma_yy``, ...).
    norm : {"max", "rms"}
    threads : int, optional
        Threads of the planned run (the calibration uses them too, so the
        cost model is this machine's at this thread count).
    max_seconds : float, optional
        Wall-time budget of the planned run.
    ladder : sequence of float
        Calibration spacings [m], coarse, 3 or more.
    window : (t0, t1), optional
        Part of [0, until] over which the error counts (default all).
    candidates : sequence of Setting or dict, optional
        Settings to choose from (default: every kernel x h/dx x integrator
        the library offers, with the effects the scene calls for).
    detect : bool
        Run the effect detection (else the candidates' effects are used
        as given).
    max_refinement : float
        How far below the finest calibrated spacing predictions may go
        (default 2: on the piston scene the self-convergence order of
        three coarse levels, 0.85, over-predicts the order the error
        keeps below them, about 0.5; a finer level shows it).
    max_order : float or None
        Largest order of convergence a prediction uses (default
        :data:`FORMAL_ORDER`, 1); a faster observed order is fitted again
        at it. None trusts any observed order.
    timing_checks : int
        How many of the cheapest candidates get a timing of a few steps at
        their planned spacing.
    refinements, refine_best : int
        Up to ``refinements`` rounds in which the ``refine_best`` cheapest
        settings that need a spacing below half their finest calibrated
        one, or below it with the large safety factor, get a finer level
        (finest / 1.5) and are fitted again. A setting never gets more
        than ``refinements`` levels below ``ladder``, counting those of
        earlier plans in ``cache``: the cache saves a plan time, it does
        not let later plans refine deeper.
    calibration_seconds : float, optional
        Budget of the calibration runs (default: no limit); a refinement
        that would exceed it is not run.
    options : dict, optional
        Narrows the default candidates: ``kernels``, ``ratios`` (h/dx),
        ``integrators``, ``extra_kernel_correction``
        (see :func:`default_candidates`).
    record : Record, True or None
        The verification record (:mod:`.record`; True: the one shipped
        with the package). Each setting's upper prediction is multiplied
        by its factor and never planned at or below its bias; of the
        default candidates, those the record does not verify in the norm
        asked for, or whose bias is at or above the request, are not
        calibrated. None plans with self-convergence alone.
    cache : dict, optional
        Calibration runs by (dx, setting, until, quantity, threads), reused
        and filled (several requests on one scene share their ladders; the
        same factory and probes are assumed).
    log : callable(str), optional
        Progress messages.

    Returns
    -------
    Plan
    """
    request = PlanRequest(
        scene_factory, error, until, probes, quantity, norm, threads,
        max_seconds, ladder, window, candidates, detect, max_refinement,
        max_order, timing_checks, refinements, refine_best,
        calibration_seconds, cache, options, scene, log, record)
    search = _Search(request.checked())
    search.choose_candidates()
    search.calibrate_ladders()
    search.refine()
    return search.conclude(search.time_cheapest())


@dataclass
class PlanRequest:
    """What :func:`plan` was asked (its parameters, in its order)."""

    scene_factory: Callable
    error: float
    until: float | None
    probes: object
    quantity: str
    norm: str
    threads: int | None
    max_seconds: float | None
    ladder: Sequence[float] | None
    window: tuple | None
    candidates: Sequence | None
    detect: bool
    max_refinement: float
    max_order: float | None
    timing_checks: int
    refinements: int
    refine_best: int
    calibration_seconds: float | None
    cache: dict | None
    options: dict | None
    scene: str
    log: Callable[[str], None] | None
    record: Record | bool | None

    def checked(self) -> "PlanRequest":
        """The request with its values checked, the ladder sorted coarse
        to fine and the shipped record taken for ``record=True``."""
        _check_request(self.error, self.until, self.norm, self.max_seconds,
                       self.ladder)
        if self.probes is None:
            raise ValueError("probes must name where the error is measured "
                             "(mapping name -> point, or callable(scene))")
        ladder = sorted((float(d) for d in self.ladder), reverse=True)
        window = (self.window if self.window is not None
                  else (0.0, float(self.until)))
        return replace(self, ladder=ladder, window=window)

    def to_dict(self) -> dict:
        """The request as a plan file records it."""
        t0, t1 = self.window
        probe_names = (list(self.probes) if isinstance(self.probes, Mapping)
                       else [])
        return {"error": float(self.error), "until": float(self.until),
                "norm": self.norm, "quantity": self.quantity,
                "probes": probe_names, "threads": self.threads,
                "max_seconds": self.max_seconds, "window": [t0, t1],
                "ladder": self.ladder, "smoothing_s": metrics.SMOOTHING}


class _Search:
    """One plan's search, step by step: the candidates and the record's
    verdicts on them (:meth:`choose_candidates`), their calibration
    ladders (:meth:`calibrate_ladders`), rounds of finer levels for the
    most promising (:meth:`refine`), a timing of the cheapest at their
    planned spacing (:meth:`time_cheapest`) and the plan or the refusal
    (:meth:`conclude`)."""

    def __init__(self, request: PlanRequest):
        self.request = request
        self.say = request.log or (lambda message: None)
        self.clock = wallclock.perf_counter()
        self.record = (shipped_record() if request.record is True
                       else request.record)
        self.findings = []
        self.verdicts = {}
        self.cands, self.skipped, self.usable = [], [], []
        self.counter = 0
        self.progress = Progress(request.ladder[0])
        self.grid = None
        self.needs = {}
        # settings whose need recedes as fast as their levels approach
        # it, settings beyond reach whose levels stalled, settings at the
        # depth limit, and settings the record's prior leaves out (refine)
        self.receding, self.stalled, self.deepest = set(), set(), set()
        self.pruned = set()
        # the last step of each setting's need: (need, finest level)
        # before and after its finest level
        self.steps_of = {}
        # calibration seconds spent and allowed (refine)
        self.spent, self.budget = 0.0, math.inf

    # 1. effects the scene calls for, per integrator; the record's
    # verdicts --------------------------------------------------------
    def choose_candidates(self) -> None:
        q, say, record = self.request, self.say, self.record
        if q.candidates is None:
            settings, self.findings = candidate_settings(
                q.scene_factory, q.until, q.probes, q.quantity, q.threads,
                q.ladder, options=q.options, detect=q.detect,
                max_refinement=q.max_refinement, cache=q.cache, log=say)
        else:
            settings = [c if isinstance(c, Setting) else Setting.from_dict(c)
                        for c in q.candidates]
        # the verification record: what each setting's prediction is worth
        cands, skipped = self.cands, self.skipped
        for setting in settings:
            verdict = record.verdict(setting, q.norm) if record else None
            self.verdicts[setting] = verdict
            # a setting the user named is ruled out by its bias alone,
            # which no margin covers
            why = (refusal(verdict, q.error, check_ratio=q.candidates is None)
                   if verdict is not None else None)
            if record and verdict is None and q.candidates is None:
                skipped.append(Candidate(setting, [], note=(
                    f"not verified in the {q.norm} norm by the verification "
                    "record: not planned")))
            elif why is not None:
                skipped.append(Candidate(setting, [], note=why))
            else:
                cands.append(Candidate(setting, []))
        if record and q.candidates is None:
            # a setting another candidate dominated on every fitted scene
            kept = [c.setting for c in cands]
            for cand in list(cands):
                better = record.dominated(cand.setting, kept)
                if better is not None:
                    cands.remove(cand)
                    kept.remove(cand.setting)
                    skipped.append(Candidate(cand.setting, [], note=(
                        f"dominated by {better} on every fitted scene of the "
                        "verification record: not planned")))
        if skipped:
            say(f"verification record: {len(cands)} of {len(settings)} "
                f"settings calibrated ({len(skipped)} unverified, under-"
                "predicted, biased above the request or dominated)")

    # 2. calibration ladder -------------------------------------------
    def calibrate(self, cand, dx, total) -> bool:
        """One level of ``cand`` at ``dx`` (from the cache if an earlier
        plan ran it); False if it is unsupported or failed."""
        q, say, cache = self.request, self.say, self.request.cache
        self.counter += 1
        key = (float(f"{dx:.6g}"), cand.setting, float(q.until), q.quantity,
               q.threads)
        cached = cache is not None and key in cache
        say(f"{self.progress.bar(self.counter, total)} "
            f"{cand.setting.label()}, "
            f"dx = {dx * 1e3:.3g} mm" + (" (kept from an earlier plan)"
                                          if cached else " ..."))
        try:
            if cached:
                run = cache[key]
            else:
                run = ladder_run(q.scene_factory, dx, cand.setting, q.until,
                                 q.probes, q.quantity, q.threads)
                if cache is not None:
                    cache[key] = run
        except UnsupportedError as unsupported:
            cand.note = f"left out: {unsupported}"
            say(f"  {cand.note}")
            return False
        self.progress.done(run, cached)
        cand.runs.append(run)
        if run.failed:
            say(f"  failed: {run.failed}")
            self.progress.skip(len(q.ladder) - len(cand.runs))
            return False
        say(f"  {run.particles} particles, {run.steps} steps, "
            f"{run.wall:.2f} s")
        return True

    def calibrate_ladders(self) -> None:
        """Every candidate's ladder; the usable ones (whole ladders) take
        the finer levels earlier plans calibrated."""
        q, say, ladder = self.request, self.say, self.request.ladder
        total = len(self.cands) * len(ladder)
        self.progress.plan([dx for _ in self.cands for dx in ladder])
        for cand in self.cands:
            for dx in ladder:
                if not self.calibrate(cand, dx, total):
                    break
        t0, t1 = q.window
        self.grid = metrics.time_grid(t0, t1)
        for cand in self.cands:
            if (len(cand.runs) < len(ladder)
                    or any(r.failed for r in cand.runs)):
                cand.note = cand.note or ("failed: " + next(
                    (r.failed for r in cand.runs if r.failed), ""))[:80]
                continue
            # every finer level of this setting that an earlier plan of
            # the scene calibrated enters its fit: one verdict per
            # setting, not one per request
            finer = [r for r in cached_levels(q.cache, cand.setting, q.until,
                                              q.quantity, q.threads)
                     if r.dx < ladder[-1] * (1 - 1e-6)]
            if finer:
                say(f"{cand.setting.label()}: {len(finer)} finer level(s) "
                    "from earlier plans (" + ", ".join(
                        f"{r.dx * 1e3:.3g}" for r in finer) + " mm)")
            cand.runs.extend(finer)
            cand.smoothed = [_smoothed(r, self.grid) for r in cand.runs]
            self.usable.append(cand)

    # 3. error models, floors, spacings and costs; refine the ladder of
    # the most promising settings while they need far extrapolation ----
    def price(self, cand):
        """(dx, CPU seconds) the setting needs for the request, or None;
        sets the candidate's spacing, size and predicted times."""
        q, error, ladder = self.request, self.request.error, self.request.ladder
        cand.dx = cand.particles = cand.steps = cand.seconds = None
        cand.cpu_seconds = None
        cand.note = ""
        dx = cand.model.spacing_for(error)
        if dx is None:
            cand.note = (f"no convergence on the ladder: error bounded by "
                         f"3 x data range = {cand.model.upper(ladder[-1]) * 100:.2f} %"
                         if cand.model.anomalous else
                         f"floor {cand.model.floor * 100:.2f} % >= request")
            return None
        dx = float(f"{min(dx, ladder[0]):.3g}")
        while cand.model.upper(dx) > error and dx > cand.model.finest * 1e-6:
            dx *= 0.99
        if dx < cand.model.smallest_dx:
            # never build a scene this fine: scale from the ladder
            n, steps = _size_at(cand.runs, dx)
            cand.note = (f"needs dx {dx * 1e3:.3g} mm, below the finest "
                         f"calibrated spacing / {q.max_refinement:g}")
            return dx, cand.cost.predict_cpu(n, steps)
        n, steps = _steps_to(q.scene_factory, dx, cand.setting, q.until)
        cand.dx, cand.particles, cand.steps = dx, n, steps
        cand.seconds = cand.cost.predict(n, steps)
        cand.cpu_seconds = cand.cost.predict_cpu(n, steps)
        return dx, cand.cpu_seconds

    def fit_verified(self, cand) -> None:
        """The setting's error model on its levels, with the record's
        factor and bias (its floor is the caller's)."""
        q, record = self.request, self.record
        _fit_candidate(cand, q.norm, q.max_refinement, q.threads, q.max_order,
                       record.orders(cand.setting, q.norm) if record
                       else None)
        verdict = self.verdicts.get(cand.setting)
        if verdict is not None:
            cand.model.verified = verdict["factor"]
            cand.model.bias = verdict["bias"]

    def fit_all(self) -> dict:
        """Every usable setting fitted, floored and priced: {id: price}."""
        q, record, usable = self.request, self.record, self.usable
        for cand in usable:
            self.fit_verified(cand)
        floors = consistency_floors(
            [c.model for c in usable],
            [c.smoothed[:len(q.ladder)] for c in usable], q.norm, q.ladder,
            trust=([record.promise(c.setting, q.norm) for c in usable]
                   if record else None))
        for cand, floor in zip(usable, floors):
            cand.model.floor = floor
        return {id(c): self.price(c) for c in usable}

    def power_need(self, model):
        """The spacing the power law of ``model`` alone gives the
        requested error (no floor: the needs of one setting before and
        after a level compare on the same terms), and its finest level."""
        if model.anomalous:
            return None, model.finest
        return (replace(model, floor=0.0).spacing_for(self.request.error),
                model.finest)

    def last_step(self, cand):
        """(need, finest level) without the setting's finest level and
        with it (its current model, which fit_all has just made)."""
        kept = cand.runs, cand.smoothed, cand.model, cand.cost
        cand.runs, cand.smoothed = cand.runs[:-1], cand.smoothed[:-1]
        try:
            self.fit_verified(cand)
            before = self.power_need(cand.model)
        finally:
            cand.runs, cand.smoothed, cand.model, cand.cost = kept
        return before, self.power_need(cand.model)

    def depth(self, cand) -> int:
        """The setting's levels below the ladder (earlier plans' too)."""
        return sum(1 for r in cand.runs
                   if not r.failed and r.dx < self.request.ladder[-1] * (1 - 1e-6))

    def determined(self, c) -> bool:
        return self.needs[id(c)] is not None and not c.model.anomalous

    def refine(self) -> None:
        """Fit every usable setting, then up to ``refinements`` rounds of
        a finer level for the most promising ones."""
        q, say = self.request, self.say
        # settings whose need recedes as fast as their levels approach
        # it: the error does not follow the power law there, and a finer
        # level costs 3.4x the last without bringing a plan closer
        # (cubic_o4 on the piston with nu = 0.45, max 2.5 %: needs of
        # 0.232 and then 0.132 mm at levels of 0.445 and 0.297 mm; its
        # 0.198 mm level took 800 s of CPU and the request was refused
        # after 929 s); and settings beyond reach whose levels stalled
        # (below)
        self.needs = self.fit_all()
        # the last step of each setting's need: (need, finest level)
        # before and after its finest level, from the levels of earlier
        # plans too
        for cand in self.usable:
            if len(cand.runs) > len(q.ladder):
                self.steps_of[id(cand)] = self.last_step(cand)
                (old_need, old_finest), (new_need, new_finest) = \
                    self.steps_of[id(cand)]
                # a need that receded as fast as an earlier plan's level
                # approached it: no further level in this plan either
                if (old_need is not None and new_need is not None
                        and old_need / new_need >= old_finest / new_finest):
                    self.receding.add(id(cand))
                    say(f"not refining {cand.setting.label()} further: its "
                        f"need went from {old_need * 1e3:.3g} to "
                        f"{new_need * 1e3:.3g} mm as its finest level went "
                        f"from {old_finest * 1e3:.3g} to "
                        f"{new_finest * 1e3:.3g} mm in an earlier plan (its "
                        "error does not follow the power law there)")
        self.spent = sum(r.wall for c in self.cands for r in c.runs
                         if not r.failed)
        self.budget = (q.calibration_seconds
                       if q.calibration_seconds is not None else math.inf)
        for round_ in range(q.refinements):
            wanted = self.refinement_targets(round_)
            if not wanted:
                break
            self.refine_round(wanted)

    def refinement_targets(self, round_: int) -> list:
        """The settings that get a finer level in this round."""
        q, say, record, needs = self.request, self.say, self.record, self.needs
        usable, norm = self.usable, q.norm
        # a setting that needs a spacing far below its ladder, or below
        # it with the large safety factor (a fit outside the asymptotic
        # range: a finer level may bring the small one, which costs
        # Fs^(d/q) less), gets a finer level -- if the rounds left can
        # bring its need within the extrapolation limit (a setting that
        # needs 1e-5 mm at the order its ladder shows is not worth a
        # level: the piston's plans spent their rounds on such ones)
        reach = 1.5 ** (q.refinements - round_) * q.max_refinement
        wanted = sorted(
            (c for c in usable if needs[id(c)] is not None
             and needs[id(c)][0] >= c.model.finest / reach
             and (needs[id(c)][0] < c.model.finest / 2
                  or (c.model.safety > SAFETY_GOOD
                      and needs[id(c)][0] < c.model.finest))),
            key=lambda c: needs[id(c)][1])[:q.refine_best]
        # a setting whose ladder determines no order (no convergence
        # observed, or the large safety factor) has no trustworthy
        # prediction to rank it by: its levels may be outside the
        # asymptotic range (cubic_o4 on the piston in the max norm: the
        # largest difference of 3 and 2 mm is a feature at 238 us, those
        # of the finer levels one at 280-290 us; from 2 to 0.67 mm the
        # order is 1.26 with a good fit). It gets a finer level too, the
        # cheapest first, besides those ranked by their need, when that
        # level costs less CPU time than the cheapest run planned so far
        # (else running the plan is the cheaper way to the answer)
        next_size = {id(c): _size_at(c.runs, c.model.finest / 1.5)
                     for c in usable}
        next_cost = {id(c): c.cost.predict(*next_size[id(c)])
                     for c in usable}
        next_cpu = {id(c): c.cost.predict_cpu(*next_size[id(c)])
                    for c in usable}
        cheapest = min((needs[id(c)][1] for c in usable
                        if needs[id(c)] is not None), default=math.inf)
        # a finer level that costs more CPU time than running the best
        # plan found so far is not worth its price: that plan is the
        # cheaper way to the answer (on the piston, levels of 0.3 mm
        # were refined for 5 % requests that a 1 mm run met); while no
        # plan is in reach, every undetermined setting gets its level
        # (cubic_o4 with the leapfrog needs 0.75 mm on the piston before
        # its max-norm ladder determines an order, and lost its rounds to
        # cheaper settings two at a time)
        # and when the verification record is at hand, they are taken in
        # the order of its promise (how close each came to the record's
        # best setting on the fitted scenes), refine_best at a time: on
        # the piston, four settings of the cubic spline and Wendland
        # kernels that needed spacings of 1e-7 mm took a 1 mm level each
        # beside cubic_o4's, whose record error is 2.5x below theirs
        planned = min((c.cpu_seconds for c in usable
                       if c.cpu_seconds is not None), default=math.inf)

        def order(c):
            promise = record.promise(c.setting, norm) if record else None
            return (math.inf if promise is None else promise,
                    next_cost[id(c)])

        prior = _record_prior(usable, needs, record, norm, len(q.ladder),
                              self.progress.exponent())
        # while no plan is in reach, a setting whose need lies beyond the
        # rounds left is taken the same way: its order may be that of
        # levels outside the asymptotic range (cubic_o4 on the piston
        # with nu = 0.45 in the max norm: order 0.64 from 3-1.5 mm, a need
        # of 0.1 mm; with a 1 mm level its order is 1 and it needs 0.9 mm,
        # where its error is 2.3 % against a 5 % request)
        beyond = {id(c) for c in usable
                  if not math.isfinite(planned) and needs[id(c)] is not None
                  and needs[id(c)][0] < c.model.finest / reach}
        self.drop_stalled(beyond, round_)
        undetermined = sorted(
            (c for c in usable if c not in wanted
             and (c.model.anomalous or c.model.safety > SAFETY_GOOD
                  or id(c) in beyond)
             and next_cpu[id(c)] <= cheapest
             and prior.get(id(c), 1.0) <= RECORD_PRUNE),
            key=order)[:q.refine_best if math.isfinite(planned) or record
                       else None]
        for c in usable:
            if (prior.get(id(c), 1.0) > RECORD_PRUNE
                    and id(c) not in self.pruned):
                self.pruned.add(id(c))
                say(f"not refining {c.setting.label()}: the verification "
                    f"record prices its error at {prior[id(c)]:.0f}x the "
                    "cost of the most promising setting")
        for c in wanted + undetermined:
            if self.depth(c) >= q.refinements and id(c) not in self.deepest:
                self.deepest.add(id(c))
                say(f"not refining {c.setting.label()} further: it has "
                    f"{self.depth(c)} level(s) below its ladder (down to "
                    f"{c.model.finest * 1e3:.3g} mm, earlier plans' "
                    f"included), the most a plan refines ({q.refinements})")
        return [c for c in wanted + undetermined
                if next_cost[id(c)] + self.spent <= self.budget
                and next_cpu[id(c)] <= planned
                and id(c) not in self.receding and id(c) not in self.stalled
                and self.depth(c) < q.refinements]

    def drop_stalled(self, beyond: set, round_: int) -> None:
        """Take out of ``beyond`` the settings whose last level shows
        them stalled there: the gap from the finest level to the need
        shrank by a factor g per level, and at that pace the rounds left
        do not bring it within the extrapolation limit (the cubic spline
        on the squat piston, max 2.5 %: needs of 0.76 um at levels of
        0.67 and 0.44 mm, then a 0.088 mm level of 1.3 million
        particles, 2280 s, and the request still refused)."""
        q = self.request
        for c in self.usable:
            if (id(c) not in beyond or id(c) not in self.steps_of
                    or id(c) in self.receding):
                continue
            (old_need, old_finest), (new_need, new_finest) = \
                self.steps_of[id(c)]
            if old_need is None or new_need is None:
                continue
            gap = new_finest / new_need
            pace = (old_finest / old_need) / gap
            left = q.refinements - round_
            if pace <= 1 or gap / pace ** left > q.max_refinement:
                beyond.discard(id(c))
                if id(c) not in self.stalled:
                    self.stalled.add(id(c))
                    self.say(
                        f"not refining {c.setting.label()} further: it "
                        f"needs dx {new_need * 1e3:.3g} mm, {gap:.3g}x "
                        f"below its finest level, and its last level "
                        f"(from {old_finest * 1e3:.3g} to "
                        f"{new_finest * 1e3:.3g} mm) narrowed that gap by "
                        f"{pace:.3g}x: {left} more level(s) at that pace "
                        f"leave it beyond the extrapolation limit "
                        f"({q.max_refinement:g}x)")

    def refine_round(self, wanted: list) -> None:
        """A finer level (finest / 1.5) for each of ``wanted``, then every
        setting fitted again; a need that receded as fast as its level
        approached it stops that setting's refinement."""
        say, needs = self.say, self.needs
        before = {id(c): (needs[id(c)][0], c.model.finest) for c in wanted
                  if self.determined(c)}
        refined = []
        for cand in wanted:
            dx = float(f"{cand.model.finest / 1.5:.3g}")
            say(f"refining {cand.setting.label()}: "
                + (f"it needs dx {needs[id(cand)][0] * 1e3:.3g} mm"
                   if needs[id(cand)] is not None else
                   "its ladder determines no order"))
            if self.calibrate(cand, dx, self.counter + 1):
                cand.smoothed.append(_smoothed(cand.runs[-1], self.grid))
                self.spent += cand.runs[-1].wall
                refined.append(cand)
            else:
                cand.runs.pop()
        self.needs = needs = self.fit_all()
        for cand in refined:
            self.steps_of[id(cand)] = self.last_step(cand)
            if id(cand) not in before or not self.determined(cand):
                continue
            need, finest = before[id(cand)]
            if cand.model.finest >= finest:
                continue                      # the level failed
            if need / needs[id(cand)][0] >= finest / cand.model.finest:
                self.receding.add(id(cand))
                say(f"not refining {cand.setting.label()} further: its need "
                    f"went from {need * 1e3:.3g} to "
                    f"{needs[id(cand)][0] * 1e3:.3g} mm as its finest level "
                    f"went from {finest * 1e3:.3g} to "
                    f"{cand.model.finest * 1e3:.3g} mm (its error does not "
                    "follow the power law there)")

    # 4. timing of a few steps at the planned spacing ------------------
    def time_cheapest(self) -> list:
        """The priced settings, cheapest in CPU seconds first, after the
        ``timing_checks`` cheapest planned beyond their largest
        calibration run had a few steps timed there (the CPU seconds: the
        measure that a loaded machine disturbs least)."""
        q, say = self.request, self.say
        priced = sorted((c for c in self.usable if c.cpu_seconds is not None),
                        key=lambda c: c.cpu_seconds)
        # within the calibrated sizes the calibration runs (whole runs,
        # probe sampling included) measure the cost; a few steps timed
        # there only add noise (on the gravity column at 8 mm, 0.1 s runs
        # of 3200 steps, two plans of the same run predicted 0.148 and
        # 0.111 CPU s after their five timed steps, the run took
        # 0.096-0.101 s): the timing checks are for scenes larger than
        # the largest calibration run
        for cand in [c for c in priced if c.particles > max(
                r.particles for r in c.runs if not r.failed)][
                :max(0, q.timing_checks)]:
            say(f"timing a few steps of {cand.setting.label()} at dx = "
                f"{cand.dx * 1e3:.3g} mm ...")
            n, _, per_step = time_steps(q.scene_factory, cand.dx, cand.setting,
                                        q.threads, clock=cand.cost.clock,
                                        min_seconds=TIMING_SECONDS)
            finest = min(cand.runs, key=lambda r: r.dx)
            n0, _, per_step0 = time_steps(q.scene_factory, finest.dx,
                                          cand.setting, q.threads,
                                          clock=cand.cost.clock,
                                          min_seconds=TIMING_SECONDS)
            # anchored on the finest calibration run's own cost (the line
            # through all runs misses single sizes by several per cent)
            cand.cost.correct(n, per_step, n0, per_step0, reference_cost(
                finest, cand.cost.clock,
                lambda run=finest, setting=cand.setting: ladder_run(
                    q.scene_factory, run.dx, setting, q.until, q.probes,
                    q.quantity, q.threads)))
            cand.seconds = cand.cost.predict(cand.particles, cand.steps)
            cand.cpu_seconds = cand.cost.predict_cpu(cand.particles,
                                                     cand.steps)
        priced.sort(key=lambda c: c.cpu_seconds)
        return priced

    def conclude(self, priced: list) -> Plan:
        """The plan: the cheapest affordable setting, or the refusal."""
        q, record, skipped = self.request, self.record, self.skipped
        affordable = [c for c in priced
                      if q.max_seconds is None or c.seconds <= q.max_seconds]
        result = Plan(request=q.to_dict(), feasible=bool(affordable),
                      threads=q.threads, findings=self.findings,
                      candidates=self.cands + skipped, scene=q.scene)
        if affordable:
            result.adopt(affordable[0])
        elif not self.cands and skipped:
            # the record left every candidate out: say which effects made
            # them unverified, and how to plan without the record
            verified = ({name for key in record.families()
                         for name in key.split(" + ")[1:]} if record else set())
            effects = sorted({name for c in skipped
                              for name, _ in c.setting.effects
                              if name not in verified})
            unverified = sum(c.note.startswith("not verified") for c in skipped)
            result.best_reachable_error = None
            result.reason = (
                f"the verification record verifies none of the {len(skipped)} "
                f"candidate settings in the {q.norm} norm ({unverified} not "
                "verified" + (f"; the record has no setting with "
                              f"{', '.join(effects)}, which this scene calls "
                              "for" if effects else "")
                + f"; {len(skipped) - unverified} biased at or above the "
                "request or dominated); plan without the record (sphsolid "
                "plan --no-record, planner.plan(..., record=None)) to choose "
                "by self-convergence alone, without the record's margins")
        else:
            result.best_reachable_error, result.reason = _refusal(
                self.usable, q.error, q.max_seconds, q.scene_factory, q.until)
        result.calibration_seconds = wallclock.perf_counter() - self.clock
        return result


def _record_prior(usable, needs, record, norm: str, levels: int,
                  exponent: float) -> dict:
    """What the verification record expects each setting to pay for one
    error, relative to the most promising setting still in play (one that
    is priced or whose ladder shows no convergence yet; a floor at or
    above the request puts a setting out): by {id: ratio}.

    A setting whose error at the record's finest level was R times the
    best setting's reaches a given error, converging at the formal order,
    at a spacing R^(1/q) finer, which costs R^(p/q) more work (p the
    exponent of work in 1/dx: 3 in 2D), times the ratio of the two
    settings' own calibration runs at the finest common ladder level (a
    wider kernel, more steps). Settings the record does not place get no
    prior."""
    if not record:
        return {}
    expected = {}
    for c in usable:
        promise = record.promise(c.setting, norm)
        if (promise is None or len(c.runs) < levels
                or not (needs[id(c)] is not None or c.model.anomalous)):
            continue
        unit = c.runs[levels - 1].cpu
        if not (math.isfinite(unit) and unit > 0):
            unit = c.runs[levels - 1].wall
        if math.isfinite(unit) and unit > 0:
            expected[id(c)] = math.exp(
                promise * exponent / FORMAL_ORDER) * unit
    if not expected:
        return {}
    best = min(expected.values())
    return {key: value / best for key, value in expected.items()}


def _size_at(runs: Sequence[LadderRun], dx: float) -> tuple[int, int]:
    """(particles, steps) at ``dx`` scaled from the ladder's runs by the
    power laws they follow (particles ~ dx^-dim, steps ~ dx^-1), without
    building the scene."""
    h = np.log([r.dx for r in runs])
    n = np.polyfit(h, np.log([r.particles for r in runs]), 1)
    k = np.polyfit(h, np.log([r.steps for r in runs]), 1)
    return (int(math.exp(np.polyval(n, math.log(dx)))),
            int(math.ceil(math.exp(np.polyval(k, math.log(dx))))))


def _smoothed(run: LadderRun, grid) -> dict:
    return {n: metrics.smooth(grid, metrics.on_grid(run.times, run.series[n],
                                                    grid))
            for n in run.series}


def _fit_candidate(cand, norm, max_refinement, threads,
                   max_order=FORMAL_ORDER, prior=None) -> None:
    """Error model on the finest four levels (three differences: the
    coarsest levels of a long ladder are the least asymptotic), all on
    the finest level's scale, with the record's orders ``prior``
    (:func:`fit_error_model`); every level's difference from the next
    coarser one is kept for its own bound
    (:meth:`ErrorModel.level_bounds`); cost model on all its runs."""
    every = [r.dx for r in cand.runs]
    scales = {n: metrics.scale_of(s, norm)
              for n, s in cand.smoothed[-1].items()}

    def distance(a, b):
        return max(metrics.deviation(a[n], b[n], norm, scales[n]) for n in a)
    steps = [distance(a, b) for a, b in zip(cand.smoothed, cand.smoothed[1:])]
    spacings, levels, diffs = every[-4:], cand.smoothed[-4:], steps[-3:]
    spread = max(distance(a, b) for a, b in
                 itertools.combinations(levels, 2))
    cand.model = fit_error_model(spacings, diffs, 0.0, max_refinement,
                                 spread, max_order, prior)
    cand.model.calibrated = list(zip(every, [None] + steps))
    if not cand.model.anomalous:
        cand.model.repeating = repeating_factor(spacings, levels,
                                                cand.model.order, norm)[0]
        cand.model.levels = [(dx, cand.model.power(dx)) for dx in spacings]
    cand.cost = CostModel.from_runs(cand.runs, threads)


def _default_dt(scene_factory, dx, integrator) -> float:
    scene = build_scene(scene_factory, dx, Setting.make(integrator=integrator),
                        1)
    return make_dynamics(scene, integrator, progress=False).dt


def _reach(cand, max_seconds):
    """(bound, dx): the smallest bound ``cand`` reaches within the
    extrapolation limit and ``max_seconds`` (the largest affordable
    refinement, or an affordable calibrated level's own bound)."""
    def affordable(dx):
        return (max_seconds is None or len(cand.runs) < 2
                or cand.cost.predict(*_size_at(cand.runs, dx))
                <= max_seconds)
    model = cand.model
    dx = model.smallest_dx
    while not affordable(dx) and dx < model.finest * 4:
        dx *= 1.25
    options = [(model.upper(dx), -dx)] + [
        (bound, -level) for level, _, bound in model.level_bounds()
        if affordable(level)]
    bound, spacing = min(options)
    return bound, -spacing


def _measured(cand) -> str:
    """What the calibration of ``cand`` measured, for a refusal: its
    finest level, the self-convergence difference there and the bound
    the record allows on it; and, where its ladder is not in its
    asymptotic range, why, and the level that would settle it."""
    model = cand.model
    finest, diff = (model.calibrated or [(model.finest, None)])[-1]
    bounds = model.level_bounds()
    line = f"{cand.setting.label()}: finest level {finest * 1e3:.3g} mm"
    if diff is not None and bounds:
        order = (model.order if model.prior is None
                 else min(model.order, model.prior[0]))
        line += (f", self-convergence difference there {diff * 100:.2f} %,"
                 f" bound {bounds[-1][2] * 100:.2f} % ("
                 + ("3 x the largest difference of its levels"
                    if model.anomalous else
                    f"order {order:.2f}, safety {model.safety:g}, "
                    f"share that repeats {model.repeating:.2f}")
                 + f", record factor {model.verified:.2f}"
                 + (f", floor {model.floor * 100:.2f} %" if model.floor
                    else "")
                 + (f", record bias {model.bias * 100:.2f} %" if model.bias
                    else "") + ")")
    issues = model.asymptotic_issues()
    if issues:
        line += ("; its ladder is not in its asymptotic range: "
                 + "; ".join(issues))
        finer = float(f"{finest / 1.5:.3g}")
        line += f"; a level at {finer * 1e3:.3g} mm would settle it"
        if len(cand.runs) >= 2 and cand.cost is not None:
            n, steps = _size_at(cand.runs, finer)
            line += (f" ({n} particles, {steps} steps, predicted "
                     f"{cand.cost.predict_cpu(n, steps):.3g} s of CPU)")
    return line


def _refusal(modelled, error, max_seconds, scene_factory, until):
    """The best error any setting reaches (within max_seconds and the
    extrapolation limit; at a calibrated level, that level's own bound
    where it is smaller) and the reason for refusing, with what each
    setting's calibration measured (:func:`_measured`)."""
    if not modelled:
        return None, ("no setting could be calibrated (every candidate "
                      "failed or was unavailable)")
    # the best error within the extrapolation limit alone: when it meets
    # the request, the time budget is what refuses
    unlimited = min(_reach(c, None)[0] for c in modelled)
    best, dx, cand = min(((*_reach(c, max_seconds), c) for c in modelled),
                         key=lambda x: (x[0], -x[1]))
    floors = min(c.model.floor for c in modelled)
    if cand.model.anomalous:
        reason = (f"no setting meets {error * 100:g} %: the calibration "
                  f"levels show no convergence (observed order "
                  f"{cand.model.observed_order:.2f}, fit residual "
                  f"{cand.model.residual:.2f}), so the error of each "
                  f"calibrated level is only bounded by 3 x their largest "
                  f"difference ({cand.model.data_range * 100:.2f} %; Eça & "
                  f"Hoekstra) and nothing finer can be promised")
    elif max_seconds is not None and unlimited <= error:
        reason = (f"no setting meets {error * 100:g} % within "
                  f"{max_seconds:g} s")
    elif floors >= error:
        reason = (f"the request {error * 100:g} % is below the observed error"
                  f" floor: the settings differ by {floors * 100:.2f} %, a "
                  f"difference that does not shrink with refinement or "
                  f"that their own predicted errors do not explain (a bias "
                  f"refinement does not remove)")
    else:
        reason = (f"no setting meets {error * 100:g} % within the "
                  f"extrapolation limit (dx >= finest ladder spacing / "
                  f"{cand.model.max_refinement:g})")
    level = any(abs(level - dx) <= 1e-6 * level
                for level, _, _ in cand.model.level_bounds())
    reason += (f"; best reachable: {best * 100:.2f} % with "
               f"{cand.setting.label()} at dx = {dx * 1e3:.3g} mm"
               + (" (a calibrated level: the bound of its own differences)"
                  if level else ""))
    reason += "\nmeasured, per setting calibrated:" + "".join(
        "\n  " + _measured(c) for c in modelled)
    return float(best), reason
