"""Units wherever a length or a time is taken: every public function of
the package with a length or time parameter (found by its parameter names)
gives the same result for a unit string as for the SI number."""
import importlib
import inspect

import numpy as np
import pytest

import sphsolid
import sphsolid.lammps
from sphsolid import build, scenes

from scene_texts import block_toml

LENGTHS = {"dx", "lo", "hi", "x", "y", "z", "width", "depth", "height",
           "radius", "length", "diameter", "base", "center", "centre",
           "r_inner", "r_outer", "point", "points", "spacing", "domain"}
TIMES = {"dt", "until", "time", "t"}
MODULES = ["sphsolid.builders", "sphsolid.scenes", "sphsolid.scene",
           "sphsolid.probes", "sphsolid.dynamics", "sphsolid.io.trajectory",
           "sphsolid.calculators", "sphsolid.lammps", "sphsolid.io.scenefile",
           "sphsolid.presets"]
#: records filled by the readers, not entry points
NOT_ENTRY_POINTS = {"sphsolid.io.trajectory.Frame",
                    "sphsolid.io.trajectory.ProbeSeries"}


def _entry_points() -> dict:
    """{qualified name: the length and time parameters} of the public
    functions, classes and methods of MODULES (abstract methods aside)."""
    found = {}
    for module_name in MODULES:
        module = importlib.import_module(module_name)
        for name in module.__all__:
            obj = getattr(module, name)
            if getattr(obj, "__module__", None) != module_name:
                continue
            targets = [(f"{module_name}.{name}", obj)]
            if inspect.isclass(obj):
                targets += [(f"{module_name}.{name}.{m}", f)
                            for m, f in vars(obj).items()
                            if not m.startswith("_") and inspect.isfunction(f)
                            and not getattr(f, "__isabstractmethod__", False)]
            for qualified, target in targets:
                try:
                    parameters = inspect.signature(target).parameters
                except (TypeError, ValueError):
                    continue
                taken = set(parameters) & (LENGTHS | TIMES)
                if taken and qualified not in NOT_ENTRY_POINTS:
                    found[qualified] = taken
    return found


def rock():
    return scenes.paper_material()


def same_body(a, b):
    np.testing.assert_allclose(a.positions, b.positions, rtol=0, atol=1e-15)
    assert a.dx == pytest.approx(b.dx, rel=1e-15)


def small_scene(dx="4mm"):
    return scenes.uniaxial_piston(dx)


def _body(tmp_path):
    with_units = build.Body(name="b", material=rock(), dx="1mm",
                            lo=("0mm", "0mm"), hi=("4mm", "2mm"))
    same_body(with_units, build.Body(name="b", material=rock(), dx=1e-3,
                                     lo=(0, 0), hi=(0.004, 0.002)))
    cloud = build.Body(name="c", material=rock(), dx="1mm",
                       points=[("0.5mm", "0.5mm"), ("1.5mm", "0.5mm")])
    np.testing.assert_allclose(cloud.points, [[5e-4, 5e-4], [1.5e-3, 5e-4]])
    tube = build.Body(name="t", material=rock(), dx="2mm", radius="5mm",
                      length="1cm", base=("0mm", "0mm", "0mm"))
    assert (tube.shape, tube.radius, tube.length) == ("cylinder", 5e-3, 1e-2)


def _rotation(tmp_path):
    assert build.Rotation(2.0, ("0mm", "5mm")).vector(None, 2) == \
        pytest.approx([0.0, 5e-3])


