"""The accuracy-front study's bookkeeping (validation/front.py): the
Pareto front, the observed orders and the generated section, on made-up
points (the runs themselves are the study's, not a test's)."""
import pytest

from validation import front


def _point(option, dx, rms, cpu, steps):
    return {"option": option, "dx": dx, "rms": rms, "max": 2 * rms,
            "cpu": cpu, "wall": 3 * cpu, "steps": steps,
            "particle_steps": steps * 1000, "load": 4.0}


def test_pareto_keeps_the_points_no_other_beats_on_both_axes():
    a, b = list(front.OPTIONS)[:2]
    points = [_point(a, 2e-3, 0.08, 1.0, 10), _point(a, 1e-3, 0.04, 8.0, 20),
              _point(b, 2e-3, 0.05, 2.0, 10), _point(b, 1e-3, 0.05, 9.0, 20)]
    assert front.pareto(points, "cpu") == [True, True, True, False]
    # on particle-steps b at 2 mm ties a at 2 mm in cost and beats it
    assert front.pareto(points, "particle_steps") == [False, True, True,
                                                      False]


def test_observed_orders_per_option():
    a = list(front.OPTIONS)[0]
    points = [_point(a, 2e-3, 0.08, 1, 1), _point(a, 1e-3, 0.04, 8, 2),
              _point(a, 5e-4, 0.01, 64, 4)]
    orders = front.observed_orders(points)[a]
    assert orders["rms"] == pytest.approx([1.0, 2.0])


def test_section_lists_every_run_and_replaces_only_the_marked_block(tmp_path):
    a, b = list(front.OPTIONS)[:2]
    points = [_point(a, 1e-3, 0.04, 8.0, 20), _point(b, 1e-3, 0.02, 4.0, 20)]
    text = front.section(points, "figure.png")
    assert text.count(f"| {a} | 1 |") == 1 and text.count(f"| {b} | 1 |") == 1
    doc = tmp_path / "doc.md"
    doc.write_text(f"before\n{front.BEGIN}\nold\n{front.END}\nafter\n")
    front.write_doc(doc, text)
    body = doc.read_text()
    assert body.startswith("before\n") and body.endswith("after\n")
    assert "old" not in body and f"| {b} | 1 |" in body
    bare = tmp_path / "bare.md"
    bare.write_text("no markers\n")
    with pytest.raises(SystemExit, match="markers"):
        front.write_doc(bare, text)


def test_an_option_with_effects_runs_with_them():
    """An option's "effects" reach its scene: the kernel-correction row
    runs with the effect on and at half the fronts preset's step (a few
    steps at 4 mm)."""
    plain = front.run(4e-3, "fronts (cubic_o4 at M = 1, leapfrog at half "
                      "step, static inset)", window=4e-6)
    corrected = front.run(4e-3, "fronts, kernel correction, quarter step",
                          window=4e-6)
    assert "kernel_correction" in corrected["effects"]
    assert "kernel_correction" not in plain["effects"]
    assert corrected["dt"] == pytest.approx(0.5 * plain["dt"], rel=1e-12)
