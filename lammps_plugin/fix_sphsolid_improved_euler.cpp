/*
 * fix_sphsolid_improved_euler.cpp - Improved Euler for pair sphsolid (see
 * the header).
 *
 * The stages are the library's sph_improved_euler_predict_strided() and
 * sph_improved_euler_correct_strided(), working on LAMMPS's own x and v (3
 * doubles per atom); this file hands them dv/dt and keeps the two rate
 * evaluations in step with LAMMPS's communication.
 */
#include "fix_sphsolid_improved_euler.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "sphsolid_error.h"
#include "update.h"

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;
using namespace FixConst;

// LAMMPS's per-atom 3-vectors (x, v) as one block of doubles, 3 per atom
static double *xv(double **array)
{
  return array ? array[0] : nullptr;
}

/* ---------------------------------------------------------------------- */

FixSPHSolidImprovedEuler::FixSPHSolidImprovedEuler(LAMMPS *lmp, int narg, char **arg) :
    FixSPHSolidIntegrate(lmp, narg, arg, "improved_euler"), stage_atoms(-1), stage_in_rows(false)
{
}

/* the deprecated style name of the 0.2 series, removed in release 0.3.0 */
FixSPHSolidHeun::FixSPHSolidHeun(LAMMPS *lmp, int narg, char **arg) :
    FixSPHSolidImprovedEuler(lmp, narg, arg)
{
  if (comm->me == 0)
    error->warning(FLERR,
                   "fix {} {}: style sphsolid/heun is deprecated and will be removed in "
                   "release 0.3.0; use fix sphsolid/improved_euler (the same integrator)",
                   id, style);
}

/* ---------------------------------------------------------------------- */

/* ---------------------------------------------------------------------- */

