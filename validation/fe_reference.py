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

__all__ = ["available", "piston_fe", "save_series", "static_pattern"]


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
              speed: float = 1.5e-3, progress=None, every: int = 500,
              extent=((-0.043, 0.043), (0.0, 0.140))) -> dict:
    """Newmark run to ``until`` [s]; von Mises [Pa] at ``points`` sampled
    on ``grid`` [s] (linear interpolation between steps), on the specimen
    ``extent`` ((x0, x1), (y0, y1)) [m] (default the paper's). ``progress``,
    if given, is called every ``every`` steps and at the end with the
    time reached and the result so far (the series filled up to that
    time), so that a long run can report and keep its partial series."""
    from scipy.sparse.linalg import splu
    basis, Kmat, Mmat, fixed, top_y, lam = _setup(element_size, K, mu, rho0,
                                                  *extent)
    ndof = Kmat.shape[0]
    free = np.setdiff1d(np.arange(ndof), fixed)
    beta, gamma = 0.25, 0.5
    A = (Kmat + Mmat / (beta * dt * dt)).tocsr()
    A_ff = A[free][:, free].tocsc()
    A_fd = A[free][:, fixed]
    # A is symmetric positive definite: a symmetric fill-reducing
    # ordering without pivoting keeps the factors 2-3 times smaller than
    # the default column ordering (same solution to round-off)
    lu = splu(A_ff, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
              options={"SymmetricMode": True})
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

    def result(done):
        return {"element_size": element_size, "dt": dt, "dofs": ndof,
                "steps": done, "wall": wallclock.perf_counter() - start,
                "filled": k,
                "vm": {name: out[i] for i, name in enumerate(points)}}
    for step in range(1, steps + 1):
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
        if progress is not None and (step % every == 0 or step == steps):
            progress(t, result(step))
    return result(steps)


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


def save_series(path, grid, result) -> None:
    """Write the series of :func:`piston_fe` (``result``, possibly partial:
    the grid up to the time reached) to ``path`` (npz: grid, one array per
    probe (A, B, C for the paper's), wall,
    dt, dofs, steps, element_size). Written to a temporary file and renamed,
    so a failed write leaves the last good file."""
    from pathlib import Path
    path = Path(path)
    k = result.get("filled", len(grid))
    tmp = path.with_name(path.name + ".part.npz")
    np.savez_compressed(tmp, grid=np.asarray(grid)[:k],
                        wall=result["wall"], dt=result["dt"],
                        dofs=result["dofs"], steps=result["steps"],
                        element_size=result["element_size"],
                        **{n: v[:k] for n, v in result["vm"].items()})
    tmp.replace(path)


def _paper():
    from sphsolid import scenes
    from sphsolid.probes import PAPER_PROBES
    return (scenes.paper_material(), (scenes.SPECIMEN_X, scenes.SPECIMEN_Y),
            scenes.PISTON_SPEED, PAPER_PROBES)


def _nu045():
    from sphsolid.planner import scenes as planned
    _, extent, speed, points = _paper()
    return planned.nearly_incompressible_material(), extent, speed, points


def _squat():
    from sphsolid.planner import scenes as planned
    return (planned.squat_material(), planned.SQUAT_EXTENT,
            planned.SQUAT_SPEED, planned.SQUAT_PROBES)


def _slender():
    from sphsolid.planner import scenes as planned
    return (planned.slender_material(), planned.SLENDER_EXTENT,
            planned.SLENDER_SPEED, planned.SLENDER_PROBES)


#: the scenes main() runs: material, extent, piston speed, probes
SCENES = {"piston": _paper, "piston_nu045": _nu045, "piston_squat": _squat,
          "piston_slender": _slender}


def main(argv=None) -> int:
    """``python -m validation.fe_reference --size 5e-4 --until 1e-3 --out
    docs/accuracy/fe_piston_0.5mm.npz``: one FE series of the paper's
    piston test at A, B, C on a 0.1 us grid, with the step the other series
    use (0.25 us x size / 2 mm, times ``--dt-factor``); the partial series
    is written every ``--every`` steps. ``--scene piston_squat`` (or
    ``piston_nu045``) runs that planner scene's specimen, material, piston
    speed and probes instead."""
    import argparse
    parser = argparse.ArgumentParser(description=main.__doc__.split(":")[0])
    parser.add_argument("--size", type=float, required=True,
                        help="element size [m]")
    parser.add_argument("--until", type=float, default=0.3e-3)
    parser.add_argument("--dt-factor", type=float, default=1.0)
    parser.add_argument("--every", type=int, default=500)
    parser.add_argument("--out", required=True)
    parser.add_argument("--scene", default="piston",
                        choices=sorted(SCENES))
    args = parser.parse_args(argv)
    for name in ("size", "until", "dt_factor"):
        value = getattr(args, name)
        if not (math.isfinite(value) and value > 0):
            parser.error(f"--{name.replace('_', '-')} must be positive, "
                         f"got {value!r}")
    if not available():
        parser.error("needs scikit-fem and scipy (pip install scikit-fem)")
    rock, extent, speed, points = SCENES[args.scene]()
    grid = np.linspace(0.0, args.until, int(round(args.until / 1e-7)) + 1)
    dt = 0.25e-6 * args.size / 2e-3 * args.dt_factor

    def progress(t, result):
        save_series(args.out, grid, result)
        print(f"t = {t * 1e6:.1f} us, {result['steps']} steps, "
              f"{result['wall']:.0f} s", flush=True)
    r = piston_fe(args.size, args.until, dt, grid, points, rock.K,
                  rock.mu, rock.rho0, speed, progress=progress,
                  every=args.every, extent=extent)
    print(f"{args.out}: {r['dofs']} dofs, {r['steps']} steps of "
          f"{dt * 1e6:g} us, {r['wall']:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
