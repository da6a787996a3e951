/*
 * compute_sphsolid_atom.cpp - per-atom SPH quantities (see the header).
 */
#include "compute_sphsolid_atom.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"
#include "sphsolid_scratch.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "update.h"

#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

ComputeSPHSolidAtom::ComputeSPHSolidAtom(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nmax(0), pair(nullptr), values(nullptr), columns(nullptr)
{
  if (narg != 3)
    error->all(FLERR, "compute {} takes no arguments after the style name, got '{}'", style,
               arg[3]);
  const std::string name = style;
  if (name == "sphsolid/density/atom")
    quantity = DENSITY;
  else if (name == "sphsolid/pressure/atom")
    quantity = PRESSURE;
  else if (name == "sphsolid/vonmises/atom")
    quantity = VON_MISES;
  else
    quantity = STRESS;

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
  for (int i = 0; i < nlocal; i++) {
    if (quantity == STRESS)
      for (int c = 0; c < ncomp; c++) columns[i][c] = 0.0;
    else
      values[i] = 0.0;
  }

  FixSPHSolidState *state = pair->state();
  if (!state) error->all(FLERR, "compute {}: pair sphsolid has no per-atom state yet", style);

  if (quantity == DENSITY) {
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & groupbit) values[i] = state->rho[i];
  } else if (quantity == VON_MISES) {
    for (int i = 0; i < nlocal; i++)
      if (mask[i] & groupbit) values[i] = sph_von_mises(dim, state->S[i]);
  } else {
    derived_field(quantity == PRESSURE ? SPH_FIELD_PRESSURE : SPH_FIELD_STRESS);
  }
}

/* ----------------------------------------------------------------------
   a field the library derives from (rho, S): one scratch handle per
   material, so that particles of different materials never meet there
------------------------------------------------------------------------- */

void ComputeSPHSolidAtom::derived_field(int field)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const int *type = atom->type;
  double **x = atom->x;
  FixSPHSolidState *state = pair->state();

  int nmaterials = 0;
  for (int t = 1; t <= atom->ntypes; t++)
    nmaterials = std::max(nmaterials, pair->material_of_type(t) + 1);

  std::vector<int> atoms;
  std::vector<double> out;
  for (int m = 0; m < nmaterials; m++) {
    atoms.clear();
    for (int i = 0; i < nlocal; i++)
      if ((mask[i] & groupbit) && pair->material_of_type(type[i]) == m) atoms.push_back(i);
    if (atoms.empty()) continue;

    SPHSolidScratch scratch(pair);
    for (int i : atoms) scratch.add(m, x[i], pair->mass_of(i), state->rho[i], state->S[i]);
    sph_status status = scratch.build();
    if (status != SPH_OK)
      error->one(FLERR, "compute {}: {} ({})", style, scratch.message(), sph_status_name(status));
    const int cols = field == SPH_FIELD_STRESS ? ncomp : 1;
    out.resize(scratch.size() * cols);
    status = sph_field_copy(scratch.sim, (sph_field_id) field, out.data());
    if (status != SPH_OK)
      error->one(FLERR, "compute {}: {} ({})", style, sph_errmsg(scratch.sim),
                 sph_status_name(status));
    for (size_t k = 0; k < atoms.size(); k++) {
      const size_t j = scratch.handle_index[k];
      if (field == SPH_FIELD_STRESS)
        for (int c = 0; c < ncomp; c++) columns[atoms[k]][c] = out[j * ncomp + c];
      else
        values[atoms[k]] = out[j];
    }
  }
}

double ComputeSPHSolidAtom::memory_usage()
{
  return (double) nmax * (quantity == STRESS ? ncomp : 1) * sizeof(double);
}