RECIPES = {
    "sphsolid.builders.Body": _body,
    "sphsolid.builders.Rotation": _rotation,
    "sphsolid.builders.block": lambda tmp_path: same_body(
        build.block(("0mm", "0mm"), ("10mm", "2cm"), "1mm", rock()),
        build.block((0, 0), (0.01, 0.02), 1e-3, rock())),
    "sphsolid.builders.rectangle": lambda tmp_path: same_body(
        build.rectangle(x=("-25mm", "25mm"), y=(0, "50mm"), dx="5mm",
                        material=rock()),
        build.rectangle((-0.025, 0.025), (0, 0.05), 5e-3, rock())),
    "sphsolid.builders.box": lambda tmp_path: same_body(
        build.box(("0mm", "6mm"), ("0mm", "4mm"), ("0mm", "2mm"), "2mm",
                  rock()),
        build.box((0, 0.006), (0, 0.004), (0, 0.002), 2e-3, rock())),
    "sphsolid.builders.prism": lambda tmp_path: same_body(
        build.prism("8mm", "4mm", "6mm", "2mm", rock(),
                    base=("0mm", "1mm", "0mm")),
        build.prism(0.008, 0.004, 0.006, 2e-3, rock(), base=(0, 1e-3, 0))),
    "sphsolid.builders.cylinder": lambda tmp_path: same_body(
        build.cylinder("5mm", "1cm", "2mm", rock(), base=("1mm", 0, 0)),
        build.cylinder(0.005, 0.01, 2e-3, rock(), base=(1e-3, 0, 0))),
    "sphsolid.builders.particles": lambda tmp_path: same_body(
        build.particles([("0.5mm", "0.5mm"), ("1.5mm", 5e-4)], "1mm",
                        rock()),
        build.particles([(5e-4, 5e-4), (1.5e-3, 5e-4)], 1e-3, rock())),
    "sphsolid.builders.disc": lambda tmp_path: same_body(
        build.disc(("0mm", "1cm"), "5mm", "1mm", rock()),
        build.disc((0, 0.01), 0.005, 1e-3, rock())),
    "sphsolid.builders.ring": lambda tmp_path: same_body(
        build.ring(("0mm", "0mm"), "2mm", "5mm", "1mm", rock()),
        build.ring((0, 0), 0.002, 0.005, 1e-3, rock())),
}


def _scenes_equal(a, b):
    np.testing.assert_allclose(a.positions, b.positions, rtol=0, atol=1e-15)
    np.testing.assert_allclose(a.velocities, b.velocities, rtol=1e-15)


def _scene_domain(tmp_path):
    a = sphsolid.Scene(2, domain=(("-1m", "-10cm"), ("1m", "10cm")))
    b = sphsolid.Scene(2, domain=((-1.0, -0.1), (1.0, 0.1)))
    assert a.domain == b.domain


def _set_domain(tmp_path):
    a, b = small_scene(), small_scene()
    a.set_domain(("-10cm", "-10cm"), ("10cm", "30cm"))
    b.set_domain((-0.1, -0.1), (0.1, 0.3))
    assert a.domain == b.domain


def _probes(tmp_path):
    scene = small_scene()
    probes = sphsolid.Probes(scene, {"centre": (0, "50mm")})
    probes.add("upper", ("0mm", "10cm"))
    assert probes.points == {"centre": (0.0, 0.05), "upper": (0.0, 0.1)}


def _dynamics(kind):
    def recipe(tmp_path):
        dyn = kind(small_scene(), dt="0.1us")
        assert dyn.dt == pytest.approx(1e-7, rel=1e-15)
    return recipe


def _run_until(tmp_path):
    dyn = sphsolid.ImprovedEuler(small_scene())
    dyn.run(until="1us")
    assert dyn.time == pytest.approx(1e-6, rel=1e-12)


def _nearest(tmp_path):
    scene = small_scene()
    dyn = sphsolid.ImprovedEuler(scene)
    traj = sphsolid.Trajectory(tmp_path / "t.h5", "w", scene,
                               snapshot_interval=2)
    dyn.run(steps=6)
    traj.close()
    with sphsolid.Trajectory(tmp_path / "t.h5") as reader:
        t = float(reader.times[2])
        assert reader.nearest(f"{t * 1e6}us").index == \
            reader.nearest(t).index == 2


def _c_set_dt(tmp_path):
    scene = small_scene()
    scene.calc.set_dt("0.1us")
    assert scene.calc.dt == pytest.approx(1e-7, rel=1e-15)


def _c_advance_until(tmp_path):
    scene = small_scene()
    scene.calc.advance_until("2us")
    assert scene.calc.time == pytest.approx(2e-6, rel=1e-12)


def _lammps(method):
    def recipe(tmp_path):
        if not sphsolid.lammps.available():
            pytest.skip("LAMMPS is not installed")
        scene = small_scene("8mm")
        scene.calc = sphsolid.lammps.Lammps(threads=1)
        if method == "set_dt":
            scene.calc.set_dt("0.1us")
            assert scene.calc.dt == pytest.approx(1e-7, rel=1e-15)
        else:
            scene.calc.set_dt(1e-7)
            scene.calc.advance_until("0.5us")
            assert scene.calc.time == pytest.approx(5e-7, rel=1e-12)
        scene.calc.close()
    return recipe


SCENE_FILE = block_toml(10, "2mm")


