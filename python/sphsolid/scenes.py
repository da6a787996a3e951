"""The paper's scenes, ready to run (Das & Cleary, uniaxial compression).

:func:`uniaxial_piston` is the default scene everywhere: an 86 mm x 140 mm
specimen between a fixed plate and a piston moving down at 1.5 mm/s.
:func:`gravity` is the same specimen resting on the plate under gravity,
with damping so the static, height-graded stress is reached fast.
"""
from __future__ import annotations

from .build import cylinder, layer_spacing, piston, plate, rectangle
from .material import Material
from .probes import PAPER_PROBES
from .scene import Scene

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


def _walled(specimen, effects: dict, layers: int | None, piston_speed=None) -> Scene:
    """The specimen in a scene, on a fixed plate and (with a piston speed)
    under a piston moving down, as the library's sph_build_paper_scene
    lays them: walls on the specimen's lattice rows, ``layers`` rows thick
    or, by default, the rows the library asks for one kernel support."""
    scene = Scene(2, [specimen], effects=effects)
    if layers is None:
        layers = scene.support_layers(layer_spacing(specimen))
    scene.add(plate(under=specimen, layers=layers))
    if piston_speed is not None:
        scene.add(piston(over=specimen, layers=layers,
                         velocity=(0.0, -piston_speed)))
    return scene


def uniaxial_piston(dx: float = 1e-3, velocity: float = PISTON_SPEED,
                    layers: int | None = None,
                    viscosity: dict | None = WAVE_VISCOSITY,
                    material: Material | None = None) -> Scene:
    """The paper's uniaxial piston test in 2D plane strain.

    With the defaults it is particle for particle the library's
    ``sph_build_paper_scene`` (plus the artificial viscosity).

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
        Artificial viscosity parameters (alpha, beta); None switches it off.
    material : Material, optional
        Default :func:`paper_material`.
    """
    material = material or paper_material()
    specimen = rectangle(SPECIMEN_X, SPECIMEN_Y, dx, material, "specimen")
    effects = {}
    if viscosity is not None:
        effects["artificial_viscosity"] = dict(viscosity)
    return _walled(specimen, effects, layers, piston_speed=velocity)


def uniaxial_cylinder(dx: float = 2e-3, velocity: float = PISTON_SPEED,
                      layers: int | None = None,
                      viscosity: dict | None = WAVE_VISCOSITY,
                      material: Material | None = None,
                      diameter: float = CYLINDER_DIAMETER,
                      length: float = CYLINDER_LENGTH) -> Scene:
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
    """
    material = material or paper_material()
    specimen = cylinder(diameter / 2, length, dx, material, name="specimen")
    effects = {}
    if viscosity is not None:
        effects["artificial_viscosity"] = dict(viscosity)
    return Scene(3, [specimen,
                     plate(under=specimen, layers=layers),
                     piston(over=specimen, layers=layers,
                            velocity=(0.0, -velocity, 0.0))],
                 effects=effects)


def gravity(dx: float = 1e-3, g: float = 9.81,
            damping: float | None = GRAVITY_DAMPING, layers: int | None = None,
            viscosity: dict | None = WAVE_VISCOSITY,
            material: Material | None = None) -> Scene:
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
    """
    material = material or paper_material()
    specimen = rectangle(SPECIMEN_X, SPECIMEN_Y, dx, material, "specimen")
    effects = {"gravity": {"gx": 0.0, "gy": -float(g)}}
    if viscosity is not None:
        effects["artificial_viscosity"] = dict(viscosity)
    if damping is not None:
        effects["damping"] = {"rate": float(damping)}
    return _walled(specimen, effects, layers)
