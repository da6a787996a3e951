/* -*- c++ -*-
 * compute_sphsolid_atom.h - per-atom SPH quantities of pair sphsolid.
 *
 * One class behind five styles, each a per-atom vector or array:
 *   sphsolid/density/atom   density rho [kg/m^3]
 *   sphsolid/pressure/atom  pressure P from the library's equation of state [Pa]
 *   sphsolid/vonmises/atom  von Mises stress sqrt(3/2 S:S) [Pa]
 *   sphsolid/stress/atom    full Cauchy stress sigma = -P I + S, columns
 *                           xx yy zz xy (2D) or xx yy zz xy xz yz (3D) [Pa]
 *   sphsolid/energy/atom    elastic energy m (u_vol(rho) + S:S/(4 mu rho)) [J]
 *   sphsolid/atom NAME      any of the above by name (density, pressure,
 *                           vonmises, stress, energy) or a quantity of the
 *                           damage effect: damage (D), flaws (number of
 *                           flaws), flaw_strain (weakest activation strain),
 *                           active_flaws (flaws active at the current state)
 * Pressure, stress and von Mises come from the library's
 * sph_derived_fields(), the energy from sph_energy_fields(), the active
 * flaws from sph_damage_active(), on the state arrays in place.
 */
#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(sphsolid/density/atom,ComputeSPHSolidAtom);
ComputeStyle(sphsolid/pressure/atom,ComputeSPHSolidAtom);
ComputeStyle(sphsolid/vonmises/atom,ComputeSPHSolidAtom);
ComputeStyle(sphsolid/stress/atom,ComputeSPHSolidAtom);
ComputeStyle(sphsolid/energy/atom,ComputeSPHSolidAtom);
ComputeStyle(sphsolid/atom,ComputeSPHSolidAtom);
// clang-format on
#else

#ifndef SPHSOLID_COMPUTE_SPHSOLID_ATOM_H
#define SPHSOLID_COMPUTE_SPHSOLID_ATOM_H

#include "compute.h"

#include <vector>

namespace LAMMPS_NS {

class PairSPHSolid;

class ComputeSPHSolidAtom : public Compute {
 public:
  ComputeSPHSolidAtom(class LAMMPS *, int, char **);
  ~ComputeSPHSolidAtom() override;
  void init() override;
  void compute_peratom() override;
  double memory_usage() override;

 private:
  enum Quantity {
    DENSITY,
    PRESSURE,
    VON_MISES,
    STRESS,
    ENERGY,
    DAMAGE,
    FLAWS,
    FLAW_STRAIN,
    ACTIVE_FLAWS
  };
  bool is_damage() const { return quantity >= DAMAGE; }
  Quantity quantity;
  int dim, ncomp, nmax;
  PairSPHSolid *pair;
  double *values;               // per-atom vector
  double **columns;             // per-atom array (stress)
  std::vector<int> material;    // library material of each owned atom
  std::vector<double> mass;     // mass of each owned atom (energy)
};

}    // namespace LAMMPS_NS

#endif
#endif
