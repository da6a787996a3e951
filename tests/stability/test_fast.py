"""Fast subset of the stability suite, collected by pytest.

Each case of stability_cases.py in its fast variant must pass all its rows;
then checkpoint/resume through the front end and blow-up handling through
each entry point (C status, Python exception, LAMMPS error when the plugin
is available). The full suite: ``tests/stability/run.py --full``.
"""
import ctypes
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import stability_cases as cases  # noqa: E402

import sphsolid  # noqa: E402  (stability_cases made it importable)
from sphsolid import _lib  # noqa: E402


@pytest.mark.parametrize("name", list(cases.CASES))
def test_hard_case_meets_its_criterion(name):
    rows = cases.CASES[name](full=False)
    failed = [f"{r.case}: wanted {r.criterion}; got {r.measured}"
              for r in rows if not r.passed]
    assert not failed, "\n".join(failed)


def test_pressure_piston_reaches_the_applied_stress_through_lammps():
    """The pressure-loading case on the LAMMPS plugin (fix sphsolid/force):
    the same steady state, mean sigma_yy = -p within 2 %, and the same
    value as the C library's run to round-off of the damped transient."""
    lammps_backend = pytest.importorskip("sphsolid.lammps")
    if not lammps_backend.available():
        pytest.skip("LAMMPS backend unavailable (lammps module or plugin missing)")
    (plugin,) = cases.pressure_loading(backend="lammps")
    (library,) = cases.pressure_loading()
    assert plugin.passed, f"wanted {plugin.criterion}; got {plugin.measured}"
    assert plugin.values["ratio"] == pytest.approx(library.values["ratio"], rel=1e-9)


def _piston(viscosity=cases.VISCOSITY):
    scene = sphsolid.scenes.uniaxial_piston(dx=4e-3, viscosity=viscosity)
    return scene, cases.dynamics(scene)


def test_checkpoint_resume_continues_bit_identically(tmp_path):
    """Run 60 steps, checkpoint, run 60 more; a scene built the same way
    that reads the checkpoint and runs 60 steps ends in the same state, to
    the bit."""
    scene, dyn = _piston()
    dyn.run(steps=60)
    path = tmp_path / "piston.chk"
    scene.write_checkpoint(path)
    dyn.run(steps=60)
    resumed, dyn2 = _piston()
    resumed.read_checkpoint(path)
    assert resumed.step == 60 and resumed.time == pytest.approx(60 * dyn.dt)
    dyn2.run(steps=60)
    for name in ("positions", "velocities", "density", "deviatoric_stress"):
        assert np.array_equal(getattr(scene, name), getattr(resumed, name)), \
            name
    assert resumed.time == scene.time and resumed.step == scene.step


def test_killed_run_loses_only_the_work_since_the_last_checkpoint(tmp_path):
    """Checkpoints every 40 steps from an observer; the run is 'killed'
    (stopped by an exception) at step 100; resuming from the file restarts
    at step 80 and reaches the uninterrupted state at step 120."""
    path = tmp_path / "run.chk"
    reference, dyn_ref = _piston()
    dyn_ref.run(steps=120)

    scene, dyn = _piston()

    def checkpoint():
        if scene.step:
            scene.write_checkpoint(path)

    def kill():
        if scene.step == 100:
            raise KeyboardInterrupt("killed")

    dyn.attach(checkpoint, 40)
    dyn.attach(kill, 1)
    with pytest.raises(KeyboardInterrupt):
        dyn.run(steps=120)
    resumed, dyn2 = _piston()
    resumed.read_checkpoint(path)
    assert resumed.step == 80
    dyn2.run(steps=40)
    assert np.array_equal(resumed.positions, reference.positions)
    assert np.array_equal(resumed.deviatoric_stress,
                          reference.deviatoric_stress)


def _blow_up_scene():
    """The piston at 4 mm with no dissipation: Improved Euler's growth of
    undamped modes blows it up after about 1300 steps."""
    return _piston(viscosity=None)


def test_blow_up_returns_a_c_status_with_its_location():
    scene, dyn = _blow_up_scene()
    status = _lib.lib.sph_run(scene.handle, 5000)
    assert status in (9, _lib.SPH_ERR_NONFINITE)   # 9: SPH_ERR_UNSTABLE
    step, particle, body = ctypes.c_long(), ctypes.c_long(), ctypes.c_int()
    quantity = ctypes.c_char_p()
    assert _lib.lib.sph_failure(scene.handle, ctypes.byref(step),
                                ctypes.byref(particle), ctypes.byref(body),
                                ctypes.byref(quantity)) == 0
    assert 0 < step.value <= 5000
    assert 0 <= particle.value < len(scene)
    assert quantity.value.decode() in ("speed", "density ratio", "position",
                                       "velocity", "density",
                                       "deviatoric stress")
    message = _lib.errmsg(scene.handle)
    assert f"step {step.value}" in message
    assert f"particle {particle.value}" in message


def test_blow_up_raises_a_python_exception_naming_step_and_particle():
    scene, dyn = _blow_up_scene()
    with pytest.raises((sphsolid.SimulationError, RuntimeError)) as info:
        dyn.run(until=5e-3)
    message = str(info.value)
    assert "step" in message and "particle" in message
    assert "specimen" in message
    if hasattr(_lib, "SPH_ERR_UNSTABLE"):  # the front end maps status 9
        assert isinstance(info.value, sphsolid.SimulationError)
        assert info.value.step is not None and info.value.particle is not None


def test_blow_up_stops_lammps_with_an_error_naming_step_and_particle():
    lammps_backend = pytest.importorskip("sphsolid.lammps")
    if not lammps_backend.available():
        pytest.skip("the lammps module or the sphsolid plugin is missing")
    scene = sphsolid.scenes.uniaxial_piston(dx=4e-3, viscosity=None)
    scene.calc = lammps_backend.Lammps(threads=1)
    dyn = sphsolid.ImprovedEuler(scene, progress=False)
    with pytest.raises(Exception) as info:
        dyn.run(until=5e-3)
    # the plugin has no watchdog (yet): it stops when the library refuses a
    # non-positive density, a few tens of steps after the library's
    # watchdog would; the error names the step and the particle
    assert scene.time < 5e-3
    message = str(info.value)
    assert "step" in message and "particle" in message


def test_an_effect_given_to_the_suite_reaches_every_case(monkeypatch):
    """run.py --effect: the effect is switched on in the case's scene (the
    kernel correction removes the spurious stress of a rigid rotation,
    so the row that shows that stress without it no longer sees it) and
    named in the effects column."""
    monkeypatch.setattr(cases, "EXTRA_EFFECTS", ["kernel_correction"])
    rows = {r.case: r for r in cases.rigid_rotation(full=False)}
    shown = rows["rigid rotation 1 turn (no KC)"]
    assert shown.effects.endswith("KC")
    assert not shown.passed, shown.measured
