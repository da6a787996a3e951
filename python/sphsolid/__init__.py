"""sphsolid: SPH for elastic solids, scripted from Python.

An ASE-like front end to libsphsolid (the C library that holds all the
physics): build bodies, put them in a :class:`Scene` with the effects it
calls for, advance it with :class:`ImprovedEuler`, watch it with
:class:`Probes` and a :class:`Trajectory`, and draw the paper's figures::

    from sphsolid import ImprovedEuler, Probes, Trajectory, scenes

    scene = scenes.uniaxial_piston(dx=2e-3)
    probes = Probes(scene, scenes.PAPER_PROBES)
    dyn = ImprovedEuler(scene)
    dyn.attach(probes, interval=10)
    dyn.run(until=0.3e-3)
"""
import sys as _sys

from . import _moved  # first: sphsolid.build, sphsolid.trajectory, ... import
from ._lib import (SimulationError, StoppedError, UnsupportedError,
                   effect_names, effect_registry, kernel_names,
                   kernel_negative_from, kernel_values, library_path,
                   version)
from .builders import (Body, Fixed, Force, Free, Pressure, Rotation,
                       Velocity, block, box, cylinder, disc, particles,
                       piston, plate, prism, rectangle, ring)
from .calculators import Calculator, CLibrary
from .dynamics import Dynamics, ImprovedEuler, Leapfrog
from .material import Material
from .probes import PAPER_PROBES, Probes
from .scene import Scene, allowing_large
from . import scenes
from . import planner


class _PlanEntry:
    """``sphsolid.plan(factory, error=...)`` plans a run
    (:func:`sphsolid.planner.plan`); ``sphsolid.plan.Plan`` and the other
    names of :mod:`sphsolid.planner` are reachable through it."""

    __wrapped__ = staticmethod(planner.plan)

    def __call__(self, *args, **kwargs):
        return planner.plan(*args, **kwargs)

    def __getattr__(self, name):
        return getattr(planner, name)

    def __dir__(self):
        return dir(planner)

    def __repr__(self):
        return "<sphsolid.plan: the planner (sphsolid.planner.plan)>"


plan = _PlanEntry()


class _EnsembleEntry:
    """``sphsolid.ensemble(test, members, out, ...)`` runs an ensemble of
    flaw draws (:func:`sphsolid.ensemble.ensemble`); the module's other
    names (``bootstrap_mean_interval``, ``run_member``, ...) are reachable
    through it."""

    def __init__(self, module):
        self._module = module
        self.__wrapped__ = module.ensemble
        self.__doc__ = module.ensemble.__doc__

    def __call__(self, *args, **kwargs):
        return self._module.ensemble(*args, **kwargs)

    def __getattr__(self, name):
        return getattr(self._module, name)

    def __dir__(self):
        return dir(self._module)

    def __repr__(self):
        return "<sphsolid.ensemble: flaw ensembles (sphsolid.ensemble.ensemble)>"


from .fracture import ensemble as _ensemble_module  # noqa: E402

ensemble = _EnsembleEntry(_ensemble_module)
# the old module path, registered now so that importing it keeps the entry
_sys.modules.setdefault("sphsolid.ensemble", _ensemble_module)


def _package_version() -> str:
    """The installed package's version (scikit-build-core takes it from
    project(VERSION) in CMakeLists.txt); from a source tree, the library's."""
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as metadata_version
    try:
        return metadata_version("sphsolid")
    except PackageNotFoundError:
        return version().split()[0]


__version__ = _package_version()

__all__ = ["Material", "Scene", "allowing_large", "Body", "Free", "Fixed", "Velocity", "Force",
           "Pressure", "Rotation", "block", "rectangle", "box", "prism", "cylinder",
           "particles", "plate", "piston", "disc", "ring", "Calculator", "CLibrary", "Dynamics", "ImprovedEuler",
           "Leapfrog", "Probes", "PAPER_PROBES", "Trajectory", "scenes", "plan", "planner", "ensemble",
           "effect_names", "effect_registry", "kernel_names",
           "kernel_negative_from", "kernel_values", "version",
           "library_path", "SimulationError", "StoppedError",
           "UnsupportedError"]


def __getattr__(name):
    if name == "Trajectory":  # h5py is imported only when needed
        from .io.trajectory import Trajectory
        return Trajectory
    if f"{__name__}.{name}" in _moved.MOVED:  # sphsolid.trajectory.Frame
        import importlib
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'sphsolid' has no attribute {name!r}")
