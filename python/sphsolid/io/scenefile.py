# Over 600 lines: one TOML schema: its reader, key checks and runner share the key tables.
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
    probe_interval = 10          # steps (default: every step within 0.25 us)

Top-level keys: ``dimension`` (2 or 3, default 2), ``until`` (end time
> 0, required unless given on the command line), ``dt``, ``integrator``
(``"improved_euler"``, the default, or ``"leapfrog"``), ``preset`` (a
named setting of :mod:`sphsolid.presets` filling in kernel, h/dx,
integrator and step, artificial viscosity and platen inset where the file
gives none), ``threads``, ``smoothing_ratio``, ``kernel``, ``domain``
(``{lo = [...], hi = [...], periodic = [true/false, ...]}``), ``title``.

``[output]``: ``file`` (a name in the output folder), ``snapshot_every``
(a time > 0) or ``snapshot_interval`` (steps >= 1), not both,
``probe_interval`` (steps >= 1), ``figures`` (true or false).

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

Materials: ``rho0`` and K/mu, E/nu or K/nu, and every key of the library's
material registry in its unit (read at run time, :func:`material_key_units`:
``weibull_k`` [m^-3] and ``weibull_m`` of the ``damage`` effect, ...).
``[effects]``: ``NAME = { parameter = value, ... }`` for every effect of the
library, each value in its parameter's unit (:func:`effect_parameter_units`;
e.g. ``drucker_prager = { cohesion = "5MPa" }``,
``damage = { seed = 1 }``)::

    [materials.rock]
    K = "12.2GPa"
    mu = "2.67GPa"
    rho0 = 2300
    weibull_k = 1e28             # flaws per m^3 (2D: per metre of depth)
    weibull_m = 9

    [effects]
    damage = { seed = 1, flaws = 10 }

