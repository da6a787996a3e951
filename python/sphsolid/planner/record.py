"""The verification record: how far each setting's self-convergence
prediction is from its true error, measured once on reference scenes.

Self-convergence (the error model of :mod:`.error_model`) sees the error
that refinement removes; it cannot see a bias that does not go away (a
lattice moment at fixed h/dx, a dissipation floor), nor a prediction that
its own levels under-state. Following Roache, the code is verified before
a solution is: ``python -m validation.record`` runs every setting the
planner may choose (the CLI's default candidates,
:func:`~sphsolid.planner.search.candidate_settings`) on reference scenes
with a trusted answer, at the spacings a plan would use, and records for
each setting and norm

- ``ratio``: the largest ratio of its true error at a spacing to the
  planner's upper prediction there, made from the coarser levels only
  (the fit a plan would have made), over the fitted scenes;
- ``bias``: the error that refinement does not remove (a non-negative
  least-squares fit ``e(dx) = a dx^q + b`` of the true errors, at the
  order the levels' differences show), the largest over the fitted scenes.

The planner does not plan a setting whose ratio exceeds 1 (its
prediction under-stated its true error on a fitted scene: a margin fitted
there need not hold on another scene), multiplies the others' upper
prediction by ``factor = max(1, MARGIN x ratio)`` and never plans them for
a request at or below their bias; a setting the record does not list
(never verified) is not planned. The record also lists, per setting, the settings that dominated
it on every fitted scene that verified it (errors at most 1.05 times its
own at every level in both norms, for at most 0.8 times its CPU time):
when one of those is among a plan's candidates, the dominated one is not
calibrated (the leapfrog dominates Improved Euler with the same kernel and
effects: the same errors for half the evaluations per step). Scenes declared held out are run and reported beside the fitted
ones, never used for the factors. The file ships with the package
(``record.json``, next to this module); the verification
table of validation/reports/accuracy/quick.md is generated from it
(docs/accuracy.md summarises it).
"""
from __future__ import annotations

import math
from functools import lru_cache
from pathlib import Path

#: The record's file, shipped with the package.
RECORD_FILE = Path(__file__).with_name("record.json")
#: Format of record.json (its "format" key).
RECORD_FORMAT = 1
#: Margin on the largest observed ratio of true to predicted error.
MARGIN = 1.2


def family(setting) -> str:
    """The record's key of a setting: kernel, h/dx, end placement,
    integrator, its step when not the default, and the names of its
    effects (their parameters are the
    effect detection's, which may differ from scene to scene)."""
    inset = ("" if setting.inset in (0, 0.0) else f" inset={setting.inset}"
             if isinstance(setting.inset, str) else f" inset={setting.inset:g}")
    names = sorted(name for name, _ in setting.effects)
    step = ("" if getattr(setting, "step", 1.0) == 1.0
            else f" step={setting.step:g}")
    return (f"{setting.kernel} h/dx={setting.smoothing_ratio:g}{inset} "
            f"{setting.integrator}{step}" + ("" if not names else
                                        " + " + " + ".join(names)))


