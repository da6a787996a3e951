/*
 * sphsolid/rates.h - the low-level rate engine, for codes that own their particles.
 * Part of the public API of libsphsolid: include <sphsolid.h>, which
 * includes every part in order (its conventions hold for all).
 */
#ifndef SPHSOLID_PUBLIC_RATES_H
#define SPHSOLID_PUBLIC_RATES_H

#include "sphsolid/scenes.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------- low-level rate engine */
/*
 * For codes that own their particles and neighbour lists (the LAMMPS
 * plugin): evaluate the rates of particles [0, n_local) of arrays laid out as
 * above, with neighbours drawn from [0, n_total).  Materials, kernel,
 * smoothing length and effects are those of `sim`, which needs no bodies.
 * Neighbours are given either as CSR (offsets, n_local + 1 entries, and
 * indices) or as one pointer and count per particle (lists, counts).
 *
 * Two ways to call it:
 *  - sph_rates_evaluate: one call, a full list (b in list(a) iff a in
 *    list(b) for local a and b; a ghost b is listed in a's row only).  Each
 *    pair of locals is still computed once, except a pair whose indices are
 *    far apart (in chunks of the pair pass at least two apart; a chunk is
 *    n_local/64 rows, at least 256 in 2D and 4096 in 3D): each of its rows
 *    computes it for its own particle, so that no pair terms are stored.
 *  - sph_rates_pairs, then sph_rates_finish: for Newton's third law across
 *    processes (LAMMPS newton_pair on).  sph_rates_pairs takes a half list
 *    (every pair at most once over all rows and all processes; rows sorted
 *    by index and local pairs listed in the row of the smaller index run
 *    fastest) and writes partial sums for all n_total particles, ghosts
 *    included: sph_rates_partial_size(sim) doubles per particle.  The caller
 *    adds each ghost's partial sums to its owner's (a reverse
 *    communication), then sph_rates_finish turns the sums of the n_local
 *    particles into rates.  The partial sums are plain sums over pairs, so
 *    adding them in any order is correct (the order decides the rounding).
 *    Without ghosts shared by processes (one process, or newton_pair off
 *    with each local-ghost pair listed on both sides) the ghost sums are
 *    simply not used.
 *  - sph_rates_pass_half (below): one call, a half list for the local
 *    pairs (each once) in which each pair of a local and a ghost particle
 *    is listed in the local particle's row, and on the ghost's own process
 *    too: the rates of the n_local particles, the ghosts' terms dropped,
 *    no partial sums and no reverse communication.
 * Results do not depend on the number of threads (bitwise).
 */
typedef struct sph_particles {
    size_t n_local;
    size_t n_total;
    const double *x;      /* n_total * stride */
    const double *v;      /* n_total * stride */
    const double *rho;    /* n_total */
    const double *S;      /* n_total * ncomp */
    const double *mass;   /* n_total */
    const int *material;  /* n_total */
    size_t stride;        /* doubles from one particle's x (and v) to the
                               next's: 0 means dim; e.g. 3 for LAMMPS's
                               arrays in 2D */
    const double *damage; /* n_total: D of each particle when effect damage
                             is on (ghosts too), else ignored */
} sph_particles;

/* Neighbours of each local particle a (row a): indices[offsets[a] ..
 * offsets[a + 1]) or lists[a][0 .. counts[a]).  Rows in ascending order
 * without repeats are the fastest: the pair pass then gathers runs of
 * consecutive neighbours at once (each call tests the rows). */
typedef struct sph_neighbours {
    const size_t *offsets;
    const int *indices;
    const int *const *lists;
    const int *counts;
} sph_neighbours;

typedef struct sph_rates {
    double *dv_dt;   /* n_local * dim (gravity and damping included) */
    double *drho_dt; /* n_local */
    double *dS_dt;   /* n_local * ncomp */
    double *dx_dt;   /* n_local * dim, XSPH-corrected velocity, or NULL */
} sph_rates;

SPH_API sph_status sph_rates_evaluate(sph_sim *sim, const sph_particles *particles,
                                      const sph_neighbours *neighbours, sph_rates *rates);

/* Doubles per particle of the partial sums of sph_rates_pairs (depends on
 * the dimension and on kernel_correction and xsph being on). */
SPH_API size_t sph_rates_partial_size(const sph_sim *sim);
/* The pair pass over a half list: partial[n_total * sph_rates_partial_size]
 * is overwritten with the sums of every particle, local and ghost. */
