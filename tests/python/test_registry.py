"""One registry per concept: the library names the effects and kernels,
and Python, the plugin's page and the library's docs follow it."""
import importlib.util
import math
import re
from pathlib import Path

import numpy as np
import pytest

import sphsolid

ROOT = Path(__file__).resolve().parents[2]


def _effect_tables():
    spec = importlib.util.spec_from_file_location(
        "effect_tables", ROOT / "scripts" / "effect_tables.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_docs_effect_tables_match_the_registry():
    problems = _effect_tables().differences(sphsolid.effect_registry())
    assert not problems, ("docs disagree with the effect registry (fix with "
                          "python scripts/effect_tables.py --write):\n"
                          + "\n".join(problems))


def test_docs_check_notices_a_wrong_default():
    registry = sphsolid.effect_registry()
    registry["xsph"]["parameters"]["epsilon"]["default"] = 0.25
    problems = _effect_tables().differences(registry)
    assert any("xsph" in p for p in problems)


def test_pair_style_page_lists_the_library_kernels():
    text = (ROOT / "docs" / "lammps" / "pair_sphsolid.rst").read_text()
    line = next(s for s in text.splitlines() if "*kernel* name =" in s)
    assert re.findall(r"\*(\w+)\*", line.split("=", 1)[1]) == \
        sphsolid.kernel_names()


def test_registry_lists_every_effect_name():
    registry = sphsolid.effect_registry()
    assert list(registry) == sphsolid.effect_names()
    for name, effect in registry.items():
        assert effect["description"], name
        for key, p in effect["parameters"].items():
            assert p["min"] <= p["max"], (name, key)
            if p["default"] is not None:
                assert p["min"] <= p["default"] <= p["max"], (name, key)


def test_scene_takes_every_kernel_and_the_library_names_a_wrong_one():
    for name in sphsolid.kernel_names():
        assert sphsolid.Scene(kernel=name).kernel == name
    with pytest.raises(ValueError, match="unknown kernel 'gauss'.*cubic_spline"):
        sphsolid.Scene(kernel="gauss")


def test_library_judges_effects_and_smoothing_ratio():
    scene = sphsolid.Scene()
    with pytest.raises(ValueError, match="unknown effect 'viscosity'.*known"):
        scene.effect("viscosity", alpha=1.0)
    with pytest.raises(ValueError, match="rate"):
        scene.effect("damping")
    with pytest.raises(ValueError, match="alpha='inf'"):
        scene.effect("artificial_viscosity", alpha=math.inf)
    # the library's range, not a looser Python copy of it
    with pytest.raises(ValueError, match=r"h/dx=0.3"):
        scene.set_smoothing_ratio(0.3)


@pytest.mark.parametrize("kernel", sphsolid.kernel_names())
def test_kernel_values_are_the_library_kernel(kernel):
    """dw/dq is the derivative of w (centred differences), and in 2D the
    kernel integrates to one: 2 pi int w(q) q dq = 1."""
    q = np.linspace(0.0, 3.0, 30001)
    w, dw_dq = sphsolid.kernel_values(kernel, q)
    dq = q[1] - q[0]
    assert 2 * np.pi * np.trapezoid(w * q, q) == pytest.approx(1.0, abs=1e-6)
    centred = (w[2:] - w[:-2]) / (2 * dq)
    assert np.max(np.abs(centred - dw_dq[1:-1])) < 1e-5
    assert w[-1] == 0.0 and dw_dq[-1] == 0.0
