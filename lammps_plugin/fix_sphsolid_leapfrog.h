/* -*- c++ -*-
 * fix_sphsolid_leapfrog.h - fix sphsolid/leapfrog: the library's leapfrog
 * (kick-drift-kick, velocity Verlet) for the SPH elastic solid, with density
 * and deviatoric stress advanced by the half-step velocity.
 *
 * Used like fix nve, in place of fix sphsolid/improved_euler.  Per step n -> n+1 in
 * Verlet's order:
 *   initial_integrate  v += dt/2 a_n (the atoms of the group), every
 *                      position by dt/2 v, rho and S predicted at the half
 *                      step with the last half step's rates
 *                      (sph_leapfrog_begin_strided); the density and stress
 *                      rates there (the library's continuity pass, ghosts
 *                      updated in one exchange, only its sums sent back);
 *                      then x = x_n + dt v for the group (the other atoms
 *                      back at x_n, for fix move or nve/noforce to move), rho
 *                      and S to n+1 (sph_leapfrog_drift_strided)
 *   Verlet's force     a_{n+1} (pair sphsolid's momentum pass only, plus fix
 *                      gravity etc.)
 *   final_integrate    v += dt/2 a_{n+1} and the library's watchdog
 *                      (sph_leapfrog_end_strided)
 * so velocities are at whole steps after each step, as with fix nve, and
 * run, thermo, restart and fix move work as usual.  Groups of fix
 * sphsolid/force inside the group kick as rigid bodies.  The half step's
 * density and stress rates travel with the atoms and are written to
 * restart files (fix SPHSOLID/STATE).  A restart (or a new run command)
 * re-evaluates the acceleration at the whole-step velocity, where an
 * unbroken run has it at the half-step velocity: the continued run agrees
 * with the unbroken one exactly without velocity-dependent forces
 * (artificial viscosity, damping), and to the scheme's truncation error
 * with them.
 */
#ifdef FIX_CLASS
// clang-format off
FixStyle(sphsolid/leapfrog,FixSPHSolidLeapfrog);
// clang-format on
#else

#ifndef SPHSOLID_FIX_SPHSOLID_LEAPFROG_H
#define SPHSOLID_FIX_SPHSOLID_LEAPFROG_H

#include "fix_sphsolid_integrate.h"

namespace LAMMPS_NS {

class FixSPHSolidLeapfrog : public FixSPHSolidIntegrate {
 public:
  FixSPHSolidLeapfrog(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void initial_integrate(int) override;
  void final_integrate() override;

 private:
  void fail(sph_status, long atom, const char *stage);
  void keep_rates(bool only_missing);
};

}    // namespace LAMMPS_NS

#endif
#endif
