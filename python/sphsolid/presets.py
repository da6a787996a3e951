"""Named settings of the paper's scenes: the paper's own scheme, the most
accurate one per CPU second measured for wave problems, and that one made
for sharp fronts at fine spacings (docs/validation.md, sections "End
placement and presets" and "What limits the observed order").

    scene = scenes.uniaxial_piston(1e-3, preset="waves")
    dyn = presets.dynamics(scene)          # the preset's integrator
    dyn.run(until=0.3e-3)

A preset fixes what the scene builders and the integrator leave open:
kernel, h/dx, artificial viscosity, end placement of plate and piston, the
integrator and its step (as a fraction of the integrator's default). It changes no physics; every choice is a library setting.
"""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Preset", "PRESETS", "preset", "dynamics"]


@dataclass(frozen=True)
class Preset:
    """A named setting: kernel, h/dx, integrator, viscosity (None: off),
    platen inset (lattice steps, or "static") and the time step as a
    fraction of the integrator's default step (1: the default)."""
    name: str
    kernel: str
    smoothing_ratio: float
    integrator: str
    viscosity: dict | None
    inset: float | str
    description: str
    step: float = 1.0

    def to_dict(self) -> dict:
        return {"kernel": self.kernel, "smoothing_ratio": self.smoothing_ratio,
                "integrator": self.integrator,
                "viscosity": None if self.viscosity is None
                else dict(self.viscosity), "inset": self.inset,
                "step": self.step}


PRESETS = {
    "paper": Preset(
        "paper", "cubic_spline", 1.2, "improved_euler",
        {"alpha": 1.0, "beta": 0.0}, 0.0,
        "Das & Cleary's scheme: cubic spline, h = 1.2 dx, Improved Euler at "
        "0.5 h/c0, Monaghan viscosity alpha 1, platens on the specimen's "
        "extent (the library's defaults)"),
    "waves": Preset(
        "waves", "cubic_o4", 1.65, "leapfrog", None, "static",
        "fourth-order kernel cubic_o4 at h = 1.65 dx, leapfrog at its "
        "default step h/(1.5 c0), no viscosity, plate and piston at the "
        "static inset (0.227 steps): the most accurate per CPU second on "
        "the piston test; not for rebounding impacts or tension without "
        "artificial stress (docs/stability.md)"),
    "fronts": Preset(
        "fronts", "cubic_o4", 1.6525, "leapfrog", None, "static",
        "the waves setting made for sharp fronts at 1 mm and below: "
        "cubic_o4 at h = 1.6525 dx, where its lattice gradient moment is 1 "
        "(waves run at c_p, not 0.08 % fast), the leapfrog at half its "
        "default step (its phase error, which runs short waves ahead of a "
        "front, a quarter), no viscosity, static platen inset: on the "
        "piston test at 0.5 mm 1.5 % max / 0.49 % RMS against the 1 mm FE "
        "series (0.94 / 0.37 % against the 0.5 mm one) for twice the "
        "waves preset's cost; the same exclusions "
        "as waves (docs/validation.md, section 4d)", step=0.5),
}


def preset(name) -> Preset:
    """The preset of that name (a Preset passes through)."""
    if isinstance(name, Preset):
        return name
    if name not in PRESETS:
        raise ValueError(f"preset {name!r}: known presets are "
                         f"{', '.join(PRESETS)}")
    return PRESETS[name]


def dynamics(scene, preset_name=None, **kwargs):
    """A Dynamics object of the scene's preset integrator (the scene
    builders record the preset as ``scene.preset``) at the preset's step
    (its ``step`` times the integrator's default); ``kwargs`` go to it
    (dt, progress, ...), an explicit ``dt`` overriding the preset's."""
    from .dynamics import dynamics_for
    chosen = preset(preset_name if preset_name is not None
                    else getattr(scene, "preset", None) or "paper")
    kind = dynamics_for(chosen.integrator)
    dyn = kind(scene, **kwargs)
    if chosen.step != 1.0 and kwargs.get("dt") is None:
        kwargs["dt"] = dyn.dt * chosen.step
        dyn = kind(scene, **kwargs)
    return dyn
