/*
 * compute_sphsolid_atom.cpp - per-atom SPH quantities (see the header).
 */
#include "compute_sphsolid_atom.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "sphsolid_error.h"
#include "force.h"
#include "memory.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <cstring>
#include <string>
#include <utility>
#include <vector>

using namespace LAMMPS_NS;

ComputeSPHSolidAtom::ComputeSPHSolidAtom(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nmax(0), pair(nullptr), values(nullptr), columns(nullptr),
    list(nullptr)
{
  // sphsolid/<quantity>/atom, or sphsolid/atom <quantity>
  const std::string name = style;
  const bool by_name = name == "sphsolid/atom";
  if (by_name && narg != 4)
    error->all(FLERR,
               "compute sphsolid/atom takes one quantity: density, pressure, vonmises, stress, "
               "energy, damage, flaws, flaw_strain, active_flaws or fragment");
  if (!by_name && narg != 3)
    error->all(FLERR, "compute {} takes no arguments after the style name, got '{}'", style,
               arg[3]);
  const std::string what = by_name ? std::string(arg[3]) : name.substr(9, name.size() - 14);
  const std::pair<const char *, Quantity> names[] = {
      {"density", DENSITY},  {"pressure", PRESSURE},       {"vonmises", VON_MISES},
      {"stress", STRESS},    {"energy", ENERGY},           {"damage", DAMAGE},
      {"flaws", FLAWS},      {"flaw_strain", FLAW_STRAIN}, {"active_flaws", ACTIVE_FLAWS},
      {"fragment", FRAGMENT}};
  bool found = false;
  for (const auto &n : names)
    if (what == n.first) quantity = n.second, found = true;
  if (!found)
    error->all(FLERR,
               "compute sphsolid/atom: unknown quantity '{}' (known: density pressure vonmises "
               "stress energy damage flaws flaw_strain active_flaws fragment)",
               what);

  dim = domain->dimension;
  ncomp = SPH_STRESS_COMPONENTS(dim);
  peratom_flag = 1;
  size_peratom_cols = quantity == STRESS ? ncomp : 0;
  comm_forward = quantity == FRAGMENT ? 1 : 0;    // the ghosts' labels
}

ComputeSPHSolidAtom::~ComputeSPHSolidAtom()
{
  memory->destroy(values);
  memory->destroy(columns);
}

void ComputeSPHSolidAtom::init()
{
  pair = dynamic_cast<PairSPHSolid *>(force->pair_match("sphsolid", 1));
  if (!pair) error->all(FLERR, "compute {} needs 'pair_style sphsolid'", style);
  if (is_damage() && !pair->damage_on())
    error->all(FLERR,
               "compute {} {}: the damage quantities exist while pair sphsolid's damage effect "
               "is on (pair_style sphsolid ... damage seed S)",
               id, style);
  // fragments: neighbours within the pair cutoff, ghosts included, each
  // owned atom's row complete (a full list, built when asked for)
  if (quantity == FRAGMENT)
    neighbor->add_request(this, NeighConst::REQ_FULL | NeighConst::REQ_OCCASIONAL);
}

void ComputeSPHSolidAtom::init_list(int /*id*/, NeighList *ptr)
{
  list = ptr;
}

/* ---------------------------------------------------------------------- */

void ComputeSPHSolidAtom::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    if (quantity == STRESS) {
      memory->destroy(columns);
      memory->create(columns, nmax, ncomp, "sphsolid/stress/atom:columns");
      array_atom = columns;
    } else {
      memory->destroy(values);
      memory->create(values, nmax, "sphsolid/atom:values");
      vector_atom = values;
    }
  }

  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  if (quantity == DENSITY)
    for (int i = 0; i < nlocal; i++) values[i] = 0.0;

  FixSPHSolidState *state = pair->state();
  if (!state) error->all(FLERR, "compute {}: pair sphsolid has no per-atom state yet", style);

  if (quantity == DENSITY) {
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & groupbit) values[i] = state->rho[i];
    return;
  }
  if (is_damage()) {
    if (!state->damage_on())
      error->all(FLERR, "compute {}: pair sphsolid has no damage state", style);
    if (quantity == FRAGMENT) {
      fragments();
      return;
    }
    if (quantity == ACTIVE_FLAWS) pair->active_flaws(values);
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & groupbit))
        values[i] = 0.0;
      else if (quantity == DAMAGE)
        values[i] = state->damage[i];
      else if (quantity == FLAWS)
        values[i] = state->flaw_count[i];
      else if (quantity == FLAW_STRAIN)
        values[i] = state->flaw_strain[i];
    }
    return;
  }

  // pressure, Cauchy stress, von Mises or elastic energy of every owned
  // atom from the library, in place; atoms outside the group are zeroed
  // afterwards
  if ((int) material.size() < nmax) material.resize(nmax);
  const int *type = atom->type;
  for (int i = 0; i < nlocal; i++) material[i] = pair->material_of_type(type[i]);
  if (quantity == ENERGY) {
    if ((int) mass.size() < nmax) mass.resize(nmax);
    for (int i = 0; i < nlocal; i++) mass[i] = atom->rmass ? atom->rmass[i] : atom->mass[type[i]];
    const sph_status status = sph_energy_fields(pair->handle(), nlocal, mass.data(), state->rho,
                                                state->S_data(), material.data(), values);
    if (status != SPH_OK)
      sphsolid_one(lmp, FLERR, "compute {}: {} ({})", style, sph_errmsg(pair->handle()),
                   sph_status_name(status));
    for (int i = 0; i < nlocal; i++)
      if (!(mask[i] & groupbit)) values[i] = 0.0;
    return;
  }
  const sph_status status =
      sph_derived_fields(pair->handle(), nlocal, state->rho, state->S_data(), material.data(),
                         quantity == PRESSURE ? values : nullptr,
                         quantity == STRESS && nlocal > 0 ? columns[0] : nullptr,
                         quantity == VON_MISES ? values : nullptr);
  if (status != SPH_OK)
    sphsolid_one(lmp, FLERR, "compute {}: {} ({})", style, sph_errmsg(pair->handle()),
                 sph_status_name(status));
  for (int i = 0; i < nlocal; i++) {
    if (mask[i] & groupbit) continue;
    if (quantity == STRESS)
      for (int c = 0; c < ncomp; c++) columns[i][c] = 0.0;
    else
      values[i] = 0.0;
  }
}

