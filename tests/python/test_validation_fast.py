"""Fast subset of the validation study (docs/validation.md): seconds.

The full study is ``sphsolid study paper``; these checks keep its two
headline properties in the default suite.
"""
import math

import numpy as np

from sphsolid import ImprovedEuler, Probes, Scene, build, scenes
from validation import study


def _standing_wave_error(dx, rock):
    """Relative RMS error of sigma_yy of a standing plane P-wave in a
    doubly periodic strip (no dissipation), after 1.25 periods.

    Exact solution of the linear plane-strain equations rho0 dv/dt =
    d sigma_yy/dy, d sigma_yy/dt = (K + 4 mu/3) dv/dy:
    v = V sin(ky) cos(wt), sigma_yy = rho0 c V cos(ky) sin(wt), w = c k.
    At fixed h/dx the SPH gradient on the lattice is M times the exact one
    (M = -sum_b V_b y_ab^2 W'/r_ab, a lattice sum of the kernel, 1 in the
    continuum limit of h/dx), so the SPH continuum carries the wave at
    c = M c_p: that is the speed the scheme converges to at fixed h/dx.
    """
    wavelength, amplitude, width = 0.08, 0.01, 8 * dx
    strip = build.rectangle((-width / 2, width / 2), (0.0, wavelength), dx,
                            rock, name="strip")
    scene = Scene(2, [strip], domain=((-width / 2, 0.0),
                                      (width / 2, wavelength)),
                  periodic=(True, True))
    scene.freeze()
    k = 2 * math.pi / wavelength
    c_p = math.sqrt((rock.K + 4 * rock.mu / 3) / rock.rho0)
    omega = study.lattice_gradient_moment(1.2, "cubic_spline") * c_p * k
    y0 = scene.positions[:, 1].copy()
    scene.velocities[:, 1] = amplitude * np.sin(k * y0)
    ImprovedEuler(scene, progress=False).run(until=2.5 * math.pi / omega)
    scale = rock.rho0 * c_p * amplitude
    exact = scale * np.cos(k * y0) * np.sin(omega * scene.time)
    return np.sqrt(np.mean((scene.stress[:, 1] - exact) ** 2)) / scale


def test_lattice_moment_tends_to_one_for_wide_kernels():
    """The lattice sum M is a kernel property: 1 in the continuum limit
    (large h/dx), within 1 % at the default h/dx = 1.2."""
    assert abs(study.lattice_gradient_moment(3.0) - 1) < 1e-3
    assert abs(study.lattice_gradient_moment(1.2) - 1) < 0.01


def test_periodic_strip_converges_at_second_order(rock):
    """Standing P-wave in the periodic strip: observed order >= 1.5 over
    dx = 2, 1, 0.5 mm against the derived exact solution."""
    dxs = [2e-3, 1e-3, 0.5e-3]
    errors = [_standing_wave_error(dx, rock) for dx in dxs]
    order = np.polyfit(np.log(dxs), np.log(errors), 1)[0]
    assert errors[-1] < 1e-3
    assert order >= 1.5, (errors, order)


def test_paper_scene_front_reaches_B_first_then_A_and_C_together():
    """The paper's scene at 2 mm: the front from the piston face (y = 140
    mm) reaches B (y = 103.5 mm) first, then A and C (both y = 70 mm)
    together, each near (H - y)/c_p."""
    scene = scenes.uniaxial_piston(2e-3)
    probes = Probes(scene, scenes.PAPER_PROBES)
    dyn = ImprovedEuler(scene, progress=False)
    dyn.attach(probes, interval=2)
    dyn.run(until=40e-6)
    rock = scenes.paper_material()
    # von Mises behind a plane front of uniaxial strain eps = v/c_p:
    # S_yy = 4/3 mu eps, S_xx = S_zz = -2/3 mu eps -> sigma_vm = 2 mu eps
    jump = 2 * rock.mu * scenes.PISTON_SPEED / rock.c_p
    vm = {n: probes[n]["von_mises"] for n in "ABC"}
    arrival = study.arrival_times(probes.times, vm, 0.5 * jump)
    exact = {n: (scenes.SPECIMEN_Y[1] - scenes.PAPER_PROBES[n][1]) / rock.c_p
             for n in "ABC"}
    assert arrival["B"] < arrival["A"] and arrival["B"] < arrival["C"]
    assert abs(arrival["A"] - arrival["C"]) < 0.05 * exact["A"]
    for n in "ABC":
        assert abs(arrival[n] / exact[n] - 1) < 0.15, (n, arrival, exact)
