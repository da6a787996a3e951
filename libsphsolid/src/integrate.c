/*
 * Time integration: Improved Euler (Heun), two rate evaluations per step,
 *   y*      = y_n + dt f(y_n)
 *   y_{n+1} = y_n + dt/2 (f(y_n) + f(y*)) = (y_n + y*)/2 + dt/2 f(y*)
 * for positions, velocities, densities and deviatoric stresses.  Positions
 * use x_{n+1} = x* + dt/2 (v* - v_n), which needs only v_n saved.
 * Bodies with prescribed motion keep their velocity (a prescribed rotation
 * moves its particles exactly along their arcs instead); their density and
 * stress evolve like everyone else's.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim.h"

/* ------------------------------------------------ stages on plain arrays */

typedef struct saved_state {
    double *v, *rho, *S, *u;    /* u: transport velocity, only with XSPH */
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

static inline void predict_particle(int dim, int ncomp, double dt, size_t a,
                                    double *x, double *v, size_t xs, double *rho, double *S,
                                    const sph_rates *r, int integrate, int move,
                                    const saved_state *s)
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
static inline double correct_particle(int dim, int ncomp, double dt, size_t a,
                                      double *x, double *v, size_t xs, double *rho, double *S,
                                      const sph_rates *r, int integrate, int move,
                                      const saved_state *s)
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
            v[a * xs + i] = 0.5 * (s->v[a * dim + i] + v[a * xs + i]) +
                            0.5 * dt * r->dv_dt[a * dim + i];
        ok *= isfinite(x[a * xs + i]) && isfinite(v[a * xs + i]);
    }
    rho[a] = 0.5 * (s->rho[a] + rho[a]) + 0.5 * dt * r->drho_dt[a];
    ok *= isfinite(rho[a]) && rho[a] > 0.0;
    for (int c = 0; c < ncomp; ++c) {
        S[a * ncomp + c] = 0.5 * (s->S[a * ncomp + c] + S[a * ncomp + c]) +
                           0.5 * dt * r->dS_dt[a * ncomp + c];
        ok *= isfinite(S[a * ncomp + c]);
    }
    return ok ? sqrt(moved2) : NAN;
}

static sph_status check_stage_args(sph_sim *sim, size_t n, double dt,
                                   double *x, double *v, double *rho, double *S,
                                   const sph_rates *r, const double *saved)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(dt > 0.0) || !isfinite(dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "dt=%g: must be finite and > 0", dt);
    if (n > 0 && (!x || !v || !rho || !S || !r || !saved || !r->dv_dt || !r->drho_dt || !r->dS_dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "Improved Euler stage: an array argument is NULL");
    return SPH_OK;
}

/* The watchdog's bounds for one material; a zero setting switches a bound
 * off.  Prescribed particles (integrate = 0) are not held to the speed. */
static void watchdog_bounds(const sph_sim *sim, const material *m, int integrate,
                            double *vmax2, double *rho_lo, double *rho_hi)
{
    *vmax2 = integrate && sim->watch_speed > 0.0
                 ? (sim->watch_speed * m->c_p) * (sim->watch_speed * m->c_p)
                 : INFINITY;
    *rho_lo = sim->watch_rho_min * m->rho0;
    *rho_hi = sim->watch_rho_max > 0.0 ? sim->watch_rho_max * m->rho0 : INFINITY;
}

static inline int watchdog_trips(int dim, const double *v, double rho, double vmax2,
                                 double rho_lo, double rho_hi)
{
    double v2 = 0.0;
    for (int i = 0; i < dim; ++i)
        v2 += v[i] * v[i];
    return v2 > vmax2 || rho < rho_lo || rho > rho_hi;
}

/* The watchdog's report for particle a of external arrays, which tripped
 * it: its speed if that is above the bound, else its density ratio. */