/* ----------------------------------------------------------------------
   fragments: every atom of the group starts with its ID as label; rounds
   of the library's labelling over this rank's owned and ghost atoms, the
   ghosts' labels sent from their owners before each round, until no rank
   changes a label.  Each fragment then carries the least ID of its atoms,
   on any number of ranks.
------------------------------------------------------------------------- */

void ComputeSPHSolidAtom::fragments()
{
  FixSPHSolidState *state = pair->state();
  comm->forward_comm(state);    // the ghosts' D (with their density and stress)
  neighbor->build_one(list);
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  label.resize(std::max(nall, 1));
  member.resize(std::max(nall, 1));
  const int *mask = atom->mask;
  const tagint *tag = atom->tag;
  for (int i = 0; i < nall; i++) {
    member[i] = (mask[i] & groupbit) ? 1 : 0;
    label[i] = (double) tag[i];
  }
  sph_particles particles{};
  particles.n_local = nlocal;
  particles.n_total = nall;
  particles.x = nall > 0 ? atom->x[0] : nullptr;
  particles.stride = 3;
  particles.damage = state->damage;
  sph_neighbours neighbours{};
  neighbours.lists = list->firstneigh;
  neighbours.counts = list->numneigh;
  for (int round = 0;; round++) {
    comm->forward_comm(this);
    int changed = 0, any = 0;
    const sph_status status = sph_damage_fragment_labels(pair->handle(), &particles, &neighbours,
                                                         member.data(), label.data(), &changed);
    if (status != SPH_OK)
      sphsolid_one(lmp, FLERR, "compute {}: fragments: {} ({})", style, sph_errmsg(pair->handle()),
                   sph_status_name(status));
    MPI_Allreduce(&changed, &any, 1, MPI_INT, MPI_MAX, world);
    if (!any) break;
    if (round > atom->natoms)
      error->all(FLERR, "compute {}: fragment labels did not settle in {} rounds", style, round);
  }
  for (int i = 0; i < nlocal; i++) values[i] = member[i] ? label[i] : 0.0;
}

int ComputeSPHSolidAtom::pack_forward_comm(int n, int *list_, double *buf, int /*pbc_flag*/,
                                           int * /*pbc*/)
{
  for (int k = 0; k < n; k++) buf[k] = label[list_[k]];
  return n;
}

void ComputeSPHSolidAtom::unpack_forward_comm(int n, int first, double *buf)
{
  for (int k = 0; k < n; k++) label[first + k] = buf[k];
}

/* ---------------------------------------------------------------------- */

double ComputeSPHSolidAtom::memory_usage()
{
  return (double) nmax * (quantity == STRESS ? ncomp : 1) * sizeof(double) +
         (double) material.capacity() * sizeof(int) +
         (double) (mass.capacity() + label.capacity()) * sizeof(double) +
         (double) member.capacity();
}
