"""SPHSOLID_RATE_PATH: the pair loop's instruction-set path, from the
environment, for every handle the package creates.

A name that is not a path is refused with its value named; `baseline`
(which every build and CPU has) is taken, and its rates agree with those
of the widest path to the bound docs/library.md gives (1e-12 of each
rate's largest value), while the same path twice gives the same bits;
where the CPU has a wide path, its bits differ from the baseline's, so
the variable is seen to take effect.
"""

import numpy as np
import pytest

import sphsolid
from sphsolid import _lib, scenes


def has_path(monkeypatch, path):
    """Whether this build on this CPU has `path` (sph_create takes it)."""
    monkeypatch.setenv("SPHSOLID_RATE_PATH", path)
    try:
        _lib.lib.sph_destroy(_lib.new_handle(2))
    except ValueError:
        return False
    return True


def state_after(monkeypatch, path):
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
    wide_path = has_path(monkeypatch, "avx2")
    base = state_after(monkeypatch, "baseline")
    again = state_after(monkeypatch, "baseline")
    wide = state_after(monkeypatch, None)
    for b, a, w in zip(base, again, wide):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_allclose(w, b, rtol=0, atol=1e-12 * np.abs(b).max())
    if wide_path:  # the wide path fuses multiplies and adds: the variable took effect
        assert any((w != b).any() for b, w in zip(base, wide))
