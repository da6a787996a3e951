"""Scene(allow_large=...) reaches the library's memory limit
(sph_set_allow_large): half of the available memory by default, all of
it when allowed (the limits themselves: tests/c/test_bad_input.c)."""
from __future__ import annotations

import sphsolid
from sphsolid._lib import lib


def test_allow_large_is_set_on_the_handle():
    assert lib.sph_allow_large(sphsolid.Scene(2)._handle) == 0
    assert lib.sph_allow_large(sphsolid.Scene(3, allow_large=True)._handle) == 1
