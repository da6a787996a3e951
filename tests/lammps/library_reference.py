"""The standalone library on the paper's scene, through the sphsolid
package's binding (sphsolid._lib: the prototypes are declared once).

The reference the plugin is compared with: libsphsolid's own scene builder
(sph_build_paper_scene), its own neighbour search, integrators and probes.
The plugin compiles the same library sources, so both run the same code.
"""
from __future__ import annotations

import ctypes
from ctypes import byref, c_double
from pathlib import Path

import numpy as np
from sphsolid import _lib

PROBE_VALUES_2D = _lib.probe_values(2)  # von Mises, pressure, sigma xx yy zz xy


def load_library(plugin: Path):
    """The library as the sphsolid package loads it (``plugin`` is kept for
    the fixture's signature: the plugin holds its own copy of the code)."""
    return _lib.lib


# sph_field_id values and their columns in 2D
FIELDS_2D = {"position": (_lib.FIELD_POSITION, 2), "velocity": (_lib.FIELD_VELOCITY, 2),
             "density": (_lib.FIELD_DENSITY, 1),
             "deviatoric_stress": (_lib.FIELD_DEVIATORIC_STRESS, 4),
             "pressure": (_lib.FIELD_PRESSURE, 1), "von_mises": (_lib.FIELD_VON_MISES, 1),
             "stress": (_lib.FIELD_STRESS, 4)}


class PaperRun:
    """The paper scene in the library, sampled like the LAMMPS deck."""

    def __init__(self, lib: ctypes.CDLL, dx: float, speed: float = 0.0015,
                 gravity_only: bool = False, effects: dict[str, str] | None = None,
                 pressure: float = 0.0, integrator: str = "improved_euler"):
        self.lib = lib
        self.dx = dx
        self.sim = _lib.new_handle(2)
        self._check(lib.sph_set_threads(self.sim, 1))
        self.scene = _lib.PaperScene()
        self._check(lib.sph_build_paper_scene(self.sim, dx, speed, int(gravity_only),
                                              byref(self.scene)))
        if pressure > 0.0:
            # SPH_MOTION_FORCE: the pressure on the piston's 86 mm face
            force = (c_double * 3)(0.0, -pressure * 0.086, 0.0)
            self._check(lib.sph_set_motion(self.sim, self.scene.piston, _lib.MOTION_FORCE,
                                           force))
        for name, parameters in (effects or {}).items():
            self._check(lib.sph_effect(self.sim, name.encode(), parameters.encode()))
        self._check(lib.sph_set_integrator(self.sim, integrator.encode()))
        self.dt = lib.sph_default_dt(self.sim)

    def _check(self, status: int) -> None:
        _lib.check(status, self.sim)

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
                                            out.ctypes.data_as(ctypes.POINTER(c_double))))
        return out.reshape(n, cols)

    def body_field(self, name: str, body: int) -> np.ndarray:
        """`field(name)` restricted to one body's particles."""
        info = _lib.BodyInfo()
        self._check(self.lib.sph_body_info_get(self.sim, body, byref(info)))
        return self.field(name)[info.first:info.first + info.count]

    def close(self) -> None:
        if self.sim:
            self.lib.sph_destroy(self.sim)
            self.sim = None