SPH_API sph_status sph_rates_pairs(sph_sim *sim, const sph_particles *particles,
                                   const sph_neighbours *half_list, double *partial);
/* Rates of the n_local particles from their complete partial sums (ghost
 * contributions already added): the corrected velocity gradient, the
 * Jaumann stress rate, gravity, damping and the XSPH velocity. */
SPH_API sph_status sph_rates_finish(sph_sim *sim, const sph_particles *particles,
                                    const double *partial, sph_rates *rates);

/* The rates in two passes over the pairs, for integrators that need them
 * at different states (the leapfrog: density and stress rates at the half
 * step, accelerations at the whole step).  The continuity pass computes
 * drho/dt, dS/dt (velocity gradient, with the kernel-correction matrix when
 * that effect is on) and the XSPH velocity; the momentum pass dv/dt
 * (stress, artificial viscosity and stress, gravity, damping).  A pass
 * writes only its own rate arrays (the others may be NULL) and its partial
 * sums hold only what it computes: sph_rates_pass_size(sim, pass) doubles
 * per particle, which is what a reverse communication needs to send.  The
 * rates of the two passes at one state equal those of SPH_RATES_ALL
 * bitwise. */
typedef enum sph_rate_pass {
    SPH_RATES_CONTINUITY = 1,
    SPH_RATES_MOMENTUM = 2,
    SPH_RATES_ALL = 3
} sph_rate_pass;
SPH_API size_t sph_rates_pass_size(const sph_sim *sim, int pass);
SPH_API sph_status sph_rates_pass_pairs(sph_sim *sim, int pass, const sph_particles *particles,
                                        const sph_neighbours *half_list, double *partial);
SPH_API sph_status sph_rates_pass_finish(sph_sim *sim, int pass, const sph_particles *particles,
                                         const double *partial, sph_rates *rates);
/* One pass (or SPH_RATES_ALL) over a half list, finished: each pair of
 * local particles listed once (best in the row of the smaller index), each
 * pair of a local particle a and a ghost listed in a's row; a's rates get
 * the pair's terms, the ghost's are dropped (its own process lists the
 * pair too).  The rates equal those of sph_rates_pass_pairs +
 * sph_rates_pass_finish when the ghosts' sums reach their owners (to
 * round-off: the order of the sums differs). */
SPH_API sph_status sph_rates_pass_half(sph_sim *sim, int pass, const sph_particles *particles,
                                       const sph_neighbours *half_list, sph_rates *rates);

/* Improved Euler stages on external arrays of n particles (dim, ncomp
 * from sim).  Stage 1 (predict): saves y_n into `saved` (v, rho, S:
 * dim + 1 + ncomp doubles per particle) and sets y* = y_n + dt f(y_n).
 * Stage 2 (correct): y_{n+1} = (y_n + y*)/2 + dt/2 f(y*), with
 * x_{n+1} = x* + dt/2 (v* - v_n).  `integrate_motion[i]` is 0 for
 * particles whose velocity is prescribed: their velocity is left alone
 * while their position still advances by dt v and their density and stress
 * evolve (pass NULL to integrate all). */
SPH_API sph_status sph_improved_euler_predict(sph_sim *sim, size_t n, double dt, double *x,
                                              double *v, double *rho, double *S,
                                              const sph_rates *rates,
                                              const unsigned char *integrate_motion, double *saved);
SPH_API sph_status sph_improved_euler_correct(sph_sim *sim, size_t n, double dt, double *x,
                                              double *v, double *rho, double *S,
                                              const sph_rates *rates,
                                              const unsigned char *integrate_motion,
                                              const double *saved);

/* Rigid translation under an applied force (SPH_MOTION_FORCE), split for
 * distributed particles.  sph_rigid_force_sum() adds the contributions of
 * the members among n particles to `sums` (dim + 1 doubles, zeroed by the
 * caller: the total mass, then the sum of m dv/dt); add the sums of all
 * ranks together.  sph_rigid_force_apply() then gives every member the
 * common acceleration (applied + sum m dv/dt) / total mass, with `applied`
 * the external force on the whole body (dim entries).  `member` (n
 * entries, non-zero for members) may be NULL: all n are members. */
SPH_API sph_status sph_rigid_force_sum(sph_sim *sim, size_t n, const double *mass,
                                       const double *dv_dt, const unsigned char *member,
                                       double *sums);
