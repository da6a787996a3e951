"""End placement of plate and piston (platen inset) and the named presets.

Derived truths: the laterally periodic strip between plate and piston has
an exact answer (linear acoustics): fronts at (2kH +- y)/c_p, a jump of
rho0 c_p v in sigma_yy behind the first one. Its quasi-static stiffness
M/L is checked in C (tests/c/test_geometry.c); here the end placement's
effect on the reflections and the presets' plumbing.
"""
import numpy as np
import pytest

from sphsolid import build, presets, scenes
from sphsolid.calculators import CLibrary
from sphsolid.probes import Probes

from validation import decomposition, end_placement


def _strip_delays(dx, preset, until, **overrides):
    scene = end_placement.strip_scene(dx, preset, **overrides)
    scene.calc = CLibrary(threads=1)
    dyn = presets.dynamics(scene, progress=False)
    probes = Probes(scene, decomposition.STRIP_PROBES)
    dyn.attach(probes, interval=1)
    dyn.run(until=until)
    result = {"times": np.asarray(probes.times),
              "vm": {n: np.asarray(probes[n]["von_mises"])
                     for n in probes.names}}
    return decomposition.front_delays(result)


def test_paper_preset_is_the_library_default_scene():
    default = scenes.uniaxial_piston(4e-3)
    paper = scenes.uniaxial_piston(4e-3, preset="paper")
    assert paper.preset.name == "paper"
    assert np.array_equal(default.positions, paper.positions)
    assert paper.kernel == "cubic_spline" and paper.smoothing_ratio == 1.2
    assert paper.effects == {"artificial_viscosity": {"alpha": 1.0,
                                                      "beta": 0.0}}
    assert type(presets.dynamics(paper, progress=False)).__name__ \
        == "ImprovedEuler"
    # the platens touch the specimen's extent
    assert paper.bodies[1].hi[1] == 0.0
    assert paper.bodies[2].lo[1] == pytest.approx(scenes.SPECIMEN_Y[1])


def test_waves_preset_sets_kernel_integrator_and_static_inset():
    scene = scenes.uniaxial_piston(2e-3, preset="waves")
    assert scene.kernel == "cubic_o4" and scene.smoothing_ratio == 1.65
    assert scene.effects == {}
    assert type(presets.dynamics(scene, progress=False)).__name__ \
        == "Leapfrog"
    dy = 2e-3
    inset = scene.bodies[1].hi[1] / dy
    assert 0.2 < inset < 0.25                      # 0.227 steps
    assert scene.bodies[2].lo[1] == pytest.approx(
        scenes.SPECIMEN_Y[1] - inset * dy, abs=1e-12)
    # nearest platen rows (1 - inset) dy from the specimen's extreme rows
    plate = scene.positions[scene.body_slice("plate"), 1]
    assert plate.max() == pytest.approx(-(0.5 - inset) * dy, abs=1e-12)
    # explicit arguments override the preset
    other = scenes.uniaxial_piston(2e-3, preset="waves", inset=0.0,
                                   viscosity={"alpha": 0.5, "beta": 0.0})
    assert other.bodies[1].hi[1] == 0.0
    assert other.effects["artificial_viscosity"]["alpha"] == 0.5


@pytest.mark.parametrize("bad", [0.5, -1.0, "rigid", True, float("nan")])
def test_bad_inset_is_refused_naming_the_value(bad):
    rock = scenes.paper_material()
    body = build.rectangle((0, 0.01), (0, 0.02), 1e-3, rock)
    with pytest.raises(ValueError, match="inset"):
        build.plate(under=body, inset=bad)


def test_static_inset_is_refused_where_none_exists():
    with pytest.raises(ValueError, match="least end offset is 1.0"):
        scenes.uniaxial_piston(4e-3, smoothing_ratio=1.5, inset="static")


def test_unknown_preset_lists_the_known_ones():
    with pytest.raises(ValueError, match="paper, waves"):
        scenes.uniaxial_piston(4e-3, preset="fastest")


