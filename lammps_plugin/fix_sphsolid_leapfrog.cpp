/*
 * fix_sphsolid_leapfrog.cpp - the library's leapfrog for pair sphsolid (see
 * the header).  The stages are sph_leapfrog_{begin,drift,end}_strided() on
 * LAMMPS's own x and v; this file hands them dv/dt (with the rigid bodies'
 * accelerations, from fix sphsolid/heun's pack()) and keeps the extra rate
 * evaluation of the half step in step with LAMMPS's communication.
 */
#include "fix_sphsolid_leapfrog.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "atom.h"
#include "error.h"
#include "update.h"

#include <algorithm>

using namespace LAMMPS_NS;
using namespace FixConst;

FixSPHSolidLeapfrog::FixSPHSolidLeapfrog(LAMMPS *lmp, int narg, char **arg) :
    FixSPHSolidHeun(lmp, narg, arg, "leapfrog")
{
}

int FixSPHSolidLeapfrog::setmask()
{
  return INITIAL_INTEGRATE | FINAL_INTEGRATE;
}

void FixSPHSolidLeapfrog::fail(sph_status status, long atom_index, const char *stage_name)
{
  if (status == SPH_ERR_NONFINITE) check_finite();    // names the atom by its ID
  if (status == SPH_ERR_UNSTABLE && atom_index >= 0)
    error->one(FLERR, "fix {}: atom {} at step {}: {} (libsphsolid watchdog)", style,
               atom->tag[atom_index], update->ntimestep, sph_errmsg(pair->handle()));
  error->one(FLERR, "fix {}: {} at step {}: {} ({})", style, stage_name, update->ntimestep,
             sph_errmsg(pair->handle()), sph_status_name(status));
}

void FixSPHSolidLeapfrog::initial_integrate(int /*vflag*/)
{
  const int nlocal = atom->nlocal;
  if (pair->rates_count() != nlocal)
    error->one(FLERR, "fix {}: the stored rates are for {} atoms, this rank owns {}", style,
               pair->rates_count(), nlocal);
  pack();    // dv/dt = f/m of every force, rigid bodies applied; which atoms integrate
  sph_rates start = stage_rates();
  stage.resize((size_t) std::max(nlocal, 1) * saved_values());
  FixSPHSolidState *state = pair->state();
  double *x = atom->x[0], *v = atom->v[0];
  sph_status status =
      sph_leapfrog_begin_strided(pair->handle(), nlocal, update->dt, x, v, 3, state->rho,
                                 state->S_data(), &start, integrate_motion.data(), stage.data());
  if (status != SPH_OK) fail(status, -1, "kick");

  // the rates at the half step: ghosts' x, v, rho and S in one exchange
  pair->evaluate_rates(true);
  const sph_rates half = stage_rates();
  long bad = -1;
  status = sph_leapfrog_drift_strided(pair->handle(), nlocal, update->dt, x, v, 3, state->rho,
                                      state->S_data(), &half, integrate_motion.data(), stage.data(),
                                      pair->atom_materials(), &bad);
  if (status != SPH_OK) fail(status, bad, "drift");
}

void FixSPHSolidLeapfrog::final_integrate()
{
  const int nlocal = atom->nlocal;
  pack();
  long bad = -1;
  const sph_status status = sph_leapfrog_end_strided(
      pair->handle(), nlocal, update->dt, atom->v[0], 3, pair->state()->rho, dvbuf.data(),
      integrate_motion.data(), pair->atom_materials(), &bad);
  if (status != SPH_OK) fail(status, bad, "kick");
}
