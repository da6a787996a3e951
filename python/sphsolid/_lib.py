# Over 600 lines: the ctypes prototypes of all of sphsolid.h and the status mapping.
"""ctypes binding to libsphsolid, the C library that holds all the physics.

Nothing in this module computes anything physical: it finds the shared
library, declares the prototypes of ``sphsolid.h`` and turns the library's
status codes into Python exceptions whose message is the library's own
(which names the bad value).

The library is looked up, in order, at

1. the path in the environment variable ``SPHSOLID_LIBRARY``;
2. ``libsphsolid.so`` inside this package (a wheel built with
   scikit-build-core installs it there);
3. a development build tree of this repository
   (``build/libsphsolid/libsphsolid.so`` or ``build/libsphsolid.so``);
4. the system's library path (``ctypes.util.find_library``).
"""
from __future__ import annotations

import ctypes
import ctypes.util
import os
from ctypes import (CFUNCTYPE, POINTER, Structure, c_char_p, c_double, c_int,
                    c_long, c_size_t, c_void_p)
from pathlib import Path

__all__ = ["lib", "library_path", "check", "SimulationError",
           "UnsupportedError", "StoppedError", "STATUS"]

# sph_status values (sphsolid.h)
SPH_OK = 0
SPH_ERR_ARGUMENT = 1
SPH_ERR_MEMORY = 2
SPH_ERR_STATE = 3
SPH_ERR_IO = 4
SPH_ERR_NONFINITE = 5
SPH_ERR_UNSUPPORTED = 6
SPH_ERR_STOPPED = 7
SPH_ERR_DOMAIN = 8
SPH_ERR_UNSTABLE = 9
STATUS = {0: "SPH_OK", 1: "SPH_ERR_ARGUMENT", 2: "SPH_ERR_MEMORY",
          3: "SPH_ERR_STATE", 4: "SPH_ERR_IO", 5: "SPH_ERR_NONFINITE",
          6: "SPH_ERR_UNSUPPORTED", 7: "SPH_ERR_STOPPED",
          8: "SPH_ERR_DOMAIN", 9: "SPH_ERR_UNSTABLE"}

# sph_motion
MOTION_FREE, MOTION_FIXED, MOTION_VELOCITY, MOTION_FORCE = 0, 1, 2, 3
MOTION_ROTATION = 4
# sph_field_id
FIELD_POSITION = 0
FIELD_VELOCITY = 1
FIELD_DENSITY = 2
FIELD_DEVIATORIC_STRESS = 3
FIELD_MASS = 4
FIELD_PRESSURE = 5
FIELD_VON_MISES = 6
FIELD_STRESS = 7
FIELD_ACCELERATION = 8
# effect damage
FIELD_DAMAGE = 9
FIELD_FRAGMENT = 10
FIELD_FLAWS = 11
FIELD_FLAW_STRAIN = 12
FIELD_ACTIVE_FLAWS = 13


def stress_components(dim: int) -> int:
    """SPH_STRESS_COMPONENTS(dim): stored stress components per particle."""
    return 4 if dim == 2 else 6


def probe_values(dim: int) -> int:
    """SPH_PROBE_VALUES(dim): von Mises, pressure, then the stress."""
    return 2 + stress_components(dim)


class SimulationError(RuntimeError):
    """A run stopped on a non-finite value or a particle leaving the domain.

    Attributes ``step``, ``particle``, ``body`` and ``quantity`` say where
    (from ``sph_failure``), when the library reported it.
    """

    def __init__(self, message, step=None, particle=None, body=None,
                 quantity=None):
        super().__init__(message)
        self.step = step
        self.particle = particle
        self.body = body
        self.quantity = quantity


class UnsupportedError(RuntimeError):
    """The library was built without a feature (e.g. HDF5)."""


class StoppedError(RuntimeError):
    """A progress callback asked the library to stop the run."""


class MaterialInfo(Structure):
    _fields_ = [("bulk_modulus", c_double), ("shear_modulus", c_double),
                ("rho0", c_double), ("poisson_ratio", c_double),
                ("youngs_modulus", c_double), ("c0", c_double),
                ("c_p", c_double), ("weibull_k", c_double),
                ("weibull_m", c_double)]


class BodyInfo(Structure):
    _fields_ = [("name", c_char_p), ("material", c_int), ("motion", c_int),
                ("first", c_size_t), ("count", c_size_t),
                ("spacing", c_double)]


