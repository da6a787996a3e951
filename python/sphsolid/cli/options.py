"""Argument types and option groups shared by the ``sphsolid`` commands.

Lengths and times take an optional unit (``--dx 2mm``, ``--until 0.3ms``;
plain numbers are metres and seconds), converted by :mod:`sphsolid.units`.
A type names the text it refuses; the library judges the values it owns.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

__all__ = ["quantity", "positive", "positive_length", "positive_time",
           "finite", "whole", "fraction", "length_list", "time_list",
           "threads", "jobs", "seed", "usable_cores", "clip",
           "add_scene_options", "add_plan_options"]

#: Characters of a refused value echoed in a message (the rest elided).
CLIP = 60


def clip(text: str, keep: int = CLIP) -> str:
    """``text`` as repr() shows it, cut to ``keep`` characters with the
    length said (a 5000-character value is not echoed in full)."""
    shown = repr(text)
    if len(text) <= keep:
        return shown
    return f"{text[:keep]!r}... ({len(text)} characters)"


def usable_cores() -> int:
    """The cores this process may run on (its CPU affinity, else
    os.cpu_count())."""
    import os
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def quantity(text: str, kind: str | None = None) -> float:
    """'2mm' -> 0.002, '0.3ms' -> 3e-4, '1e-3' -> 0.001 (sphsolid.units);
    ``kind`` ("length", "time"): a unit of another kind is refused."""
    from ..units import quantity as to_si
    try:
        return to_si(text, kind, "value")
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def _positive(kind: str | None):
    def parse(text: str) -> float:
        value = quantity(text, kind)
        if not (math.isfinite(value) and value > 0):
            raise argparse.ArgumentTypeError(
                f"{text!r}: must be finite and > 0")
        return value
    parse.__name__ = kind or "quantity"      # argparse's name of the type
    return parse


#: A quantity that must be finite and > 0: of any kind, a length (a
#: spacing) or a time.
positive = _positive(None)
positive_length = _positive("length")
positive_time = _positive("time")


def finite(low: float, what: str, kind: str | None = None):
    """A number, finite and >= low (``what`` says the rule); with
    ``kind`` ("velocity", "time", ...) a unit of that kind too."""
    def parse(text: str) -> float:
        if kind is not None:
            value = quantity(text, kind)
        else:
            try:
                value = float(text)
            except ValueError:
                raise argparse.ArgumentTypeError(
                    f"{clip(text)}: not a number") from None
        if not (math.isfinite(value) and value >= low):
            raise argparse.ArgumentTypeError(f"{text!r}: {what}")
        return value
    return parse


def whole(low: int, high: int | None = None, why: str = ""):
    """A whole number >= low (and <= high, refused with ``why``)."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{clip(text)}: not a whole number") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"{text!r}: must be >= {low}")
        if high is not None and value > high:
            raise argparse.ArgumentTypeError(
                f"{text!r}: must be <= {high}{why}")
        return value
    return parse


def _per_core(what: str):
    """A whole number in [1, the usable cores]: more threads or processes
    than cores only slow a run down (and 100000 threads exhaust the
    OpenMP runtime), so more is refused, naming the cores."""
    def parse(text: str) -> int:
        cores = usable_cores()
        return whole(1, cores, f" ({what}: this process may use {cores} "
                     f"core{'s' if cores != 1 else ''}; more only slows the "
                     "run down)")(text)
    parse.__name__ = what
    return parse


#: --threads: OpenMP threads, 1 .. the usable cores.
threads = _per_core("threads")
#: --jobs: processes at once, 1 .. the usable cores.
jobs = _per_core("jobs")
#: --seed: a seed of a flaw draw, a whole number in [0, 2^53) (the
#: library holds it in a double).
seed = whole(0, 2**53 - 1, " (seeds are below 2^53)")


def fraction(text: str) -> float:
    """'3%' -> 0.03, '0.03' -> 0.03."""
    value = text.strip()
    try:
        if value.endswith("%"):
            return float(value[:-1]) / 100.0
        return float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r}: expected a fraction (0.03) or a percentage "
            "(3%)") from None


def length_list(text: str) -> list[float]:
    """'1mm,2mm' -> [0.001, 0.002], each finite and > 0."""
    return [positive_length(part) for part in text.split(",")
            if part.strip()]


def time_list(text: str) -> list[float]:
    """'0.1ms,0.2ms' -> [1e-4, 2e-4], each finite and > 0."""
    return [positive_time(part) for part in text.split(",") if part.strip()]


def inset(text: str):
    """'static' or a number of lattice steps (the library judges its
    range)."""
    if text.strip() == "static":
        return "static"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r}: a number of lattice steps or 'static'") from None


def _step_rule() -> str:
    """'0.5 h/c0 for improved_euler, 1 h/c0 for leapfrog' from the
    library's integrator registry ('' when the library is not found)."""
    try:
        from .._lib import integrator_registry
        registry = integrator_registry()
    except OSError:
        return ""
    return ", ".join(f"{info['default_factor']:g} h/c0 for {name}"
                     for name, info in registry.items())


