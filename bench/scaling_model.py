#!/usr/bin/env python3
"""Cost model of the cylinder run on many MPI ranks (docs/scaling.md).

Per step, every rank computes the rates of its own particles and exchanges
the state of its ghost atoms (LAMMPS's forward communication; bulk
synchronous, so the slowest rank sets the pace):

  T_step = max over ranks [ n_local t_p + sum over messages (alpha + bytes / beta) ]

* t_p: compute time per particle-step on one core, measured (the plugin on
  one rank: its loop time over particles x steps);
* ghosts: the atoms within the ghost cutoff 2h + skin (2.4 dx + 0.3 dx) of
  a subdomain; each step sends 26 doubles per ghost atom, 208 bytes: LAMMPS's
  own forward exchange of x and v (6), the plugin's density and deviatoric
  stress before the first Improved Euler stage (1 + 6) and x, v, density and
  stress before the second (13);
* 3 exchanges per step, each 6 messages in 3D (one per face direction; a
  ghost cutoff longer than a subdomain needs more swaps, counted);
* subdomains: LAMMPS's processor grid for the box (the factorisation of P
  with the least subdomain surface, as `processors * * *` picks) with cut
  planes balanced per axis (as `balance shift xyz`: cuts at the quantiles
  of the particles along each axis); particle counts per subdomain and
  ghost shell counted on the particles' lattice (coarsened to about 2 M
  points for the large runs, each standing for its share of particles;
  the platens included).

Efficiency E(P) = (N t_p / P) / T_step; "balanced" is the same with equal
counts on every rank (recursive bisection, `-var rcb 1` in the deck):
(N t_p / P) / (N t_p / P + the largest exchange time).  Predictions for 10 M and 100 M
particles at 16 ... 1024 ranks with network figures of a cluster
(--alpha latency per message, --beta bandwidth per rank), and a check against
the 1- and 2-rank measurements on this machine (shared memory).

    python bench/scaling_model.py --t-particle 1.4e-6 [--measured-speedup 1.9
        --measured-comm 0.05] [--alpha 2e-6 --beta 5e9]
"""
from __future__ import annotations

import argparse
import itertools
import math

import numpy as np

D, L = 0.054, 0.135
BYTES_PER_GHOST_STEP = 26 * 8
EXCHANGES_PER_STEP = 3


def spacing_for(particles: float) -> float:
    """dx [m] that gives about `particles` (cylinder + 2 platens of 3
    layers over the square D x D): N(dx) = (pi/4 D^2 L + 6 D^2 dx)/dx^3."""
    dx = (math.pi / 4 * D * D * L / particles) ** (1 / 3)
    for _ in range(50):
        dx = ((math.pi / 4 * D * D * L + 6 * D * D * dx) / particles) ** (1 / 3)
    return dx


def sample_points(dx: float, count: int) -> tuple[np.ndarray, float]:
    """About `count` points on the particles' lattice coarsened to spacing
    s (the cylinder's lattice points and its two platens of 3 layers of dx
    over the square), each standing for (s/dx)^3 particles."""
    v_cyl = math.pi / 4 * D * D * L
    s = max(dx, (v_cyl / count) ** (1 / 3))
    n, ny = round(D / s), round(L / s)
    g = -D / 2 + (np.arange(n) + 0.5) * D / n
    x, z = np.meshgrid(g, g, indexing="ij")
    x, z = x.ravel(), z.ravel()
    inside = x * x + z * z < D * D / 4
    y = (np.arange(ny) + 0.5) * L / ny
    cyl = np.stack([np.tile(x[inside], ny), np.repeat(y, inside.sum()),
                    np.tile(z[inside], ny)], axis=1)
    weight = (L / ny) * (D / n) ** 2 / dx ** 3
    layers = max(1, round(3 * dx / s))
    plates = []
    for y0 in (-3 * dx, L):
        yp = y0 + (np.arange(layers) + 0.5) * 3 * dx / layers
        plates.append(np.stack([np.tile(x, layers), np.repeat(yp, len(x)),
                                np.tile(z, layers)], axis=1))
    plate_weight = (3 * dx / layers) * (D / n) ** 2 / dx ** 3
    points = np.concatenate([cyl] + plates)
    weights = np.concatenate([np.full(len(cyl), weight),
                              np.full(len(points) - len(cyl), plate_weight)])
    return points, weights


