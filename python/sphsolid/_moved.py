"""Module paths that moved when the package was laid out by job: each old
path still imports, and gives the module at its new path (the same module
object, so ``from sphsolid.build import block``,
``import sphsolid.trajectory`` and a test's
``monkeypatch.setattr(sys.modules["sphsolid.ensemble"], ...)`` work as
before).  No file is left at an old path; the module is imported only when
the old path is, as a file there would be."""
from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys

#: {old module path: new module path}
MOVED = {
    "sphsolid.build": "sphsolid.builders",
    "sphsolid.trajectory": "sphsolid.io.trajectory",
    "sphsolid.scenefile": "sphsolid.io.scenefile",
    "sphsolid.checkpoint": "sphsolid.io.checkpoint",
    "sphsolid.figures": "sphsolid.io.figures",
    "sphsolid.ensemble": "sphsolid.fracture.ensemble",
    "sphsolid.planner.strength": "sphsolid.fracture.strength",
}


class _OldPaths(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds an old path of :data:`MOVED` and loads it as its new one."""

    def find_spec(self, name, path=None, target=None):
        if name not in MOVED:
            return None
        return importlib.util.spec_from_loader(name, self)

    def create_module(self, spec):
        module = importlib.import_module(MOVED[spec.name])
        spec.loader_state = module.__spec__
        return module

    def exec_module(self, module):
        # the import system gave the module the old path's spec: give its
        # own back (reload and introspection see the new path)
        module.__spec__ = module.__spec__.loader_state


def install() -> None:
    """Let the old paths import (once per process)."""
    if not any(isinstance(finder, _OldPaths) for finder in sys.meta_path):
        sys.meta_path.append(_OldPaths())


install()  # on importing sphsolid, which imports this module first
