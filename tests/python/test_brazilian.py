"""The Brazilian disc against derived truths (docs/fracture.md; the study
with more resolutions is validation/brazilian.py)."""
import math

import numpy as np
import pytest

from sphsolid import fracture
from sphsolid.build import disc
from validation import brazilian

R = 0.025


def test_centre_factors_reduce_to_the_point_load_and_to_hondros():
    # a -> 0: the diametral point loads, sigma_xx = 2P/(pi D t), sigma_yy = -3x
    for case in brazilian.centre_factors(1e-4).values():
        assert case == pytest.approx((1.0, -3.0), abs=1e-6)
    # the radial case integrated as the others (a uniform density in theta)
    # is Hondros' closed form
    a = math.radians(15.0)
    t = np.linspace(-a, a, 200001)
    sxx = np.trapezoid(1 - 4 * np.sin(t) ** 2, t) / (2 * math.sin(a))
    syy = np.trapezoid(1 - 4 * np.cos(t) ** 2, t) / (2 * math.sin(a))
    assert brazilian.centre_factors(a)["radial"] == pytest.approx((sxx, syy),
                                                                  rel=1e-9)


def test_centre_stress_before_damage_is_hondros_for_the_contact_width():
    """dx = 1 mm: the disc touches each platen along its top lattice row,
    10 particles (b = 5 mm, 2 alpha = 23.1 deg).  The centre stress lies in
    the band that the contact's load distribution spans (uniform radial
    pressure, Hondros; a uniform vertical load; the rigid punch's), 4 % and
    2.5 % wide at this angle, to within 1 % of each (the fit's spread over
    its radius: 0.5 % at 1 mm, 3 % at 2 mm; sigma_yy lies 1.5 %, 0.3 % and
    0.3 % beyond the band at 2, 1 and 0.5 mm: validation/brazilian.py)."""
    scene, alpha = brazilian.elastic_disc(1e-3, until=1.5e-3)
    assert math.degrees(2 * alpha) == pytest.approx(
        2 * math.degrees(math.asin(5.0 / 25.0)))
    ref = 2 * brazilian.platen_load(scene) / (math.pi * 2 * R)
    # quasi-static: the plate carries what the piston does
    assert abs(scene.reaction("piston")[1] + scene.reaction("plate")[1]) \
        < 0.02 * brazilian.platen_load(scene)
    centre = np.array(brazilian.centre_stress(scene, R)) / ref
    theory = np.array(list(brazilian.centre_factors(alpha).values()))
    lo, hi = theory.min(axis=0), theory.max(axis=0)
    assert (hi - lo < np.array([0.05, 0.08])).all()
    tol = 0.01 * np.abs(theory).max(axis=0)
    assert (lo - tol < centre).all() and (centre < hi + tol).all(), \
        (centre, lo, hi)


@pytest.mark.parametrize("dx", [4e-3, 2e-3, 1e-3, 0.5e-3])
def test_the_round_discs_end_row_is_a_chord_dx_over_2_deep(dx):
    # the rows within dx/2 of the lowest lie on a chord dx/2 above the
    # circle's lowest point, 2 sqrt(R dx - dx^2/4) long: the contact with
    # the platen narrows like dx^(1/2) (docs/ensembles.md), up to the
    # lattice's spacing either side
    points = fracture.brazilian_disc(dx=dx).bodies[0].points
    low = points[:, 1].min()
    row = points[np.abs(points[:, 1] - low) < 0.5 * dx, 0]
    width = row.max() - row.min() + dx
    chord = 2 * math.sqrt(R * dx - dx * dx / 4)
    assert abs(width - chord) <= 2 * dx, (width, chord)


def test_flat_ends_cut_the_disc_and_bad_angles_are_named():
    round_disc = fracture.brazilian_disc(2e-3, flat_angle=0.0)
    flat = fracture.brazilian_disc(2e-3, flat_angle=60.0)
    a = round_disc.positions[round_disc.body_slice("specimen")]
    b = flat.positions[flat.body_slice("specimen")]
    cut = R * math.cos(math.radians(30.0))
    np.testing.assert_array_equal(b, a[np.abs(a[:, 1]) < cut])
    assert len(b) < len(a)
    # the platens touch the flats: one lattice step above the top row
    piston = flat.positions[flat.body_slice("piston")]
    assert piston[:, 1].min() == pytest.approx(b[:, 1].max() + 2e-3)
    # the default is the round disc of before: every lattice point inside
    # the circle (at 0.5 mm the top rows lie at 24.75 mm, above the cut of
    # any flat of 2 alpha > 16 degrees)
    default = fracture.brazilian_disc(5e-4)
    whole = disc((0.0, 0.0), R, 5e-4, fracture.fracture_material()).points
    np.testing.assert_array_equal(
        default.positions[default.body_slice("specimen")], whole)
    for bad in (-5.0, 90.0, "20", True, float("nan")):
        with pytest.raises(ValueError, match="flat_angle"):
            fracture.brazilian_disc(2e-3, flat_angle=bad)


def test_damage_starts_where_the_elastic_field_first_reaches_a_flaw():
    """Before damage the field scales with the platen travel, so each
    particle's activating strain is c_i t; its weakest flaw activates at
    t_i = eps_flaw,i / c_i, and the first damaged particles are those of
    least t_i.  With the library's rule (the largest principal strain) and
    bonded platens these lie at the contact's edges, not in the central
    third (docs/fracture.md)."""
    dx = 2e-3
    elastic, _ = brazilian.elastic_disc(dx, until=2e-3)
    strain, _ = brazilian.activating_strains(elastic)
    rate = strain / elastic.time
    scene = fracture.brazilian_disc(dx, seed=1)
    sl = scene.body_slice("specimen")
    flaw = scene.flaw_strain[sl]
    t_first = np.where(rate > 0, flaw / np.where(rate > 0, rate, 1.0), np.inf)
    first = {}

    def look(sc, t, load, peak):
        d = sc.damage[sl]
        if not first and d.max() > 0:
            first["damaged"] = np.flatnonzero(d > 0)
            first["time"] = t

    samples = 1e4                       # per unit strain: every 0.25 ms
    fracture.load_to_break(scene, max_strain=0.006, drop=0.9,
                           samples_per_strain=samples, on_sample=look)
    damaged = first["damaged"]
    # damage is first seen at the first sample past the predicted onset
    # (the field scales with the travel to within 2 %), and the first
    # damaged particles include the one predicted first
    interval = 0.05 / (fracture.DISC_SPEED * samples)
    assert 0.98 * t_first.min() <= first["time"] < t_first.min() + interval
    k = damaged[np.argmin(t_first[damaged])]
    assert k == np.argmin(t_first)