def test_static_end_offset_predicts_the_delay_of_each_reflection():
    """The strip's fronts against their exact arrivals (2kH +- y)/c_p, paper
    preset at 2 mm. Less the lattice speed's share (the fronts run at
    M c_p, M the lattice gradient moment: a delay (1/M - 1) t), every
    passage adds the delay 2 e dy / c_p of the end it reflected from, e
    the static end offset (sph_platen_end_offset, 1.12 steps): the same
    number must come out of the dynamics. At the static inset (0.396
    steps) that growth is gone."""
    from validation.study import lattice_gradient_moment
    rock = scenes.paper_material()
    dx, until = 2e-3, 0.2e-3
    H = scenes.SPECIMEN_Y[1]
    y = dict(decomposition.STRIP_PROBES)
    probe_scene = end_placement.strip_scene(dx, "paper")
    e = probe_scene.platen_end_offset("specimen", 0.0)
    assert 1.0 < e < 1.25
    M = lattice_gradient_moment(1.2)
    off = _strip_delays(dx, "paper", until)
    on = _strip_delays(dx, "paper", until, inset="static")
    for probe in ("A", "B"):
        yp = y[probe][1]
        arrivals = sorted([(2 * k * H + H - yp) / rock.c_p for k in range(4)]
                          + [(2 * k * H + H + yp) / rock.c_p
                             for k in range(4)])
        speed = [(1 / M - 1) * t for t in arrivals]
        assert len(off[probe]) >= 3 and len(on[probe]) >= 3
        n = min(len(off[probe]), len(on[probe]))
        end_off = [off[probe][i] - speed[i] for i in range(n)]
        end_on = [on[probe][i] - speed[i] for i in range(n)]
        per_front = 2 * e * dx / rock.c_p
        growth_off = (end_off[n - 1] - end_off[0]) / (n - 1)
        growth_on = (end_on[n - 1] - end_on[0]) / (n - 1)
        assert growth_off == pytest.approx(per_front, rel=0.15), (probe, off)
        assert abs(growth_on) < 0.15 * per_front, (probe, on)


def test_waves_preset_front_carries_rho_c_v():
    """Behind the first front, before any reflection: sigma_yy = -rho0 c_p v
    (a front the platen inset must not change)."""
    rock = scenes.paper_material()
    dx, H = 2e-3, scenes.SPECIMEN_Y[1]
    scene = end_placement.strip_scene(dx, "waves")
    scene.calc = CLibrary(threads=1)
    dyn = presets.dynamics(scene, progress=False)
    dyn.run(until=0.5 * H / rock.c_p)
    part = scene.body_slice("specimen")
    y, s_yy = scene.positions[part, 1], scene.stress[part, 1]
    front = H - rock.c_p * scene.time
    behind = (y > front + 5 * scene.h) & (y < H - 4 * scene.h)
    jump = rock.rho0 * rock.c_p * scenes.PISTON_SPEED
    assert -s_yy[behind].mean() / jump == pytest.approx(1.0, abs=0.01)
    # the front where sigma_yy crosses half the jump (lateral means)
    rows = np.round(y / dx).astype(int)
    levels = {r: -s_yy[rows == r].mean() / jump for r in np.unique(rows)}
    crossed = [r * dx for r, v in sorted(levels.items()) if v > 0.5]
    assert abs(min(crossed) - front) < 2 * dx


def test_fronts_preset_runs_the_leapfrog_at_half_its_step():
    """The fronts preset: cubic_o4 at the h/dx of unit lattice moment, the
    leapfrog at half its default step, unless a step is given."""
    from validation.study import lattice_gradient_moment
    scene = scenes.uniaxial_piston(4e-3, preset="fronts")
    assert scene.kernel == "cubic_o4"
    assert lattice_gradient_moment(scene.smoothing_ratio, "cubic_o4") \
        == pytest.approx(1.0, abs=1e-5)
    assert scene.effects == {}
    full = presets.dynamics(scenes.uniaxial_piston(4e-3, preset="waves"),
                            progress=False)
    dyn = presets.dynamics(scene, progress=False)
    assert type(dyn).__name__ == "Leapfrog"
    ratio = scene.smoothing_ratio / 1.65
    assert dyn.dt == pytest.approx(0.5 * ratio * full.dt, rel=1e-12)
    assert presets.dynamics(scene, dt=1e-7, progress=False).dt == 1e-7
    assert presets.preset("fronts").to_dict()["step"] == 0.5
    assert presets.preset("waves").step == 1.0
