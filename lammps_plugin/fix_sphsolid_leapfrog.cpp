/*
 * fix_sphsolid_leapfrog.cpp - the library's leapfrog for pair sphsolid (see
 * the header).  The stages are sph_leapfrog_{begin,drift,end}_strided() on
 * LAMMPS's own x and v; this file hands them dv/dt (with the rigid bodies'
 * accelerations, from the base's pack(), fix_sphsolid_integrate.cpp), runs the continuity pass
 * of the half step in step with LAMMPS's communication, has pair sphsolid
 * compute only the momentum pass, and keeps the half step's density and
 * stress rates with the atoms (fix SPHSOLID/STATE) for the next predictor.
 */
#include "fix_sphsolid_leapfrog.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "atom.h"
#include "error.h"
#include "sphsolid_error.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;
using namespace FixConst;

FixSPHSolidLeapfrog::FixSPHSolidLeapfrog(LAMMPS *lmp, int narg, char **arg) :
    FixSPHSolidIntegrate(lmp, narg, arg, "leapfrog")
{
}

int FixSPHSolidLeapfrog::setmask()
{
  return INITIAL_INTEGRATE | FINAL_INTEGRATE;
}

void FixSPHSolidLeapfrog::init()
{
  FixSPHSolidIntegrate::init();
  // the density and stress rates come from the half step (initial_integrate)
  pair->set_compute_pass(SPH_RATES_MOMENTUM);
}

void FixSPHSolidLeapfrog::fail(sph_status status, long atom_index, const char *stage_name)
{
  if (status == SPH_ERR_NONFINITE) check_finite();    // names the atom by its ID
  if (status == SPH_ERR_UNSTABLE && atom_index >= 0)
    sphsolid_one(lmp, FLERR, "fix {}: atom {} at step {}: {} (libsphsolid watchdog)", style,
                 atom->tag[atom_index], update->ntimestep, sph_errmsg(pair->handle()));
  sphsolid_one(lmp, FLERR, "fix {}: {} at step {}: {} ({})", style, stage_name, update->ntimestep,
               sph_errmsg(pair->handle()), sph_status_name(status));
}

void FixSPHSolidLeapfrog::initial_integrate(int /*vflag*/)
{
  const int nlocal = atom->nlocal;
  if (pair->rates_count() != nlocal)
    sphsolid_one(lmp, FLERR, "fix {}: the stored rates are for {} atoms, this rank owns {}", style,
                 pair->rates_count(), nlocal);
  pack();    // dv/dt = f/m of every force, rigid bodies applied; which atoms integrate
  // energy account: the step's trapezoid opens with the powers of the
  // rates it starts from, those the last step ended with (or evaluated
  // again after damage grew, as the library's leapfrog does); the first
  // step of a run has them evaluated here
  if (pair->energy_account_on() && !pair->account_carry()) account_evaluation();
  FixSPHSolidState *state = pair->state();

  // The predictor takes the density and stress rates of the last half step.
  // Atoms without them (the first step, a new atom, a restart file written
  // without them) take those of the current state: a continuity pass here,
  // on every rank if any rank needs it (it communicates).  Every step sets
  // them for all owned atoms and they move with their atoms, so atoms
  // without them can only appear when LAMMPS re-neighbours (atoms are
  // created or read between runs or in a re-neighbouring step): the check,
  // a collective, is made on the first step of a run and after a
  // re-neighbouring only.
  int any_missing = 0;
  if (neighbor->ago == 0 || update->ntimestep == update->firststep + 1) {
    int missing = 0;
    for (int i = 0; i < nlocal && !missing; i++) missing = std::isnan(state->carried_rho[i]);
    MPI_Allreduce(&missing, &any_missing, 1, MPI_INT, MPI_MAX, world);
  }
  if (any_missing) {
    pair->evaluate_rates(true, SPH_RATES_CONTINUITY);
    keep_rates(true);
  }
  sph_rates start = stage_rates();
  start.drho_dt = state->carried_rho;
  start.dS_dt = state->carried_S_data();
  stage.resize((size_t) std::max(nlocal, 1) * saved_doubles_per_atom());
  double *x = atom->x[0], *v = atom->v[0];
  double begin = PairSPHSolid::cpu_seconds();
  sph_status status =
      sph_leapfrog_begin_strided(pair->handle(), nlocal, update->dt, x, v, 3, state->rho,
                                 state->S_data(), &start, integrate_motion.data(), stage.data());
  pair->add_seconds(PairSPHSolid::PART_STAGES, PairSPHSolid::cpu_seconds() - begin);
  if (status != SPH_OK) fail(status, -1, "kick");

  // the density and stress rates at the half step (the continuity pass):
  // ghosts' x, v, rho and S in one exchange; written where the atoms carry
  // them, as they also predict the next half step
  pair->evaluate_rates(true, SPH_RATES_CONTINUITY, state->carried_rho, state->carried_S_data());
  sph_rates half = stage_rates();
  half.drho_dt = state->carried_rho;
  half.dS_dt = state->carried_S_data();
  long bad = -1;
  begin = PairSPHSolid::cpu_seconds();
  status = sph_leapfrog_drift_strided(pair->handle(), nlocal, update->dt, x, v, 3, state->rho,
                                      state->S_data(), &half, integrate_motion.data(), stage.data(),
                                      pair->atom_materials(), &bad);
  pair->add_seconds(PairSPHSolid::PART_STAGES, PairSPHSolid::cpu_seconds() - begin);
  if (status != SPH_OK) fail(status, bad, "drift");
}

