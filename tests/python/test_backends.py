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


def run_both(make_scene, until, interval=5):
    results = []
    for backend in ("c", "lammps"):
        scene = make_scene()
        if backend == "lammps":
            scene.calc = lammps_backend.Lammps()
        probes = sphsolid.Probes(scene, scenes.PAPER_PROBES)
        dyn = sphsolid.ImprovedEuler(scene)
        dyn.attach(probes, interval=interval)
        dyn.run(until=until)
        results.append((scene, probes, dyn))
    return results


def test_backends_agree_on_the_piston_scene():
    (c, pc, dc), (l, pl, dl) = run_both(
        lambda: scenes.uniaxial_piston(4e-3), until=150.5e-6)
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


def test_backends_agree_under_gravity_with_damping():
    (c, pc, _), (l, pl, _) = run_both(
        lambda: scenes.gravity(4e-3), until=100e-6, interval=10)
    for name in "ABC":
        close(pc[name]["von_mises"], pl[name]["von_mises"], name)
    close(c.velocities, l.velocities, "velocities")
    assert np.abs(c.velocities).max() > 0


def test_lammps_backend_refuses_to_write_a_library_trajectory(tmp_path):
    scene = scenes.uniaxial_piston(4e-3)
    scene.calc = lammps_backend.Lammps()
    dyn = sphsolid.ImprovedEuler(scene)
    dyn.run(steps=3)
    with pytest.raises(sphsolid.UnsupportedError, match="clock"):
        sphsolid.Trajectory(tmp_path / "l.h5", "w", scene)
