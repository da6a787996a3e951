"""The project's reference scenes for ``sphsolid plan NAME``."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from .settings import MANAGED_EFFECTS



# ------------------------------------------------ the project's scenes
def _platens(scene, body, speed: float | None, inset):
    """A fixed plate under ``body`` and a piston moving down at ``speed``
    over it (default the paper's), in ``scene``, each as many rows thick
    as the library asks for one kernel support on the body's lattice
    rows (``Scene.support_layers``)."""
    from .. import builders as build, scenes
    layers = scene.support_layers(build.layer_spacing(body))
    v = scenes.PISTON_SPEED if speed is None else speed
    scene.add(build.plate(under=body, layers=layers, inset=inset))
    scene.add(build.piston(over=body, layers=layers, velocity=(0.0, -v),
                           inset=inset))
    return scene


def _between_platens(body, smoothing_ratio: float, kernel: str,
                     speed: float | None, inset, **scene_options):
    """``body`` between a fixed plate and a piston (:func:`_platens`) in a
    2D scene with the planner's h/dx and kernel."""
    from ..scene import Scene
    scene = Scene(2, [body], smoothing_ratio=smoothing_ratio, kernel=kernel,
                  **scene_options)
    return _platens(scene, body, speed, inset)


def piston_factory(dx: float, smoothing_ratio: float = 1.2,
                   kernel: str = "cubic_spline",
                   speed: float | None = None, inset: float | str = 0.0,
                   material=None, extent=None):
    """The paper's piston scene (:func:`sphsolid.scenes.uniaxial_piston`)
    with the planner's h/dx, kernel and end placement (``inset``, see
    :func:`sphsolid.build.plate`) and no optional effect; plate and
    piston one kernel support thick (the library's rows). ``material``
    replaces the paper's rock, ``extent`` ((x0, x1), (y0, y1)) [m] its
    specimen."""
    from .. import builders as build, scenes
    rock = scenes.paper_material() if material is None else material
    xs, ys = ((scenes.SPECIMEN_X, scenes.SPECIMEN_Y) if extent is None
              else extent)
    specimen = build.rectangle(xs, ys, dx, rock, "specimen")
    return _between_platens(specimen, smoothing_ratio, kernel, speed, inset)


def nearly_incompressible_material():
    """The paper's shear modulus with Poisson's ratio 0.45 (K = 25.8 GPa,
    c_p = 3573 m/s): a held-out scene of the verification record."""
    from ..material import Material
    mu, nu = 2.67e9, 0.45
    return Material(K=2.0 * mu * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu)),
                    mu=mu, rho0=2300.0, name="nu = 0.45")


def piston_nu045_factory(dx: float, smoothing_ratio: float = 1.2,
                         kernel: str = "cubic_spline",
                         inset: float | str = 0.0):
    """:func:`piston_factory` with :func:`nearly_incompressible_material`."""
    return piston_factory(dx, smoothing_ratio, kernel, inset=inset,
                          material=nearly_incompressible_material())


def _rock(E: float, nu: float, rho0: float, name: str):
    """The elastic material of Young's modulus E [Pa] and Poisson's ratio
    nu (K = E / (3 (1 - 2 nu)), mu = E / (2 (1 + nu)))."""
    from ..material import Material
    return Material(K=E / (3.0 * (1.0 - 2.0 * nu)), mu=E / (2.0 * (1.0 + nu)),
                    rho0=rho0, name=name)


def squat_material():
    """A softer, lighter rock than the paper's (E = 10 GPa, nu = 0.25,
    rho0 = 2200 kg/m^3: K = 6.67 GPa, mu = 4 GPa, c_p = 2335 m/s): the
    squat piston scene's, held out of the verification record."""
    return _rock(10e9, 0.25, 2200.0, "squat specimen")


