/* -*- c++ -*-
 * compute_sphsolid_probe.h - compute sphsolid/probe: SPH values at a point.
 *
 *   compute ID group sphsolid/probe x y [z]
 *
 * A global vector of SPH_PROBE_VALUES(dim) values at the fixed point
 * (x, y[, z]): von Mises stress, pressure, then the full Cauchy stress
 * (xx yy zz xy, or xx yy zz xy xz yz), each a Shepard-normalised kernel
 * interpolation over the atoms of the group: each rank adds up its owned
 * atoms within the kernel support of the point (the library's
 * sph_probe_accumulate()), the sums are added over the ranks
 * (MPI_Allreduce) and the library normalises them (sph_probe_finish()).
 * The values depend on the number of ranks only through the order of
 * that sum (round-off).
 */
#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(sphsolid/probe,ComputeSPHSolidProbe);
// clang-format on
#else

#ifndef SPHSOLID_COMPUTE_SPHSOLID_PROBE_H
#define SPHSOLID_COMPUTE_SPHSOLID_PROBE_H

#include "compute.h"

#include <vector>

namespace LAMMPS_NS {

class PairSPHSolid;

class ComputeSPHSolidProbe : public Compute {
 public:
  ComputeSPHSolidProbe(class LAMMPS *, int, char **);
  ~ComputeSPHSolidProbe() override;
  void init() override;
  void compute_vector() override;

 private:
  int dim, ncomp;
  double point[3];
  bool outside_nan;    // 'outside nan': NaN instead of an error outside every body
  PairSPHSolid *pair;
  // the owned atoms near the point, in the library's layout
  std::vector<double> positions, rho, S, mass;
  std::vector<int> material;
};

}    // namespace LAMMPS_NS

#endif
#endif
