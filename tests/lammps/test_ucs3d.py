"""The 3D cylinder to failure: examples/ucs3d/in.ucs3d (docs/fracture.md).

The laboratory cylinder (D = 54 mm, L = 135 mm) at dx = 6 mm (1,587
specimen atoms, about 4 s of CPU on one rank) compressed past its peak
with the damage effect on, on 1 and on 2 MPI ranks.  The atoms are
renumbered by position (reset_atoms id sort yes), so their IDs, and the
flaws drawn from them, do not depend on the decomposition: the damage
field and the fragment labels are bitwise the same on both; the rest of
the state agrees to round-off (the sums run in another order).
"""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from conftest import REPOSITORY, run_deck

DECK = REPOSITORY / "examples" / "ucs3d" / "in.ucs3d"
DX, D, L = 0.006, 0.054, 0.135


def printed(log: str, label: str) -> float:
    return float(re.search(rf"^{re.escape(label)}\s*(\S+)", log, re.M).group(1))


@pytest.fixture(scope="module")
def runs(tmp_path_factory, plugin):
    out = {}
    for ranks in (1, 2):
        work = tmp_path_factory.mktemp(f"ucs3d_np{ranks}")
        run_deck(DECK, work, {"dx": DX}, plugin, ranks=ranks)
        out[ranks] = {
            "log": (work / "log.lammps").read_text(),
            "load": np.loadtxt(work / "ucs3d_load.txt", comments="#", ndmin=2),
            "field": np.loadtxt(work / "ucs3d_damage.txt", skiprows=9)}
    return out


def test_cylinder_fails_past_its_peak_and_prints_the_peak_stress(runs):
    log, load, field = (runs[1][k] for k in ("log", "load", "field"))
    peak, onset = printed(log, "peak load:"), printed(log, "damage onset:")
    # the peak is the largest sample; damage began before it; the run
    # stopped once the load fell below half the peak, every sample before
    # the stop at least half of it
    k = int(np.argmax(load[:, 3]))
    assert peak == pytest.approx(load[k, 3], rel=1e-9)
    assert 0 < onset <= load[k, 1] < load[-1, 1]
    assert load[-1, 3] < 0.5 * peak <= load[:-1, 3][load[:-1, 1] >= onset].min()
    # the strain is the piston's travel over L
    assert load[k, 2] == pytest.approx(load[k, 1] * 1.0, rel=1e-9)
    # peak stress = peak load over a layer's lattice cells: the specimen's
    # atoms over its round(L/dx) layers, each cell (D/round(D/dx))^2
    # (LAMMPS rounds halves up: 22.5 layers are 23)
    n, ny = math.floor(D / DX + 0.5), math.floor(L / DX + 0.5)
    area = len(field) / ny * (D / n) ** 2
    assert len(field) % ny == 0
    assert printed(log, "peak stress (UCS):") == pytest.approx(peak / area, rel=1e-9)
    assert abs(area - math.pi * D * D / 4) < 0.1 * math.pi * D * D / 4
    # columns id x y z D fragment: damaged through, split, labels at D = 1
    # are -1 and each fragment is labelled by its least ID
    D_, F = field[:, 4], field[:, 5]
    assert (D_ == 1.0).any() and (D_ == 0.0).any()
    assert ((F == -1) == (D_ == 1.0)).all()
    labels = F[F >= 0]
    for label in np.unique(labels):
        assert field[F == label, 0].min() == label
    assert printed(log, "fragments:") == len(np.unique(labels)) >= 1


def test_one_and_two_ranks_give_bitwise_the_same_damage_field(runs):
    one, two = runs[1]["field"], runs[2]["field"]
    np.testing.assert_array_equal(one[:, 0], two[:, 0])
    # damage and fragments bitwise; positions to round-off
    np.testing.assert_array_equal(one[:, 4:6], two[:, 4:6])
    np.testing.assert_allclose(one[:, 1:4], two[:, 1:4], rtol=0, atol=1e-12)
    assert (one[:, 4] > 0).sum() > 0.05 * len(one)
    a, b = runs[1]["load"], runs[2]["load"]
    assert a.shape == b.shape
    np.testing.assert_array_equal(a[:, 4], b[:, 4])
    assert np.abs(a[:, 3] - b[:, 3]).max() <= 1e-9 * np.abs(a[:, 3]).max()
    for label in ("damage onset:", "fragments:"):
        assert printed(runs[1]["log"], label) == printed(runs[2]["log"], label)
