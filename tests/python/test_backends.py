"""The C library and LAMMPS backends agree on the same scene.

Both run the same equations through the same library code (LAMMPS calls
sph_rates_evaluate and the Heun stages on its own arrays); they differ only
in the order of the neighbour sums, so they agree to accumulated round-off.
Tolerance: 1e-8 of the largest magnitude of each compared quantity. Skipped
when the lammps module or the plugin (build*/lammps_plugin/sphsolidplugin.so
or $SPHSOLID_LAMMPS_PLUGIN) is not there.
"""
import numpy as np
import pytest

import sphsolid
from sphsolid import scenes

lammps_backend = pytest.importorskip("sphsolid.lammps")
if not lammps_backend.available():
    pytest.skip("LAMMPS backend unavailable (lammps module or plugin "
                "missing)", allow_module_level=True)

RELATIVE = 1e-8


def close(a, b, what):
    scale = max(np.abs(a).max(), np.abs(b).max(), 1e-300)
    assert np.abs(a - b).max() <= RELATIVE * scale, what


def run_both(make_scene, until, interval=5, dynamics=sphsolid.ImprovedEuler,
             steps=None, probe_outside="error"):
    results = []
    for backend in ("c", "lammps"):
        scene = make_scene()
        if backend == "lammps":
            scene.calc = lammps_backend.Lammps()
        probes = sphsolid.Probes(scene, scenes.PAPER_PROBES,
                                 outside=probe_outside)
        dyn = dynamics(scene)
        dyn.attach(probes, interval=interval)
        if steps is None:
            dyn.run(until=until)
        else:
            dyn.run(steps=steps)
        results.append((scene, probes, dyn))
    return results


@pytest.mark.parametrize("dynamics", [sphsolid.ImprovedEuler, sphsolid.Leapfrog])
def test_backends_agree_on_the_piston_scene(dynamics):
    """fix sphsolid/improved_euler or fix sphsolid/leapfrog against the library.  The
    leapfrog runs whole steps: a shortened last step makes LAMMPS set up
    again, which re-evaluates the rates at the whole-step velocity where the
    library carries those of the half step (docs/lammps)."""
    leapfrog = dynamics is sphsolid.Leapfrog
    (c, pc, dc), (l, pl, dl) = run_both(
        lambda: scenes.uniaxial_piston(4e-3), until=150.5e-6, dynamics=dynamics,
        steps=73 if leapfrog else None)
    assert c.calc.integrator == l.calc.integrator == dynamics.integrator
    if not leapfrog:
        assert dc.time == dl.time == 150.5e-6      # both land on t exactly
    assert dc.nsteps == dl.nsteps
    np.testing.assert_array_equal(pc.steps, pl.steps)
    for name in "ABC":
        for value in ("von_mises", "pressure", "sigma_yy"):
            close(pc[name][value], pl[name][value], f"{name} {value}")
    close(c.positions, l.positions, "positions")
    close(c.velocities, l.velocities, "velocities")
    close(c.density, l.density, "density")
    close(c.deviatoric_stress, l.deviatoric_stress, "deviatoric stress")
    # the wave has arrived at B: the comparison is not of zeros
    assert pc["B"]["von_mises"].max() > 1e3


@pytest.mark.parametrize("dynamics", [sphsolid.ImprovedEuler, sphsolid.Leapfrog])
def test_backends_agree_on_a_pressure_driven_piston(dynamics):
    # Pressure -> the library's SPH_MOTION_FORCE or fix sphsolid/force
    def make():
        specimen = sphsolid.rectangle(scenes.SPECIMEN_X, scenes.SPECIMEN_Y, 4e-3,
                                      scenes.paper_material(), "specimen")
        return sphsolid.Scene(2, [specimen, sphsolid.plate(under=specimen, layers=3),
                                  sphsolid.piston(over=specimen, layers=3,
                                                  motion=sphsolid.Pressure(1.0e6))],
                              effects={"artificial_viscosity": scenes.WAVE_VISCOSITY})

    (c, pc, _), (l, pl, _) = run_both(make, until=100e-6, interval=10,
                                      dynamics=dynamics,
                                      steps=48 if dynamics is sphsolid.Leapfrog else None)
    for name in "ABC":
        close(pc[name]["sigma_yy"], pl[name]["sigma_yy"], name)
    close(c.velocities, l.velocities, "velocities")
    piston_c = c.velocities[c.body_ids == 2]
    piston_l = l.velocities[l.body_ids == 2]
    assert np.ptp(piston_l[:, 1]) == 0.0            # one rigid velocity
    assert piston_c[0, 1] < 0.0                     # pushed down
    close(piston_c, piston_l, "piston velocity")


def test_backends_agree_on_a_prescribed_rotation():
    # Rotation -> the library's sph_set_rotation or LAMMPS's fix move
    # rotate: both move particles on exact arcs; with kernel correction the
    # stress stays at round-off on both.  A quarter turn ending on a
    # shortened step (the LAMMPS backend re-creates fix move around it).
    omega = 2000.0

    def make():
        block = sphsolid.rectangle((-0.01, 0.01), (-0.01, 0.01), 2e-3,
                                   scenes.paper_material(), "block",
                                   motion=sphsolid.Rotation(omega, (0.0, 0.0)))
        return sphsolid.Scene(2, [block], effects={"kernel_correction": {}})

    quarter = 0.5 * np.pi / omega
    # the paper's probes lie outside this small block: recorded as NaN
    (c, _, dc), (l, _, dl) = run_both(make, until=quarter + 0.3e-6, interval=100,
                                      probe_outside="nan")
    assert dc.time == dl.time
    close(c.positions, l.positions, "positions")
    close(c.velocities, l.velocities, "velocities")
    for scene in (c, l):
        # rotated by omega t on exact circles; no stress
        angle = omega * scene.time
        x0 = make().positions
        turned = np.column_stack([np.cos(angle) * x0[:, 0] - np.sin(angle) * x0[:, 1],
                                  np.sin(angle) * x0[:, 0] + np.cos(angle) * x0[:, 1]])
        assert np.abs(scene.positions - turned).max() < 1e-12
        assert scene.von_mises.max() < 1e-12 * 2 * scenes.paper_material().mu * omega * scene.time


