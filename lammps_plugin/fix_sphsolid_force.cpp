/*
 * fix_sphsolid_force.cpp - a rigid body under a constant applied force
 * (see the header).
 */
#include "fix_sphsolid_force.h"

#include "domain.h"
#include "error.h"

using namespace LAMMPS_NS;

FixSPHSolidForce::FixSPHSolidForce(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const int dim = domain->dimension;
  if (narg != 3 + dim)
    error->all(FLERR,
               "fix sphsolid/force needs the applied total force's {} components, e.g. "
               "'fix load piston sphsolid/force 0.0 -86000.0{}'; got {} values",
               dim, dim == 3 ? " 0.0" : "", narg - 3);
  force_applied[0] = force_applied[1] = force_applied[2] = 0.0;
  // utils::numeric refuses nan and out-of-range numbers, naming them
  for (int d = 0; d < dim; d++) force_applied[d] = utils::numeric(FLERR, arg[3 + d], false, lmp);
  // the applied force as a global vector (thermo output, fix ave/time)
  vector_flag = 1;
  size_vector = 3;
  extvector = 0;
  global_freq = 1;
}

int FixSPHSolidForce::setmask()
{
  return 0;    // fix sphsolid/heun applies it
}

double FixSPHSolidForce::compute_vector(int i)
{
  return force_applied[i];
}
