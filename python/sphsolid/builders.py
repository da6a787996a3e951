# Over 600 lines: every body builder with its documented options; each calls an sph_add_*.
"""Builders of bodies: blocks, prisms, cylinders, point sets, plates,
pistons, discs, rings.

Each builder returns a :class:`Body`, a description that a
:class:`~sphsolid.Scene` turns into particles with the library's own
builders: ``sph_add_block`` (per axis ``n = round(L/dx)`` particles with
centres at ``lo + (i + 1/2) L/n``), ``sph_add_prism``,
``sph_add_cylinder`` (axis along y), ``sph_add_plate`` and
``sph_add_piston`` (against any body), ``sph_add_particles`` (your own
points, :func:`particles`). Discs and rings are the lattice points of
their bounding block that fall inside them, passed as points.

Lengths, velocities, forces and pressures are SI numbers or strings with
a unit (``dx="1mm"``, ``lo=("0mm", "0mm")``, ``Velocity((0, "-1.5mm/s"))``,
see :mod:`sphsolid.units`).

Motions (:class:`Free`, :class:`Fixed`, :class:`Velocity`, :class:`Force`,
:class:`Pressure`, :class:`Rotation`) say how a body moves. A piston or plate is a body of
particles at least one kernel support (2h) thick whose density and
deviatoric stress evolve like the specimen's; only its motion is
prescribed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import ctypes

import numpy as np

from . import _lib
from ._lib import lib
from .material import Material
from .units import length as _length, lengths as _lengths, \
    quantities as _quantities, quantity as _quantity

__all__ = ["Body", "Motion", "Free", "Fixed", "Velocity", "Force",
           "Pressure", "Rotation", "block", "rectangle", "box", "prism",
           "cylinder", "particles", "plate", "piston", "disc", "ring"]


# ------------------------------------------------------------------ motions

class Motion:
    """How a body moves (base class)."""

    kind = "free"

    def vector(self, body: "Body", dim: int):
        """The vector passed to ``sph_set_motion`` (or None)."""
        return None


@dataclass(frozen=True)
class Free(Motion):
    """Integrated by the SPH equations (the default)."""

    kind = "free"


@dataclass(frozen=True)
class Fixed(Motion):
    """Does not move (density and stress still evolve)."""

    kind = "fixed"


def _vector(name, values, dim, kind=None):
    vec = list(_quantities(values, kind, name))   # "1.5mm/s" too
    if len(vec) != dim:
        raise ValueError(f"{name} must have {dim} entries (one per "
                         f"dimension), got {len(vec)}")
    if not all(math.isfinite(v) for v in vec):
        raise ValueError(f"{name} must be finite, got {values!r}")
    return vec


@dataclass(frozen=True)
class Velocity(Motion):
    """Moves at a prescribed constant velocity [m/s] (a piston)."""

    velocity: Sequence[float]
    kind = "velocity"

    def __post_init__(self):
        _quantities(self.velocity, "velocity", "Velocity.velocity", (2, 3))

    def vector(self, body, dim):
        return _vector("Velocity.velocity", self.velocity, dim, "velocity")


@dataclass(frozen=True)
class Force(Motion):
    """Rigid translation under a constant applied force plus the SPH forces.

    ``force`` is the total force on the body [N; N per metre of depth in
    2D].
    """

    force: Sequence[float]
    kind = "force"

    def __post_init__(self):
        _quantities(self.force, "force", "Force.force", (2, 3))

    def vector(self, body, dim):
        return _vector("Force.force", self.force, dim, "force")


@dataclass(frozen=True)
class Pressure(Motion):
    """Rigid translation under a pressure on a face of a block.

    The total force is ``pressure * area`` along ``direction`` (a unit
    vector, default -y: pushing down), with ``area`` the block's extent
    across ``direction`` (its width in 2D, per metre of depth).

    Parameters
    ----------
    pressure : float
        [Pa], > 0.
    direction : sequence of float
        Direction of the push, one of the coordinate axes (+ or -).
    """

    pressure: float
    direction: Sequence[float] = (0.0, -1.0)
    kind = "force"

    def vector(self, body, dim):
        p = _quantity(self.pressure, "pressure", "Pressure.pressure")
        if not (math.isfinite(p) and p > 0):
            raise ValueError(f"Pressure.pressure must be > 0 Pa, got "
                             f"{self.pressure!r}")
        direction = _vector("Pressure.direction", self.direction, dim)
        axes = [i for i, d in enumerate(direction) if d != 0.0]
        if len(axes) != 1 or abs(direction[axes[0]]) != 1.0:
            raise ValueError("Pressure.direction must be a coordinate axis "
                             f"such as (0, -1), got {self.direction!r}")
        lo, hi = body.bounds
        area = 1.0
        for i in range(dim):
            if i != axes[0]:
                area *= hi[i] - lo[i]
        return [p * area * d for d in direction]


@dataclass(frozen=True)
class Rotation(Motion):
    """A prescribed rigid rotation at constant angular velocity.

    Every particle moves exactly along its arc about ``centre`` with
    velocity ``omega x (x - centre)``; density and stress evolve through
    the SPH equations (the library's ``sph_set_rotation``).

    Parameters
    ----------
    omega : float or sequence of float
        Angular velocity [rad/s]: a number in 2D (about z, counter-clockwise
        positive), the rotation vector (3 numbers) in 3D.
    centre : sequence of float
        A point on the axis [m], one entry per dimension.
    """

    omega: float | Sequence[float]
    centre: Sequence[float]
    kind = "rotation"

    def angular_velocity(self, dim):
        """The rotation vector, 3 numbers."""
        if dim == 2:
            if isinstance(self.omega, (list, tuple, np.ndarray)):
                raise ValueError("Rotation.omega must be one number in 2D "
                                 f"(rad/s about z), got {self.omega!r}")
            w = _quantity(self.omega, "angular velocity", "Rotation.omega")
            if not math.isfinite(w):
                raise ValueError(f"Rotation.omega must be finite, got {self.omega!r}")
            return [0.0, 0.0, w]
        return _vector("Rotation.omega", self.omega, 3, "angular velocity")

    def vector(self, body, dim):
        return _vector("Rotation.centre", self.centre, dim, "length")


def _motion(motion) -> Motion:
    if motion is None:
        return Free()
    if isinstance(motion, Motion):
        return motion
    if motion == "free":
        return Free()
    if motion == "fixed":
        return Fixed()
    raise ValueError(f"motion must be 'free', 'fixed' or a Motion "
                     f"(Velocity, Force, Pressure, Rotation), got {motion!r}")


# -------------------------------------------------------------------- bodies

#: inset="static" is refused when the end offset left at the best inset
#: exceeds this many lattice steps.
STATIC_INSET_TOLERANCE = 0.05

_SHAPES = ("block", "points", "prism", "cylinder", "plate", "piston")


@dataclass
class Body:
    """A body: a material, particles on a lattice and a motion.

    Built by the functions of this module; added to a scene with
    ``Scene.add``, which lays its particles with the library's builder for
    its ``shape`` (``sph_add_block``, ``sph_add_particles``,
    ``sph_add_prism``, ``sph_add_cylinder``, ``sph_add_plate``,
    ``sph_add_piston``). Before that, :attr:`positions`, :attr:`count` and
    :attr:`bounds` ask the same builders on a scratch handle (platens with
    the default h = 1.2 dx).

    Attributes
    ----------
    name : str
    material : Material
    dx : float
        Lattice spacing [m].
    motion : Motion
    velocity : sequence of float or None
        Initial velocity of every particle [m/s] (free bodies).
    role : str
        "specimen", "plate", "piston" or "".
    shape : str
        One of "block", "points", "prism", "cylinder", "plate", "piston".
    lo, hi : tuple or None
        Corners of a block or prism [m]; for a platen, its extent once
        added to a scene.
    points, volumes : ndarray or None
        Particle centres [m] and volumes [m^dim] of a "points" body.
    against : Body or None
        The body a plate or piston sits against.
    layers : int or None
        Layers of a plate or piston (None: the least that is 2h thick).
    inset : float or "static"
        Plate or piston: laid this many lattice steps closer to the body
        (``sph_set_platen_inset``); "static": the inset that makes the
        quasi-static stiffness exact (``sph_static_platen_inset``).
    """

    name: str
    material: Material
    dx: float
    motion: Motion = field(default_factory=Free)
    lo: tuple | None = None
    hi: tuple | None = None
    points: np.ndarray | None = None
    velocity: Sequence[float] | None = None
    role: str = ""
    layers: int | None = None
    shape: str | None = None
    volumes: np.ndarray | None = None
    base: tuple | None = None
    radius: float | None = None
    length: float | None = None
    against: "Body | None" = None
    inset: float | str = 0.0
    #: particles per axis of a block or prism (the library's lattice, asked
    #: for once; not an init field, so a copy with another dx or extent,
    #: dataclasses.replace, asks again)
    counts: tuple | None = field(default=None, init=False, repr=False)

    def __post_init__(self):
        # what each shape needs; a shape not given follows from the fields
        needs = {"block": ("lo", "hi"), "prism": ("lo", "hi", "base"),
                 "points": ("points",), "cylinder": ("radius", "length"),
                 "plate": ("against",), "piston": ("against",)}
        if self.shape is None:
            given = [shape for shape in ("points", "cylinder", "block")
                     if all(getattr(self, k) is not None
                            for k in needs[shape])]
            if self.against is not None:
                given = [self.role] if self.role in ("plate", "piston") \
                    else given
            if len(given) != 1:
                raise ValueError(
                    f"Body {self.name!r}: give points (a point set), lo and "
                    "hi (a block), radius and length (a cylinder), or "
                    "against with role 'plate' or 'piston'; or build it "
                    "with sphsolid.build (block, particles, cylinder, ...)"
                    + (f"; the fields fit {' and '.join(given)}" if given
                       else ""))
            self.shape = given[0]
        if self.shape not in needs:
            raise ValueError(f"Body {self.name!r}: shape {self.shape!r} is "
                             f"not one of {', '.join(needs)}")
        missing = [k for k in needs[self.shape] if getattr(self, k) is None]
        if missing:
            raise ValueError(f"Body {self.name!r}: a {self.shape!r} body "
                             f"needs {' and '.join(missing)}")
        self.dx = _length(self.dx, "dx")
        for key in ("lo", "hi"):
            if getattr(self, key) is not None:
                setattr(self, key, _lengths(getattr(self, key), key))
        for key in ("radius", "length"):
            if getattr(self, key) is not None:
                setattr(self, key, _length(getattr(self, key), key))
        if self.base is not None:
            self.base = _lengths(self.base, "base")
        if self.shape == "points":
            self.points = _point_array(self.points)

    @property
    def dimension(self) -> int:
        if self.shape in ("plate", "piston"):
            return self.against.dimension
        if self.shape in ("prism", "cylinder"):
            return 3
        return len(self.lo) if self.lo is not None else self.points.shape[1]

    @property
    def lattice_shape(self) -> tuple:
        """Particles per axis of a block, ``round(L/dx)`` each."""
        if self.shape not in ("block", "prism"):
            raise ValueError(f"body {self.name!r} is not a block")
        if self.counts is None:
            self.counts = _block_lattice(self.name, self.lo, self.hi,
                                         self.dx)
        return self.counts

    def add_to(self, handle, material: int, against: int | None = None) -> int:
        """Lay this body's particles in a library handle with the library's
        builder for its shape; returns the body index. ``material`` is the
        material's index in the handle, ``against`` (platens) the index of
        the body the platen sits against."""
        index = ctypes.c_int()
        name = self.name.encode()
        dim = self.dimension
        ref = ctypes.byref(index)
        if self.shape == "block":
            lo = _lib.as_doubles(list(self.lo) + [0.0] * (3 - dim), 3, "lo")
            hi = _lib.as_doubles(list(self.hi) + [0.0] * (3 - dim), 3, "hi")
            status = lib.sph_add_block(handle, name, material, lo, hi, self.dx, ref)
        elif self.shape == "points":
            points = np.ascontiguousarray(self.points, dtype=np.float64)
            volumes = (None if self.volumes is None else
                       np.ascontiguousarray(self.volumes, dtype=np.float64))
            status = lib.sph_add_particles(
                handle, name, material, len(points),
                points.ctypes.data_as(ctypes.POINTER(ctypes.c_double)),
                None if volumes is None else
                volumes.ctypes.data_as(ctypes.POINTER(ctypes.c_double)),
                self.dx, ref)
        elif self.shape == "prism":
            base = _lib.as_doubles(self.base, 3, "base")
            width, height, depth = (h - l for l, h in zip(self.lo, self.hi))
            status = lib.sph_add_prism(handle, name, material, base, width,
                                       depth, height, self.dx, ref)
        elif self.shape == "cylinder":
            base = _lib.as_doubles(self.base, 3, "base")
            status = lib.sph_add_cylinder(handle, name, material, base,
                                          self.radius, self.length, self.dx,
                                          ref)
        else:
            status = self._add_platen(handle, name, material, against, ref)
        _lib.check(status, handle, f"body {self.name!r}")
        return index.value

    def _add_platen(self, handle, name, material, against, ref) -> int:
        """sph_add_plate or sph_add_piston at this platen's inset (the
        handle's inset is restored afterwards)."""
        inset = self.inset
        if isinstance(inset, str):
            value, left = ctypes.c_double(), ctypes.c_double()
            if lib.sph_static_platen_inset(handle, against,
                                           ctypes.byref(value),
                                           ctypes.byref(left)):
                raise ValueError(f"inset='static': "
                                 f"{lib.sph_errmsg(handle).decode()}")
            if abs(left.value) > STATIC_INSET_TOLERANCE:
                raise ValueError(
                    f"inset='static': no inset makes the static stiffness "
                    f"exact for this kernel and h/dx: the least end offset "
                    f"is {left.value:.3g} lattice steps (at inset "
                    f"{value.value:.3g}); give a number instead")
            inset = value.value
        before = lib.sph_platen_inset(handle)
        if inset != before:
            _lib.check(lib.sph_set_platen_inset(handle, inset), handle,
                       f"{self.role} {self.name!r}")
        try:
            if self.shape == "plate":
                return lib.sph_add_plate(handle, name, material, against,
                                         self.layers or 0, ref)
            return lib.sph_add_piston(handle, name, material, against,
                                      self.layers or 0, 0.0, ref)
        finally:
            if inset != before:
                lib.sph_set_platen_inset(handle, before)

    def _layout(self):
        """Positions, extent (lo, hi) and lattice step of this body as the
        library lays it, from a scratch handle."""
        chain = [self]
        while chain[-1].against is not None:
            chain.append(chain[-1].against)
        handle = _lib.new_handle(self.dimension)
        try:
            materials: dict[int, int] = {}
            index = None
            for body in reversed(chain):
                key = id(body.material)
                if key not in materials:
                    materials[key] = body.material.add_to(handle)
                index = body.add_to(handle, materials[key], index)
            n, dim = int(lib.sph_particle_count(handle)), self.dimension
            positions = np.empty((n, dim))
            _lib.check(lib.sph_field_copy(
                handle, _lib.FIELD_POSITION,
                positions.ctypes.data_as(ctypes.POINTER(ctypes.c_double))),
                handle, "positions")
            info = _lib.BodyInfo()
            _lib.check(lib.sph_body_info_get(handle, index, ctypes.byref(info)),
                       handle, "body")
            extent = [(ctypes.c_double * 3)() for _ in range(3)]
            _lib.check(lib.sph_body_extent(handle, index, *extent), handle,
                       "extent")
            lo, hi, step = (tuple(e[:dim]) for e in extent)
            return positions[info.first:info.first + info.count], lo, hi, step
        finally:
            lib.sph_destroy(handle)

    @property
    def positions(self) -> np.ndarray:
        """Particle centres [m], (count, dim), as the library lays them.

        Once in a scene, read ``Scene.positions``, the library's own.
        """
        if self.shape == "points":
            return self.points
        return self._layout()[0]

    @property
    def count(self) -> int:
        """Number of particles."""
        if self.shape == "points":
            return len(self.points)
        if self.shape == "block":
            return int(np.prod(self.lattice_shape))
        return len(self.positions)

    @property
    def bounds(self) -> tuple:
        """(lo, hi) of the body's extent [m]: its lattice cells (a block's
        corners, a cylinder's bounding box; points: their extent plus half a
        spacing), from the library's ``sph_body_extent``."""
        if self.lo is not None and self.shape != "points":
            return tuple(self.lo), tuple(self.hi)
        _, lo, hi, _ = self._layout()
        return lo, hi


def _block_lattice(name: str, lo, hi, dx: float, what: str = "") -> tuple:
    """Particles per axis of the block the library lays over [lo, hi] at
    dx (``sph_block_lattice``), after its checks: dx, the extents and the
    memory a run of that many particles needs, its message naming the
    value."""
    dim = len(lo)
    handle = _lib.new_handle(dim)
    try:
        count = (ctypes.c_long * 3)()
        _lib.check(lib.sph_block_lattice(
            handle, _lib.encode_name(name),
            _lib.as_doubles(list(lo) + [0.0] * (3 - dim), 3, "lo"),
            _lib.as_doubles(list(hi) + [0.0] * (3 - dim), 3, "hi"),
            _lib.as_double(dx, "dx"), count, None), handle,
            what or f"body {name!r}")
        return tuple(int(c) for c in count[:dim])
    finally:
        lib.sph_destroy(handle)


def _check_material(material):
    if not isinstance(material, Material):
        raise ValueError(f"material must be a sphsolid.Material, got "
                         f"{type(material).__name__}")
    return material


def _check_name(name):
    """A body name must be a str; the library judges it (empty, too long,
    already used) when the body is added to a scene."""
    if not isinstance(name, str):
        raise ValueError(f"name must be a str, got {name!r}")
    return name


def block(lo: Sequence[float], hi: Sequence[float], dx: float,
          material: Material, name: str = "block", motion=None,
          velocity=None, role: str = "") -> Body:
    """A block of particles on a square (cubic) lattice over [lo, hi].

    Parameters
    ----------
    lo, hi : sequence of float
        Corners [m], 2 or 3 entries each, ``hi > lo`` on every axis.
    dx : float
        Lattice spacing [m]; per axis ``round((hi - lo)/dx)`` particles.
    material : Material
    name : str
    motion : Motion or "free" or "fixed"
    velocity : sequence of float, optional
        Initial velocity [m/s].
    """
    dx = _length(dx, "dx")      # 0.001 or "1mm"
    _check_material(material)
    _check_name(name)
    lo = _lengths(lo, "lo", (2, 3))
    hi = _lengths(hi, "hi", (2, 3))
    if len(hi) != len(lo):
        raise ValueError(f"lo and hi must both have 2 or 3 entries, got "
                         f"lo={lo!r}, hi={hi!r}")
    counts = _block_lattice(name, lo, hi, dx)    # the library judges them
    if velocity is not None:
        velocity = _vector("velocity", velocity, len(lo), "velocity")
    body = Body(name=name, material=material, dx=dx, motion=_motion(motion),
                lo=lo, hi=hi, velocity=velocity, role=role, shape="block")
    body.counts = counts
    return body


def rectangle(x: Sequence[float], y: Sequence[float], dx: float,
              material: Material, name: str = "specimen", motion=None,
              velocity=None) -> Body:
    """A 2D rectangle x in [x0, x1], y in [y0, y1] [m] (see :func:`block`)."""
    x = _lengths(x, "rectangle x (x0, x1)", 2)
    y = _lengths(y, "rectangle y (y0, y1)", 2)
    return block((x[0], y[0]), (x[1], y[1]), dx, material, name, motion,
                 velocity, role="specimen")


def box(x, y, z, dx: float, material: Material, name: str = "specimen",
        motion=None, velocity=None) -> Body:
    """A 3D box x in [x0, x1], y in [y0, y1], z in [z0, z1] [m] (see
    :func:`block`)."""
    x, y, z = (_lengths(v, f"box {a} ({a}0, {a}1)", 2)
               for v, a in ((x, "x"), (y, "y"), (z, "z")))
    return block((x[0], y[0], z[0]), (x[1], y[1], z[1]), dx, material, name,
                 motion, velocity, role="specimen")


def layer_spacing(body: Body) -> float:
    """Distance between the particle rows (along y) of a body [m]: a block's
    L / round(L / dx); other shapes' lattice step from the library."""
    if body.shape in ("block", "prism"):
        return (body.hi[1] - body.lo[1]) / body.lattice_shape[1]
    return body._layout()[3][1]


def _check_inset(inset):
    """'static' or a number of lattice steps in the range the library
    accepts (``sph_set_platen_inset`` judges it and names it)."""
    if isinstance(inset, str):
        if inset != "static":
            raise ValueError(f"inset must be a number of lattice steps or "
                             f"'static', got {inset!r}")
        return inset
    value = _lib.as_double(inset, "inset")
    handle = _lib.new_handle(2)
    try:
        _lib.check(lib.sph_set_platen_inset(handle, value), handle, "inset")
    finally:
        lib.sph_destroy(handle)
    return value


def _platen(body, layers, material, name, motion, role, inset=0.0):
    if not isinstance(body, Body):
        raise ValueError(f"{role} needs a Body to sit against, got "
                         f"{type(body).__name__}")
    if layers is not None and (isinstance(layers, bool)
                               or not isinstance(layers, int) or layers < 1):
        raise ValueError(f"layers must be a positive integer or None, got "
                         f"{layers!r}")
    _check_name(name)
    material = body.material if material is None else _check_material(material)
    return Body(name=name, material=material, dx=body.dx,
                motion=_motion(motion), role=role, layers=layers, shape=role,
                against=body, inset=_check_inset(inset))


def plate(under: Body, layers: int | None = None,
          material: Material | None = None, name: str = "plate",
          motion="fixed", inset: float | str = 0.0) -> Body:
    """A plate under any body (a block, a disc, a cylinder), fixed by default.

    The library's ``sph_add_plate`` lays it against the body's face of
    least y, over the body's extent across y (x in 2D, x and z in 3D) with
    the body's lattice columns, ``layers`` layers of the body's lattice step
    dy thick. ``layers=None`` takes the least number that is one kernel
    support 2h thick, ``ceil(2h/dy)`` (3 at h = 1.2 dx); fewer is a
    ValueError when it is added to a scene.

    Parameters
    ----------
    under : Body
        The body the plate supports (added to the scene before the plate).
    layers : int, optional
    material : Material, optional
        Default: that of ``under``.
    inset : float or "static"
        End placement: the plate is laid ``inset`` lattice steps closer to
        the body (-1 < inset < 0.5; negative opens a gap). 0 (default) puts
        its face on the body's extent. "static" takes the inset at which
        the quasi-static stiffness of a body between plate and piston is
        exact for the scene's kernel and h/dx (``sph_static_platen_inset``:
        0.227 for cubic_o4 at h/dx 1.65, 0.396 for the cubic spline at
        1.2; none exists for some kernels, an error says so).
    """
    return _platen(under, layers, material, name, motion, "plate", inset)


def piston(over: Body, layers: int | None = None, velocity=None,
           material: Material | None = None, name: str = "piston",
           motion: Motion | None = None, inset: float | str = 0.0) -> Body:
    """A piston on top of any body, laid like :func:`plate` above it.

    Moves at the constant ``velocity`` [m/s] (default the paper's 1.5 mm/s
    downward, (0, -1.5e-3) in 2D, (0, -1.5e-3, 0) in 3D). Give
    ``motion=Pressure(p)`` or ``Force(F)`` for a load-controlled piston
    instead. ``inset``: the end placement, as for :func:`plate`.
    """
    if motion is None:
        if velocity is None:
            velocity = (0.0, -1.5e-3, 0.0)[:over.dimension]
        motion = Velocity(tuple(_vector("piston velocity", velocity,
                                        over.dimension, "velocity")))
    return _platen(over, layers, material, name, motion, "piston", inset)


def _base(base):
    if base is None:
        return (0.0, 0.0, 0.0)
    return _lengths(base, "base", 3)


def cylinder(radius: float, length: float, dx: float, material: Material,
             base: Sequence[float] | None = None, name: str = "specimen",
             motion=None, velocity=None) -> Body:
    """A circular cylinder (3D) with its axis along y, the loading axis.

    The library's ``sph_add_cylinder``: ``round(length/dx)`` layers, each
    the points of a square lattice of ``round(2 radius/dx)`` per side that
    lie strictly inside the circle; every particle has the volume of its
    lattice cell.

    Parameters
    ----------
    radius, length : float
        [m]; a laboratory specimen has length 2 to 2.5 diameters.
    dx : float
        Lattice spacing [m].
    material : Material
    base : sequence of 3 floats, optional
        Centre of the base (the face of least y) [m]; default the origin.
    """
    dx = _length(dx, "dx")
    _check_material(material)
    _check_name(name)
    # 0.027 or "27mm"; the library judges the values when it lays the body
    radius, length = _length(radius, "radius"), _length(length, "length")
    if velocity is not None:
        velocity = _vector("velocity", velocity, 3, "velocity")
    return Body(name=name, material=material, dx=dx, motion=_motion(motion),
                velocity=velocity, role="specimen", shape="cylinder",
                base=_base(base), radius=float(radius), length=float(length))


def prism(width: float, depth: float, height: float, dx: float,
          material: Material, base: Sequence[float] | None = None,
          name: str = "specimen", motion=None, velocity=None) -> Body:
    """A rectangular prism (3D): ``width`` along x, ``height`` along y (the
    loading axis), ``depth`` along z [m], its base centred on ``base``.

    The library's ``sph_add_prism`` (the lattice of a block).
    """
    centre = _base(base)
    width, depth, height = (_length(v, n) for v, n in ((width, "width"), (depth, "depth"),
                                                       (height, "height")))
    body = block((centre[0] - width / 2, centre[1], centre[2] - depth / 2),
                 (centre[0] + width / 2, centre[1] + height,
                  centre[2] + depth / 2), dx, material, name, motion,
                 velocity, role="specimen")
    body.shape = "prism"
    body.base = centre
    return body


def particles(points, dx: float, material: Material,
              volumes=None, name: str = "body", motion=None,
              velocity=None) -> Body:
    """A body from your own particle centres (any shape, 2D or 3D).

    Parameters
    ----------
    points : array_like, (n, 2) or (n, 3)
        Particle centres [m]; they must keep half a spacing from the
        particles of other bodies (checked when added to a scene).
    dx : float
        Nominal particle spacing [m]: it sets h (first body), the artificial
        stress reference and the platens' columns of a plate or piston laid
        against this body.
    material : Material
    volumes : array_like, (n,), optional
        Particle volumes [m^dim] (mass = rho0 x volume); default dx^dim.
    name : str
    motion : Motion or "free" or "fixed"
    velocity : sequence of float, optional
        Initial velocity [m/s].

    Examples
    --------
    A ball of radius 5 mm from a cubic lattice::

        g = (np.arange(10) - 4.5) * 1e-3
        p = np.stack(np.meshgrid(g, g, g), -1).reshape(-1, 3)
        ball = particles(p[(p ** 2).sum(1) < 0.005 ** 2], 1e-3, rock)
    """
    dx = _length(dx, "dx")
    _check_material(material)
    _check_name(name)
    pts = _point_array(points)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3) or len(pts) == 0:
        raise ValueError(f"points must be an (n, 2) or (n, 3) array with n "
                         f"> 0, got shape {pts.shape}")
    if volumes is not None:
        volumes = np.array(volumes, dtype=np.float64)
        if volumes.shape != (len(pts),):
            raise ValueError(f"volumes must have shape ({len(pts)},), got "
                             f"{volumes.shape}")
    if velocity is not None:
        velocity = _vector("velocity", velocity, pts.shape[1], "velocity")
    return Body(name=name, material=material, dx=dx, motion=_motion(motion),
                points=pts, volumes=volumes, velocity=velocity,
                shape="points")