int FixSPHSolidImprovedEuler::setmask()
{
  return INITIAL_INTEGRATE | PRE_EXCHANGE | FINAL_INTEGRATE;
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidImprovedEuler::initial_integrate(int /*vflag*/)
{
  const int nlocal = atom->nlocal;
  if (pair->rates_count() != nlocal)
    sphsolid_one(lmp, FLERR, "fix {}: the stored rates are for {} atoms, this rank owns {}", style,
                 pair->rates_count(), nlocal);
  pack();
  account_evaluation();    // energy account: the evaluation at y_n
  const sph_rates rates = stage_rates();
  const int nsaved = saved_doubles_per_atom();
  stage.resize((size_t) std::max(nlocal, 1) * nsaved);

  FixSPHSolidState *state = pair->state();
  const double start = PairSPHSolid::cpu_seconds();
  const sph_status status = sph_improved_euler_predict_strided(
      pair->handle(), nlocal, update->dt, xv(atom->x), xv(atom->v), 3, state->rho, state->S_data(),
      &rates, integrate_motion.data(), stage.data());
  pair->add_seconds(PairSPHSolid::PART_STAGES, PairSPHSolid::cpu_seconds() - start);
  if (status != SPH_OK)
    sphsolid_one(lmp, FLERR, "fix {}: predictor at step {}: {} ({})", style, update->ntimestep,
                 sph_errmsg(pair->handle()), sph_status_name(status));

  // y_n stays in the library's block layout in `stage` unless atoms move
  // or are reordered before the corrector (pre_exchange).
  stage_atoms = nlocal;
  stage_in_rows = false;
}

/* ----------------------------------------------------------------------
   Verlet calls this only on steps that re-neighbour, before atoms migrate
   between ranks or are sorted: each atom's y_n goes to its row of the
   state fix, which travels with the atom.
------------------------------------------------------------------------- */

void FixSPHSolidImprovedEuler::pre_exchange()
{
  if (stage_atoms < 0 || stage_in_rows) return;
  if (atom->nlocal != stage_atoms)
    sphsolid_one(lmp, FLERR,
                 "fix {}: {} atoms before re-neighbouring, {} after the predictor "
                 "(atoms deleted or created inside a step are not supported)",
                 style, atom->nlocal, stage_atoms);
  copy_stage(true);
  stage_in_rows = true;
}

/* blocks of `stage` (all v, all rho, all S[, all dx/dt]) <-> per-atom rows
   of the state fix's `saved`, for the stage_atoms owned atoms */
void FixSPHSolidImprovedEuler::copy_stage(bool to_rows)
{
  const double start = PairSPHSolid::cpu_seconds();
  const int dim = pair->dimension(), ncomp = pair->stress_components();
  const int nsaved = saved_doubles_per_atom();
  FixSPHSolidState *state = pair->state();
  const size_t n = stage_atoms;
  const int blocks[4] = {dim, 1, ncomp, nsaved - dim - 1 - ncomp};
  size_t offset = 0;
  int column = 0;
  for (int block : blocks) {
    for (size_t i = 0; i < n; i++) {
      double *row = state->saved[i] + column;
      double *packed = &stage[offset + i * block];
      for (int k = 0; k < block; k++) {
        if (to_rows)
          row[k] = packed[k];
        else
          packed[k] = row[k];
      }
    }
    offset += n * block;
    column += block;
  }
  pair->add_seconds(PairSPHSolid::PART_COPIES, PairSPHSolid::cpu_seconds() - start);
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidImprovedEuler::final_integrate()
{
  const int nlocal = atom->nlocal;
  pack();
  account_evaluation();    // energy account: the evaluation at y*
  const sph_rates rates = stage_rates();
  const int nsaved = saved_doubles_per_atom();
  stage.resize((size_t) std::max(nlocal, 1) * nsaved);

  if (stage_atoms < 0)
    sphsolid_one(lmp, FLERR, "fix {}: corrector at step {} without a predictor", style,
                 update->ntimestep);
  if (stage_in_rows) {
    // atoms were exchanged or sorted since the predictor: gather the rows
    stage_atoms = nlocal;
    copy_stage(false);
  } else if (stage_atoms != nlocal) {
    sphsolid_one(lmp, FLERR, "fix {}: {} atoms at the predictor, {} at the corrector", style,
                 stage_atoms, nlocal);
  }

  // the corrector, then the library's watchdog on the integrated atoms
  // (runaway speed or density), in one pass
  FixSPHSolidState *state = pair->state();
  long bad = -1;
  const double start = PairSPHSolid::cpu_seconds();
  const sph_status status = sph_improved_euler_correct_strided(
      pair->handle(), nlocal, update->dt, xv(atom->x), xv(atom->v), 3, state->rho, state->S_data(),
      &rates, integrate_motion.data(), pair->atom_materials(), stage.data(), &bad);
  pair->add_seconds(PairSPHSolid::PART_STAGES, PairSPHSolid::cpu_seconds() - start);
  if (status == SPH_ERR_NONFINITE) check_finite();    // names the atom by its ID
  if (status == SPH_ERR_UNSTABLE)
    sphsolid_one(lmp, FLERR,
                 "fix {}: atom {} at step {}: {} (libsphsolid watchdog: speed above c_p "
                 "or density outside [0.5, 2] rho0; {})",
                 style, atom->tag[bad], update->ntimestep, sph_errmsg(pair->handle()),
                 pair->step_advice(integrator));
  if (status != SPH_OK)
    sphsolid_one(lmp, FLERR, "fix {}: corrector at step {}: {} ({})", style, update->ntimestep,
                 sph_errmsg(pair->handle()), sph_status_name(status));
  stage_atoms = -1;

  // effect damage: flaws activate and D grows on the step's end state,
  // before the rates of the next step are evaluated there (which they are
  // whether D grew or not: no collective needed)
  pair->grow_damage(update->dt, false, pair->drucker_prager_on() ? free_atoms() : nullptr);
  if (pair->energy_account_on()) pair->account_step(update->dt);    // the trapezoid of the two

  // The first rate evaluation of the next step, at y_{n+1}.  Forces from
  // other fixes (gravity) are kept as they were added to f(y*): they do not
  // depend on the SPH state.
  evaluate_keeping_other_forces(SPH_RATES_ALL);
}
