"""What the user names is what runs: an explicit LAMMPS plugin is the one
loaded (a bad one is an error even when another would load by itself),
cmdargs are a list, and a Dynamics object never drives the integrator of
another one or of a checkpoint."""
import pytest

import sphsolid
from sphsolid import lammps, scenes

ROOT_LIB = sphsolid._lib.library_path


def test_cmdargs_as_a_string_is_refused():
    with pytest.raises(ValueError, match=r"cmdargs must be a list of "
                       r"strings, e\.g\. \['-log', 'none'\], got "
                       r"'-log none'"):
        lammps.open_lammps("-log none")


@pytest.mark.skipif(not lammps.available(), reason="LAMMPS is not installed")
@pytest.mark.parametrize("kind", ["missing", "directory", "text", "library"])
def test_an_explicit_plugin_that_fails_is_an_error(kind, tmp_path,
                                                   monkeypatch):
    good = lammps.find_plugin()
    # the good plugin loads by itself (as an installed entry point does)
    monkeypatch.setenv("LAMMPS_PLUGIN_PATH", str(good.parent))
    lmp = lammps.open_lammps()
    assert lmp.has_style("pair", "sphsolid")
    lmp.close()
    path, message = {
        "missing": (tmp_path / "none.so", "no such file"),
        "directory": (tmp_path, "is a directory, not a plugin file"),
        "text": (tmp_path / "notes.so", "cannot be loaded"),
        "library": (ROOT_LIB(), "is not a LAMMPS plugin (it has no "
                    "lammpsplugin_init"),
    }[kind]
    if kind == "text":
        path.write_text("not a shared object\n")
    with pytest.raises(OSError) as info:
        lammps.open_lammps(plugin=path)
    assert f"plugin {str(path)!r}" in str(info.value)
    assert message in str(info.value)
    # the good plugin, named, still loads
    lmp = lammps.open_lammps(plugin=good)
    assert lmp.has_style("pair", "sphsolid")
    lmp.close()


def test_a_dynamics_object_does_not_drive_another_integrator():
    scene = scenes.uniaxial_piston(8e-3)
    first = sphsolid.ImprovedEuler(scene)
    second = sphsolid.Leapfrog(scene)
    second.run(steps=2)
    with pytest.raises(RuntimeError, match="ImprovedEuler drives the "
                       "'improved_euler' integrator, but the scene now runs "
                       r"'leapfrog'.*make a Leapfrog\(scene\)"):
        first.run(steps=1)
    assert scene.step == 2
    # a new object of the first kind switches back, explicitly
    sphsolid.ImprovedEuler(scene).run(steps=1)
    assert scene.integrator == "improved_euler" and scene.step == 3


def test_a_checkpoint_read_does_not_change_a_dynamics_integrator(tmp_path):
    written = scenes.uniaxial_piston(8e-3)
    sphsolid.Leapfrog(written).run(steps=3)
    written.write_checkpoint(tmp_path / "state.h5")
    scene = scenes.uniaxial_piston(8e-3)
    dyn = sphsolid.ImprovedEuler(scene)
    scene.read_checkpoint(tmp_path / "state.h5")
    assert scene.integrator == "leapfrog"
    with pytest.raises(RuntimeError, match="checkpoint read"):
        dyn.run(steps=1)
    sphsolid.Leapfrog(scene).run(steps=1)
    assert scene.step == 4