static sph_status watchdog_report(sph_sim *sim, long a, int dim, const double *v_a,
                                  double rho_a, const material *m, int integrate)
{
    double vmax2, rho_lo, rho_hi, v2 = 0.0;
    watchdog_bounds(sim, m, integrate, &vmax2, &rho_lo, &rho_hi);
    for (int i = 0; i < dim; ++i)
        v2 += v_a[i] * v_a[i];
    if (v2 > vmax2)
        return sph_fail(sim, SPH_ERR_UNSTABLE,
                        "particle %ld moves at %g m/s, more than %g times the P-wave speed %g m/s (watchdog)",
                        a, sqrt(v2), sim->watch_speed, m->c_p);
    return sph_fail(sim, SPH_ERR_UNSTABLE,
                    "particle %ld has density ratio rho/rho0 = %g outside [%g, %g] (watchdog)",
                    a, rho_a / m->rho0, sim->watch_rho_min, sim->watch_rho_max);
}

/* The external stages: `move` 1 advances every position (sph_heun_*), 0
 * leaves the prescribed particles' x and v to the caller (*_strided). */
static sph_status predict_external(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                   size_t xs, double *rho, double *S, const sph_rates *r,
                                   const unsigned char *integrate_motion, double *saved, int move_all)
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
            watchdog_bounds(sim, &sim->materials[material_of[a]], integrate, &vmax2, &rho_lo, &rho_hi);
            if (watchdog_trips(dim, v + a * xs, rho[a], vmax2, rho_lo, rho_hi))
                wild = a;
        }
    }
    if (particle)
        *particle = bad < nn ? bad : wild < nn ? wild : -1;
    if (bad < nn)
        return sph_fail(sim, SPH_ERR_NONFINITE,
                        "Improved Euler correction produced a non-finite value (or non-positive density) at particle %ld",
                        bad);
    if (wild < nn)
        return watchdog_report(sim, wild, dim, v + wild * xs, rho[wild],
                               &sim->materials[material_of[wild]],
                               integrate_motion ? integrate_motion[wild] : 1);
    return SPH_OK;
}

sph_status sph_heun_predict(sph_sim *sim, size_t n, double dt, double *x,
                            double *v, double *rho, double *S, const sph_rates *r,
                            const unsigned char *integrate_motion, double *saved)
{
    return predict_external(sim, n, dt, x, v, sim ? (size_t)sim->dim : 0, rho, S, r,
                            integrate_motion, saved, 1);
}

sph_status sph_heun_correct(sph_sim *sim, size_t n, double dt, double *x,
                            double *v, double *rho, double *S, const sph_rates *r,
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

sph_status sph_heun_predict_strided(sph_sim *sim, size_t n, double dt, double *x,
                                    double *v, size_t stride, double *rho, double *S,
                                    const sph_rates *r, const unsigned char *integrate_motion,
                                    double *saved)
{
    sph_status st = check_stride(sim, stride);
    return st ? st : predict_external(sim, n, dt, x, v, stride, rho, S, r, integrate_motion, saved, 0);
}

sph_status sph_heun_correct_strided(sph_sim *sim, size_t n, double dt, double *x,
                                    double *v, size_t stride, double *rho, double *S,
                                    const sph_rates *r, const unsigned char *integrate_motion,
                                    const int *material_of, const double *saved, long *particle)
{
    if (particle)
        *particle = -1;
    sph_status st = check_stride(sim, stride);
    if (st)
        return st;
    if (n > 0 && !material_of)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_heun_correct_strided: material must not be NULL");
    for (size_t a = 0; a < n; ++a)
        if (material_of[a] < 0 || material_of[a] >= sim->n_materials)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "sph_heun_correct_strided: particle %zu has material %d, but %d materials are defined",
                            a, material_of[a], sim->n_materials);
    return correct_external(sim, n, dt, x, v, stride, rho, S, r, integrate_motion, saved, 0,
                            material_of, particle);
}

/* ------------------------------------------------- the simulation's run */

static int body_integrates(const body *b)
{
    return b->motion == SPH_MOTION_FREE || b->motion == SPH_MOTION_FORCE;
}

