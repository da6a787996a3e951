"""Observed order of each accuracy option on the exact strip.

The laterally periodic strip (the specimen's height between plate and
piston, no free surface) has an exact answer (``validation.order``,
linear acoustics): fronts at (2kH +- y)/c_p, each adding 2 mu V/c_p to
the von Mises stress, V the piston's speed. With the piston's speed ramped
up smoothly (a C2 quintic over 10-20 us) the fronts are smooth, so what
each option changes shows as a clean rate of convergence:

- the static platen inset removes the loaded ends' first-order delay
  e dy/c_p (e the library's end offset at inset 0, from the kernel and the
  lattice alone);
- the fourth-order kernel cubic_o4 carries the front at c_p: its error
  falls with dx where the cubic spline's stalls at the lattice speed;
- the leapfrog's error falls at second order in its step.
"""
import numpy as np
import pytest

from sphsolid import scenes

from validation import end_placement, order

ROCK = scenes.paper_material()
RISE = 20e-6
#: the first front passes B (14 us) and A (27 us) before any reflection
#: reaches them (80 us at A)
FIRST = 75e-6


@pytest.mark.parametrize("dx", [4e-3, 2e-3, 1e-3])
def test_static_inset_removes_the_end_delay(dx):
    """Waves preset (cubic_o4 at h/dx 1.65, leapfrog at a quarter of its
    step, so that its own phase error stays below 1 % of the delays). At
    inset 0 the piston acts as if e dy behind its face, e = 0.72 steps
    (``sph_platen_end_offset``): the first front arrives e dy/c_p late at
    every probe, first order in dx (1.1, 0.55, 0.27 us at 4, 2, 1 mm;
    measured within 1 % at A, 11 % at B, 36 mm from the piston). At the
    static inset the delay is gone (measured below 30 ns, under a
    twentieth of it). The lattice speed's share (1/M - 1) t, M = 1.0008
    for cubic_o4, is taken off first."""
    from validation.study import lattice_gradient_moment
    e = end_placement.strip_scene(dx, "waves").platen_end_offset(
        "specimen", 0.0)
    assert 0.6 < e < 0.8
    predicted = e * dx / ROCK.c_p
    speed = 1 / lattice_gradient_moment(1.65, "cubic_o4") - 1
    H = scenes.SPECIMEN_Y[1]
    runs = {inset: order.front_delays(order.strip_run(
        dx, "waves", rise=RISE, until=FIRST, dt_factor=0.25, inset=inset),
        RISE) for inset in (0.0, "static")}
    for probe, (_, y) in order.STRIP_PROBES.items():
        share = speed * (H - y) / ROCK.c_p
        off = runs[0.0][probe][0] - share
        on = runs["static"][probe][0] - share
        assert off == pytest.approx(predicted, rel=0.12), (probe, off)
        assert abs(on) < 0.05 * predicted, (probe, on, predicted)


def _first_front_errors(preset, dxs, **options):
    return [order.deviation(order.strip_run(dx, preset, rise=RISE,
                                            until=FIRST, **options),
                            order.strip_reference(RISE), "rms",
                            window=FIRST) for dx in dxs]


def test_cubic_o4_front_converges_where_the_cubic_spline_stalls():
    """The first smooth front against the exact one (RMS of the smoothed
    von Mises, worst probe), leapfrog at half its default step, no
    viscosity. cubic_o4 at h/dx 1.65 (lattice moment M = 1.0008):
    measured 0.78, 0.27, 0.14 % at 4, 2, 1 mm (order 1.6 then 0.9, where
    its 0.08 % fast lattice speed starts to show). The cubic spline at
    h/dx 1.2 (M = 0.9908: 0.9 % slow) with the same step: 10.5, 5.2,
    3.1 %."""
    dxs = [4e-3, 2e-3, 1e-3]
    o4 = _first_front_errors("waves", dxs, dt_factor=0.5)
    cubic = _first_front_errors("paper", dxs, viscosity=None,
                                integrator="leapfrog", dt_factor=0.5)
    p = order.orders(dxs, o4)
    assert p[0] > 1.4 and np.polyfit(np.log(dxs), np.log(o4), 1)[0] > 1.1, \
        (o4, p)
    assert o4[-1] < 0.002, o4
    assert all(a < 0.1 * b for a, b in zip(o4, cubic)), (o4, cubic)


def test_leapfrog_error_on_the_strip_falls_at_second_order_in_dt():
    """Waves preset at 2 mm, ramp 10 us, to 0.1 ms (the first fronts and
    one reflection at B): the probe series at dt, dt/2, dt/4 of the
    default step against the same run at dt/8. With an error C dt^p the
    differences fall by (1 - 8^-p)/(2^-p - 8^-p), then (2^-p - 8^-p)/
    (4^-p - 8^-p): 4.2 and 5.0 for p = 2 (measured 3.9 and 5.0), 2.3 and
    3.0 for a first-order scheme."""
    dx, rise, until = 2e-3, 10e-6, 0.1e-3
    runs = [order.strip_run(dx, "waves", rise=rise, until=until,
                            dt_factor=f) for f in (1, 0.5, 0.25, 0.125)]
    grid = np.linspace(0, until, 1000)
    stack = [np.concatenate([np.interp(grid, r["times"], r["vm"][n])
                             for n in ("A", "B")]) for r in runs]
    diffs = [np.linalg.norm(s - stack[-1]) for s in stack[:-1]]
    ratios = [diffs[0] / diffs[1], diffs[1] / diffs[2]]
    assert 3.4 < ratios[0] < 4.8 and 4.2 < ratios[1] < 5.8, (diffs, ratios)