def _point_array(points) -> np.ndarray:
    """Particle centres as an (n, dim) float array: an array as it is, a
    sequence of points whose coordinates may carry units row by row."""
    if isinstance(points, np.ndarray) and points.dtype.kind in "fiu":
        return np.array(points, dtype=np.float64)
    try:
        return np.array(points, dtype=np.float64)
    except (TypeError, ValueError):
        return np.array([_lengths(p, f"points[{i}]")
                         for i, p in enumerate(points)], dtype=np.float64)


def _annulus_points(center, r_inner, r_outer, counts):
    """The lattice points of the block [center - r_outer, center + r_outer]
    (``counts`` per axis, the library's) with r_inner <= r < r_outer."""
    center = np.asarray([float(c) for c in center])
    axes = [-r_outer + (np.arange(n) + 0.5) * (2 * r_outer / n)
            for n in counts]
    grids = np.meshgrid(*axes, indexing="ij")
    points = np.stack([g.ravel() for g in grids], axis=1)
    radius = np.sqrt((points ** 2).sum(axis=1))
    keep = (radius < r_outer) & (radius >= r_inner)
    points = points[keep] + center
    order = np.lexsort(points.T)  # x fastest, like blocks
    return points[order]


def disc(center: Sequence[float], radius: float, dx: float,
         material: Material, name: str = "disc", motion=None,
         velocity=None) -> Body:
    """A disc (2D) or ball (3D) of radius ``radius`` [m] at ``center`` [m].

    The particles are the points of the lattice of spacing ``dx`` over the
    bounding square inside the radius, each of volume dx^dim.
    """
    return ring(center, 0.0, radius, dx, material, name, motion, velocity)


