/*
 * fix_sphsolid_integrate.cpp - what the integrating fixes of pair sphsolid
 * share (see the header): the deck checks at init, the library's default
 * time step, dv/dt of every force with the rigid bodies of fix
 * sphsolid/force applied, the stage buffer's size and the report of a
 * non-finite value.
 */
#include "fix_sphsolid_integrate.h"

#include "fix_sphsolid_force.h"
#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "sphsolid_error.h"
#include "force.h"
#include "group.h"
#include "modify.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ---------------------------------------------------------------------- */

FixSPHSolidIntegrate::FixSPHSolidIntegrate(LAMMPS *lmp, int narg, char **arg, const char *name) :
    Fix(lmp, narg, arg), integrator(name), pair(nullptr), timestep_from_library(false)
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

void FixSPHSolidIntegrate::init()
{
  pair = dynamic_cast<PairSPHSolid *>(force->pair_match("sphsolid", 1));
  if (!pair) error->all(FLERR, "fix {} needs 'pair_style sphsolid'", style);
  if (modify->get_fix_by_style("^sphsolid/improved_euler$").size() +
          modify->get_fix_by_style("^sphsolid/heun$").size() +
          modify->get_fix_by_style("^sphsolid/leapfrog$").size() >
      1)
    error->all(FLERR, "only one fix sphsolid/improved_euler or sphsolid/leapfrog may be defined: "
                      "it evolves the SPH state of every atom; its group selects whose motion it "
                      "integrates");
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
  draw_flaws();
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

void FixSPHSolidIntegrate::init_rigid_bodies()
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

/* the library's prescribed and force-driven bodies have no flaws: here the
   atoms outside the group and those of a fix sphsolid/force body */
void FixSPHSolidIntegrate::draw_flaws()
{
  if (!pair->damage_on()) return;
  pair->draw_flaws(free_atoms());
}

/* the atoms in the group and in no fix sphsolid/force body */
const unsigned char *FixSPHSolidIntegrate::free_atoms()
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  free_mask.assign((size_t) std::max(nlocal, 1), 0);
  for (int i = 0; i < nlocal; i++) {
    free_mask[i] = (mask[i] & groupbit) ? 1 : 0;
    for (FixSPHSolidForce *body : rigid)
      if (mask[i] & body->groupbit) free_mask[i] = 0;
  }
  return free_mask.data();
}

/* every atom of a fix sphsolid/force group gets the body's acceleration */
void FixSPHSolidIntegrate::apply_rigid_bodies()
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
      sphsolid_one(lmp, FLERR, "fix {} (sphsolid/force) at step {}: {}", body->id,
                   update->ntimestep, sph_errmsg(pair->handle()));
  }
}

/* the end of a run's set-up: pair sphsolid's timers count the loop from
   here on (the set-up's rate evaluation is not part of it) */
void FixSPHSolidIntegrate::setup(int /*vflag*/)
{
  forces_of_pair_only = pair_forces_only();
  pair->reset_seconds();
  // the energy account's starting energy, the first time it runs
  if (pair->energy_account_on()) pair->account_start();
}

/* energy account: the powers of the rate evaluation whose accelerations
   pack() just put into stage_dv */
void FixSPHSolidIntegrate::account_evaluation()
{
  if (pair->energy_account_on()) pair->account_evaluation(stage_dv(), integrate_motion.data());
}

/* ----------------------------------------------------------------------
   LAMMPS clears f before the force computation; pair sphsolid's compute
   adds m dv/dt.  Other styles add in their compute and fixes in pre_force,
   pre_reverse or post_force (gravity, setforce, addforce, ...).  Without
   any of them f is m dv/dt exactly, so dv/dt is the pair's own and the
   other forces are zero: pack() and evaluate_keeping_other_forces() then
   make one copy instead of three per evaluation.
------------------------------------------------------------------------- */

const double *FixSPHSolidIntegrate::stage_dv() const
{
  return dv_of_pair ? pair->dv_dt() : dvbuf.data();
}

