"""Python holds no copy of the library's rules: the enums of sphsolid.h
are the binding's, and a bad value is judged by the library, whose
message (naming the value) reaches the user unchanged."""
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import sphsolid
from sphsolid import _lib, build, scenes

from public_header import public_header_text

ROOT = Path(__file__).resolve().parents[2]
HEADER = ROOT / "libsphsolid" / "include" / "sphsolid.h"
SOURCES = ROOT / "libsphsolid" / "src"


def _enum(name: str) -> dict:
    """{constant: value} of ``typedef enum name {...}`` in sphsolid.h."""
    text = public_header_text()
    body = re.search(r"typedef enum %s \{(.*?)\} %s;" % (name, name), text,
                     re.S).group(1)
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    return {k: int(v) for k, v in re.findall(r"(SPH_\w+)\s*=\s*(\d+)", body)}


@pytest.mark.skipif(not HEADER.is_file(), reason="no source tree")
def test_status_codes_match_the_header():
    status = _enum("sph_status")
    assert status and status == {k: getattr(_lib, k) for k in status}
    assert _lib.STATUS == {v: k for k, v in status.items()}


@pytest.mark.skipif(not HEADER.is_file(), reason="no source tree")
@pytest.mark.parametrize("enum, prefix", [("sph_field_id", "FIELD_"),
                                          ("sph_motion", "MOTION_")])
def test_field_and_motion_ids_match_the_header(enum, prefix):
    header = {k[len("SPH_"):]: v for k, v in _enum(enum).items()}
    binding = {k: getattr(_lib, k) for k in dir(_lib)
               if k.startswith(prefix) and k.isupper()}
    assert header and binding == header


@pytest.mark.skipif(not HEADER.is_file(), reason="no source tree")
def test_stress_components_match_the_header_macro():
    text = public_header_text()
    two, three = re.search(r"#define SPH_STRESS_COMPONENTS\(dim\) "
                           r"\(\(dim\) == 2 \? (\d+) : (\d+)\)", text).groups()
    assert (_lib.stress_components(2), _lib.stress_components(3)) == \
        (int(two), int(three))
    assert _lib.probe_values(3) == 2 + int(three)


def rock():
    return scenes.paper_material()


def block():
    return build.rectangle((0, 0.01), (0, 0.02), 1e-3, rock())


def _set_dt():
    sphsolid.ImprovedEuler(scenes.uniaxial_piston(4e-3), dt=-1e-7)


def _duplicate_body():
    sphsolid.Scene(2, [block(), build.rectangle((0.1, 0.2), (0, 0.1), 2e-3,
                                                rock())])


def _duplicate_probe():
    sphsolid.Probes(scenes.uniaxial_piston(4e-3), {"A": (0, 0.07)}).add(
        "A", (0, 0.05))


def _domain():
    sphsolid.Scene(2, domain=((1.0, 0.0), (0.0, 1.0)))


# (call, the library's message for it, the format in libsphsolid/src)
CASES = [
    (lambda: sphsolid.Material(K=-1e9, mu=1e9, rho0=1000),
     "bulk modulus K=-1e+09: must be finite and > 0",
     "bulk modulus K=%g: must be finite and > 0"),
    (lambda: sphsolid.Material(K=1e9, mu=-1.0, rho0=1000),
     "shear modulus mu=-1: must be finite and >= 0",
     "shear modulus mu=%g: must be finite and >= 0"),
    (lambda: sphsolid.Material(E=1e9, nu=0.5, rho0=1000),
     "Poisson ratio nu=0.5: must be in (-1, 0.5)",
     "Poisson ratio nu=%g: must be in (-1, 0.5)"),
    (lambda: sphsolid.Material(E=0.0, nu=0.3, rho0=1000),
     "Young's modulus E=0: must be finite and > 0", "%s=%g: must be finite"),
    (lambda: sphsolid.Material(K=1e9, mu=1e9, rho0=0.0),
     "reference density rho0=0: must be finite and > 0",
     "reference density rho0=%g: must be finite and > 0"),
    (lambda: build.plate(under=block(), inset=0.7),
     "platen inset=0.7 lattice steps: must be in (-1, 0.5)",
     "platen inset=%g lattice steps: must be in (-1, 0.5)"),
    (lambda: build.rectangle((0, 1), (0, 1), -1e-3, rock()),
     "block 'specimen': dx=-0.001 must be finite and > 0",
     "block '%s': dx=%g must be finite and > 0"),
    (lambda: build.block((0, 0), (0.01, 0.0), 1e-3, rock()),
     "extent along y is hi-lo=0 (must be > 0)",
     "extent along %c is hi-lo=%g (must be > 0)"),
    (_set_dt, "dt=-1e-07: must be finite and > 0",
     "dt=%g: must be finite and > 0"),
    (_domain, "domain along x: [1, 0] is empty or not finite",
     "domain along %c: [%g, %g] is empty or not finite"),
    (_duplicate_body, "body name 'specimen' is already used",
     "body name '%s' is already used"),
    (_duplicate_probe, "probe name 'A' is already used",
     "probe name '%s' is already used"),
    (lambda: sphsolid.Scene(3, [build.cylinder("-10mm", 0.02, 1e-3,
                                               rock())]),
     "cylinder 'specimen': radius=-0.01 m must be finite and > 0",
     "cylinder '%s': radius=%g m must be finite and > 0"),
    (lambda: sphsolid.Scene(2, [build.particles(np.zeros((1, 2)), 0.0,
                                                rock())]),
     "spacing dx=0 must be finite and > 0",
     "spacing dx=%g must be finite and > 0"),
]


@pytest.mark.parametrize("call, message, source", CASES,
                         ids=[c[1][:40] for c in CASES])
