/*
 * Improved Euler (Heun), two rate evaluations per step,
 *   y*      = y_n + dt f(y_n)
 *   y_{n+1} = y_n + dt/2 (f(y_n) + f(y*)) = (y_n + y*)/2 + dt/2 f(y*)
 * for positions, velocities, densities and deviatoric stresses.  Positions
 * use x_{n+1} = x* + dt/2 (v* - v_n), which needs only v_n saved.
 * Bodies with prescribed motion keep their velocity (a prescribed rotation
 * moves its particles exactly along their arcs instead); their density and
 * stress evolve like everyone else's.
 *
 * The stages on caller arrays (sph_improved_euler_*, used by the LAMMPS plugin) and
 * the step of a handle share the per-particle updates below.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/integrator.h"

/* ------------------------------------------------ stages on caller arrays */

typedef struct saved_state {
    double *v, *rho, *S, *u; /* u: transport velocity, only with XSPH */
} saved_state;

static saved_state saved_layout(double *saved, size_t n, int dim, int ncomp, int with_u)
{
    saved_state s;
    s.v = saved;
    s.rho = saved + n * dim;
    s.S = s.rho + n;
    s.u = with_u ? s.S + n * ncomp : NULL;
    return s;
}

static inline void predict_particle(int dim, int ncomp, double dt, size_t a, double *x, double *v,
                                    size_t xs, double *rho, double *S, const sph_rates *r,
                                    int integrate, int move, const saved_state *s)
{
    const double *u = (integrate && r->dx_dt) ? r->dx_dt + a * dim : v + a * xs;
    for (int i = 0; i < dim; ++i) {
        s->v[a * dim + i] = v[a * xs + i];
        if (s->u)
            s->u[a * dim + i] = u[i];
        if (move)
            x[a * xs + i] += dt * u[i];
        if (integrate)
            v[a * xs + i] += dt * r->dv_dt[a * dim + i];
    }
    s->rho[a] = rho[a];
    rho[a] += dt * r->drho_dt[a];
    for (int c = 0; c < ncomp; ++c) {
        s->S[a * ncomp + c] = S[a * ncomp + c];
        S[a * ncomp + c] += dt * r->dS_dt[a * ncomp + c];
    }
}

/* Returns the distance bound moved in this step (for the neighbour list),
 * or NAN if a value went non-finite. */
static inline double correct_particle(int dim, int ncomp, double dt, size_t a, double *x, double *v,
                                      size_t xs, double *rho, double *S, const sph_rates *r,
                                      int integrate, int move, const saved_state *s)
{
    const double *u_star = (integrate && r->dx_dt) ? r->dx_dt + a * dim : v + a * xs;
    const double *u_n = s->u ? s->u + a * dim : s->v + a * dim;
    double moved2 = 0.0, ok = 1.0;
    for (int i = 0; i < dim; ++i) {
        const double step = 0.5 * dt * (u_star[i] + u_n[i]);
        moved2 += step * step;
        if (move)
            x[a * xs + i] += 0.5 * dt * (u_star[i] - u_n[i]);
        if (integrate)
            v[a * xs + i] =
                0.5 * (s->v[a * dim + i] + v[a * xs + i]) + 0.5 * dt * r->dv_dt[a * dim + i];
        ok *= isfinite(x[a * xs + i]) && isfinite(v[a * xs + i]);
    }
    rho[a] = 0.5 * (s->rho[a] + rho[a]) + 0.5 * dt * r->drho_dt[a];
    ok *= isfinite(rho[a]) && rho[a] > 0.0;
    for (int c = 0; c < ncomp; ++c) {
        S[a * ncomp + c] =
            0.5 * (s->S[a * ncomp + c] + S[a * ncomp + c]) + 0.5 * dt * r->dS_dt[a * ncomp + c];
        ok *= isfinite(S[a * ncomp + c]);
    }
    return ok ? sqrt(moved2) : NAN;
}

static sph_status check_stage_args(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                   double *rho, double *S, const sph_rates *r, const double *saved)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(dt > 0.0) || !isfinite(dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "dt=%g: must be finite and > 0", dt);
    if (n > 0 && (!x || !v || !rho || !S || !r || !saved || !r->dv_dt || !r->drho_dt || !r->dS_dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "Improved Euler stage: an array argument is NULL");
    return SPH_OK;
}

/* The external stages: `move` 1 advances every position (sph_improved_euler_*), 0
 * leaves the prescribed particles' x and v to the caller (*_strided). */
static sph_status predict_external(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                   size_t xs, double *rho, double *S, const sph_rates *r,
                                   const unsigned char *integrate_motion, double *saved,
                                   int move_all)
{
    sph_status st = check_stage_args(sim, n, dt, x, v, rho, S, r, saved);
    if (st)
        return st;
    const int dim = sim->dim, nc = sim->ncomp;
    const saved_state s = saved_layout(saved, n, dim, nc, r->dx_dt != NULL);
    const long nn = (long)n;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim))
    for (long a = 0; a < nn; ++a) {
        const int integrate = integrate_motion ? integrate_motion[a] : 1;
        predict_particle(dim, nc, dt, (size_t)a, x, v, xs, rho, S, r, integrate,
                         move_all || integrate, &s);
    }
    return SPH_OK;
}