#: The squat piston scene: a 100 mm x 100 mm specimen, the piston at twice
#: the paper's speed, probes off the axis and near the ends.
SQUAT_EXTENT = ((-0.05, 0.05), (0.0, 0.1))
SQUAT_SPEED = 3e-3
SQUAT_PROBES = {"D": (0.0, 0.025), "E": (0.03, 0.05), "F": (-0.035, 0.08)}
SQUAT_UNTIL = 0.25e-3


def piston_squat_factory(dx: float, smoothing_ratio: float = 1.2,
                         kernel: str = "cubic_spline",
                         inset: float | str = 0.0):
    """:func:`piston_factory` with another material
    (:func:`squat_material`), shape (:data:`SQUAT_EXTENT`) and piston
    speed (:data:`SQUAT_SPEED`): a held-out scene of the verification
    record."""
    return piston_factory(dx, smoothing_ratio, kernel, speed=SQUAT_SPEED,
                          inset=inset, material=squat_material(),
                          extent=SQUAT_EXTENT)


def slender_material():
    """A stiffer, denser rock than the paper's (E = 50 GPa, nu = 0.2,
    rho0 = 2650 kg/m^3: K = 27.8 GPa, mu = 20.8 GPa, c_p = 4578 m/s): the
    slender piston scene's, held out of the verification record."""
    return _rock(50e9, 0.2, 2650.0, "slender specimen")


#: The slender piston scene: a 40 mm x 120 mm specimen of a stiff rock,
#: the piston at two thirds of the paper's speed, probes near the free
#: sides (8 and 5 mm from them) and the ends.
SLENDER_EXTENT = ((-0.02, 0.02), (0.0, 0.12))
SLENDER_SPEED = 1e-3
SLENDER_PROBES = {"G": (0.0, 0.03), "H": (0.012, 0.07), "I": (-0.015, 0.105)}
SLENDER_UNTIL = 0.2e-3


def piston_slender_factory(dx: float, smoothing_ratio: float = 1.2,
                           kernel: str = "cubic_spline",
                           inset: float | str = 0.0):
    """:func:`piston_factory` with :func:`slender_material`, the shape
    :data:`SLENDER_EXTENT` and the piston speed :data:`SLENDER_SPEED`: a
    held-out scene of the verification record."""
    return piston_factory(dx, smoothing_ratio, kernel, speed=SLENDER_SPEED,
                          inset=inset, material=slender_material(),
                          extent=SLENDER_EXTENT)


def gravity_factory(dx: float, smoothing_ratio: float = 1.2,
                    kernel: str = "cubic_spline", g: float = 9.81,
                    inset: float | str = 0.0):
    """The paper's gravity scene: the specimen on the fixed plate under
    gravity, with no optional effect (the planner finds what it needs)."""
    from .. import builders as build, scenes
    from ..scene import Scene
    rock = scenes.paper_material()
    specimen = build.rectangle(scenes.SPECIMEN_X, scenes.SPECIMEN_Y, dx, rock,
                               "specimen")
    scene = Scene(2, [specimen],
                  effects={"gravity": {"gx": 0.0, "gy": -float(g)}},
                  smoothing_ratio=smoothing_ratio, kernel=kernel)
    layers = scene.support_layers(build.layer_spacing(specimen))
    scene.add(build.plate(under=specimen, layers=layers, inset=inset))
    return scene


#: Laterally periodic strip under the piston: height [m] and width in dx.
STRIP_HEIGHT, STRIP_WIDTH_DX = 0.1, 8


def cylinder_factory(dx: float, smoothing_ratio: float = 1.2,
                     kernel: str = "cubic_spline",
                     inset: float | str = 0.0):
    """The 3D laboratory cylinder (:func:`sphsolid.scenes.uniaxial_cylinder`:
    54 x 135 mm, the paper's rock, the piston at 1.5 mm/s) with the
    planner's h/dx, kernel and end placement and no optional effect."""
    from .. import scenes
    return scenes.uniaxial_cylinder(dx, viscosity=None, kernel=kernel,
                                    smoothing_ratio=smoothing_ratio,
                                    inset=inset)


