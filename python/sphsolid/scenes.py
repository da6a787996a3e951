"""The paper's scenes, ready to run (Das & Cleary, uniaxial compression).

:func:`uniaxial_piston` is the default scene everywhere: an 86 mm x 140 mm
specimen between a fixed plate and a piston moving down at 1.5 mm/s.
:func:`gravity` is the same specimen resting on the plate under gravity,
with damping so the static, height-graded stress is reached fast.
"""
from __future__ import annotations

from . import presets as _presets
from .builders import cylinder, layer_spacing, piston, plate, rectangle
from .material import Material
from .probes import PAPER_PROBES
from .scene import Scene
from .units import length as _length, quantity as _quantity, velocity as _velocity

__all__ = ["paper_material", "uniaxial_piston", "uniaxial_cylinder",
           "gravity", "PAPER_PROBES", "CYLINDER_PROBES", "SPECIMEN_X",
           "SPECIMEN_Y", "CYLINDER_DIAMETER", "CYLINDER_LENGTH",
           "PISTON_SPEED", "WAVE_VISCOSITY"]

#: Specimen extent [m]: 86 mm wide, 140 mm high.
SPECIMEN_X = (-0.043, 0.043)
SPECIMEN_Y = (0.0, 0.140)
#: The 3D laboratory specimen: a cylinder of diameter 54 mm and length
#: 135 mm (2.5 diameters, ISRM / ASTM D7012), axis along y, base at y = 0.
CYLINDER_DIAMETER = 0.054
CYLINDER_LENGTH = 0.135
#: Probes of the cylinder [m]: A at the centre and D three quarters up, on
#: the axis; B and C a quarter diameter off it (the paper's A, B, C placed
#: alike: B at 3/4 of the length, C at mid-length).
CYLINDER_PROBES = {"A": (0.0, CYLINDER_LENGTH / 2, 0.0),
                   "B": (CYLINDER_DIAMETER / 4, 0.75 * CYLINDER_LENGTH, 0.0),
                   "C": (CYLINDER_DIAMETER / 4, CYLINDER_LENGTH / 2, 0.0),
                   "D": (0.0, 0.75 * CYLINDER_LENGTH, 0.0)}
#: Piston speed [m/s] (downward).
PISTON_SPEED = 1.5e-3
#: Monaghan artificial viscosity for wave problems (on by default): with no
#: dissipation Improved Euler lets high-frequency modes grow (docs/library.md, "Dissipation for wave problems").
WAVE_VISCOSITY = {"alpha": 1.0, "beta": 0.0}
#: Damping rate [1/s] of the gravity scene (dv/dt -= rate v).
GRAVITY_DAMPING = 2000.0


def paper_material() -> Material:
    """K = 12.2 GPa, mu = 2.67 GPa, rho0 = 2300 kg/m^3."""
    return Material(K=12.2e9, mu=2.67e9, rho0=2300.0, name="paper specimen")


#: An argument not given (the preset's, or the paper's, value applies).
_UNSET = object()


def _setting(preset, viscosity, kernel, smoothing_ratio, inset):
    """The preset's setting with the arguments given explicitly on top."""
    chosen = _presets.preset(preset or "paper")
    return (chosen,
            chosen.viscosity if viscosity is _UNSET else viscosity,
            chosen.kernel if kernel is None else kernel,
            chosen.smoothing_ratio if smoothing_ratio is None
            else smoothing_ratio,
            chosen.inset if inset is None else inset)


def _walled(specimen, effects: dict, layers: int | None, piston_speed=None,
            kernel="cubic_spline", smoothing_ratio=None, inset=0.0,
            dimension=2) -> Scene:
    """The specimen in a scene, on a fixed plate and (with a piston speed)
    under a piston moving down, as the library's sph_build_paper_scene
    lays them: walls on the specimen's lattice rows, ``layers`` rows thick
    or, by default, the rows the library asks for one kernel support,
    their faces ``inset`` lattice steps inside the specimen's extent."""
    scene = Scene(dimension, [specimen], effects=effects, kernel=kernel,
                  smoothing_ratio=smoothing_ratio)
    if layers is None:
        layers = scene.support_layers(layer_spacing(specimen))
    scene.add(plate(under=specimen, layers=layers, inset=inset))
    if piston_speed is not None:
        v = (0.0, -piston_speed, 0.0)[:dimension]
        scene.add(piston(over=specimen, layers=layers, velocity=v,
                         inset=inset))
    return scene


def _effects(viscosity) -> dict:
    return {} if viscosity is None else {"artificial_viscosity":
                                         dict(viscosity)}


