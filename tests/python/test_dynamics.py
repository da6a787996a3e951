"""ImprovedEuler: observer schedule, run(until=t), Ctrl-C, progress."""
import math
import os
import signal
import threading

import numpy as np
import pytest

import sphsolid
from sphsolid import scenes


def recorder(dyn, log):
    return lambda: log.append(dyn.nsteps)


def test_observers_fire_at_the_right_steps(coarse_piston):
    dyn = sphsolid.ImprovedEuler(coarse_piston)
    every3, every5, every1 = [], [], []
    dyn.attach(recorder(dyn, every3), interval=3)
    dyn.attach(recorder(dyn, every5), interval=5)
    dyn.attach(recorder(dyn, every1))
    assert dyn.run(steps=20) == 20
    # multiples of the interval from step 0 to 20 inclusive, once each
    assert every3 == list(range(0, 21, 3))
    assert every5 == list(range(0, 21, 5))
    assert every1 == list(range(0, 21))
    dyn.run(steps=7)                     # continues the global schedule
    assert every3 == list(range(0, 28, 3))
    assert every5 == list(range(0, 28, 5))
    assert every1 == list(range(0, 28))


def test_observer_gets_its_arguments(coarse_piston):
    dyn = sphsolid.ImprovedEuler(coarse_piston)
    seen = []
    dyn.attach(lambda a, b=0: seen.append((a, b)), 4, "x", b=2)
    dyn.run(steps=8)
    assert seen == [("x", 2)] * 3


def test_run_until_ends_exactly_at_t(coarse_piston):
    dyn = sphsolid.ImprovedEuler(coarse_piston)
    t_end = 10.3 * dyn.dt                # not a whole number of steps
    steps = dyn.run(until=t_end)
    assert coarse_piston.time == t_end   # the last step is shortened
    assert steps == math.ceil(10.3)      # 10 whole steps and a short one


def test_run_until_with_observers_keeps_their_schedule(coarse_piston):
    dyn = sphsolid.ImprovedEuler(coarse_piston)
    log, times = [], []
    dyn.attach(recorder(dyn, log), interval=4)
    dyn.attach(lambda: times.append(dyn.time), interval=4)
    t_end = 17.5 * dyn.dt
    dyn.run(until=t_end)
    assert dyn.time == t_end
    assert log == [0, 4, 8, 12, 16]
    np.testing.assert_allclose(times, np.array(log) * dyn.dt, rtol=1e-12)
    dyn.run(until=30 * dyn.dt)           # ends on a whole step this time
    assert dyn.time == pytest.approx(30 * dyn.dt, rel=1e-12)
    assert log == [0, 4, 8, 12, 16, 20, 24, 28]


def test_run_until_in_pieces_equals_one_run():
    a, b = scenes.uniaxial_piston(4e-3), scenes.uniaxial_piston(4e-3)
    dyn_a, dyn_b = sphsolid.ImprovedEuler(a), sphsolid.ImprovedEuler(b)
    dyn_a.run(steps=40)
    dyn_b.attach(lambda: None, interval=7)   # chunks of at most 7 steps
    dyn_b.run(steps=40)
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.deviatoric_stress, b.deviatoric_stress)


def test_run_needs_exactly_one_of_steps_and_until(coarse_piston):
    dyn = sphsolid.ImprovedEuler(coarse_piston)
    with pytest.raises(ValueError, match="exactly one"):
        dyn.run()
    with pytest.raises(ValueError, match="exactly one"):
        dyn.run(steps=3, until=1e-6)
    with pytest.raises(ValueError, match="until"):
        dyn.run(until=-1.0)