def ring(center: Sequence[float], r_inner: float, r_outer: float, dx: float,
         material: Material, name: str = "ring", motion=None,
         velocity=None) -> Body:
    """A ring r_inner <= |r - center| < r_outer [m] on a lattice of spacing dx.
    """
    dx = _length(dx, "dx")
    _check_material(material)
    _check_name(name)
    center = _lengths(center, "center", (2, 3))
    r_inner = _length(r_inner, "r_inner")
    r_outer = _length(r_outer, "r_outer (radius)")
    # the bounding block's lattice, from the library: its checks of dx and
    # of the radius (an empty or too small block, too many particles)
    counts = _block_lattice(
        name, [c - r_outer for c in center], [c + r_outer for c in center],
        dx, f"{'ring' if r_inner else 'disc'} {name!r} of radius "
        f"{r_outer!r} m (its bounding square)")
    if not 0 <= r_inner < r_outer:
        raise ValueError(f"r_inner must be in [0, r_outer), got "
                         f"r_inner={r_inner!r}, r_outer={r_outer!r}")
    points = _annulus_points(center, r_inner, r_outer, counts)
    if len(points) == 0:
        raise ValueError(f"ring {name!r} holds no particle at dx={dx!r} m")
    if velocity is not None:
        velocity = _vector("velocity", velocity, len(center), "velocity")
    return Body(name=name, material=material, dx=dx, motion=_motion(motion),
                points=points, velocity=velocity, shape="points")
