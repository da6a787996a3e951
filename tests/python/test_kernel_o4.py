"""The fourth-order cubic kernel ("cubic_o4") against exact solutions.

Standing plane P-wave in a doubly periodic strip (derivation in
``sphsolid.study.standing_wave``): v = V sin(ky) cos(wt), sigma_yy =
rho0 c_p V cos(ky) sin(wt), w = c_p k. No dissipation, 1.25 periods.
"""
import math

import numpy as np
import pytest

from sphsolid import ImprovedEuler, Scene, build, scenes


def _wave_error(dx, wavelength, kernel, ratio, periods=1.25, dt_factor=1.0):
    rock = scenes.paper_material()
    width = 8 * dx
    strip = build.rectangle((-width / 2, width / 2), (0.0, wavelength), dx,
                            rock, name="strip")
    scene = Scene(2, [strip], domain=((-width / 2, 0.0),
                                      (width / 2, wavelength)),
                  periodic=(True, True), smoothing_ratio=ratio, kernel=kernel)
    scene.freeze()
    k = 2 * math.pi / wavelength
    omega = rock.c_p * k
    amplitude = 0.01
    y0 = scene.positions[:, 1].copy()
    scene.velocities[:, 1] = amplitude * np.sin(k * y0)
    dyn = ImprovedEuler(scene, progress=False)
    dyn = ImprovedEuler(scene, dt=dyn.dt * dt_factor, progress=False)
    dyn.run(until=periods * 2 * math.pi / omega)
    scale = rock.rho0 * rock.c_p * amplitude
    exact = scale * np.cos(k * y0) * np.sin(omega * scene.time)
    return float(np.sqrt(np.mean((scene.stress[:, 1] - exact) ** 2)) / scale)


def test_short_wave_keeps_its_speed():
    """10 particles per wavelength, time step a quarter of the default (so
    that the spatial error shows): the cubic spline at h/dx 1.2 carries
    the wave about 8.5 % slow (lattice dispersion), so after 1.25 periods
    its stress is off by 18 %; the fourth-order kernel at h/dx 1.65 keeps
    the speed within 0.5 % (measured error 0.06 %)."""
    cubic = _wave_error(2e-3, 0.02, "cubic_spline", 1.2, dt_factor=0.25)
    o4 = _wave_error(2e-3, 0.02, "cubic_o4", 1.65, dt_factor=0.25)
    assert cubic > 0.1, cubic
    assert o4 < 0.005, o4


def test_standing_wave_converges_to_the_exact_speed():
    """Against the exact solution at c_p itself (not the lattice speed):
    the cubic spline at 1.2 stalls at its lattice-speed floor (about
    2e-3 from 1 mm on), the fourth-order kernel converges at about third
    order (measured 4.1e-3, 5.2e-4, 4.7e-5 at 4, 2, 1 mm). Without any
    dissipation Improved Euler lets the shortest modes grow slowly, which
    shows from 0.5 mm on: hence 4 to 1 mm."""
    dxs = [4e-3, 2e-3, 1e-3]
    errors = [_wave_error(dx, 0.08, "cubic_o4", 1.65) for dx in dxs]
    order = np.polyfit(np.log(dxs), np.log(errors), 1)[0]
    assert order >= 2.5, (errors, order)
    assert errors[-1] < 2e-4, errors


def test_default_time_step_follows_the_inner_spline():
    """The default and stable time steps of cubic_o4 are those of a cubic
    spline at h/s = h/1.5 (its inner smoothing length)."""
    rock = scenes.paper_material()
    dts = {}
    for kernel in ("cubic_spline", "cubic_o4"):
        block = build.rectangle((0, 0.02), (0, 0.02), 1e-3, rock)
        scene = Scene(2, [block], smoothing_ratio=1.65, kernel=kernel)
        dts[kernel] = scene.calc.default_dt()
    assert dts["cubic_o4"] == pytest.approx(dts["cubic_spline"] / 1.5, rel=1e-12)


@pytest.mark.parametrize("alpha", [0.5, 1.0, 2.0])
def test_viscosity_shortens_only_the_leapfrogs_cubic_o4_step(alpha):
    """With artificial viscosity alpha the leapfrog's stable step is its
    step without viscosity / (1 + kappa alpha), kappa the kernel's (0.85
    for cubic_o4, 0 for the cubic spline), and its default step at most
    0.8 of that; Improved Euler's steps do not change."""
    from sphsolid import Leapfrog
    rock = scenes.paper_material()
    steps = {}
    for kernel in ("cubic_spline", "cubic_o4"):
        for integrator in (ImprovedEuler, Leapfrog):
            for viscous in (False, True):
                block = build.rectangle((0, 0.02), (0, 0.02), 1e-3, rock)
                effects = ({"artificial_viscosity": {"alpha": alpha, "beta": 0.0}}
                           if viscous else {})
                scene = Scene(2, [block], smoothing_ratio=1.65, kernel=kernel,
                              effects=effects)
                dyn = integrator(scene, progress=False)
                steps[kernel, integrator.__name__, viscous] = (
                    scene.calc.stable_dt(), scene.calc.default_dt(), dyn.dt)
    divisor = 1 + 0.85 * alpha
    plain, viscous = steps["cubic_o4", "Leapfrog", False], steps["cubic_o4", "Leapfrog", True]
    assert viscous[0] == pytest.approx(plain[0] / divisor, rel=1e-12)
    assert viscous[1] == pytest.approx(min(plain[1], 0.8 * plain[0] / divisor), rel=1e-12)
    assert viscous[2] == viscous[1]
    for kernel, integrator in (("cubic_spline", "Leapfrog"), ("cubic_spline", "ImprovedEuler"),
                               ("cubic_o4", "ImprovedEuler")):
        assert steps[kernel, integrator, True] == steps[kernel, integrator, False]
