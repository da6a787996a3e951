"""The analysis of the finite-element reference's own convergence
(``validation.order.fe_self``) and the partial series file of
``validation.fe_reference`` (no FE run: synthetic series of known error).

A series whose deviation from the converged answer is C h^p in every
probe and at every time gives successive differences C h^p (1 - 2^-p)
for halved sizes: the observed order is p, and the Richardson estimate
d / (2^p - 1) of the finest series' error is C h_finest^p (to the 0.1-1 %
by which the metric's normalisation, the RMS of the finer series of each
pair, differs from that of the converged answer)."""
import numpy as np
import pytest

from validation import fe_reference, order


def _exact(t):
    # a smooth von Mises history with a front at 20 us
    return {"A": 1e4 * (1 + np.tanh((t - 20e-6) / 3e-6)) + 3e7 * t,
            "B": 2e4 * np.sin(2e4 * t) ** 2 + 1e3,
            "C": 5e3 * (1 + np.tanh((t - 40e-6) / 5e-6))}


def _write(path, sizes_mm, p, until=1e-3):
    grid = np.linspace(0.0, until, int(round(until / 1e-7)) + 1)
    shape = 1e3 * np.cos(3e4 * grid)          # the error's time shape
    for s in sizes_mm:
        series = {n: v + shape * (s / 4.0) ** p for n, v in
                  _exact(grid).items()}
        np.savez(path / f"fe_piston_{s:g}mm.npz", grid=grid, **series)
    return [path / f"fe_piston_{s:g}mm.npz" for s in sizes_mm]


@pytest.mark.parametrize("p", [1.0, 2.0])
def test_fe_self_finds_the_order_and_the_richardson_error(tmp_path, p):
    paths = _write(tmp_path, (4, 2, 1, 0.5), p)
    out = order.fe_self(paths)
    for window in (" 0.3ms", " 1ms"):
        w = out["windows"][window]
        assert w["orders"] == pytest.approx([p, p], abs=0.01)
        assert w["finest"] == "fe_piston_0.5mm"
        # the finest series against the exact answer, in the same metric
        from sphsolid import metrics
        stop = 0.3e-3 if window == " 0.3ms" else 1e-3
        grid = metrics.time_grid(0.0, stop)
        ref, _ = order.fe_series(paths[-1])
        true = metrics.worst_deviation(ref(grid), _exact(grid), grid, "rms")
        assert w["richardson"] == pytest.approx(true, rel=0.01)
        assert w["richardson_previous"] == pytest.approx(true * 2 ** p,
                                                         rel=0.01)
    labels = [q["pair"] for q in out["pairs"]]
    assert labels[:3] == ["fe_piston_4mm vs fe_piston_2mm",
                          "fe_piston_2mm vs fe_piston_1mm",
                          "fe_piston_1mm vs fe_piston_0.5mm"]


def test_fe_self_leaves_out_the_long_window_where_a_series_stops_early(
        tmp_path):
    paths = _write(tmp_path, (4, 2), 2.0)
    paths += _write(tmp_path, (1,), 2.0, until=0.3e-3)
    out = order.fe_self(paths)
    assert "rms" in out["pairs"][1] and "rms 1ms" not in out["pairs"][1]
    assert "rms 1ms" in out["pairs"][0]
    assert " 1ms" not in out["windows"]


def test_fitted_order_is_the_least_squares_slope():
    dxs = [2e-3, 1e-3, 5e-4]
    assert order.fitted_order(dxs, [4.0, 1.0, 0.25]) == pytest.approx(2.0)
    # pairwise 1 and 2: the fit lies between them
    assert 1.0 < order.fitted_order(dxs, [4.0, 2.0, 0.5]) < 2.0


def test_partial_fe_series_is_written_up_to_the_time_reached(tmp_path):
    grid = np.linspace(0.0, 1e-5, 101)
    vm = {n: np.arange(101.0) for n in "ABC"}
    partial = {"element_size": 1e-3, "dt": 1e-7, "dofs": 10, "steps": 40,
               "wall": 1.0, "filled": 41, "vm": vm}
    path = tmp_path / "fe.npz"
    fe_reference.save_series(path, grid, partial)
    data = np.load(path)
    assert data["grid"][-1] == pytest.approx(4e-6)
    assert len(data["A"]) == 41 and data["A"][-1] == 40.0
    assert int(data["steps"]) == 40
    assert not list(tmp_path.glob("*.part*"))
