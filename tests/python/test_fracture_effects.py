"""The optional effects of the tests to failure: ``drucker_prager`` (the
builders' ``plasticity``) and ``artificial_stress`` (docs/fracture.md,
"Pressure-dependent strength")."""
import json
import math

import numpy as np
import pytest

from sphsolid import fracture

#: The effects of the fracture scenes before the options existed (seed 1,
#: member 0): damage and the artificial viscosity alpha 1, nothing else.
PLAIN = {"damage": {"seed": 1.0, "flaws": 10.0, "member": 0.0},
         "artificial_viscosity": {"alpha": 1.0, "beta": 0.0}}
BUILDERS = {"ucs": (fracture.ucs, 4e-3),
            "brazilian": (fracture.brazilian_disc, 4e-3),
            "tensile": (fracture.tensile_bar, 5e-3)}


def cone_strength(c, phi_deg, r):
    """Axial strength of the library's Drucker-Prager cone (fitted to
    Mohr-Coulomb on its compression meridian) for principal stresses
    (sigma, r sigma, 0), compression positive:
    sqrt(J2) = A + B P with P = (1 + r) sigma / 3 and
    J2 = sigma^2 (1 + r^2 + (1 - r)^2) / 6."""
    s = math.sin(math.radians(phi_deg))
    A = 6 * c * math.cos(math.radians(phi_deg)) / (math.sqrt(3) * (3 - s))
    B = 6 * s / (math.sqrt(3) * (3 - s))
    return A / (math.sqrt((1 + r * r + (1 - r) ** 2) / 6) - B * (1 + r) / 3)


def test_the_cone_is_mohr_coulomb_in_uniaxial_stress():
    # r = 0 is the uniaxial stress state: 2 c cos(phi) / (1 - sin(phi))
    phi = math.radians(30)
    assert cone_strength(2e6, 30, 0.0) == pytest.approx(
        2 * 2e6 * math.cos(phi) / (1 - math.sin(phi)), rel=1e-12)


def test_drucker_prager_caps_the_ucs_at_its_plane_strain_cone():
    """c = 2 MPa, phi = 30 deg, dx = 4 mm, seed 1, to 0.8 % strain.

    Uniaxial stress would fail at 2 c cos(phi) / (1 - sin(phi)) = 6.93
    MPa, but the specimen is in plane strain: elastic, sigma_zz = nu sigma
    (nu = 0.398), where the cone gives 13.3 MPa; steady plastic flow
    (no out-of-plane plastic strain: s_zz = 0, sigma_zz = sigma / 2)
    would raise it to 15.6 MPa (1.17 x). The bonded platens make the
    field uneven (the corners yield first), which lowers the load a
    little: 12.8 MPa at 2 mm (docs/fracture.md); at 4 mm the plateau
    from 0.2 % on lies between 11.1 and 13.2 MPa (mean 12.0). So the
    band is 0.8-1.2 x 13.3 MPa: wide enough for those, and far from
    the elastic-damage UCS (26.5 MPa at 4 mm), from the uniaxial 6.93
    MPa and from the extension meridian (sigma_zz = sigma: 20.8 MPa).
    """
    rock = fracture.fracture_material()
    nu = (3 * rock.K - 2 * rock.mu) / (2 * (3 * rock.K + rock.mu))
    cone = cone_strength(2e6, 30, nu)
    assert cone == pytest.approx(13.3e6, rel=0.01)

    brittle = fracture.load_to_break(fracture.ucs(4e-3), max_strain=0.008)
    scene = fracture.ucs(4e-3, plasticity={"cohesion": 2e6,
                                           "friction_angle": 30})
    assert scene.effects["drucker_prager"] == {"cohesion": 2e6,
                                               "friction_angle": 30.0}
    plastic = fracture.load_to_break(scene, max_strain=0.008)

    # the elastic-damage specimen cracks at about twice the cone
    assert brittle.post_peak_ratio < 0.5
    assert plastic.strength_Pa < 0.7 * brittle.strength_Pa
    # a plastic plateau: no drop to the strain limit, no fragments
    assert plastic.strain[-1] >= 0.008 - 1e-6
    assert plastic.post_peak_ratio > 0.8
    assert plastic.fragments == 1
    stress = plastic.load / 0.086
    plateau = stress[plastic.strain >= 0.002]
    assert 0.8 * cone < plateau.min() and plateau.max() < 1.2 * cone
    assert np.mean(plateau) == pytest.approx(cone, rel=0.2)
    assert plastic.strength_Pa == pytest.approx(cone, rel=0.2)


@pytest.mark.parametrize("test", sorted(BUILDERS))
def test_without_the_options_the_effects_are_as_before(test):
    make, dx = BUILDERS[test]
    assert make(dx).effects == PLAIN
    assert make(dx, plasticity=None, artificial_stress=None).effects == PLAIN
    assert fracture.test_scene(test, dx).effects == PLAIN


