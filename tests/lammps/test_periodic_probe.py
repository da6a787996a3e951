"""A probe on a periodic boundary sees the atoms on both sides of it.

`compute sphsolid/probe` sums the owned atoms near its point at their
nearest image of it.  A 2D strip, periodic in x with width W = 20 dx,
starts with the shear velocity v_y = V sin(2 pi x / W).  The initial state,
the lattice (centres at x = -W/2 + (i + 1/2) dx) and the equations are all
symmetric under the reflection x -> -W/2 - x (about x = -W/4): v_y, rho,
sigma_xx, sigma_yy and sigma_zz are even under it, sigma_xy odd.  The probe
at x = -W/2 + 0.3 dx, whose kernel support reaches across the periodic
boundary, is the mirror image of the probe at x = -0.3 dx, inside the
strip, so the two record equal von Mises, pressure and normal stresses and
opposite shear stress.  A probe that missed the atoms across the boundary
would average one side of it only.  On 2 ranks (x split at 0) the inner
probe's atoms sit on both ranks, and so do the boundary probe's; both runs
record the same histories.
"""
from __future__ import annotations

import textwrap

import numpy as np

from conftest import read_probes, run_on_one_and_two_ranks

PERIODIC_STRIP = textwrap.dedent("""\
    plugin load ${plugin}
    units si
    dimension 2
    boundary p f p
    atom_style atomic
    atom_modify map array
    comm_modify vel yes
    processors ${px} 1 1
    region box block -0.01 0.01 -0.004 0.014 -0.0005 0.0005 units box
    create_box 1 box
    lattice sq 0.001 origin 0.5 0.5 0.0
    region strip block -0.01 0.01 0.0 0.01 -0.0005 0.0005 units box
    create_atoms 1 region strip
    mass 1 $(2300.0*0.001^2)
    pair_style sphsolid 0.001
    pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0
    neighbor 0.0003 bin
    neigh_modify every 1 delay 0 check yes
    variable vy atom 2.0*sin(2.0*PI*x/0.02)
    velocity all set 0.0 v_vy 0.0 units box
    fix integrate all sphsolid/improved_euler
    compute edge all sphsolid/probe -0.0097 0.005
    compute inside all sphsolid/probe -0.0003 0.005
    fix probes all ave/time 10 1 10 c_edge[*] c_inside[*] file probes.txt format " %.17g"
    run 80
    """)

# fix ave/time rows: step, then von Mises, pressure, sigma_xx, sigma_yy,
# sigma_zz, sigma_xy for each probe
VALUES = 6
EVEN = slice(0, 5)
SHEAR = 5


def test_probe_on_a_periodic_boundary_mirrors_one_inside(tmp_path, plugin):
    work1, work2, _ = run_on_one_and_two_ranks(tmp_path, PERIODIC_STRIP, {}, plugin)
    one, two = read_probes(work1 / "probes.txt"), read_probes(work2 / "probes.txt")
    assert one.shape == two.shape == (9, 1 + 2 * VALUES)  # steps 0, 10, ..., 80
    edge, inside = one[:, 1:1 + VALUES], one[:, 1 + VALUES:]
    scale = np.abs(one[:, 1:]).max()
    assert scale > 1.0e5  # the shear wave has built stress at both probes
    assert np.abs(inside[:, SHEAR]).max() > 0.1 * scale
    np.testing.assert_allclose(edge[:, EVEN], inside[:, EVEN], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(edge[:, SHEAR], -inside[:, SHEAR], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(two, one, rtol=0, atol=1e-10 * scale)
