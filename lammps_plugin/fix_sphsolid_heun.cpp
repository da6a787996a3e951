/*
 * fix_sphsolid_heun.cpp - Improved Euler for pair sphsolid (see the header).
 *
 * The stages are the library's sph_heun_predict_strided() and
 * sph_heun_correct_strided(), working on LAMMPS's own x and v (3 doubles
 * per atom); this file hands them dv/dt and keeps the two rate
 * evaluations in step with LAMMPS's communication.
 */
#include "fix_sphsolid_heun.h"

#include "fix_sphsolid_force.h"
#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "modify.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

// LAMMPS's per-atom 3-vectors (x, v) as one block of doubles, 3 per atom
static double *xv(double **array)
{
  return array ? array[0] : nullptr;
}

/* ---------------------------------------------------------------------- */

FixSPHSolidHeun::FixSPHSolidHeun(LAMMPS *lmp, int narg, char **arg) :
    FixSPHSolidHeun(lmp, narg, arg, "improved_euler")
{
}

FixSPHSolidHeun::FixSPHSolidHeun(LAMMPS *lmp, int narg, char **arg, const char *name) :
    Fix(lmp, narg, arg), integrator(name), pair(nullptr), timestep_from_library(false),
    stage_atoms(-1), stage_in_rows(false)
{
  if (narg != 3)
    error->all(FLERR, "fix {} takes no arguments after the style name, got '{}'", style, arg[3]);
  time_integrate = 1;
  dynamic_group_allow = 0;

  // Without a timestep command the step is the library's default
  // 0.5 h / c0, set now so that every fix defined later sees it.
  if (update->dt_default) {
    auto p = dynamic_cast<PairSPHSolid *>(force->pair_match("sphsolid", 1));
    const double dt = p ? p->default_timestep(integrator) : 0.0;
    if (dt > 0.0) {
      update->update_time();
      update->dt = dt;
      update->dt_default = 0;
      timestep_from_library = true;
      if (comm->me == 0)
        utils::logmesg(lmp, "fix {}: timestep {:.6g} s, the library default {:g} h/c0 of {}\n",
                       style, dt, default_factor(), integrator);
    }
  }
}

/* ---------------------------------------------------------------------- */

int FixSPHSolidHeun::setmask()
{
  return INITIAL_INTEGRATE | PRE_EXCHANGE | FINAL_INTEGRATE;
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidHeun::init()
{
  pair = dynamic_cast<PairSPHSolid *>(force->pair_match("sphsolid", 1));
  if (!pair) error->all(FLERR, "fix {} needs 'pair_style sphsolid'", style);
  if (modify->get_fix_by_style("^sphsolid/heun$").size() +
          modify->get_fix_by_style("^sphsolid/leapfrog$").size() >
      1)
    error->all(FLERR, "only one fix sphsolid/heun or sphsolid/leapfrog may be defined: it evolves "
                      "the SPH state of every atom; its group selects whose motion it integrates");
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, "fix {} does not support run_style respa", style);
  // an empty group is a deck whose atoms all move by prescription (fix
  // move); without such a fix nothing would move at all
  if (group->count(igroup) == 0) {
    bool others = false;
    for (int k = 0; k < modify->nfix; k++)
      if (modify->fix[k]->time_integrate && !utils::strmatch(modify->fix[k]->style, "^sphsolid/"))
        others = true;
    if (!others)
      error->all(FLERR,
                 "fix {} {}: group {} has no atoms and no other fix moves any atom, so nothing "
                 "would move; give it the group of the atoms it should integrate (e.g. all)",
                 id, style, group->names[igroup]);
  }
  init_rigid_bodies();
  if (update->dt_default)
    error->all(FLERR,
               "fix {}: no timestep given; use the timestep command or define the fix "
               "after pair_coeff to get the library default {:g} h/c0 of {} ({:.6g} s for the "
               "current coefficients)",
               style, default_factor(), integrator, pair->default_timestep(integrator));
}