static sph_status correct_external(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                   size_t xs, double *rho, double *S, const sph_rates *r,
                                   const unsigned char *integrate_motion, const double *saved,
                                   int move_all, const int *material_of, long *particle)
{
    sph_status st = check_stage_args(sim, n, dt, x, v, rho, S, r, saved);
    if (st)
        return st;
    const int dim = sim->dim, nc = sim->ncomp;
    const saved_state s = saved_layout((double *)saved, n, dim, nc, r->dx_dt != NULL);
    const long nn = (long)n;
    long bad = nn, wild = nn;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(min : bad, wild)
    for (long a = 0; a < nn; ++a) {
        const int integrate = integrate_motion ? integrate_motion[a] : 1;
        const double moved = correct_particle(dim, nc, dt, (size_t)a, x, v, xs, rho, S, r,
                                              integrate, move_all || integrate, &s);
        if (isnan(moved)) {
            if (a < bad)
                bad = a;
        } else if (material_of && a < wild) {
            double vmax2, rho_lo, rho_hi;
            watchdog_bounds(sim, &sim->materials[material_of[a]], integrate, &vmax2, &rho_lo,
                            &rho_hi);
            if (watchdog_trips(dim, v + a * xs, rho[a], vmax2, rho_lo, rho_hi))
                wild = a;
        }
    }
    const stage_arrays out = {v, xs, rho, material_of, integrate_motion};
    return stage_outcome(
        sim, "Improved Euler correction produced a non-finite value (or non-positive density)", nn,
        bad, wild, particle, &out);
}

sph_status sph_improved_euler_predict(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                      double *rho, double *S, const sph_rates *r,
                                      const unsigned char *integrate_motion, double *saved)
{
    return predict_external(sim, n, dt, x, v, sim ? (size_t)sim->dim : 0, rho, S, r,
                            integrate_motion, saved, 1);
}

sph_status sph_improved_euler_correct(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                      double *rho, double *S, const sph_rates *r,
                                      const unsigned char *integrate_motion, const double *saved)
{
    return correct_external(sim, n, dt, x, v, sim ? (size_t)sim->dim : 0, rho, S, r,
                            integrate_motion, saved, 1, NULL, NULL);
}

static sph_status check_stride(sph_sim *sim, size_t stride)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (stride < (size_t)sim->dim)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "stride=%zu is smaller than the dimension %d",
                        stride, sim->dim);
    return SPH_OK;
}

sph_status sph_improved_euler_predict_strided(sph_sim *sim, size_t n, double dt, double *x,
                                              double *v, size_t stride, double *rho, double *S,
                                              const sph_rates *r,
                                              const unsigned char *integrate_motion, double *saved)
{
    sph_status st = check_stride(sim, stride);
    return st ? st
              : predict_external(sim, n, dt, x, v, stride, rho, S, r, integrate_motion, saved, 0);
}

sph_status sph_improved_euler_correct_strided(sph_sim *sim, size_t n, double dt, double *x,
                                              double *v, size_t stride, double *rho, double *S,
                                              const sph_rates *r,
                                              const unsigned char *integrate_motion,
                                              const int *material_of, const double *saved,
                                              long *particle)
{
    if (particle)
        *particle = -1;
    sph_status st = check_stride(sim, stride);
    if (st)
        return st;
    if (n > 0 && !material_of)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_improved_euler_correct_strided: material must not be NULL");
    for (size_t a = 0; a < n; ++a)
        if (material_of[a] < 0 || material_of[a] >= sim->n_materials)
            return sph_fail(
                sim, SPH_ERR_ARGUMENT,
                "sph_improved_euler_correct_strided: particle %zu has material %d, but %d "
                "materials are defined",
                a, material_of[a], sim->n_materials);
    return correct_external(sim, n, dt, x, v, stride, rho, S, r, integrate_motion, saved, 0,
                            material_of, particle);
}

/* Deprecated aliases of the stages above (sphsolid.h), kept for one
 * release. */
sph_status sph_heun_predict(sph_sim *sim, size_t n, double dt, double *x, double *v, double *rho,
                            double *S, const sph_rates *r, const unsigned char *integrate_motion,
                            double *saved)
{
    return sph_improved_euler_predict(sim, n, dt, x, v, rho, S, r, integrate_motion, saved);
}

sph_status sph_heun_correct(sph_sim *sim, size_t n, double dt, double *x, double *v, double *rho,
                            double *S, const sph_rates *r, const unsigned char *integrate_motion,
                            const double *saved)
{
    return sph_improved_euler_correct(sim, n, dt, x, v, rho, S, r, integrate_motion, saved);
}

sph_status sph_heun_predict_strided(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                    size_t stride, double *rho, double *S, const sph_rates *r,
                                    const unsigned char *integrate_motion, double *saved)
{
    return sph_improved_euler_predict_strided(sim, n, dt, x, v, stride, rho, S, r, integrate_motion,
                                              saved);
}