bool FixSPHSolidIntegrate::pair_forces_only() const
{
  if (force->pair != pair || force->kspace || force->bond || force->angle || force->dihedral ||
      force->improper)
    return false;
  return modify->n_pre_force == 0 && modify->n_pre_reverse == 0 && modify->n_post_force_any == 0;
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidIntegrate::pack()
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
  // (LAMMPS's per-atom arrays are contiguous: f[i] is f[0] + 3 i; the
  // pointers are read once, as the stores below could alias LAMMPS's own)
  const double start = PairSPHSolid::cpu_seconds();
  const int *mask = atom->mask;
  unsigned char *moves = integrate_motion.data();
  const int bit = groupbit;
  for (int i = 0; i < nlocal; i++) moves[i] = (mask[i] & bit) ? 1 : 0;
  dv_of_pair = forces_of_pair_only && rigid.empty();
  if (dv_of_pair) {    // f / m would give back the pair's dv/dt, rounded twice
    pair->add_seconds(PairSPHSolid::PART_COPIES, PairSPHSolid::cpu_seconds() - start);
    return;
  }
  const double *f = nlocal > 0 ? atom->f[0] : nullptr;
  const double *rmass = atom->rmass;
  double *dv = dvbuf.data();
  if (rmass) {
    for (int i = 0; i < nlocal; i++) {
      const double inverse_mass = 1.0 / rmass[i];
      for (int d = 0; d < dim; d++) dv[(size_t) i * dim + d] = f[3 * i + d] * inverse_mass;
    }
  } else {    // one division per type
    inverse_type_mass.resize((size_t) atom->ntypes + 1);
    for (int t = 1; t <= atom->ntypes; t++) inverse_type_mass[t] = 1.0 / atom->mass[t];
    const double *inverse = inverse_type_mass.data();
    const int *type = atom->type;
    for (int i = 0; i < nlocal; i++)
      for (int d = 0; d < dim; d++) dv[(size_t) i * dim + d] = f[3 * i + d] * inverse[type[i]];
  }
  pair->add_seconds(PairSPHSolid::PART_COPIES, PairSPHSolid::cpu_seconds() - start);
  apply_rigid_bodies();
}

void FixSPHSolidIntegrate::evaluate_keeping_other_forces(int pass)
{
  const int nlocal = atom->nlocal;
  const int dim = pair->dimension();
  double *f = nlocal > 0 ? atom->f[0] : nullptr;
  const PairSPHSolid::AtomMasses mass = pair->atom_masses();
  // without other forces (forces_of_pair_only) f is m dv/dt: nothing to keep
  const bool keep = !forces_of_pair_only;
  double start = PairSPHSolid::cpu_seconds();
  double *other = nullptr;
  if (keep) {
    other_force.resize((size_t) std::max(nlocal, 1) * dim);
    other = other_force.data();
    const double *dv_pair = pair->dv_dt();
    for (int i = 0; i < nlocal; i++) {
      const double m = mass[i];
      for (int d = 0; d < dim; d++)
        other[(size_t) i * dim + d] = f[3 * i + d] - m * dv_pair[(size_t) i * dim + d];
    }
  }
  pair->add_seconds(PairSPHSolid::PART_COPIES, PairSPHSolid::cpu_seconds() - start);
  pair->evaluate_rates(true, pass);    // ghosts' x, v, rho and S in one exchange
  start = PairSPHSolid::cpu_seconds();
  const double *dv_pair = pair->dv_dt();
  for (int i = 0; i < nlocal; i++) {
    const double m = mass[i];
    for (int d = 0; d < dim; d++) {
      const double pair_force = m * dv_pair[(size_t) i * dim + d];
      f[3 * i + d] = keep ? pair_force + other[(size_t) i * dim + d] : pair_force;
    }
  }
  pair->add_seconds(PairSPHSolid::PART_COPIES, PairSPHSolid::cpu_seconds() - start);
}

/* the integrator's default step in units of h/c0 (sph_integrator_info_get) */
double FixSPHSolidIntegrate::default_factor()
{
  sph_sim *s = nullptr;
  sph_integrator_info info;
  const bool ok = sph_create(domain->dimension, &s) == SPH_OK &&
                  sph_integrator_info_get(s, integrator, &info) == SPH_OK;
  sph_destroy(s);
  return ok ? info.default_factor : 0.0;
}

/* values per atom of the library's stage buffer (sph_integrator_info_get) */
int FixSPHSolidIntegrate::saved_doubles_per_atom() const
{
  sph_integrator_info info;
  if (sph_integrator_info_get(pair->handle(), integrator, &info) != SPH_OK)
    sphsolid_one(lmp, FLERR, "fix {}: {}", style, sph_errmsg(pair->handle()));
  return (int) info.saved_values;
}

sph_rates FixSPHSolidIntegrate::stage_rates()
{
  sph_rates rates;
  rates.dv_dt = const_cast<double *>(stage_dv());
  rates.drho_dt = const_cast<double *>(pair->drho_dt());
  rates.dS_dt = const_cast<double *>(pair->dS_dt());
  rates.dx_dt = const_cast<double *>(pair->dx_dt());
  return rates;
}

/* ----------------------------------------------------------------------
   stop at once on a non-finite value, naming step, atom and quantity
------------------------------------------------------------------------- */

void FixSPHSolidIntegrate::check_finite()
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
      sphsolid_one(lmp, FLERR, "fix {}: {} of atom {} at step {} ({})", style, quantity,
                   atom->tag[i], update->ntimestep, pair->step_advice(integrator));
  }
}

/* ---------------------------------------------------------------------- */

double FixSPHSolidIntegrate::memory_usage()
{
  return sizeof(double) * (double) (dvbuf.capacity() + other_force.capacity() + stage.capacity()) +
         (double) integrate_motion.capacity();
}