@pytest.mark.parametrize("test", sorted(BUILDERS))
def test_the_options_reach_every_builder_through_test_scene(test):
    _, dx = BUILDERS[test]
    scene = fracture.test_scene(
        test, dx, plasticity={"cohesion": 5e6, "friction_angle": 40},
        artificial_stress={"epsilon": 0.3})
    assert scene.effects == {
        **PLAIN, "drucker_prager": {"cohesion": 5e6, "friction_angle": 40.0},
        "artificial_stress": {"epsilon": 0.3}}


def test_bad_effect_options_are_named():
    with pytest.raises(ValueError, match="plasticity=5000000.0"):
        fracture.ucs(4e-3, plasticity=5e6)
    with pytest.raises(ValueError, match="cohesion"):
        fracture.ucs(4e-3, plasticity={"friction_angle": 30})
    with pytest.raises(ValueError, match="friction_angle=90"):
        fracture.ucs(4e-3, plasticity={"cohesion": 1e6, "friction_angle": 90})
    with pytest.raises(ValueError, match="epsilon=2"):
        fracture.tensile_bar(5e-3, artificial_stress={"epsilon": 2})


# ------------------------------------------------------------ the CLI
def _run(capsys, argv, out):
    from sphsolid.cli import main
    assert main(argv + ["--threads", "1", "--out", str(out)]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    return json.loads((out / "summary.json").read_text()), first


def test_sphsolid_ucs_cohesion_reaches_the_scene_and_caps_the_ucs(
        tmp_path, capsys):
    summary, first = _run(capsys, ["ucs", "--dx", "4mm", "--cohesion",
                                   "2MPa", "--friction-angle", "30"],
                          tmp_path)
    assert summary["effects"] == {
        **PLAIN, "drucker_prager": {"cohesion": 2e6, "friction_angle": 30.0}}
    assert first.endswith("optional effects: drucker_prager (cohesion 2 "
                          "MPa, friction angle 30 deg)")
    # the plane-strain cone (see the test above), no drop to 0.8 %
    cone = cone_strength(2e6, 30, 0.398)
    assert summary["strength_Pa"] == pytest.approx(cone, rel=0.2)
    assert summary["post_peak_ratio"] > 0.8


def test_sphsolid_ucs_defaults_leave_the_effects_as_before(tmp_path,
                                                           capsys):
    summary, first = _run(capsys, ["ucs", "--dx", "4mm", "--max-strain",
                                   "0.05%"], tmp_path)
    assert summary["effects"] == PLAIN == fracture.ucs(4e-3).effects
    assert first.endswith("optional effects: none")


@pytest.mark.parametrize("test, dx", [("tensile", "5mm"),
                                      ("brazilian", "4mm")])
def test_the_effect_options_reach_every_test(test, dx, tmp_path, capsys):
    # --cohesion alone takes the library's friction angle, 30 degrees
    summary, first = _run(capsys, [test, "--dx", dx, "--max-strain",
                                   "0.02%", "--cohesion", "5e6",
                                   "--artificial-stress", "0.3"], tmp_path)
    assert summary["effects"] == {
        **PLAIN, "drucker_prager": {"cohesion": 5e6, "friction_angle": 30.0},
        "artificial_stress": {"epsilon": 0.3}}
    assert first.endswith("drucker_prager (cohesion 5 MPa, friction angle "
                          "30 deg), artificial_stress (epsilon 0.3)")


@pytest.mark.parametrize("argv, message", [
    (["--cohesion", "-1MPa"], "--cohesion: '-1MPa': must be a finite "
     "stress >= 0"),
    (["--cohesion", "5mm"], "'5mm' is a length"),
    (["--cohesion", "2MPa", "--friction-angle", "90"],
     "--friction-angle: '90': must be in [0, 90) degrees"),
    (["--cohesion", "2MPa", "--friction-angle", "-5"],
     "--friction-angle: '-5': must be in [0, 90) degrees"),
    (["--artificial-stress", "1"], "--artificial-stress: '1': must be in "
     "(0, 1)"),
    (["--artificial-stress", "0"], "--artificial-stress: '0': must be in "
     "(0, 1)"),
    (["--artificial-stress", "x"], "--artificial-stress: 'x': not a "
     "number")])
def test_bad_effect_values_are_refused_naming_them(argv, message, capsys):
    from sphsolid import cli
    with pytest.raises(SystemExit) as stop:
        cli.build_parser().parse_args(["ucs"] + argv)
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_friction_angle_without_cohesion_is_refused(tmp_path, capsys):
    from sphsolid.cli import main
    out = tmp_path / "out"
    assert main(["ucs", "--friction-angle", "30", "--out", str(out)]) == 2
    assert ("--friction-angle 30 applies only with --cohesion"
            in capsys.readouterr().err)
    assert not out.exists()            # refused before anything is made