class EnergyInfo(Structure):
    _fields_ = [("kinetic", c_double), ("elastic", c_double),
                ("momentum", c_double * 3), ("work", c_double),
                ("dissipated_damage", c_double),
                ("dissipated_plastic", c_double),
                ("dissipated_viscosity", c_double)]


class IntegratorInfo(Structure):
    _fields_ = [("name", c_char_p), ("description", c_char_p),
                ("evaluations", c_int), ("stable_factor", c_double),
                ("default_factor", c_double), ("saved_values", c_size_t),
                ("carries_rates", c_int)]


class EffectInfo(Structure):
    _fields_ = [("name", c_char_p), ("description", c_char_p),
                ("parameter_count", c_int)]


class EffectParameter(Structure):
    _fields_ = [("key", c_char_p), ("unit", c_char_p),
                ("description", c_char_p), ("default_value", c_double),
                ("required", c_int), ("min", c_double), ("max", c_double),
                ("min_inclusive", c_int), ("max_inclusive", c_int)]


class MaterialKeyInfo(Structure):
    _fields_ = [("key", c_char_p), ("unit", c_char_p),
                ("description", c_char_p), ("default_value", c_double),
                ("min", c_double), ("max", c_double)]


class PaperScene(Structure):
    _fields_ = [("specimen", c_int), ("piston", c_int), ("plate", c_int),
                ("material", c_int), ("probe_A", c_int), ("probe_B", c_int),
                ("probe_C", c_int)]


PROGRESS_FN = CFUNCTYPE(c_int, c_void_p, c_void_p)

