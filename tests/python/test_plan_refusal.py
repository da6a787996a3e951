"""The planner on a ladder with one non-monotone level: the error model
with the verification record's orders as a prior
(sphsolid.planner.error_model.fit_order_with_prior), each calibrated
level's own bound (ErrorModel.level_bounds), and what a refusal says.

The ladders are synthetic (no runs): the strip's probe series plus an
error of one shape whose size is given per level, so every difference of
two levels and every level's true error are known exactly.
"""
from __future__ import annotations

import numpy as np
import pytest

from sphsolid import metrics, planner
from sphsolid.planner import record as record_module

STRIP = planner.project_scenes()["strip"]
UNTIL = STRIP.until
TIMES = np.linspace(0.0, UNTIL, 400)
LIMIT = {n: -1e6 * np.clip((TIMES - i * 8e-6) / 4e-6, 0, 1)
         for i, n in enumerate(STRIP.probes)}
SHAPE = np.sin(2 * np.pi * TIMES / UNTIL) + 0.3
LADDER = (2e-3, 1.4e-3, 1e-3, 0.7e-3)
#: error sizes per level: they fall with dx (1, 0.75, 0.45, 0.292), but
#: the 1 mm level's sits low, so the differences go 0.25, 0.30, 0.158:
#: the second rises, the ladder is not monotone
SIZES = dict(zip(LADDER, (1.0, 0.75, 0.45, 0.292)))
SETTING = planner.Setting.make(1.2, effects={
    "artificial_viscosity": {"alpha": 1.0, "beta": 0.0}})


def _fake_run(factory, dx, setting, until, probes, quantity, threads):
    size = SIZES[min(SIZES, key=lambda level: abs(level - dx))]
    series = {n: LIMIT[n] + 0.05e6 * size * SHAPE for n in LIMIT}
    n, steps = int(0.8 / dx), int(UNTIL / (0.1 * dx / 3000.0))
    return planner.LadderRun(setting, dx, n, steps, UNTIL / steps, 1.0,
                             UNTIL, TIMES, series, cpu=n * steps * 1e-8,
                             threads=1)


def _true_error(dx):
    """The RMS error of the fake level at ``dx`` against its limit, worst
    probe, on the scale of the finest level's series (the planner's)."""
    run = _fake_run(None, dx, SETTING, UNTIL, None, None, 1)
    finest = _fake_run(None, LADDER[-1], SETTING, UNTIL, None, None, 1)
    grid = metrics.time_grid(0.0, UNTIL)
    worst = 0.0
    for n in LIMIT:
        level = metrics.smooth(grid, metrics.on_grid(TIMES, run.series[n],
                                                     grid))
        limit = metrics.smooth(grid, metrics.on_grid(TIMES, LIMIT[n], grid))
        scale = metrics.scale_of(metrics.smooth(grid, metrics.on_grid(
            TIMES, finest.series[n], grid)), "rms")
        worst = max(worst, metrics.deviation(level, limit, "rms", scale))
    return worst


def _record(orders=(0.8, 1.0)):
    """A record verifying SETTING in the RMS norm (factor 1, no bias)
    whose fitted scenes saw its errors fall at ``orders``."""
    spacings = [2e-3, 1e-3, 0.5e-3]
    scenes = {f"s{i}": {"rms": {"spacings": spacings,
                                "errors": [0.1 * (dx / 2e-3) ** q
                                           for dx in spacings]}}
              for i, q in enumerate(orders)}
    return record_module.Record({
        "format": 1, "fitted": list(scenes), "held_out": [],
        "settings": {record_module.family(SETTING): {
            "rms": {"ratio": 0.5, "bias": 0.0}, "scenes": scenes}}})


@pytest.fixture
def plan(monkeypatch):
    monkeypatch.setattr(planner.search, "ladder_run", _fake_run)

    def plan_(error, **options):
        return planner.plan(STRIP.factory, error=error, until=UNTIL,
                            probes=STRIP.probes, quantity=STRIP.quantity,
                            norm="rms", threads=1, ladder=LADDER,
                            candidates=[SETTING], detect=False,
                            timing_checks=0, refinements=0, scene="strip",
                            record=_record(), **options)
    return plan_


