"""Quantities with units: ``"2mm"``, ``"0.3ms"``, ``"1.5mm/s"``, ``"12.2GPa"``.

Everything in sphsolid is SI (metres, seconds, kilograms, pascals). Where
a length, time or other quantity is given, a string with a unit is
accepted as well and converted here: the builders (``dx="1mm"``,
``lo=("0mm", "0mm")``), the dynamics (``dt="0.1us"``,
``run(until="0.3ms")``), scene files and the command line. A plain number
(or a string without a unit) is taken as SI. A unit of the wrong kind
(``dx="3ms"``) is an error naming the value.

Large scenes are usually a unit slip (``block((0, 0), (50, 50), dx=2)``
meant millimetres): :func:`check_scale` warns with the numbers.
"""
from __future__ import annotations

import re
import warnings

__all__ = ["quantity", "quantities", "length", "lengths", "time",
           "velocity", "to_si", "in_unit", "UNITS", "ScaleWarning",
           "check_scale"]

_LENGTH = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6,
           "nm": 1e-9, "km": 1e3}
_TIME = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "ns": 1e-9,
         "min": 60.0, "h": 3600.0}

#: unit -> (kind, factor to SI)
UNITS: dict[str, tuple[str, float]] = {}
UNITS.update({u: ("length", f) for u, f in _LENGTH.items()})
UNITS.update({u: ("time", f) for u, f in _TIME.items()})
UNITS.update({f"{lu}/{tu}": ("velocity", lf / tf)
              for lu, lf in _LENGTH.items() for tu, tf in _TIME.items()})
UNITS.update({u: ("pressure", f) for u, f in
              {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9}.items()})
UNITS.update({u: ("force", f) for u, f in
              {"N": 1.0, "kN": 1e3, "MN": 1e6}.items()})
UNITS.update({u: ("density", f) for u, f in
              {"kg/m3": 1.0, "kg/m^3": 1.0, "g/cm3": 1e3,
               "g/cm^3": 1e3}.items()})
UNITS.update({u: ("acceleration", 1.0) for u in ("m/s2", "m/s^2")})
UNITS.update({u: ("energy per area", f) for u, f in
              {"J/m^2": 1.0, "J/m2": 1.0, "kJ/m^2": 1e3,
               "kJ/m2": 1e3}.items()})
UNITS.update({u: ("rate", 1.0) for u in ("1/s", "Hz")})
UNITS.update({u: ("angular velocity", 1.0) for u in ("rad/s",)})

# a number as float() reads it (inf and nan included: the value's own
# check names them), then an optional unit
_PATTERN = re.compile(r"\s*([-+]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
                      r"|(?i:inf(?:inity)?|nan)))\s*(\S*)\s*")


def quantity(value, kind: str | None = None, name: str = "value") -> float:
    """A number in SI units from a number or a string with a unit.

    Parameters
    ----------
    value : float or str
        ``2e-3``, ``"2e-3"``, ``"2mm"``, ``"2 mm"``.
    kind : str, optional
        "length", "time", "velocity", "pressure", ...: the unit must be
        of this kind (a plain number is always accepted).
    name : str
        What the value is, for the error message.
    """
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number or a quantity such as "
                         f"'1mm', got {value!r}")
    if isinstance(value, str):
        match = _PATTERN.fullmatch(value)
        if not match:
            raise ValueError(f"{name}: {value!r} is not a number with an "
                             f"optional unit (e.g. '1mm', '0.3ms')")
        number, unit = float(match.group(1)), match.group(2)
        if unit:
            if unit not in UNITS:
                known = ", ".join(u for u, (k, _) in UNITS.items()
                                  if kind is None or k == kind)
                raise ValueError(f"{name}: unknown unit {unit!r} in "
                                 f"{value!r} (known: {known})")
            unit_kind, factor = UNITS[unit]
            if kind is not None and unit_kind != kind:
                raise ValueError(f"{name} is a {kind}, but {value!r} is a "
                                 f"{unit_kind}")
            number *= factor
        return number
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number or a quantity such as "
                         f"'1mm', got {value!r}") from None


