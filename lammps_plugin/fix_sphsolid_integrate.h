/* -*- c++ -*-
 * fix_sphsolid_integrate.h - the base of the fixes that integrate pair
 * sphsolid's SPH state (fix sphsolid/improved_euler, fix
 * sphsolid/leapfrog), one per library integrator, named after it: what
 * they share.
 *
 * Density and deviatoric stress evolve for every atom of pair sphsolid;
 * the fix group selects the atoms whose position and velocity it
 * integrates.  The others are moved by fix move or stay where they are.
 * Groups of fix sphsolid/force inside it move as rigid bodies under their
 * applied force: their atoms' dv/dt is the body's (pack()).  Without a
 * timestep command the fix sets the library's default step of its
 * integrator when it is defined.  With pair sphsolid's damage effect on,
 * the atoms it moves freely get flaws at init, and the derived fix runs
 * the library's damage stage after each step (an operator split, as the
 * library's own runs do).  With pair sphsolid's energy account on, the
 * derived fix hands it the powers of each rate evaluation and closes its
 * steps.
 */
#ifndef SPHSOLID_FIX_SPHSOLID_INTEGRATE_H
#define SPHSOLID_FIX_SPHSOLID_INTEGRATE_H

#include "fix.h"

#include "sphsolid.h"

#include <vector>

namespace LAMMPS_NS {

class PairSPHSolid;
class FixSPHSolidForce;

class FixSPHSolidIntegrate : public Fix {
 public:
  void init() override;
  void setup(int) override;
  double memory_usage() override;

 protected:
  // `integrator` is the library's name (sph_set_integrator), whose default
  // step the fix takes and whose stages the derived fix calls
  FixSPHSolidIntegrate(class LAMMPS *, int, char **, const char *integrator);
  const char *integrator;
  PairSPHSolid *pair;
  bool timestep_from_library;
  std::vector<double> dvbuf, other_force, stage;
  // where pack() left dv/dt for the stages: pair sphsolid's own rates when
  // f holds nothing else (pair_forces_only), else dvbuf
  bool dv_of_pair = false;
  const double *stage_dv() const;
  // set at setup(): no other style or fix adds to f (pair_forces_only())
  bool forces_of_pair_only = false;
  std::vector<unsigned char> integrate_motion;
  std::vector<FixSPHSolidForce *> rigid;    // fix sphsolid/force bodies
  std::vector<unsigned char> member;        // atoms of one of them
  std::vector<double> masses;
  std::vector<double> inverse_type_mass;    // pack(): 1/m of each atom type

  void init_rigid_bodies();
  // whether f holds exactly m dv/dt of pair sphsolid after the force
  // computation: no other pair, bond, long-range style or force-adding fix
  bool pair_forces_only() const;
  void apply_rigid_bodies();
  // dv/dt of every force into stage_dv (rigid bodies applied), and which
  // atoms the stages integrate (integrate_motion)
  void pack();
  // pair sphsolid's rates of `pass` again at the current state, f set to
  // m dv/dt plus the forces the other fixes (gravity) added to it before
  void evaluate_keeping_other_forces(int pass);
  int saved_doubles_per_atom() const;    // of the library's stages (sph_integrator_info_get)
  double default_factor();               // default step / (h/c0) of the integrator
  sph_rates stage_rates();
  void check_finite();
  // pair sphsolid's energy account on: the powers of the evaluation whose
  // accelerations pack() put into stage_dv (after each pack() of an
  // evaluation the account has not seen); the step is closed with
  // pair->account_step() once its stages are done
  void account_evaluation();
  // effect damage: the flaws of the atoms this fix moves freely (in its
  // group, in no fix sphsolid/force body), none for the others
  void draw_flaws();
  // the atoms this fix moves freely (1), the others 0 (nlocal values)
  const unsigned char *free_atoms();
  std::vector<unsigned char> free_mask;
};

}    // namespace LAMMPS_NS

#endif