#: the cylinder's end time and the start of its slope fit [s]: the
#: window of the 3D validation (docs/validation/cylinder_3d), where
#: sigma_yy at the centre rises at the quasi-static slope
CYLINDER_UNTIL, CYLINDER_SLOPE_FROM = 1.5e-3, 0.75e-3


class CentreSlope:
    """``probes(scene) -> {"slope": s}``: the least-squares slope [Pa/s]
    of sigma_yy at the cylinder's centre over the samples from ``start``
    [s] to now (0 before two samples), the quantity the 3D validation
    compares with the finite-element quasi-static slope. Its running
    sums are kept per scene."""

    def __init__(self, start: float = CYLINDER_SLOPE_FROM):
        import weakref
        self.start = start
        self._sums = weakref.WeakKeyDictionary()

    def __call__(self, scene) -> dict:
        from .. import scenes
        from ..probes import Probes
        state = self._sums.get(scene)
        if state is None:
            probes = Probes(scene, {"centre": (
                0.0, 0.5 * scenes.CYLINDER_LENGTH, 0.0)})
            state = self._sums[scene] = (
                probes, probes.values.index("sigma_yy"), np.zeros(5))
        probes, column, sums = state
        t = scene.time
        if t >= self.start:
            value = float(probes._sample_array()[0, column])
            sums += (1.0, t, value, t * t, t * value)
        n, st, sv, stt, stv = sums
        spread = n * stt - st * st
        return {"slope": (n * stv - st * sv) / spread
                if n >= 2 and spread > 0 else 0.0}


def strip_factory(dx: float, smoothing_ratio: float = 1.2,
                  kernel: str = "cubic_spline", speed: float | None = None,
                  inset: float | str = 0.0):
    """A laterally periodic strip (the paper's material, 100 mm high, 8 dx
    wide) on a fixed plate, hit by the piston at t = 0: a plane P-wave with
    the exact stress jump -rho0 c_p v behind a front at y = H - c_p t."""
    from .. import builders as build, scenes
    rock = scenes.paper_material()
    width = STRIP_WIDTH_DX * dx
    strip = build.rectangle((-width / 2, width / 2), (0.0, STRIP_HEIGHT), dx,
                            rock, name="strip")
    # the domain reaches past the platens: their rows are the library's
    # answer for this kernel and h/dx, asked of a scene of the strip alone
    from ..scene import Scene
    layers = Scene(2, [build.rectangle(
        (-width / 2, width / 2), (0.0, STRIP_HEIGHT), dx, rock, name="strip")],
        smoothing_ratio=smoothing_ratio, kernel=kernel).support_layers(
            build.layer_spacing(strip))
    return _between_platens(
        strip, smoothing_ratio, kernel, speed, inset,
        domain=((-width / 2, -layers * dx - 0.01),
                (width / 2, STRIP_HEIGHT + layers * dx + 0.01)),
        periodic=(True, False))


def strip_tension_factory(dx: float, smoothing_ratio: float = 1.2,
                          kernel: str = "cubic_spline",
                          speed: float | None = None,
                          inset: float | str = 0.0):
    """The strip of :func:`strip_factory` pulled: the piston moves up at
    ``speed`` (default the paper's piston speed), and a plane P-wave in
    tension, of exact stress jump +rho0 c_p v, runs down behind a front at
    y = H - c_p t (linear elasticity: the compressive front's mirror)."""
    from .. import scenes
    v = scenes.PISTON_SPEED if speed is None else speed
    return strip_factory(dx, smoothing_ratio, kernel, -v, inset)


#: Probe points of the strip [m] (on the axis, a quarter, half and three
#: quarters down).
STRIP_PROBES = {"y75": (0.0, 0.075), "y50": (0.0, 0.050),
                "y25": (0.0, 0.025)}
#: Heights [m] of the gravity column's section means.
GRAVITY_SECTIONS = {"y35": 0.035, "y70": 0.070, "y105": 0.105}


