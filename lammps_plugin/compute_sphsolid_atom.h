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
 *                           active_flaws (flaws active at the current state),
 *                           fragment (the least atom ID of the atom's
 *                           fragment: connected atoms of the group with
 *                           D < 1, as the library's fragment field; -1)
 * Pressure, stress and von Mises come from the library's
 * sph_derived_fields(), the energy from sph_energy_fields(), the active
 * flaws from sph_damage_active(), the fragments from rounds of
 * sph_damage_fragment_labels() over an occasional full neighbour list,
 * with the labels of ghost atoms brought up to date between rounds, until
 * no rank changes one.
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
  void init_list(int, class NeighList *) override;
  void compute_peratom() override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
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
    ACTIVE_FLAWS,
    FRAGMENT
  };
  bool is_damage() const { return quantity >= DAMAGE; }
  Quantity quantity;
  int dim, ncomp, nmax;
  PairSPHSolid *pair;
  double *values;                       // per-atom vector
  double **columns;                     // per-atom array (stress)
  std::vector<int> material;            // library material of each owned atom
  std::vector<double> mass;             // mass of each owned atom (energy)
  class NeighList *list;                // full list (fragment)
  std::vector<double> label;            // fragment labels of owned and ghost atoms
  std::vector<unsigned char> member;    // atoms of the group (fragment)
  void fragments();
};

}    // namespace LAMMPS_NS

#endif
#endif