sph_status sph_heun_correct_strided(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                    size_t stride, double *rho, double *S, const sph_rates *r,
                                    const unsigned char *integrate_motion, const int *material_of,
                                    const double *saved, long *particle)
{
    return sph_improved_euler_correct_strided(sim, n, dt, x, v, stride, rho, S, r, integrate_motion,
                                              material_of, saved, particle);
}

/* ------------------------------------------------ the step of a handle */

static size_t improved_euler_saved_values(int dim, int ncomp, int xsph)
{
    return (size_t)dim + 1 + (size_t)ncomp + (xsph ? (size_t)dim : 0);
}

static void improved_euler_undo(sph_sim *sim)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const saved_state s = saved_layout(sim->saved, sim->n, dim, nc, sim->fx.xsph);
    memcpy(sim->x, sim->x_saved, sim->n * dim * sizeof(double));
    memcpy(sim->v, s.v, sim->n * dim * sizeof(double));
    memcpy(sim->rho, s.rho, sim->n * sizeof(double));
    memcpy(sim->S, s.S, sim->n * nc * sizeof(double));
}

static sph_status improved_euler_stage(sph_sim *sim, double dt, int corrector, double *moved)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const sph_rates r = {.dv_dt = sim->dv_dt,
                         .drho_dt = sim->drho_dt,
                         .dS_dt = sim->dS_dt,
                         .dx_dt = sim->fx.xsph ? sim->dx_dt : NULL};
    const saved_state s = saved_layout(sim->saved, sim->n, dim, nc, sim->fx.xsph);
    body_stage small[8], *bs;
    sph_status st = body_stages_make(sim, dt, small, &bs);
    if (st)
        return st;
    const long n = (long)sim->n;
    const int *body_of = sim->body_of;
    double max_moved = 0.0;
    long bad = n, wild = n;
    if (!corrector) {
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim))
        for (long a = 0; a < n; ++a) {
            for (int i = 0; i < dim; ++i)
                sim->x_saved[a * dim + i] = sim->x[a * dim + i];
            /* (the dimension a constant of each call: loops unrolled) */
            if (dim == 2)
                predict_particle(2, 4, dt, (size_t)a, sim->x, sim->v, 2, sim->rho, sim->S, &r,
                                 bs[body_of[a]].integrate, 1, &s);
            else
                predict_particle(3, 6, dt, (size_t)a, sim->x, sim->v, 3, sim->rho, sim->S, &r,
                                 bs[body_of[a]].integrate, 1, &s);
            if (bs[body_of[a]].rotate)
                rotate_particle(dim, &bs[body_of[a]], sim->x_saved + a * dim, sim->x + a * dim,
                                sim->v + a * dim);
        }
    } else {
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(min : bad, wild) \
    reduction(max : max_moved)
        for (long a = 0; a < n; ++a) {
            const body_stage *b = &bs[body_of[a]];
            double d = dim == 2 ? correct_particle(2, 4, dt, (size_t)a, sim->x, sim->v, 2, sim->rho,
                                                   sim->S, &r, b->integrate, 1, &s)
                                : correct_particle(3, 6, dt, (size_t)a, sim->x, sim->v, 3, sim->rho,
                                                   sim->S, &r, b->integrate, 1, &s);
            if (b->rotate && !isnan(d))
                d = rotate_particle(dim, b, sim->x_saved + a * dim, sim->x + a * dim,
                                    sim->v + a * dim);
            if (isnan(d)) {
                if (a < bad)
                    bad = a;
                continue;
            }
            if (d > max_moved)
                max_moved = d;
            if (watchdog_trips(dim, sim->v + a * dim, sim->rho[a], b->vmax2, b->rho_lo,
                               b->rho_hi) &&
                a < wild)
                wild = a;
        }
    }
    body_stages_free(bs, small);
    *moved = max_moved;
    if (bad < n || wild < n)
        return step_failure(sim, dt, bad < n ? bad : -1, wild < n ? wild : -1);
    return SPH_OK;
}

static sph_status improved_euler_step(sph_sim *sim, double dt, double *moved)
{
    sph_status st;
    if ((st = sim_evaluate(sim)))
        return st;
    if ((st = improved_euler_stage(sim, dt, 0, moved)))
        return st;
    if ((st = sim_evaluate(sim))) {
        improved_euler_undo(sim);
        return st;
    }
    if ((st = improved_euler_stage(sim, dt, 1, moved))) {
        improved_euler_undo(sim);
        return st;
    }
    return SPH_OK;
}

const integrator integrator_improved_euler = INTEGRATOR_RECORD(
    "improved_euler",
    "Improved Euler (Heun): two rate evaluations per step, second order; needs artificial "
    "viscosity for wave problems (the paper's scheme)",
    /* evaluations */ 2, /* stable */ 1.0, /* default */ 0.5, /* viscosity shortens step */ 0,
    improved_euler_saved_values, improved_euler_step, /* carries rates */ 0);
