/* -*- c++ -*-
 * fix_sphsolid_force.h - fix sphsolid/force: a rigid body driven by a
 * constant applied force (the library's SPH_MOTION_FORCE).
 *
 *   fix ID group sphsolid/force Fx Fy [Fz]
 *
 * The group moves as one rigid translation: every atom gets the common
 * acceleration (F + sum of the forces on the group's atoms) / (group mass),
 * with F the total applied force (force units; per unit depth in 2D, as
 * the masses are).  A uniform pressure p on a face of width w is F = p w.
 * The integrating fix (sphsolid/improved_euler, sphsolid/leapfrog) applies
 * it to its dv/dt at each rate evaluation of a step (the library's
 * sph_rigid_force_sum/_apply, sums added over the ranks), so the group must
 * be part of the integrating fix's group.  This fix
 * does nothing on its own.
 */
#ifdef FIX_CLASS
// clang-format off
FixStyle(sphsolid/force,FixSPHSolidForce);
// clang-format on
#else

#ifndef SPHSOLID_FIX_SPHSOLID_FORCE_H
#define SPHSOLID_FIX_SPHSOLID_FORCE_H

#include "fix.h"

namespace LAMMPS_NS {

class FixSPHSolidForce : public Fix {
 public:
  FixSPHSolidForce(class LAMMPS *, int, char **);
  int setmask() override;
  double compute_vector(int) override;

  // the applied total force, 3 components (z is 0 in 2D)
  const double *applied() const { return force_applied; }

 private:
  double force_applied[3];
};

}    // namespace LAMMPS_NS

#endif
#endif