def processor_grid(P: int, box: np.ndarray) -> tuple[int, int, int]:
    """The factorisation px py pz = P of least subdomain surface."""
    best, grid = None, None
    for px in range(1, P + 1):
        if P % px:
            continue
        for py in range(1, P // px + 1):
            if (P // px) % py:
                continue
            pz = P // px // py
            a = box / np.array([px, py, pz])
            area = a[0] * a[1] + a[1] * a[2] + a[0] * a[2]
            if best is None or area < best - 1e-15:
                best, grid = area, (px, py, pz)
    return grid


def step_time(P: int, dx: float, t_p: float, alpha: float, beta: float,
              samples: int = 2_000_000) -> dict:
    points, weight = sample_points(dx, samples)
    lo, hi = points.min(axis=0), points.max(axis=0)
    grid = processor_grid(P, hi - lo)
    cuts = [np.quantile(points[:, a], np.linspace(0, 1, grid[a] + 1)) for a in range(3)]
    for a in range(3):
        cuts[a][0], cuts[a][-1] = lo[a], hi[a]
    cutoff = 2.7 * dx
    index = [np.clip(np.searchsorted(cuts[a], points[:, a], side="right") - 1, 0, grid[a] - 1)
             for a in range(3)]
    cell = (index[0] * grid[1] + index[1]) * grid[2] + index[2]
    local = np.bincount(cell, weights=weight, minlength=grid[0] * grid[1] * grid[2])
    order = np.argsort(points[:, 0], kind="stable")
    xs = points[order, 0]
    worst, total_ghost, worst_comm_share, worst_comm = 0.0, 0.0, 0.0, 0.0
    for i in range(grid[0]):
        a, b = np.searchsorted(xs, [cuts[0][i] - cutoff, cuts[0][i + 1] + cutoff])
        slab, w_slab = points[order[a:b]], weight[order[a:b]]
        for j, k in itertools.product(range(grid[1]), range(grid[2])):
            box_lo = np.array([cuts[0][i], cuts[1][j], cuts[2][k]])
            box_hi = np.array([cuts[0][i + 1], cuts[1][j + 1], cuts[2][k + 1]])
            near = np.all((slab > box_lo - cutoff) & (slab < box_hi + cutoff), axis=1)
            n_local = local[(i * grid[1] + j) * grid[2] + k]
            n_ghost = w_slab[near].sum() - n_local
            swaps = sum(2 * max(1, math.ceil(cutoff / (box_hi[d] - box_lo[d])))
                        for d in range(3) if grid[d] > 1)
            comm = EXCHANGES_PER_STEP * swaps * alpha + n_ghost * BYTES_PER_GHOST_STEP / beta
            compute = n_local * t_p
            worst_comm = max(worst_comm, comm)
            total_ghost += n_ghost
            if compute + comm > worst:
                worst = compute + comm
                worst_comm_share = comm / (compute + comm)
    loads = local
    total_local = local.sum()
    N = total_local
    ideal = N * t_p / P
    return {"P": P, "grid": grid, "particles": N, "dx": dx,
            "local_per_rank": N / P, "ghosts_per_rank": total_ghost / P,
            "imbalance": max(loads) / (N / P), "step_seconds": worst,
            "efficiency": ideal / worst, "comm_share_slowest": worst_comm_share,
            "efficiency_balanced": ideal / (ideal + worst_comm)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--t-particle", type=float, required=True,
                        help="measured compute time per particle-step on one core [s]")
    parser.add_argument("--alpha", type=float, default=2e-6, help="latency per message [s]")
    parser.add_argument("--beta", type=float, default=5e9, help="bandwidth per rank [B/s]")
    parser.add_argument("--ranks", type=int, nargs="+", default=[16, 64, 256, 1024])
    parser.add_argument("--particles", type=float, nargs="+", default=[1e7, 1e8])
    parser.add_argument("--check-dx", type=float, default=0.002,
                        help="spacing of the 1- and 2-rank measurement")
    parser.add_argument("--local-alpha", type=float, default=1e-6,
                        help="latency per message on this machine (shared memory)")
    parser.add_argument("--local-beta", type=float, default=2e9,
                        help="bandwidth per rank on this machine (shared memory)")
    parser.add_argument("--measured-speedup", type=float, default=None)
    parser.add_argument("--measured-comm", type=float, default=None,
                        help="LAMMPS's Comm share at 2 ranks")
    parser.add_argument("--measured-ghosts", type=float, default=None,
                        help="LAMMPS's Nghost per rank at 2 ranks")
    args = parser.parse_args(argv)
    print(f"t_p = {args.t_particle * 1e6:.3f} us per particle-step; {BYTES_PER_GHOST_STEP} B "
          f"per ghost atom per step in {EXCHANGES_PER_STEP} exchanges; ghost cutoff 2.7 dx")
    print(f"check at dx = {args.check_dx * 1e3:g} mm on this machine (alpha "
          f"{args.local_alpha * 1e6:g} us, beta {args.local_beta / 1e9:g} GB/s):")
    one = step_time(1, args.check_dx, args.t_particle, args.local_alpha, args.local_beta)
    two = step_time(2, args.check_dx, args.t_particle, args.local_alpha, args.local_beta)
    print(f"  2 ranks: grid {two['grid']}, {two['local_per_rank']:.0f} local and "
          f"{two['ghosts_per_rank']:.0f} ghost atoms per rank, imbalance "
          f"{two['imbalance']:.3f}, predicted speed-up "
          f"{one['step_seconds'] / two['step_seconds']:.2f}, comm share "
          f"{two['comm_share_slowest']:.1%}"
          + ("; measured:" if (args.measured_speedup or args.measured_comm is not None
                               or args.measured_ghosts) else "")
          + (f" speed-up {args.measured_speedup:.2f}" if args.measured_speedup else "")
          + (f" comm share {args.measured_comm:.1%}" if args.measured_comm is not None else "")
          + (f", Nghost {args.measured_ghosts:.0f} per rank" if args.measured_ghosts else ""))
    print(f"cluster (alpha {args.alpha * 1e6:g} us per message, beta {args.beta / 1e9:g} GB/s "
          "per rank):")
    print(f"{'particles':>10} {'dx [mm]':>8} {'ranks':>6} {'grid':>12} {'local/rank':>11} "
          f"{'ghosts/rank':>12} {'imbalance':>10} {'step [ms]':>10} {'comm share':>11} "
          f"{'efficiency':>11} {'balanced (rcb)':>15}")
    for n in args.particles:
        dx = spacing_for(n)
        for P in args.ranks:
            r = step_time(P, dx, args.t_particle, args.alpha, args.beta)
            print(f"{r['particles']:>10.3g} {dx * 1e3:>8.3f} {P:>6} {'x'.join(map(str, r['grid'])):>12} "
                  f"{r['local_per_rank']:>11.0f} {r['ghosts_per_rank']:>12.0f} "
                  f"{r['imbalance']:>10.3f} {r['step_seconds'] * 1e3:>10.2f} "
                  f"{r['comm_share_slowest']:>11.1%} {r['efficiency']:>11.1%} "
                  f"{r['efficiency_balanced']:>15.1%}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
