"""The Brazilian disc against its derived truths (docs/fracture.md).

    python validation/brazilian.py [--quick] [--seeds N] [--out DIR]
        [--strength-only] [--artificial-stress]

prints three checks and writes them to ``DIR/brazilian.json``:

1. **Hondros.**  The horizontal (tensile) and vertical stress at the
   disc's centre before damage, over 2P/(pi D t) with P the platens' mean
   load, against the elastic solution for a load spread over the actual
   contact (the disc's top lattice row, half-width b, sin alpha = b/R) at
   dx = 2, 1 and 0.5 mm (2 and 1 mm with ``--quick``).
2. **Where damage starts.**  From the elastic field: the largest principal
   strain (the library's activation rule) and the largest principal stress
   over E (Benz & Asphaug's), their maxima against the centre's, and the
   probability that the first flaw of the disc activates in its central
   third (|y| < D/6); then, from damage runs, where the first damaged
   particles lie.
3. **Strength.**  The disc's 2P/(pi D t) against the tensile bar's
   strength at the same rate of the activating strain, for seeds 1..N,
   with the ratio the activation rule and the Weibull volumes predict.

The flaws of a particle follow a Poisson process in u = k V eps^m, so under
loading that scales the whole field, eps_i = c_i lambda(t), the first flaw
of the body activates in particle i with probability
V_i c_i^m / sum_j V_j c_j^m: check 2's probability is that sum over the
central third.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time as clock
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "python"))

from sphsolid import fracture  # noqa: E402
from sphsolid.dynamics import ImprovedEuler  # noqa: E402

#: The fracture material's elastic constants (fracture.fracture_material).
K, MU = 12.2e9, 2.67e9
YOUNG = 9.0 * K * MU / (3.0 * K + MU)
POISSON = (3.0 * K - 2.0 * MU) / (2.0 * (3.0 * K + MU))
DIAMETER = 0.05


def _quad(f, lo, hi, n=20001):
    x = np.linspace(lo, hi, n)
    return float(np.trapezoid(f(x), x))


def centre_factors(alpha: float) -> dict:
    """The centre stress of a disc over 2P/(pi D t), loaded at both ends
    over arcs of half-angle ``alpha`` [rad] with total load P.

    A pair of opposite forces f at the boundary points at angle theta from
    the loaded diameter (and their mirror images) puts at the centre

        sigma_xx = f_n (1 - 4 sin^2 theta) / (pi R t),
        sigma_yy = f_n (1 - 4 cos^2 theta) / (pi R t),

    f_n the forces' normal (radial) component: two Flamant fields plus the
    uniform tension sum f_n / (2 pi R t) that frees the circle of traction
    (Michell 1900); a tangential component adds nothing at the centre.
    Integrated over the arc:

    - ``radial``: uniform radial pressure p (Hondros 1959),
      sigma_xx = (2p/pi)(sin 2a - a), sigma_yy = -(2p/pi)(sin 2a + a),
      with P = 2 p R t sin a: sigma_xx / (2P/(pi D t)) = (sin 2a - a)/sin a;
    - ``uniform``: a vertical load of uniform density over the contact's
      width (x = R sin theta);
    - ``punch``: a vertical load of the rigid flat punch's density,
      proportional to 1/sqrt(b^2 - x^2).

    Each entry is (sigma_xx, sigma_yy) over 2P/(pi D t); a -> 0 gives the
    point-load values (1, -3).
    """
    a = float(alpha)
    s = math.sin(a)
    radial = ((math.sin(2 * a) - a) / s, -(math.sin(2 * a) + a) / s)
    # vertical load dF = q R cos(theta) dtheta, normal part cos(theta) dF
    uniform = tuple(_quad(lambda t, g=g: np.cos(t) ** 2 * g(t), -a, a)
                    / (2 * s) for g in (lambda t: 1 - 4 * np.sin(t) ** 2,
                                        lambda t: 1 - 4 * np.cos(t) ** 2))
    # punch: x = b sin(phi), the density uniform in phi
    theta = lambda phi: np.arcsin(s * np.sin(phi))  # noqa: E731
    punch = tuple(_quad(lambda p, g=g: np.cos(theta(p)) * g(theta(p)),
                        -math.pi / 2, math.pi / 2) / math.pi
                  for g in (lambda t: 1 - 4 * np.sin(t) ** 2,
                            lambda t: 1 - 4 * np.cos(t) ** 2))
    return {"radial": radial, "uniform": uniform, "punch": punch}


def contact_alpha(scene, radius: float, dx: float) -> float:
    """Half the angle [rad] the disc's contact subtends: its top lattice
    row, whose cells (half a step beyond the outer centres) the platen
    touches, of half-width b; sin alpha = b / R."""
    p = scene.positions[scene.body_slice("specimen")]
    top = p[p[:, 1] > p[:, 1].max() - 0.25 * dx]
    step = 2 * radius / round(2 * radius / dx)
    return math.asin(min(1.0, (np.abs(top[:, 0]).max() + step / 2) / radius))


def elastic_disc(dx: float, flat_angle: float = 0.0, until: float = 2e-3):
    """The disc (fracture.brazilian_disc) loaded for ``until`` [s] with
    flaws too strong to activate (k = 1 m^-3: (k V)^(-1/m) > 1), so it
    stays elastic: the scene and the half-angle of its contact [rad]
    (:func:`contact_alpha` of the lattice as laid)."""
    scene = fracture.brazilian_disc(
        dx, material=fracture.fracture_material(weibull_k=1.0),
        flat_angle=flat_angle)
    alpha = contact_alpha(scene, DIAMETER / 2, dx)
    dyn = ImprovedEuler(scene, progress=False)
    dyn.run(steps=int(round(until / dyn.dt)))
    assert float(scene.damage.max()) == 0.0
    return scene, alpha


def platen_load(scene) -> float:
    """P [N/m]: the mean of the piston's and the plate's loads."""
    return 0.5 * float(scene.reaction("piston")[1]
                       - scene.reaction("plate")[1])


def centre_stress(scene, radius: float) -> tuple:
    """sigma_xx and sigma_yy at the centre [Pa]: a quadratic least-squares
    fit over the particles within R/4 of it."""
    sl = scene.body_slice("specimen")
    p, s = scene.positions[sl], scene.stress[sl]
    near = np.hypot(p[:, 0], p[:, 1]) < radius / 4
    x, y = p[near, 0], p[near, 1]
    basis = np.stack([np.ones_like(x), x, y, x * x, y * y, x * y], axis=1)
    return tuple(float(np.linalg.lstsq(basis, s[near, c], rcond=None)[0][0])
                 for c in (0, 1))


def activating_strains(scene) -> tuple:
    """Per specimen particle: the largest principal strain of Hooke's law
    inverted, eps = S/(2 mu) - P/(3K) I (the library's activation rule),
    and the largest principal stress over E (Benz & Asphaug's rule);
    2D plane strain, S_zz included."""
    sl = scene.body_slice("specimen")
    s, pressure = scene.deviatoric_stress[sl], scene.pressure[sl]
    n = len(pressure)
    dev = np.zeros((n, 3, 3))
    for i in range(3):
        dev[:, i, i] = s[:, i]
    dev[:, 0, 1] = dev[:, 1, 0] = s[:, 3]
    eye = np.eye(3)[None]
    strain = dev / (2 * MU) - (pressure / (3 * K))[:, None, None] * eye
    stress = dev - pressure[:, None, None] * eye
    return (np.linalg.eigvalsh(strain)[:, -1],
            np.linalg.eigvalsh(stress)[:, -1] / YOUNG)


def first_flaw_weights(values, positions, volumes, m: float,
                       radius: float) -> dict:
    """Where the first flaw activates under loading that scales the field
    ``values``: the probability of the central third (|y| < R/3), the
    largest value over the centre's and where it lies."""
    v = np.clip(values, 0.0, None)
    w = volumes * v ** m
    r = np.hypot(positions[:, 0], positions[:, 1])
    centre = float(values[r <= r.min() + 1e-12].mean())
    k = int(np.argmax(values))
    return {"central_third": float(w[np.abs(positions[:, 1]) < radius / 3]
                                   .sum() / w.sum()),
            "max_over_centre": float(values[k] / centre),
            "max_at_mm": [float(positions[k, 0] * 1e3),
                          float(positions[k, 1] * 1e3)],
            "effective_volume": float(w.sum() / centre ** m)}


def hondros(dxs) -> list:
    rows = []
    for dx in dxs:
        t0 = clock.process_time()
        scene, alpha = elastic_disc(dx)
        ref = 2 * platen_load(scene) / (math.pi * DIAMETER)
        sxx, syy = centre_stress(scene, DIAMETER / 2)
        rows.append({"dx": dx, "two_alpha_deg": math.degrees(2 * alpha),
                     "sxx": sxx / ref, "syy": syy / ref,
                     "theory": centre_factors(alpha),
                     "cpu_s": clock.process_time() - t0})
    return rows


def onset_weights(dx: float, flats) -> list:
    rows = []
    m = fracture.fracture_material().weibull_m
    for flat in flats:
        scene, alpha = elastic_disc(dx, flat)
        sl = scene.body_slice("specimen")
        p = scene.positions[sl]
        vol = scene.masses[sl] / 2300.0
        strain, stress = activating_strains(scene)
        rows.append({"dx": dx, "flat_angle": flat,
                     "two_alpha_deg": math.degrees(2 * alpha),
                     "strain_rule": first_flaw_weights(strain, p, vol, m,
                                                       DIAMETER / 2),
                     "stress_rule": first_flaw_weights(stress, p, vol, m,
                                                       DIAMETER / 2)})
    return rows


def centre_strain_rate(dx: float, until: float = 2e-3) -> tuple:
    """The disc centre's largest principal strain rate [1/s] (the
    activating strain, growing linearly under the constant platen speed)
    and its strain over E / (2P/(pi D t))."""
    scene, _ = elastic_disc(dx, until=until)
    strain, _ = activating_strains(scene)
    p = scene.positions[scene.body_slice("specimen")]
    r = np.hypot(p[:, 0], p[:, 1])
    centre = float(strain[r <= r.min() + 1e-12].mean())
    ref = 2 * platen_load(scene) / (math.pi * DIAMETER)
    return centre / scene.time, centre * YOUNG / ref


def strengths(dx: float, seeds, rate: float,
              artificial_stress: bool = False) -> dict:
    """Disc and bar to failure for each seed (with the
    ``artificial_stress`` effect at its defaults if asked): strengths
    [Pa], where the disc's first damaged particles lie."""
    out = {"disc": [], "bar": [], "disc_onset": []}
    for seed in seeds:
        scene = fracture.brazilian_disc(dx, seed=seed)
        if artificial_stress:
            scene.effect("artificial_stress")
        sl = scene.body_slice("specimen")
        first = {}

        def look(sc, t, load, peak, first=first, sl=sl):
            d = sc.damage[sl]
            if not first and d.max() > 0:
                p = sc.positions[sl][d > 0]
                first["y_over_R"] = float(np.abs(p[:, 1]).max()
                                          / (DIAMETER / 2))
                first["count"] = int((d > 0).sum())
        run = fracture.load_to_break(scene, max_strain=0.02,
                                     samples_per_strain=1e4,
                                     on_sample=look)
        out["disc"].append(run.strength_Pa)
        out["disc_onset"].append(first)
        bar = fracture.tensile_bar(dx, strain_rate=rate, seed=seed)
        if artificial_stress:
            bar.effect("artificial_stress")
        out["bar"].append(fracture.load_to_break(
            bar, max_strain=0.01).strength_Pa)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="dx 2 and 1 mm for Hondros, strengths at 2 mm")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--artificial-stress", action="store_true",
                    help="strengths with the artificial_stress effect on")
    ap.add_argument("--strength-only", action="store_true",
                    help="check 3 only")
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)
    result = {}
    dxs = (2e-3, 1e-3) if args.quick else (2e-3, 1e-3, 5e-4)
    if not args.strength_only:
        checks_1_2(dxs, result)
    check_3(args, result)
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "brazilian.json").write_text(json.dumps(result, indent=1))
    return 0


