/*
 * sphsolid/integrators.h - time steps, integrators and runs.
 * Part of the public API of libsphsolid: include <sphsolid.h>, which
 * includes every part in order (its conventions hold for all).
 */
#ifndef SPHSOLID_PUBLIC_INTEGRATORS_H
#define SPHSOLID_PUBLIC_INTEGRATORS_H

#include "sphsolid/effects.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------ time steps */

/* Time integrators, selected by name (default "improved_euler"):
 *   "improved_euler"  Heun, two rate evaluations per step; the paper's
 *                     scheme; wave problems need artificial viscosity
 *   "leapfrog"        kick-drift-kick (velocity Verlet) with density and
 *                     stress advanced by the half-step velocity: symplectic,
 *                     stable without viscosity, one evaluation's pair work
 *                     per step (continuity pass at the half step, momentum
 *                     pass at the end) at a step up to 1.75 times Improved
 *                     Euler's limit
 * The stable and default steps below are the integrator's.  Selecting an
 * integrator keeps a step set with sph_set_dt() if it is within the new
 * integrator's stability limit, else fails (SPH_ERR_STATE). */
SPH_API sph_status sph_set_integrator(sph_sim *sim, const char *name);
/* Name of the handle's integrator (static storage). */
SPH_API const char *sph_integrator_name(const sph_sim *sim);
/* Space-separated list of known integrator names (static storage). */
SPH_API const char *sph_integrator_names(void);

typedef struct sph_integrator_info {
    const char *name;        /* static storage */
    const char *description; /* one line, static storage */
    int evaluations;         /* rate evaluations per step */
    double stable_factor;    /* stable step = stable_factor h / max(c_p + |v|) */
    double default_factor;   /* default step = default_factor h / max(c0),
                                  capped at the stable step */
    size_t saved_values;     /* doubles per particle of the `saved` buffer of
                                  its low-level stages, for this handle's
                                  dimension and effects */
    int carries_rates;       /* 1: the rates at the end of a step start the
                                  next (kept across runs and in checkpoints) */
} sph_integrator_info;

/* Describe integrator `name` (NULL: the handle's). */
SPH_API sph_status sph_integrator_info_get(sph_sim *sim, const char *name,
                                           sph_integrator_info *info);

/* Largest stable step of the handle's integrator,
 * stable_factor h / max(c_p + |v|) over the particles (over the
 * materials for a handle without particles; 0 while h is unknown). */
SPH_API double sph_stable_dt(const sph_sim *sim);
/* Default step default_factor h / max(c0) (bodies' materials, or all
 * materials of a handle without bodies), capped at sph_stable_dt(): for
 * Improved Euler 0.5 h/c0, the paper's 0.261 us at dx = 1 mm. */
SPH_API double sph_default_dt(const sph_sim *sim);
/* Set the step.  A step above sph_stable_dt() is refused unless
 * `allow_unstable` is non-zero. */
SPH_API sph_status sph_set_dt(sph_sim *sim, double dt, int allow_unstable);
SPH_API double sph_dt(const sph_sim *sim);
SPH_API double sph_time(const sph_sim *sim);
/* Set the clock (time [s] and step count), e.g. when the state was advanced
 * by another engine and is copied back into this handle. */
SPH_API sph_status sph_set_time(sph_sim *sim, double t, long step);
SPH_API long sph_step_count(const sph_sim *sim);

/* Called every `interval` steps during sph_run*() (and after the last);
 * a non-zero return stops the run with SPH_ERR_STOPPED after a
 * completed step. */
typedef int (*sph_progress_fn)(const sph_sim *sim, void *user);
SPH_API sph_status sph_set_progress(sph_sim *sim, long interval, sph_progress_fn fn, void *user);

/* Advance by n steps of the handle's integrator. */
SPH_API sph_status sph_run(sph_sim *sim, long steps);
/* Advance until time t (the last step is shortened to land on t). */
SPH_API sph_status sph_run_until(sph_sim *sim, double t);
/* How sph_run_until(sim, t) gets there from the current time with the
 * current step dt: *whole steps of dt, then, if *last > 0, one shortened
 * step of *last seconds that lands exactly on t. */
SPH_API sph_status sph_steps_until(sph_sim *sim, double t, long *whole, double *last);

/* The watchdog stops a run (SPH_ERR_UNSTABLE) when a particle of a free
 * body moves faster than `max_speed_over_cp` times its material's P-wave
 * speed, or its density leaves [min_density_ratio, max_density_ratio] times
 * rho0.  Defaults 1, 0.5, 2: a solid beyond them is no longer described by
 * the linear model.  A zero switches that check off. */
SPH_API sph_status sph_set_watchdog(sph_sim *sim, double max_speed_over_cp,
                                    double min_density_ratio, double max_density_ratio);

/* The watchdog's test on external arrays (n particles, material indices of
 * sim; integrate_motion as for sph_improved_euler_correct, NULL for all): returns
 * SPH_ERR_UNSTABLE, with *particle the lowest offending index and a message
 * naming speed or density ratio, or SPH_OK (*particle = -1). */
SPH_API sph_status sph_watchdog_check(sph_sim *sim, size_t n, const double *v, const double *rho,
                                      const int *material, const unsigned char *integrate_motion,
                                      long *particle);

/* A step that goes non-finite or trips the watchdog is undone: the state is
 * left as it was at the start of that step (the last good state), and is
 * written as a snapshot if an output file is open.
 *
 * Where a run stopped on a non-finite value or a domain exit: step, global
 * particle index, body and quantity name ("position", "velocity",
 * "density", "deviatoric stress", "speed", "density ratio").  Returns
 * SPH_ERR_STATE if the last run did not fail that way; either way the
 * handle's message (the failed run's) is left as it is. */
SPH_API sph_status sph_failure(const sph_sim *sim, long *step, long *particle, int *body,
                               const char **quantity);

#ifdef __cplusplus
}
#endif

#endif /* SPHSOLID_PUBLIC_INTEGRATORS_H */
