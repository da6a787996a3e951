"""What ``sphsolid ucs``, ``sphsolid brazilian`` and ``sphsolid tensile``
share: the fracture tests to failure (docs/fracture.md).

    sphsolid ucs       [--dx 2mm] [--seed 1] [--max-strain 0.8%] [--out DIR]
    sphsolid brazilian [--dx 1mm] [--seed 1] [--max-strain 2%] [--out DIR]
    sphsolid tensile   [--dx 2mm] [--seed 1] [--max-strain 1%] [--out DIR]
        [--cohesion 5MPa [--friction-angle 30]] [--artificial-stress 0.3]

``--cohesion`` (a stress, >= 0) switches on the ``drucker_prager`` effect,
the pressure-dependent shear strength, with ``--friction-angle`` degrees in
[0, 90) (default: the library's, 30); ``--artificial-stress EPS`` the
``artificial_stress`` effect with epsilon EPS in (0, 1). Without them the
scene is the test's own (damage and artificial viscosity only).

Each writes DIR/NAME.h5 (+ .xmf: snapshots with the damage and fragment
fields), DIR/NAME_load.csv (time, strain, load), DIR/NAME_damage.png (the
damage field at the peak and at the end) and DIR/summary.json
(peak_load_N, strength_Pa, strain_at_peak, fragments, damage_onset_s, and
``effects``: the scene's effects with their parameters).
"""
from __future__ import annotations

import argparse
import json
import math
import time as wallclock
from pathlib import Path

from .options import (add_allow_large_option, finite, output_folder,
                      positive, seed, threads)

__all__ = ["add_arguments", "add_effect_arguments", "scene_options",
           "run"]

#: Snapshots written to the HDF5 file over a run.
_SNAPSHOTS = 12


def _strain(text: str) -> float:
    """'0.8%' -> 0.008; a plain number is a strain."""
    try:
        value = (float(text[:-1]) / 100 if text.endswith("%")
                 else float(text))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: not a strain (e.g. "
                                         "0.008 or 0.8%)") from None
    if not (math.isfinite(value) and 0 < value < 1):
        raise argparse.ArgumentTypeError(f"{text!r}: must be in (0, 1)")
    return value


#: --cohesion: a stress (``5MPa``, ``5e6``: pascals), finite and >= 0.
_cohesion = finite(0.0, "must be a finite stress >= 0 (e.g. 5MPa)",
                   "pressure")