Everything else is checked: an unknown key or shape is an error naming it.
"""
from __future__ import annotations

import math
import sys
from dataclasses import fields
import time as wallclock
from pathlib import Path

from .. import builders as build
from ..material import Material
from ..metrics import probe_interval_for
from ..units import in_unit, length, lengths, quantity, time, to_si

__all__ = ["load", "SceneFile", "run_file", "material_key_units",
           "effect_parameter_units"]

_TOP = {"dimension", "until", "dt", "integrator", "preset", "threads",
        "smoothing_ratio", "kernel", "domain", "materials", "bodies",
        "effects", "probes", "output", "title"}
_OUTPUT = {"file", "snapshot_every", "snapshot_interval", "probe_interval",
           "figures"}
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


#: The elastic constants of a material table and their SI units; the
#: other keys are the library's registry of material keys
#: (material_key_units).
_ELASTIC = {"rho0": "kg/m^3", "K": "Pa", "mu": "Pa", "E": "Pa", "nu": ""}


def material_key_units() -> dict:
    """Every key a ``[materials.NAME]`` table takes and its SI unit: the
    elastic constants and, read from the library at run time, every key
    of its material registry (``sph_material_key_get``: weibull_k [m^-3],
    weibull_m, ...), so a key the library learns is a scene file's key
    too."""
    from .._lib import material_keys
    units = dict(_ELASTIC)
    units.update({key: info["unit"] for key, info in material_keys().items()})
    return units


def effect_parameter_units() -> dict:
    """{effect: {parameter: SI unit}} from the library's effect registry:
    the keys and units of ``[effects] NAME = {...}``."""
    from .._lib import effect_registry
    return {name: {key: p["unit"] for key, p in info["parameters"].items()}
            for name, info in effect_registry().items()}


class SceneFileError(ValueError):
    """A scene file that does not describe a scene (names file and key)."""


def _toml(path: Path) -> dict:
    if sys.version_info >= (3, 11):
        import tomllib
    else:                                       # pragma: no cover
        import tomli as tomllib
    if path.is_dir():
        raise SceneFileError(f"scene file {str(path)!r} is a directory, not "
                             "a TOML file")
    if not path.is_file():
        raise OSError(f"scene file {str(path)!r}: no such file")
    data = path.read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as error:
        kind = ("UTF-16 text" if data[:2] in (b"\xff\xfe", b"\xfe\xff")
                else "binary data")
        raise SceneFileError(
            f"{path}: not a UTF-8 text file (byte {error.start}: "
            f"{data[error.start:error.start + 1]!r}; it looks like {kind}); "
            "save the scene file as UTF-8 TOML") from None
    if "\x00" in text:
        raise SceneFileError(f"{path}: not a text file (a NUL byte at "
                             f"{text.index(chr(0))}); a scene file is TOML")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise SceneFileError(f"{path}: not valid TOML: {error}") from None


def _whole(value, key: str, low: int) -> int:
    """A whole number >= low (not a bool, a float or a string)."""
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise SceneFileError(f"{key} must be a whole number >= {low}, got "
                             f"{value!r}")
    return value


def _flag(value, key: str) -> bool:
    if not isinstance(value, bool):
        raise SceneFileError(f"{key} must be true or false, got {value!r}")
    return value


def _name(value, key: str) -> str:
    if not isinstance(value, str) or not value:
        raise SceneFileError(f"{key} must be a non-empty string, got "
                             f"{value!r}")
    return value


def _unknown(where: str, given, known) -> None:
    extra = sorted(set(given) - set(known))
    if extra:
        raise SceneFileError(f"{where}: unknown key(s) {', '.join(extra)} "
                             f"(known: {', '.join(sorted(known))})")


class SceneFile:
    """A scene file read and built: ``scene``, ``probes`` (points),
    ``until``, ``dt``, ``integrator`` (and the preset's ``step``, a
    fraction of its default step), ``threads`` and the ``output``
    settings.

    ``preset`` (a name of :mod:`sphsolid.presets`, else the file's
    ``preset`` key) fills in what the file does not give: kernel, h/dx,
    integrator and its step, artificial viscosity and the platens' inset;
    ``integrator`` overrides the file's and the preset's.
    """

    def __init__(self, path, preset=None, integrator=None):
        self.path = Path(path)
        data = _toml(self.path)
        try:
            self._build(data, str(self.path), preset, integrator)
        except SceneFileError as error:
            message = str(error)
            if message.startswith(str(self.path)):
                raise
            raise SceneFileError(f"{self.path}: {message}") from None
        except ValueError as error:       # a value's own check, named
            raise SceneFileError(f"{self.path}: {error}") from None

    def _build(self, data: dict, name: str, preset=None,
               integrator=None) -> None:
        from .._lib import integrator_names
        from ..presets import preset as named_preset
        _unknown(name, data, _TOP)
        self.title = _name(data.get("title", self.path.stem), "title")
        self.dimension = data.get("dimension", 2)
        self.until = None
        if "until" in data:
            self.until = time(data["until"], "until")
            if not (math.isfinite(self.until) and self.until > 0):
                raise SceneFileError(f"until must be a finite time > 0, got "
                                     f"{data['until']!r}")
        self.dt = time(data["dt"], "dt") if "dt" in data else None
        self.threads = (_whole(data["threads"], "threads", 1)
                        if "threads" in data else None)
        chosen = preset if preset is not None else data.get("preset")
        self.preset = None if chosen is None else named_preset(chosen)
        self.integrator = (integrator or data.get("integrator")
                           or (self.preset.integrator if self.preset
                               else "improved_euler"))
        if self.integrator not in integrator_names():
            raise SceneFileError(
                f"integrator must be one of {', '.join(integrator_names())},"
                f" got {self.integrator!r}")
        # the preset's step applies to its own integrator, when dt is not
        # given (as presets.dynamics)
        self.step = (self.preset.step if self.preset is not None
                     and self.integrator == self.preset.integrator else 1.0)
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
            # each value in its parameter's unit (the library's registry);
            # an unknown effect or key is the library's to name
            known = effect_parameter_units().get(effect, {})
            self.effects[effect] = {
                key: (in_unit(value, known[key], f"effects.{effect}.{key}")
                      if key in known
                      else quantity(value, None, f"effects.{effect}.{key}"))
                for key, value in parameters.items()}
        if (self.preset is not None and self.preset.viscosity is not None
                and "artificial_viscosity" not in self.effects):
            self.effects["artificial_viscosity"] = dict(self.preset.viscosity)
        self.probe_points = {
            probe: lengths(point, f"probes.{probe}")
            for probe, point in data.get("probes", {}).items()}
        self.output = self._output(data.get("output", {}), name)
        domain = data.get("domain")
        kwargs = {}
        if domain is not None:
            if not isinstance(domain, dict):
                raise SceneFileError(f"domain must be a table {{lo = [..], "
                                     f"hi = [..]}}, got {domain!r}")
            _unknown(f"{name}: domain", domain, {"lo", "hi", "periodic"})
            kwargs["domain"] = (lengths(domain.get("lo"), "domain.lo"),
                                lengths(domain.get("hi"), "domain.hi"))
            if "periodic" in domain:
                periodic = domain["periodic"]
                if not isinstance(periodic, list):
                    raise SceneFileError(f"domain.periodic must be a list of "
                                         f"true/false, got {periodic!r}")
                kwargs["periodic"] = [
                    _flag(p, f"domain.periodic[{i}]")
                    for i, p in enumerate(periodic)]
        ratio = data.get("smoothing_ratio")
        kernel = data.get("kernel")
        if self.preset is not None:
            ratio = self.preset.smoothing_ratio if ratio is None else ratio
            kernel = self.preset.kernel if kernel is None else kernel
        if "damage" in self.effects and not any(
                isinstance(b.motion, build.Free)
                and b.material.weibull_k > 0 and b.material.weibull_m > 0
                for b in self.bodies):
            # the library's rule, said in the file's words (it names
            # sph_material_set, the C call)
            raise SceneFileError(
                f"{name}: [effects] damage needs flaws: give weibull_k "
                "[m^-3] and weibull_m > 0 in the [materials.NAME] table of a "
                "free body's material")
        from ..scene import Scene
        try:
            self.scene = Scene(self.dimension, self.bodies,
                               effects=self.effects, smoothing_ratio=ratio,
                               kernel=kernel or "cubic_spline", **kwargs)
        except ValueError as error:
            raise SceneFileError(f"{name}: {error}") from None
        except MemoryError as error:      # the large-run guard's refusal
            raise MemoryError(f"{name}: {error}") from None

    @staticmethod
    def _output(output, name) -> dict:
        """The [output] table checked: file (a name), snapshot_every (a
        time > 0) or snapshot_interval (steps >= 1), probe_interval (steps
        >= 1), figures (true/false)."""
        if not isinstance(output, dict):
            raise SceneFileError(f"[output] must be a table, got {output!r}")
        output = dict(output)
        _unknown(f"{name}: [output]", output, _OUTPUT)
        if "file" in output:
            _name(output["file"], "output.file")
        if "snapshot_every" in output and "snapshot_interval" in output:
            raise SceneFileError("[output] gives both snapshot_every and "
                                 "snapshot_interval: keep one")
        if "snapshot_every" in output:
            every = time(output["snapshot_every"], "output.snapshot_every")
            if not (math.isfinite(every) and every > 0):
                raise SceneFileError(f"output.snapshot_every must be a "
                                     f"finite time > 0, got "
                                     f"{output['snapshot_every']!r}")
            output["snapshot_every"] = every
        if "snapshot_interval" in output:
            _whole(output["snapshot_interval"], "output.snapshot_interval", 1)
        if "probe_interval" in output:
            _whole(output["probe_interval"], "output.probe_interval", 1)
        if "figures" in output:
            _flag(output["figures"], "output.figures")
        return output

    def _material(self, spec, where) -> Material:
        if not isinstance(spec, dict):
            raise SceneFileError(f"{where}: a material is a table of rho0 and "
                                 f"K/mu, E/nu or K/nu, got {spec!r}")
        units = material_key_units()
        _unknown(where, spec, set(units) | {"name"})
        own = {f.name for f in fields(Material) if f.init}
        values, keys = {}, {}
        for key, value in spec.items():
            if key == "name":
                continue
            converted = in_unit(value, units[key], f"{where} {key}")
            if key in _ELASTIC or key in own:
                values[key] = converted
            else:
                keys[key] = converted
        try:
            return Material(name=spec.get("name", ""), keys=keys, **values)
        except (TypeError, ValueError) as error:
            raise SceneFileError(f"{where}: {error}") from None

    def _body(self, spec, where):
        if not isinstance(spec, dict):
            raise SceneFileError(f"{where}: a body is a table")
        shape = spec.get("shape")
        if not isinstance(shape, str) or shape not in _SHAPES:
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
            try:
                kwargs["motion"] = self._motion(spec["motion"], where)
            except SceneFileError:
                raise
            except ValueError as error:
                raise SceneFileError(f"{where}: {error}") from None
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
                if "inset" not in kwargs and self.preset is not None:
                    kwargs["inset"] = self.preset.inset
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


def load(path, preset=None, integrator=None) -> SceneFile:
    """Read and build a scene file (see the module documentation)."""
    return SceneFile(path, preset=preset, integrator=integrator)



def make_folder(path: Path, label: str) -> Path:
    """Make an output folder (and its parents), or refuse with ``label``
    (how the caller names it): a file in its place, a folder that cannot
    be made."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{label}: is a file, not a folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise ValueError(f"{label}: cannot make the folder "
                         f"({error.strerror})") from None
    return path

