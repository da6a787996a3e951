"""The sweep table of ``validation.order`` (docs/validation.md, section
4d): its orders and least-squares slopes recover the exponent of an error
that is a known power of the spacing, and an experiment's effects are
switched on in the scene it runs."""
import json

import numpy as np

from validation import decomposition, order


def _row(label, dxs, errors):
    ref = order.FE_NAMES[0]
    return {"kind": "sweep", "label": label, "dx": list(dxs),
            "runs": [{"dx": d, "cpu": 1.0, "errors": {f"{ref} rms 1us": e}}
                     for d, e in zip(dxs, errors)]}


def test_sweep_slopes_recover_a_power_law():
    """error = C dx^p on the nine spacings: every successive order and
    every least-squares slope is p; a different power per half shows in
    the halves' slopes."""
    dxs = np.asarray(order.SWEEP_DX)
    line = order.sweep_table([_row("p", dxs, 3.0 * dxs ** 1.7)]).splitlines()[2]
    cells = [c.strip() for c in line.split("|")]
    assert cells[5] == ", ".join(["1.70"] * (len(dxs) - 1))
    assert cells[6] == "1.70 (9) / 1.70 (5) / 1.70 (5)"
    # p = 1 above 1 mm, p = 2 below (continuous at 1 mm)
    kinked = np.where(dxs >= 1e-3, dxs / 1e-3, (dxs / 1e-3) ** 2)
    line = order.sweep_table([_row("k", dxs, kinked)]).splitlines()[2]
    slopes = [c.strip() for c in line.split("|")][6]
    assert slopes.split(" / ")[1:] == ["1.00 (5)", "2.00 (5)"]
    json.dumps(_row("p", dxs, dxs))  # rows are plain JSON, as order.json


def test_experiment_effects_reach_the_scene():
    """``effects`` of an experiment are switched on in its scene: the
    kernel correction changes the specimen's stress after a few steps,
    and an unknown effect is an error naming it."""
    from sphsolid import scenes
    from sphsolid.calculators import CLibrary

    def stress(effects):
        scene = decomposition.with_effects(
            scenes.uniaxial_piston(4e-3, preset="fronts"), effects)
        scene.calc = CLibrary(threads=1)
        dyn = order._dynamics(scene, None, 1.0)
        dyn.run(steps=20)
        return scene.effects, scene.stress

    (fx_plain, plain), (fx_kc, corrected) = (
        stress(None), stress({"kernel_correction": {}}))
    assert "kernel_correction" not in fx_plain and "kernel_correction" in fx_kc
    assert np.abs(plain - corrected).max() > 1e-6 * np.abs(plain).max()
    try:
        stress({"no_such_effect": {}})
    except ValueError as err:
        assert "no_such_effect" in str(err)
    else:
        raise AssertionError("an unknown effect was accepted")
