"""SPHSOLID_RATE_PATH: the pair loop's instruction-set path, from the
environment, for every handle the package creates.

A name that is not a path is refused with its value named; `baseline`
(which every build and CPU has) is taken, and its rates agree with those
of the widest path to the bound docs/library.md gives (1e-12 of each
rate's largest value), while the same path twice gives the same bits.
"""

import numpy as np
import pytest

import sphsolid
from sphsolid import _lib, scenes


def rates(monkeypatch, path):
    if path:
        monkeypatch.setenv("SPHSOLID_RATE_PATH", path)
    else:
        monkeypatch.delenv("SPHSOLID_RATE_PATH", raising=False)
    scene = scenes.uniaxial_piston(4e-3)
    sphsolid.Leapfrog(scene).run(steps=20)
    return scene.velocities.copy(), scene.density.copy(), scene.deviatoric_stress.copy()


def test_a_name_that_is_not_a_path_is_refused(monkeypatch):
    monkeypatch.setenv("SPHSOLID_RATE_PATH", "sse9")
    with pytest.raises(ValueError, match="SPHSOLID_RATE_PATH='sse9'"):
        _lib.new_handle(2)


def test_the_baseline_path_agrees_with_the_widest(monkeypatch):
    base = rates(monkeypatch, "baseline")
    again = rates(monkeypatch, "baseline")
    wide = rates(monkeypatch, None)
    for b, a, w in zip(base, again, wide):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_allclose(w, b, rtol=0, atol=1e-12 * np.abs(b).max())
