/*
 * fix_sphsolid_heun.cpp - Improved Euler for pair sphsolid (see the header).
 *
 * The stages are the library's sph_heun_predict() and sph_heun_correct();
 * this file packs LAMMPS's arrays for them and keeps the two rate
 * evaluations in step with LAMMPS's communication.
 */
#include "fix_sphsolid_heun.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ---------------------------------------------------------------------- */

FixSPHSolidHeun::FixSPHSolidHeun(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), pair(nullptr), timestep_from_library(false)
{
  if (narg != 3)
    error->all(FLERR, "fix sphsolid/heun takes no arguments after the style name, got '{}'",
               arg[3]);
  time_integrate = 1;
  dynamic_group_allow = 0;

  // Without a timestep command the step is the library's default
  // 0.5 h / c0, set now so that every fix defined later sees it.
  if (update->dt_default) {
    auto p = dynamic_cast<PairSPHSolid *>(force->pair_match("sphsolid", 1));
    const double dt = p ? p->default_timestep() : 0.0;
    if (dt > 0.0) {
      update->update_time();
      update->dt = dt;
      update->dt_default = 0;
      timestep_from_library = true;
      if (comm->me == 0)
        utils::logmesg(lmp, "fix sphsolid/heun: timestep {:.6g} s, the library default 0.5 h/c0\n",
                       dt);
    }
  }
}

/* ---------------------------------------------------------------------- */

