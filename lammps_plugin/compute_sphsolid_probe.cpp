/*
 * compute_sphsolid_probe.cpp - SPH values at a point (see the header).
 */
#include "compute_sphsolid_probe.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"
#include "sphsolid_scratch.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "update.h"

#include <algorithm>
#include <numeric>
#include <vector>

using namespace LAMMPS_NS;

ComputeSPHSolidProbe::ComputeSPHSolidProbe(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), pair(nullptr)
{
  dim = domain->dimension;
  ncomp = SPH_STRESS_COMPONENTS(dim);
  if (narg != 3 + dim)
    error->all(FLERR, "compute sphsolid/probe needs the point's {} coordinates in m, e.g. "
                      "'compute A all sphsolid/probe 0.0 0.07{}'; got {} values",
               dim, dim == 3 ? " 0.0" : "", narg - 3);
  point[0] = point[1] = point[2] = 0.0;
  for (int d = 0; d < dim; d++) point[d] = utils::numeric(FLERR, arg[3 + d], false, lmp);

  vector_flag = 1;
  size_vector = SPH_PROBE_VALUES(dim);
  extvector = 0;
  vector = new double[size_vector];
  for (int k = 0; k < size_vector; k++) vector[k] = 0.0;
}

ComputeSPHSolidProbe::~ComputeSPHSolidProbe()
{
  delete[] vector;
}

void ComputeSPHSolidProbe::init()
{
  pair = dynamic_cast<PairSPHSolid *>(force->pair_match("sphsolid", 1));
  if (!pair) error->all(FLERR, "compute sphsolid/probe needs 'pair_style sphsolid'");
}

/* ---------------------------------------------------------------------- */

void ComputeSPHSolidProbe::compute_vector()
{
  invoked_vector = update->ntimestep;
  FixSPHSolidState *state = pair->state();
  if (!state) error->all(FLERR, "compute sphsolid/probe: pair sphsolid has no per-atom state yet");

  // owned atoms of the group within the kernel support of the point, as
  // records: tag, material, mass, rho, position (nearest image), S
  const int record = 4 + dim + ncomp;
  const double reach = pair->kernel_support() * (1.0 + 1.0e-9);
  const int nlocal = atom->nlocal;
  double **x = atom->x;
  const int *mask = atom->mask;
  std::vector<double> mine;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double delta[3] = {x[i][0] - point[0], x[i][1] - point[1], x[i][2] - point[2]};
    if (dim == 2) delta[2] = 0.0;
    domain->minimum_image(FLERR, delta);
    double r2 = 0.0;
    for (int d = 0; d < dim; d++) r2 += delta[d] * delta[d];
    if (r2 > reach * reach) continue;
    mine.push_back((double) atom->tag[i]);
    mine.push_back((double) pair->material_of_type(atom->type[i]));
    mine.push_back(pair->mass_of(i));
    mine.push_back(state->rho[i]);
    for (int d = 0; d < dim; d++) mine.push_back(point[d] + delta[d]);
    for (int c = 0; c < ncomp; c++) mine.push_back(state->S[i][c]);
  }

  const int nprocs = comm->nprocs;
  int count = (int) mine.size();
  std::vector<int> counts(nprocs), displs(nprocs);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  int total = 0;
  for (int p = 0; p < nprocs; p++) {
    displs[p] = total;
    total += counts[p];
  }
  std::vector<double> all(std::max(total, 1));
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(),
                 MPI_DOUBLE, world);

  const int n = total / record;
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return all[(size_t) a * record] < all[(size_t) b * record]; });

  SPHSolidScratch scratch(pair);
  for (int k : order) {
    const double *r = &all[(size_t) k * record];
    scratch.add((int) r[1], r + 4, r[2], r[3], r + 4 + dim);
  }
  sph_status status = scratch.build();
  int probe = 0;
  if (status == SPH_OK) status = sph_add_probe(scratch.sim, id, point, &probe);
  if (status == SPH_OK) status = sph_probe_sample(scratch.sim, probe, vector);
  if (status != SPH_OK)
    error->all(FLERR, "compute sphsolid/probe {} at ({}, {}, {}) at step {}: {} ({})", id,
               point[0], point[1], point[2], update->ntimestep,
               scratch.message().empty() ? sph_errmsg(scratch.sim) : scratch.message(),
               sph_status_name(status));
}
