/* -*- c++ -*-
 * compute_sphsolid_energy.h - compute sphsolid/energy: the energy account
 * of pair sphsolid.
 *
 *   compute ID all sphsolid/energy
 *
 * A global vector of 7 energies [J; J per metre of depth in 2D], summed
 * over the MPI ranks: 1 kinetic, 2 elastic (of the damaged stress with
 * effect damage on), 3 work done on the atoms by everything but the SPH
 * forces among them (fix move's prescribed motions, fix sphsolid/force,
 * other fixes' forces on the integrated atoms), 4 dissipated by damage,
 * 5 by the drucker_prager return, 6 by artificial viscosity, and 7 the
 * imbalance: 1 + 2 + 4 + 5 + 6 - 3 less the kinetic plus elastic energy
 * when the account started (0 up to the discretisation's error in a run
 * without the damping effect).  Kinetic and elastic energy come from the
 * library's sph_energy_sums() on each rank's owned atoms; 3-6 are pair
 * sphsolid's account (pair_style keyword energy_account yes), which the
 * integrator fix keeps with the library's sph_energy_power() and
 * sph_energy_released().
 */
#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(sphsolid/energy,ComputeSPHSolidEnergy);
// clang-format on
#else

#ifndef SPHSOLID_COMPUTE_SPHSOLID_ENERGY_H
#define SPHSOLID_COMPUTE_SPHSOLID_ENERGY_H

#include "compute.h"

namespace LAMMPS_NS {

class PairSPHSolid;

class ComputeSPHSolidEnergy : public Compute {
 public:
  enum {
    KINETIC,
    ELASTIC,
    WORK,
    DISSIPATED_DAMAGE,
    DISSIPATED_PLASTIC,
    DISSIPATED_VISCOSITY,
    IMBALANCE,
    N_VALUES
  };
  ComputeSPHSolidEnergy(class LAMMPS *, int, char **);
  ~ComputeSPHSolidEnergy() override;
  void init() override;
  void compute_vector() override;

 private:
  PairSPHSolid *pair;
};

}    // namespace LAMMPS_NS

#endif
#endif