def gravity_sections(scene) -> dict:
    """Mean sigma_yy [Pa] over the specimen's section at each height of
    :data:`GRAVITY_SECTIONS` (the section carries the weight above it:
    exactly -rho0 g (H - y) at rest, whatever the base does).

    The section between two particle rows is represented by the mean of
    the two rows that meet there, interpolated linearly in y between the
    cuts that bracket the height. The static SPH field carries a row-to-row
    alternation of the row means (+-1 to 5 % of the weight at mid-height on
    the cubic spline at h/dx 1.2, growing towards the free top): the
    kernel-sum divergence of the stress does not see a mode that alternates
    from row to row, so equilibrium leaves it undetermined. The mean of two
    neighbouring rows cancels it, as the force carried across the cut (a
    sum over pairs with one particle on each side) does; the mean of one
    row, or an interpolation between single rows, picks up a share of it
    that jumps with where the height falls between rows (errors of 8, 1,
    4, 1, 3 % at 8, 6, 4, 3, 2 mm instead of a convergence)."""
    part = scene.body_slice("specimen")
    y = scene.positions[part, 1]
    s_yy = scene.stress[part, 1]
    tolerance = 1e-3 * (scene.h or 1.0)
    order = np.argsort(y)
    y, s_yy = y[order], s_yy[order]
    starts = np.concatenate(([0], np.nonzero(np.diff(y) > tolerance)[0] + 1))
    counts = np.diff(np.append(starts, len(y)))
    rows_y = np.add.reduceat(y, starts) / counts
    rows_s = np.add.reduceat(s_yy, starts) / counts
    cuts_y = 0.5 * (rows_y[1:] + rows_y[:-1])
    cuts_s = 0.5 * (rows_s[1:] + rows_s[:-1])
    return {name: float(np.interp(height, cuts_y, cuts_s))
            for name, height in GRAVITY_SECTIONS.items()}


@dataclass
class PlanScene:
    """A named scene for ``sphsolid plan NAME``: factory, probes, quantity,
    the default window, calibration ladder and end time."""
    factory: Callable
    probes: object
    quantity: str
    ladder: tuple
    until: float
    window: Callable | None = None     # until -> (t0, t1)
    description: str = ""


def project_scenes() -> dict:
    from ..probes import PAPER_PROBES
    from ..scenes import paper_material
    # the strip's window ends before the front reaches the plate
    strip_until = 0.95 * STRIP_HEIGHT / paper_material().c_p
    return {
        "piston": PlanScene(piston_factory, PAPER_PROBES, "von_mises",
                            (3e-3, 2e-3, 1.5e-3), 0.3e-3,
                            description="the paper's piston test, von Mises "
                            "at A, B, C"),
        "piston_nu045": PlanScene(piston_nu045_factory, PAPER_PROBES,
                                  "von_mises", (3e-3, 2e-3, 1.5e-3), 0.3e-3,
                                  description="the piston test with a "
                                  "nearly incompressible material (nu = "
                                  "0.45), von Mises at A, B, C"),
        "piston_squat": PlanScene(piston_squat_factory, SQUAT_PROBES,
                                  "von_mises", (3e-3, 2e-3, 1.5e-3),
                                  SQUAT_UNTIL,
                                  description="a squat specimen of a "
                                  "softer rock under a faster piston, von "
                                  "Mises at D, E, F"),
        "piston_slender": PlanScene(piston_slender_factory, SLENDER_PROBES,
                                    "von_mises", (3e-3, 2e-3, 1.5e-3),
                                    SLENDER_UNTIL,
                                    description="a slender specimen of a "
                                    "stiff rock under a slower piston, von "
                                    "Mises at G, H, I"),
        "gravity": PlanScene(gravity_factory, gravity_sections, "sigma_yy",
                             (8e-3, 6e-3, 4e-3, 3e-3), 2.5e-3,
                             window=lambda until: (0.5 * until, until),
                             description="the specimen settling under "
                             "gravity: section means of sigma_yy at y = 35, "
                             "70, 105 mm over the second half of the run "
                             "(damped at c_p/L, the waves have decayed by "
                             "e^-12 at its start)"),
        "cylinder": PlanScene(cylinder_factory, CentreSlope(), "sigma_yy",
                              (9e-3, 6e-3, 4.5e-3), CYLINDER_UNTIL,
                              window=lambda until: (until - 20e-6, until),
                              description="the 3D laboratory cylinder: the "
                              "least-squares slope of sigma_yy at its "
                              "centre from 0.75 ms to the end (its value "
                              "over the last 20 us)"),
        "strip": PlanScene(strip_factory, STRIP_PROBES, "sigma_yy",
                           (2e-3, 1.4e-3, 1e-3, 0.7e-3), strip_until,
                           description="laterally periodic strip hit by the "
                           "piston, sigma_yy at y = 75, 50, 25 mm"),
        "strip_tension": PlanScene(strip_tension_factory, STRIP_PROBES,
                                   "sigma_yy", (2e-3, 1.4e-3, 1e-3, 0.7e-3),
                                   strip_until,
                                   description="the strip pulled by the "
                                   "piston: a plane wave in tension, "
                                   "sigma_yy at y = 75, 50, 25 mm"),
    }