/* ----------------------------------------------------------------------
   fix sphsolid/force groups: each inside this fix's group, no atom in two
------------------------------------------------------------------------- */

void FixSPHSolidHeun::init_rigid_bodies()
{
  rigid.clear();
  for (Fix *f : modify->get_fix_by_style("^sphsolid/force$"))
    rigid.push_back(dynamic_cast<FixSPHSolidForce *>(f));
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  for (size_t k = 0; k < rigid.size(); k++) {
    bigint outside = 0, shared = 0, all[2];
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & rigid[k]->groupbit)) continue;
      if (!(mask[i] & groupbit)) outside++;
      for (size_t j = k + 1; j < rigid.size(); j++)
        if (mask[i] & rigid[j]->groupbit) shared++;
    }
    const bigint mine[2] = {outside, shared};
    MPI_Allreduce(mine, all, 2, MPI_LMP_BIGINT, MPI_SUM, world);
    if (all[0] > 0)
      error->all(FLERR,
                 "fix {} (sphsolid/force): {} atoms of its group are not in group {} of "
                 "fix {}, which integrates the body's motion",
                 rigid[k]->id, all[0], group->names[igroup], style);
    if (all[1] > 0)
      error->all(FLERR,
                 "fix {} (sphsolid/force): {} atoms of its group belong to another "
                 "fix sphsolid/force too",
                 rigid[k]->id, all[1]);
  }
}

/* every atom of a fix sphsolid/force group gets the body's acceleration */
void FixSPHSolidHeun::apply_rigid_bodies()
{
  if (rigid.empty()) return;
  const int nlocal = atom->nlocal;
  const int dim = pair->dimension();
  const int *mask = atom->mask;
  member.resize((size_t) std::max(nlocal, 1));
  masses.resize((size_t) std::max(nlocal, 1));
  for (int i = 0; i < nlocal; i++) masses[i] = pair->mass_of(i);
  for (FixSPHSolidForce *body : rigid) {
    for (int i = 0; i < nlocal; i++) member[i] = (mask[i] & body->groupbit) ? 1 : 0;
    double mine[4] = {0.0, 0.0, 0.0, 0.0}, sums[4];
    sph_rigid_force_sum(pair->handle(), nlocal, masses.data(), dvbuf.data(), member.data(), mine);
    MPI_Allreduce(mine, sums, dim + 1, MPI_DOUBLE, MPI_SUM, world);
    if (sph_rigid_force_apply(pair->handle(), nlocal, body->applied(), sums, member.data(),
                              dvbuf.data()) != SPH_OK)
      error->all(FLERR, "fix {} (sphsolid/force) at step {}: {}", body->id, update->ntimestep,
                 sph_errmsg(pair->handle()));
  }
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
  }

  // dv/dt of every force on the atom: pair sphsolid plus other fixes
  // (gravity); the stages advance x and v only of the atoms in the group,
  // so fix move's positions stand whatever the order of the fixes
  double **f = atom->f;
  const int *mask = atom->mask;
  const double *rmass = atom->rmass, *type_mass = atom->mass;
  const int *type = atom->type;
  for (int i = 0; i < nlocal; i++) {
    const double inverse_mass = 1.0 / (rmass ? rmass[i] : type_mass[type[i]]);
    for (int d = 0; d < dim; d++) dvbuf[(size_t) i * dim + d] = f[i][d] * inverse_mass;
    integrate_motion[i] = (mask[i] & groupbit) ? 1 : 0;
  }
  apply_rigid_bodies();
}

/* the integrator's default step in units of h/c0 (sph_integrator_info_get) */
double FixSPHSolidHeun::default_factor()
{
  sph_sim *s = nullptr;
  sph_integrator_info info;
  const bool ok = sph_create(domain->dimension, &s) == SPH_OK &&
                  sph_integrator_info_get(s, integrator, &info) == SPH_OK;
  sph_destroy(s);
  return ok ? info.default_factor : 0.0;
}