def checks_1_2(dxs, result: dict) -> None:
    print("1. Hondros: centre stress / (2P/(pi D t)) before damage")
    result["hondros"] = hondros(dxs)
    for row in result["hondros"]:
        th = row["theory"]
        print(f"  dx {row['dx'] * 1e3:.1f} mm, 2 alpha {row['two_alpha_deg']:.1f} deg:"
              f" sxx {row['sxx']:.4f} (radial {th['radial'][0]:.4f}, uniform"
              f" {th['uniform'][0]:.4f}, punch {th['punch'][0]:.4f});"
              f" syy {row['syy']:.4f} (radial {th['radial'][1]:.4f}, uniform"
              f" {th['uniform'][1]:.4f}, punch {th['punch'][1]:.4f});"
              f" {row['cpu_s']:.0f} s CPU")
    print("2. where the first flaw activates (elastic field, m = 9)")
    result["onset"] = []
    for dx in dxs:
        result["onset"] += onset_weights(dx, (0.0, 40.0, 60.0))
    for row in result["onset"]:
        a, b = row["strain_rule"], row["stress_rule"]
        print(f"  dx {row['dx'] * 1e3:.1f} mm, flat {row['flat_angle']:.0f} deg"
              f" (contact 2 alpha {row['two_alpha_deg']:.1f}): principal"
              f" strain: max/centre {a['max_over_centre']:.2f} at"
              f" {a['max_at_mm']} mm, P(central third)"
              f" {a['central_third']:.3f}; principal stress / E: max/centre"
              f" {b['max_over_centre']:.2f} at {b['max_at_mm']} mm,"
              f" P(central third) {b['central_third']:.3f}")


