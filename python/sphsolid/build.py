"""Builders of bodies on a lattice: blocks, plates, pistons, discs, rings.

Each builder returns a :class:`Body`, a description that a
:class:`~sphsolid.Scene` turns into particles in libsphsolid. Lattice
blocks are created by the library's own ``sph_add_block`` (per axis
``n = round(L/dx)`` particles with centres at ``lo + (i + 1/2) L/n``);
discs and rings are the lattice points of their bounding block that fall
inside them, passed to ``sph_add_particles``.

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

import numpy as np

from . import _lib
from ._lib import lib
from .material import Material
from .units import length as _length, quantity as _quantity, to_si as _to_si

__all__ = ["Body", "Motion", "Free", "Fixed", "Velocity", "Force",
           "Pressure", "Rotation", "block", "rectangle", "box", "plate", "piston",
           "disc", "ring"]


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
    vec = _lib.numbers(_to_si(values, kind, name), name)   # "1.5mm/s" too
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
        _lib.numbers(_to_si(self.velocity, "velocity", "Velocity.velocity"),
                     "Velocity.velocity", (2, 3))

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
        _lib.numbers(_to_si(self.force, "force", "Force.force"), "Force.force",
                     (2, 3))

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
        if body.lo is None:
            raise ValueError("Pressure needs a block body (its face area)")
        area = 1.0
        for i in range(dim):
            if i != axes[0]:
                area *= body.hi[i] - body.lo[i]
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
            try:
                w = float(self.omega)
            except TypeError:
                raise ValueError("Rotation.omega must be one number in 2D "
                                 f"(rad/s about z), got {self.omega!r}") from None
            if not math.isfinite(w):
                raise ValueError(f"Rotation.omega must be finite, got {self.omega!r}")
            return [0.0, 0.0, w]
        return _vector("Rotation.omega", self.omega, 3)

    def vector(self, body, dim):
        return _vector("Rotation.centre", self.centre, dim)


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

@dataclass
class Body:
    """A body: a material, particles on a lattice and a motion.

    Built by the functions of this module; added to a scene with
    ``Scene.add``. ``lo``/``hi`` are set for blocks (the library lays
    the lattice), ``points`` for other shapes.

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
        "specimen", "plate", "piston" or "" (plates and pistons are
        checked to be at least one kernel support thick).
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

    @property
    def dimension(self) -> int:
        return len(self.lo) if self.lo is not None else self.points.shape[1]

    @property
    def lattice_shape(self) -> tuple:
        """Particles per axis of a block, ``round(L/dx)`` each."""
        if self.lo is None:
            raise ValueError(f"body {self.name!r} is not a block")
        return tuple(int(round((h - l) / self.dx))
                     for l, h in zip(self.lo, self.hi))

    @property
    def positions(self) -> np.ndarray:
        """Particle centres [m], (count, dim): the lattice the library lays.

        For a block this repeats the library's rule (``lo + (i+1/2) L/n``)
        for inspection before a scene exists; once in a scene, read
        ``Scene.positions``, which are the library's own.
        """
        if self.points is not None:
            return self.points
        axes = [lo + (np.arange(n) + 0.5) * (hi - lo) / n
                for lo, hi, n in zip(self.lo, self.hi, self.lattice_shape)]
        grids = np.meshgrid(*axes, indexing="ij")
        # x varies fastest, as in the library's lattice loops
        return np.stack([g.T.ravel() if len(axes) == 2 else
                         g.transpose(2, 1, 0).ravel() for g in grids], axis=1)

    @property
    def count(self) -> int:
        """Number of particles."""
        if self.points is not None:
            return len(self.points)
        return int(np.prod(self.lattice_shape))

    @property
    def bounds(self) -> tuple:
        """(lo, hi) of the body's extent [m]."""
        if self.lo is not None:
            return tuple(self.lo), tuple(self.hi)
        half = 0.5 * self.dx
        return (tuple(self.points.min(axis=0) - half),
                tuple(self.points.max(axis=0) + half))


def _check_dx(dx) -> float:
    value = _length(dx, "dx")      # 0.001 or "1mm"
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"dx must be > 0 m, got {dx!r}")
    return value


def _check_memory(particles: float, dim: int, what: str) -> None:
    """Refuse, before numpy allocates them, more particles than a run could
    hold in the memory available (the library's estimate)."""
    handle = _lib.new_handle(dim)
    try:
        _lib.check(lib.sph_memory_check(handle, float(particles)), handle,
                   what)
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
    dx = _check_dx(dx)
    _check_material(material)
    _check_name(name)
    lo = tuple(_lib.numbers(_to_si(lo, "length", "lo"), "lo", (2, 3)))
    hi = tuple(_lib.numbers(_to_si(hi, "length", "hi"), "hi", (2, 3)))
    if len(hi) != len(lo):
        raise ValueError(f"lo and hi must both have 2 or 3 entries, got "
                         f"lo={lo!r}, hi={hi!r}")
    for axis, (l, h) in enumerate(zip(lo, hi)):
        if not (math.isfinite(l) and math.isfinite(h)) or h <= l:
            raise ValueError(f"hi[{axis}] must exceed lo[{axis}], got "
                             f"lo={lo!r}, hi={hi!r}")
        if round((h - l) / dx) < 1:
            raise ValueError(f"dx={dx!r} m is larger than the block's extent "
                             f"{h - l!r} m along axis {axis}")
    if velocity is not None:
        velocity = _vector("velocity", velocity, len(lo), "velocity")
    return Body(name=name, material=material, dx=dx, motion=_motion(motion),
                lo=lo, hi=hi, velocity=velocity, role=role)


