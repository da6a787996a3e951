/*
 * fix_sphsolid_force.cpp - a rigid body under a constant applied force
 * (see the header).
 */
#include "fix_sphsolid_force.h"

#include "sphsolid_args.h"

#include "domain.h"

using namespace LAMMPS_NS;

FixSPHSolidForce::FixSPHSolidForce(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  const int dim = domain->dimension;
  read_dim_vector(lmp, narg - 3, arg + 3, dim, "fix sphsolid/force", "the applied total force's",
                  "components", "fix load piston sphsolid/force 0.0 -86000.0", "", force_applied);
  // the applied force as a global vector (thermo output, fix ave/time)
  vector_flag = 1;
  size_vector = 3;
  extvector = 0;
  global_freq = 1;
}

int FixSPHSolidForce::setmask()
{
  return 0;    // the integrating fix applies it (pack())
}

double FixSPHSolidForce::compute_vector(int i)
{
  return force_applied[i];
}
