"""Finite-element reference for the 3D cylinder (verification only).

Not part of the product's physics (that is the C library's): an
independent solution of the same continuum problem to measure the SPH
error against.  Static linear elasticity of the bonded-end cylinder
(D = 54 mm, L = 135 mm, K = 12.2 GPa, mu = 2.67 GPa): bottom face fixed,
top face displaced by (0, -delta, 0), lateral surface free.  By symmetry
one eighth is meshed: x >= 0 and z >= 0 (symmetry planes: u_x = 0 on
x = 0, u_z = 0 on z = 0) and y in [L/2, L] (the mid-plane moves rigidly
by -delta/2 along y, free to slide in x and z).  27-node quadratic
hexahedra (scikit-fem ElementHex2) on a tensor mesh of the quarter
disc mapped to the circle (an O-grid blend: square near the axis, circle at
the surface) times the half length.

The quasi-static slope of the axial stress at the centre under a piston at
speed v is d sigma_yy / dt = v * sigma_yy(delta = 1 m).
"""
from __future__ import annotations

import math
import time as wallclock

import numpy as np

__all__ = ["available", "centre_stress_per_displacement", "convergence"]


def available() -> bool:
    try:
        import scipy  # noqa: F401
        import skfem  # noqa: F401
    except ImportError:
        return False
    return True


def _disc_map(xi, eta, radius):
    """Map [0, 1]^2 to the quarter disc: a square core blended into the
    circle as max(xi, eta) -> 1 (nodes on xi or eta = 1 land on the
    circle, nodes on xi = 0 or eta = 0 stay on the symmetry planes)."""
    r_inf = np.maximum(xi, eta)
    r_2 = np.hypot(xi, eta)
    with np.errstate(invalid="ignore", divide="ignore"):
        circle = np.where(r_2 > 0, r_inf / r_2, 1.0)
    t = r_inf ** 2
    scale = (1.0 - t) + t * circle
    return radius * xi * scale, radius * eta * scale


def _graded(n: int, grading: float) -> np.ndarray:
    """n + 1 nodes on [0, 1], denser towards 1 (the bonded edge) for
    grading > 1: 1 - (1 - s)^grading."""
    s = np.linspace(0.0, 1.0, n + 1)
    return 1.0 - (1.0 - s) ** grading


def centre_stress_per_displacement(n: int, K: float = 12.2e9,
                                   mu: float = 2.67e9, radius: float = 0.027,
                                   length: float = 0.135, grading: float = 1.0) -> dict:
    """sigma_yy [Pa] at the centre for delta = 1 m of end displacement
    (compression: negative), on n x n elements over the quarter disc and
    round(n (L/2)/R) along the half length.  ``grading`` > 1 concentrates
    the elements towards the bonded edge (the circle where the end face
    meets the free surface, where the stress is singular), across the disc
    and along the length alike."""
    from skfem import Basis, ElementHex2, ElementVector, MeshHex, asm, condense, solve
    from skfem.models.elasticity import linear_elasticity

    start = wallclock.perf_counter()
    nz = max(1, int(round(n * (length / 2) / radius)))
    s = _graded(n, grading)
    mesh = MeshHex.init_tensor(s, length / 2 + (length / 2) * _graded(nz, grading), s)
    p = mesh.p.copy()
    p[0], p[2] = _disc_map(mesh.p[0], mesh.p[2], radius)
    mesh = MeshHex(p, mesh.t)
    basis = Basis(mesh, ElementVector(ElementHex2()), intorder=4)
    lam = K - 2.0 * mu / 3.0
    A = asm(linear_elasticity(lam, mu), basis)
    locs = basis.doflocs
    cx, cy, cz = basis.split_indices()
    tol = 1e-9 * length
    on = lambda values, target: np.abs(values - target) < tol  # noqa: E731
    x_sym = np.intersect1d(np.nonzero(on(locs[0], 0.0))[0], cx)
    z_sym = np.intersect1d(np.nonzero(on(locs[2], 0.0))[0], cz)
    mid_y = np.intersect1d(np.nonzero(on(locs[1], length / 2))[0], cy)
    top = np.nonzero(on(locs[1], length))[0]
    top_y = np.intersect1d(top, cy)
    delta = 1.0
    u = np.zeros(basis.N)
    u[mid_y] = -delta / 2
    u[top_y] = -delta
    fixed = np.unique(np.concatenate([x_sym, z_sym, mid_y, top]))
    u = solve(*condense(A, np.zeros(basis.N), x=u, D=fixed))
    # strain at the centre from the displacement interpolated at points a
    # small step d into the model (the field is a polynomial in the element)
    d = 1e-4 * radius
    points = np.array([[0.0, length / 2, 0.0], [d, length / 2, 0.0],
                       [0.0, length / 2 + d, 0.0], [0.0, length / 2, d]]).T
    probe = basis.probes(points) @ u
    ux, uy, uz = probe[:4], probe[4:8], probe[8:]
    exx = (ux[1] - ux[0]) / d
    eyy = (uy[2] - uy[0]) / d
    ezz = (uz[3] - uz[0]) / d
    sigma_yy = lam * (exx + eyy + ezz) + 2 * mu * eyy
    return {"n": n, "nz": nz, "grading": grading, "dofs": int(basis.N),
            "sigma_yy": float(sigma_yy),
            "wall_s": wallclock.perf_counter() - start}


def convergence(levels=(2, 4, 8), log=print, **kwargs) -> dict:
    """The centre's sigma_yy per unit displacement on refined meshes, the
    observed order and the Richardson-extrapolated value."""
    rows = []
    for n in levels:
        row = centre_stress_per_displacement(n, **kwargs)
        log(f"  FE n = {n}: {row['dofs']} dofs, sigma_yy/delta = "
            f"{row['sigma_yy']:.6e} Pa/m ({row['wall_s']:.1f} s)")
        rows.append(row)
    values = [r["sigma_yy"] for r in rows]
    result = {"levels": rows, "value": values[-1]}
    if len(values) >= 3:
        e1, e2 = values[-2] - values[-3], values[-1] - values[-2]
        if e1 != 0 and e2 != 0 and e1 / e2 > 0:
            ratio = levels[-1] / levels[-2]
            order = math.log(abs(e1 / e2)) / math.log(levels[-2] / levels[-3])
            result["order"] = order
            result["extrapolated"] = values[-1] + e2 / (ratio ** order - 1)
            result["error_estimate"] = abs(result["extrapolated"] - values[-1]) / abs(values[-1])
    return result