sph_status sim_prepare(sph_sim *sim)
{
    if (sim->failed == -1)
        return sph_fail(sim, SPH_ERR_STATE, "this handle was created with an invalid dimension");
    if (sim->n == 0)
        return sph_fail(sim, SPH_ERR_STATE, "the simulation has no particles: add a body first");
    if (!sim->dt_set)
        sim->dt = sph_default_dt(sim);
    sim_shrink_to_fit(sim);
    const size_t n = sim->n;
    const int dim = sim->dim, nc = sim->ncomp;
    const size_t saved_per = (size_t)dim + 1 + nc + (sim->fx.xsph ? dim : 0);
    double *saved = realloc(sim->saved, n * saved_per * sizeof(double));
    double *dv = realloc(sim->dv_dt, n * dim * sizeof(double));
    double *dr = realloc(sim->drho_dt, n * sizeof(double));
    double *dS = realloc(sim->dS_dt, n * nc * sizeof(double));
    double *xs = realloc(sim->x_saved, n * dim * sizeof(double));
    if (xs) sim->x_saved = xs;
    if (saved) sim->saved = saved;
    if (dv) sim->dv_dt = dv;
    if (dr) sim->drho_dt = dr;
    if (dS) sim->dS_dt = dS;
    if (!saved || !dv || !dr || !dS || !xs)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate integrator storage for %zu particles", n);
    if (sim->fx.xsph) {
        double *dx = realloc(sim->dx_dt, n * dim * sizeof(double));
        if (!dx)
            return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate XSPH velocities for %zu particles", n);
        sim->dx_dt = dx;
    } else {
        free(sim->dx_dt);
        sim->dx_dt = NULL;
    }
    for (int k = 0; k < sim->n_bodies; ++k)
        for (int i = 0; i < dim && sim->bodies[k].motion == SPH_MOTION_ROTATION; ++i)
            if (sim->has_domain && sim->periodic[i])
                return sph_fail(sim, SPH_ERR_STATE,
                                "body '%s' rotates (sph_set_rotation), which needs a domain without periodic axes (%c is periodic)",
                                sim->bodies[k].name, "xyz"[i]);
    sim->nl.skin = 0.25 * sim->h;
    const double rc = 2.0 * sim->h + sim->nl.skin;
    for (int i = 0; i < dim; ++i)
        if (sim->has_domain && sim->periodic[i] && sim->hi[i] - sim->lo[i] < 2.0 * rc)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "periodic length along %c is %g m, shorter than twice the neighbour cutoff 2h + skin = %g m",
                            "xyz"[i], sim->hi[i] - sim->lo[i], rc);
    if (!sim->nl.valid || sim->nl.n != n) {
        sph_status st = neighbour_build(sim);
        if (st)
            return st;
    }
    return SPH_OK;
}

static sph_status evaluate(sph_sim *sim)
{
    sph_neighbours nb = {sim->nl.offsets, sim->nl.indices, NULL, NULL};
    rate_call call = {sim->n, sim->n, sim->x, sim->v, sim->rho, sim->S, sim->mass, (size_t)sim->dim,
                      sim->material_of, &nb, 1, sim->dv_dt, sim->drho_dt,
                      sim->dS_dt, sim->fx.xsph ? sim->dx_dt : NULL};
    sph_status st = rates_run(sim, &call);
    if (st)
        return st;
    /* Prescribed motions: no acceleration; force-driven bodies translate
     * rigidly under the applied force plus the SPH forces on them. */
    const int dim = sim->dim;
    for (int k = 0; k < sim->n_bodies; ++k) {
        const body *b = &sim->bodies[k];
        if (b->motion == SPH_MOTION_FIXED || b->motion == SPH_MOTION_VELOCITY) {
            memset(sim->dv_dt + b->first * dim, 0, b->count * dim * sizeof(double));
        } else if (b->motion == SPH_MOTION_FORCE) {
            double sums[4] = {0.0, 0.0, 0.0, 0.0};
            double *dv = sim->dv_dt + b->first * dim;
            sph_rigid_force_sum(sim, b->count, sim->mass + b->first, dv, NULL, sums);
            sph_rigid_force_apply(sim, b->count, b->vector, sums, NULL, dv);
        }
    }
    return SPH_OK;
}