_sim = c_void_p
_dp = POINTER(c_double)
_PROTOTYPES = {
    # name: (restype, argtypes)
    "sph_create": (c_int, [c_int, POINTER(c_void_p)]),
    "sph_destroy": (None, [_sim]),
    "sph_errmsg": (c_char_p, [_sim]),
    "sph_status_name": (c_char_p, [c_int]),
    "sph_version": (c_char_p, []),
    "sph_dimension": (c_int, [_sim]),
    "sph_set_threads": (c_int, [_sim, c_int]),
    "sph_add_material_K_mu": (c_int, [_sim, c_double, c_double, c_double,
                                      POINTER(c_int)]),
    "sph_add_material_E_nu": (c_int, [_sim, c_double, c_double, c_double,
                                      POINTER(c_int)]),
    "sph_add_material_K_nu": (c_int, [_sim, c_double, c_double, c_double,
                                      POINTER(c_int)]),
    "sph_material_info_get": (c_int, [_sim, c_int, POINTER(MaterialInfo)]),
    "sph_material_set": (c_int, [_sim, c_int, c_char_p, c_double]),
    "sph_material_key_count": (c_int, []),
    "sph_material_key_get": (c_int, [c_int, POINTER(MaterialKeyInfo)]),
    "sph_flaws_active_at": (c_int, [_sim, c_double, _dp]),
    "sph_body_reaction": (c_int, [_sim, c_int, _dp]),
    "sph_add_block": (c_int, [_sim, c_char_p, c_int, _dp, _dp, c_double,
                              POINTER(c_int)]),
    "sph_block_lattice": (c_int, [_sim, c_char_p, _dp, _dp, c_double,
                                  POINTER(c_long), _dp]),
    "sph_add_particles": (c_int, [_sim, c_char_p, c_int, c_size_t, _dp, _dp,
                                  c_double, POINTER(c_int)]),
    "sph_add_prism": (c_int, [_sim, c_char_p, c_int, _dp, c_double, c_double,
                              c_double, c_double, POINTER(c_int)]),
    "sph_add_cylinder": (c_int, [_sim, c_char_p, c_int, _dp, c_double,
                                 c_double, c_double, POINTER(c_int)]),
    "sph_add_plate": (c_int, [_sim, c_char_p, c_int, c_int, c_int,
                              POINTER(c_int)]),
    "sph_add_piston": (c_int, [_sim, c_char_p, c_int, c_int, c_int, c_double,
                               POINTER(c_int)]),
    "sph_set_platen_inset": (c_int, [_sim, c_double]),
    "sph_platen_inset": (c_double, [_sim]),
    "sph_static_platen_inset": (c_int, [_sim, c_int, _dp, _dp]),
    "sph_platen_end_offset": (c_int, [_sim, c_int, c_double, _dp]),
    "sph_body_extent": (c_int, [_sim, c_int, _dp, _dp, _dp]),
    "sph_set_motion": (c_int, [_sim, c_int, c_int, _dp]),
    "sph_set_body_velocity": (c_int, [_sim, c_int, _dp]),
    "sph_set_rotation": (c_int, [_sim, c_int, _dp, _dp]),
    "sph_particle_count": (c_size_t, [_sim]),
    "sph_body_count": (c_int, [_sim]),
    "sph_body_info_get": (c_int, [_sim, c_int, POINTER(BodyInfo)]),
    "sph_body_find": (c_int, [_sim, c_char_p, POINTER(c_int)]),
    "sph_set_domain": (c_int, [_sim, _dp, _dp, POINTER(c_int)]),
    "sph_set_kernel": (c_int, [_sim, c_int]),
    "sph_set_smoothing_ratio": (c_int, [_sim, c_double]),
    "sph_smoothing_length": (c_double, [_sim]),
    "sph_support_radius": (c_double, [_sim]),
    "sph_support_layers": (c_int, [_sim, c_double]),
    "sph_effect": (c_int, [_sim, c_char_p, c_char_p]),
    "sph_effect_off": (c_int, [_sim, c_char_p]),
    "sph_effect_is_on": (c_int, [_sim, c_char_p]),
    "sph_effect_names": (c_char_p, []),
    "sph_effect_count": (c_int, []),
    "sph_effect_info_get": (c_int, [c_int, POINTER(EffectInfo)]),
    "sph_effect_parameter_get": (c_int, [c_int, c_int,
                                         POINTER(EffectParameter)]),
    "sph_set_kernel_by_name": (c_int, [_sim, c_char_p]),
    "sph_kernel_name": (c_char_p, [c_int]),
    "sph_kernel_from_name": (c_int, [c_char_p]),
    "sph_kernel_names": (c_char_p, []),
    "sph_kernel_negative_from": (c_double, [c_int, c_int]),
    "sph_kernel_values": (c_int, [_sim, c_size_t, _dp, _dp, _dp]),
    "sph_stable_dt": (c_double, [_sim]),
    "sph_default_dt": (c_double, [_sim]),
    "sph_set_dt": (c_int, [_sim, c_double, c_int]),
    "sph_dt": (c_double, [_sim]),
    "sph_time": (c_double, [_sim]),
    "sph_step_count": (c_long, [_sim]),
    "sph_set_time": (c_int, [_sim, c_double, c_long]),
    "sph_set_watchdog": (c_int, [_sim, c_double, c_double, c_double]),
    "sph_set_progress": (c_int, [_sim, c_long, PROGRESS_FN, c_void_p]),
    "sph_run": (c_int, [_sim, c_long]),
    "sph_run_until": (c_int, [_sim, c_double]),
    "sph_steps_until": (c_int, [_sim, c_double, POINTER(c_long),
                                POINTER(c_double)]),
    "sph_set_integrator": (c_int, [_sim, c_char_p]),
    "sph_integrator_name": (c_char_p, [_sim]),
    "sph_integrator_names": (c_char_p, []),
    "sph_integrator_info_get": (c_int, [_sim, c_char_p,
                                        POINTER(IntegratorInfo)]),
    "sph_failure": (c_int, [_sim, POINTER(c_long), POINTER(c_long),
                            POINTER(c_int), POINTER(c_char_p)]),
    "sph_field": (c_int, [_sim, c_int, POINTER(_dp), POINTER(c_size_t),
                          POINTER(c_size_t)]),
    "sph_field_copy": (c_int, [_sim, c_int, _dp]),
    "sph_body_ids": (c_int, [_sim, POINTER(c_int)]),
    "sph_von_mises": (c_double, [c_int, _dp]),
    "sph_energy": (c_int, [_sim, c_int, POINTER(EnergyInfo)]),
    "sph_set_energy_account": (c_int, [_sim, c_int]),
    "sph_energy_account": (c_int, [_sim]),
    "sph_add_probe": (c_int, [_sim, c_char_p, _dp, POINTER(c_int)]),
    "sph_probe_count": (c_int, [_sim]),
    "sph_probe_name": (c_char_p, [_sim, c_int]),
    "sph_probe_sample": (c_int, [_sim, c_int, _dp]),
    "sph_set_probe_outside": (c_int, [_sim, c_int]),
    "sph_memory_check": (c_int, [_sim, c_double]),
    "sph_set_allow_large": (c_int, [_sim, c_int]),
    "sph_allow_large": (c_int, [_sim]),
    "sph_output_open": (c_int, [_sim, c_char_p, c_long, c_long]),
    "sph_output_snapshot": (c_int, [_sim]),
    "sph_output_close": (c_int, [_sim]),
    "sph_write_xdmf": (c_int, [_sim, c_char_p]),
    "sph_output_format_version": (c_int, []),
    "sph_read_frame_count": (c_int, [_sim, c_char_p, POINTER(c_long)]),
    "sph_read_frame": (c_int, [_sim, c_char_p, c_long]),
    "sph_checkpoint_write": (c_int, [_sim, c_char_p]),
    "sph_checkpoint_read": (c_int, [_sim, c_char_p]),
    "sph_build_paper_scene": (c_int, [_sim, c_double, c_double, c_int,
                                      POINTER(PaperScene)]),
}


