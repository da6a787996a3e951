"""A fuzz pass over the two file parsers users hand files to: plan files
(sphsolid.planner.Plan.load) and scene files (sphsolid.scenefile.load).

Random mutations of the shipped examples, for a fixed number of cases
with a printed seed (``SPHSOLID_FUZZ_SEED`` replays one, ``SPHSOLID_FUZZ_CASES``
sets the budget): every input is either read or refused with a
ValueError or OSError that names the file (or a MemoryError naming it,
for a scene the large-run guard refuses); no other exception escapes
the package. Spacings are only ever made coarser, so that a mutated
scene stays small.
"""
import copy
import json
import math
import os
import random
import re
from pathlib import Path

import pytest

from sphsolid import planner, scenefile

ROOT = Path(__file__).resolve().parents[2]
SEED = int(os.environ.get("SPHSOLID_FUZZ_SEED", random.randrange(2**31)))
CASES = int(os.environ.get("SPHSOLID_FUZZ_CASES", "150"))

ODD_VALUES = ['""', "0", "-1", "1e300", "-1e-300", "nan", "inf", "true",
              "[]", "{}", '"x"', '"1mm"', '"-2mm"', "[1, 2, 3]", '[0, "a"]',
              '{ a = 1 }', '"\\u0000"', "3.5", '"static"']


def _plan_text(rng: random.Random) -> str:
    data = {"format": "sphsolid-plan 1", "scene": "piston",
            "request": {"error": 0.03, "until": 3e-4, "norm": "max"},
            "feasible": True,
            "settings": {"dx": 1e-3, "smoothing_ratio": 1.65,
                         "kernel": "cubic_o4", "integrator": "leapfrog",
                         "effects": {"artificial_viscosity": {"alpha": 1.0}},
                         "inset": "static", "threads": 1},
            "predicted_error": 0.02, "error_upper": 0.03,
            "predicted_seconds": 1.0, "effects": []}
    odd = [None, True, "no", -1, 0, 1e308, [], {}, "1mm", [1, 2], {"a": 1}]

    def mutate(node, depth=0):
        if isinstance(node, dict) and node:
            key = rng.choice(list(node))
            action = rng.random()
            if action < 0.3:
                del node[key]
            elif action < 0.6 or depth > 3:
                node[key] = copy.deepcopy(rng.choice(odd))
            else:
                mutate(node[key], depth + 1)
        elif isinstance(node, list) and node:
            node[rng.randrange(len(node))] = copy.deepcopy(rng.choice(odd))
    for _ in range(rng.randint(1, 3)):
        mutate(data)
    text = json.dumps(data)
    if rng.random() < 0.3:                       # byte-level damage
        cut = rng.randrange(len(text))
        text = text[:cut] + rng.choice(["", "}", "\x00", "\"", ",]"]) + \
            text[cut + rng.randint(0, 5):]
    return text


def _scene_text(rng: random.Random, lines: list) -> str:
    lines = list(lines)
    for _ in range(rng.randint(1, 3)):
        i = rng.randrange(len(lines))
        action = rng.random()
        line = lines[i]
        if action < 0.2:
            del lines[i]
        elif action < 0.35:
            lines.insert(i, line)
        elif action < 0.5:
            j = rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], line
        elif "=" in line and not line.lstrip().startswith("#"):
            key, _ = line.split("=", 1)
            if key.strip() == "dx":              # only ever coarser
                value = rng.choice(['"4mm"', '"8mm"', "0.005", '"x"', "[]"])
            else:
                value = rng.choice(ODD_VALUES)
            lines[i] = f"{key}= {value}"
        else:
            cut = rng.randrange(len(line) + 1)
            lines[i] = line[:cut] + rng.choice(["[", "]", "=", "\"", ""]) \
                + line[cut + 1:]
    return "\n".join(lines) + "\n"


def _accepts_or_names(path: Path, read) -> None:
    try:
        read(path)
    except (ValueError, OSError, MemoryError) as error:
        assert str(path) in str(error) or path.name in str(error), (
            f"seed {SEED}: the message does not name the file: {error}")


def test_fuzz_plan_files(tmp_path):
    print(f"fuzz seed {SEED} (SPHSOLID_FUZZ_SEED replays it)")
    rng = random.Random(SEED)
    for case in range(CASES):
        path = tmp_path / f"plan{case}.json"
        path.write_text(_plan_text(rng))
        _accepts_or_names(path, planner.Plan.load)


