"""Brittle fracture scenes: the compression test, the Brazilian disc and
the tensile bar to failure, with the library's ``damage`` effect
(docs/fracture.md) and, on request, its ``drucker_prager`` (the builders'
``plasticity``) and ``artificial_stress`` effects.

:func:`ucs` is the paper's specimen (86 mm x 140 mm, plane strain) between a
fixed plate and a piston, loaded past its peak; :func:`brazilian_disc` a
disc between flat platens, loaded until it splits; :func:`tensile_bar` a
bar pulled apart by its bonded end platens. :func:`load_to_break` runs
any of them until the specimen breaks and returns the load history and
the strength (a broken specimen is a *break*; a *failure* is the
library's numerical stop, ``sph_failure``: docs/glossary.md).

A strength is one sample of the flaw draw (the ``seed`` and the ensemble
``member``): compare ensembles over members (sphsolid.ensemble), not single
runs.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from .. import _lib
from ..builders import Velocity, disc, piston, plate, rectangle
from ..dynamics import ImprovedEuler
from ..material import Material
from ..scene import Scene

__all__ = ["ucs", "brazilian_disc", "tensile_bar", "load_to_break",
           "BreakRun", "load_to_failure", "FailureRun", "fracture_material", "UCS_STRAIN_RATE", "DISC_SPEED",
           "TENSILE_STRAIN_RATE", "TESTS", "test_scene"]

#: Axial strain rate of the compression test [1/s]: the load rises over
#: ~50 wave transits of the specimen (0.14 m / 2300 m/s = 61 us) before the
#: peak, and a run at dx = 2 mm takes well under a minute.
UCS_STRAIN_RATE = 1.0
#: Piston speed of the Brazilian disc [m/s] (the plate below is fixed).
DISC_SPEED = 0.02
#: Strain rate of the tensile bar [1/s] (each end moves at half of
#: rate x length).
TENSILE_STRAIN_RATE = 1.0
#: The artificial viscosity of the wave scenes (alpha 1).
_VISCOSITY = {"alpha": 1.0, "beta": 0.0}


def fracture_material(weibull_k: float = 1e28, weibull_m: float = 9.0,
                      name: str = "rock") -> Material:
    """The paper's rock (K = 12.2 GPa, mu = 2.67 GPa, rho0 = 2300 kg/m^3)
    with Weibull flaws: k [m^-3], m [-].

    The defaults put the strain at which a 2 mm plane-strain particle
    (V = 4e-6 m^3 per metre of depth) expects one active flaw at
    (1 / (k V))^(1/m) = 3.0e-3.
    """
    return Material(K=12.2e9, mu=2.67e9, rho0=2300.0, name=name,
                    weibull_k=weibull_k, weibull_m=weibull_m)


#: The builders' options of optional effects and the effects they switch
#: on.
OPTIONAL_EFFECTS = {"plasticity": "drucker_prager",
                    "artificial_stress": "artificial_stress"}


def _damage_effects(seed: int, flaws: float, viscosity,
                    member: int = 0, plasticity=None,
                    artificial_stress=None) -> dict:
    """The effects of a test to failure: ``damage``, the artificial
    viscosity and, when given (None: off), ``drucker_prager`` with the
    ``plasticity`` parameters and ``artificial_stress`` with its own (the
    library checks their keys and ranges)."""
    effects = {"damage": {"seed": seed, "flaws": flaws, "member": member}}
    if viscosity:
        effects["artificial_viscosity"] = dict(viscosity)
    given = {"plasticity": plasticity, "artificial_stress": artificial_stress}
    for name, effect in OPTIONAL_EFFECTS.items():
        parameters = given[name]
        if parameters is None:
            continue
        if not isinstance(parameters, Mapping):
            raise ValueError(f"{name}={parameters!r} must be a dict of the "
                             f"{effect} effect's parameters or None")
        effects[effect] = dict(parameters)
    return effects


def _fracture_watchdog(scene: Scene) -> None:
    """Damaged particles that separate expand freely (they carry no
    tension), so the watchdog's lower density bound is off; the speed and
    upper density bounds stay (1 x c_p, 2 rho0)."""
    _lib.check(_lib.lib.sph_set_watchdog(scene.handle, 1.0, 0.0, 2.0),
               scene.handle, "watchdog")


def ucs(dx: float = 2e-3, material: Material | None = None,
        strain_rate: float = UCS_STRAIN_RATE, seed: int = 1,
        flaws: float = 10.0, viscosity=_VISCOSITY,
        width: float = 0.086, height: float = 0.140,
        member: int = 0, plasticity: dict | None = None,
        artificial_stress: dict | None = None) -> Scene:
    """The uniaxial compression test to failure (2D plane strain).

    The specimen ``width`` x ``height`` [m] (the paper's 86 mm x 140 mm)
    stands on a fixed plate under a piston moving down at
    ``strain_rate * height`` [m/s], with the ``damage`` effect on.

    Parameters
    ----------
    dx : float
        Particle spacing [m].
    material : Material, optional
        Must have Weibull flaws; default :func:`fracture_material`.
    strain_rate : float
        Nominal axial strain rate [1/s].
    seed, flaws, member :
        The damage effect's parameters (the flaw draw; ``member`` is the
        ensemble member, drawn from hash(seed, member)).
    viscosity : dict or None
        Artificial viscosity (alpha, beta); None: off.
    plasticity : dict or None
        The ``drucker_prager`` effect's parameters, e.g. ``{"cohesion":
        5e6, "friction_angle": 30}`` (cohesion [Pa], required; friction
        angle [deg] in [0, 90), default 30): the pressure-dependent shear
        strength of docs/fracture.md. None (default): off.
    artificial_stress : dict or None
        The ``artificial_stress`` effect's parameters, e.g. ``{"epsilon":
        0.3}`` ({} takes the library's defaults, epsilon 0.3, n 4): the
        cure of SPH's tensile instability. None (default): off.

    The scene's ``failure`` attribute records what :func:`load_to_break`
    needs: the loaded body, the gauge length and the loaded area.
    """
    material = material or fracture_material()
    specimen = rectangle((-width / 2, width / 2), (0.0, height), dx,
                         material, "specimen")
    scene = Scene(2, [specimen],
                  effects=_damage_effects(seed, flaws, viscosity, member,
                                          plasticity, artificial_stress))
    layers = scene.support_layers(dx)
    scene.add(plate(under=specimen, layers=layers))
    scene.add(piston(over=specimen, layers=layers,
                     velocity=(0.0, -strain_rate * height)))
    _fracture_watchdog(scene)
    scene.failure = {"kind": "ucs", "piston": "piston", "length": height,
                     "speed": strain_rate * height, "area": width * 1.0,
                     "diameter": None}
    return scene


def brazilian_disc(dx: float = 1e-3, diameter: float = 0.05,
                   material: Material | None = None,
                   speed: float = DISC_SPEED, seed: int = 1,
                   flaws: float = 10.0, viscosity=_VISCOSITY,
                   member: int = 0,
                   flat_angle: float = 0.0,
                   plasticity: dict | None = None,
                   artificial_stress: dict | None = None) -> Scene:
    """The Brazilian (indirect tensile) test: a disc of ``diameter`` [m]
    (2D plane strain, 1 m deep) between a fixed flat plate and a flat
    piston moving down at ``speed`` [m/s], with the ``damage`` effect on.

    ``flat_angle`` [degrees] is the angle 2 alpha that each of the two flat
    loading ends subtends at the centre (the flattened Brazilian disc of
    Wang et al. 2004): the disc keeps its lattice points with
    |y| < R cos(alpha), and the platens are bonded to the flats. 0, the
    default, is the round disc, which touches each platen along its top
    lattice row. With the damage model's strain rule and bonded platens
    neither starts the crack at the centre (docs/fracture.md, "The
    Brazilian disc checked").

    The indirect tensile strength is 2P / (pi D t) with P the peak load
    and t the depth (1 m in 2D: P in N per metre). ``plasticity`` and
    ``artificial_stress`` as for :func:`ucs`.
    """
    if not (isinstance(flat_angle, float | int)
            and not isinstance(flat_angle, bool)
            and 0.0 <= flat_angle < 90.0):
        raise ValueError(f"brazilian_disc: flat_angle={flat_angle!r} must "
                         "be a number of degrees in [0, 90)")
    material = material or fracture_material()
    specimen = disc((0.0, 0.0), diameter / 2, dx, material, "specimen")
    if flat_angle > 0.0:
        cut = 0.5 * diameter * math.cos(math.radians(0.5 * flat_angle))
        keep = np.abs(specimen.points[:, 1]) < cut
        specimen = replace(specimen, points=specimen.points[keep])
    scene = Scene(2, [specimen],
                  effects=_damage_effects(seed, flaws, viscosity, member,
                                          plasticity, artificial_stress))
    layers = scene.support_layers(dx)
    scene.add(plate(under=specimen, layers=layers))
    scene.add(piston(over=specimen, layers=layers, velocity=(0.0, -speed)))
    _fracture_watchdog(scene)
    scene.failure = {"kind": "brazilian", "piston": "piston",
                     "length": diameter, "speed": speed, "area": None,
                     "diameter": diameter, "flat_angle": flat_angle}
    return scene


def tensile_bar(dx: float = 2e-3, material: Material | None = None,
                strain_rate: float = TENSILE_STRAIN_RATE, seed: int = 1,
                flaws: float = 10.0, viscosity=_VISCOSITY,
                width: float = 0.020, length: float = 0.080,
                member: int = 0, plasticity: dict | None = None,
                artificial_stress: dict | None = None) -> Scene:
    """The tensile bar (Benz & Asphaug 1994's test of the model), 2D plane
    strain: a ``width`` x ``length`` [m] bar (1 m deep) bonded to a plate
    below and a piston above that move apart at ``strain_rate * length / 2``
    [m/s] each, with the ``damage`` effect on.

    The strength is the peak tensile load over the cross-section
    ``width * 1 m``; the platens are one kernel support thick and bonded
    (SPH's own interaction carries the tension into them). Parameters as
    for :func:`ucs` (``plasticity``, ``artificial_stress`` too).

    The bar starts stretching everywhere at once, as Benz & Asphaug
    (1994) start theirs: its particles get the velocity
    ``strain_rate * (y - length / 2)``, the platens' at its ends, so no
    wave runs in from the ends (a platen started alone sends a stress
    jump rho c_p v, which at 100/s, v = 4 m/s, is 24 MPa: more than the
    bar's strength).
    """
    for name, value in (("strain_rate", strain_rate), ("width", width),
                        ("length", length)):
        if not (isinstance(value, float | int) and math.isfinite(value)
                and value > 0):
            raise ValueError(f"tensile_bar: {name}={value!r} must be "
                             "finite and > 0")
    material = material or fracture_material()
    specimen = rectangle((-width / 2, width / 2), (0.0, length), dx,
                         material, "specimen")
    scene = Scene(2, [specimen],
                  effects=_damage_effects(seed, flaws, viscosity, member,
                                          plasticity, artificial_stress))
    layers = scene.support_layers(dx)
    half = 0.5 * strain_rate * length
    scene.add(plate(under=specimen, layers=layers,
                    motion=Velocity((0.0, -half))))
    scene.add(piston(over=specimen, layers=layers, velocity=(0.0, half)))
    bar = scene.body_slice("specimen")
    scene.freeze()
    scene.velocities[bar, 1] = strain_rate * (
        scene.positions[bar, 1] - 0.5 * length)
    _fracture_watchdog(scene)
    scene.failure = {"kind": "tensile", "piston": "piston", "length": length,
                     "speed": strain_rate * length, "area": width * 1.0,
                     "diameter": None}
    return scene


#: The tests to failure by name (``sphsolid ucs|brazilian|tensile``, the
#: ensembles): default dx [m], strain at which a run stops if the load has
#: not dropped, load samples per unit strain.
TESTS = {"ucs": (2e-3, 0.008, 2e4), "brazilian": (1e-3, 0.02, 1e4),
         "tensile": (2e-3, 0.01, 2e4)}


def test_scene(test: str, dx: float, seed: int = 1, member: int = 0,
               **options) -> Scene:
    """The scene of test ``test`` (a key of :data:`TESTS`): :func:`ucs`,
    :func:`brazilian_disc` or :func:`tensile_bar` with the flaw draw
    (``seed``, ``member``) and the builder's keyword ``options``;
    ``weibull_k`` and ``weibull_m`` among them give the material
    :func:`fracture_material` with those flaws (plain numbers, so an
    ensemble records its options as JSON), and ``plasticity`` and
    ``artificial_stress`` (dicts of numbers) switch on those effects."""
    makers = {"ucs": ucs, "brazilian": brazilian_disc,
              "tensile": tensile_bar}
    if test not in makers:
        raise ValueError(f"test {test!r}: not one of {', '.join(makers)}")
    options = dict(options)
    weibull = {key: options.pop(key) for key in ("weibull_k", "weibull_m")
               if key in options}
    if weibull:
        if "material" in options:
            raise ValueError("test_scene: give material or weibull_k/"
                             "weibull_m, not both")
        options["material"] = fracture_material(**weibull)
    return makers[test](dx, seed=seed, member=member, **options)


@dataclass
class BreakRun:
    """The load history of a test loaded until the specimen breaks.

    Attributes
    ----------
    time, load, strain : ndarray
        Time [s], the piston's load [N; N/m in 2D, compression positive,
        tension positive for the tensile bar] and the nominal strain
        (platen travel / length).
    peak_load_N : float
        Largest load [N/m in 2D].
    strength_Pa : float
        UCS (or the tensile bar's strength) = peak load / area, or
        2P/(pi D t) for the disc (t = 1 m).
    strain_at_peak : float
    damage_onset_s : float or None
        First sample time with some D > 0.
    damage_onset_stress_Pa : float or None
        The load at that sample as a stress (as ``strength_Pa``): where
        the weakest flaw of the specimen activates.
    fragments : int
        Connected regions with D < 1 at the end.
    post_peak_ratio : float
        Load at the end over the peak (the drop after the peak).
    load_lost_before_damage : bool
        The load fell below ``drop`` times its peak while no particle was
        damaged: not fracture but a loss of load the damage model did not
        cause (in tension, SPH's tensile instability: switch on
        ``artificial_stress``); the peak is then no strength of the rock.
    """

    time: np.ndarray
    load: np.ndarray
    strain: np.ndarray
    peak_load_N: float
    strength_Pa: float
    strain_at_peak: float
    damage_onset_s: float | None
    fragments: int
    post_peak_ratio: float
    peak_time: float = 0.0
    damage_onset_stress_Pa: float | None = None
    frames: list = field(default_factory=list)
    load_lost_before_damage: bool = False

    def summary(self) -> dict:
        """The fields of ``summary.json``."""
        return {"peak_load_N": self.peak_load_N,
                "strength_Pa": self.strength_Pa,
                "strain_at_peak": self.strain_at_peak,
                "fragments": self.fragments,
                "damage_onset_s": self.damage_onset_s,
                "damage_onset_stress_Pa": self.damage_onset_stress_Pa,
                "post_peak_ratio": self.post_peak_ratio,
                "peak_time_s": self.peak_time,
                "load_lost_before_damage": self.load_lost_before_damage}


def load_to_break(scene: Scene, max_strain: float = 0.02,
                  drop: float = 0.5, samples_per_strain: float = 2e4,
                  dynamics=None, on_sample=None) -> BreakRun:
    """Load a scene of :func:`ucs`, :func:`brazilian_disc` or
    :func:`tensile_bar` until the load
    falls below ``drop`` times its peak (or the strain reaches
    ``max_strain``), sampling the piston's load.

    ``on_sample(scene, time, load, peak)`` is called at each sample (a
    place to write snapshots). The load is the piston's reaction
    (``Scene.reaction``) at the last rate evaluation of each sample.
    """
    info = getattr(scene, "failure", None)
    if info is None:
        raise ValueError("load_to_break: the scene was not built by "
                         "sphsolid.scenes.ucs, brazilian_disc or "
                         "tensile_bar")
    if not 0.0 < drop < 1.0:
        raise ValueError(f"drop must be in (0, 1), got {drop!r}")
    if not max_strain > 0.0:
        raise ValueError(f"max_strain must be > 0, got {max_strain!r}")
    dyn = dynamics or ImprovedEuler(scene, progress=False)
    length, speed = info["length"], info["speed"]
    interval = 1.0 / (samples_per_strain * speed / length)   # [s]
    steps = max(1, int(round(interval / dyn.dt)))
    times, loads, strains = [], [], []
    onset = onset_load = None
    lost = False
    peak, t0 = 0.0, dyn.time
    # the piston's reaction is pushed up (> 0) in compression, pulled
    # down in tension
    sign = -1.0 if info["kind"] == "tensile" else 1.0
    while True:
        dyn.run(steps=steps)
        t = dyn.time
        load = sign * float(scene.reaction(info["piston"])[1])
        strain = speed * (t - t0) / length
        times.append(t)
        loads.append(load)
        strains.append(strain)
        if onset is None and float(scene.damage.max()) > 0.0:
            onset, onset_load = t, load
        peak = max(peak, load)
        if onset is None and peak > 0 and load < drop * peak:
            lost = True
        if on_sample is not None:
            on_sample(scene, t, load, peak)
        if strain >= max_strain or (peak > 0 and load < drop * peak
                                    and onset is not None):
            break
    time = np.asarray(times)
    load = np.asarray(loads)
    strain = np.asarray(strains)
    k = int(np.argmax(load))
    peak = float(load[k])
    def stress(load):
        if info["kind"] in ("ucs", "tensile"):
            return load / info["area"]
        return 2.0 * load / (math.pi * info["diameter"] * 1.0)
    strength = stress(peak)
    fragments = scene.fragments
    return BreakRun(time=time, load=load, strain=strain,
                    peak_load_N=peak, strength_Pa=strength,
                    strain_at_peak=float(strain[k]),
                    damage_onset_s=onset,
                    fragments=int(fragments.max() + 1)
                    if fragments.size else 0,
                    post_peak_ratio=float(load[-1] / peak) if peak else 0.0,
                    peak_time=float(time[k]),
                    damage_onset_stress_Pa=(None if onset_load is None
                                            else stress(onset_load)),
                    load_lost_before_damage=lost)


#: Deprecated name of :class:`BreakRun` (0.2 series), removed in 0.3.0.
FailureRun = BreakRun


def load_to_failure(*args, **kwargs) -> BreakRun:
    """Deprecated name of :func:`load_to_break` (0.2 series), removed in
    0.3.0: "failure" names the library's numerical stop."""
    import warnings
    warnings.warn("sphsolid.fracture.load_to_failure is load_to_break "
                  "(removed in 0.3.0)", DeprecationWarning, stacklevel=2)
    return load_to_break(*args, **kwargs)