class Record:
    """The verification record (see the module's text)."""

    def __init__(self, data: dict, source: str = "record"):
        if not isinstance(data, dict):
            raise ValueError(f"{source}: the verification record must be a "
                             f"JSON object, got {type(data).__name__}")
        if data.get("format") != RECORD_FORMAT:
            raise ValueError(f"{source}: verification record format "
                             f"{data.get('format')!r}, this version reads "
                             f"{RECORD_FORMAT}")
        settings = data.get("settings")
        if not isinstance(settings, dict):
            raise ValueError(f"{source}: 'settings' must be an object")
        for key, entry in settings.items():
            for norm in ("max", "rms"):
                verdict = (entry or {}).get(norm)
                if verdict is None:
                    continue
                for name in ("ratio", "bias"):
                    value = verdict.get(name) if isinstance(
                        verdict, dict) else None
                    if not (isinstance(value, (int, float))
                            and math.isfinite(value) and value >= 0):
                        raise ValueError(
                            f"{source}: settings[{key!r}][{norm!r}]"
                            f"[{name!r}] must be a number >= 0, got "
                            f"{value!r}")
        self.data = data
        self.settings = settings
        self.margin = float(data.get("margin", MARGIN))

    @classmethod
    def load(cls, path: Path | str = RECORD_FILE) -> "Record":
        from .search import read_json
        return cls(read_json(path, "verification record"), str(path))

    def verdict(self, setting, norm: str) -> dict | None:
        """{"ratio", "bias", "factor"} of a setting in a norm, or None when
        the record does not verify it. ``setting`` may also be its
        family (:func:`family`)."""
        key = setting if isinstance(setting, str) else family(setting)
        verdict = (self.settings.get(key) or {}).get(norm)
        if not verdict:
            return None
        return {"ratio": float(verdict["ratio"]),
                "bias": float(verdict["bias"]),
                "factor": max(1.0, self.margin * float(verdict["ratio"]))}

    def dominated(self, setting, others) -> str | None:
        """The label of a setting among ``others`` that dominated
        ``setting`` on every fitted scene (as good at every level, for
        clearly less CPU time: the record's ``dominated_by``), or None."""
        better = set(self.data.get("dominated_by", {}).get(
            family(setting), []))
        for other in others:
            if other != setting and family(other) in better:
                return other.label()
        return None

    def promise(self, setting, norm: str) -> float | None:
        """How close a setting came to the best setting of the record at
        the finest level of each fitted scene that verified it: the mean
        over those scenes of log(its error / the smallest error of any
        setting there), 0 for the best; None when no fitted scene
        verified it. Orders the refinement of settings whose own ladder
        determines no order (a prior from the record, not a prediction)."""
        fitted = set(self.data.get("fitted", []))
        logs = []
        for scene, entry in self._scene_errors(norm, family(setting)):
            best = self._best_finest(norm).get(scene)
            if scene in fitted and best:
                logs.append(math.log(entry / best))
        return sum(logs) / len(logs) if logs else None

    def orders(self, setting, norm: str) -> tuple[float, float] | None:
        """The range (low, high) of the orders at which the setting's true
        errors fell on the fitted scenes that verified it in ``norm``:
        per scene the least-squares slope of log error against log dx
        over its levels (three or more); None when no fitted scene has
        them. The slope of the whole error, bias included, not of the
        part refinement removes: the slower of the two, so a prior on it
        errs towards larger errors below the ladder. The prior of the
        error model's fit (:func:`~.error_model.fit_order_with_prior`)."""
        fitted = set(self.data.get("fitted", []))
        key = setting if isinstance(setting, str) else family(setting)
        scenes = (self.settings.get(key) or {}).get("scenes") or {}
        slopes = []
        for scene, by_norm in scenes.items():
            entry = (by_norm or {}).get(norm) or {}
            errors = entry.get("errors") or []
            spacings = entry.get("spacings") or []
            if (scene not in fitted or len(errors) < 3
                    or len(errors) != len(spacings)
                    or not all(isinstance(e, (int, float)) and e > 0
                               for e in errors)):
                continue
            x = [math.log(dx) for dx in spacings]
            y = [math.log(e) for e in errors]
            mx, my = sum(x) / len(x), sum(y) / len(y)
            sxx = sum((a - mx) ** 2 for a in x)
            if sxx > 0:
                slopes.append(sum((a - mx) * (b - my)
                                  for a, b in zip(x, y)) / sxx)
        if not slopes:
            return None
        return float(min(slopes)), float(max(slopes))

    def _scene_errors(self, norm: str, key: str):
        scenes = (self.settings.get(key) or {}).get("scenes") or {}
        for scene, by_norm in scenes.items():
            errors = ((by_norm or {}).get(norm) or {}).get("errors") or []
            finest = errors[-1] if errors else None
            if isinstance(finest, (int, float)) and finest > 0:
                yield scene, float(finest)

    def _best_finest(self, norm: str) -> dict:
        cache = self.__dict__.setdefault("_best", {})
        if norm not in cache:
            best = {}
            for key in self.settings:
                for scene, error in self._scene_errors(norm, key):
                    best[scene] = min(best.get(scene, math.inf), error)
            cache[norm] = best
        return cache[norm]

    def families(self) -> list[str]:
        return sorted(self.settings)


def refusal(verdict: dict, error: float,
            check_ratio: bool = True) -> str | None:
    """Why the planner does not plan a setting of this ``verdict``
    (:meth:`Record.verdict`) for a request of ``error``, or None: its bias
    is at or above the request, or (``check_ratio``) its prediction
    under-stated its true error on a fitted scene, where a margin fitted
    there does not carry to other scenes (the cubic spline at h/dx 1.2 in
    the RMS norm: 1.32 on the piston, a factor of 1.58; on the held-out
    slender piston its 3 % plan achieved 3.67 %, 1.93x its own
    prediction)."""
    if verdict["bias"] >= error:
        return (f"its verified bias {verdict['bias'] * 100:.2f} % is at or "
                "above the request")
    if check_ratio and verdict["ratio"] > 1.0:
        return (f"its prediction under-stated its true error "
                f"{verdict['ratio']:.2f}x on a fitted scene of the "
                "verification record: not planned")
    return None


@lru_cache(maxsize=1)
def shipped() -> Record | None:
    """The record shipped with the package (None when it is absent)."""
    if not RECORD_FILE.exists():
        return None
    return Record.load(RECORD_FILE)