def in_unit(value, unit: str, name: str = "value") -> float:
    """A number in the SI unit ``unit`` of a registry (the library's
    effect parameters and material keys: "Pa", "m^-3", "deg", "" for a
    pure number): a unit of the table above converts within its kind
    (``"12MPa"`` for "Pa"); any other takes a plain number or one followed
    by exactly that unit (``"1e28 m^-3"``, ``"30deg"``)."""
    if unit in UNITS:
        return quantity(value, UNITS[unit][0], name)
    if isinstance(value, str):
        match = _PATTERN.fullmatch(value)
        if match and match.group(2) in ("", unit):
            return float(match.group(1))
        raise ValueError(f"{name}: {value!r} is not a number"
                         + (f" in {unit}" if unit else " (it has no unit)"))
    return quantity(value, None, name)


def quantities(values, kind: str | None = None, name: str = "value",
               n=None) -> tuple:
    """A sequence of quantities (numbers or strings with units) in SI
    units, as a tuple of floats; ``n``: the number of entries (or a tuple
    of the allowed numbers)."""
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise ValueError(f"{name} must be a sequence of numbers or "
                         f"quantities such as '1mm', got {values!r}")
    out = tuple(quantity(v, kind, f"{name}[{i}]")
                for i, v in enumerate(values))
    check_entries(out, values, name, n)
    return out


def check_entries(converted, values, name: str, n) -> None:
    """A ValueError naming ``name`` unless ``converted`` has ``n`` entries
    (an int, a tuple of the allowed numbers, or None: any)."""
    allowed = (n,) if isinstance(n, int) else n
    if allowed is not None and len(converted) not in allowed:
        want = " or ".join(str(k) for k in allowed)
        raise ValueError(f"{name} must have {want} entries, got "
                         f"{len(converted)}: {values!r}")


def lengths(values, name: str = "lengths", n=None) -> tuple:
    """Metres from a sequence such as ``(0, "50mm")`` (see
    :func:`quantities`)."""
    return quantities(values, "length", name, n)


def length(value, name: str = "length") -> float:
    """Metres from ``0.002`` or ``"2mm"``."""
    return quantity(value, "length", name)


def time(value, name: str = "time") -> float:
    """Seconds from ``3e-4`` or ``"0.3ms"``."""
    return quantity(value, "time", name)


def velocity(value, name: str = "velocity") -> float:
    """Metres per second from ``1.5e-3`` or ``"1.5mm/s"``."""
    return quantity(value, "velocity", name)


def to_si(values, kind: str | None, name: str):
    """Strings with units in one value or a sequence converted to SI
    numbers (a sequence comes back as a tuple); anything else is returned
    as it is, for the caller's own checks to judge."""
    if isinstance(values, str):
        return quantity(values, kind, name)
    if isinstance(values, (list, tuple)):
        return tuple(quantity(v, kind, f"{name}[{i}]") if isinstance(v, str)
                     else v for i, v in enumerate(values))
    return values


class ScaleWarning(UserWarning):
    """A scene's size or particle count is implausible (a unit slip?)."""


#: Warn above these (the paper's specimen is 0.14 m of 12,040 particles).
LARGEST_PLAUSIBLE_SIZE = 10.0          # [m]
LARGEST_PLAUSIBLE_COUNT = 20_000_000   # particles


def check_scale(name: str, extent, dx: float, count: int,
                stacklevel: int = 3) -> None:
    """Warn (ScaleWarning) about a body larger than 10 m or of more than
    20 million particles, with its size, spacing and count."""
    size = max(float(e) for e in extent) if len(extent) else 0.0
    problems = []
    if size > LARGEST_PLAUSIBLE_SIZE:
        problems.append(f"it is {size:g} m across (lengths are in metres: "
                        f"'{size:g}mm' is {size * 1e-3:g} m)")
    if count > LARGEST_PLAUSIBLE_COUNT:
        problems.append(f"it has {count:,} particles")
    if problems:
        dims = " x ".join(f"{e:g}" for e in extent)
        warnings.warn(f"body {name!r}: {' and '.join(problems)}; size "
                      f"{dims} m, dx = {dx:g} m, {count:,} particles. "
                      "Pass lengths with units (e.g. '50mm') if that is not "
                      "what you meant", ScaleWarning, stacklevel=stacklevel)