sph_status sph_rigid_force_sum(sph_sim *sim, size_t n, const double *mass,
                               const double *dv_dt, const unsigned char *member, double *sums)
{
    if (!sim || !sums)
        return SPH_ERR_ARGUMENT;
    if (n > 0 && (!mass || !dv_dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rigid_force_sum: mass and dv_dt must not be NULL");
    const int dim = sim->dim;
    for (size_t a = 0; a < n; ++a) {
        if (member && !member[a])
            continue;
        sums[0] += mass[a];
        for (int i = 0; i < dim; ++i)
            sums[1 + i] += mass[a] * dv_dt[a * dim + i];
    }
    return SPH_OK;
}

sph_status sph_rigid_force_apply(sph_sim *sim, size_t n, const double *applied,
                                 const double *sums, const unsigned char *member, double *dv_dt)
{
    if (!sim || !applied || !sums)
        return SPH_ERR_ARGUMENT;
    if (n > 0 && !dv_dt)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rigid_force_apply: dv_dt must not be NULL");
    if (!(sums[0] > 0.0) || !isfinite(sums[0]))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_rigid_force_apply: total mass %g of the body must be finite and > 0", sums[0]);
    const int dim = sim->dim;
    double a_body[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < dim; ++i)
        a_body[i] = (applied[i] + sums[1 + i]) / sums[0];
    for (size_t a = 0; a < n; ++a) {
        if (member && !member[a])
            continue;
        for (int i = 0; i < dim; ++i)
            dv_dt[a * dim + i] = a_body[i];
    }
    return SPH_OK;
}

sph_status sph_watchdog_check(sph_sim *sim, size_t n, const double *v, const double *rho,
                              const int *material_of, const unsigned char *integrate_motion,
                              long *particle)
{
    if (!sim || !particle)
        return SPH_ERR_ARGUMENT;
    *particle = -1;
    if (n > 0 && (!v || !rho || !material_of))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_watchdog_check: v, rho and material must not be NULL");
    const int dim = sim->dim;
    for (size_t a = 0; a < n; ++a) {
        if (material_of[a] < 0 || material_of[a] >= sim->n_materials)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_watchdog_check: particle %zu has material %d, but %d materials are defined",
                            a, material_of[a], sim->n_materials);
        const material *m = &sim->materials[material_of[a]];
        double vmax2, rho_lo, rho_hi;
        watchdog_bounds(sim, m, integrate_motion ? integrate_motion[a] : 1, &vmax2, &rho_lo, &rho_hi);
        if (!watchdog_trips(dim, v + a * dim, rho[a], vmax2, rho_lo, rho_hi))
            continue;
        *particle = (long)a;
        return watchdog_report(sim, (long)a, dim, v + a * dim, rho[a], m,
                               integrate_motion ? integrate_motion[a] : 1);
    }
    return SPH_OK;
}

/* Per-body constants of a stage. */
typedef struct body_stage {
    int integrate;
    int rotate;                     /* prescribed rotation by R about c */
    double vmax2, rho_lo, rho_hi;   /* watchdog bounds */
    double R[3][3], c[3];
    const double *omega;
} body_stage;

/* The rotation by the angle |omega| dt about omega (Rodrigues). */
static void rotation_matrix(const double *omega, double dt, double R[3][3])
{
    const double w = sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
    const double k[3] = {w > 0.0 ? omega[0] / w : 0.0, w > 0.0 ? omega[1] / w : 0.0,
                         w > 0.0 ? omega[2] / w : 1.0};
    const double c = cos(w * dt), s = sin(w * dt), C = 1.0 - c;
    R[0][0] = c + k[0] * k[0] * C;
    R[0][1] = k[0] * k[1] * C - k[2] * s;
    R[0][2] = k[0] * k[2] * C + k[1] * s;
    R[1][0] = k[1] * k[0] * C + k[2] * s;
    R[1][1] = c + k[1] * k[1] * C;
    R[1][2] = k[1] * k[2] * C - k[0] * s;
    R[2][0] = k[2] * k[0] * C - k[1] * s;
    R[2][1] = k[2] * k[1] * C + k[0] * s;
    R[2][2] = c + k[2] * k[2] * C;
}

/* A particle of a rotating body: x = c + R (x_n - c) at both stages (the
 * exact arc; the corrector lands where the predictor did) and v = omega x
 * (x - c).  Returns the distance moved from x_n. */
static double rotate_particle(int dim, const body_stage *b, const double *x_n, double *x, double *v)
{
    const double r[3] = {x_n[0] - b->c[0], x_n[1] - b->c[1], dim == 3 ? x_n[2] - b->c[2] : 0.0};
    double moved2 = 0.0;
    for (int i = 0; i < dim; ++i) {
        x[i] = b->c[i] + b->R[i][0] * r[0] + b->R[i][1] * r[1] + b->R[i][2] * r[2];
        moved2 += (x[i] - x_n[i]) * (x[i] - x_n[i]);
    }
    rotation_velocity(dim, b->omega, b->c, x, v);
    return sqrt(moved2);
}

static sph_status stage(sph_sim *sim, double dt, int corrector, double *moved)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const sph_rates r = {sim->dv_dt, sim->drho_dt, sim->dS_dt, sim->fx.xsph ? sim->dx_dt : NULL};
    const saved_state s = saved_layout(sim->saved, sim->n, dim, nc, sim->fx.xsph);
    body_stage small[8], *bs = sim->n_bodies <= 8 ? small : malloc((size_t)sim->n_bodies * sizeof *bs);
    if (!bs)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %d body records", sim->n_bodies);
    for (int k = 0; k < sim->n_bodies; ++k) {
        const body *b = &sim->bodies[k];
        const material *m = &sim->materials[b->material];
        bs[k].integrate = body_integrates(b);
        bs[k].rotate = b->motion == SPH_MOTION_ROTATION;
        bs[k].omega = b->vector;
        memcpy(bs[k].c, b->centre, sizeof bs[k].c);
        if (bs[k].rotate)
            rotation_matrix(b->vector, dt, bs[k].R);
        watchdog_bounds(sim, m, bs[k].integrate, &bs[k].vmax2, &bs[k].rho_lo, &bs[k].rho_hi);
    }
    const long n = (long)sim->n;
    const int *body_of = sim->body_of;
    double max_moved = 0.0;
    long first_bad = -1, first_wild = -1;
    if (!corrector) {
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim))
        for (long a = 0; a < n; ++a) {
            for (int i = 0; i < dim; ++i)
                sim->x_saved[a * dim + i] = sim->x[a * dim + i];
            predict_particle(dim, nc, dt, (size_t)a, sim->x, sim->v, (size_t)dim, sim->rho, sim->S, &r,
                             bs[body_of[a]].integrate, 1, &s);
            if (bs[body_of[a]].rotate)
                rotate_particle(dim, &bs[body_of[a]], sim->x_saved + a * dim, sim->x + a * dim, sim->v + a * dim);
        }
    } else {
        long bad = n, wild = n;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(min : bad, wild) reduction(max : max_moved)
        for (long a = 0; a < n; ++a) {
            const body_stage *b = &bs[body_of[a]];
            double d = correct_particle(dim, nc, dt, (size_t)a, sim->x, sim->v, (size_t)dim, sim->rho,
                                        sim->S, &r, b->integrate, 1, &s);
            if (b->rotate && !isnan(d))
                d = rotate_particle(dim, b, sim->x_saved + a * dim, sim->x + a * dim, sim->v + a * dim);
            if (isnan(d)) {
                if (a < bad)
                    bad = a;
                continue;
            }
            if (d > max_moved)
                max_moved = d;
            if (watchdog_trips(dim, sim->v + a * dim, sim->rho[a], b->vmax2, b->rho_lo, b->rho_hi) && a < wild)
                wild = a;
        }
        if (bad < n)
            first_bad = bad;
        if (wild < n)
            first_wild = wild;
    }
    if (bs != small)
        free(bs);
    *moved = max_moved;
    if (first_bad >= 0) {
        const size_t a = (size_t)first_bad;
        const char *what = "deviatoric stress";
        for (int i = 0; i < dim; ++i)
            if (!isfinite(sim->x[a * dim + i]))
                what = "position";
        for (int i = 0; i < dim && what[0] == 'd'; ++i)
            if (!isfinite(sim->v[a * dim + i]))
                what = "velocity";
        if (what[0] == 'd' && !(isfinite(sim->rho[a]) && sim->rho[a] > 0.0))
            what = "density";
        sim->failed = 1;
        sim->fail_step = sim->step + 1;
        sim->fail_particle = first_bad;
        sim->fail_body = sim->body_of[a];
        sim->fail_quantity = what;
        return sph_fail(sim, SPH_ERR_NONFINITE,
                        "step %ld (t = %.9g s): particle %ld of body '%s' has a %s %s",
                        sim->fail_step, sim->t + dt, sim->fail_particle,
                        sim->bodies[sim->fail_body].name,
                        what[0] == 'd' && what[1] == 'e' && what[2] == 'n' ? "non-positive or non-finite" : "non-finite",
                        what);
    }
    if (first_wild >= 0) {
        const size_t a = (size_t)first_wild;
        const material *m = &sim->materials[sim->material_of[a]];
        double v2 = 0.0;
        for (int i = 0; i < dim; ++i)
            v2 += sim->v[a * dim + i] * sim->v[a * dim + i];
        const int speed = sim->watch_speed > 0.0 && v2 > pow(sim->watch_speed * m->c_p, 2);
        sim->failed = 1;
        sim->fail_step = sim->step + 1;
        sim->fail_particle = first_wild;
        sim->fail_body = sim->body_of[a];
        sim->fail_quantity = speed ? "speed" : "density ratio";
        if (speed)
            return sph_fail(sim, SPH_ERR_UNSTABLE,
                            "step %ld (t = %.9g s): particle %ld of body '%s' moves at %g m/s, more than %g times the P-wave speed %g m/s (watchdog; see sph_set_watchdog)",
                            sim->fail_step, sim->t + dt, sim->fail_particle, sim->bodies[sim->fail_body].name,
                            sqrt(v2), sim->watch_speed, m->c_p);
        return sph_fail(sim, SPH_ERR_UNSTABLE,
                        "step %ld (t = %.9g s): particle %ld of body '%s' has density ratio rho/rho0 = %g outside [%g, %g] (watchdog; see sph_set_watchdog)",
                        sim->fail_step, sim->t + dt, sim->fail_particle, sim->bodies[sim->fail_body].name,
                        sim->rho[a] / m->rho0, sim->watch_rho_min, sim->watch_rho_max);
    }
    return SPH_OK;
}

