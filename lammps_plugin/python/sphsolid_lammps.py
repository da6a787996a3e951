"""Run the libsphsolid LAMMPS plugin from Python (repository scripts).

The helpers live in the installed package, :mod:`sphsolid.lammps`
(``open_lammps``, ``preload_mpi``, ``mpi_bin_dir``, ``find_plugin``); this
module re-exports them for the repository's tests, examples and
benchmarks, and looks for the plugin of this checkout first:

1. the environment variable ``SPHSOLID_LAMMPS_PLUGIN``;
2. ``build-lammps/lammps_plugin/sphsolidplugin.so`` and
   ``build/lammps_plugin/sphsolidplugin.so`` in this repository;
3. wherever :func:`sphsolid.lammps.find_plugin` finds one.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parents[2]
_BUILD_DIRS = ("build-lammps", "build")

try:
    import sphsolid.lammps as _backend
except ImportError:     # not installed: the package of this checkout
    sys.path.insert(0, str(REPOSITORY / "python"))
    import sphsolid.lammps as _backend

from sphsolid.lammps import mpi_bin_dir, preload_mpi  # noqa: E402

__all__ = ["REPOSITORY", "plugin_path", "preload_mpi", "open_lammps", "mpi_bin_dir"]


def plugin_path() -> Path:
    """Path of ``sphsolidplugin.so``; raises FileNotFoundError naming where it looked."""
    env = os.environ.get("SPHSOLID_LAMMPS_PLUGIN")
    candidates = [Path(env)] if env else [
        REPOSITORY / d / "lammps_plugin" / "sphsolidplugin.so" for d in _BUILD_DIRS]
    for c in candidates:
        if c.is_file():
            return c.resolve()
    if not env:
        try:
            return _backend.find_plugin(search_cwd=False).resolve()
        except OSError:
            pass
    raise FileNotFoundError(
        "sphsolidplugin.so not found (looked at %s); build it with "
        "lammps_plugin/setup_env.sh or 'sphsolid build-plugin', or set "
        "SPHSOLID_LAMMPS_PLUGIN" % ", ".join(str(c) for c in candidates))


def open_lammps(cmdargs: list[str] | None = None, plugin: Path | None = None):
    """:func:`sphsolid.lammps.open_lammps` with this checkout's plugin."""
    return _backend.open_lammps(cmdargs, plugin=plugin or plugin_path())
