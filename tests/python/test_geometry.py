"""Specimen geometry from Python: cylinders, prisms, point sets and platens
against any body, laid by the library's builders."""
from __future__ import annotations

import math

import numpy as np
import pytest

import sphsolid
from sphsolid import build, scenes


@pytest.fixture
def rock():
    return scenes.paper_material()


def test_cylinder_particles_lie_inside_its_radius_on_the_lattice(rock):
    R, L, dx = 0.01, 0.02, 2e-3
    body = build.cylinder(R, L, dx, rock, base=(0.0, 0.005, 0.0))
    scene = sphsolid.Scene(3, [body])
    x = scene.positions
    # integer form of "inside": (2i+1-n)^2 + (2k+1-n)^2 < n^2, n = 2R/dx
    n, ny = round(2 * R / dx), round(L / dx)
    i = np.arange(n)
    a = (2 * i + 1 - n)[:, None] ** 2 + (2 * i + 1 - n)[None, :] ** 2
    assert len(x) == int((a < n * n).sum()) * ny
    assert np.all(x[:, 0] ** 2 + x[:, 2] ** 2 < R * R)
    assert x[:, 1].min() == pytest.approx(0.005 + dx / 2, abs=1e-15)
    np.testing.assert_array_equal(body.positions, x)
    # each particle carries rho0 times its lattice cell
    np.testing.assert_allclose(scene.masses, rock.rho0 * dx ** 3, rtol=1e-12)


def test_platens_sit_against_a_cylinder_with_its_columns(rock):
    dx = 2e-3
    specimen = build.cylinder(0.01, 0.02, dx, rock)
    plate, piston = build.plate(under=specimen), build.piston(over=specimen)
    scene = sphsolid.Scene(3, [specimen, plate, piston])
    layers = math.ceil(2 * 1.2 * dx / dx - 1e-9)       # ceil(2h/dy), dy = dx
    assert plate.layers == piston.layers == layers
    xs = scene.positions[scene.body_slice("specimen")]
    xp = scene.positions[scene.body_slice("plate")]
    xq = scene.positions[scene.body_slice("piston")]
    assert len(xp) == len(xq) == 10 * 10 * layers     # a square slab
    assert xp[:, 1].max() == pytest.approx(xs[:, 1].min() - dx, abs=1e-15)
    assert xq[:, 1].min() == pytest.approx(xs[:, 1].max() + dx, abs=1e-15)
    bottom = {(round(p[0] / dx, 6), round(p[2] / dx, 6))
              for p in xs if p[1] < dx}
    top_of_plate = {(round(p[0] / dx, 6), round(p[2] / dx, 6))
                    for p in xp if p[1] > -dx}
    assert bottom <= top_of_plate
    v = scene.velocities[scene.body_slice("piston")]
    np.testing.assert_array_equal(v, np.tile([0.0, -1.5e-3, 0.0], (len(v), 1)))


def test_plate_sits_under_a_disc_in_2d(rock):
    dx = 1e-3
    disc = build.disc((0.0, 0.0), 0.01, dx, rock)
    scene = sphsolid.Scene(2, [disc, build.plate(under=disc)])
    xd = scene.positions[scene.body_slice("disc")]
    xp = scene.positions[scene.body_slice("plate")]
    assert xp[:, 1].max() == pytest.approx(xd[:, 1].min() - dx, abs=1e-12)
    assert xp[:, 0].min() == pytest.approx(xd[:, 0].min(), abs=1e-12)
    assert xp[:, 0].max() == pytest.approx(xd[:, 0].max(), abs=1e-12)


def test_prism_stands_on_its_base(rock):
    body = build.prism(0.01, 0.006, 0.02, 1e-3, rock, base=(0.0, 0.01, 0.0))
    scene = sphsolid.Scene(3, [body])
    assert len(scene) == 10 * 6 * 20
    lo, hi = body.bounds
    assert lo == pytest.approx((-0.005, 0.01, -0.003))
    assert hi == pytest.approx((0.005, 0.03, 0.003))


def test_particles_take_their_volumes(rock):
    points = np.array([[0.0, 0.0], [2e-3, 0.0], [0.0, 2e-3]])
    volumes = np.array([4e-6, 3e-6, 5e-6])
    scene = sphsolid.Scene(2, [build.particles(points, 2e-3, rock,
                                               volumes=volumes)])
    np.testing.assert_allclose(scene.masses, rock.rho0 * volumes, rtol=1e-15)


def test_bad_geometry_is_refused_with_its_value(rock):
    # the library judges the radius when it lays the body
    with pytest.raises(ValueError, match=r"cylinder 'specimen': "
                       r"radius=-0\.01 m must be finite and > 0"):
        sphsolid.Scene(3, [build.cylinder(-0.01, 0.02, 1e-3, rock)])
    with pytest.raises(ValueError, match=r"shape \(3,\)"):
        build.particles(np.zeros(3), 1e-3, rock)
    specimen = build.cylinder(0.01, 0.02, 2e-3, rock)
    with pytest.raises(ValueError, match="not in this scene"):
        sphsolid.Scene(3, [build.plate(under=specimen)])
    with pytest.raises(ValueError, match="layers=2"):
        sphsolid.Scene(3, [specimen, build.plate(under=specimen, layers=2)])
    with pytest.raises(ValueError, match="is 3D but the scene is 2D"):
        sphsolid.Scene(2, [specimen])


def test_uniaxial_cylinder_scene_has_the_lab_specimen():
    scene = scenes.uniaxial_cylinder(dx=6e-3)
    x = scene.positions[scene.body_slice("specimen")]
    R = scenes.CYLINDER_DIAMETER / 2
    assert np.all(x[:, 0] ** 2 + x[:, 2] ** 2 < R * R)
    assert x[:, 1].min() > 0 and x[:, 1].max() < scenes.CYLINDER_LENGTH
    assert set(scene.body_counts()) == {"specimen", "plate", "piston"}


def test_cli_piston_in_3d_writes_the_cylinder_outputs(tmp_path):
    from test_probes_and_figures import cli
    run = cli("piston", "--dim", "3", "--dx", "9mm", "--until", "0.02ms",
              "--out", str(tmp_path))
    assert run.returncode == 0, run.stderr
    specimen = sphsolid.Scene(3, [build.cylinder(
        scenes.CYLINDER_DIAMETER / 2, scenes.CYLINDER_LENGTH, 9e-3,
        scenes.paper_material())])
    assert f"specimen {len(specimen)}," in run.stdout
    for name in ("piston.h5", "piston.xmf", "piston_probes.csv",
                 "piston_probes.png", "piston_von_mises.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    header = (tmp_path / "piston_probes.csv").read_text().splitlines()[0]
    assert "D_von_mises_Pa" in header and "A_sigma_yz_Pa" in header
