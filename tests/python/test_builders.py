"""Builders and scenes give the particles the paper describes."""
import ctypes
import math

import numpy as np
import pytest

import sphsolid
from sphsolid import _lib, build, scenes


def test_paper_scene_has_12040_specimen_particles_at_1mm():
    scene = scenes.uniaxial_piston(dx=1e-3)
    # round(86 mm / 1 mm) x round(140 mm / 1 mm) lattice sites
    expected = round(0.086 / 1e-3) * round(0.140 / 1e-3)
    assert expected == 12040
    counts = scene.body_counts()
    assert counts["specimen"] == expected
    # piston and plate: 3 layers of the specimen's 86 columns each
    assert counts["piston"] == counts["plate"] == 3 * 86
    assert len(scene) == expected + 2 * 3 * 86


@pytest.mark.parametrize("dx, gravity", [(2e-3, False), (3e-3, False),
                                         (7e-3, True)])
def test_python_scene_matches_the_library_paper_scene(dx, gravity):
    """scenes.uniaxial_piston / scenes.gravity built from Python builders
    equal the library's own sph_build_paper_scene particle for particle,
    also where dx does not divide the specimen (walls on its row spacing,
    as many rows as the library's sph_support_layers asks)."""
    ours = scenes.gravity(dx=dx) if gravity else scenes.uniaxial_piston(dx=dx)
    theirs = sphsolid.Scene(2)
    info = _lib.PaperScene()
    _lib.check(_lib.lib.sph_build_paper_scene(theirs.handle, dx, 1.5e-3,
                                              int(gravity),
                                              ctypes.byref(info)),
               theirs.handle)
    assert len(ours) == len(theirs)
    for name in ("specimen", "plate") + (() if gravity else ("piston",)):
        a, b = ours.body_slice(name), theirs.body_slice(name)
        np.testing.assert_array_equal(ours.positions[a], theirs.positions[b])
        np.testing.assert_array_equal(ours.masses[a], theirs.masses[b])


