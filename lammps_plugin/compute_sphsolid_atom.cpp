/*
 * compute_sphsolid_atom.cpp - per-atom SPH quantities (see the header).
 */
#include "compute_sphsolid_atom.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "update.h"

#include <cstring>
#include <string>
#include <utility>
#include <vector>

using namespace LAMMPS_NS;

ComputeSPHSolidAtom::ComputeSPHSolidAtom(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nmax(0), pair(nullptr), values(nullptr), columns(nullptr)
{
  // sphsolid/<quantity>/atom, or sphsolid/atom <quantity>
  const std::string name = style;
  const bool by_name = name == "sphsolid/atom";
  if (by_name && narg != 4)
    error->all(FLERR,
               "compute sphsolid/atom takes one quantity: density, pressure, vonmises, stress, "
               "energy, damage, flaws, flaw_strain or active_flaws");
  if (!by_name && narg != 3)
    error->all(FLERR, "compute {} takes no arguments after the style name, got '{}'", style,
               arg[3]);
  const std::string what = by_name ? std::string(arg[3]) : name.substr(9, name.size() - 14);
  const std::pair<const char *, Quantity> names[] = {
      {"density", DENSITY}, {"pressure", PRESSURE},       {"vonmises", VON_MISES},
      {"stress", STRESS},   {"energy", ENERGY},           {"damage", DAMAGE},
      {"flaws", FLAWS},     {"flaw_strain", FLAW_STRAIN}, {"active_flaws", ACTIVE_FLAWS}};
  bool found = false;
  for (const auto &n : names)
    if (what == n.first) quantity = n.second, found = true;
  if (!found)
    error->all(FLERR,
               "compute sphsolid/atom: unknown quantity '{}' (known: density pressure vonmises "
               "stress energy damage flaws flaw_strain active_flaws)",
               what);

  dim = domain->dimension;
  ncomp = SPH_STRESS_COMPONENTS(dim);
  peratom_flag = 1;
  size_peratom_cols = quantity == STRESS ? ncomp : 0;
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
      error->one(FLERR, "compute {}: {} ({})", style, sph_errmsg(pair->handle()),
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
    error->one(FLERR, "compute {}: {} ({})", style, sph_errmsg(pair->handle()),
               sph_status_name(status));
  for (int i = 0; i < nlocal; i++) {
    if (mask[i] & groupbit) continue;
    if (quantity == STRESS)
      for (int c = 0; c < ncomp; c++) columns[i][c] = 0.0;
    else
      values[i] = 0.0;
  }
}

/* ---------------------------------------------------------------------- */

double ComputeSPHSolidAtom::memory_usage()
{
  return (double) nmax * (quantity == STRESS ? ncomp : 1) * sizeof(double) +
         (double) material.capacity() * sizeof(int) + (double) mass.capacity() * sizeof(double);
}
