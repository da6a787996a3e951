"""A 3D block squeezed along x: the plugin equals the library, on 1 and 2 ranks.

Covers the 3D paths (six stress components, positions passed in place) with
a free 10 x 10 x 10 block of spacing 1 mm given the velocity field
v_x = -100/s * (x - 5 mm): a uniaxial strain rate that builds pressure and
deviatoric stress.  Same tolerances as the 2D comparisons.
"""
from __future__ import annotations

import ctypes
import textwrap
from ctypes import POINTER, byref, c_double, c_int, c_void_p

import numpy as np

from conftest import run_deck

DECK = textwrap.dedent("""\
    plugin load ${plugin}
    units si
    dimension 3
    boundary f f f
    atom_style atomic
    atom_modify map array
    comm_modify vel yes
    region box block -0.005 0.015 -0.005 0.015 -0.005 0.015 units box
    create_box 1 box
    lattice sc 0.001 origin 0.5 0.5 0.5
    region block block 0.0 0.01 0.0 0.01 0.0 0.01 units box
    create_atoms 1 region block
    mass 1 $(2300.0*0.001^3)
    pair_style sphsolid 0.001 artificial_viscosity alpha 1.0 beta 0.0
    pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0
    neighbor 0.0003 bin
    variable vx atom -100.0*(x-0.005)
    velocity all set v_vx 0.0 0.0 units box
    fix integrate all sphsolid/improved_euler
    compute rho all sphsolid/density/atom
    compute stress all sphsolid/stress/atom
    run 50
    write_dump all custom final.txt id x y z c_rho c_stress[*] modify sort id format float %.17g
    """)


def library_block(lib: ctypes.CDLL, steps: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    sim = c_void_p()
    assert lib.sph_create(3, byref(sim)) == 0

    def check(status):
        assert status == 0, lib.sph_errmsg(sim).decode()

    try:
        check(lib.sph_set_threads(sim, 1))
        material, body = c_int(), c_int()
        lib.sph_add_material_K_mu.argtypes = [c_void_p, c_double, c_double, c_double, POINTER(c_int)]
        check(lib.sph_add_material_K_mu(sim, 12.2e9, 2.67e9, 2300.0, byref(material)))
        lo, hi = (c_double * 3)(0, 0, 0), (c_double * 3)(0.01, 0.01, 0.01)
        lib.sph_add_block.argtypes = [c_void_p, ctypes.c_char_p, c_int, POINTER(c_double),
                                      POINTER(c_double), c_double, POINTER(c_int)]
        check(lib.sph_add_block(sim, b"block", material, lo, hi, 0.001, byref(body)))
        check(lib.sph_effect(sim, b"artificial_viscosity", b"alpha=1 beta=0"))
        n = lib.sph_particle_count(sim)
        x = np.zeros(3 * n)
        check(lib.sph_field_copy(sim, 0, x.ctypes.data_as(POINTER(c_double))))
        v = np.zeros((n, 3))
        v[:, 0] = -100.0 * (x.reshape(n, 3)[:, 0] - 0.005)
        lib.sph_field.argtypes = [c_void_p, c_int, POINTER(POINTER(c_double)),
                                  POINTER(ctypes.c_size_t), POINTER(ctypes.c_size_t)]
        data, rows, cols = POINTER(c_double)(), ctypes.c_size_t(), ctypes.c_size_t()
        check(lib.sph_field(sim, 1, byref(data), byref(rows), byref(cols)))
        for k, value in enumerate(v.ravel()):
            data[k] = value
        check(lib.sph_run(sim, steps))
        fields = []
        for field_id, ncol in ((0, 3), (2, 1), (7, 6)):
            out = np.zeros(n * ncol)
            check(lib.sph_field_copy(sim, field_id, out.ctypes.data_as(POINTER(c_double))))
            fields.append(out.reshape(n, ncol))
        return tuple(fields)
    finally:
        lib.sph_destroy(sim)


def lattice_order(x: np.ndarray) -> np.ndarray:
    cells = np.round(x / 0.0005).astype(np.int64)
    return np.lexsort((cells[:, 0], cells[:, 1], cells[:, 2]))


def test_squeezed_3d_block_matches_library_on_one_and_two_ranks(tmp_path, plugin, library):
    deck = tmp_path / "in.block3d"
    deck.write_text(DECK)
    runs = {}
    for ranks in (1, 2):
        work = tmp_path / f"np{ranks}"
        work.mkdir()
        run_deck(deck, work, {}, plugin, ranks=ranks)
        runs[ranks] = np.loadtxt(work / "final.txt", skiprows=9)
    one, two = runs[1], runs[2]
    assert one.shape == (1000, 11)
    scale = np.abs(one).max(axis=0)
    assert (np.abs(one - two) / scale).max() < 1e-10

    x, rho, stress = library_block(library, 50)
    mine, theirs = lattice_order(one[:, 1:4]), lattice_order(x)
    np.testing.assert_allclose(one[mine, 1:4], x[theirs], rtol=0, atol=1e-15)
    np.testing.assert_allclose(one[mine, 4], rho[theirs, 0], rtol=1e-14)
    c0_squared_ulp = 12.2e9 / 2300.0 * np.spacing(2300.0)
    assert np.abs(stress[theirs]).max() > 1.0e5  # the squeeze built stress
    assert np.abs(one[mine, 5:] - stress[theirs]).max() < 64 * c0_squared_ulp
