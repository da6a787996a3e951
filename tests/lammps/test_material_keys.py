"""pair_coeff takes every key of the library's material registry by name.

The registry (sph_material_key_count/get, read here through
sphsolid._lib.material_keys) lists the keys sph_material_set takes beyond
the elastic constants (the flaw and strength constants of the damage
effect, ...).  The pair style reads the same registry, so a key the
library learns reaches decks with no edit of the plugin.  These tests walk
the registry: each key given to pair_coeff must arrive in the pair
(lammps.extract_pair), a key not given must keep the library's default,
and a value outside the key's range must be refused by the library,
naming the key and the value (so the value was passed on, not dropped).
"""
from __future__ import annotations

import math

import pytest
from sphsolid import _lib
from test_bad_input import BOX, fails_with

KEYS = _lib.material_keys()
ELASTIC = "K 12.2e9 mu 2.67e9 rho0 2300.0"


def inside(info: dict, k: int) -> float:
    """A value inside the key's range, other than its default (k spreads
    the values of several keys apart)."""
    low, high = info["min"], info["max"]
    if math.isfinite(low) and math.isfinite(high):
        return low + (high - low) * (0.25 + 0.5 * (k + 1) / (len(KEYS) + 1))
    if math.isfinite(low):
        return low + 1.5 + k
    if math.isfinite(high):
        return high - 1.5 - k
    return info["default"] + 1.5 + k


def outside(info: dict) -> list[float]:
    """Values beyond the key's closed range."""
    values = []
    if math.isfinite(info["min"]):
        values.append(info["min"] - max(1.0, abs(info["min"])))
    if math.isfinite(info["max"]):
        values.append(info["max"] + max(1.0, abs(info["max"])))
    return values


def test_the_registry_is_not_empty():
    # the damage effect's flaw law is in it; an empty registry would make
    # the walks below vacuous
    assert {"weibull_k", "weibull_m"} <= set(KEYS)


def test_every_registry_key_given_reaches_the_pair(lmp_factory):
    given = {key: inside(info, k) for k, (key, info) in enumerate(KEYS.items())}
    words = " ".join(f"{key} {value!r}" for key, value in given.items())
    lmp = lmp_factory()
    for c in BOX + ["pair_style sphsolid 0.001", f"pair_coeff 1 1 {ELASTIC} {words}",
                    "pair_coeff 2 2 E 30e9 nu 0.25 rho0 2500.0"]:
        lmp.command(c)
    assert lmp.extract_pair("rho0")[1:] == [2300.0, 2500.0]
    for key, info in KEYS.items():
        values = lmp.extract_pair(key)
        assert values is not None, f"the pair does not know the registry key {key}"
        assert values[1] == pytest.approx(given[key], rel=1e-15), key
        assert values[2] == info["default"], key     # not given: the default
    assert lmp.extract_pair("no_such_key") is None


@pytest.mark.parametrize("key", sorted(KEYS))
def test_a_registry_key_beyond_its_range_is_refused_by_the_library(lmp_factory, key):
    values = outside(KEYS[key])
    if not values:
        pytest.skip(f"{key} is unbounded")
    for value in values:
        fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                       f"pair_coeff * * {ELASTIC} {key} {value!r}"],
                   "pair_coeff * *", key, f"{value:g}")


@pytest.mark.parametrize("key", sorted(KEYS))
def test_a_registry_key_at_its_bounds_is_taken(lmp_factory, key):
    info = KEYS[key]
    for value in (info["min"], info["max"], info["default"]):
        if not math.isfinite(value):
            continue
        lmp = lmp_factory()
        for c in BOX + ["pair_style sphsolid 0.001", f"pair_coeff * * {ELASTIC} {key} {value!r}"]:
            lmp.command(c)
        assert lmp.extract_pair(key)[1:] == [value, value]


def test_an_unknown_key_names_every_key_of_the_registry(lmp_factory):
    message = fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                             f"pair_coeff * * {ELASTIC} weibul_k 1e28"],
                         "unknown keyword 'weibul_k'")
    for key in ["K", "mu", "E", "nu", "rho0", *KEYS]:
        assert key in message, (key, message)


def test_an_unknown_key_of_5000_characters_is_clipped(lmp_factory):
    message = fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                             f"pair_coeff * * {ELASTIC} {'w' * 5000} 1"],
                         "unknown keyword", "(5000 characters)")
    # LAMMPS adds the input line; the pair style's own line is short
    ours = message.split("\n")[0].split("(expected")[0]
    assert len(ours) < 200, ours


@pytest.mark.parametrize("key", sorted(KEYS))
def test_a_registry_key_twice_or_without_value_is_named(lmp_factory, key):
    value = inside(KEYS[key], 0)
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                   f"pair_coeff * * {ELASTIC} {key} {value!r} {key} {value!r}"],
               key, "given twice")
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001", f"pair_coeff * * {ELASTIC} {key}"],
               key, "needs a value")
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                   f"pair_coeff * * {ELASTIC} {key} nan"],
               "nan")
