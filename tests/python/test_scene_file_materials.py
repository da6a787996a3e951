"""Scene files speak the whole material model: every key of the library's
material registry in ``[materials.NAME]`` (with its unit) and every
effect's parameters in ``[effects]``; a scene with Weibull flaws and the
``damage`` effect runs and fractures.

The key lists are walked, not copied: the TOML reader's keys are the
elastic constants and the library's registry (sph_material_key_get), each
key of that registry reaches the library's own range check through a
file, and each effect's parameters reach the effect."""
from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from sphsolid import _lib
from sphsolid.cli import main
from sphsolid.scenefile import (SceneFileError, effect_parameter_units, load,
                                material_key_units)

from scene_texts import block_toml, platens_toml

ELASTIC = {"rho0", "K", "mu", "E", "nu"}


def _material_file(tmp_path, lines: str, tail: str = "") -> object:
    text = block_toml(6, "3mm", tail=tail).replace(
        "rho0 = 2300\n", "rho0 = 2300\n" + lines + "\n", 1)
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def test_the_readers_material_keys_are_the_librarys():
    """The keys [materials.NAME] takes are exactly the elastic constants
    and the library's registry, with the registry's units; the registry
    holds at least the Weibull keys of the damage effect."""
    library = _lib.material_keys()
    reader = material_key_units()
    assert set(reader) - ELASTIC == set(library)
    assert {"weibull_k", "weibull_m"} <= set(library)
    for key, info in library.items():
        assert reader[key] == info["unit"], key
        assert info["min"] <= info["default"] <= info["max"], key


def _inside(info) -> float:
    low, high = info["min"], info["max"]
    return 0.5 * (low + high) if math.isfinite(high) else low + 1.0


@pytest.mark.parametrize("key", sorted(_lib.material_keys()))
def test_every_library_key_reaches_the_library_from_a_file(key, tmp_path):
    """A value inside the key's range builds the scene; one below it is
    refused by the library's own check, naming the file and the key; the
    value may carry the key's unit."""
    info = _lib.material_keys()[key]
    value = _inside(info)
    scene = load(_material_file(tmp_path, f"{key} = {value!r}")).scene
    material = scene.bodies[0].material
    assert (getattr(material, key) if hasattr(material, key)
            else material.keys[key]) == value
    if info["unit"]:
        text = f'{key} = "{value!r} {info["unit"]}"'
        load(_material_file(tmp_path, text))
    below = info["min"] - max(1.0, abs(info["min"]))
    with pytest.raises(SceneFileError, match=rf"scene.toml: .*{key}"):
        load(_material_file(tmp_path, f"{key} = {below!r}"))
    with pytest.raises(SceneFileError, match=rf"{key}: '1 kg' is not a "
                       "number"):
        load(_material_file(tmp_path, f'{key} = "1 kg"'))


def test_an_unknown_material_key_lists_the_librarys(tmp_path):
    with pytest.raises(SceneFileError) as error:
        load(_material_file(tmp_path, "weibull_q = 3"))
    known = sorted(material_key_units().keys() | {"name"})
    assert (f"unknown key(s) weibull_q (known: {', '.join(known)})"
            in str(error.value)), str(error.value)


def _parameter_value(effect, key, p):
    """A value of an effect parameter inside its range, as TOML text with
    its unit where it has one."""
    if p["default"] is not None:
        value = p["default"]
    else:
        value = _inside(p)
    if effect == "damage" and key == "flaws":
        value = 10.0
    unit = p["unit"]
    return value, (f'"{value!r} {unit}"' if unit else repr(value))


@pytest.mark.parametrize("effect", sorted(effect_parameter_units()))
def test_every_effects_parameters_are_taken_in_their_units(effect,
                                                           tmp_path):
    """[effects] NAME = {every parameter, in its unit}: the scene has the
    effect on with those values (the flaw keys on the material for the
    damage effect)."""
    parameters = _lib.effect_registry()[effect]["parameters"]
    values, items = {}, []
    for key, p in parameters.items():
        value, text = _parameter_value(effect, key, p)
        values[key] = value
        items.append(f"{key} = {text}")
    tail = f"[effects]\n{effect} = {{ {', '.join(items)} }}\n"
    path = _material_file(tmp_path, "weibull_k = 1e28\nweibull_m = 9", tail)
    scene = load(path).scene
    assert scene.effects[effect] == pytest.approx(values), effect


def test_an_effect_parameter_in_the_wrong_unit_is_named(tmp_path):
    tail = '[effects]\ndrucker_prager = { cohesion = "5mm" }\n'
    with pytest.raises(SceneFileError, match=r"effects.drucker_prager."
                       r"cohesion is a pressure, but '5mm' is a length"):
        load(_material_file(tmp_path, "", tail))


PULLED = platens_toml("puller", "20m/s")


def test_a_scene_file_with_weibull_flaws_and_damage_runs_and_breaks(
        tmp_path, capsys):
    """A block pulled at 20 m/s (a tensile strain rho0 c_p v / (K + 4/3
    mu) = 8e-3 behind the wave, above the 3e-3 at which a 3 mm particle
    expects a flaw): the file's Weibull keys and damage effect run and the
    block is damaged; without the keys the library's refusal arrives as
    one line, naming the keys."""
    text = block_toml(6, "2mm", until="50us").replace(
        "rho0 = 2300\n", 'rho0 = 2300\nweibull_k = "1e28 m^-3"\n'
        "weibull_m = 9\n", 1).replace("[probes]", PULLED + "[probes]", 1)
    text += ("[effects]\ndamage = { seed = 1 }\n"
             "artificial_viscosity = { alpha = 1, beta = 0 }\n")
    path = tmp_path / "break.toml"
    path.write_text(text)
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    with h5py.File(tmp_path / "out" / "break.h5", "r") as f:
        damage = f["particles/all/damage/value"][-1]
        body = f["particles/all/body"][:]
    assert np.all(damage[body != 0] == 0.0)        # the platens stay whole
    assert damage[body == 0].max() == 1.0
    capsys.readouterr()
    path.write_text(text.replace('weibull_k = "1e28 m^-3"\n', ""))
    assert main(["run", str(path), "--out", str(tmp_path / "no")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert ("[effects] damage needs flaws: give weibull_k [m^-3] and "
            "weibull_m > 0 in the [materials.NAME] table") in err, err
