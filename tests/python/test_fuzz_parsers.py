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
