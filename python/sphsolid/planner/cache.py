"""Calibration runs kept on disk between plans.

A plan's calibration runs (and effect detection runs) are keyed by what
determines them: the scene (its name and the parameters its factory was
given), the library's version and a digest of its file (a rebuilt
library is a new scope), and the run's own key (spacing, setting, end
time, quantity, threads). :class:`RunCache` is the dictionary
:func:`~sphsolid.planner.plan` fills (its ``cache=``), backed by one
file per entry under ``$SPHSOLID_CACHE`` (default
``$XDG_CACHE_HOME/sphsolid/plan``, else ``~/.cache/sphsolid/plan``), so a
second request on the same scene reuses them. An entry that cannot be
read (truncated, written by another version of Python's pickle) is a miss
and is written again; entries are written to a temporary name and renamed,
so an interrupted plan leaves no partial entry.
"""
from __future__ import annotations

import hashlib
import os
import pickle
from collections.abc import MutableMapping
from pathlib import Path

from .._lib import library_path
from .._lib import version as library_version


def cache_root() -> Path:
    """Where calibration runs are kept (see the module's text)."""
    explicit = os.environ.get("SPHSOLID_CACHE")
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "sphsolid" / "plan"


def _library_digest() -> str:
    """A digest of the loaded library's file: a rebuilt library (whose
    version string a development build does not change) is a new scope."""
    try:
        return hashlib.sha256(library_path().read_bytes()).hexdigest()[:16]
    except OSError:
        return "unknown"


def _digest(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:32]


class RunCache(MutableMapping):
    """Calibration runs of one scene, in memory and on disk.

    ``scene`` names what the factory builds (for the project's scenes their
    name and factory parameters; for a scene file its contents' hash): two
    caches with the same ``scene`` on the same library version share runs.
    ``root=None`` keeps them in memory only."""

    def __init__(self, scene: str, root: Path | str | None = "default"):
        self.scope = f"{scene}|{library_version()}|{_library_digest()}"
        self.memory: dict = {}
        if root == "default":
            root = cache_root()
        self.folder = (Path(root) / _digest(self.scope)
                       if root is not None else None)
        self.hits = self.misses = 0

    def _path(self, key) -> Path | None:
        if self.folder is None:
            return None
        return self.folder / (_digest(repr(key)) + ".pkl")

    def __getitem__(self, key):
        if key in self.memory:
            return self.memory[key]
        path = self._path(key)
        if path is not None and path.is_file():
            try:
                with open(path, "rb") as handle:
                    stored_key, value = pickle.load(handle)
            except Exception:   # unreadable entry: a miss, written again
                stored_key, value = None, None
            if stored_key == repr(key):
                self.memory[key] = value
                self.hits += 1
                return value
        self.misses += 1
        raise KeyError(key)

    def __contains__(self, key) -> bool:
        try:
            self[key]
        except KeyError:
            return False
        return True

    def __setitem__(self, key, value) -> None:
        self.memory[key] = value
        path = self._path(key)
        if path is None:
            return
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            temporary = path.with_suffix(f".tmp{os.getpid()}")
            with open(temporary, "wb") as handle:
                pickle.dump((repr(key), value), handle)
            os.replace(temporary, path)
        except OSError:
            # a cache that cannot be written costs time, never a result
            self.folder = None

    def runs_of(self, setting, until: float, quantity: str,
                threads) -> list:
        """Every calibration run of ``setting`` kept in this cache (in
        memory or on disk) to ``until``, of ``quantity``, on ``threads``."""
        def wanted(key) -> bool:
            return (isinstance(key, tuple) and len(key) == 5
                    and key[1] == setting and key[2] == float(until)
                    and key[3] == quantity and key[4] == threads)
        found = {repr(k): v for k, v in self.memory.items() if wanted(k)}
        if self.folder is not None and self.folder.is_dir():
            for path in self.folder.glob("*.pkl"):
                try:
                    with open(path, "rb") as handle:
                        stored_key, value = pickle.load(handle)
                except Exception:
                    continue
                run_setting = getattr(value, "setting", None)
                if stored_key in found or run_setting != setting:
                    continue
                key = (float(f"{value.dx:.6g}"), setting, float(until),
                       quantity, threads)
                if repr(key) == stored_key:
                    found[stored_key] = value
                    self.memory[key] = value
        return list(found.values())

    def __delitem__(self, key) -> None:
        self.memory.pop(key, None)
        path = self._path(key)
        if path is not None and path.is_file():
            path.unlink()

    def __iter__(self):
        return iter(self.memory)

    def __len__(self) -> int:
        return len(self.memory)

    def values(self):
        return self.memory.values()
