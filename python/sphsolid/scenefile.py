"""Scenes from a file: ``sphsolid run scene.toml``.

A TOML file describes bodies (made by the builders of :mod:`sphsolid.build`
with their materials and motions), effects, probes, outputs and the end
time. Lengths, times, velocities, pressures and forces take unit strings
(``"2mm"``, ``"0.3ms"``, ``"1.5mm/s"``, ``"12.2GPa"``) or SI numbers::

    # pull.toml: a block pulled upward by a piston glued on its top
    dimension = 2
    until = "0.1ms"

    [materials.rock]
    K = "12.2GPa"
    mu = "2.67GPa"
    rho0 = 2300

    [[bodies]]
    name = "block"
    shape = "block"              # block, rectangle, box, disc, ring, cylinder, prism, plate, piston
    lo = ["-20mm", "0mm"]
    hi = ["20mm", "60mm"]
    dx = "2mm"
    material = "rock"            # default motion: free

    [[bodies]]
    name = "base"
    shape = "plate"              # layers under a block, fixed by default
    under = "block"

    [[bodies]]
    name = "puller"
    shape = "piston"             # layers on top of a block
    over = "block"
    motion = { velocity = [0, "0.5m/s"] }

    [effects]
    artificial_viscosity = { alpha = 1, beta = 0 }

    [probes]
    centre = ["0mm", "30mm"]

    [output]
    file = "pull.h5"             # relative to the output folder
    snapshot_every = "0.025ms"   # or snapshot_interval = <steps>
    probe_interval = 10          # steps

Top-level keys: ``dimension`` (2 or 3, default 2), ``until`` (end time,
required unless given on the command line), ``dt``, ``integrator``
(``"improved_euler"``, the default, or ``"leapfrog"``), ``smoothing_ratio``,
``kernel``, ``domain`` (``{lo = [...], hi = [...], periodic = [...]}``).

Bodies: ``name``, ``shape`` and the builder's own arguments (``lo``/``hi``
for ``block``; ``x``/``y`` for ``rectangle``; ``x``/``y``/``z`` for
``box``; ``center``/``radius`` for ``disc``; ``center``/``r_inner``/
``r_outer`` for ``ring``; ``radius``/``length`` and optional ``base``
for ``cylinder`` (3D, axis along y); ``width``/``depth``/``height`` and
optional ``base`` for ``prism`` (3D); ``under`` or ``over`` (a body named
before) and optional ``layers`` and ``inset`` (lattice steps closer to
the body, or ``"static"``: ``build.plate``) for ``plate`` and
``piston``), ``dx`` (not for a plate or
piston: it takes its body's lattice), ``material`` (a name from ``[materials]``, or an
inline table of ``rho0`` and K/mu, E/nu or K/nu), ``velocity`` (initial,
free bodies) and ``motion``: ``"free"``, ``"fixed"``, ``{velocity = [..]}``,
``{force = [..]}``, ``{pressure = "1MPa", direction = [0, -1]}`` or
``{omega = .., centre = [..]}`` (rotation).

Everything else is checked: an unknown key or shape is an error naming it.
"""
from __future__ import annotations

import math
import sys
import time as wallclock
from pathlib import Path

from . import build
from .material import Material
from .units import length, quantity, time, to_si

__all__ = ["load", "SceneFile", "run_file"]

_TOP = {"dimension", "until", "dt", "integrator", "smoothing_ratio", "kernel", "domain",
        "materials", "bodies", "effects", "probes", "output", "title"}
_OUTPUT = {"file", "snapshot_every", "snapshot_interval", "probe_interval",
           "probes_csv", "figures"}
_SHAPES = {
    "block": {"lo", "hi", "dx"},
    "rectangle": {"x", "y", "dx"},
    "box": {"x", "y", "z", "dx"},
    "disc": {"center", "radius", "dx"},
    "ring": {"center", "r_inner", "r_outer", "dx"},
    "cylinder": {"radius", "length", "dx"},
    "prism": {"width", "depth", "height", "dx"},
    "plate": {"under"},
    "piston": {"over"},
}
#: Keys a shape may give and need not.
_OPTIONAL = {"cylinder": {"base"}, "prism": {"base"},
             "plate": {"layers", "inset"}, "piston": {"layers", "inset"}}