static sph_status wrap_and_check_domain(sph_sim *sim)
{
    if (!sim->has_domain)
        return SPH_OK;
    const int dim = sim->dim;
    for (size_t a = 0; a < sim->n; ++a)
        for (int i = 0; i < dim; ++i) {
            double *xi = &sim->x[a * dim + i];
            if (sim->periodic[i]) {
                const double L = sim->hi[i] - sim->lo[i];
                if (*xi >= sim->hi[i])
                    *xi -= L;
                else if (*xi < sim->lo[i])
                    *xi += L;
            } else if (*xi < sim->lo[i] || *xi > sim->hi[i]) {
                sim->failed = 1;
                sim->fail_step = sim->step;
                sim->fail_particle = (long)a;
                sim->fail_body = sim->body_of[a];
                sim->fail_quantity = "position";
                return sph_fail(sim, SPH_ERR_DOMAIN,
                                "step %ld (t = %.9g s): particle %zu of body '%s' left the domain along %c (%c=%g, domain [%g, %g])",
                                sim->step, sim->t, a, sim->bodies[sim->body_of[a]].name,
                                "xyz"[i], "xyz"[i], *xi, sim->lo[i], sim->hi[i]);
            }
        }
    return SPH_OK;
}

/* Put back the state at the start of the step (the last good state) after a
 * corrector that went non-finite or tripped the watchdog, and write it to
 * the output file if one is open. */