SPH_API sph_status sph_rigid_force_apply(sph_sim *sim, size_t n, const double *applied,
                                         const double *sums, const unsigned char *member,
                                         double *dv_dt);

/* The same stages for a code that moves some particles itself (the LAMMPS
 * plugin: fix move), on its own position and velocity arrays, `stride`
 * doubles apart (>= dim; 3 for LAMMPS's x and v in 2D).  Particles with
 * integrate_motion[i] == 0 keep their x and v untouched; their density
 * and stress evolve.  The corrector also applies the watchdog
 * (sph_set_watchdog) to the integrated particles, `material` giving each
 * particle's material: on SPH_ERR_UNSTABLE or SPH_ERR_NONFINITE,
 * *particle is the first particle concerned (else -1). */
SPH_API sph_status sph_improved_euler_predict_strided(sph_sim *sim, size_t n, double dt, double *x,
                                                      double *v, size_t stride, double *rho,
                                                      double *S, const sph_rates *rates,
                                                      const unsigned char *integrate_motion,
                                                      double *saved);
SPH_API sph_status sph_improved_euler_correct_strided(sph_sim *sim, size_t n, double dt, double *x,
                                                      double *v, size_t stride, double *rho,
                                                      double *S, const sph_rates *rates,
                                                      const unsigned char *integrate_motion,
                                                      const int *material, const double *saved,
                                                      long *particle);

/* Deprecated aliases of the 0.2 series, removed in release 0.3.0:
 * the Improved Euler stages were named after Heun's method before the
 * registry's name "improved_euler" was used throughout.  Each calls the
 * function named in its warning with the same arguments. */
SPH_API sph_status sph_heun_predict(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                    double *rho, double *S, const sph_rates *rates,
                                    const unsigned char *integrate_motion, double *saved)
    SPH_DEPRECATED("sph_improved_euler_predict");
SPH_API sph_status sph_heun_correct(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                    double *rho, double *S, const sph_rates *rates,
                                    const unsigned char *integrate_motion, const double *saved)
    SPH_DEPRECATED("sph_improved_euler_correct");
SPH_API sph_status sph_heun_predict_strided(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                            size_t stride, double *rho, double *S,
                                            const sph_rates *rates,
                                            const unsigned char *integrate_motion, double *saved)
    SPH_DEPRECATED("sph_improved_euler_predict_strided");
SPH_API sph_status sph_heun_correct_strided(
    sph_sim *sim, size_t n, double dt, double *x, double *v, size_t stride, double *rho, double *S,
    const sph_rates *rates, const unsigned char *integrate_motion, const int *material,
    const double *saved, long *particle) SPH_DEPRECATED("sph_improved_euler_correct_strided");

/* The leapfrog (sph_set_integrator "leapfrog") in three stages on external
 * arrays, `stride` doubles apart (>= dim), for a code that owns its
 * particles (the LAMMPS plugin: fix sphsolid/leapfrog).  Per step:
 *   1. sph_leapfrog_begin_strided() with the rates at the start (a_n: dv/dt
 *      with the forces of the rigid bodies applied; drho/dt, dS/dt of the
 *      previous step's half step, or of the start on a first step): saves
 *      x_n, rho_n, S_n in `saved` (dim + 1 + ncomp doubles per particle,
 *      sph_integrator_info_get's saved_values), kicks the integrated
 *      velocities by dt/2 dv/dt, moves every position by dt/2 v and
 *      predicts rho and S at the half step;
 *   2. evaluate the density and stress rates there (the continuity pass,
 *      sph_rates_pass_pairs/pass_finish; keep them for the next step's
 *      stage 1), then
 *      sph_leapfrog_drift_strided(): x = x_n + dt v (or the XSPH velocity)
 *      for the integrated particles, x = x_n for the others (their mover
 *      moves them on), rho = rho_n + dt drho/dt, S = S_n + dt dS/dt, with
 *      the watchdog's density bounds;
 *   3. evaluate the acceleration at the new state (the momentum pass), then
 *      sph_leapfrog_end_strided():
 *      v += dt/2 dv/dt for the integrated particles, and the watchdog.
 * On SPH_ERR_NONFINITE or SPH_ERR_UNSTABLE *particle is the first particle
 * concerned (else -1). */
