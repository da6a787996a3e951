/* -*- c++ -*-
 * sphsolid_scratch.h - a throw-away library handle holding given particles.
 *
 * Quantities the library derives from the state (pressure, full Cauchy
 * stress, probe values) are asked of the library through a scratch handle
 * that holds copies of the LAMMPS atoms concerned, so the plugin carries
 * no second copy of the equation of state or of the probe interpolation.
 * One body per material; the first body's spacing dx fixes h.
 */
#ifndef SPHSOLID_SCRATCH_H
#define SPHSOLID_SCRATCH_H

#include "sphsolid.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class PairSPHSolid;

class SPHSolidScratch {
 public:
  explicit SPHSolidScratch(PairSPHSolid *pair);
  ~SPHSolidScratch();
  SPHSolidScratch(const SPHSolidScratch &) = delete;
  SPHSolidScratch &operator=(const SPHSolidScratch &) = delete;

  /* One particle: position (dim values), mass, density, deviatoric stress. */
  void add(int material, const double *x, double mass, double rho, const double *S);
  size_t size() const { return material.size(); }

  /* Create the bodies and set the state.  On failure returns the status
   * and leaves the library's message in message(). */
  sph_status build();
  const std::string &message() const { return error_message; }

  sph_sim *sim;
  /* handle_index[k] is the library's index of the k-th particle added */
  std::vector<size_t> handle_index;

 private:
  int dim, ncomp;
  double spacing;
  std::vector<int> material;
  std::vector<double> x, mass, rho, S;
  std::string error_message;
};

}    // namespace LAMMPS_NS

#endif
