"""The standalone library on the paper's scene, through ctypes.

The reference the plugin is compared with: libsphsolid's own scene builder
(sph_build_paper_scene), its own neighbour search, Improved Euler driver
and probes.  The shared library is the one built next to the plugin
(``<build>/libsphsolid/libsphsolid.so``), so both use the same code.
"""
from __future__ import annotations

import ctypes
from ctypes import POINTER, Structure, byref, c_char_p, c_double, c_int, c_long, c_void_p
from pathlib import Path

import numpy as np

PROBE_VALUES_2D = 6  # von Mises, pressure, sigma xx yy zz xy


class PaperScene(Structure):
    _fields_ = [(name, c_int) for name in
                ("specimen", "piston", "plate", "material", "probe_A", "probe_B", "probe_C")]


class BodyInfo(Structure):
    _fields_ = [("name", c_char_p), ("material", c_int), ("motion", c_int),
                ("first", ctypes.c_size_t), ("count", ctypes.c_size_t), ("spacing", c_double)]


def load_library(plugin: Path) -> ctypes.CDLL:
    path = plugin.parent.parent / "libsphsolid" / "libsphsolid.so"
    if not path.is_file():
        raise FileNotFoundError(f"libsphsolid.so not found next to the plugin: {path}")
    lib = ctypes.CDLL(str(path))
    lib.sph_create.argtypes = [c_int, POINTER(c_void_p)]
    lib.sph_destroy.argtypes = [c_void_p]
    lib.sph_errmsg.argtypes = [c_void_p]
    lib.sph_errmsg.restype = c_char_p
    lib.sph_build_paper_scene.argtypes = [c_void_p, c_double, c_double, c_int, POINTER(PaperScene)]
    lib.sph_effect.argtypes = [c_void_p, c_char_p, c_char_p]
    lib.sph_set_integrator.argtypes = [c_void_p, c_char_p]
    lib.sph_body_info_get.argtypes = [c_void_p, c_int, POINTER(BodyInfo)]
    lib.sph_set_motion.argtypes = [c_void_p, c_int, c_int, POINTER(c_double)]
    lib.sph_default_dt.argtypes = [c_void_p]
    lib.sph_default_dt.restype = c_double
    lib.sph_run.argtypes = [c_void_p, c_long]
    lib.sph_probe_sample.argtypes = [c_void_p, c_int, POINTER(c_double)]
    lib.sph_set_threads.argtypes = [c_void_p, c_int]
    lib.sph_particle_count.argtypes = [c_void_p]
    lib.sph_particle_count.restype = ctypes.c_size_t
    lib.sph_field_copy.argtypes = [c_void_p, c_int, POINTER(c_double)]
    return lib


# sph_field_id values and their columns in 2D
FIELDS_2D = {"position": (0, 2), "velocity": (1, 2), "density": (2, 1),
             "deviatoric_stress": (3, 4), "pressure": (5, 1), "von_mises": (6, 1),
             "stress": (7, 4)}


class PaperRun:
    """The paper scene in the library, sampled like the LAMMPS deck."""

    def __init__(self, lib: ctypes.CDLL, dx: float, speed: float = 0.0015,
                 gravity_only: bool = False, effects: dict[str, str] | None = None,
                 pressure: float = 0.0, integrator: str = "improved_euler"):
        self.lib = lib
        self.dx = dx
        self.sim = c_void_p()
        self._check(lib.sph_create(2, byref(self.sim)))
        self._check(lib.sph_set_threads(self.sim, 1))
        self.scene = PaperScene()
        self._check(lib.sph_build_paper_scene(self.sim, dx, speed, int(gravity_only),
                                              byref(self.scene)))
        if pressure > 0.0:
            # SPH_MOTION_FORCE: the pressure on the piston's 86 mm face
            force = (c_double * 3)(0.0, -pressure * 0.086, 0.0)
            self._check(lib.sph_set_motion(self.sim, self.scene.piston, 3, force))
        for name, parameters in (effects or {}).items():
            self._check(lib.sph_effect(self.sim, name.encode(), parameters.encode()))
        self._check(lib.sph_set_integrator(self.sim, integrator.encode()))
        self.dt = lib.sph_default_dt(self.sim)

    def _check(self, status: int) -> None:
        if status != 0:
            raise RuntimeError(self.lib.sph_errmsg(self.sim).decode())

    def run(self, steps: int) -> None:
        self._check(self.lib.sph_run(self.sim, steps))

    def probes(self) -> np.ndarray:
        """A, B, C values in a row: 3 x (von Mises, P, sxx, syy, szz, sxy)."""
        out = []
        for probe in (self.scene.probe_A, self.scene.probe_B, self.scene.probe_C):
            values = (c_double * PROBE_VALUES_2D)()
            self._check(self.lib.sph_probe_sample(self.sim, probe, values))
            out.extend(values)
        return np.array(out)

    def history(self, steps: int, every: int) -> np.ndarray:
        """Rows (step, time, A..., B..., C...) every `every` steps from step 0."""
        rows = [np.concatenate([[0, 0.0], self.probes()])]
        for k in range(every, steps + 1, every):
            self.run(every)
            rows.append(np.concatenate([[k, k * self.dt], self.probes()]))
        return np.array(rows)

    def field(self, name: str) -> np.ndarray:
        """A copy of a per-particle field (2D scene), shape (n, columns)."""
        field_id, cols = FIELDS_2D[name]
        n = self.lib.sph_particle_count(self.sim)
        out = np.zeros(n * cols)
        self._check(self.lib.sph_field_copy(self.sim, field_id,
                                            out.ctypes.data_as(POINTER(c_double))))
        return out.reshape(n, cols)

    def body_field(self, name: str, body: int) -> np.ndarray:
        """`field(name)` restricted to one body's particles."""
        info = BodyInfo()
        self._check(self.lib.sph_body_info_get(self.sim, body, byref(info)))
        return self.field(name)[info.first:info.first + info.count]

    def close(self) -> None:
        if self.sim:
            self.lib.sph_destroy(self.sim)
            self.sim = c_void_p()