int FixSPHSolidHeun::setmask()
{
  return INITIAL_INTEGRATE | FINAL_INTEGRATE;
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidHeun::init()
{
  pair = dynamic_cast<PairSPHSolid *>(force->pair_match("sphsolid", 1));
  if (!pair) error->all(FLERR, "fix sphsolid/heun needs 'pair_style sphsolid'");
  if (modify->get_fix_by_style("^sphsolid/heun$").size() > 1)
    error->all(FLERR, "only one fix sphsolid/heun may be defined: it evolves the SPH state of "
                      "every atom; its group selects whose motion it integrates");
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, "fix sphsolid/heun does not support run_style respa");
  if (update->dt_default)
    error->all(FLERR,
               "fix sphsolid/heun: no timestep given; use the timestep command or define the fix "
               "after pair_coeff to get the library default 0.5 h/c0 ({:.6g} s for the current "
               "coefficients)",
               pair->default_timestep());
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidHeun::pack()
{
  const int nlocal = atom->nlocal;
  const int dim = pair->dimension();
  const size_t n = atom->nmax > 0 ? atom->nmax : 1;
  if (dvbuf.size() < n * dim) {
    dvbuf.resize(n * dim);
    other_force.resize(n * dim);
    integrate_motion.resize(n);
    xbuf.resize(n * dim);
    vbuf.resize(n * dim);
  }

  // copies with dim values per atom: the library advances every position
  // with its velocity, but only integrated atoms get the result back, so
  // fix move's positions stand whatever the order of the fixes
  double **ax = atom->x, **av = atom->v, **f = atom->f;
  const int *mask = atom->mask;
  for (int i = 0; i < nlocal; i++) {
    const double inverse_mass = 1.0 / pair->mass_of(i);
    for (int d = 0; d < dim; d++) {
      xbuf[(size_t) i * dim + d] = ax[i][d];
      vbuf[(size_t) i * dim + d] = av[i][d];
      // dv/dt of every force on the atom: pair sphsolid plus other fixes (gravity)
      dvbuf[(size_t) i * dim + d] = f[i][d] * inverse_mass;
    }
    integrate_motion[i] = (mask[i] & groupbit) ? 1 : 0;
  }
}

void FixSPHSolidHeun::unpack()
{
  const int nlocal = atom->nlocal;
  const int dim = pair->dimension();
  double **ax = atom->x, **av = atom->v;
  for (int i = 0; i < nlocal; i++) {
    if (!integrate_motion[i]) continue;
    for (int d = 0; d < dim; d++) {
      ax[i][d] = xbuf[(size_t) i * dim + d];
      av[i][d] = vbuf[(size_t) i * dim + d];
    }
  }
}

/* number of stage-1 values per atom: v, rho, S and, with XSPH, dx/dt */
int FixSPHSolidHeun::saved_values() const
{
  const int dim = pair->dimension();
  return dim + 1 + pair->stress_components() + (pair->dx_dt() ? dim : 0);
}

sph_rates FixSPHSolidHeun::stage_rates()
{
  sph_rates rates;
  rates.dv_dt = dvbuf.data();
  rates.drho_dt = const_cast<double *>(pair->drho_dt());
  rates.dS_dt = const_cast<double *>(pair->dS_dt());
  rates.dx_dt = const_cast<double *>(pair->dx_dt());
  return rates;
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidHeun::initial_integrate(int /*vflag*/)
{
  const int nlocal = atom->nlocal;
  if (pair->rates_count() != nlocal)
    error->one(FLERR, "fix sphsolid/heun: the stored rates are for {} atoms, this rank owns {}",
               pair->rates_count(), nlocal);
  pack();
  const sph_rates rates = stage_rates();
  const int nsaved = saved_values();
  stage.resize((size_t) std::max(nlocal, 1) * nsaved);

  FixSPHSolidState *state = pair->state();
  const sph_status status =
      sph_heun_predict(pair->handle(), nlocal, update->dt, xbuf.data(), vbuf.data(), state->rho,
                       state->S_data(), &rates, integrate_motion.data(), stage.data());
  if (status != SPH_OK)
    error->one(FLERR, "fix sphsolid/heun: predictor at step {}: {} ({})", update->ntimestep,
               sph_errmsg(pair->handle()), sph_status_name(status));
  unpack();

  // The library keeps y_n in blocks (all v, all rho, all S, ...); atoms may
  // change rank before the corrector, so each atom's y_n goes to its row.
  const size_t n = nlocal;
  for (size_t i = 0; i < n; i++) {
    int c = 0;
    size_t offset = 0;
    for (int block : {pair->dimension(), 1, pair->stress_components(),
                      nsaved - pair->dimension() - 1 - pair->stress_components()}) {
      for (int k = 0; k < block; k++) state->saved[i][c++] = stage[offset + i * block + k];
      offset += n * block;
    }
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidHeun::final_integrate()
{
  const int nlocal = atom->nlocal;
  const int dim = pair->dimension();
  pack();
  const sph_rates rates = stage_rates();
  const int nsaved = saved_values();
  stage.resize((size_t) std::max(nlocal, 1) * nsaved);

  FixSPHSolidState *state = pair->state();
  const size_t n = nlocal;
  for (size_t i = 0; i < n; i++) {
    int c = 0;
    size_t offset = 0;
    for (int block :
         {dim, 1, pair->stress_components(), nsaved - dim - 1 - pair->stress_components()}) {
      for (int k = 0; k < block; k++) stage[offset + i * block + k] = state->saved[i][c++];
      offset += n * block;
    }
  }

  const sph_status status =
      sph_heun_correct(pair->handle(), nlocal, update->dt, xbuf.data(), vbuf.data(), state->rho,
                       state->S_data(), &rates, integrate_motion.data(), stage.data());
  if (status == SPH_ERR_NONFINITE) {
    unpack();
    check_finite();    // names the atom by its ID
  }
  if (status != SPH_OK)
    error->one(FLERR, "fix sphsolid/heun: corrector at step {}: {} ({})", update->ntimestep,
               sph_errmsg(pair->handle()), sph_status_name(status));
  unpack();
  check_finite();

  // The first rate evaluation of the next step, at y_{n+1}.  Forces from
  // other fixes (gravity) are kept as they were added to f(y*): they do not
  // depend on the SPH state.
  double **f = atom->f;
  const double *dv_pair = pair->dv_dt();
  for (int i = 0; i < nlocal; i++) {
    const double m = pair->mass_of(i);
    for (int d = 0; d < dim; d++)
      other_force[(size_t) i * dim + d] = f[i][d] - m * dv_pair[(size_t) i * dim + d];
  }
  comm->forward_comm();    // positions and velocities of the ghosts
  pair->evaluate_rates();
  dv_pair = pair->dv_dt();
  for (int i = 0; i < nlocal; i++) {
    const double m = pair->mass_of(i);
    for (int d = 0; d < dim; d++)
      f[i][d] = m * dv_pair[(size_t) i * dim + d] + other_force[(size_t) i * dim + d];
  }
}

/* ----------------------------------------------------------------------
   stop at once on a non-finite value, naming step, atom and quantity
------------------------------------------------------------------------- */

void FixSPHSolidHeun::check_finite()
{
  const int nlocal = atom->nlocal;
  const int dim = pair->dimension();
  const int ncomp = pair->stress_components();
  FixSPHSolidState *state = pair->state();
  double **x = atom->x, **v = atom->v;
  for (int i = 0; i < nlocal; i++) {
    const char *quantity = nullptr;
    for (int d = 0; d < dim; d++) {
      if (!std::isfinite(x[i][d])) quantity = "non-finite position";
      if (!std::isfinite(v[i][d])) quantity = "non-finite velocity";
    }
    if (!std::isfinite(state->rho[i])) quantity = "non-finite density";
    if (std::isfinite(state->rho[i]) && !(state->rho[i] > 0.0)) quantity = "non-positive density";
    for (int k = 0; k < ncomp; k++)
      if (!std::isfinite(state->S[i][k])) quantity = "non-finite deviatoric stress";
    if (quantity)
      error->one(FLERR, "fix sphsolid/heun: {} of atom {} at step {}", quantity,
                 atom->tag[i], update->ntimestep);
  }
}

/* ---------------------------------------------------------------------- */

double FixSPHSolidHeun::memory_usage()
{
  return sizeof(double) *
      (double) (xbuf.capacity() + vbuf.capacity() + dvbuf.capacity() + other_force.capacity() +
                stage.capacity()) +
      (double) integrate_motion.capacity();
}
