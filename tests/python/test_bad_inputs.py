"""Bad input fails at once with a ValueError or OSError naming the field."""
import pytest

import sphsolid
from sphsolid import build, scenes


def rock():
    return scenes.paper_material()


def specimen(dx=2e-3):
    return build.rectangle((-0.043, 0.043), (0.0, 0.140), dx, rock())


def _negative_dx():
    build.rectangle((0, 1), (0, 1), -1e-3, rock())


def _zero_dx():
    build.block((0, 0), (1, 1), 0.0, rock())


def _poisson_one_half():
    sphsolid.Material(E=1e9, nu=0.5, rho0=1000)


def _negative_bulk_modulus():
    sphsolid.Material(K=-1e9, mu=1e9, rho0=1000)


def _negative_shear_modulus():
    sphsolid.Material(K=1e9, mu=-1.0, rho0=1000)


def _zero_density():
    sphsolid.Material(K=1e9, mu=1e9, rho0=0.0)


def _inconsistent_pair():
    sphsolid.Material(K=1e9, E=1e9, rho0=1000)


def _overlapping_bodies():
    body = specimen()
    # a lattice shifted by dx/4 from the specimen's: particles dx/4 apart
    sphsolid.Scene(2, [body, build.rectangle((0.0005, 0.0205), (0.1, 0.12),
                                             2e-3, rock(), name="intruder")])


def _unknown_effect():
    sphsolid.Scene(2, effects={"artificial_viscocity": {"alpha": 1.0}})


def _unknown_effect_key():
    sphsolid.Scene(2, effects={"gravity": {"gq": -9.81}})


def _probe_point_wrong_shape():
    sphsolid.Probes(scenes.uniaxial_piston(4e-3), {"A": (0.0, 0.07, 0.0)})


def _velocity_wrong_shape():
    build.piston(over=specimen(), velocity=(0.0, -1.0, 0.0, 1.0))


def _domain_wrong_shape():
    sphsolid.Scene(2, domain=((0.0, 0.0, 0.0), (1.0, 1.0)))


def _unreadable_file(tmp_path):
    sphsolid.Trajectory(tmp_path / "missing.h5")


def _not_hdf5_file(tmp_path):
    path = tmp_path / "notes.h5"
    path.write_text("not an HDF5 file")
    sphsolid.Trajectory(path)


def _bad_dimension():
    sphsolid.Scene(4)


def _thin_plate():
    body = specimen()
    sphsolid.Scene(2, [body, build.plate(under=body, layers=2)])


def _body_outside_domain():
    sphsolid.Scene(2, [specimen()], domain=((-0.01, -0.01), (0.01, 0.01)))


def _negative_dt():
    sphsolid.ImprovedEuler(scenes.uniaxial_piston(4e-3), dt=-1e-7)


def _unstable_dt():
    sphsolid.ImprovedEuler(scenes.uniaxial_piston(4e-3), dt=1e-4)


def _zero_interval():
    dyn = sphsolid.ImprovedEuler(scenes.uniaxial_piston(4e-3))
    dyn.attach(lambda: None, interval=0)


def _negative_steps():
    sphsolid.ImprovedEuler(scenes.uniaxial_piston(4e-3)).run(steps=-5)


def _negative_pressure():
    body = specimen()
    sphsolid.Scene(2, [body, build.plate(under=body),
                       build.piston(over=body,
                                    motion=build.Pressure(-1e5))])


def _rotation_vector_in_2d():
    sphsolid.Scene(2, [build.rectangle((0, 0.01), (0, 0.01), 1e-3, rock(),
                                       motion=build.Rotation((0.0, 0.0, 5.0), (0.0, 0.0)))])


def _rotation_centre_wrong_shape():
    sphsolid.Scene(2, [build.rectangle((0, 0.01), (0, 0.01), 1e-3, rock(),
                                       motion=build.Rotation(5.0, (0.0,)))])


def _rotation_about_x_in_2d_refused_by_the_library():
    # the library names the component: in 2D only omega_z
    scene = sphsolid.Scene(2, [build.rectangle((0, 0.01), (0, 0.01), 1e-3, rock())])
    centre = sphsolid._lib.as_doubles([0.0, 0.0], 2, "centre")
    omega = sphsolid._lib.as_doubles([1.0, 0.0, 0.0], 3, "omega")
    scene._check(sphsolid._lib.lib.sph_set_rotation(scene.handle, 0, centre, omega), "rotation")


def _duplicate_body_name():
    sphsolid.Scene(2, [specimen(), build.rectangle((0.1, 0.2), (0, 0.1),
                                                   2e-3, rock())])


CASES = [
    (_negative_dx, ValueError, r"dx"),
    (_zero_dx, ValueError, r"dx"),
    (_poisson_one_half, ValueError, r"nu|Poisson"),
    (_negative_bulk_modulus, ValueError, r"\bK\b|bulk"),
    (_negative_shear_modulus, ValueError, r"mu|shear"),
    (_zero_density, ValueError, r"rho0"),
    (_inconsistent_pair, ValueError, r"pair"),
    (_overlapping_bodies, ValueError, r"intruder|overlap"),
    (_unknown_effect, ValueError, r"artificial_viscocity"),
    (_unknown_effect_key, ValueError, r"gq"),
    (_probe_point_wrong_shape, ValueError, r"probe 'A' point"),
    (_velocity_wrong_shape, ValueError, r"velocity"),
    (_domain_wrong_shape, ValueError, r"domain lo"),
    (_unreadable_file, OSError, r"missing\.h5"),
    (_not_hdf5_file, OSError, r"notes\.h5"),
    (_bad_dimension, ValueError, r"dimension"),
    (_thin_plate, ValueError, r"layers=2"),
    (_body_outside_domain, ValueError, r"specimen|domain"),
    (_negative_dt, ValueError, r"dt"),
    (_unstable_dt, ValueError, r"dt"),
    (_zero_interval, ValueError, r"interval"),
    (_negative_steps, ValueError, r"steps"),
    (_negative_pressure, ValueError, r"Pressure\.pressure"),
    (_duplicate_body_name, ValueError, r"specimen"),
    (_rotation_vector_in_2d, ValueError, r"Rotation\.omega"),
    (_rotation_centre_wrong_shape, ValueError, r"Rotation\.centre"),
    (_rotation_about_x_in_2d_refused_by_the_library, ValueError, r"omega_x=1"),
]


@pytest.mark.parametrize("case, error, field", CASES,
                         ids=[c[0].__name__.strip("_") for c in CASES])
def test_bad_input_raises_naming_the_field(case, error, field, tmp_path):
    import inspect
    args = (tmp_path,) if inspect.signature(case).parameters else ()
    with pytest.raises(error, match=field) as info:
        case(*args)
    print(f"{case.__name__}: {info.value}")


def test_at_least_ten_bad_inputs_are_checked():
    assert len(CASES) >= 10