def _run_file(tmp_path):
    from sphsolid.scenefile import load, run_file
    path = tmp_path / "block.toml"
    path.write_text(SCENE_FILE)
    spec = load(path)
    body = spec.scene.bodies[0]
    assert (body.lo, body.hi) == ((-0.01, 0.0), (0.01, 0.02))
    written = run_file(path, out=tmp_path, until="1us", log=lambda m: None)
    with sphsolid.Trajectory(written["h5"]) as reader:
        assert reader.times[-1] == pytest.approx(1e-6, rel=1e-12)


RECIPES.update({
    "sphsolid.scenes.uniaxial_piston": lambda tmp_path: _scenes_equal(
        scenes.uniaxial_piston("4mm", velocity="1.5mm/s"),
        scenes.uniaxial_piston(4e-3, velocity=1.5e-3)),
    "sphsolid.scenes.uniaxial_cylinder": lambda tmp_path: _scenes_equal(
        scenes.uniaxial_cylinder("9mm", diameter="54mm", length="13.5cm"),
        scenes.uniaxial_cylinder(9e-3, diameter=0.054, length=0.135)),
    "sphsolid.scenes.gravity": lambda tmp_path: _scenes_equal(
        scenes.gravity("4mm", g="9.81m/s2"), scenes.gravity(4e-3, g=9.81)),
    "sphsolid.scene.Scene": _scene_domain,
    "sphsolid.scene.Scene.set_domain": _set_domain,
    "sphsolid.scene.Scene.support_layers": lambda tmp_path: (
        small_scene().support_layers("4mm")
        == small_scene().support_layers(4e-3) == 3) or pytest.fail(),
    "sphsolid.probes.Probes": _probes,
    "sphsolid.probes.Probes.add": _probes,
    "sphsolid.dynamics.Dynamics": _dynamics(sphsolid.ImprovedEuler),
    "sphsolid.dynamics.ImprovedEuler": _dynamics(sphsolid.ImprovedEuler),
    "sphsolid.dynamics.Leapfrog": _dynamics(sphsolid.Leapfrog),
    "sphsolid.dynamics.Dynamics.run": _run_until,
    "sphsolid.io.trajectory.Trajectory.nearest": _nearest,
    "sphsolid.calculators.Calculator.steps_until": lambda tmp_path: (
        small_scene().calc.steps_until("1.05us")
        == small_scene().calc.steps_until(1.05e-6)) or pytest.fail(),
    "sphsolid.calculators.CLibrary.set_dt": _c_set_dt,
    "sphsolid.calculators.CLibrary.advance_until": _c_advance_until,
    "sphsolid.lammps.Lammps.set_dt": _lammps("set_dt"),
    "sphsolid.lammps.Lammps.advance_until": _lammps("advance_until"),
    "sphsolid.io.scenefile.run_file": _run_file,
})


def test_every_entry_point_with_a_length_or_time_has_a_unit_check():
    found = _entry_points()
    assert set(found) == set(RECIPES), (
        f"without a check: {sorted(set(found) - set(RECIPES))}; "
        f"no longer entry points: {sorted(set(RECIPES) - set(found))}")


@pytest.mark.parametrize("name", sorted(RECIPES))
def test_a_unit_string_gives_the_si_result(name, tmp_path):
    RECIPES[name](tmp_path)


@pytest.mark.parametrize("call, message", [
    (lambda: build.rectangle(x=("-25ms", "25mm"), y=(0, 1), dx=1e-3,
                             material=rock()),
     "rectangle x (x0, x1)[0] is a length, but '-25ms' is a time"),
    (lambda: sphsolid.Probes(small_scene(), {"c": (0, "50mm/s")}),
     "probe 'c' point[1] is a length, but '50mm/s' is a velocity"),
    (lambda: sphsolid.ImprovedEuler(small_scene()).run(until="3mm"),
     "until is a time, but '3mm' is a length"),
])
def test_a_unit_of_the_wrong_kind_is_named(call, message):
    with pytest.raises(ValueError) as info:
        call()
    assert message in str(info.value)


def test_effect_parameters_take_units_on_every_backend():
    scene = small_scene("8mm")
    scene.effect("gravity", gx=0, gy="-9.81m/s2")
    # the scene keeps the SI numbers it passed to the library (a LAMMPS
    # backend builds its deck from them)
    assert scene.effects["gravity"] == {"gx": 0.0, "gy": -9.81}
    with pytest.raises(ValueError, match="effect parameter alpha: 'x' is "
                       "not a number"):
        scene.effect("artificial_viscosity", alpha="x")
    if sphsolid.lammps.available():
        scene.calc = sphsolid.lammps.Lammps(threads=1)
        sphsolid.ImprovedEuler(scene).run(steps=1)
        scene.calc.close()