def test_the_library_judges_and_names_the_value(call, message, source):
    with pytest.raises(ValueError) as info:
        call()
    assert message in str(info.value)
    if SOURCES.is_dir():
        # the message is the library's: its format is in the C sources
        assert any(source in p.read_text() for p in SOURCES.rglob("*.c"))


def test_cli_passes_the_librarys_inset_message(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "sphsolid", "piston", "--dx", "4mm",
         "--inset", "0.7", "--out", str(tmp_path)],
        capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert "platen inset=0.7 lattice steps: must be in (-1, 0.5)" in \
        done.stderr
    assert "Traceback" not in done.stderr


def test_a_body_of_points_follows_from_the_points():
    points = np.array([[0.0005 + i * 1e-3, 0.0005 + j * 1e-3]
                       for j in range(4) for i in range(4)])
    body = build.Body(name="cloud", material=rock(), dx=1e-3, points=points)
    assert body.shape == "points" and body.count == 16
    scene = sphsolid.Scene(2, [body])
    assert len(scene) == 16
    np.testing.assert_allclose(scene.positions, points)
    corner = build.Body(name="b", material=rock(), dx=1e-3, lo=(0, 0),
                        hi=(0.004, 0.004))
    assert corner.shape == "block" and corner.count == 16


@pytest.mark.parametrize("fields, message", [
    ({}, "give points (a point set), lo and hi (a block)"),
    ({"lo": (0, 0)}, "give points"),
    ({"lo": (0, 0), "hi": (1, 1), "points": np.zeros((1, 2))},
     "the fields fit points and block"),
    ({"shape": "cylinder", "radius": 0.01}, "'cylinder' body needs length"),
    ({"shape": "sphere"}, "shape 'sphere' is not one of"),
])
def test_a_body_without_its_shape_says_what_is_missing(fields, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        build.Body(name="x", material=rock(), dx=1e-3, **fields)


def test_a_copy_at_another_spacing_has_its_own_lattice():
    import dataclasses
    body = build.rectangle((0, 0.012), (0, 0.024), 1e-3, rock())
    assert body.lattice_shape == (12, 24)
    coarse = dataclasses.replace(body, dx=3e-3)
    assert coarse.lattice_shape == (4, 8) and coarse.count == 32


def test_the_file_format_is_the_librarys(tmp_path):
    import h5py
    from sphsolid import trajectory
    scene = scenes.uniaxial_piston(8e-3)
    traj = sphsolid.Trajectory(tmp_path / "run.h5", "w", scene)
    sphsolid.ImprovedEuler(scene).run(steps=2)
    traj.close()
    with h5py.File(tmp_path / "run.h5") as f:
        written = int(np.ravel(f.attrs["sphsolid_format"])[0])
    assert written == trajectory.file_format() == \
        _lib.lib.sph_output_format_version()
    with sphsolid.Trajectory(tmp_path / "run.h5") as reader:
        assert len(reader.times) == 2


def test_a_format_1_output_is_read():
    """tests/data/format1_output.h5, written by libsphsolid 0.1.0
    (tests/data/make_format1_output.c): a free 6 x 4 block at 1 mm pushed
    down at 1 m/s, dt 1e-7 s, a frame and a probe sample every step for 3
    steps.  With no internal rates frame k is the lattice moved by
    -1 m/s x k dt, at rho0 and zero stress."""
    with sphsolid.Trajectory(ROOT / "tests" / "data" / "format1_output.h5") as old:
        assert old.format == 1
        assert len(old) == 4 and list(old.steps) == [0, 1, 2, 3]
        assert old.times == pytest.approx([0, 1e-7, 2e-7, 3e-7], abs=1e-20)
        assert old.dimension == 2 and old.body_names == ["block"]
        first = old[0]
        i, j = np.meshgrid(np.arange(6), np.arange(4), indexing="ij")
        lattice = {(round(x, 9), round(y, 9)) for x, y in
                   zip(((i + 0.5) * 1e-3).ravel(), ((j + 0.5) * 1e-3).ravel())}
        assert {(round(x, 9), round(y, 9)) for x, y in first.positions} == lattice
        for k, frame in enumerate(old):
            np.testing.assert_allclose(frame.positions[:, 1] - first.positions[:, 1],
                                       -1.0 * k * 1e-7, atol=1e-15)
            np.testing.assert_allclose(frame.velocities, [[0, -1.0]] * 24)
            np.testing.assert_allclose(frame.density, 2300.0)
            assert not frame.deviatoric_stress.any()
        probes = old.probes
        assert probes.names == ["centre"] and len(probes.times) == 4
        assert probes["centre"]["von_mises"] == pytest.approx(np.zeros(4), abs=1e-6)
        assert "frames: 4" in old.describe()


@pytest.mark.parametrize("ratio, kernel", [(1.2, "cubic_spline"),
                                           (1.5, "wendland_c2"),
                                           (1.65, "cubic_o4")])
def test_the_planners_platens_are_the_librarys_support_rows(ratio, kernel):
    # every kernel's support is 2h; the strip's lattice is exactly dx, so
    # at h/dx = 1.5 the support is exactly 3 rows: the library's answer,
    # where a rule with a margin of its own would add a fourth
    from sphsolid.planner import scenes as planner_scenes
    dx = 2e-3
    scene = planner_scenes.strip_factory(dx, smoothing_ratio=ratio,
                                         kernel=kernel)
    strip, plate, piston = scene.bodies
    rows = scene.support_layers(build.layer_spacing(strip))
    assert rows == math.ceil(round(2 * ratio, 9))
    for wall in (plate, piston):
        assert wall.layers == rows