@pytest.mark.parametrize("example", ["pull.toml", "cylinder.toml"])
def test_fuzz_scene_files(tmp_path, example):
    print(f"fuzz seed {SEED} (SPHSOLID_FUZZ_SEED replays it)")
    rng = random.Random(SEED + len(example))
    text = (ROOT / "examples" / "scene_file" / example).read_text()
    # the example at a coarse spacing: the fuzz is about parsing
    text = re.sub(r'dx = "[^"]*"', 'dx = "6mm"', text)
    lines = text.splitlines()
    for case in range(CASES // 3):
        path = tmp_path / f"scene{case}.toml"
        path.write_text(_scene_text(rng, lines))
        _accepts_or_names(path, scenefile.load)


# ------------------------------------- properties, with the registries as oracle
# Random values for the material keys and effect parameters of a scene file
# (numbers in and out of range, strings with the right unit, another unit
# of the same kind, another kind, none, junk; booleans, arrays, tables),
# and random parameter texts for the library's effect parser.  An oracle
# built from the library's registries says what must be accepted and what
# refused: the reader and the parser must agree with it on every case.

#: Effects whose parameters alone decide (gravity and damage add rules of
#: the scene: the dimension, flaws on a free body).
_PLAIN_EFFECTS = ("artificial_viscosity", "artificial_stress", "damping",
                  "xsph", "drucker_prager", "kernel_correction")


def _inside(p, value) -> bool:
    low = value >= p["min"] if p.get("min_inclusive", True) else value > p["min"]
    high = value <= p["max"] if p.get("max_inclusive", True) else value < p["max"]
    return math.isfinite(value) and low and high


def _number_in(rng, p) -> float:
    """A number inside the range of ``p`` (most cases) or outside it."""
    low = p["min"] if math.isfinite(p["min"]) else -1e6
    high = p["max"] if math.isfinite(p["max"]) else low + 1e6
    pick = rng.random()
    if pick < 0.6:
        return low + (high - low) * rng.uniform(0.01, 0.99)
    if pick < 0.7:
        return low
    if pick < 0.8:
        return high
    return rng.choice([low - 1.0, high + 1.0, -1e300, 1e300, -0.0])


def _toml_value(rng, p) -> tuple[str, float | None]:
    """(TOML text, the SI number the oracle expects or None: refused)."""
    from sphsolid.units import UNITS
    unit = p["unit"]
    number = _number_in(rng, p)
    pick = rng.random()
    if pick < 0.35:                                   # a plain number
        return repr(number), number
    if pick < 0.6:                                    # with its own unit
        # a unit that starts with a digit ("1/s") needs the space
        space = " " if unit[:1].isdigit() else rng.choice(["", " "])
        text = f"{number!r}{space}{unit}"
        return json.dumps(text), number
    if pick < 0.7 and unit in UNITS:                  # a unit of its kind
        kind = UNITS[unit][0]
        other = rng.choice([u for u, (k, _) in UNITS.items() if k == kind])
        scaled = number / UNITS[other][1]
        return json.dumps(f"{scaled!r} {other}"), scaled * UNITS[other][1]
    if pick < 0.8:                                    # another kind of unit
        wrong = rng.choice([u for u, (k, _) in UNITS.items()
                            if unit not in UNITS or k != UNITS[unit][0]])
        return json.dumps(f"{number!r} {wrong}"), None
    return rng.choice(["true", "[1, 2]", "{ a = 1 }", '"x"', '""', "nan",
                       "inf", '"1 2"', json.dumps("9" * 400)]), None


def _accepted(value, p):
    return value if value is not None and _inside(p, value) else None


def test_fuzz_scene_file_material_keys_and_effects_follow_the_registries(
        tmp_path):
    """A random [materials.rock] key set (every registry key, random values)
    and random [effects] tables are read exactly when every value is of
    the parameter's unit and within its range (the values then reach the
    scene as the oracle converts them), else refused naming the file."""
    from scene_texts import block_toml

    from sphsolid import _lib
    print(f"fuzz seed {SEED} (SPHSOLID_FUZZ_SEED replays it)")
    rng = random.Random(SEED + 7)
    keys = _lib.material_keys()
    effects = _lib.effect_registry()
    agreed = {"read": 0, "refused": 0}
    for case in range(CASES):
        lines, want_keys, ok = [], {}, True
        for key, info in keys.items():
            if rng.random() < 0.7:
                text, value = _toml_value(rng, info)
                lines.append(f"{key} = {text}")
                value = _accepted(value, info)
                ok &= value is not None
                want_keys[key] = value
        tables, want_effects = [], {}
        for name in rng.sample(_PLAIN_EFFECTS, rng.randint(0, 3)):
            items, want = [], {}
            for key, p in effects[name]["parameters"].items():
                if p["default"] is not None and rng.random() < 0.3:
                    continue                         # its default
                text, value = _toml_value(rng, p)
                items.append(f"{key} = {text}")
                value = _accepted(value, p)
                ok &= value is not None
                want[key] = value
            tables.append(f"{name} = {{ {', '.join(items)} }}")
            want_effects[name] = want
        tail = "[effects]\n" + "\n".join(tables) + "\n" if tables else ""
        text = block_toml(6, "3mm", tail=tail).replace(
            "rho0 = 2300\n", "rho0 = 2300\n" + "\n".join(lines) + "\n", 1)
        path = tmp_path / f"case{case}.toml"
        path.write_text(text)
        try:
            scene = scenefile.load(path).scene
        except (ValueError, OSError) as error:
            assert str(path) in str(error), (SEED, case, str(error))
            assert not ok, (SEED, case, text, str(error))
            agreed["refused"] += 1
            continue
        assert ok, (SEED, case, text)
        material = scene.bodies[0].material
        for key, value in want_keys.items():
            assert getattr(material, key, material.keys.get(key)) == value
        for name, want in want_effects.items():
            assert scene.effects[name] == want, (SEED, case, name)
        agreed["read"] += 1
    # both sides of the oracle were exercised
    assert min(agreed.values()) > CASES // 10, agreed


_SEPARATORS = [" ", "  ", ",", ", ", "\t"]


def _parameter_text(rng, parameters):
    """A random text for sph_effect and the oracle's verdict (True: the
    library must take it)."""
    words, seen, ok = [], set(), True
    names = list(parameters)
    for _ in range(rng.randint(0, len(names) + 1)):
        pick = rng.random()
        if names and pick < 0.75:
            key = rng.choice(names)
            p = parameters[key]
            number = _number_in(rng, p)
            form = rng.random()
            if form < 0.8:
                value = repr(number)
                good = _inside(p, number)
            else:
                value = rng.choice(["", "abc", "1.5.2", "nan", "inf", "1e999",
                                    "2x", "9" * 70, "--1", "0x"])
                good = False
            ok &= good and key not in seen
            seen.add(key)
            words.append(f"{key}={value}")
        elif pick < 0.9:
            words.append(rng.choice(["bogus=1", "=1", "alpha", "x" * 300,
                                     "==", "a=b=c", "\u00e9=1"]))
            ok = False
        else:
            words.append("")                          # an empty field
    required = {k for k, p in parameters.items() if p["default"] is None}
    ok &= required <= seen
    return rng.choice(_SEPARATORS).join(words), ok


def test_fuzz_effect_parameter_parser_follows_the_registry():
    """sph_effect's parameter text, random: it is taken exactly when every
    word is key=value with a known key, given once, a finite number within
    the key's range, and every required key is there; a refusal is
    SPH_ERR_ARGUMENT with a one-line message naming the effect, of a
    bounded length; nothing crashes."""
    from sphsolid import _lib
    print(f"fuzz seed {SEED} (SPHSOLID_FUZZ_SEED replays it)")
    rng = random.Random(SEED + 11)
    registry = _lib.effect_registry()
    handle = _lib.new_handle(2)
    agreed = {True: 0, False: 0}
    try:
        for case in range(CASES * 4):
            name = rng.choice(_PLAIN_EFFECTS)
            text, ok = _parameter_text(rng, registry[name]["parameters"])
            status = _lib.lib.sph_effect(handle, name.encode(),
                                         text.encode())
            message = _lib.errmsg(handle)
            assert status in (0, 1), (SEED, case, name, text, status)
            assert (status == 0) == ok, (SEED, case, name, text, message)
            if status:
                assert name in message and "\n" not in message, message
                assert len(message) < 512, message
            agreed[ok] += 1
            _lib.lib.sph_effect_off(handle, name.encode())
        # a 5000-character name or key is cut, the known ones still listed
        assert _lib.lib.sph_effect(handle, b"x" * 5000, b"") == 1
        assert "(known: artificial_viscosity" in _lib.errmsg(handle)
        assert _lib.lib.sph_effect(handle, b"xsph", b"y" * 5000 + b"=1") == 1
        assert _lib.errmsg(handle).endswith("...' (known: epsilon)")
    finally:
        _lib.lib.sph_destroy(handle)
    assert min(agreed.values()) > CASES // 2, agreed
