/* -*- c++ -*-
 * pair_sphsolid.h - pair style sphsolid: the SPH elastic solid of libsphsolid.
 *
 * A translation layer: LAMMPS's atoms, ghost atoms and half neighbour list
 * go in, the library's pair pass and finish compute every rate, and the
 * accelerations come back as forces (f = m dv/dt).  The density and deviatoric stress
 * rates are kept for the integrator (fix sphsolid/improved_euler or sphsolid/leapfrog).  Materials come
 * from pair_coeff per atom type; effects (artificial viscosity, artificial
 * stress, XSPH, damping) are pair_style keywords, off by default.
 */
#ifdef PAIR_CLASS
// clang-format off
PairStyle(sphsolid,PairSPHSolid);
// clang-format on
#else

#ifndef SPHSOLID_PAIR_SPHSOLID_H
#define SPHSOLID_PAIR_SPHSOLID_H

#include "atom.h"
#include "pair.h"

#include "sphsolid.h"

#include <ctime>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace LAMMPS_NS {

class FixSPHSolidState;

/* One material as given to pair_coeff: the pair of constants that defines
 * it (K and mu, E and nu, or K and nu), the reference density and the keys
 * of the library's material registry (sph_material_key_get: the flaw and
 * strength constants of the damage effect, ...) given, by name; a key not
 * given keeps the library's default. */
struct SPHSolidMaterial {
  std::string kind;    // "K_mu", "E_nu" or "K_nu"
  double first = 0.0, second = 0.0, rho0 = 0.0;
  std::map<std::string, double> keys;    // registry key -> value given
  bool operator==(const SPHSolidMaterial &o) const
  {
    return kind == o.kind && first == o.first && second == o.second && rho0 == o.rho0 &&
           keys == o.keys;
  }
};

class PairSPHSolid : public Pair {
 public:
  PairSPHSolid(class LAMMPS *);
  ~PairSPHSolid() override;

  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  double memory_usage() override;
  /* Per atom type (dim 1): "rho0" and every key of the library's material
   * registry, the value its pair_coeff gave or the library's default (for
   * lammps.extract_pair, the tests' check that a key reaches the pair). */
  void *extract(const char *, int &) override;
  void finish() override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;

  /* Rates of the owned atoms at the current state of owned and ghost atoms.
   * Density and deviatoric stress are sent to the ghosts here; with
   * with_motion their positions and velocities too (in the same message),
   * otherwise those must be current already (Verlet's forward comm).
   * drho_into and dS_into, if given, take the density and stress rates of
   * the owned atoms (nlocal and nlocal x ncomp doubles) in place of the
   * pair's own arrays, which then keep the rates of an earlier call. */
  void evaluate_rates(bool with_motion = false, int pass = SPH_RATES_ALL,
                      double *drho_into = nullptr, double *dS_into = nullptr);
  /* The rates compute() evaluates (SPH_RATES_ALL; the leapfrog, which
   * takes the density and stress rates at the half step, asks for
   * SPH_RATES_MOMENTUM). */
  void set_compute_pass(int pass) { compute_pass = pass; }

  /* A new library handle configured from pair_style and pair_coeff:
   * kernel, smoothing ratio, spacing dx (sph_set_spacing: the handle holds
   * no bodies), effects (if with_effects) and one material per distinct
   * pair_coeff (material index = material_of_type()).  The caller owns the
   * handle.  On a library error this raises a LAMMPS error naming the
   * problem. */
  sph_sim *build_handle(bool with_effects);