static void undo_step(sph_sim *sim)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const saved_state s = saved_layout(sim->saved, sim->n, dim, nc, sim->fx.xsph);
    memcpy(sim->x, sim->x_saved, sim->n * dim * sizeof(double));
    memcpy(sim->v, s.v, sim->n * dim * sizeof(double));
    memcpy(sim->rho, s.rho, sim->n * sizeof(double));
    memcpy(sim->S, s.S, sim->n * nc * sizeof(double));
    sim->rates_valid = 0;
    if (sim->out) {
        char message[SPH_ERRMSG_SIZE];
        memcpy(message, sim->errmsg, sizeof message);
        sph_output_snapshot(sim);
        memcpy(sim->errmsg, message, sizeof message);
    }
}

static sph_status one_step(sph_sim *sim, double dt)
{
    double moved;
    sph_status st;
    if ((st = evaluate(sim)))
        return st;
    if ((st = stage(sim, dt, 0, &moved)))
        return st;
    if ((st = evaluate(sim)))
        return st;
    if ((st = stage(sim, dt, 1, &moved))) {
        undo_step(sim);
        return st;
    }
    sim->rates_valid = 0;
    sim->t += dt;
    sim->step++;
    if ((st = wrap_and_check_domain(sim)))
        return st;
    sim->nl.displacement_bound += moved;
    if (sim->nl.displacement_bound > 0.5 * sim->nl.skin)
        if ((st = neighbour_build(sim)))
            return st;
    if (sim->out && (st = output_write_due(sim)))
        return st;
    return SPH_OK;
}