def _preset_help(default: str) -> str:
    from ..presets import PRESETS
    listed = "; ".join(
        f"{p.name}: {p.integrator}"
        + (f" at {p.step:g} of its default step" if p.step != 1 else "")
        + f", {p.kernel} at h = {p.smoothing_ratio:g} dx"
        for p in PRESETS.values())
    return (f"named setting (kernel, h/dx, integrator, viscosity, platen "
            f"inset, step): {listed} (docs/validation.md); default "
            f"{default}; the other options override it")


def add_integrator_options(parser, preset_default: str = "paper (Das & "
                           "Cleary's scheme)") -> None:
    """--preset, --integrator and --dt (``sphsolid piston``, ``gravity``,
    ``run``)."""
    from .._lib import integrator_names
    from ..presets import PRESETS
    rule = _step_rule()
    parser.add_argument("--dt", type=positive_time, default=None,
                        help="time step (default: the preset's fraction of "
                             "the integrator's default step"
                             + (f", {rule}" if rule else "") + ")")
    parser.add_argument("--preset", choices=tuple(PRESETS), default=None,
                        help=_preset_help(preset_default))
    parser.add_argument("--integrator", default=None,
                        choices=integrator_names(),
                        help="time integrator of the library (default: the "
                             "preset's)")


def add_checkpoint_options(parser) -> None:
    """--checkpoint-every and --resume (``sphsolid piston``, ``gravity``,
    ``run``)."""
    parser.add_argument("--checkpoint-every", type=positive_time,
                        default=None, metavar="TIME",
                        help="write NAME_checkpoint.h5 beside the output "
                        "every TIME of simulated time (the last one kept)")
    parser.add_argument("--resume", type=Path, default=None, metavar="FILE",
                        help="continue from a checkpoint of the same scene "
                        "and integrator (C backend); the outputs hold the "
                        "run from there")


def output_folder(path: Path, option: str = "--out") -> Path:
    """Make the output folder (and its parents), or refuse naming the
    option: a file in its place, a folder that cannot be made."""
    from ..io.scenefile import make_folder
    return make_folder(path, f"{option} {path}")


def add_allow_large_option(parser) -> None:
    """--allow-large of the commands that build a scene."""
    parser.add_argument("--allow-large", action="store_true",
                        help="build and run a scene that needs more than "
                        "half of the available memory (up to all of it; "
                        "refused otherwise, naming the particle count and "
                        "bytes)")


def add_scene_options(parser, dx: float | None, until: float,
                      frames: int) -> None:
    """The options of the project scenes (``sphsolid piston``, ``gravity``);
    ``dx`` None: the command says its default in its own help."""
    if dx is not None:
        parser.add_argument("--dx", type=positive_length, default=dx,
                            help=f"particle spacing (default {dx * 1e3:g}mm)")
    parser.add_argument("--until", type=positive_time, default=None,
                        help=f"end time (default {until * 1e3:g}ms, or the "
                             "plan's)")
    parser.add_argument("--out", type=Path, default=Path("."),
                        help="output directory (default: current)")
    parser.add_argument("--backend", choices=("c", "lammps"), default="c",
                        help="c: libsphsolid (default); lammps: the plugin")
    parser.add_argument("--threads", type=threads, default=None,
                        help="OpenMP threads, at most the cores (default: "
                        "OpenMP's)")
    from .._lib import kernel_names
    add_integrator_options(parser)
    add_checkpoint_options(parser)
    add_allow_large_option(parser)
    parser.add_argument("--kernel", default=None, choices=kernel_names(),
                        help="smoothing kernel (default: the preset's)")
    parser.add_argument("--h-over-dx", type=finite(-math.inf, "must be "
                        "finite"), default=None, dest="smoothing_ratio",
                        metavar="RATIO",
                        help="smoothing length over spacing (default: the "
                             "preset's; paper: 1.2)")
    parser.add_argument("--inset", type=inset, default=None,
                        help="plate and piston laid this many lattice steps"
                             " closer to the specimen, or 'static' (the "
                             "inset that makes the quasi-static stiffness "
                             "exact); default: the preset's (paper: 0)")
    parser.add_argument("--times", type=time_list, default=None,
                        help="comma-separated times of the von Mises maps "
                             f"(default {frames} evenly to --until)")
    parser.add_argument("--probe-interval", type=whole(1), default=None,
                        help="steps between probe samples (default: every "
                        "step within 0.25 us, a quarter of the accuracy "
                        "metric's smoothing)")
    parser.add_argument("--viscosity", type=finite(0.0, "must be finite "
                        "and >= 0 (0 switches it off)"), default=None,
                        metavar="ALPHA",
                        help="Monaghan artificial viscosity alpha (beta=0);"
                             " 0 switches it off (default: the preset's; "
                             "paper: 1)")
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction,
                        default=None, help="progress bar (default: on a "
                        "terminal for long runs)")
    add_plan_options(parser)


def add_plan_options(parser) -> None:
    """--plan and --error-estimate of the project scenes."""
    parser.add_argument("--plan", type=Path, default=None,
                        help="run the settings of a plan.json from "
                        "'sphsolid plan' (spacing, h/dx, kernel, "
                        "integrator, effects)")
    parser.add_argument("--error-estimate", action="store_true",
                        help="error band on every probe series from shadow "
                        "runs at 2dx and 4dx (about +14 %% in 2D; with "
                        "--plan, the order of the plan's calibration of its "
                        "setting when it is well determined); written "
                        "as *_error_Pa columns and /observables/"
                        "probes_error, drawn in the probe figure")
