"""Finite-element reference for the paper's piston test (verification only).

Not part of the product's physics (that is the C library's): an
independent solution of the same continuum problem, as the paper made
one, to measure the SPH error against. Plane-strain linear elasticity on
the 86 mm x 140 mm specimen, 9-node quadratic quadrilaterals
(scikit-fem), implicit Newmark (average acceleration, beta = 1/4,
gamma = 1/2), consistent mass. Boundary conditions as the SPH scene's
bonded ends: bottom fixed, top moving down at v (both components
prescribed), sides free; at rest at t = 0. Needs ``scikit-fem`` and
``scipy`` (``pip install scikit-fem``).
"""
from __future__ import annotations

import math
import time as wallclock

import numpy as np

__all__ = ["available", "piston_fe", "static_pattern"]


def available() -> bool:
    try:
        import scipy  # noqa: F401
        import skfem  # noqa: F401
    except ImportError:
        return False
    return True


def _setup(element_size: float, K: float, mu: float, rho0: float,
           x=(-0.043, 0.043), y=(0.0, 0.140)):
    from skfem import (Basis, BilinearForm, ElementQuad2, ElementVector,
                       MeshQuad, asm)
    from skfem.helpers import dot
    from skfem.models.elasticity import linear_elasticity
    nx = int(round((x[1] - x[0]) / element_size))
    ny = int(round((y[1] - y[0]) / element_size))
    mesh = MeshQuad.init_tensor(np.linspace(x[0], x[1], nx + 1),
                                np.linspace(y[0], y[1], ny + 1))
    basis = Basis(mesh, ElementVector(ElementQuad2()), intorder=4)
    lam = K - 2.0 * mu / 3.0
    stiffness = asm(linear_elasticity(lam, mu), basis)

    @BilinearForm
    def mass(u, v, w):
        return rho0 * dot(u, v)
    mass_matrix = asm(mass, basis)
    locs = basis.doflocs
    comp_x, comp_y = basis.split_indices()
    bottom = np.nonzero(np.isclose(locs[1], y[0]))[0]
    top = np.nonzero(np.isclose(locs[1], y[1]))[0]
    top_y = np.intersect1d(top, comp_y)
    fixed = np.union1d(bottom, top)
    return basis, stiffness, mass_matrix, fixed, top_y, lam


def _stress_sampler(basis, points, lam, mu, delta=1e-5):
    """Von Mises (full 3D plane-strain stress) at ``points`` from u, by
    central differences of the interpolated displacement (delta << the
    element size; across an element edge this averages the two sides)."""
    points = np.asarray(points, float).T          # (2, n)
    offsets = [(delta, 0), (-delta, 0), (0, delta), (0, -delta)]
    probes = [basis.probes(points + np.array(o)[:, None]) for o in offsets]
    n = points.shape[1]

    def sample(u):
        vals = [p @ u for p in probes]            # each (2n,): x comps, y
        ux = [vv[:n] for vv in vals]
        uy = [vv[n:] for vv in vals]
        dux_dx = (ux[0] - ux[1]) / (2 * delta)
        duy_dy = (uy[2] - uy[3]) / (2 * delta)
        dux_dy = (ux[2] - ux[3]) / (2 * delta)
        duy_dx = (uy[0] - uy[1]) / (2 * delta)
        exx, eyy, exy = dux_dx, duy_dy, 0.5 * (dux_dy + duy_dx)
        tr = exx + eyy
        sxx = lam * tr + 2 * mu * exx
        syy = lam * tr + 2 * mu * eyy
        szz = lam * tr
        sxy = 2 * mu * exy
        p = (sxx + syy + szz) / 3
        return np.sqrt(1.5 * ((sxx - p) ** 2 + (syy - p) ** 2 + (szz - p) ** 2
                              + 2 * sxy ** 2))
    return sample


def piston_fe(element_size: float, until: float, dt: float, grid,
              points: dict, K: float, mu: float, rho0: float,
              speed: float = 1.5e-3) -> dict:
    """Newmark run to ``until`` [s]; von Mises [Pa] at ``points`` sampled
    on ``grid`` [s] (linear interpolation between steps)."""
    from scipy.sparse.linalg import splu
    basis, Kmat, Mmat, fixed, top_y, lam = _setup(element_size, K, mu, rho0)
    ndof = Kmat.shape[0]
    free = np.setdiff1d(np.arange(ndof), fixed)
    beta, gamma = 0.25, 0.5
    A = (Kmat + Mmat / (beta * dt * dt)).tocsr()
    A_ff = A[free][:, free].tocsc()
    A_fd = A[free][:, fixed]
    lu = splu(A_ff)
    sample = _stress_sampler(basis, list(points.values()), lam, mu)
    u = np.zeros(ndof)
    v = np.zeros(ndof)
    v[top_y] = -speed
    a = np.zeros(ndof)
    grid = np.asarray(grid, float)
    out = np.zeros((len(points), len(grid)))
    t, k = 0.0, 0
    prev_vm = sample(u)
    start = wallclock.perf_counter()
    steps = int(math.ceil(until / dt - 1e-9))
    for _ in range(steps):
        t_new = t + dt
        u_d = np.zeros(ndof)
        u_d[top_y] = -speed * t_new
        rhs = Mmat @ (u / (beta * dt * dt) + v / (beta * dt)
                      + (0.5 / beta - 1.0) * a)
        u_new = u_d.copy()
        u_new[free] = lu.solve(rhs[free] - A_fd @ u_d[fixed])
        a_new = ((u_new - u) / (beta * dt * dt) - v / (beta * dt)
                 - (0.5 / beta - 1.0) * a)
        v = v + dt * ((1 - gamma) * a + gamma * a_new)
        u, a = u_new, a_new
        vm = sample(u)
        while k < len(grid) and grid[k] <= t_new + 1e-15:
            w = (grid[k] - t) / dt
            out[:, k] = (1 - w) * prev_vm + w * vm
            k += 1
        prev_vm, t = vm, t_new
    return {"element_size": element_size, "dt": dt, "dofs": ndof,
            "steps": steps, "wall": wallclock.perf_counter() - start,
            "vm": {name: out[i] for i, name in enumerate(points)}}


def static_pattern(element_size: float, points: dict, K: float, mu: float,
                   compression: float = 1e-6) -> dict:
    """Quasi-static solution with the top pushed down by ``compression``
    [m]: von Mises at ``points`` [Pa], the pattern the steady state of the
    piston test grows with."""
    from scipy.sparse.linalg import spsolve
    basis, Kmat, _, fixed, top_y, lam = _setup(element_size, K, mu, 1.0)
    ndof = Kmat.shape[0]
    free = np.setdiff1d(np.arange(ndof), fixed)
    u = np.zeros(ndof)
    u[top_y] = -compression
    Kc = Kmat.tocsr()
    u[free] = spsolve(Kc[free][:, free].tocsc(),
                      -Kc[free][:, fixed] @ u[fixed])
    vm = _stress_sampler(basis, list(points.values()), lam, mu)(u)
    return {name: float(vm[i]) for i, name in enumerate(points)}