/* values per atom of the library's stage buffer (sph_integrator_info_get) */
int FixSPHSolidHeun::saved_values() const
{
  sph_integrator_info info;
  if (sph_integrator_info_get(pair->handle(), integrator, &info) != SPH_OK)
    error->one(FLERR, "fix {}: {}", style, sph_errmsg(pair->handle()));
  return (int) info.saved_values;
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
  const sph_status status = sph_heun_predict_strided(
      pair->handle(), nlocal, update->dt, xv(atom->x), xv(atom->v), 3, state->rho, state->S_data(),
      &rates, integrate_motion.data(), stage.data());
  if (status != SPH_OK)
    error->one(FLERR, "fix sphsolid/heun: predictor at step {}: {} ({})", update->ntimestep,
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

void FixSPHSolidHeun::pre_exchange()
{
  if (stage_atoms < 0 || stage_in_rows) return;
  if (atom->nlocal != stage_atoms)
    error->one(FLERR,
               "fix sphsolid/heun: {} atoms before re-neighbouring, {} after the predictor "
               "(atoms deleted or created inside a step are not supported)",
               atom->nlocal, stage_atoms);
  copy_stage(true);
  stage_in_rows = true;
}

/* blocks of `stage` (all v, all rho, all S[, all dx/dt]) <-> per-atom rows
   of the state fix's `saved`, for the stage_atoms owned atoms */
void FixSPHSolidHeun::copy_stage(bool to_rows)
{
  const int dim = pair->dimension(), ncomp = pair->stress_components();
  const int nsaved = saved_values();
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

  if (stage_atoms < 0)
    error->one(FLERR, "fix sphsolid/heun: corrector at step {} without a predictor",
               update->ntimestep);
  if (stage_in_rows) {
    // atoms were exchanged or sorted since the predictor: gather the rows
    stage_atoms = nlocal;
    copy_stage(false);
  } else if (stage_atoms != nlocal) {
    error->one(FLERR, "fix sphsolid/heun: {} atoms at the predictor, {} at the corrector",
               stage_atoms, nlocal);
  }

  // the corrector, then the library's watchdog on the integrated atoms
  // (runaway speed or density), in one pass
  FixSPHSolidState *state = pair->state();
  long bad = -1;
  const sph_status status = sph_heun_correct_strided(
      pair->handle(), nlocal, update->dt, xv(atom->x), xv(atom->v), 3, state->rho, state->S_data(),
      &rates, integrate_motion.data(), pair->atom_materials(), stage.data(), &bad);
  if (status == SPH_ERR_NONFINITE) check_finite();    // names the atom by its ID
  if (status == SPH_ERR_UNSTABLE)
    error->one(FLERR,
               "fix sphsolid/heun: atom {} at step {}: {} (libsphsolid watchdog: speed above c_p "
               "or density outside [0.5, 2] rho0; {})",
               atom->tag[bad], update->ntimestep, sph_errmsg(pair->handle()),
               pair->step_advice(integrator));
  if (status != SPH_OK)
    error->one(FLERR, "fix sphsolid/heun: corrector at step {}: {} ({})", update->ntimestep,
               sph_errmsg(pair->handle()), sph_status_name(status));
  stage_atoms = -1;

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
  pair->evaluate_rates(true);    // ghosts' x, v, rho and S in one exchange
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
      error->one(FLERR, "fix {}: {} of atom {} at step {} ({})", style, quantity, atom->tag[i],
                 update->ntimestep, pair->step_advice(integrator));
  }
}

/* ---------------------------------------------------------------------- */

double FixSPHSolidHeun::memory_usage()
{
  return sizeof(double) * (double) (dvbuf.capacity() + other_force.capacity() + stage.capacity()) +
         (double) integrate_motion.capacity();
}