  sph_sim *handle() const { return sim; }
  FixSPHSolidState *state() const { return state_fix; }
  int dimension() const { return dim; }
  int stress_components() const { return SPH_STRESS_COMPONENTS(dim); }
  int material_of_type(int type) const { return type_material[type]; }
  /* library material of every owned and ghost atom, as of the last
   * evaluate_rates() (atoms are not reordered between evaluations) */
  const int *atom_materials() const { return materialbuf.data(); }
  double particle_spacing() const { return spacing; }
  double kernel_support() const { return support; }
  // the mass of each atom (per atom or per type) with LAMMPS's arrays read
  // once: for loops whose stores the compiler cannot tell from atom->...
  struct AtomMasses {
    const double *rmass, *type_mass;
    const int *type;
    double operator[](int i) const { return rmass ? rmass[i] : type_mass[type[i]]; }
  };
  AtomMasses atom_masses() const { return {atom->rmass, atom->mass, atom->type}; }
  double mass_of(int i) const { return atom_masses()[i]; }
  /* Library default time step of `integrator` (0.5 h / c0 for
   * improved_euler, h / c0 for leapfrog) for the current coefficients, or 0
   * if some atom type has no material yet. */
  double default_timestep(const char *integrator = "improved_euler");
  /* "timestep T s, stable step S s" of `integrator` (default: that of the
   * deck's sphsolid integrator fix): appended to reports of a run that
   * went unstable. */
  std::string step_advice(const char *integrator = nullptr);
  /* sph_stable_dt of `integrator` for the current coefficients, or 0 if
   * some atom type has no material yet. */
  double stable_timestep(const char *integrator);
  /* The library integrator of the deck's sphsolid integrator fix. */
  const char *integrator_name();

  // rates of the owned atoms from the last evaluate_rates()
  const double *dv_dt() const { return rate_dv.data(); }
  const double *drho_dt() const { return rate_drho.data(); }
  const double *dS_dt() const { return rate_dS.data(); }
  const double *dx_dt() const { return xsph ? rate_dx.data() : nullptr; }
  int rates_count() const { return nrates; }    // owned atoms at the last evaluation

  /* Effect damage (pair_style keyword damage): whether it is on, and the
   * library calls on the owned atoms' state (fix SPHSOLID/STATE), each
   * atom's flaws keyed by its ID (tag - 1, the index the library's own
   * particles use).  draw_flaws: the flaws of every owned atom, none for
   * atoms whose flawed[i] is 0 (those the integrator does not move freely:
   * platens, rigid bodies).  grow_damage: the stages after a step of dt,
   * the damage stage and, with effect drucker_prager, the return of the
   * deviators of the atoms whose free_atoms[i] is 1 (those the integrator
   * moves freely) onto the cone (sph_drucker_prager_return); with
   * any_rank, true on every rank if D grew or a deviator was returned on
   * any (a collective), else whether that happened on this rank.
   * active_flaws: the flaws active at the current state (nlocal values
   * into out). */
  bool damage_on() const { return damage; }
  /* The energy account (pair_style keyword energy_account yes; the
   * library's sph_set_energy_account for the atoms of LAMMPS), kept in
   * the state fix (account[]: this rank's shares).  account_start: at the
   * integrator's set-up, a collective; the first time the account runs
   * (after pair_style), the kinetic plus elastic energy of all atoms
   * becomes its starting energy.  account_evaluation: the powers of the
   * last rate evaluation (sph_energy_power), given the accelerations the
   * integrator gives the owned atoms (dv_dt: the integrator fix's, after
   * its rigid bodies) and which atoms it integrates; account_step: the
   * step of dt closed, its mean power times dt added to the work and the
   * viscous heat.  account_carry: for an integrator whose step starts
   * from the rates its last step ended with (leapfrog), the powers of
   * that evaluation open the step (its trapezoid, as the library's
   * leapfrog integrates its own account); false if there are none (a
   * run's first step), the caller then evaluates them; true, adding
   * nothing, if the step has its start already (an evaluation made after
   * the last step closed: damage grew).  grow_damage adds the energy its
   * stages release (sph_energy_released).  energy_sums: kinetic and
   * elastic energy of this rank's owned atoms (sph_energy_sums) into
   * out[0], out[1]. */
  bool energy_account_on() const { return account; }
  void account_start();
  void account_evaluation(const double *dv_dt, const unsigned char *integrate_motion);
  void account_step(double dt);
  bool account_carry();
  void energy_sums(double out[2]);
  bool drucker_prager_on() const { return drucker_prager; }
  void draw_flaws(const unsigned char *flawed);
  bool grow_damage(double dt, bool any_rank, const unsigned char *free_atoms);
  void active_flaws(double *out);
  /* CPU seconds of this process (cpu_seconds(): all its threads) in each
   * part of the plugin's work during a run's loop (from reset_seconds(),
   * which the integrator fix calls at the end of the set-up), for the
   * end-of-run line of finish(): the library's rate calls, the integrator
   * fix's library stages, the ghost exchanges of evaluate_rates() (and,
   * newton on, the sums sent back), and the refresh of masses, materials
   * and the neighbour rows after a re-neighbouring, and the plugin's own
   * copies between LAMMPS's arrays and the library's (f += m dv/dt,
   * dv/dt = f/m, the other fixes' forces kept around an evaluation, the
   * stage buffers and carried rates).  What the loop holds beyond these is
   * LAMMPS's own work.  CPU time, not wall time: on a shared machine it is
   * what the parts cost, whatever else runs. */
  enum Part { PART_RATES, PART_STAGES, PART_EXCHANGE, PART_REFRESH, PART_COPIES, N_PARTS };
  void add_seconds(Part part, double seconds) { part_seconds[part] += seconds; }
  void reset_seconds()
  {
    for (double &t : part_seconds) t = 0.0;
  }
  static double cpu_seconds()
  {
    timespec now;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return (double) now.tv_sec + 1e-9 * (double) now.tv_nsec;
  }