def test_block_positions_follow_the_lattice_rule(rock):
    """Centres at lo + (i + 1/2) L / n with n = round(L / dx), x fastest."""
    body = build.rectangle((-0.043, 0.043), (0.0, 0.140), 3e-3, rock)
    scene = sphsolid.Scene(2, [body])
    nx, ny = round(0.086 / 3e-3), round(0.140 / 3e-3)
    x = -0.043 + (np.arange(nx) + 0.5) * 0.086 / nx
    y = 0.0 + (np.arange(ny) + 0.5) * 0.140 / ny
    expected = np.stack([np.tile(x, ny), np.repeat(y, nx)], axis=1)
    np.testing.assert_allclose(scene.positions, expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose(body.positions, expected, rtol=0, atol=1e-15)


def test_plate_and_piston_sit_below_and_above_the_specimen(rock):
    dx = 2e-3
    specimen = build.rectangle((-0.043, 0.043), (0.0, 0.140), dx, rock)
    scene = sphsolid.Scene(2, [specimen, build.plate(under=specimen),
                               build.piston(over=specimen)])
    plate = scene.positions[scene.body_slice("plate")]
    piston = scene.positions[scene.body_slice("piston")]
    # three layers: centres at -dx/2, -3dx/2, -5dx/2 below and above
    assert np.isclose(plate[:, 1].max(), -dx / 2)
    assert np.isclose(plate[:, 1].min(), -2.5 * dx)
    assert np.isclose(piston[:, 1].min(), 0.140 + dx / 2)
    assert np.isclose(piston[:, 1].max(), 0.140 + 2.5 * dx)
    assert np.isclose(piston[:, 0].min(), -0.043 + dx / 2)


def test_default_dt_is_half_h_over_c0_at_1mm():
    scene = scenes.uniaxial_piston(dx=1e-3)
    dyn = sphsolid.ImprovedEuler(scene)
    c0 = math.sqrt(12.2e9 / 2300.0)          # bulk sound speed, eq. (9)
    expected = 0.5 * 1.2e-3 / c0              # 0.5 h / c0, h = 1.2 dx
    assert dyn.dt == pytest.approx(expected, rel=1e-12)
    assert round(dyn.dt * 1e6, 3) == 0.261    # the paper's 0.261 us


def test_disc_and_ring_fill_their_area(rock):
    dx = 1e-3
    disc = build.disc((0.0, 0.0), 0.02, dx, rock, name="disc")
    ring = build.ring((0.1, 0.0), 0.01, 0.02, dx, rock, name="ring")
    # each particle carries dx^2 of area: counts approximate the areas
    assert disc.count * dx ** 2 == pytest.approx(math.pi * 0.02 ** 2, rel=0.02)
    assert ring.count * dx ** 2 == pytest.approx(
        math.pi * (0.02 ** 2 - 0.01 ** 2), rel=0.03)
    r = np.hypot(ring.positions[:, 0] - 0.1, ring.positions[:, 1])
    assert r.min() >= 0.01 and r.max() < 0.02
    scene = sphsolid.Scene(2, [disc, ring])
    np.testing.assert_array_equal(scene.positions[scene.body_slice("ring")],
                                  ring.positions)


def test_material_pairs_agree(rock):
    """(E, nu) and (K, nu) built from the (K, mu) material give it back."""
    K, mu = 12.2e9, 2.67e9
    E = 9 * K * mu / (3 * K + mu)                     # elasticity identity
    nu = (3 * K - 2 * mu) / (2 * (3 * K + mu))        # elasticity identity
    from_E = sphsolid.Material(E=E, nu=nu, rho0=2300)
    from_K = sphsolid.Material(K=K, nu=nu, rho0=2300)
    assert from_E.K == pytest.approx(K, rel=1e-12)
    assert from_E.mu == pytest.approx(mu, rel=1e-12)
    assert from_K.mu == pytest.approx(mu, rel=1e-12)
    assert rock.E == pytest.approx(E, rel=1e-12)
    assert rock.c0 == pytest.approx(math.sqrt(K / 2300), rel=1e-12)
    assert rock.c_p == pytest.approx(math.sqrt((K + 4 * mu / 3) / 2300),
                                     rel=1e-12)


def test_material_poisson_ratio_is_the_elastic_identity(rock):
    """nu = (3K - 2mu) / (2(3K + mu)) for an isotropic solid, so the (E, nu)
    a user gives comes back unchanged."""
    expected = (3 * 12.2e9 - 2 * 2.67e9) / (2 * (3 * 12.2e9 + 2.67e9))
    assert rock.nu == pytest.approx(expected, rel=1e-12)
    steel = sphsolid.Material(E=200e9, nu=0.3, rho0=7850)
    assert steel.nu == pytest.approx(0.3, rel=1e-12)


def test_state_arrays_are_views_of_the_library_data(coarse_piston):
    scene = coarse_piston
    scene.freeze()
    v = scene.velocities
    assert v.base is not None and not v.flags.owndata
    specimen = scene.body_slice("specimen")
    v[specimen] = (0.0, 1.0)     # every specimen particle at 1 m/s up
    energy = scene.energy()
    mass = scene.masses[specimen].sum()
    assert energy["kinetic"] == pytest.approx(0.5 * mass * 1.0, rel=1e-12)
    assert scene.velocities[specimen][0, 1] == 1.0


def test_arrays_before_freezing_are_read_only_copies(rock):
    scene = sphsolid.Scene(2, [build.rectangle((0, 0.01), (0, 0.01), 1e-3,
                                               rock)])
    x = scene.positions
    with pytest.raises(ValueError):
        x[0, 0] = 1.0


def test_pressure_piston_is_pushed_by_its_force(rock):
    """A pressure-loaded piston (Force = p x width, downward) starts moving
    down; the library reports its motion as 'force'."""
    dx = 4e-3
    specimen = build.rectangle((-0.043, 0.043), (0.0, 0.140), dx, rock)
    ram = build.piston(over=specimen, motion=build.Pressure(1e6))
    # Pressure resolves to the total force on the block's top face
    lo, hi = ram.bounds
    width = hi[0] - lo[0]
    assert ram.motion.vector(ram, 2) == [0.0, -1e6 * width]
    scene = sphsolid.Scene(2, [specimen, build.plate(under=specimen), ram])
    dyn = sphsolid.ImprovedEuler(scene)
    dyn.run(steps=20)
    v = scene.velocities[scene.body_slice("piston")]
    assert np.all(v[:, 1] < 0)
    assert np.allclose(v, v[0])          # rigid translation


def test_periodic_strip_wraps_and_stays_laterally_uniform(rock):
    """A strip periodic along x under a piston: every column sees the same
    load, so the stress is the same across x (to round-off)."""
    dx = 4e-3
    domain = ((-0.02, -0.05), (0.02, 0.2))
    strip = build.rectangle((-0.02, 0.02), (0.0, 0.1), dx, rock, name="strip")
    scene = sphsolid.Scene(
        2, [strip, build.plate(under=strip), build.piston(over=strip)],
        effects={"artificial_viscosity": {"alpha": 1.0, "beta": 0.0}},
        domain=domain, periodic=(True, False))
    dyn = sphsolid.ImprovedEuler(scene)
    dyn.run(steps=60)
    s_yy = scene.stress[scene.body_slice("strip"), 1].reshape(-1, 10)
    assert np.abs(s_yy).max() > 0
    spread = np.abs(s_yy - s_yy.mean(axis=1, keepdims=True)).max()
    assert spread <= 1e-9 * np.abs(s_yy).max()