_COMMON = {"name", "shape", "material", "motion", "velocity"}


class SceneFileError(ValueError):
    """A scene file that does not describe a scene (names file and key)."""


def _toml(path: Path) -> dict:
    if sys.version_info >= (3, 11):
        import tomllib
    else:                                       # pragma: no cover
        import tomli as tomllib
    try:
        with open(path, "rb") as handle:
            return tomllib.load(handle)
    except tomllib.TOMLDecodeError as error:
        raise SceneFileError(f"{path}: not valid TOML: {error}") from None


def _unknown(where: str, given, known) -> None:
    extra = sorted(set(given) - set(known))
    if extra:
        raise SceneFileError(f"{where}: unknown key(s) {', '.join(extra)} "
                             f"(known: {', '.join(sorted(known))})")


class SceneFile:
    """A scene file read and built: ``scene``, ``probes`` (points),
    ``until``, ``dt`` and the ``output`` settings."""

    def __init__(self, path):
        self.path = Path(path)
        if not self.path.is_file():
            raise OSError(f"scene file {str(self.path)!r}: no such file")
        data = _toml(self.path)
        try:
            self._build(data, str(self.path))
        except SceneFileError:
            raise
        except ValueError as error:       # a value's own check, named
            raise SceneFileError(f"{self.path}: {error}") from None

    def _build(self, data: dict, name: str) -> None:
        _unknown(name, data, _TOP)
        self.title = data.get("title", self.path.stem)
        self.dimension = data.get("dimension", 2)
        self.until = (time(data["until"], f"{name}: until")
                      if "until" in data else None)
        self.dt = time(data["dt"], f"{name}: dt") if "dt" in data else None
        self.integrator = data.get("integrator", "improved_euler")
        self.materials = {
            key: self._material(value, f"{name}: [materials.{key}]")
            for key, value in data.get("materials", {}).items()}
        bodies = data.get("bodies", [])
        if not bodies:
            raise SceneFileError(f"{name}: no [[bodies]]")
        self.bodies = []
        for k, spec in enumerate(bodies):
            self.bodies.append(self._body(spec, f"{name}: [[bodies]] #{k + 1}"))
        self.effects = {}
        for effect, parameters in data.get("effects", {}).items():
            if not isinstance(parameters, dict):
                raise SceneFileError(f"{name}: [effects] {effect} must be a "
                                     f"table of parameters, got {parameters!r}")
            self.effects[effect] = {
                key: quantity(value, None, f"{name}: effects.{effect}.{key}")
                for key, value in parameters.items()}
        self.probe_points = {
            probe: to_si(point, "length", f"{name}: probes.{probe}")
            for probe, point in data.get("probes", {}).items()}
        output = dict(data.get("output", {}))
        _unknown(f"{name}: [output]", output, _OUTPUT)
        self.output = output
        domain = data.get("domain")
        kwargs = {}
        if domain is not None:
            _unknown(f"{name}: domain", domain, {"lo", "hi", "periodic"})
            kwargs["domain"] = (to_si(domain["lo"], "length", "domain.lo"),
                                to_si(domain["hi"], "length", "domain.hi"))
            if "periodic" in domain:
                kwargs["periodic"] = domain["periodic"]
        from .scene import Scene
        try:
            self.scene = Scene(self.dimension, self.bodies,
                               effects=self.effects,
                               smoothing_ratio=data.get("smoothing_ratio"),
                               kernel=data.get("kernel", "cubic_spline"),
                               **kwargs)
        except ValueError as error:
            raise SceneFileError(f"{name}: {error}") from None

    def _material(self, spec, where) -> Material:
        if not isinstance(spec, dict):
            raise SceneFileError(f"{where}: a material is a table of rho0 and "
                                 f"K/mu, E/nu or K/nu, got {spec!r}")
        _unknown(where, spec, {"rho0", "K", "mu", "E", "nu", "name"})
        kinds = {"rho0": "density", "K": "pressure", "mu": "pressure",
                 "E": "pressure", "nu": None}
        values = {key: quantity(value, kinds[key], f"{where} {key}")
                  for key, value in spec.items() if key != "name"}
        try:
            return Material(name=spec.get("name", ""), **values)
        except (TypeError, ValueError) as error:
            raise SceneFileError(f"{where}: {error}") from None

    def _body(self, spec, where):
        if not isinstance(spec, dict):
            raise SceneFileError(f"{where}: a body is a table")
        shape = spec.get("shape")
        if shape not in _SHAPES:
            raise SceneFileError(f"{where}: shape must be one of "
                                 f"{', '.join(sorted(_SHAPES))}, got {shape!r}")
        _unknown(f"{where} ({shape})", spec,
                 _SHAPES[shape] | _OPTIONAL.get(shape, set()) | _COMMON)
        if "name" not in spec:
            raise SceneFileError(f"{where}: every body needs a name")
        name = spec["name"]
        where = f"{where} {name!r}"
        kwargs = {"name": name}
        if "material" in spec:
            material = spec["material"]
            if isinstance(material, str):
                if material not in self.materials:
                    raise SceneFileError(
                        f"{where}: no material {material!r} in [materials] "
                        f"(defined: {', '.join(self.materials) or 'none'})")
                kwargs["material"] = self.materials[material]
            else:
                kwargs["material"] = self._material(material, f"{where} material")
        elif shape not in ("plate", "piston"):
            raise SceneFileError(f"{where}: needs a material")
        if "motion" in spec:
            kwargs["motion"] = self._motion(spec["motion"], where)
        if "velocity" in spec:
            kwargs["velocity"] = spec["velocity"]
        if "dx" in spec and shape in ("plate", "piston"):
            raise SceneFileError(f"{where}: a {shape} takes the lattice of the "
                                 "body it sits against; remove dx")
        if "dx" in spec:
            kwargs["dx"] = length(spec["dx"], f"{where} dx")
        try:
            if shape in ("plate", "piston"):
                key = "under" if shape == "plate" else "over"
                other = spec.get(key)
                found = [b for b in self.bodies if b.name == other]
                if not found:
                    raise SceneFileError(
                        f"{where}: {key} must name a body defined before it, "
                        f"got {other!r}")
                if "velocity" in kwargs:
                    raise SceneFileError(f"{where}: a {shape} moves by its "
                                         "motion, not an initial velocity")
                for key in ("layers", "inset"):
                    if key in spec:
                        kwargs[key] = spec[key]
                builder = build.plate if shape == "plate" else build.piston
                return builder(found[0], **kwargs)
            if "dx" not in kwargs:
                raise SceneFileError(f"{where}: needs dx")
            geometry = {key: spec[key]
                        for key in (_SHAPES[shape] | _OPTIONAL.get(shape, set())) - {"dx"}
                        if key in spec}
            missing = _SHAPES[shape] - {"dx"} - set(geometry)
            if missing:
                raise SceneFileError(f"{where}: needs {', '.join(sorted(missing))}")
            return getattr(build, shape)(**geometry, **kwargs)
        except (TypeError, ValueError) as error:
            if isinstance(error, SceneFileError):
                raise
            raise SceneFileError(f"{where}: {error}") from None

    @staticmethod
    def _motion(spec, where):
        if spec in ("free", "fixed"):
            return spec
        if not isinstance(spec, dict):
            raise SceneFileError(f"{where}: motion must be \"free\", \"fixed\" "
                                 f"or a table, got {spec!r}")
        keys = set(spec)
        if keys == {"velocity"}:
            return build.Velocity(tuple(spec["velocity"]))
        if keys == {"force"}:
            return build.Force(tuple(spec["force"]))
        if keys <= {"pressure", "direction"} and "pressure" in keys:
            return build.Pressure(spec["pressure"],
                                  tuple(spec.get("direction", (0.0, -1.0))))
        if keys == {"omega", "centre"}:
            omega = spec["omega"]
            omega = (quantity(omega, "angular velocity", f"{where} omega")
                     if not isinstance(omega, list) else
                     tuple(quantity(w, "angular velocity", f"{where} omega")
                           for w in omega))
            return build.Rotation(omega, to_si(spec["centre"], "length",
                                               f"{where} centre"))
        raise SceneFileError(
            f"{where}: motion table must be {{velocity = [..]}}, "
            "{force = [..]}, {pressure = .., direction = [..]} or "
            f"{{omega = .., centre = [..]}}, got keys {sorted(keys)}")


