#!/usr/bin/env python3
"""Linear stability limit of the library's leapfrog with Monaghan viscosity.

On the 2D square lattice (cubic spline), a plane wave exp(i k.x) of the
linearised scheme has the frequency omega(k) = c_p |g(k)|, with
g(k) = sum_b V_b sin(k.r) grad W(r) (docs/library.md, "Stable step"), and
the artificial viscosity (beta = 0) damps its velocity at the rate

    gamma(k) = alpha c0 h sum_b V_b (1 - cos k.r) |W'(r)| (k^.r)^2 / (r (r^2 + 0.01 h^2))

(the viscosity on every pair; the library applies it to approaching pairs
only).  The leapfrog takes the viscous force at the half-step velocity,
so one step of a mode is

    v+ = v + dt/2 a,  x' = x + dt v+,  a' = -omega^2 x' - gamma v+,  v' = v+ + dt/2 a'

and this prints the largest dt (in h/c0 and h/c_p) for which every mode
on a grid of the Brillouin zone has spectral radius <= 1.

    .venv/bin/python bench/leapfrog_viscous_limit.py [--h-over-dx 1.2]
        [--alpha 1 0.5 0] [--K 12.2e9 --mu 2.67e9]
"""
from __future__ import annotations

import argparse

import numpy as np


def lattice(h_over_dx: float):
    """Neighbour offsets within 2h (dx = 1), their distances and W'(r)."""
    h = h_over_dx
    reach = int(np.ceil(2 * h)) + 1
    pts = np.array([(i, j) for i in range(-reach, reach + 1)
                    for j in range(-reach, reach + 1)
                    if (i, j) != (0, 0) and np.hypot(i, j) < 2 * h], float)
    r = np.hypot(pts[:, 0], pts[:, 1])
    q = r / h
    sigma = 10.0 / (7.0 * np.pi) / h**2                  # 2D cubic spline
    dW = np.where(q < 1, sigma / h * (-3 * q + 2.25 * q * q),
                  -0.75 * sigma / h * (2 - q) ** 2)
    return h, pts, r, dW


def modes(h_over_dx: float, n: int = 40):
    """(|g(k)|, gamma(k) / (alpha c0)) over an n x n grid of k in (0, pi]."""
    h, pts, r, dW = lattice(h_over_dx)
    out = []
    for a in np.linspace(0.05, np.pi, n):
        for b in np.linspace(0.0, np.pi, n):
            k = np.array([a, b])
            kr = pts @ k
            g = (np.sin(kr) * dW / r) @ pts              # V_b = dx^2 = 1
            along = (pts @ (k / np.linalg.norm(k))) ** 2 / r
            gamma = h * ((1 - np.cos(kr)) * np.abs(dW) * along
                         / (r * r + 0.01 * h * h)).sum()
            out.append((np.linalg.norm(g), gamma))
    return h, out


def spectral_radius(omega: float, gamma: float, dt: float) -> float:
    """One step of a mode, state (x, v, a): the largest |eigenvalue|."""
    v_half = np.array([0.0, 1.0, dt / 2])
    x_new = np.array([1.0, 0.0, 0.0]) + dt * v_half
    a_new = -omega**2 * x_new - gamma * v_half
    v_new = v_half + dt / 2 * a_new
    return max(abs(np.linalg.eigvals(np.array([x_new, v_new, a_new]))))


def limit(h, table, cp_over_c0: float, alpha: float) -> float:
    """Largest stable dt in units of h/c0 (c0 = 1), by bisection."""
    low, high = 0.1, 4.0
    for _ in range(50):
        mid = 0.5 * (low + high)
        stable = all(spectral_radius(g * cp_over_c0, alpha * gam, mid * h)
                     <= 1 + 1e-6 for g, gam in table)
        low, high = (mid, high) if stable else (low, mid)
    return low


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--h-over-dx", type=float, default=1.2)
    parser.add_argument("--alpha", type=float, nargs="+", default=[0.0, 1.0, 0.5])
    parser.add_argument("--K", type=float, default=12.2e9, help="bulk modulus [Pa]")
    parser.add_argument("--mu", type=float, default=2.67e9, help="shear modulus [Pa]")
    args = parser.parse_args(argv)
    cp_over_c0 = np.sqrt((args.K + 4 * args.mu / 3) / args.K)
    h, table = modes(args.h_over_dx)
    print(f"cubic spline, h/dx = {args.h_over_dx}: max |g| h = "
          f"{max(g for g, _ in table) * h:.4f}; c_p / c0 = {cp_over_c0:.4f}")
    for alpha in args.alpha:
        dt = limit(h, table, cp_over_c0, alpha)
        print(f"  alpha {alpha:g} on every pair: stable dt < {dt:.3f} h/c0 = "
              f"{dt * cp_over_c0:.3f} h/c_p")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