def uniaxial_piston(dx: float = 1e-3, velocity: float = PISTON_SPEED,
                    layers: int | None = None,
                    viscosity=_UNSET,
                    material: Material | None = None,
                    preset: str | None = None, kernel: str | None = None,
                    smoothing_ratio: float | None = None,
                    inset=None) -> Scene:
    """The paper's uniaxial piston test in 2D plane strain.

    With the defaults (``preset="paper"``) it is particle for particle the
    library's ``sph_build_paper_scene`` (plus the artificial viscosity).
    The returned scene records its preset as ``scene.preset``;
    ``presets.dynamics(scene)`` runs it with the preset's integrator.

    Parameters
    ----------
    dx : float
        Particle spacing [m] (the paper: 1 mm -> 86 x 140 = 12,040
        specimen particles).
    velocity : float
        Piston speed downward [m/s].
    layers : int, optional
        Particle rows of piston and plate; default: one kernel support
        (``Scene.support_layers``; 3 at h = 1.2 dx).
    viscosity : dict or None
        Artificial viscosity parameters (alpha, beta); None switches it off
        (default: the preset's, alpha 1 for "paper").
    material : Material, optional
        Default :func:`paper_material`.
    preset : {"paper", "waves", "fronts"}, optional
        Named setting (:mod:`sphsolid.presets`); default "paper".
    kernel, smoothing_ratio, inset : optional
        Override the preset's kernel, h/dx and platen inset (lattice steps
        or "static", see :func:`sphsolid.build.plate`).
    """
    chosen, viscosity, kernel, smoothing_ratio, inset = _setting(
        preset, viscosity, kernel, smoothing_ratio, inset)
    material = material or paper_material()
    specimen = rectangle(SPECIMEN_X, SPECIMEN_Y, dx, material, "specimen")
    scene = _walled(specimen, _effects(viscosity), layers,
                    piston_speed=_velocity(velocity, "velocity"), kernel=kernel,
                    smoothing_ratio=smoothing_ratio, inset=inset)
    scene.preset = chosen
    return scene


def uniaxial_cylinder(dx: float = 2e-3, velocity: float = PISTON_SPEED,
                      layers: int | None = None,
                      viscosity=_UNSET,
                      material: Material | None = None,
                      diameter: float = CYLINDER_DIAMETER,
                      length: float = CYLINDER_LENGTH,
                      preset: str | None = None, kernel: str | None = None,
                      smoothing_ratio: float | None = None,
                      inset=None) -> Scene:
    """The 3D uniaxial compression test of a laboratory cylinder.

    A cylinder of the paper's material, diameter 54 mm and length 135 mm,
    axis along y, between a fixed plate below and a piston moving down at
    1.5 mm/s, both bonded (particle platens, as in the paper's 2D test).
    Probes: :data:`CYLINDER_PROBES`.

    Parameters
    ----------
    dx : float
        Particle spacing [m]: 2 mm -> 577 particles per layer (of a 27 x 27
        lattice), 68 layers, 39,236 specimen particles; 1 mm -> 309,420.
    velocity : float
        Piston speed downward [m/s].
    layers : int, optional
        Layers of plate and piston (default: the least that is 2h thick).
    viscosity : dict or None
        Artificial viscosity parameters (alpha, beta); None switches it off.
    material : Material, optional
        Default :func:`paper_material`.
    diameter, length : float
        [m].
    preset, kernel, smoothing_ratio, inset : optional
        As for :func:`uniaxial_piston`.
    """
    chosen, viscosity, kernel, smoothing_ratio, inset = _setting(
        preset, viscosity, kernel, smoothing_ratio, inset)
    material = material or paper_material()
    diameter = _length(diameter, "diameter")
    specimen = cylinder(diameter / 2, length, dx, material, name="specimen")
    scene = Scene(3, [specimen], effects=_effects(viscosity), kernel=kernel,
                  smoothing_ratio=smoothing_ratio)
    scene.add(plate(under=specimen, layers=layers, inset=inset))
    scene.add(piston(over=specimen, layers=layers,
                     velocity=(0.0, -_velocity(velocity, "velocity"), 0.0),
                     inset=inset))
    scene.preset = chosen
    return scene


def gravity(dx: float = 1e-3, g: float = 9.81,
            damping: float | None = GRAVITY_DAMPING, layers: int | None = None,
            viscosity=_UNSET,
            material: Material | None = None,
            preset: str | None = None, kernel: str | None = None,
            smoothing_ratio: float | None = None, inset=None) -> Scene:
    """The specimen resting on the fixed plate under gravity (no piston).

    Parameters
    ----------
    dx : float
        Particle spacing [m].
    g : float
        Gravitational acceleration [m/s^2], acting along -y.
    damping : float or None
        Damping rate [1/s] for fast settling to the static field; None for
        none.
    layers : int, optional
        Particle rows of the plate; default: one kernel support.
    preset, kernel, smoothing_ratio, inset : optional
        As for :func:`uniaxial_piston`.
    """
    chosen, viscosity, kernel, smoothing_ratio, inset = _setting(
        preset, viscosity, kernel, smoothing_ratio, inset)
    material = material or paper_material()
    specimen = rectangle(SPECIMEN_X, SPECIMEN_Y, dx, material, "specimen")
    effects = {"gravity": {"gx": 0.0,
                           "gy": -_quantity(g, "acceleration", "g")}}
    effects.update(_effects(viscosity))
    if damping is not None:
        effects["damping"] = {"rate": _quantity(damping, "rate", "damping")}
    scene = _walled(specimen, effects, layers, kernel=kernel,
                    smoothing_ratio=smoothing_ratio, inset=inset)
    scene.preset = chosen
    return scene


# Brittle fracture scenes (the damage effect), in their own module.
from .fracture import brazilian_disc, tensile_bar, ucs  # noqa: E402

__all__ += ["ucs", "brazilian_disc", "tensile_bar"]