def load(path) -> SceneFile:
    """Read and build a scene file (see the module documentation)."""
    return SceneFile(path)


def run_file(path, out=None, until=None, progress=None, log=print) -> dict:
    """Build and run a scene file; returns the paths written.

    The HDF5 file (with its XDMF companion, written by the library on
    close) goes to ``out`` (default: the scene file's folder), with the
    probe series as CSV and, when ``figures`` is true (the default), the
    probe curves and a von Mises map of the final state as PNG.
    """
    from . import Probes
    from .dynamics import dynamics_for
    from .trajectory import Trajectory

    spec = load(path)
    until = spec.until if until is None else time(until, "until")
    if until is None:
        raise SceneFileError(f"{path}: no end time: give until = \"...\" in "
                             "the file or --until")
    scene = spec.scene
    out = Path(out) if out is not None else spec.path.parent
    out.mkdir(parents=True, exist_ok=True)
    output = spec.output
    probes = Probes(scene, spec.probe_points) if spec.probe_points else None
    dyn = dynamics_for(spec.integrator)(scene, dt=spec.dt, progress=progress)
    interval = output.get("snapshot_interval")
    if "snapshot_every" in output:
        every = time(output["snapshot_every"], f"{path}: output.snapshot_every")
        interval = max(1, int(round(every / dyn.dt)))
    if interval is None:
        interval = max(1, math.ceil(until / dyn.dt / 10))   # ~10 frames
    probe_interval = int(output.get("probe_interval", 10))
    h5 = out / output.get("file", f"{spec.path.stem}.h5")
    counts = ", ".join(f"{k} {v:,}" for k, v in scene.body_counts().items())
    log(f"{spec.title}: {scene.dimension}D, {counts} particles, dt = "
        f"{dyn.dt * 1e6:.4g} us, until {until * 1e3:g} ms")
    traj = Trajectory(h5, "w", scene, snapshot_interval=int(interval),
                      probe_interval=probe_interval if probes else 0)
    if probes is not None:
        dyn.attach(probes, interval=probe_interval)
    start = wallclock.perf_counter()
    try:
        dyn.run(until=until)
    finally:
        traj.close()                 # the final state and the .xmf
    wall = wallclock.perf_counter() - start
    log(f"{dyn.nsteps} steps to t = {dyn.time * 1e3:.6g} ms in {wall:.2f} s")
    written = {"h5": h5, "xdmf": traj.xdmf_path}
    if probes is not None:
        written["csv"] = out / f"{h5.stem}_probes.csv"
        probes.write_csv(written["csv"])
    if output.get("figures", True):
        from .figures import probe_curves, von_mises_map
        from .trajectory import Frame
        if probes is not None and len(probes.times):
            written["probes_png"] = out / f"{h5.stem}_probes.png"
            probe_curves(probes.times,
                         {n: probes[n]["von_mises"] for n in probes.names},
                         written["probes_png"], title=spec.title)
        written["map_png"] = out / f"{h5.stem}_von_mises.png"
        von_mises_map(Frame.from_scene(scene), written["map_png"],
                      title=spec.title)
    for value in written.values():
        log(f"wrote {value}")
    return written