def _candidates():
    env = os.environ.get("SPHSOLID_LIBRARY")
    if env:
        yield Path(env), True
    here = Path(__file__).resolve().parent
    yield here / "libsphsolid.so", False
    for root in (here.parent.parent, Path.cwd()):
        yield root / "build" / "libsphsolid" / "libsphsolid.so", False
        yield root / "build" / "libsphsolid.so", False
    found = ctypes.util.find_library("sphsolid")
    if found:
        yield Path(found), False


class _Library:
    """Lazily loaded handle on libsphsolid with typed prototypes."""

    def __init__(self):
        self._cdll = None
        self.path = None

    def _load(self):
        tried = []
        for path, explicit in _candidates():
            if explicit and not path.exists():
                raise OSError(f"SPHSOLID_LIBRARY={path}: no such file")
            if not path.exists() and path.is_absolute():
                tried.append(str(path))
                continue
            try:
                cdll = ctypes.CDLL(str(path))
            except OSError as error:
                if explicit:
                    raise OSError(f"SPHSOLID_LIBRARY={path}: cannot load: "
                                  f"{error}") from error
                tried.append(f"{path} ({error})")
                continue
            self.missing = []
            for name, (restype, argtypes) in _PROTOTYPES.items():
                try:
                    function = getattr(cdll, name)
                except AttributeError:
                    self.missing.append(name)
                    continue
                function.restype = restype
                function.argtypes = argtypes
            self._cdll, self.path = cdll, path
            return
        raise OSError("libsphsolid.so not found; build it (cmake -S . -B "
                      "build && cmake --build build) or set SPHSOLID_LIBRARY."
                      " Tried: " + "; ".join(tried))

    def __getattr__(self, name):
        if name.startswith("sph_"):
            if self._cdll is None:
                self._load()
            if name in self.missing:
                raise UnsupportedError(f"{self.path} does not export {name}"
                                       " (an older or partial build)")
            return getattr(self._cdll, name)
        raise AttributeError(name)


lib = _Library()


def library_path() -> Path:
    """Path of the loaded libsphsolid (loading it if needed)."""
    if lib._cdll is None:
        lib._load()
    return lib.path


def errmsg(sim) -> str:
    message = lib.sph_errmsg(sim)
    return message.decode("utf-8", "replace") if message else ""


def check(status: int, sim, what: str = "") -> None:
    """Raise the Python exception matching a non-zero sph_status.

    ``SPH_ERR_ARGUMENT`` -> ValueError, ``SPH_ERR_IO`` -> OSError,
    ``SPH_ERR_MEMORY`` -> MemoryError, ``SPH_ERR_NONFINITE``,
    ``SPH_ERR_DOMAIN`` and ``SPH_ERR_UNSTABLE`` (the watchdog) ->
    SimulationError (with step, particle, body and quantity), ``SPH_ERR_UNSUPPORTED`` -> UnsupportedError,
    ``SPH_ERR_STOPPED`` -> StoppedError, ``SPH_ERR_STATE`` -> RuntimeError.
    The message is the library's, prefixed with ``what``.
    """
    if status == SPH_OK:
        return
    message = errmsg(sim) if sim else ""
    if not message:
        message = STATUS.get(status, f"status {status}")
    if what and not message.startswith(what):
        message = f"{what}: {message}"
    if status == SPH_ERR_ARGUMENT:
        raise ValueError(message)
    if status == SPH_ERR_IO:
        raise OSError(message)
    if status == SPH_ERR_MEMORY:
        raise MemoryError(message)
    if status in (SPH_ERR_NONFINITE, SPH_ERR_DOMAIN, SPH_ERR_UNSTABLE):
        step, particle, body = c_long(), c_long(), c_int()
        quantity = c_char_p()
        if lib.sph_failure(sim, ctypes.byref(step), ctypes.byref(particle),
                           ctypes.byref(body), ctypes.byref(quantity)) == 0:
            raise SimulationError(
                message, step.value, particle.value, body.value,
                quantity.value.decode() if quantity.value else None)
        raise SimulationError(message)
    if status == SPH_ERR_UNSUPPORTED:
        raise UnsupportedError(message)
    if status == SPH_ERR_STOPPED:
        raise StoppedError(message)
    raise RuntimeError(message)