def check_3(args, result: dict) -> None:
    dx = 2e-3 if args.quick else 1e-3
    rate, c_disc = centre_strain_rate(dx)
    c_bar = 1.0 - POISSON ** 2
    m = fracture.fracture_material().weibull_m
    weights = onset_weights(dx, (0.0,))[0]["strain_rule"]
    v_bar = 0.020 * 0.080 * 1.0
    predicted = c_bar / c_disc * (v_bar / weights["effective_volume"]) ** (1 / m)
    print(f"3. strength at dx {dx * 1e3:.0f} mm: the disc centre's activating"
          f" strain rate {rate:.3f} /s, its strain E eps / (2P/(pi D t)) ="
          f" {c_disc:.3f} (the bar's: 1 - nu^2 = {c_bar:.3f}); effective"
          f" volumes {weights['effective_volume']:.3e} (disc) and"
          f" {v_bar:.3e} (bar) m^3; first-flaw ratio disc/bar predicted"
          f" {predicted:.3f}")
    seeds = range(1, args.seeds + 1)
    s = strengths(dx, seeds, rate, args.artificial_stress)
    ratio = np.array(s["disc"]) / np.array(s["bar"])
    for seed, a, b, o in zip(seeds, s["disc"], s["bar"], s["disc_onset"]):
        print(f"  seed {seed}: disc 2P/(pi D t) {a / 1e6:.2f} MPa, bar"
              f" {b / 1e6:.2f} MPa, ratio {a / b:.3f}; disc's first damage:"
              f" {o.get('count')} particles, |y|/R <= {o.get('y_over_R', float('nan')):.2f}")
    print(f"  mean ratio {ratio.mean():.3f} (predicted {predicted:.3f})")
    result["strength"] = {"dx": dx, "rate": rate, "c_disc": c_disc,
                          "c_bar": c_bar, "predicted_ratio": predicted,
                          "artificial_stress": args.artificial_stress,
                          **s, "ratio": ratio.tolist()}


if __name__ == "__main__":
    sys.exit(main())
