"""scripts/probe_series_bound.py: the bounded comparison of probe series.

Two outputs of bench/probe_series agree to a bound when every value lies
within it of the largest magnitude its group (a probe's values, a field's
two checksums) reaches over the base series.  Checked on made-up series
in the program's format: equal series agree at any bound, a perturbation
of a known size is found at its size, and a component that is zero by
symmetry is judged against its probe's stresses, not against itself.
"""

import importlib.util
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "probe_series_bound.py"


@pytest.fixture(scope="module")
def bound():
    spec = importlib.util.spec_from_file_location("probe_series_bound", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def probe_line(label, step, values):
    return f"{label} step {step}: " + " ".join(float(v).hex() for v in values) + "\n"


def series(noise=0.0, shear=1e-18, stopped=False):
    """A 2D series of two probes (6 values each) and 4 fields (2 checksums
    each), three samples; `noise` is added to one stress of the last
    sample, `shear` is a component zero by symmetry."""
    lines = []
    for step in (10, 20, 30):
        probes = [1e4 * step, -5e3 * step, 2e3, -3e3, 1e3, shear] * 2
        fields = [0.5, 1.5, 1e-3, 2e-3, 2.7e3 * step, 5e3, -1e2, 3e2]
        if step == 30:
            probes[2] += noise
        lines.append(probe_line("paper leapfrog cubic_spline", step, probes + fields))
    if stopped:
        lines.append("paper leapfrog cubic_spline step 40: stopped: step 40: density\n")
    return "".join(lines)


def run(bound, tmp_path, base, head, x):
    (tmp_path / "base.txt").write_text(base)
    (tmp_path / "head.txt").write_text(head)
    return bound.main(str(tmp_path / "base.txt"), str(tmp_path / "head.txt"), x)


def test_equal_series_agree(bound, tmp_path):
    assert run(bound, tmp_path, series(), series(), 0.0) == 0


def test_a_difference_is_measured_against_the_probes_largest_value(bound, tmp_path):
    # the probe's largest value is 1e4 * 30: a change of 3e-7 Pa is 1e-12 of it
    head = series(noise=3e-7)
    assert run(bound, tmp_path, series(), head, 2e-12) == 0
    assert run(bound, tmp_path, series(), head, 0.5e-12) == 1


def test_a_component_zero_by_symmetry_is_judged_against_its_probe(bound, tmp_path):
    # rounding noise of opposite sign in a shear that is zero by symmetry:
    # relative to itself it differs by 2, against the probe's 3e5 Pa by 7e-24
    assert run(bound, tmp_path, series(shear=1e-18), series(shear=-1e-18), 1e-20) == 0


def test_one_side_stopped_fails(bound, tmp_path):
    base = series(stopped=True)
    head = series() + "paper leapfrog cubic_spline step 40: " + "0x0p+0 " * 20 + "\n"
    assert run(bound, tmp_path, base, head, 1.0) == 1


def test_different_lines_fail(bound, tmp_path):
    assert run(bound, tmp_path, series(), series().rsplit("paper", 1)[0], 1.0) == 1