def version() -> str:
    """Version string of the library and its compiled-in options."""
    return lib.sph_version().decode()


def effect_names() -> list[str]:
    """Effect names the library knows (``sph_effect_names``)."""
    return lib.sph_effect_names().decode().split()


def integrator_names() -> list[str]:
    """Integrator names the library knows (``sph_integrator_names``)."""
    return lib.sph_integrator_names().decode().split()


def integrator_registry() -> dict:
    """The library's integrator registry: for each integrator name, its
    one-line ``description``, rate ``evaluations`` per step, and the
    ``stable_factor`` and ``default_factor`` of its steps (stable step
    stable_factor h / max(c_p + |v|), default step default_factor h / c0;
    ``sph_integrator_info_get``)."""
    out = {}
    handle = new_handle(2)
    try:
        for name in integrator_names():
            info = IntegratorInfo()
            check(lib.sph_integrator_info_get(handle, name.encode(),
                                              ctypes.byref(info)),
                  handle, f"integrator {name!r}")
            out[name] = {"description": info.description.decode(),
                         "evaluations": int(info.evaluations),
                         "stable_factor": float(info.stable_factor),
                         "default_factor": float(info.default_factor)}
    finally:
        lib.sph_destroy(handle)
    return out


def steps_until(sim, t: float) -> tuple[int, float]:
    """How ``sph_run_until(sim, t)`` gets to ``t``: whole steps of the
    current dt, then one shortened step of the returned length (0: none)."""
    whole = ctypes.c_long()
    last = ctypes.c_double()
    check(lib.sph_steps_until(sim, float(t), ctypes.byref(whole),
                              ctypes.byref(last)), sim, "until")
    return int(whole.value), float(last.value)


def kernel_names() -> list[str]:
    """Kernel names the library knows, in the order of their numbers."""
    return lib.sph_kernel_names().decode().split()


def kernel_negative_from(kernel: str, dimension: int = 2) -> float:
    """The smallest q = r/h at which the library's kernel is negative, 0
    when it is non-negative over its support (``sph_kernel_negative_from``;
    the artificial_stress effect needs 0)."""
    number = lib.sph_kernel_from_name(as_name(kernel, "kernel"))
    if number < 0:
        raise ValueError(f"unknown kernel {kernel!r} (known: "
                         f"{', '.join(kernel_names())})")
    q = float(lib.sph_kernel_negative_from(number, int(dimension)))
    if q < 0:
        raise ValueError(f"dimension={dimension!r} must be 2 or 3")
    return q


def kernel_values(kernel: str, q, dimension: int = 2):
    """The library's kernel at q = r/h (array-like, >= 0), in the
    dimensionless form of ``sph_kernel_values``: returns (w, dw_dq) with
    W(r) = w / h^dimension and dW/dr = dw_dq / h^(dimension + 1)."""
    import numpy as np
    q = np.ascontiguousarray(q, dtype=np.float64)
    w = np.empty_like(q)
    dw_dq = np.empty_like(q)
    handle = new_handle(dimension)
    try:
        check(lib.sph_set_kernel_by_name(handle, as_name(kernel, "kernel")),
              handle, "kernel")
        check(lib.sph_kernel_values(handle, q.size, q.ctypes.data_as(_dp),
                                    w.ctypes.data_as(_dp),
                                    dw_dq.ctypes.data_as(_dp)),
              handle, "kernel_values")
    finally:
        lib.sph_destroy(handle)
    return w, dw_dq


