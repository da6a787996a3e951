# Over 600 lines: the Scene class, one wrapper of the library handle: many thin methods.
"""The Scene: bodies of particles, the effects they call for, and the arrays.

A :class:`Scene` owns one libsphsolid simulation handle. Bodies are added to
the library as soon as they are added to the scene (so overlapping bodies or
particles outside the domain fail at once, with the library's message), and
the particle arrays are numpy views of the library's own storage.
"""
from __future__ import annotations

import contextlib
import contextvars
import ctypes
from typing import Iterable, Mapping, Sequence

import numpy as np

from . import _lib
from ._lib import lib
from .builders import Body, Free
from .units import check_scale, length as _length, lengths as _lengths
from .units import quantity as _quantity

__all__ = ["Scene", "DEFAULT_SMOOTHING_RATIO", "allowing_large"]

#: h / dx used when a scene does not say otherwise (h = 1.2 dx, as in the paper)
DEFAULT_SMOOTHING_RATIO = 1.2

#: allow_large of the scenes that do not pass their own (allowing_large)
_ALLOW_LARGE = contextvars.ContextVar("sphsolid_allow_large", default=False)


@contextlib.contextmanager
def allowing_large(allow: bool = True):
    """Scenes built inside the ``with`` block take ``allow_large=allow``
    unless they pass their own: the scene builders (:mod:`sphsolid.scenes`,
    scene files, plans) build large scenes this way, as ``sphsolid ...
    --allow-large`` does::

        with sphsolid.allowing_large():
            scene = sphsolid.scenes.uniaxial_cylinder("0.5mm")
    """
    token = _ALLOW_LARGE.set(_lib.flag(allow, "allowing_large: allow"))
    try:
        yield
    finally:
        _ALLOW_LARGE.reset(token)


class _Buffer:
    """Exposes library memory to numpy and keeps the scene alive."""

    def __init__(self, owner, address, shape, writeable):
        self.owner = owner
        self.__array_interface__ = {
            "shape": shape, "typestr": "<f8", "version": 3,
            "data": (address, not writeable)}