def _number_in(low: float, high: float, closed_low: bool, what: str,
               example: str):
    """An argparse type: a finite number in [low, high) (``closed_low``)
    or (low, high), refused with the text given and the range."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{text!r}: not a number{what} (e.g. {example})") from None
        inside = (low <= value if closed_low else low < value) and value < high
        if not (math.isfinite(value) and inside):
            bracket = "[" if closed_low else "("
            raise argparse.ArgumentTypeError(
                f"{text!r}: must be in {bracket}{low:g}, {high:g})"
                + (" degrees" if what else ""))
        return value
    return parse


#: --friction-angle: degrees in [0, 90).
_friction_angle = _number_in(0.0, 90.0, True, " of degrees", "30")
#: --artificial-stress: the artificial stress's epsilon, in (0, 1).
_epsilon = _number_in(0.0, 1.0, False, "", "0.3")


def _default_friction_angle() -> float:
    """The drucker_prager effect's default friction angle (the library's
    registry)."""
    from .._lib import effect_registry
    parameters = effect_registry()["drucker_prager"]["parameters"]
    return parameters["friction_angle"]["default"]


def scene_options(args) -> dict:
    """The builder options of the optional effects the arguments ask for:
    ``plasticity`` (drucker_prager) and ``artificial_stress``; {} for
    none. A ValueError names --friction-angle given without --cohesion."""
    options = {}
    if args.cohesion is not None:
        angle = (args.friction_angle if args.friction_angle is not None
                 else _default_friction_angle())
        options["plasticity"] = {"cohesion": args.cohesion,
                                 "friction_angle": angle}
    elif args.friction_angle is not None:
        raise ValueError(f"--friction-angle {args.friction_angle:g} applies "
                         "only with --cohesion (the drucker_prager effect "
                         "needs its cohesion)")
    if args.artificial_stress is not None:
        options["artificial_stress"] = {"epsilon": args.artificial_stress}
    return options


def _optional_effects_text(effects: dict) -> str:
    """'drucker_prager (cohesion 2 MPa, friction angle 30 deg)', ... or
    'none'."""
    words = []
    if "drucker_prager" in effects:
        dp = effects["drucker_prager"]
        words.append(f"drucker_prager (cohesion {dp['cohesion'] / 1e6:g} "
                     f"MPa, friction angle {dp['friction_angle']:g} deg)")
    if "artificial_stress" in effects:
        words.append("artificial_stress (epsilon "
                     f"{effects['artificial_stress']['epsilon']:g})")
    return ", ".join(words) or "none"


def add_effect_arguments(parser) -> None:
    """--cohesion, --friction-angle and --artificial-stress, the optional
    effects :func:`scene_options` turns into builder options (shared with
    ``sphsolid ensemble`` and ``sphsolid plan``)."""
    parser.add_argument("--cohesion", type=_cohesion, default=None,
                        metavar="STRESS",
                        help="switch on the drucker_prager effect (a shear "
                             "strength rising with the pressure, "
                             "docs/fracture.md) with this Mohr-Coulomb "
                             "cohesion, a stress >= 0 (e.g. 5MPa; a plain "
                             "number is pascals; default: off)")
    parser.add_argument("--friction-angle", type=_friction_angle,
                        default=None, metavar="DEG",
                        help="Mohr-Coulomb friction angle of the "
                             "drucker_prager effect, degrees in [0, 90); "
                             "only with --cohesion (default: the library's,"
                             " 30)")
    parser.add_argument("--artificial-stress", type=_epsilon, default=None,
                        metavar="EPS",
                        help="switch on the artificial_stress effect (the "
                             "cure of SPH's tensile instability) with "
                             "epsilon EPS in (0, 1), e.g. 0.3 (default: "
                             "off)")


def add_arguments(parser, name: str) -> None:
    """The options of ``sphsolid ucs`` (name "ucs"), ``brazilian`` or
    ``tensile``."""
    from ..fracture import TESTS
    dx, max_strain, _ = TESTS[name]
    parser.add_argument("--dx", type=positive, default=dx,
                        help=f"particle spacing (default {dx * 1e3:g}mm)")
    parser.add_argument("--seed", type=seed, default=1,
                        help="seed of the flaw draw, in [0, 2^53) (default 1)")
    parser.add_argument("--max-strain", type=_strain, default=max_strain,
                        help="stop at this nominal strain if the load has "
                             f"not dropped (default {max_strain * 100:.1f}%%)")
    parser.add_argument("--drop", type=_strain, default=0.5,
                        help="stop when the load falls below this share of "
                             "its peak (default 0.5)")
    parser.add_argument("--threads", type=threads, default=None,
                        help="OpenMP threads (default: OpenMP's)")
    parser.add_argument("--out", type=Path, default=Path("."),
                        help="output directory (default: current)")
    add_effect_arguments(parser)
    add_allow_large_option(parser)


def run(args, name: str) -> int:
    from .. import fracture
    from ..calculators import CLibrary
    from ..io.trajectory import Trajectory

    options = scene_options(args)
    output_folder(args.out)
    scene = fracture.test_scene(name, args.dx, seed=args.seed, **options)
    if args.threads is not None:
        scene.calc = CLibrary(threads=args.threads)
    info = scene.failure
    print(f"{name}: dx = {args.dx * 1e3:g} mm, "
          + ", ".join(f"{k} {v}" for k, v in scene.body_counts().items())
          + f" particles, platen speed {info['speed'] * 1e3:g} mm/s, "
          f"seed {args.seed}; optional effects: "
          + _optional_effects_text(scene.effects))
    h5 = args.out / f"{name}.h5"
    specimen = scene.body_slice("specimen")
    state = {"peak": None, "samples": 0}
    samples = fracture.TESTS[name][2]   # load samples per unit strain
    every = max(1, int(args.max_strain * samples / _SNAPSHOTS))

    with Trajectory(h5, "w", scene) as traj:
        def on_sample(scene, t, load, peak):
            state["samples"] += 1
            if load >= peak:
                state["peak"] = (t, scene.positions[specimen].copy(),
                                 scene.damage[specimen])
            if state["samples"] % every == 0:
                traj.write()
        start = wallclock.perf_counter()
        run = fracture.load_to_break(
            scene, max_strain=args.max_strain, drop=args.drop,
            samples_per_strain=samples,
            on_sample=on_sample)
        traj.write()
        wall = wallclock.perf_counter() - start
    summary = run.summary()
    summary.update(scene=name, dx_m=args.dx, seed=args.seed,
                   steps=int(scene.step), wall_s=wall,
                   effects=scene.effects)
    (args.out / "summary.json").write_text(json.dumps(summary, indent=2))
    csv = args.out / f"{name}_load.csv"
    with open(csv, "w") as f:
        f.write("time_s,strain,load_N_per_m\n")
        for t, e, load in zip(run.time, run.strain, run.load):
            f.write(f"{float(t)!r},{float(e)!r},{float(load)!r}\n")
    png = args.out / f"{name}_damage.png"
    _damage_figure(png, state["peak"], (scene.time,
                   scene.positions[specimen], scene.damage[specimen]),
                   f"{name}, dx = {args.dx * 1e3:g} mm, seed {args.seed}")
    label = {"ucs": "UCS", "brazilian": "2P/(pi D t)",
             "tensile": "tensile strength"}[name]
    onset = run.damage_onset_s
    print(f"{scene.step} steps in {wall:.1f} s; peak load "
          f"{run.peak_load_N:.4g} N/m at strain {run.strain_at_peak:.4g}; "
          f"{label} = {run.strength_Pa / 1e6:.4g} MPa; damage onset "
          + (f"{onset * 1e3:.4g} ms" if onset is not None else "none")
          + f"; {run.fragments} fragment(s); load at the end "
          f"{run.post_peak_ratio:.2f} x peak")
    if run.load_lost_before_damage:
        print(f"warning: the load fell below {args.drop:g} x its peak "
              "before any particle was damaged: not fracture (in tension "
              "SPH's tensile instability; switch on artificial_stress), so "
              f"the {label} above is no strength of the rock "
              "(summary.json: load_lost_before_damage)")
    for path in (h5, Trajectory(h5).xdmf_path, csv, png,
                 args.out / "summary.json"):
        print(f"wrote {path}")
    return 0


def _damage_figure(path, at_peak, at_end, title) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    panels = [p for p in (at_peak, at_end) if p is not None]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 5),
                             squeeze=False, sharey=True)
    for ax, (t, x, D), what in zip(axes[0], panels, ("peak", "end")):
        dots = ax.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, c=D, s=4,
                          cmap="inferno_r", vmin=0, vmax=1)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_title(f"at the {what}: t = {t * 1e3:.3g} ms")
    axes[0][0].set_ylabel("y [mm]")
    fig.colorbar(dots, ax=list(axes[0]), label="damage D")
    fig.suptitle(title)
    fig.savefig(path, dpi=110)
    plt.close(fig)