def effect_registry() -> dict:
    """The library's effect registry: for each effect name, its one-line
    ``description`` and its ``parameters``, each a dict with ``unit``,
    ``description``, ``default`` (None when it must be given), ``min``,
    ``max`` (+-inf when unbounded), ``min_inclusive`` and
    ``max_inclusive``."""
    out = {}
    info = EffectInfo()
    for e in range(lib.sph_effect_count()):
        check(lib.sph_effect_info_get(e, ctypes.byref(info)), None,
              "sph_effect_info_get")
        parameters = {}
        for k in range(info.parameter_count):
            p = EffectParameter()
            check(lib.sph_effect_parameter_get(e, k, ctypes.byref(p)), None,
                  "sph_effect_parameter_get")
            parameters[p.key.decode()] = {
                "unit": p.unit.decode(),
                "description": p.description.decode(),
                "default": None if p.required else p.default_value,
                "min": p.min, "max": p.max,
                "min_inclusive": bool(p.min_inclusive),
                "max_inclusive": bool(p.max_inclusive)}
        out[info.name.decode()] = {"description": info.description.decode(),
                                   "parameters": parameters}
    return out


def material_keys() -> dict:
    """The library's registry of material keys (those ``sph_material_set``
    takes, beyond the elastic constants): for each key its ``unit`` (SI,
    "" for a pure number), ``description``, ``default`` and the closed
    range ``min`` .. ``max`` (inf: unbounded)."""
    out = {}
    for k in range(lib.sph_material_key_count()):
        info = MaterialKeyInfo()
        check(lib.sph_material_key_get(k, ctypes.byref(info)), None,
              "sph_material_key_get")
        out[info.key.decode()] = {"unit": info.unit.decode(),
                                  "description": info.description.decode(),
                                  "default": info.default_value,
                                  "min": info.min, "max": info.max}
    return out


def new_handle(dimension: int):
    """Create an ``sph_sim`` handle; raise ValueError on a bad dimension or
    a bad ``SPHSOLID_RATE_PATH`` in the environment (the library's message
    names the value)."""
    handle = c_void_p()
    status = lib.sph_create(int(dimension), ctypes.byref(handle))
    if status != SPH_OK:
        try:
            check(status, handle)
        finally:
            if handle:
                lib.sph_destroy(handle)
    if not handle:
        raise MemoryError("sph_create: out of memory")
    return handle


def flag(value, name: str) -> bool:
    """A yes/no argument: True or False (numpy's bools, and the integers 0
    and 1, too); anything else is a ValueError naming ``name``, never cast
    (``bool("no")`` is True)."""
    if isinstance(value, bool):
        return value
    try:
        import numpy
        if isinstance(value, numpy.bool_):
            return bool(value)
    except ImportError:                      # pragma: no cover
        pass
    if isinstance(value, int) and value in (0, 1):
        return bool(value)
    raise ValueError(f"{name} must be True or False, got {value!r}")


def number(value, name: str) -> float:
    """A float from a real number (not a bool or a string), with a
    ValueError naming ``name``."""
    if isinstance(value, (bool, str, bytes)) or value is None:
        raise ValueError(f"{name} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None


def numbers(values, name: str, n=None) -> list:
    """Floats from a sequence of numbers (``n`` of them, or one of the
    lengths in a tuple ``n``), with a ValueError naming ``name``."""
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise ValueError(f"{name} must be a sequence of numbers, got "
                         f"{values!r}")
    from .units import check_entries
    seq = [number(v, f"{name}[{i}]") for i, v in enumerate(values)]
    check_entries(seq, values, name, n)
    return seq


def as_doubles(values, n: int, name: str):
    """A ctypes double[n] from a sequence, with a ValueError naming ``name``."""
    return (c_double * n)(*numbers(values, name, n))


def as_double(value, name: str) -> float:
    """A Python number as a float (the library judges its value); other
    types are a ValueError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        try:
            import numpy
            if isinstance(value, (numpy.integer, numpy.floating)):
                return float(value)
        except ImportError:
            pass
        raise ValueError(f"{name} must be a number, got {value!r}")
    return float(value)


def as_name(value, name: str) -> bytes:
    """A name (str) as bytes for the library, which judges it."""
    if not isinstance(value, str):
        raise ValueError(f"{name} must be a name (str), got {value!r}")
    return value.encode()


def encode_path(path) -> bytes:
    return os.fsencode(os.fspath(path))


def encode_name(name) -> bytes:
    """A name for the library (it checks the value and names it)."""
    if not isinstance(name, str):
        raise ValueError(f"a name must be a string, got {name!r}")
    return name.encode()
