"""docs/developer.md's checklists name exactly the files: every path they
name exists for every registered effect, kernel, integrator, LAMMPS style
and command, and every registered integrator has its C record, stage
calls, LAMMPS fix, fix page and Python class."""
import re
from pathlib import Path

import pytest

from sphsolid import _lib, cli
from sphsolid.dynamics import dynamics_for

from public_header import public_header_text

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "developer.md"
PLUGIN = ROOT / "lammps_plugin" / "sphsolid_plugin.cpp"
pytestmark = pytest.mark.skipif(not GUIDE.is_file() or not PLUGIN.is_file(),
                                reason="no source tree")


def checklists() -> dict:
    """{title: text} of the sections of '## Checklists'."""
    text = GUIDE.read_text()
    part = text[text.index("## Checklists"):]
    part = part[:part.index("\n## ", 1)]
    sections = re.split(r"\n### ", part)[1:]
    return {s.split("\n", 1)[0].strip(): s for s in sections}


def named_paths(text: str) -> set:
    """The repository paths a checklist names in backticks."""
    return {p for p in re.findall(r"`([^`\s]+)`", text)
            if "/" in p and not p.startswith("/")
            and re.search(r"\.(c|h|cpp|py|md|rst|txt)$|/$", p)}


DEPRECATED = re.compile(r"deprecated name of (\w+) (\S+)")


def registrations() -> list:
    """(kind, style, description) of every add(...) of the plugin."""
    return re.findall(r'add\(reg, lmp, handle, "(\w+)", "([^"]+)",\s*"([^"]*)"',
                      PLUGIN.read_text())


def plugin_styles(atom_table: bool = True) -> list:
    """(kind, style) of every add(...) in the plugin but the deprecated
    aliases, and (``atom_table``) the per-atom computes of its atom_styles
    table."""
    source = PLUGIN.read_text()
    styles = [(kind, style) for kind, style, text in registrations()
              if not DEPRECATED.match(text)]
    if atom_table:
        table = source[source.index("atom_styles[][2]"):]
        table = table[:table.index("};")]
        styles += [("compute", s) for s in re.findall(r'\{"([^"]+)",', table)]
    return styles


def style_file(kind: str, style: str) -> str:
    """'fix', 'sphsolid/leapfrog' -> 'fix_sphsolid_leapfrog'."""
    return f"{kind}_{style.lower().replace('/', '_')}"


def expansions(title: str) -> list:
    """The {placeholder: value} sets a checklist's paths are read with."""
    if title == "Add an integrator":
        return [{"<name>": n} for n in _lib.integrator_names()]
    if title == "Add a LAMMPS style":
        out = []
        # the atom_styles rows share compute_sphsolid_atom.* (named there)
        for kind, style in plugin_styles(atom_table=False):
            name = style_file(kind, style)[len(kind) + len("_sphsolid"):]
            out.append({"<kind>": kind, "_<name>": name})
        return out
    if title == "Add a `sphsolid` command":
        return [{"<name>": m.__name__.rsplit(".", 1)[1]}
                for m in cli.COMMANDS]
    return [{}]


def test_the_guide_has_the_checklists():
    assert {"Add an effect", "Add a kernel", "Add an integrator",
            "Add a LAMMPS style", "Add a `sphsolid` command"} <= \
        set(checklists())


@pytest.mark.parametrize("title", sorted(checklists()) if GUIDE.is_file()
                         else [])
def test_every_path_a_checklist_names_exists(title):
    text = checklists()[title]
    missing = []
    for values in expansions(title):
        for path in named_paths(text):
            for key, value in values.items():
                path = path.replace(key, value)
            if "<" in path:
                missing.append(f"{path} (placeholder not expanded)")
            elif not (ROOT / path).exists():
                missing.append(path)
    assert not missing, f"{title}: {sorted(set(missing))}"


@pytest.mark.parametrize("name", _lib.integrator_names())
def test_every_integrator_has_its_record_fix_page_and_class(name):
    src = ROOT / "libsphsolid" / "src"
    records = [p for p in src.rglob("*.c")
               if f"const integrator integrator_{name} " in p.read_text()
               or f"const integrator integrator_{name}=" in p.read_text()]
    assert len(records) == 1, records
    assert records[0].name in (ROOT / "libsphsolid" /
                               "CMakeLists.txt").read_text()
    assert f"&integrator_{name}" in \
        (src / "integrators" / "integrator_registry.c").read_text()
    assert re.search(rf"extern const integrator integrator_{name}\b",
                     (src / "integrators" / "integrator.h").read_text())
    assert dynamics_for(name).integrator == name
    # the plugin runs integrator <name> as fix sphsolid/<name>
    fix = name
    assert ("fix", f"sphsolid/{name}") in plugin_styles()
    page = ROOT / "docs" / "lammps" / f"fix_sphsolid_{fix}.rst"
    assert page.is_file() and f"sphsolid/{fix}" in page.read_text()
    source = ROOT / "lammps_plugin" / f"fix_sphsolid_{fix}.cpp"
    assert source.is_file() and f"fix_sphsolid_{fix}.cpp" in \
        (ROOT / "lammps_plugin" / "CMakeLists.txt").read_text()
    # the fix runs the integrator through its stage API of sphsolid.h
    header = public_header_text()
    stages = set(re.findall(r"\b(sph_\w+_strided)\(", source.read_text()))
    assert stages and all(f"{s}(" in header for s in stages)


def test_every_plugin_style_has_a_doc_page():
    pages = ROOT / "docs" / "lammps"
    missing = [style_file(k, s) for k, s in plugin_styles()
               if not (pages / f"{style_file(k, s)}.rst").is_file()]
    assert not missing


def test_the_planners_effects_are_registered():
    from sphsolid.planner.settings import MANAGED_EFFECTS
    assert set(MANAGED_EFFECTS) <= set(_lib.effect_names())


def test_every_effect_and_kernel_has_its_registry_row():
    effects = (ROOT / "libsphsolid" / "src" / "effects" / "effects.c").read_text()
    rows = effects[effects.index("#define SPH_EFFECTS(X)"):]
    for name in _lib.effect_names():
        assert re.search(rf"\bX\({name},", rows), name
    kernel_h = (ROOT / "libsphsolid" / "src" / "physics" / "kernel.h").read_text()
    header = public_header_text()
    for name in _lib.kernel_names():
        assert re.search(rf"\bX\(SPH_KERNEL_{name.upper()}, {name},",
                         kernel_h), name
        assert re.search(rf"\bSPH_KERNEL_{name.upper()} = \d+", header), name


def test_a_deprecated_style_names_its_replacement_on_its_page():
    aliases = [(k, s, DEPRECATED.match(t).groups()) for k, s, t
               in registrations() if DEPRECATED.match(t)]
    for kind, style, (new_kind, new_style) in aliases:
        assert (new_kind, new_style) in plugin_styles() and new_kind == kind
        page = ROOT / "docs" / "lammps" / f"{style_file(kind, new_style)}.rst"
        assert f"{kind} {style}" in page.read_text(), (style, page)