def test_the_record_measures_the_orders_of_a_settings_true_errors():
    record = _record((0.7, 0.9))
    assert record.orders(SETTING, "rms") == pytest.approx((0.7, 0.9))
    assert record.orders(SETTING, "max") is None
    # a scene without spacings, or not fitted, says nothing about orders
    assert record.orders(planner.Setting.make(1.5), "rms") is None


def test_a_prior_fit_follows_data_in_range_and_leans_on_the_prior_else():
    h = np.array([2e-3, 1.4e-3, 1e-3, 0.7e-3])
    exact = 3.0 * (h[:-1] ** 0.9 - h[1:] ** 0.9)
    # an exact power law of an order in the range: the free fit, no scatter
    q, c, resid, cov = planner.error_model.fit_order_with_prior(
        h, exact, (0.8, 1.0))
    free = planner.fit_order(h, exact)
    assert q == pytest.approx(free[0]) and c == pytest.approx(free[1])
    model = planner.fit_error_model(h, exact, prior=(0.8, 1.0))
    assert model.scatter(h[-1] / 2) == pytest.approx(1.0)
    # the same law with its finest difference 1.6x larger (it rises): the
    # free order leaves the range, the prior keeps the fit near it, and
    # the scatter widens the bound (not the central prediction) below the
    # ladder
    bumped = exact * np.array([1.0, 1.0, 1.6])
    free_q = planner.fit_order(h, bumped)[0]
    model = planner.fit_error_model(h, bumped, prior=(0.8, 1.0))
    assert not 0.8 <= free_q <= 1.0
    assert 0.8 - 2 * planner.error_model.PRIOR_WIDTH <= model.order <= 1.0
    dx = h[-1] / 2
    law = 3.0 * dx ** 0.9                      # the error of the construction
    assert 0.5 < model.predict(dx) / law < 2.0
    assert planner.fit_error_model(h, bumped).predict(dx) / law > 5.0
    assert model.scatter(dx) > 1.05
    assert model.law_upper(dx) == pytest.approx(
        model.safety * model.predict(dx) * model.scatter(dx))


def _budget(plan, dx):
    """The predicted wall time of the setting's run at ``dx``."""
    cand = plan.candidates[0]
    return cand.cost.predict(*planner.search._size_at(cand.runs, dx))


def test_a_calibrated_level_whose_bound_meets_the_request_is_planned(plan):
    model = plan(0.02).candidates[0].model
    assert not model.anomalous
    assert model.asymptotic_issues()               # the ladder is not
    finest, _, bound = model.level_bounds()[-1]
    assert finest == pytest.approx(LADDER[-1])
    # the fitted law's bound there is larger than the level's own: a
    # request between them is planned at the level, not finer
    assert model.law_upper(finest) > bound
    request = 0.5 * (bound + model.law_upper(finest))
    planned = plan(request)
    assert planned.feasible, planned.reason
    assert planned.dx >= finest * (1 - 1e-6)         # that level or coarser
    assert planned.error_upper <= request
    # and with a budget that affords no finer run, it is still planned
    budgeted = plan(request, max_seconds=1.01 * _budget(planned, finest))
    assert budgeted.feasible, budgeted.reason
    assert budgeted.dx >= finest * (1 - 1e-6)
    # the bound is honest: the level's true error is within it
    assert _true_error(planned.dx) <= planned.error_upper