SPH_API sph_status sph_leapfrog_begin_strided(sph_sim *sim, size_t n, double dt, double *x,
                                              double *v, size_t stride, double *rho, double *S,
                                              const sph_rates *rates,
                                              const unsigned char *integrate_motion, double *saved);
SPH_API sph_status sph_leapfrog_drift_strided(sph_sim *sim, size_t n, double dt, double *x,
                                              const double *v, size_t stride, double *rho,
                                              double *S, const sph_rates *rates,
                                              const unsigned char *integrate_motion,
                                              const double *saved, const int *material,
                                              long *particle);
SPH_API sph_status sph_leapfrog_end_strided(sph_sim *sim, size_t n, double dt, double *v,
                                            size_t stride, const double *rho, const double *dv_dt,
                                            const unsigned char *integrate_motion,
                                            const int *material, long *particle);

/* Derived fields of external particles (n of them, material indices of
 * sim): pressure P (n), full Cauchy stress sigma = -P I + S (n * ncomp) and
 * von Mises stress (n).  Any output may be NULL. */
SPH_API sph_status sph_derived_fields(sph_sim *sim, size_t n, const double *rho, const double *S,
                                      const int *material, double *pressure, double *stress,
                                      double *von_mises);

/* Elastic energy of each of n external particles [J; J per metre of depth
 * in 2D]: m (u_vol(rho) + S:S / (4 mu rho)), the per-particle terms that
 * sph_energy() sums (`energy`: n doubles). */
SPH_API sph_status sph_energy_fields(sph_sim *sim, size_t n, const double *mass, const double *rho,
                                     const double *S, const int *material, double *energy);

/* The energy account (sph_set_energy_account) on a caller's particles, a
 * code that owns them (the LAMMPS plugin: pair_style sphsolid
 * energy_account yes, compute sphsolid/energy), from the terms the
 * handle's own account uses; the caller integrates and sums (over its
 * processes too):
 *  - sph_energy_power: the powers of one rate evaluation of the n_local
 *    particles [W; W/m in 2D].  power[0], the work rate of everything but
 *    the SPH forces among the particles: sum m (a - dv_sph) . v, with
 *    dv_sph the evaluation's SPH accelerations (sph_rates dv_dt, n_local
 *    * dim) and a the acceleration the integrator gives the particle:
 *    dv_dt (n_local * dim: a rigid body's common acceleration, gravity
 *    added, ...) where integrate_motion[a] is non-zero (NULL: all), 0
 *    where the caller prescribes the motion (it overrides the SPH force,
 *    doing -m dv_sph . v: constant speeds and rotations).  power[1], with
 *    effect artificial_viscosity on (else 0), the heat rate
 *    sum m_a m_b Pi_ab v_ab . grad_a W_ab over the pairs of the
 *    neighbours' rows (each pair listed once, ghosts included, positions
 *    as given); a pair with a ghost (index >= n_local) counts half if
 *    shared_ghost_pairs is non-zero (its other process lists it too).
 *    Uses particles->x, v, rho, mass, material and stride.  Integrated
 *    with the integrator's weights, the step's mean power times dt (the
 *    trapezoid of Improved Euler's two evaluations), these are the
 *    account's work and dissipated_viscosity.
 *  - sph_energy_sums: adds sum m v^2 / 2 to energy[0] and the elastic
 *    energy to energy[1] (damaged by damage[a] if damage is non-NULL, as
 *    sph_energy() reports it with effect damage on) of the n particles
 *    whose member[a] is non-zero (NULL: all); v `stride` doubles apart (0:
 *    dim).
 *  - sph_energy_released: adds to *released the elastic energy a stage
 *    took from n particles: sum m (u(rho, S_before, D_before) - u(rho, S,
 *    D)), u the damaged energy per mass; the damage stage (S unchanged:
 *    the account's dissipated_damage) or the drucker_prager return (D
 *    unchanged: dissipated_plastic).  damage_before and damage: both n
 *    values, or both NULL (undamaged). */
SPH_API sph_status sph_energy_power(sph_sim *sim, const sph_particles *particles,
                                    const sph_neighbours *neighbours, int shared_ghost_pairs,
                                    const double *dv_sph, const double *dv_dt,
                                    const unsigned char *integrate_motion, double *power);
SPH_API sph_status sph_energy_sums(sph_sim *sim, size_t n, const double *mass, const double *v,
                                   size_t stride, const double *rho, const double *S,
                                   const double *damage, const int *material,
                                   const unsigned char *member, double *energy);