 private:
  void check_deck();
  /* Stops every rank, naming the first keyword whose value differs between
   * ranks (pair_style, pair_coeff, timestep): a hash of each is reduced
   * over the communicator (min and max). */
  void check_ranks_agree();
  /* step_of (sph_default_dt, sph_stable_dt) of a handle without bodies with
   * `integrator`; 0 before every type has its pair_coeff */
  double handle_timestep(const char *integrator, double (*step_of)(const sph_sim *));
  int dim;
  double spacing;        // nominal particle spacing dx [m]
  double h_over_dx;      // smoothing length / spacing
  double support;        // kernel support radius [m] (sph_support_radius)
  std::string kernel;    // kernel name; empty: the library's default
  bool xsph;             // XSPH effect on: the rates carry dx/dt
  bool damage;           // damage effect on: the state fix keeps D and the flaws
  std::vector<std::pair<std::string, std::string>> effects;    // name, "key=value ..."
  std::vector<SPHSolidMaterial> type_params;                   // per atom type (index 0 unused)
  std::vector<int> type_material;                              // library material per atom type
  std::map<std::string, std::vector<double>> extracted;        // extract()'s arrays
  // drucker_prager effect on: the deviators are returned after a step
  bool drucker_prager;
  // energy_account yes: the account runs (account_start ...); the powers
  // of the current step's evaluations and their count; account_reset: the
  // account starts again at the next init (pair_style given again)
  bool account, account_reset;
  double power_sum[2];
  int power_evaluations;
  // the powers of the last evaluation, and whether there is one this run
  double power_last[2];
  bool power_last_valid;
  std::vector<double> damage_before, stress_before;

  sph_sim *sim;    // configured in init_style()
  FixSPHSolidState *state_fix;

  // per-atom data that changes only when LAMMPS re-neighbours (atoms
  // migrate or are sorted then): masses, materials and the neighbour
  // pointers are rebuilt when the neighbour list was rebuilt
  bigint cached_build;    // neighbor->ncalls at the last rebuild of the cache
  int cached_nall;

  // scratch sized to atom->nmax
  int nmax_scratch;
  int nrates;
  std::vector<double> massbuf;
  std::vector<int> materialbuf;
  std::vector<size_t> neighbour_offsets;    // CSR rows of the owned atoms
  std::vector<int> neighbour_indices, neighbour_counts;
  std::vector<double> rate_dv, rate_drho, rate_dS, rate_dx;
  bool send_back;                 // newton_pair on: pairs with ghosts once, ghost sums sent back
  int partial_size;               // doubles per atom of the pair sums (all rates)
  int pass_size;                  // of the pass being evaluated (reverse comm)
  std::vector<double> partial;    // pair sums of owned and ghost atoms (newton on)
  int compute_pass;               // the rates compute() evaluates
  bigint pairs_computed;          // pairs in this rank's rows (the last list)
  bigint ghost_pairs;             // of them, pairs with a ghost atom

  double part_seconds[N_PARTS];    // add_seconds(), since reset_seconds()

  void allocate();
  void grow_scratch();
  void convert_list();
  bool computes_pair_with_ghost(int i, int j) const;
  void fail(sph_sim *, sph_status, const std::string &what, bool destroy);
  void initialise_state();
  // the owned atoms' IDs (tag - 1), masses and materials for the damage calls
  void damage_inputs();
  std::vector<uint64_t> idbuf;
  std::vector<double> localmass;
  std::vector<int> localmaterial;
};

}    // namespace LAMMPS_NS

#endif
#endif