def run_file(path, out=None, until=None, progress=None, log=print,
             threads=None, integrator=None, preset=None,
             checkpoint_every=None, resume=None, dt=None,
             plan=None, probe_interval=None) -> dict:
    """Build and run a scene file; returns the paths written.

    ``plan`` (a plan.json path or :class:`~sphsolid.planner.Plan` from
    ``sphsolid plan SCENE.toml``) rebuilds the file's scene at the plan's
    spacing, h/dx, kernel, inset, integrator and effects; its end time
    applies unless ``until`` is given.

    The HDF5 file (with its XDMF companion, written by the library on
    close) goes to ``out`` (default: the scene file's folder), with the
    probe series as CSV (ending at the end time) and, when ``figures`` is
    true (the default), the probe curves and a von Mises map of the final
    state as PNG.

    ``probe_interval`` (steps between probe samples) overrides the file's
    ``[output] probe_interval``; the default samples every step within
    0.25 us (:func:`~sphsolid.metrics.probe_interval_for`). A run with a
    ``plan`` that samples more sparsely than that says so: what it writes
    may then be further from the truth than the plan's error.

    ``threads`` (else the file's ``threads``) sets the OpenMP threads;
    ``integrator`` and ``preset`` are as for :class:`SceneFile`; ``dt``
    overrides the file's.
    ``checkpoint_every`` (a time) writes ``<file>_checkpoint.h5`` at every
    multiple of it; ``resume`` continues from such a checkpoint (written by
    the same scene and integrator), its files holding the run from there.
    """
    from .. import Probes
    from ..calculators import CLibrary
    from .checkpoint import marks, resume as read_checkpoint
    from ..dynamics import dynamics_for
    from .trajectory import Trajectory

    spec = load(path, preset=preset, integrator=integrator)
    integrator, step = spec.integrator, spec.step
    given_dt = None if dt is None else time(dt, "dt")
    dt = spec.dt if given_dt is None else given_dt
    if plan is not None:
        from ..planner import Plan
        from ..planner.scenes import scene_file
        loaded = plan if isinstance(plan, Plan) else Plan.load(plan)
        if not loaded.feasible:
            raise ValueError(f"{plan}: the plan was refused: "
                             f"{loaded.reason}")
        if loaded.scene and loaded.scene != Path(path).name:
            raise ValueError(f"{plan} plans the scene {loaded.scene!r}, not "
                             f"{Path(path).name!r}")
        # the calculator is attached below, with --threads if given
        spec.scene = loaded.build(scene_file(path).factory, calculator=False)
        if threads is None:
            threads = loaded.threads
        # the plan's integrator at the plan's step (a --dt still applies)
        integrator, step = loaded.setting.integrator, loaded.setting.step
        dt = given_dt
        if until is None and loaded.request.get("until"):
            until = time(loaded.request["until"], f"{plan}: request.until")
        log(f"plan {plan}: {loaded.setting.label()}, dx = "
            f"{loaded.dx * 1e3:.4g} mm; predicted error "
            f"{loaded.predicted_error * 100:.2f} % (at most "
            f"{loaded.error_upper * 100:.2f} %)")
    until = spec.until if until is None else time(until, "until")
    if until is None:
        raise SceneFileError(f"{path}: no end time: give until = \"...\" in "
                             "the file or --until")
    scene = spec.scene
    out = Path(out) if out is not None else spec.path.parent
    output = spec.output
    h5 = out / output.get("file", f"{spec.path.stem}.h5")
    checkpoint = h5.with_name(f"{h5.stem}_checkpoint.h5")
    make_folder(out, f"output folder {str(out)!r}")
    threads = spec.threads if threads is None else threads
    if threads is not None:
        scene.calc = CLibrary(threads=threads)
    if resume is not None:
        resumed_dt = read_checkpoint(scene, resume, integrator)
        dt = resumed_dt if dt is None else dt
    probes = Probes(scene, spec.probe_points) if spec.probe_points else None
    kind = dynamics_for(integrator)
    dyn = kind(scene, dt=dt, progress=progress)
    if dt is None and step != 1.0:            # the preset's step
        dyn = kind(scene, dt=dyn.dt * step, progress=progress)
    interval = output.get("snapshot_interval")
    if "snapshot_every" in output:
        interval = max(1, int(round(output["snapshot_every"] / dyn.dt)))
    if interval is None:
        interval = max(1, math.ceil(until / dyn.dt / 10))   # ~10 frames
    needed = probe_interval_for(dyn.dt)
    if probe_interval is None:
        probe_interval = int(output.get("probe_interval", needed))
    if plan is not None and spec.probe_points and probe_interval > needed:
        log(f"warning: probes sampled every {probe_interval} steps "
            f"({probe_interval * dyn.dt * 1e6:.3g} us), more sparsely than "
            f"the planner's error metric reads them ({needed} steps, "
            f"{needed * dyn.dt * 1e6:.3g} us): the written series may be "
            "further from the truth than the plan's error (the file's "
            "[output] probe_interval; --probe-interval overrides it)")
    stops = marks(checkpoint_every, dyn.time, until)
    counts = ", ".join(f"{k} {v:,}" for k, v in scene.body_counts().items())
    log(f"{spec.title}: {scene.dimension}D, {counts} particles, "
        f"{integrator}, dt = {dyn.dt * 1e6:.4g} us, until "
        f"{until * 1e3:g} ms"
        + (f" (from t = {dyn.time * 1e3:.6g} ms, {resume})" if resume
           else ""))
    traj = Trajectory(h5, "w", scene, snapshot_interval=int(interval),
                      probe_interval=probe_interval if probes else 0)
    if probes is not None:
        dyn.attach(probes, interval=probe_interval)
    start = wallclock.perf_counter()
    try:
        for t in stops + [until]:
            dyn.run(until=t)
            if t in stops:
                scene.write_checkpoint(checkpoint)
        if probes is not None:
            probes.record_final()        # the state at the end time
    finally:
        traj.close()                 # the final state and the .xmf
    wall = wallclock.perf_counter() - start
    log(f"{dyn.nsteps} steps to t = {dyn.time * 1e3:.6g} ms in {wall:.2f} s")
    written = {"h5": h5, "xdmf": traj.xdmf_path}
    if stops:
        written["checkpoint"] = checkpoint
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
