"""The damage effect from Python: material keys, fields, files, restarts,
and the fracture scenes (docs/fracture.md)."""
import numpy as np
import pytest

from sphsolid import Material, Scene, Trajectory
from sphsolid.build import rectangle
from sphsolid.dynamics import ImprovedEuler

ROCK = dict(K=12.2e9, mu=2.67e9, rho0=2300.0)


def tension_block(seed=11, k=1e22):
    """A free 2D block released from a uniform tension eps = 2e-3: about
    half its particles' weakest flaws lie below that strain."""
    rock = Material(**ROCK, weibull_k=k, weibull_m=6.0)
    block = rectangle((-0.02, 0.02), (-0.02, 0.02), 1e-3, rock, "block")
    scene = Scene(2, [block], effects={"damage": {"seed": seed},
                                       "artificial_viscosity": {}})
    scene.freeze()
    # P = c0^2 (rho - rho0) = -3 K eps
    scene.density[:] = 2300.0 * (1.0 - 3.0 * 2e-3)
    return scene


def test_weibull_keys_reach_the_library_and_bad_ones_are_named():
    rock = Material(**ROCK, weibull_k=1e20, weibull_m=6.0)
    assert (rock.weibull_k, rock.weibull_m) == (1e20, 6.0)
    with pytest.raises(ValueError, match="weibull_k"):
        Material(**ROCK, weibull_k=-1.0)
    with pytest.raises(ValueError, match="weibull_m"):
        Material(**ROCK, weibull_m=float("nan"))


def test_damage_fields_exist_only_with_the_effect():
    block = rectangle((0, 0.01), (0, 0.01), 1e-3, Material(**ROCK), "block")
    scene = Scene(2, [block])
    with pytest.raises(RuntimeError, match="effect damage is on"):
        _ = scene.damage


def test_damage_grows_and_is_written_to_hdf5_and_xdmf(tmp_path):
    scene = tension_block()
    dyn = ImprovedEuler(scene)
    with Trajectory(tmp_path / "t.h5", "w", scene) as traj:
        dyn.run(steps=100)
        traj.write()
        D, fragments = scene.damage, scene.fragments
    assert 0 < (D > 0).sum() < len(D)         # a field worth writing
    frame = Trajectory(tmp_path / "t.h5")[-1]
    assert np.array_equal(frame.damage, D)
    assert np.array_equal(frame.fragment, fragments)
    xmf = (tmp_path / "t.xmf").read_text()
    assert 'Attribute Name="damage"' in xmf
    assert 'Attribute Name="fragment"' in xmf


def test_restart_from_a_checkpoint_gives_bitwise_the_same_damage(tmp_path):
    first = tension_block()
    ImprovedEuler(first).run(steps=40)
    first.write_checkpoint(tmp_path / "c.h5")
    ImprovedEuler(first).run(steps=60)
    again = tension_block()
    again.read_checkpoint(tmp_path / "c.h5")
    ImprovedEuler(again).run(steps=60)
    grown = first.damage
    assert grown.max() > 0 and (grown > 0).sum() > 10
    assert np.array_equal(again.damage, grown)
    assert np.array_equal(again.positions, first.positions)


def test_the_seed_changes_the_draw_and_only_it():
    a, b, c = tension_block(1), tension_block(1), tension_block(2)
    assert np.array_equal(a.flaw_strain, b.flaw_strain)
    assert not np.array_equal(a.flaw_strain, c.flaw_strain)
    assert np.array_equal(a.flaws, b.flaws)

