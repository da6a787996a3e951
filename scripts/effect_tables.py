#!/usr/bin/env python3
"""The effect tables of the docs, written from the library's registry.

    python scripts/effect_tables.py           # print both tables
    python scripts/effect_tables.py --check   # exit 1 if a doc disagrees
    python scripts/effect_tables.py --write   # rewrite the docs' tables

The registry (libsphsolid/src/effects/effects.c, asked through
``sphsolid._lib.effect_registry``) is the one place an effect, its
parameters, defaults and ranges are written; docs/library.md holds its
Markdown table and docs/lammps/pair_sphsolid.rst one keyword line per
effect.  tests/python/test_registry.py runs the check.
"""
from __future__ import annotations

import math
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LIBRARY_MD = ROOT / "docs" / "library.md"
PAIR_RST = ROOT / "docs" / "lammps" / "pair_sphsolid.rst"
# Effects the pair style does not take as keywords (LAMMPS has its own).
NOT_PAIR_KEYWORDS = {"gravity": "fix gravity"}


def _registry() -> dict:
    sys.path.insert(0, str(ROOT / "python"))
    from sphsolid import _lib
    return _lib.effect_registry()


def _number(value: float) -> str:
    return f"{value:g}"


def range_text(p: dict) -> str:
    """">= 0", "> 0", "in (0, 1]" or "any" for a registry parameter."""
    lo, hi = p["min"], p["max"]
    if math.isinf(lo) and math.isinf(hi):
        return "any"
    if math.isinf(hi):
        return (">= " if p["min_inclusive"] else "> ") + _number(lo)
    if math.isinf(lo):
        return ("<= " if p["max_inclusive"] else "< ") + _number(hi)
    return ("in " + ("[" if p["min_inclusive"] else "(") + _number(lo) + ", "
            + _number(hi) + ("]" if p["max_inclusive"] else ")"))


def markdown_rows(registry: dict) -> dict[str, str]:
    """One Markdown table row per effect, by name."""
    rows = {}
    for name, effect in registry.items():
        cells = []
        for key, p in effect["parameters"].items():
            unit = f" [{p['unit']}]" if p["unit"] else ""
            if p["default"] is None:
                cells.append(f"`{key}`{unit} (required, {range_text(p)})")
            else:
                cells.append(f"`{key}={_number(p['default'])}`{unit} "
                             f"({range_text(p)})")
        rows[name] = (f"| `{name}` | {', '.join(cells) or '—'} | "
                      f"{effect['description']} |")
    return rows


def markdown_table(registry: dict) -> str:
    return "\n".join([MD_HEADER,
                      "|---|---|---|", *markdown_rows(registry).values()])


def rst_lines(registry: dict) -> dict[str, str]:
    """One parsed-literal keyword line of the pair_style page per effect."""
    lines = {}
    for name, effect in registry.items():
        if name in NOT_PAIR_KEYWORDS:
            continue
        words = []
        for key, p in effect["parameters"].items():
            unit = f"{p['unit']}, " if p["unit"] else ""
            if p["default"] is None:
                words.append(f"*{key}* value ({unit}required, {range_text(p)})")
            else:
                words.append(f"*{key}* value ({unit}default "
                             f"{_number(p['default'])}, {range_text(p)})")
        if not words:
            args = "none"
        elif all(p["default"] is not None
                 for p in effect["parameters"].values()):
            args = "zero or more of " + ", ".join(words)
        else:
            args = ", ".join(words)
        lines[name] = f"       *{name}* args = {args}"
    return lines


_MD_ROW = re.compile(r"^\| `(\w+)` \|")
_RST_LINE = re.compile(r"^\s+\*(\w+)\* args = ")


MD_HEADER = "| effect | parameters (default, range) | what it does |"


def _effect_lines(path: Path) -> range:
    """Indices of the lines that hold the effect table (Markdown: the rows
    under MD_HEADER; rst: the whole page, whose keyword lines are unique)."""
    lines = path.read_text().splitlines()
    if path.suffix != ".md":
        return range(len(lines))
    start = lines.index(MD_HEADER) if MD_HEADER in lines else len(lines)
    end = start
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    return range(start, end)


def _doc_rows(path: Path, pattern: re.Pattern) -> dict[str, str]:
    rows = {}
    lines = path.read_text().splitlines()
    for i in _effect_lines(path):
        match = pattern.match(lines[i])
        if match:
            rows[match.group(1)] = lines[i]
    return rows


def differences(registry: dict | None = None) -> list[str]:
    """What the docs say differently from the registry (empty: agree)."""
    registry = registry or _registry()
    problems = []
    for path, pattern, wanted in (
            (LIBRARY_MD, _MD_ROW, markdown_rows(registry)),
            (PAIR_RST, _RST_LINE, rst_lines(registry))):
        found = _doc_rows(path, pattern)
        where = path.relative_to(ROOT)
        for name in sorted(set(wanted) - set(found)):
            problems.append(f"{where}: no line for effect {name}; want\n"
                            f"  {wanted[name]}")
        for name in sorted(set(found) - set(wanted)):
            problems.append(f"{where}: effect {name} is not in the registry")
        for name in sorted(set(found) & set(wanted)):
            if found[name] != wanted[name]:
                problems.append(f"{where}: effect {name}:\n  has  "
                                f"{found[name]}\n  want {wanted[name]}")
    return problems


def write(registry: dict | None = None) -> None:
    """Replace the docs' existing effect lines by the registry's."""
    registry = registry or _registry()
    for path, pattern, wanted in (
            (LIBRARY_MD, _MD_ROW, markdown_rows(registry)),
            (PAIR_RST, _RST_LINE, rst_lines(registry))):
        lines = path.read_text().splitlines()
        table = set(_effect_lines(path))
        out = []
        for i, line in enumerate(lines):
            match = pattern.match(line) if i in table else None
            if match and match.group(1) in wanted:
                out.append(wanted.pop(match.group(1)))
            elif not match:
                out.append(line)
        if wanted:
            print(f"{path.relative_to(ROOT)}: add by hand:\n  "
                  + "\n  ".join(wanted.values()))
        path.write_text("\n".join(out) + "\n")


def main(argv: list[str]) -> int:
    registry = _registry()
    if "--check" in argv:
        problems = differences(registry)
        for problem in problems:
            print(problem)
        return 1 if problems else 0
    if "--write" in argv:
        write(registry)
        return 0
    print(markdown_table(registry))
    print()
    print("\n".join(rst_lines(registry).values()))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