def test_a_refusal_names_no_error_above_a_calibrated_levels_bound(plan):
    unlimited = plan(0.02)
    finest = LADDER[-1]
    # a budget that affords no run finer than the finest level: the law's
    # bound there exceeds the level's own
    refused = plan(0.02, max_seconds=1.01 * _budget(unlimited, finest))
    assert not refused.feasible
    model = refused.candidates[0].model
    bounds = [b for _, _, b in model.level_bounds()]
    assert refused.best_reachable_error <= min(bounds)
    assert unlimited.best_reachable_error <= min(bounds)
    # a level's bound is at least its true error
    for dx, _, b in model.level_bounds():
        assert _true_error(dx) <= b
    # what was measured: the finest level, its difference and its bound,
    # why the ladder is not asymptotic and what would settle it
    finest, diff, bound = model.level_bounds()[-1]
    reason = refused.reason
    assert (f"finest level {finest * 1e3:.3g} mm, self-convergence "
            f"difference there {diff * 100:.2f} %, bound "
            f"{bound * 100:.2f} %") in reason
    assert f"best reachable: {bound * 100:.2f} %" in reason
    assert "not in its asymptotic range" in reason
    assert "differences do not fall with dx" in reason
    assert "outside the record's range for that setting" in reason
    assert f"a level at {finest / 1.5 * 1e3:.3g} mm would settle it" in reason
    assert "s of CPU" in reason


def test_a_levels_bound_covers_the_difference_to_the_finer_level():
    # four levels that follow the law (the fit's window) below a coarser
    # ladder level that hardly differs from the next (0.01 % at 3 to
    # 2 mm) but 0.3 % from the finer one: errors that do not grow with
    # refinement make the 2 mm level's error at least half the latter
    # (E_k + E_k+1 >= D_k, E_k+1 <= E_k), which its difference from the
    # coarser level alone would not show
    h = np.array([2e-3, 1.4e-3, 1e-3, 0.7e-3])
    diffs = 3.0 * (h[:-1] ** 0.9 - h[1:] ** 0.9)
    model = planner.fit_error_model(h, diffs, prior=(0.8, 1.0))
    model.calibrated = [(3e-3, None), (2e-3, 1e-4)] + list(
        zip(h[1:], diffs))
    assert not model.anomalous
    for (dx, _, bound), finer in zip(model.level_bounds()[:-1], diffs):
        assert bound >= finer / 2, dx


def test_below_a_ladder_at_its_edge_the_law_falls_at_the_records_slowest():
    # differences that fall at 1.7 (cubic_o4's on the piston: 1.69 from
    # 1.5 to 0.445 mm) where the record saw the setting's true errors fall
    # at 0.66-0.92: the part a finer level keeps is not in them. True
    # errors equal to the law's central value at the finest level, then
    # falling at the record's slowest order 0.66 (the piston's fell at
    # 0.7, 0.4 from 0.667 to 0.31 mm).
    h = np.array([1.5e-3, 1e-3, 0.667e-3, 0.445e-3])
    diffs = 2.0 * (h[:-1] ** 1.7 - h[1:] ** 1.7)
    model = planner.fit_error_model(h, diffs, max_order=1.0,
                                    prior=(0.66, 0.92))
    assert model.observed_order == pytest.approx(1.7, abs=0.01)
    finest = h[-1]
    at_finest = model.power(finest)

    def truth(dx):
        return at_finest * (dx / finest) ** 0.66
    # at and above the finest level the law is the fit's (order 1)
    assert model.power(h[1]) == pytest.approx(
        at_finest * (h[1] / finest) ** model.order)
    # (at order 1 from the finest level the bound at half of it is 1.25x
    # the central value, the error there 2^0.34 = 1.27x)
    below = (finest / 1.3, finest / 1.6, model.smallest_dx)
    assert all(model.upper(dx) >= truth(dx) for dx in below)
    for dx in below:
        # the record's spread of orders widens the bound away from the
        # level, not the central prediction
        assert model.predict(dx) == pytest.approx(truth(dx))
        assert model.scatter(dx) > model.scatter(finest)
    # a request planned below the ladder is met
    for request in (0.8 * at_finest, 0.7 * at_finest):
        dx = model.spacing_for(request)
        assert dx is not None and model.upper(dx) <= request * (1 + 1e-9)
        if dx >= model.smallest_dx:
            assert truth(dx) <= request
    assert model.extrapolation_order == pytest.approx(0.66)
    # without the record the fit's order is used below the ladder too
    free = planner.fit_error_model(h, diffs, max_order=1.0)
    assert free.extrapolation_order == free.order == 1.0