/* The pair's last density and stress rates into the atoms' carried ones
 * (only_missing: for the atoms without). */
void FixSPHSolidLeapfrog::keep_rates(bool only_missing)
{
  const double start = PairSPHSolid::cpu_seconds();
  FixSPHSolidState *state = pair->state();
  const int nlocal = atom->nlocal, ncomp = pair->stress_components();
  const double *drho = pair->drho_dt(), *dS = pair->dS_dt();
  for (int i = 0; i < nlocal; i++) {
    if (only_missing && !std::isnan(state->carried_rho[i])) continue;
    state->carried_rho[i] = drho[i];
    for (int k = 0; k < ncomp; k++) state->carried_S[i][k] = dS[(size_t) i * ncomp + k];
  }
  pair->add_seconds(PairSPHSolid::PART_COPIES, PairSPHSolid::cpu_seconds() - start);
}

void FixSPHSolidLeapfrog::final_integrate()
{
  const int nlocal = atom->nlocal;
  pack();
  account_evaluation();    // energy account: the step's momentum pass
  long bad = -1;
  const double begin = PairSPHSolid::cpu_seconds();
  const sph_status status = sph_leapfrog_end_strided(
      pair->handle(), nlocal, update->dt, atom->v[0], 3, pair->state()->rho, stage_dv(),
      integrate_motion.data(), pair->atom_materials(), &bad);
  pair->add_seconds(PairSPHSolid::PART_STAGES, PairSPHSolid::cpu_seconds() - begin);
  if (status != SPH_OK) fail(status, bad, "kick");

  // effect damage: flaws activate and D grows on the step's end state.
  // If D grew the carried rates are stale: both passes again at y_{n+1}
  // (as the library's leapfrog evaluates both when it carries none), the
  // acceleration into f with the other fixes' forces kept.
  const bool grew =
      pair->grow_damage(update->dt, true, pair->drucker_prager_on() ? free_atoms() : nullptr);
  if (pair->energy_account_on()) pair->account_step(update->dt);
  if (!grew) return;
  evaluate_keeping_other_forces(SPH_RATES_ALL);
  keep_rates(false);
  if (pair->energy_account_on()) {
    pack();    // the powers of the new rates open the next step
    account_evaluation();
  }
}