SPH_API sph_status sph_energy_released(sph_sim *sim, size_t n, const double *mass,
                                       const int *material, const double *rho,
                                       const double *S_before, const double *damage_before,
                                       const double *S, const double *damage, double *released);

/* Effect damage on n external particles (a code that owns its particles:
 * the LAMMPS plugin), with the handle's seed, flaws parameter, materials
 * and smoothing length.  A particle's flaws are drawn from (seed, id[a],
 * flaw index): id is its global index, the one the handle's own particles
 * use (0, 1, ... in the order they were added), so a code that numbers
 * its particles from 1 passes number - 1 to get the same flaws, on any
 * number of processes.  mass[a] / rho0 is its volume at rest.
 *  - sph_damage_flaws: the number of flaws of each particle and its
 *    weakest activation strain (0 and inf where flawed[a] is 0, as the
 *    handle's prescribed bodies, or the material has no flaws; flawed may
 *    be NULL: all may be damaged);
 *  - sph_damage_grow: the damage stage after a step of dt: activation by
 *    each particle's largest principal strain at (rho, S), growth of
 *    damage[a] (D in [0, 1]); *changed is 1 if any D grew (rates
 *    evaluated before are stale then);
 *  - sph_damage_active: the flaws active at the current state (n doubles).
 * SPH_ERR_STATE while the effect is off. */
/* Effect drucker_prager on n external particles: the return of each
 * deviator S (n * ncomp, changed in place) onto the cone at its pressure
 * (rho) and damage (damage: n values, required while effect damage is on,
 * else ignored); member[a] = 0 skips particle a (prescribed bodies; NULL:
 * all).  *changed is 1 if a deviator was scaled. */
SPH_API sph_status sph_drucker_prager_return(sph_sim *sim, size_t n, const int *material,
                                             const double *rho, const double *damage,
                                             const unsigned char *member, double *S, int *changed);
SPH_API sph_status sph_damage_flaws(sph_sim *sim, size_t n, const uint64_t *id, const double *mass,
                                    const int *material, const unsigned char *flawed,
                                    int *flaw_count, double *flaw_strain);
SPH_API sph_status sph_damage_grow(sph_sim *sim, size_t n, double dt, const uint64_t *id,
                                   const double *mass, const int *material, const double *rho,
                                   const double *S, const int *flaw_count,
                                   const double *flaw_strain, double *damage, int *changed);
SPH_API sph_status sph_damage_active(sph_sim *sim, size_t n, const uint64_t *id, const double *mass,
                                     const int *material, const double *rho, const double *S,
                                     const int *flaw_count, const double *flaw_strain,
                                     double *active);

/* Effect damage: fragments of caller-owned particles, one round of a
 * labelling that a code spread over processes repeats until no process
 * reports a change.  Particles whose member[a] is non-zero (the handle's
 * free bodies) and whose particles->damage is below 1 are joined when
 * closer than the kernel support (the rule of SPH_FIELD_FRAGMENT), over the
 * neighbours of the n_local particles (CSR or lists, ghosts included, each
 * joined pair listed at least once).  label (n_total, in/out): each
 * joinable particle gets the least label of its region as far as this
 * call sees it, the others -1; *changed is 1 if a local label changed.
 * With labels starting at a global number (the LAMMPS plugin: the atom
 * ID) and the ghosts' labels brought up to date before each round, the
 * fixed point gives each fragment the least number of its particles.
 * Positions are used as given (ghosts already at their image). */
SPH_API sph_status sph_damage_fragment_labels(sph_sim *sim, const sph_particles *particles,
                                              const sph_neighbours *neighbours,
                                              const unsigned char *member, double *label,
                                              int *changed);

/* Probe interpolation split for distributed particles: add the
 * contributions of particles [0, n_local) to `sums`
 * (SPH_PROBE_VALUES(dim) + 1 doubles, zeroed by the caller; add the sums of
 * all ranks together), then turn the total into values with
 * sph_probe_finish().  Gives the same values as sph_probe_sample(). */
SPH_API sph_status sph_probe_accumulate(sph_sim *sim, const sph_particles *particles,
                                        const double *point, double *sums);
SPH_API sph_status sph_probe_finish(sph_sim *sim, const double *sums, double *values);

#ifdef __cplusplus
}
#endif

#endif /* SPHSOLID_PUBLIC_RATES_H */