def scene_file(path, probes=None, quantity: str = "von_mises") -> PlanScene:
    """A scene file (``sphsolid run SCENE.toml``) as a planner scene: the
    factory rebuilds the file's bodies at the planned spacing (every
    body's ``dx`` scaled by one factor, so their ratios are kept), h/dx,
    kernel and plate/piston inset, without the effects the planner
    manages; the probes are the file's ``[probes]`` (those named in
    ``probes``, or all); the ladder is 2, 1.4 and 1 times the file's
    finest ``dx``; the end time is the file's ``until``."""
    import copy

    from ..io import scenefile
    from ..units import length
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"scene file {str(path)!r}: "
                         + ("is a directory" if path.is_dir() else
                            "no such file"))
    data = scenefile._toml(path)
    loaded = scenefile.SceneFile(path)       # every key checked once
    points = dict(loaded.probe_points)
    if not points:
        raise ValueError(f"{path}: the planner measures its error at probes:"
                         " the file has no [probes]")
    if probes:
        missing = [p for p in probes if p not in points]
        if missing:
            raise ValueError(f"{path}: no probe {', '.join(missing)} in "
                             f"[probes] (defined: {', '.join(points)})")
        points = {p: points[p] for p in probes}
    if loaded.until is None:
        raise ValueError(f"{path}: no end time: give until = \"...\" in the "
                         "file")
    spacings = [length(b["dx"], f"{path}: dx") for b in data["bodies"]
                if isinstance(b, dict) and "dx" in b]
    finest = min(spacings)
    managed = set(MANAGED_EFFECTS)

    def factory(dx: float, smoothing_ratio: float = 1.2,
                kernel: str = "cubic_spline", inset: float | str = 0.0):
        copy_ = copy.deepcopy(data)
        for body in copy_["bodies"]:
            if "dx" in body:
                body["dx"] = length(body["dx"], "dx") * dx / finest
            if body.get("shape") in ("plate", "piston"):
                # the setting's end placement, as its kernel and h/dx: a
                # file's inset = "static" has no solution for some of the
                # kernels the planner tries
                body["inset"] = inset
        copy_["smoothing_ratio"] = smoothing_ratio
        copy_["kernel"] = kernel
        copy_["effects"] = {k: v for k, v in copy_.get("effects", {}).items()
                            if k not in managed}
        built = scenefile.SceneFile.__new__(scenefile.SceneFile)
        built.path = path
        built._build(copy_, str(path))
        return built.scene
    return PlanScene(factory, points, quantity,
                     (2.0 * finest, 1.4 * finest, finest), loaded.until,
                     description=f"the scene file {path}")