def test_backends_agree_under_gravity_with_damping():
    (c, pc, _), (l, pl, _) = run_both(
        lambda: scenes.gravity(4e-3), until=100e-6, interval=10)
    for name in "ABC":
        close(pc[name]["von_mises"], pl[name]["von_mises"], name)
    close(c.velocities, l.velocities, "velocities")
    assert np.abs(c.velocities).max() > 0


def test_lammps_backend_writes_a_trajectory_with_its_clock(tmp_path):
    """The LAMMPS backend sets the library's clock (sph_set_time), so a
    Trajectory records LAMMPS's step and time with the state LAMMPS
    reached; the frames equal the scene's synced arrays exactly and the C
    library's run at the same steps to round-off."""
    runs = {}
    for backend in ("c", "lammps"):
        scene = scenes.uniaxial_piston(4e-3)
        if backend == "lammps":
            scene.calc = lammps_backend.Lammps()
        dyn = sphsolid.ImprovedEuler(scene)
        path = tmp_path / f"{backend}.h5"
        traj = sphsolid.Trajectory(path, "w", scene)
        kept = []
        dyn.attach(traj, interval=20)
        dyn.attach(lambda: kept.append((scene.step, scene.time,
                                        scene.velocities.copy())),
                   interval=20)
        dyn.run(steps=60)
        traj.close()
        runs[backend] = (path, kept)
    (c_path, _), (l_path, l_kept) = runs["c"], runs["lammps"]
    with sphsolid.Trajectory(l_path) as lt, sphsolid.Trajectory(c_path) as ct:
        assert len(lt) == len(ct) == len(l_kept) == 4       # steps 0..60
        for lf, cf, (step, time, velocities) in zip(lt, ct, l_kept):
            assert lf.step == step == cf.step
            assert lf.time == time
            assert lf.time == pytest.approx(cf.time, rel=1e-12)
            np.testing.assert_array_equal(lf.velocities, velocities)
            close(lf.velocities, cf.velocities, f"velocities at {step}")
            close(lf.deviatoric_stress, cf.deviatoric_stress,
                  f"deviatoric stress at {step}")
        # the piston has set the specimen moving: not a comparison of zeros
        assert np.abs(lt[-1].velocities).max() > 0


def test_lammps_checkpoint_continues_on_the_c_library(tmp_path):
    """30 steps in LAMMPS, a checkpoint, 20 more in the C library: the
    same state as 50 steps in the C library, to round-off."""
    lammps_scene = scenes.uniaxial_piston(4e-3)
    lammps_scene.calc = lammps_backend.Lammps()
    sphsolid.ImprovedEuler(lammps_scene).run(steps=30)
    lammps_scene.write_checkpoint(tmp_path / "l.chk")

    resumed = scenes.uniaxial_piston(4e-3)
    again = sphsolid.ImprovedEuler(resumed)
    resumed.read_checkpoint(tmp_path / "l.chk")
    assert resumed.step == 30
    assert resumed.time == pytest.approx(30 * again.dt, rel=1e-12)
    again.run(steps=20)

    direct = scenes.uniaxial_piston(4e-3)
    sphsolid.ImprovedEuler(direct).run(steps=50)
    assert resumed.step == direct.step == 50
    close(resumed.positions, direct.positions, "positions")
    close(resumed.velocities, direct.velocities, "velocities")
    close(resumed.deviatoric_stress, direct.deviatoric_stress,
          "deviatoric stress")


def test_lammps_backend_refuses_to_read_a_checkpoint(tmp_path):
    written = scenes.uniaxial_piston(4e-3)
    written.write_checkpoint(tmp_path / "c.chk")
    scene = scenes.uniaxial_piston(4e-3)
    scene.calc = lammps_backend.Lammps()
    with pytest.raises(sphsolid.UnsupportedError, match="C library backend"):
        scene.read_checkpoint(tmp_path / "c.chk")


@pytest.mark.parametrize("dynamics", [sphsolid.ImprovedEuler, sphsolid.Leapfrog])
def test_backends_agree_on_the_damage_of_a_compression_test(dynamics):
    """The damage effect: LAMMPS numbers the atoms as the library's
    particles (ID = index + 1), so they draw the same flaws, and the damage
    field comes out bitwise the same (D grows by fixed amounts once a flaw
    is active); the rest of the state to round-off."""
    from sphsolid import fracture

    results = []
    for backend in ("c", "lammps"):
        scene = fracture.ucs(6e-3, strain_rate=5.0, seed=4)
        if backend == "lammps":
            scene.calc = lammps_backend.Lammps()
        dyn = dynamics(scene)
        dyn.run(steps=300 if dynamics is sphsolid.Leapfrog else 600)
        results.append(scene)
    c, lmp = results
    D = c.damage
    assert 10 < (D > 0).sum() < len(D) - 10      # a field worth comparing
    np.testing.assert_array_equal(lmp.damage, D)
    np.testing.assert_array_equal(lmp.flaws, c.flaws)
    close(c.positions, lmp.positions, "positions")
    close(c.deviatoric_stress, lmp.deviatoric_stress, "deviatoric stress")
