/*
 * Time integrators as units.  Each integrator is one file
 * (integrator_improved_euler.c, integrator_leapfrog.c) defining one
 * `integrator` record, listed once in the registry of
 * integrator_registry.c.  The run driver (run.c), the stable and default
 * steps, checkpoints and the low-level stage calls all go through the
 * record.
 *
 * Shared pieces of a step on the handle's arrays (integrator_stages.c):
 * per-body constants (motion, watchdog bounds, rotation), exact rotation
 * arcs, and the failure report of a step that went non-finite or tripped
 * the watchdog.
 */
#ifndef SPHSOLID_INTEGRATOR_H
#define SPHSOLID_INTEGRATOR_H

#include <math.h>

#include "core/sim.h"

typedef struct integrator {
    const char *name;
    const char *description; /* one line */
    int evaluations;         /* rate evaluations per step */
    /* largest stable step as a multiple of h / max(c_p + |v|) */
    double stable_factor;
    /* default step as a multiple of h / max(c0), capped at the stable step */
    double default_factor;
    /* 1 if stable_factor was measured without artificial viscosity, which
     * then shortens the stable step by the kernel's 1 + kappa alpha
     * (kernel.h), 0 if it holds with the viscosity on */
    int viscosity_shortens_step;
    /* doubles per particle the step saves at its start (besides positions),
     * for undoing a failed step */
    size_t (*saved_values)(int dim, int ncomp, int xsph);
    /* advance the handle by dt; *moved receives a bound of any particle's
     * displacement from its position at the start of the step (NAN-free on
     * success).  On failure the step has been undone. */
    sph_status (*step)(sph_sim *sim, double dt, double *moved);
    /* 1 if the rates at the end of a step are the start of the next one
     * (kept across runs and in checkpoints), 0 if every step starts with
     * its own evaluation */
    int carries_rates;
} integrator;

/* An integrator's record, in the order of the fields above. */
#define INTEGRATOR_RECORD(NAME, DESCRIPTION, EVALUATIONS, STABLE, DEFAULT, VISCOUS, SAVED, STEP, \
                          CARRIES)                                                               \
    {.name = NAME,                                                                               \
     .description = DESCRIPTION,                                                                 \
     .evaluations = EVALUATIONS,                                                                 \
     .stable_factor = STABLE,                                                                    \
     .default_factor = DEFAULT,                                                                  \
     .viscosity_shortens_step = VISCOUS,                                                         \
     .saved_values = SAVED,                                                                      \
     .step = STEP,                                                                               \
     .carries_rates = CARRIES}

extern const integrator integrator_improved_euler;
extern const integrator integrator_leapfrog;

/* integrator_registry.c */
const integrator *integrator_find(const char *name);
const integrator *sim_integrator(const sph_sim *sim);
/* The carried rates belong to the current state: fingerprint of x, v, rho,
 * S taken after the step that computed them. */
unsigned long long state_fingerprint(const sph_sim *sim);
void carried_rates_set(sph_sim *sim);
int carried_rates_valid(const sph_sim *sim);

/* run.c */
sph_status sim_evaluate(sph_sim *sim); /* rates at the handle's state, motions applied */
sph_status sim_evaluate_pass(sph_sim *sim, int pass); /* PASS_*: only those rates */
sph_status sim_ensure_neighbours(sph_sim *sim, double extra_displacement);

/* integrator_stages.c: per-body constants of a step */
typedef struct body_stage {
    int integrate;                /* velocity integrated (free, force) */
    int rotate;                   /* prescribed rotation by R about c */
    double vmax2, rho_lo, rho_hi; /* watchdog bounds */
    double R[3][3], c[3];
    const double *omega;
} body_stage;

/* Per-body records for a step whose rotations turn by |omega| dt_rotation:
 * *out points to `small` (8 records) or to allocated memory (free with
 * body_stages_free). */
sph_status body_stages_make(sph_sim *sim, double dt_rotation, body_stage *small, body_stage **out);
void body_stages_free(body_stage *bs, const body_stage *small);
void body_stage_rotation(body_stage *b, double dt);
/* x = c + R (x_n - c), v = omega x (x - c); returns |x - x_n|. */
double rotate_particle(int dim, const body_stage *b, const double *x_n, double *x, double *v);
/* The watchdog's bounds for one material; a zero setting switches a bound
 * off.  Prescribed particles (integrate = 0) are not held to the speed.
 * Inline: the stages on caller arrays take them per particle. */
static inline void watchdog_bounds(const sph_sim *sim, const material *m, int integrate,
                                   double *vmax2, double *rho_lo, double *rho_hi)
{
    *vmax2 = integrate && sim->watch_speed > 0.0
                 ? (sim->watch_speed * m->c_p) * (sim->watch_speed * m->c_p)
                 : INFINITY;
    *rho_lo = sim->watch_rho_min * m->rho0;
    *rho_hi = sim->watch_rho_max > 0.0 ? sim->watch_rho_max * m->rho0 : INFINITY;
}
static inline int watchdog_trips(int dim, const double *v, double rho, double vmax2, double rho_lo,
                                 double rho_hi)
{
    double v2 = 0.0;
    for (int i = 0; i < dim; ++i)
        v2 += v[i] * v[i];
    return v2 > vmax2 || rho < rho_lo || rho > rho_hi;
}
/* The report of a failed step at t + dt: particle `bad` went non-finite
 * (or non-positive density), else particle `wild` tripped the watchdog
 * (-1: none).  Records sph_failure() and returns the status. */
sph_status step_failure(sph_sim *sim, double dt, long bad, long wild);
sph_status watchdog_report(sph_sim *sim, long a, int dim, const double *v_a, double rho_a,
                           const material *m, int integrate);
/* The outcome of a stage on external arrays of n particles: *particle (if
 * given) the first particle that went non-finite (`bad`), else the first
 * that tripped the watchdog (`wild`), else -1 (n: none); a non-finite one
 * is reported as "<failure> at particle <bad>". */
typedef struct stage_arrays {
    const double *v; /* `stride` doubles apart */
    size_t stride;
    const double *rho;
    const int *material_of;
    const unsigned char *integrate_motion; /* NULL: all integrated */
} stage_arrays;
sph_status stage_outcome(sph_sim *sim, const char *failure, long n, long bad, long wild,
                         long *particle, const stage_arrays *a);
/* y = y_n + dt D for one particle (rho and its ncomp stress components);
 * 0 if a value is not finite or the density not positive. */
static inline int drift_state(int nc, double dt, double rho_n, const double *S_n, double drho,
                              const double *dS, double *rho, double *S)
{
    double ok = 1.0;
    *rho = rho_n + dt * drho;
    ok *= isfinite(*rho) && *rho > 0.0;
    for (int c = 0; c < nc; ++c) {
        S[c] = S_n[c] + dt * dS[c];
        ok *= isfinite(S[c]);
    }
    return ok != 0.0;
}

#endif
