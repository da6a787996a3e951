/* -*- c++ -*-
 * fix_sphsolid_state.h - internal fix SPHSOLID/STATE: the per-atom SPH state.
 *
 * Plugins cannot add atom styles, so the state the library needs beyond
 * positions, velocities and masses lives here, created by pair sphsolid
 * (fix ID SPHSOLID_STATE):
 *   rho    density [kg/m^3]
 *   S      deviatoric stress, (xx,yy,zz,xy) in 2D, (xx,yy,zz,xy,xz,yz) in 3D [Pa]
 *   saved  the Improved Euler stage-1 copy of (v, rho, S[, XSPH velocity])
 *          made by sph_improved_euler_predict_strided() and read by
 *          sph_improved_euler_correct_strided(), one
 *          row per atom so that it migrates with the atom inside a step
 *   damage, flaw_count, flaw_strain
 *          the state of the library's damage effect, only while pair
 *          sphsolid has it on (set_damage): damage D, the number of flaws
 *          and the weakest activation strain (sph_damage_flaws)
 *   account
 *          the energy account of pair sphsolid (pair_style keyword
 *          energy_account): this rank's shares of the work and the
 *          dissipated energies since it started, and the energy then
 *          (global values, written to restart files summed over the ranks)
 * Each array is contiguous (rows of one atom), so the library reads and
 * writes it in place.  The values move with their atoms between MPI ranks,
 * rho and S (optionally with x and v, and D with damage on) are sent to
 * ghost atoms, and rho, S, the leapfrog's rates and the damage state are
 * written to and read from restart files.
 */
#ifdef FIX_CLASS
// clang-format off
FixStyle(SPHSOLID/STATE,FixSPHSolidState);
// clang-format on
#else

#ifndef SPHSOLID_FIX_SPHSOLID_STATE_H
#define SPHSOLID_FIX_SPHSOLID_STATE_H

#include "fix.h"

namespace LAMMPS_NS {

class FixSPHSolidState : public Fix {
 public:
  FixSPHSolidState(class LAMMPS *, int, char **);
  ~FixSPHSolidState() override;
  int setmask() override { return 0; }

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  double memory_usage() override;

  int dimension() const { return dim; }
  int saved_columns() const { return nsaved; }
  double *S_data() { return S ? S[0] : nullptr; }
  double *carried_S_data() { return carried_S ? carried_S[0] : nullptr; }
  double *saved_data() { return saved ? saved[0] : nullptr; }

  /* Damage state on (arrays allocated: D = 0 and no flaws drawn for atoms
   * without a restart's values) or off (arrays freed). */
  void set_damage(bool on);
  bool damage_on() const { return damage != nullptr; }

  double *rho;       // per atom
  double **S;        // per atom x ncomp
  double **saved;    // per atom x nsaved
  /* The leapfrog's density and stress rates of the last half step, which
   * predict the next half step: they travel with their atom and are
   * written to restart files.  NaN: none yet (a new atom, a restart file
   * without them). */
  double *carried_rho;    // per atom
  double **carried_S;     // per atom x ncomp
  /* effect damage (nullptr while off): D, flaw count, weakest activation
   * strain; the flaws are drawn from the atom ID (pair sphsolid) */
  double *damage;         // per atom
  int *flaw_count;        // per atom
  double *flaw_strain;    // per atom

  /* The energy account of pair sphsolid (energy_account yes): this rank's
   * shares of the totals since the account started (their sum over the
   * ranks is the account; compute sphsolid/energy adds them up) and the
   * kinetic plus elastic energy of all atoms when it started (the same on
   * every rank).  Written to restart files (summed; read back on rank 0)
   * so that a restarted run continues its account. */
  enum { WORK, DISSIPATED_DAMAGE, DISSIPATED_PLASTIC, DISSIPATED_VISCOSITY, N_ACCOUNT };
  double account[N_ACCOUNT];
  double account_reference;
  bool account_started;
  void reset_account();

  /* Forward communication sends rho and S; with forward_motion also the
   * positions and velocities (as comm->forward_comm() would), so that the
   * second rate evaluation of a step needs one ghost exchange, not two.
   * Without forward_stress S stays behind (the continuity pass does not
   * read the ghosts' stress). */
  bool forward_motion, forward_stress;

 private:
  int dim, ncomp, nsaved;
  int nmax_arrays;
  void set_comm_sizes();
};

}    // namespace LAMMPS_NS

#endif
#endif