class Scene:
    """Bodies of particles plus the effects the scene calls for.

    Parameters
    ----------
    dimension : int
        2 (plane strain) or 3.
    bodies : iterable of Body
        Added in order (see :meth:`add`).
    effects : mapping of str to mapping, optional
        Effects to switch on, by name, with their parameters, e.g.
        ``{"artificial_viscosity": {"alpha": 1.0, "beta": 0.0},
        "gravity": {"gy": -9.81}}``. Known names: see
        :func:`sphsolid.effect_names`; an unknown name is a ValueError.
    domain : (lo, hi), optional
        Bounding box [m]. A particle leaving it along a non-periodic axis
        stops the run. Without it space is unbounded.
    periodic : sequence of bool, optional
        Periodic axes (needs ``domain``).
    smoothing_ratio : float, optional
        h / dx, with dx the first body's spacing (default 1.2).
    kernel : {"cubic_spline", "wendland_c2", "cubic_o4"}
        Default "cubic_spline" (Monaghan 1992).
    allow_large : bool, optional
        Let a run take up to all of the memory available, not half of it
        (``sph_set_allow_large``); bodies beyond the limit are refused
        before they are built, naming the particle count and bytes.
        Default False, or the value of an enclosing
        :func:`allowing_large` block.

    Notes
    -----
    Before a scene is frozen (by a dynamics object, a calculator or
    :meth:`freeze`) the array properties return read-only copies, because
    adding a body moves the library's storage. After it, they are writable
    numpy views of the library's data (state fields) and bodies can no
    longer be added.
    """

    def __init__(self, dimension: int = 2, bodies: Iterable[Body] = (),
                 effects: Mapping[str, Mapping[str, float]] | None = None,
                 domain: tuple | None = None,
                 periodic: Sequence[bool] | None = None,
                 smoothing_ratio: float | None = None,
                 kernel: str = "cubic_spline", allow_large: bool | None = None):
        if dimension not in (2, 3) or isinstance(dimension, bool):
            raise ValueError(f"dimension must be 2 or 3, got {dimension!r}")
        self._handle = None
        self._handle = _lib.new_handle(dimension)
        if allow_large is None:
            allow_large = _ALLOW_LARGE.get()
        allow_large = _lib.flag(allow_large, "allow_large")
        self._check(lib.sph_set_allow_large(self._handle, allow_large),
                    "allow_large")
        self.dimension = dimension
        self.ncomp = _lib.stress_components(dimension)
        self.bodies: list[Body] = []
        self._materials: dict[int, tuple] = {}
        self._frozen = False
        self._views: dict[int, np.ndarray] = {}
        self._calc = None
        self._effects: dict[str, dict] = {}
        self.domain = None
        self.periodic = (False,) * dimension
        if not isinstance(kernel, str):
            raise ValueError(f"kernel must be a name (one of "
                             f"{_lib.kernel_names()}), got {kernel!r}")
        self._check(lib.sph_set_kernel_by_name(self._handle, kernel.encode()),
                    "kernel")
        self.kernel = kernel
        self.smoothing_ratio = DEFAULT_SMOOTHING_RATIO
        if smoothing_ratio is not None:
            self.set_smoothing_ratio(smoothing_ratio)
        if domain is not None or periodic is not None:
            if domain is None:
                raise ValueError("periodic needs a domain=(lo, hi)")
            self.set_domain(domain[0], domain[1], periodic)
        if effects is not None and not isinstance(effects, Mapping):
            raise ValueError(
                "Scene: effects must be a mapping of effect names to "
                "parameter mappings, e.g. {'artificial_viscosity': "
                f"{{'alpha': 1.0}}}}, got {type(effects).__name__} {effects!r}")
        for name, parameters in (effects or {}).items():
            if parameters is not None and not isinstance(parameters, Mapping):
                raise ValueError(
                    f"Scene: the parameters of effect {name!r} must be a "
                    f"mapping like {{'alpha': 1.0}}, got {parameters!r}")
            self.effect(name, **dict(parameters or {}))
        for body in bodies:
            self.add(body)

    # ---------------------------------------------------------- plumbing
    def _check(self, status, what=""):
        _lib.check(status, self._handle, what)

    def __del__(self):
        handle, self._handle = getattr(self, "_handle", None), None
        if handle:
            lib.sph_destroy(handle)

    @property
    def handle(self):
        """The ``sph_sim *`` handle (a ctypes c_void_p)."""
        return self._handle

    # ---------------------------------------------------- model settings
    def set_smoothing_ratio(self, ratio: float) -> None:
        """Set h / dx (dx: the first body's spacing); the library says
        which values it accepts."""
        value = _lib.as_double(ratio, "smoothing_ratio")
        self._check(lib.sph_set_smoothing_ratio(self._handle, value),
                    "smoothing_ratio")
        self.smoothing_ratio = value

    def set_kernel(self, kernel: str) -> None:
        """Set the kernel by name (one of the library's kernel names)."""
        if not isinstance(kernel, str):
            raise ValueError(f"kernel must be a name (one of "
                             f"{_lib.kernel_names()}), got {kernel!r}")
        self._check(lib.sph_set_kernel_by_name(self._handle, kernel.encode()),
                    "kernel")
        self.kernel = kernel

    def set_domain(self, lo: Sequence[float], hi: Sequence[float],
                   periodic: Sequence[bool] | None = None) -> None:
        """Bounding box [m] and periodic axes (set it before adding bodies
        for them to be checked against it)."""
        dim = self.dimension
        lo_d = list(_lengths(lo, "domain lo", dim))     # (0, "50mm") too
        hi_d = list(_lengths(hi, "domain hi", dim))
        lo3 = (ctypes.c_double * 3)(*(lo_d + [0.0] * (3 - dim)))
        hi3 = (ctypes.c_double * 3)(*(hi_d + [0.0] * (3 - dim)))
        if periodic is None:
            periodic = (False,) * dim
        if len(periodic) != dim:
            raise ValueError(f"periodic must have {dim} entries, got "
                             f"{periodic!r}")
        periodic = [_lib.flag(p, f"periodic[{i}]")
                    for i, p in enumerate(periodic)]
        flags = (ctypes.c_int * 3)(*([int(p) for p in periodic]
                                    + [0] * (3 - dim)))
        self._check(lib.sph_set_domain(self._handle, lo3, hi3, flags),
                    "domain")
        self.domain = (tuple(lo3[:dim]), tuple(hi3[:dim]))
        self.periodic = tuple(bool(p) for p in periodic)

    def effect(self, name: str, **parameters: float) -> None:
        """Switch an effect on, e.g. ``scene.effect("gravity", gy=-9.81)``.

        Parameters are passed to the library as ``key=value`` words; an
        unknown effect name or key is a ValueError that names it.
        """
        numbers = {k: _quantity(v, None, f"effect parameter {k}")
                   for k, v in parameters.items()}       # "-9.81m/s2" too
        words = " ".join(f"{k}={v!r}" for k, v in numbers.items())
        self._check(lib.sph_effect(self._handle, _lib.as_name(name, "effect"),
                                   words.encode()), "effect")
        self._effects[name] = numbers

    def effect_off(self, name: str) -> None:
        """Switch an effect off."""
        self._check(lib.sph_effect_off(self._handle,
                                       _lib.as_name(name, "effect")),
                    "effect")
        self._effects.pop(name, None)

    @property
    def effects(self) -> dict:
        """Effects switched on, with the parameters given for them."""
        return {k: dict(v) for k, v in self._effects.items()}

    # ------------------------------------------------------------ bodies
    def _material_index(self, material) -> int:
        key = id(material)
        if key not in self._materials:
            self._materials[key] = (material, material.add_to(self._handle))
        return self._materials[key][1]

    def add(self, body: Body) -> int:
        """Add a body; returns its index.

        Raises ValueError if it overlaps a body already there (closer than
        dx/2), lies outside the domain, has the wrong dimension or a name
        already used, or if a plate or piston is thinner than the kernel
        support 2h or sits against a body not in the scene.
        """
        if self._frozen:
            raise RuntimeError("the scene is frozen (a calculator or dynamics"
                               " uses it); build a new Scene to add bodies")
        if not isinstance(body, Body):
            raise ValueError(f"body must be a sphsolid.build.Body, got "
                             f"{type(body).__name__}")
        if body.dimension != self.dimension:
            raise ValueError(f"body {body.name!r} is {body.dimension}D but the"
                             f" scene is {self.dimension}D")
        against = None
        if body.shape in ("plate", "piston"):
            # the body itself, or (a scene rebuilt from copies of bodies)
            # the body of the same name
            found = ([i for i, b in enumerate(self.bodies) if b is body.against]
                     or [i for i, b in enumerate(self.bodies)
                         if b.name == body.against.name])
            if not found:
                raise ValueError(
                    f"{body.role} {body.name!r} sits against body "
                    f"{body.against.name!r}, which is not in this scene "
                    "(add it first)")
            against = found[0]
        material = self._material_index(body.material)
        what = f"body {body.name!r}"
        try:
            index = ctypes.c_int(body.add_to(self._handle, material, against))
        except ValueError as error:
            message = str(error)
            raise ValueError(message if message.startswith(what)
                             else f"{what}: {message}") from None
        # the body's extent as the library laid it (platens: and layers)
        extent = [(ctypes.c_double * 3)() for _ in range(3)]
        self._check(lib.sph_body_extent(self._handle, index.value, *extent),
                    what)
        dim = self.dimension
        lo, hi = tuple(extent[0][:dim]), tuple(extent[1][:dim])
        info = _lib.BodyInfo()
        self._check(lib.sph_body_info_get(self._handle, index.value,
                                          ctypes.byref(info)), what)
        check_scale(body.name, [b - a for a, b in zip(lo, hi)], body.dx,
                    info.count)
        if body.shape in ("plate", "piston"):
            body.lo, body.hi = lo, hi
            body.layers = int(round((hi[1] - lo[1]) / extent[2][1]))
        motion = body.motion
        kinds = {"free": _lib.MOTION_FREE, "fixed": _lib.MOTION_FIXED,
                 "velocity": _lib.MOTION_VELOCITY, "force": _lib.MOTION_FORCE}
        vector = motion.vector(body, self.dimension)
        if motion.kind == "rotation":
            self._check(lib.sph_set_rotation(
                self._handle, index.value,
                _lib.as_doubles(vector, self.dimension, "Rotation.centre"),
                _lib.as_doubles(motion.angular_velocity(self.dimension), 3,
                                "Rotation.omega")), what)
        elif not isinstance(motion, Free) or body.shape in ("plate",
                                                            "piston"):
            self._check(lib.sph_set_motion(
                self._handle, index.value, kinds[motion.kind],
                None if vector is None else
                _lib.as_doubles(vector, self.dimension, "motion")), what)
        if body.velocity is not None:
            self._check(lib.sph_set_body_velocity(
                self._handle, index.value,
                _lib.as_doubles(body.velocity, self.dimension, "velocity")),
                what)
        self.bodies.append(body)
        self._views.clear()
        return index.value

    def support_layers(self, spacing: float) -> int:
        """Rows of particles ``spacing`` [m] apart that a plate or piston
        needs to be one kernel support thick (``sph_support_layers``; 0
        until the first body sets the smoothing length)."""
        return int(lib.sph_support_layers(self._handle,
                                          _length(spacing, "spacing")))

    def _body_index(self, name: str) -> int:
        index = ctypes.c_int()
        self._check(lib.sph_body_find(self._handle, name.encode(),
                                      ctypes.byref(index)), "body")
        return index.value

    def static_platen_inset(self, body: str = "specimen") -> tuple:
        """(inset, offset): the platen inset [lattice steps] at which the
        quasi-static stiffness of ``body`` between a plate and a piston is
        exact for this scene's kernel and h/dx, and the end offset
        (L_eff - L)/2 [steps] left there (0 where such an inset exists;
        ``sph_static_platen_inset``)."""
        inset, offset = ctypes.c_double(), ctypes.c_double()
        self._check(lib.sph_static_platen_inset(
            self._handle, self._body_index(body), ctypes.byref(inset),
            ctypes.byref(offset)), "static platen inset")
        return inset.value, offset.value

    def platen_end_offset(self, body: str = "specimen",
                          inset: float = 0.0) -> float:
        """End offset (L_eff - L)/2 [lattice steps] of ``body`` between a
        plate and a piston laid ``inset`` steps in: how much longer the
        body answers quasi-statically, per end (``sph_platen_end_offset``;
        about 1.12 for the cubic spline at h/dx 1.2, 0.72 for cubic_o4 at
        1.65, at inset 0)."""
        offset = ctypes.c_double()
        self._check(lib.sph_platen_end_offset(
            self._handle, self._body_index(body),
            _lib.as_double(inset, "inset"), ctypes.byref(offset)),
            "platen end offset")
        return offset.value

    def body_slice(self, name: str) -> slice:
        """Particles of a body, as a slice into the arrays."""
        index = ctypes.c_int()
        self._check(lib.sph_body_find(self._handle, name.encode(),
                                      ctypes.byref(index)), "body")
        info = _lib.BodyInfo()
        self._check(lib.sph_body_info_get(self._handle, index.value,
                                          ctypes.byref(info)), "body")
        return slice(info.first, info.first + info.count)

    def body_counts(self) -> dict:
        """Particles per body, by name (from the library)."""
        counts = {}
        for i in range(lib.sph_body_count(self._handle)):
            info = _lib.BodyInfo()
            self._check(lib.sph_body_info_get(self._handle, i,
                                              ctypes.byref(info)), "body")
            counts[info.name.decode()] = info.count
        return counts

    def __len__(self) -> int:
        return int(lib.sph_particle_count(self._handle))

    @property
    def n_particles(self) -> int:
        """Number of particles of all bodies."""
        return len(self)

    def freeze(self) -> None:
        """Stop adding bodies; array properties become views from now on."""
        if len(self) == 0:
            raise ValueError("the scene has no particles; add a body first")
        self._frozen = True

    @property
    def frozen(self) -> bool:
        return self._frozen

    # ------------------------------------------------------------ arrays
    def _shape(self, field):
        n = len(self)
        if field in (_lib.FIELD_POSITION, _lib.FIELD_VELOCITY,
                     _lib.FIELD_ACCELERATION):
            return (n, self.dimension)
        if field in (_lib.FIELD_DEVIATORIC_STRESS, _lib.FIELD_STRESS):
            return (n, self.ncomp)
        return (n,)

    def _current(self) -> None:
        """Let a backend that keeps its own state copy it here first."""
        if self._calc is not None:
            self._calc.sync()

    def _copy(self, field) -> np.ndarray:
        self._current()
        out = np.empty(self._shape(field), dtype=np.float64)
        if out.size:
            self._check(lib.sph_field_copy(
                self._handle, field,
                out.ctypes.data_as(ctypes.POINTER(ctypes.c_double))), "field")
        return out

    def _state(self, field) -> np.ndarray:
        self._current()
        if not self._frozen:
            out = self._copy(field)
            out.flags.writeable = False
            return out
        view = self._views.get(field)
        if view is None:
            data = ctypes.POINTER(ctypes.c_double)()
            rows, cols = ctypes.c_size_t(), ctypes.c_size_t()
            self._check(lib.sph_field(self._handle, field, ctypes.byref(data),
                                      ctypes.byref(rows), ctypes.byref(cols)),
                        "field")
            shape = self._shape(field)
            if rows.value * cols.value != int(np.prod(shape)):
                raise RuntimeError(f"library field {field} has shape "
                                   f"{rows.value}x{cols.value}, expected "
                                   f"{shape}")
            address = ctypes.cast(data, ctypes.c_void_p).value
            view = np.asarray(_Buffer(self, address, shape, True))
            self._views[field] = view
        return view

    def _touch(self) -> None:
        """Tell the library that the state may have been written through
        the views (it then re-evaluates cached rates and, for positions,
        rebuilds its neighbour list). Results are unchanged: the same state
        gives the same rates."""
        data = ctypes.POINTER(ctypes.c_double)()
        for field in self._views:
            self._check(lib.sph_field(self._handle, field, ctypes.byref(data),
                                      None, None), "field")

    @property
    def positions(self) -> np.ndarray:
        """Particle positions [m], (n, dim)."""
        return self._state(_lib.FIELD_POSITION)

    @property
    def velocities(self) -> np.ndarray:
        """Particle velocities [m/s], (n, dim)."""
        return self._state(_lib.FIELD_VELOCITY)

    @property
    def density(self) -> np.ndarray:
        """Density [kg/m^3], (n,)."""
        return self._state(_lib.FIELD_DENSITY)

    @property
    def deviatoric_stress(self) -> np.ndarray:
        """Deviatoric stress S [Pa], (n, 4) as xx, yy, zz, xy in 2D; (n, 6)
        as xx, yy, zz, xy, xz, yz in 3D."""
        return self._state(_lib.FIELD_DEVIATORIC_STRESS)

    @property
    def masses(self) -> np.ndarray:
        """Particle masses [kg; kg per metre of depth in 2D], (n,)."""
        return self._state(_lib.FIELD_MASS)

    @property
    def pressure(self) -> np.ndarray:
        """Pressure c0^2 (rho - rho0) [Pa], (n,) (a copy, derived)."""
        return self._copy(_lib.FIELD_PRESSURE)

    @property
    def von_mises(self) -> np.ndarray:
        """von Mises stress sqrt(3/2 S:S) [Pa], (n,) (a copy, derived)."""
        return self._copy(_lib.FIELD_VON_MISES)

    @property
    def stress(self) -> np.ndarray:
        """Full Cauchy stress -P I + S [Pa], (n, ncomp) (a copy, derived)."""
        return self._copy(_lib.FIELD_STRESS)

    @property
    def accelerations(self) -> np.ndarray:
        """dv/dt of the last rate evaluation [m/s^2], (n, dim) (a copy)."""
        return self._copy(_lib.FIELD_ACCELERATION)

    # effect damage (docs/fracture.md): copies; RuntimeError while it is off
    @property
    def damage(self) -> np.ndarray:
        """Damage D in [0, 1] of each particle, (n,) (a copy)."""
        return self._copy(_lib.FIELD_DAMAGE)

    @property
    def fragments(self) -> np.ndarray:
        """Fragment id of each particle, (n,) int: connected regions of
        free-body particles with D < 1, numbered from 0; -1 for D = 1 and
        for prescribed bodies."""
        return self._copy(_lib.FIELD_FRAGMENT).astype(np.int64)

    @property
    def flaws(self) -> np.ndarray:
        """Number of flaws of each particle, (n,) int."""
        return self._copy(_lib.FIELD_FLAWS).astype(np.int64)

    @property
    def flaw_strain(self) -> np.ndarray:
        """Weakest activation strain of each particle, (n,) (inf: none)."""
        return self._copy(_lib.FIELD_FLAW_STRAIN)

    @property
    def active_flaws(self) -> np.ndarray:
        """Flaws active at each particle's current largest principal
        strain, (n,) int."""
        return self._copy(_lib.FIELD_ACTIVE_FLAWS).astype(np.int64)

    def reaction(self, body: str) -> np.ndarray:
        """The force [N; N/m in 2D] on a fixed or velocity-driven body
        (a plate, a piston) at the last rate evaluation, (dim,)."""
        self._current()
        index = ctypes.c_int()
        self._check(lib.sph_body_find(self._handle, body.encode(),
                                      ctypes.byref(index)), "body")
        out = np.zeros(3)
        self._check(lib.sph_body_reaction(
            self._handle, index.value,
            out.ctypes.data_as(ctypes.POINTER(ctypes.c_double))), "reaction")
        return out[:self.dimension]

    @property
    def body_ids(self) -> np.ndarray:
        """Body index of each particle, (n,) int32."""
        out = np.empty(len(self), dtype=np.int32)
        if out.size:
            self._check(lib.sph_body_ids(
                self._handle, out.ctypes.data_as(ctypes.POINTER(ctypes.c_int))),
                "body ids")
        return out

    # ----------------------------------------------------- time and model
    @property
    def h(self) -> float:
        """Smoothing length [m]."""
        return lib.sph_smoothing_length(self._handle)

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self.calc.time

    @property
    def step(self) -> int:
        """Steps taken."""
        return self.calc.step

    def energy(self, all_bodies: bool = False) -> dict:
        """Kinetic and elastic energy [J; J/m in 2D] and momentum of the free
        bodies (or all bodies), and the library's energy account
        (:meth:`energy_account`): ``work`` done by prescribed motions and
        applied forces, energy ``dissipated_damage``,
        ``dissipated_plastic`` (drucker_prager) and
        ``dissipated_viscosity`` since the account was switched on; while
        it is off nothing is kept and these four are None (not 0: a piston
        may have done work)."""
        all_bodies = _lib.flag(all_bodies, "all_bodies")
        self.calc.sync()
        info = _lib.EnergyInfo()
        self._check(lib.sph_energy(self._handle, int(all_bodies),
                                   ctypes.byref(info)), "energy")
        kept = bool(lib.sph_energy_account(self._handle))
        return {"kinetic": info.kinetic, "elastic": info.elastic,
                "momentum": np.array(info.momentum[:self.dimension]),
                "work": info.work if kept else None,
                "dissipated_damage": info.dissipated_damage if kept else None,
                "dissipated_plastic": info.dissipated_plastic if kept
                else None,
                "dissipated_viscosity": info.dissipated_viscosity if kept
                else None}

    def energy_account(self, on: bool = True) -> None:
        """Switch the library's energy account on (its totals restart from
        0) or off (``sph_set_energy_account``): with it, kinetic + elastic
        + dissipated - work of all bodies stays constant in a run without
        gravity or damping (docs/fracture.md).  ``on`` is True or False
        (``"no"`` is refused, not taken as true)."""
        on = _lib.flag(on, "energy_account: on")
        self._check(lib.sph_set_energy_account(self._handle, int(on)),
                    "energy account")

    # -------------------------------------------------------- checkpoints
    def write_checkpoint(self, path) -> None:
        """Write everything needed to continue the run bit for bit (state,
        time, step, dt, motions) with the library's
        ``sph_checkpoint_write`` (written to ``path.tmp``, then renamed)."""
        if self._calc is not None and self._calc.name != "c":
            self._calc.sync()      # another backend's state into the arrays
        self._require_library_clock("write_checkpoint")
        self._check(lib.sph_checkpoint_write(self._handle,
                                             _lib.encode_path(path)),
                    f"checkpoint {str(path)!r}")

    def read_checkpoint(self, path) -> None:
        """Continue from a checkpoint written by a scene built the same way
        (same bodies and particle counts, checked by the library)."""
        if self._calc is not None and self._calc.name != "c":
            raise _lib.UnsupportedError(
                f"Scene.read_checkpoint: the {self._calc.name!r} backend "
                "holds the state it advances outside the library; read the "
                "checkpoint into a scene on the C library backend")
        self._check(lib.sph_checkpoint_read(self._handle,
                                            _lib.encode_path(path)),
                    f"checkpoint {str(path)!r}")

    def _require_library_clock(self, what):
        """Refuse to write when the library's clock is not the backend's
        (a backend that advances the scene elsewhere must set it with
        sph_set_time, as the LAMMPS backend does)."""
        calc = self._calc
        if calc is None or calc.name == "c":
            return
        if (calc.time != lib.sph_time(self._handle)
                or calc.step != lib.sph_step_count(self._handle)):
            raise _lib.UnsupportedError(
                f"Scene.{what}: the {calc.name!r} backend is at step "
                f"{calc.step}, t = {calc.time!r} s, but the library's clock "
                f"is at step {lib.sph_step_count(self._handle)}")

    # -------------------------------------------------------- calculator
    @property
    def calc(self):
        """The calculator that advances this scene (default: the C library,
        :class:`sphsolid.calculators.CLibrary`)."""
        if self._calc is None:
            from .calculators import CLibrary
            self.calc = CLibrary()
        return self._calc

    @property
    def integrator(self) -> str:
        """The library integrator selected on this scene (by the last
        Dynamics object made on it, or a checkpoint read)."""
        return lib.sph_integrator_name(self._handle).decode()

    @property
    def has_calculator(self) -> bool:
        """True once a calculator is bound (reading :attr:`calc` binds the
        C library's on first use)."""
        return self._calc is not None

    @calc.setter
    def calc(self, calculator) -> None:
        if self._calc is not None and self._calc is not calculator:
            raise RuntimeError("the scene already has a calculator")
        self.freeze()
        calculator.bind(self)
        self._calc = calculator

    def __repr__(self):
        bodies = ", ".join(f"{b.name}: {b.count:,}" for b in self.bodies)
        clock = ""
        if self._calc is not None:
            clock = f", t={self.time:.6g} s, step {self.step}"
        return (f"Scene({self.dimension}D, {len(self):,} particles "
                f"[{bodies}], effects={sorted(self._effects)}{clock})")
