"""Linear elastic materials."""
from __future__ import annotations

import ctypes
from dataclasses import dataclass, field, fields

from . import _lib
from ._lib import lib

__all__ = ["Material"]


def _number(name: str, value) -> float:
    """A number (the library judges its value)."""
    try:
        return _lib.number(value, name)
    except ValueError:
        raise ValueError(f"Material: {name} must be a number, got "
                         f"{value!r}") from None


@dataclass(frozen=True)
class Material:
    """A linear elastic material, from any consistent pair of constants.

    Give ``rho0`` and exactly one of the pairs (K, mu), (E, nu) or (K, nu)::

        rock = Material(K=12.2e9, mu=2.67e9, rho0=2300)
        steel = Material(E=200e9, nu=0.3, rho0=7850)

    The other constants (Poisson ratio by eq. (10) of the paper, Young's
    modulus, sound speeds) are computed by libsphsolid, not here.

    Parameters
    ----------
    rho0 : float
        Reference density [kg/m^3], > 0.
    K : float, optional
        Bulk modulus [Pa], > 0.
    mu : float, optional
        Shear modulus [Pa], >= 0.
    E : float, optional
        Young's modulus [Pa], > 0.
    nu : float, optional
        Poisson ratio [-], -1 < nu < 0.5.
    name : str, optional
        A label for reports.
    weibull_k, weibull_m : float, optional
        Flaws of the Weibull law n(eps) = k V eps^m for the effect
        ``damage``: k [m^-3] (per metre of depth in 2D: V = area x 1 m)
        and the exponent m [-]; 0 (default): no flaws (docs/fracture.md).
    keys : dict, optional
        Any other key of the library's material registry
        (:func:`sphsolid._lib.material_keys`, set with ``sph_material_set``)
        by name, in SI units; the library judges names and values.

    Attributes
    ----------
    K, mu, E, nu, rho0 : float
        All five constants [Pa, Pa, Pa, -, kg/m^3].
    c0 : float
        Bulk sound speed sqrt(K/rho0) [m/s] (sets the default time step).
    c_p : float
        P-wave speed sqrt((K + 4 mu/3)/rho0) [m/s].
    """

    rho0: float
    K: float | None = None
    mu: float | None = None
    E: float | None = None
    nu: float | None = None
    name: str = ""
    weibull_k: float = 0.0
    weibull_m: float = 0.0
    keys: dict = field(default_factory=dict, hash=False)
    c0: float = field(init=False, default=0.0)
    c_p: float = field(init=False, default=0.0)
    pair: str = field(init=False, default="")

    def __post_init__(self):
        given = {k: getattr(self, k) for k in ("K", "mu", "E", "nu")
                 if getattr(self, k) is not None}
        pairs = {frozenset(("K", "mu")): "K_mu", frozenset(("E", "nu")): "E_nu",
                 frozenset(("K", "nu")): "K_nu"}
        pair = pairs.get(frozenset(given))
        if pair is None:
            raise ValueError(
                "Material: give rho0 and exactly one pair of (K, mu), (E, nu)"
                f" or (K, nu); got {sorted(given) or 'none'}")
        rho0 = _number("rho0", self.rho0)
        values = {k: _number(k, v) for k, v in given.items()}
        # the library checks the ranges and names the value
        for key in ("weibull_k", "weibull_m"):
            object.__setattr__(self, key, _number(key, getattr(self, key)))
        object.__setattr__(self, "keys", _keys(self))
        info = _library_info(pair, values, rho0, self.weibull_k,
                             self.weibull_m, self.keys)
        set_ = object.__setattr__
        set_(self, "pair", pair)
        set_(self, "rho0", rho0)
        set_(self, "K", info.bulk_modulus)
        set_(self, "mu", info.shear_modulus)
        set_(self, "E", info.youngs_modulus)
        set_(self, "nu", info.poisson_ratio)
        set_(self, "c0", info.c0)
        set_(self, "c_p", info.c_p)
        set_(self, "_given", values)

    def add_to(self, handle) -> int:
        """Register this material in a library handle; returns its index.

        The pair the user gave is passed to the matching
        ``sph_add_material_*`` so the library does the conversion.
        """
        index = ctypes.c_int()
        given = self._given
        if self.pair == "K_mu":
            status = lib.sph_add_material_K_mu(handle, given["K"], given["mu"],
                                               self.rho0, ctypes.byref(index))
        elif self.pair == "E_nu":
            status = lib.sph_add_material_E_nu(handle, given["E"], given["nu"],
                                               self.rho0, ctypes.byref(index))
        else:
            status = lib.sph_add_material_K_nu(handle, given["K"], given["nu"],
                                               self.rho0, ctypes.byref(index))
        _lib.check(status, handle, "Material")
        for key in ("weibull_k", "weibull_m"):
            value = getattr(self, key, 0.0)
            if value:
                _lib.check(lib.sph_material_set(handle, index.value,
                                                key.encode(), value),
                           handle, "Material")
        for key, value in getattr(self, "keys", {}).items():
            _lib.check(lib.sph_material_set(handle, index.value,
                                            key.encode(), value),
                       handle, "Material")
        return index.value

    def __repr__(self):
        label = f"{self.name!r}, " if self.name else ""
        return (f"Material({label}K={self.K:.4g} Pa, mu={self.mu:.4g} Pa, "
                f"E={self.E:.4g} Pa, nu={self.nu:.4g}, rho0={self.rho0:g} "
                f"kg/m^3)")


def _keys(material) -> dict:
    """Material.keys checked: a mapping of names (not the dataclass's own
    fields) to numbers."""
    keys = material.keys
    if not isinstance(keys, dict):
        raise ValueError(f"Material: keys must be a dict of material keys, "
                         f"got {keys!r}")
    own = {f.name for f in fields(Material)}
    out = {}
    for key, value in keys.items():
        if not isinstance(key, str):
            raise ValueError(f"Material: a key must be a name, got {key!r}")
        if key in own:
            raise ValueError(f"Material: give {key} as Material({key}=...),"
                             " not in keys")
        out[key] = _number(key, value)
    return out


def _library_info(pair, values, rho0, weibull_k=0.0,
                  weibull_m=0.0, keys=None) -> _lib.MaterialInfo:
    """Let libsphsolid validate and convert the constants."""
    handle = _lib.new_handle(2)
    try:
        material = Material.__new__(Material)
        object.__setattr__(material, "pair", pair)
        object.__setattr__(material, "rho0", rho0)
        object.__setattr__(material, "_given", values)
        object.__setattr__(material, "weibull_k", weibull_k)
        object.__setattr__(material, "weibull_m", weibull_m)
        object.__setattr__(material, "keys", dict(keys or {}))
        index = Material.add_to(material, handle)
        info = _lib.MaterialInfo()
        _lib.check(lib.sph_material_info_get(handle, index,
                                             ctypes.byref(info)),
                   handle, "Material")
        return info
    finally:
        lib.sph_destroy(handle)
