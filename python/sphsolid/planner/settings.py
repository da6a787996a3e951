"""Candidate settings: the options the library offers and one setting
(kernel, h/dx, end placement, integrator, effects)."""
from __future__ import annotations

import ctypes
from dataclasses import dataclass
from typing import Mapping


from .. import _lib
from .._lib import UnsupportedError, lib


DEFAULT_INTEGRATOR = "improved_euler"
#: h/dx values tried: the library's default and the wider support that the
#: validation study found more accurate.
SMOOTHING_RATIOS = (1.2, 1.5)
#: Kernels accurate at their own h/dx, with the end placement matched to
#: it: candidates only at that setting (kernel -> (h/dx, inset)). cubic_o4
#: at h/dx 1.65 with the static platen inset is the validation study's
#: most accurate setting per CPU second on the piston test (the "waves"
#: preset; its lattice moment vanishes, so its error converges at a higher
#: order than the cubic spline's).
OWN_SETTING = {"cubic_o4": (1.65, "static")}
#: The representative of the other kernels in the effect detection.
STANDARD = ("cubic_spline", 1.2, 0.0)
#: Effects the planner decides (switched off in the factory's scene first).
MANAGED_EFFECTS = ("artificial_viscosity", "artificial_stress",
                   "kernel_correction", "damping", "xsph")
#: GCI safety factors (Roache 1998): consistent observed order / otherwise.
SAFETY_GOOD, SAFETY_POOR = 1.25, 3.0


# ------------------------------------------------------------ options
def _optional_function(name, restype, argtypes):
    """A library function that may not exist in this build (None then)."""
    try:
        library_path = _lib.library_path()  # loads the library
    except OSError:
        return None
    cdll = lib._cdll
    function = getattr(cdll, name, None) if cdll is not None else None
    if function is None:
        return None
    function.restype, function.argtypes = restype, argtypes
    del library_path
    return function


def kernel_names() -> list[str]:
    """Kernels the library offers, from its own registry
    (``sph_kernel_names``, else ``sph_kernel_name`` per number), else the
    default kernel alone."""
    listed = getattr(_lib, "kernel_names", None)
    if callable(listed):
        try:
            names = list(listed())
            if names:
                return names
        except (UnsupportedError, AttributeError):
            pass
    named = _optional_function("sph_kernel_name", ctypes.c_char_p,
                               [ctypes.c_int])
    names = []
    if named is not None:
        for index in range(64):
            value = named(index)
            if not value:
                break
            names.append(value.decode())
    return names or list(getattr(_lib, "KERNELS", {"cubic_spline": 0}))


def integrator_names() -> list[str]:
    """Integrators the library offers (``sph_integrator_names`` when it is
    exported), the default first."""
    from .. import dynamics
    listed = getattr(dynamics, "integrator_names", None)
    if callable(listed):
        names = list(listed())
    else:
        function = _optional_function("sph_integrator_names", ctypes.c_char_p,
                                      [])
        names = function().decode().split() if function is not None else []
        if not names:
            names = [DEFAULT_INTEGRATOR]
    names = list(dict.fromkeys([DEFAULT_INTEGRATOR] + names))
    return names


def _effect_available(name: str) -> bool:
    return name in _lib.effect_names()


# ------------------------------------------------------------ settings
def _freeze(effects: Mapping[str, Mapping[str, float]] | None) -> tuple:
    return tuple(sorted((str(name), tuple(sorted((str(k), float(v))
                                                 for k, v in
                                                 (params or {}).items())))
                        for name, params in (effects or {}).items()))


@dataclass(frozen=True)
class Setting:
    """What the planner chooses besides dx: h/dx, kernel, integrator and
    the effects with their parameters."""
    smoothing_ratio: float = 1.2
    kernel: str = "cubic_spline"
    integrator: str = DEFAULT_INTEGRATOR
    effects: tuple = ()
    #: end placement of plates and pistons (lattice steps, or "static":
    #: see :func:`sphsolid.build.plate`); 0 puts their faces on the body
    inset: float | str = 0.0
    #: time step as a fraction of the integrator's default step (the
    #: presets' ``step``)
    step: float = 1.0

    @classmethod
    def make(cls, smoothing_ratio=1.2, kernel="cubic_spline",
             integrator=DEFAULT_INTEGRATOR, effects=None,
             inset=0.0, step=1.0) -> "Setting":
        return cls(float(smoothing_ratio), str(kernel), str(integrator),
                   _freeze(effects),
                   inset if isinstance(inset, str) else float(inset),
                   float(step))

    @property
    def effect_dict(self) -> dict:
        return {name: dict(params) for name, params in self.effects}

    def with_effects(self, effects: Mapping) -> "Setting":
        return Setting(self.smoothing_ratio, self.kernel, self.integrator,
                       _freeze(effects), self.inset, self.step)

    def dynamics(self, scene, **kwargs):
        """The Dynamics that advances ``scene`` with this setting's
        integrator at its step (``step`` times the integrator's default;
        an explicit ``dt`` in ``kwargs`` wins)."""
        from .calibration import make_dynamics
        dyn = make_dynamics(scene, self.integrator, **kwargs)
        if self.step != 1.0 and kwargs.get("dt") is None:
            dyn = make_dynamics(scene, self.integrator,
                                **{**kwargs, "dt": dyn.dt * self.step})
        return dyn

    def label(self) -> str:
        short = {"artificial_viscosity": "visc", "artificial_stress": "AS",
                 "kernel_correction": "KC", "damping": "damp",
                 "xsph": "XSPH"}
        parts = []
        for name, params in self.effects:
            p = ",".join(f"{k}={v:g}" for k, v in params
                         if k in ("alpha", "rate", "epsilon"))
            parts.append(short.get(name, name) + (f"({p})" if p else ""))
        inset = ("" if self.inset in (0, 0.0) else
                 f" inset={self.inset}" if isinstance(self.inset, str)
                 else f" inset={self.inset:g}")
        step = "" if self.step == 1.0 else f" step={self.step:g}"
        return (f"{self.kernel} h/dx={self.smoothing_ratio:g}{inset} "
                f"{self.integrator}{step}" + (" + " + " + ".join(parts)
                                              if parts else ""))

    def to_dict(self) -> dict:
        return {"smoothing_ratio": self.smoothing_ratio,
                "kernel": self.kernel, "integrator": self.integrator,
                "effects": self.effect_dict, "inset": self.inset,
                "step": self.step}

    @classmethod
    def from_dict(cls, data: Mapping) -> "Setting":
        return cls.make(data.get("smoothing_ratio", 1.2),
                        data.get("kernel", "cubic_spline"),
                        data.get("integrator", DEFAULT_INTEGRATOR),
                        data.get("effects") or {}, data.get("inset", 0.0),
                        data.get("step", 1.0))
