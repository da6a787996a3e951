/*
 * compute_sphsolid_probe.cpp - SPH values at a point (see the header).
 */
#include "compute_sphsolid_probe.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"
#include "sphsolid_args.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "sphsolid_error.h"
#include "force.h"
#include "update.h"

#include <cstring>
#include <vector>

using namespace LAMMPS_NS;

ComputeSPHSolidProbe::ComputeSPHSolidProbe(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), pair(nullptr)
{
  dim = domain->dimension;
  ncomp = SPH_STRESS_COMPONENTS(dim);
  // optional trailing 'outside error|nan' (the behaviour outside every body)
  outside_nan = false;
  if (narg == 5 + dim && strcmp(arg[3 + dim], "outside") == 0) {
    if (strcmp(arg[4 + dim], "nan") == 0)
      outside_nan = true;
    else if (strcmp(arg[4 + dim], "error") != 0)
      error->all(FLERR, "compute sphsolid/probe: outside must be 'error' or 'nan', got '{}'",
                 arg[4 + dim]);
    narg -= 2;
  }
  read_dim_vector(lmp, narg - 3, arg + 3, dim, "compute sphsolid/probe", "the point's",
                  "coordinates in m", "compute A all sphsolid/probe 0.0 0.07",
                  " [outside error|nan]", point);

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

  // owned atoms of the group within the kernel support of the point, at
  // their nearest image of it, packed in the library's layout
  const double reach = pair->kernel_support() * (1.0 + 1.0e-9);
  const int nlocal = atom->nlocal;
  double **x = atom->x;
  const int *mask = atom->mask;
  const int *type = atom->type;
  positions.clear();
  rho.clear();
  S.clear();
  mass.clear();
  material.clear();
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double delta[3] = {x[i][0] - point[0], x[i][1] - point[1], x[i][2] - point[2]};
    if (dim == 2) delta[2] = 0.0;
    // minimum_image changes only components beyond half a periodic box;
    // the inline check spares the call (and its file-name string) per atom
    if (domain->minimum_image_check(delta[0], delta[1], delta[2]))
      domain->minimum_image(FLERR, delta);
    double r2 = 0.0;
    for (int d = 0; d < dim; d++) r2 += delta[d] * delta[d];
    if (r2 > reach * reach) continue;
    for (int d = 0; d < dim; d++) positions.push_back(point[d] + delta[d]);
    rho.push_back(state->rho[i]);
    S.insert(S.end(), state->S[i], state->S[i] + ncomp);
    mass.push_back(pair->mass_of(i));
    material.push_back(pair->material_of_type(type[i]));
  }

  // this rank's kernel-weighted sums, summed over the ranks, normalised
  sph_particles particles{};    // fields not set below stay zero
  particles.n_local = particles.n_total = rho.size();
  particles.x = positions.data();
  particles.v = nullptr;
  particles.rho = rho.data();
  particles.S = S.data();
  particles.mass = mass.data();
  particles.material = material.data();
  particles.stride = 0;    // positions packed dim per atom above
  std::vector<double> sums(SPH_PROBE_VALUES(dim) + 1, 0.0), total(sums.size(), 0.0);
  sph_status status = sph_probe_accumulate(pair->handle(), &particles, point, sums.data());
  if (status != SPH_OK)
    sphsolid_one(lmp, FLERR, "compute sphsolid/probe {} at step {}: {} ({})", id, update->ntimestep,
                 sph_errmsg(pair->handle()), sph_status_name(status));
  MPI_Allreduce(sums.data(), total.data(), (int) sums.size(), MPI_DOUBLE, MPI_SUM, world);
  status = sph_probe_finish(pair->handle(), total.data(), vector);
  // outside every body: an error by default (the library's behaviour), or
  // NaN values when asked with 'outside nan'
  if (status == SPH_ERR_DOMAIN && outside_nan) status = SPH_OK;
  if (status != SPH_OK)
    error->all(FLERR, "compute sphsolid/probe {} at step {}: {} ({})", id, update->ntimestep,
               sph_errmsg(pair->handle()), sph_status_name(status));
}