def test_ctrl_c_stops_cleanly_and_flushes_the_trajectory(tmp_path):
    """SIGINT during a long run inside the C library stops it after a whole
    step, flushes the trajectory with the stopped state, raises
    KeyboardInterrupt, and leaves the process's Ctrl-C handler as it was."""
    scene = scenes.uniaxial_piston(4e-3)
    dyn = sphsolid.ImprovedEuler(scene, progress=False)
    traj = sphsolid.Trajectory(tmp_path / "stop.h5", "w", scene)
    dyn.attach(traj, interval=10 ** 6)
    handler = signal.getsignal(signal.SIGINT)
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt, match="Ctrl-C"):
            dyn.run(steps=10 ** 7)
    finally:
        timer.cancel()
    stopped_at = dyn.nsteps
    assert 0 < stopped_at < 10 ** 7
    assert signal.getsignal(signal.SIGINT) is handler
    traj.close()
    with sphsolid.Trajectory(tmp_path / "stop.h5") as reader:
        assert list(reader.steps) == [0, stopped_at]
        np.testing.assert_array_equal(reader[-1].positions, scene.positions)
    dyn.run(steps=3)                     # the scene is still usable
    assert dyn.nsteps == stopped_at + 3


def test_observer_exception_propagates(coarse_piston):
    dyn = sphsolid.ImprovedEuler(coarse_piston)

    def fail():
        if dyn.nsteps == 6:
            raise RuntimeError("observer failed")

    dyn.attach(fail, interval=3)
    with pytest.raises(RuntimeError, match="observer failed"):
        dyn.run(steps=20)
    assert dyn.nsteps == 6


def test_progress_bar_counts_every_step(coarse_piston, capsys):
    dyn = sphsolid.ImprovedEuler(coarse_piston, progress=True)
    dyn.run(steps=55)
    err = capsys.readouterr().err
    assert "55/55" in err


# ------------------------------------------------------------- Leapfrog
def test_leapfrog_selects_the_library_integrator(coarse_piston):
    dyn = sphsolid.Leapfrog(coarse_piston)
    assert coarse_piston.calc.integrator == "leapfrog"
    assert dyn.dt == pytest.approx(2 * sphsolid.ImprovedEuler(
        scenes.uniaxial_piston(4e-3)).dt, rel=1e-12)   # h/c0 vs 0.5 h/c0
    t_end = 6.3 * dyn.dt
    assert dyn.run(until=t_end) == 7
    assert coarse_piston.time == t_end
    with pytest.raises(TypeError, match="base class"):
        sphsolid.Dynamics(coarse_piston)
    with pytest.raises(ValueError, match="integrator 'heun'"):
        sphsolid.dynamics.dynamics_for("heun")


def test_leapfrog_observer_chunks_equal_one_run():
    """The rates the leapfrog carries from step to step survive the runs
    its observers cut it into (and the scene's views being handed out)."""
    a, b = scenes.uniaxial_piston(4e-3), scenes.uniaxial_piston(4e-3)
    dyn_a, dyn_b = sphsolid.Leapfrog(a), sphsolid.Leapfrog(b)
    dyn_a.run(steps=30)
    dyn_b.attach(lambda: b.velocities, interval=7)
    dyn_b.run(steps=30)
    np.testing.assert_array_equal(a.velocities, b.velocities)
    np.testing.assert_array_equal(a.deviatoric_stress, b.deviatoric_stress)


def test_calculator_evaluates_forces_and_stress(coarse_piston):
    """ASE's meaning: the calculator evaluates at the current state."""
    calc = coarse_piston.calc
    sphsolid.Leapfrog(coarse_piston).run(steps=5)
    forces = calc.get_forces()
    assert forces.shape == (len(coarse_piston), 2)
    np.testing.assert_array_equal(
        forces, coarse_piston.masses[:, None] * calc.get_accelerations())
    assert np.abs(forces).max() > 0      # the piston squeezes the specimen
    stress = calc.get_stress()
    np.testing.assert_array_equal(stress, coarse_piston.stress)


def test_switching_integrators_takes_the_new_default_step(coarse_piston):
    """The leapfrog's step is above Improved Euler's limit: a new
    ImprovedEuler on the same scene takes its own default step."""
    leapfrog = sphsolid.Leapfrog(coarse_piston)
    leapfrog.run(steps=3)
    dt_leapfrog = leapfrog.dt
    euler = sphsolid.ImprovedEuler(coarse_piston)
    assert coarse_piston.calc.integrator == "improved_euler"
    assert euler.dt == pytest.approx(dt_leapfrog / 2, rel=1e-12)
    euler.run(steps=3)
    assert coarse_piston.step == 6