static sph_status run_steps(sph_sim *sim, long steps, double t_end)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    sph_status st = sim_prepare(sim);
    if (st)
        return st;
    sim->failed = 0;
    const double dt = sim->dt;
    long done = 0;
    for (;;) {
        double h = dt;
        if (steps >= 0) {
            if (done >= steps)
                break;
        } else {
            const double left = t_end - sim->t;
            if (left <= 1e-12 * dt)
                break;
            if (left < dt * (1.0 + 1e-9))
                h = left;
        }
        if ((st = one_step(sim, h)))
            return st;
        if (steps < 0 && h != dt)
            sim->t = t_end;
        ++done;
        if (sim->progress && sim->progress_interval > 0 &&
            sim->step % sim->progress_interval == 0 &&
            sim->progress(sim, sim->progress_user))
            return sph_fail(sim, SPH_ERR_STOPPED, "stopped by the progress callback at step %ld (t = %.9g s)",
                            sim->step, sim->t);
    }
    return sph_ok(sim);
}

sph_status sph_run(sph_sim *sim, long steps)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (steps < 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "steps=%ld: must be >= 0", steps);
    return run_steps(sim, steps, 0.0);
}

sph_status sph_run_until(sph_sim *sim, double t)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!isfinite(t) || t < sim->t)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "until t=%g s: must be finite and not before the current time %g s", t, sim->t);
    return run_steps(sim, -1, t);
}

sph_status sph_set_progress(sph_sim *sim, long interval, sph_progress_fn fn, void *user)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (fn && interval <= 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "progress interval=%ld: must be > 0", interval);
    sim->progress_interval = interval;
    sim->progress = fn;
    sim->progress_user = user;
    return sph_ok(sim);
}

sph_status sph_failure(const sph_sim *sim, long *step, long *particle, int *body_id, const char **quantity)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (sim->failed != 1)
        return SPH_ERR_STATE;
    if (step) *step = sim->fail_step;
    if (particle) *particle = sim->fail_particle;
    if (body_id) *body_id = sim->fail_body;
    if (quantity) *quantity = sim->fail_quantity;
    return SPH_OK;
}