def rectangle(x: Sequence[float], y: Sequence[float], dx: float,
              material: Material, name: str = "specimen", motion=None,
              velocity=None) -> Body:
    """A 2D rectangle x in [x0, x1], y in [y0, y1] [m] (see :func:`block`)."""
    x = _lib.numbers(x, "rectangle x (x0, x1)", 2)
    y = _lib.numbers(y, "rectangle y (y0, y1)", 2)
    return block((x[0], y[0]), (x[1], y[1]), dx, material, name, motion,
                 velocity, role="specimen")


def box(x, y, z, dx: float, material: Material, name: str = "specimen",
        motion=None, velocity=None) -> Body:
    """A 3D box (see :func:`block`)."""
    return block((x[0], y[0], z[0]), (x[1], y[1], z[1]), dx, material, name,
                 motion, velocity, role="specimen")


def layer_spacing(body: Body) -> float:
    """Distance between the particle rows (along y) of a block [m]."""
    return (body.hi[1] - body.lo[1]) / body.lattice_shape[1]


def _layered(body, layers, dx, material, below, name, motion, role):
    if body.lo is None:
        raise ValueError(f"{role} needs a block to sit against, got body "
                         f"{body.name!r}")
    if not isinstance(layers, int) or layers < 1:
        raise ValueError(f"layers must be a positive integer, got {layers!r}")
    # rows as far apart as the block's own (L / round(L / dx)), unless a
    # spacing is given: the library's paper scene lays them the same way
    row = (layer_spacing(body) if dx is None else _check_dx(dx))
    dx = body.dx if dx is None else _check_dx(dx)
    material = body.material if material is None else material
    lo, hi = list(body.lo), list(body.hi)
    if below:
        hi[1] = body.lo[1]
        lo[1] = body.lo[1] - layers * row
    else:
        lo[1] = body.hi[1]
        hi[1] = body.hi[1] + layers * row
    result = block(lo, hi, dx, material, name, motion, role=role)
    result.layers = layers
    return result


def plate(under: Body, layers: int = 3, dx: float | None = None,
          material: Material | None = None, name: str = "plate",
          motion="fixed") -> Body:
    """A plate of ``layers`` particle layers below a block, same width.

    Spans y in [y0 - layers dy, y0] under ``under`` (whose bottom is y0;
    dy its row spacing, :func:`layer_spacing`); fixed by default. The
    plate must be at least one kernel support thick (checked when added to
    a scene; :meth:`Scene.support_layers` gives the rows needed): 3 layers
    at h = 1.2 dx.

    Parameters
    ----------
    under : Body
        The block the plate supports.
    layers : int
    dx : float, optional
        Spacing [m] (default: that of ``under``).
    material : Material, optional
        (default: that of ``under``).
    """
    return _layered(under, layers, dx, material, True, name, motion, "plate")


def piston(over: Body, layers: int = 3, velocity=(0.0, -1.5e-3),
           dx: float | None = None, material: Material | None = None,
           name: str = "piston", motion: Motion | None = None) -> Body:
    """A piston of ``layers`` particle layers on top of a block, same width.

    Spans y in [y1, y1 + layers dy] over ``over`` (whose top is y1) and
    moves at the constant ``velocity`` [m/s] (default the paper's
    1.5 mm/s downward). Give ``motion=Pressure(p)`` or ``Force(F)`` for a
    load-controlled piston instead.
    """
    if motion is None:
        motion = Velocity(tuple(_vector("piston velocity", velocity,
                                        over.dimension, "velocity")))
    return _layered(over, layers, dx, material, False, name, motion,
                    "piston")


def _annulus_points(center, r_inner, r_outer, dx):
    center = np.asarray([float(c) for c in center])
    n = int(round(2 * r_outer / dx))
    _check_memory(float(n) ** len(center), len(center),
                  f"ring or disc of radius {r_outer!r} m at dx={dx!r} m")
    offsets = -r_outer + (np.arange(n) + 0.5) * (2 * r_outer / n)
    grids = np.meshgrid(*([offsets] * len(center)), indexing="ij")
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
    dx = _check_dx(dx)
    _check_material(material)
    _check_name(name)
    center = _lib.numbers(_to_si(center, "length", "center"), "center", (2, 3))
    r_inner = _lib.number(_to_si(r_inner, "length", "r_inner"), "r_inner")
    r_outer = _lib.number(_to_si(r_outer, "length", "r_outer (radius)"),
                          "r_outer (radius)")
    if not r_outer > 0:
        raise ValueError(f"r_outer (radius) must be > 0 m, got {r_outer!r}")
    if not 2 * r_outer >= dx:
        raise ValueError(f"{name!r}: radius {r_outer!r} m is below half the "
                         f"spacing dx={dx!r} m (no particle would fit)")
    if not 0 <= r_inner < r_outer:
        raise ValueError(f"r_inner must be in [0, r_outer), got "
                         f"r_inner={r_inner!r}, r_outer={r_outer!r}")
    points = _annulus_points(center, r_inner, r_outer, dx)
    if len(points) == 0:
        raise ValueError(f"ring {name!r} holds no particle at dx={dx!r} m")
    if velocity is not None:
        velocity = _vector("velocity", velocity, len(center), "velocity")
    return Body(name=name, material=material, dx=dx, motion=_motion(motion),
                points=points, velocity=velocity)
