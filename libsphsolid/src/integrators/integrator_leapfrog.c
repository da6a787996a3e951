/*
 * Leapfrog (kick-drift-kick, velocity Verlet) with the density and the
 * deviatoric stress advanced by the same half-step velocity that moves the
 * positions.  With y = (rho, S), D(x, v, y) their rates (the continuity
 * pass of the rate engine) and a(x, v, y) the acceleration (its momentum
 * pass):
 *
 *   v_{n+1/2} = v_n + dt/2 a_n                                       kick
 *   x_{n+1/2} = x_n + dt/2 v_{n+1/2},  y~ = y_n + dt/2 D_{n-1/2}  half drift
 *   D_{n+1/2} = D(x_{n+1/2}, v_{n+1/2}, y~)                 continuity pass
 *   x_{n+1}   = x_n + dt v_{n+1/2},    y_{n+1} = y_n + dt D_{n+1/2}   drift
 *   a_{n+1}   = a(x_{n+1}, v_{n+1/2}, y_{n+1})                momentum pass
 *   v_{n+1}   = v_{n+1/2} + dt/2 a_{n+1}                             kick
 *
 * Each pass visits every pair once and computes only its own terms, so a
 * step costs about one whole rate evaluation (the kernel gradient of each
 * pair is computed twice, everything else once).  a_{n+1} and D_{n+1/2}
 * start the next step, so they are carried from one run to the next (and
 * written to checkpoints); a step that finds no carried rates (the first
 * one, or after the state was changed from outside) evaluates both at y_n
 * and predicts with D_n.
 *
 * Why the rates are taken at two states: rho and S are integrals of the
 * velocity gradient, as positions are integrals of the velocity.
 * Advancing them with the velocity gradient of the very velocity v_{n+1/2}
 * that drifts the positions keeps them a function of the positions in the
 * linear regime, so the scheme is velocity Verlet for a potential energy of
 * the positions: symplectic, with no drift of the total energy and a
 * stability limit dt < 2/omega_max (docs/library.md).  That velocity is
 * known only after the acceleration of the same step, so D cannot come
 * from the pass that gives the acceleration.
 *
 * The predictor y~ (the half-step density and stress, used only for the
 * volumes m/rho and the Jaumann terms S.W of the continuity pass) takes the
 * rates D_{n-1/2} of the previous step's continuity pass, which differ from
 * D_n by O(dt): y~ is off by O(dt^2) either way, D_{n+1/2} by O(dt^2), and
 * y_{n+1} by O(dt^3) per step, so the scheme stays second order.  In the
 * linear regime about a state at rest D does not depend on y at all (drho/dt
 * = sum m_b v_ab.grad W_ab; the volume and Jaumann terms are products of two
 * small quantities), so the predictor drops out: the linearised scheme, its
 * symplectic structure and its stable step are those of velocity Verlet.
 *
 * Velocity-dependent accelerations (artificial viscosity, damping) are taken
 * at v_{n+1/2}.  With XSPH the positions drift with the XSPH velocity of
 * the continuity pass.  Prescribed velocities keep their velocity;
 * prescribed rotations move on their exact arcs (half and whole angle);
 * force-driven bodies kick with the body's acceleration.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/integrator.h"

static size_t leapfrog_saved_values(int dim, int ncomp, int xsph)
{
    (void)xsph;
    return (size_t)dim + 1 + (size_t)ncomp; /* v_n, rho_n, S_n */
}

static void leapfrog_undo(sph_sim *sim)
{
    const size_t n = sim->n, dim = (size_t)sim->dim, nc = (size_t)sim->ncomp;
    memcpy(sim->x, sim->x_saved, n * dim * sizeof(double));
    memcpy(sim->v, sim->saved, n * dim * sizeof(double));
    memcpy(sim->rho, sim->saved + n * dim, n * sizeof(double));
    memcpy(sim->S, sim->saved + n * (dim + 1), n * nc * sizeof(double));
}

static sph_status leapfrog_step(sph_sim *sim, double dt, double *moved)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const long n = (long)sim->n;
    double *x = sim->x, *v = sim->v, *rho = sim->rho, *S = sim->S, *x_n = sim->x_saved;
    double *v_n = sim->saved, *rho_n = v_n + n * dim, *S_n = rho_n + n;
    const int *body_of = sim->body_of;
    sph_status st;
    if (!sim->rates_valid && (st = sim_evaluate(sim)))
        return st;
    body_stage small[8], *bs;
    if ((st = body_stages_make(sim, 0.5 * dt, small, &bs)))
        return st;

    /* kick, half drift, half-step density and stress */
    double half = 0.0;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(max : half)
    for (long a = 0; a < n; ++a) {
        const body_stage *b = &bs[body_of[a]];
        double *xa = x + a * dim, *va = v + a * dim;
        double d2 = 0.0;
        for (int i = 0; i < dim; ++i) {
            x_n[a * dim + i] = xa[i];
            v_n[a * dim + i] = va[i];
            if (b->integrate)
                va[i] += 0.5 * dt * sim->dv_dt[a * dim + i];
        }
        if (b->rotate) {
            d2 = rotate_particle(dim, b, x_n + a * dim, xa, va);
            d2 *= d2;
        } else {
            for (int i = 0; i < dim; ++i) {
                const double step = 0.5 * dt * va[i];
                xa[i] += step;
                d2 += step * step;
            }
        }
        rho_n[a] = rho[a];
        rho[a] += 0.5 * dt * sim->drho_dt[a];
        for (int c = 0; c < nc; ++c) {
            S_n[a * nc + c] = S[a * nc + c];
            S[a * nc + c] += 0.5 * dt * sim->dS_dt[a * nc + c];
        }
        if (d2 > half)
            half = d2;
    }
    half = sqrt(half);
    /* a list rebuilt here has a zero bound, which the caller's addition of
     * the whole step's displacement from x_n then over-estimates */
    if ((st = sim_ensure_neighbours(sim, half)) || (st = sim_evaluate_pass(sim, PASS_CONTINUITY))) {
        body_stages_free(bs, small);
        leapfrog_undo(sim);
        return st;
    }

    /* drift: whole step of positions, density and stress */
    for (int k = 0; k < sim->n_bodies; ++k)
        body_stage_rotation(&bs[k], dt);
    const double *u = sim->fx.xsph ? sim->dx_dt : v;
    double max_moved = 0.0;
    long bad = n, wild = n;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(min : bad, wild) \
    reduction(max : max_moved)
    for (long a = 0; a < n; ++a) {
        const body_stage *b = &bs[body_of[a]];
        double *xa = x + a * dim;
        double d = 0.0, ok = 1.0;
        if (b->rotate) {
            double v_arc[3];
            d = rotate_particle(dim, b, x_n + a * dim, xa, v_arc);
        } else {
            double d2 = 0.0;
            for (int i = 0; i < dim; ++i) {
                const double step = dt * (b->integrate ? u[a * dim + i] : v[a * dim + i]);
                xa[i] = x_n[a * dim + i] + step;
                d2 += step * step;
            }
            d = sqrt(d2);
        }
        for (int i = 0; i < dim; ++i)
            ok *= isfinite(xa[i]);
        ok *= drift_state(nc, dt, rho_n[a], S_n + a * nc, sim->drho_dt[a], sim->dS_dt + a * nc,
                          rho + a, S + a * nc);
        if (!ok) {
            if (a < bad)
                bad = a;
        } else if ((rho[a] < b->rho_lo || rho[a] > b->rho_hi) && a < wild) {
            wild = a; /* the watchdog's density bounds, before anything overflows */
        }
        if (d > max_moved)
            max_moved = d;
    }
    if (bad < n || wild < n) {
        st = step_failure(sim, dt, bad < n ? bad : -1, wild < n ? wild : -1);
        body_stages_free(bs, small);
        leapfrog_undo(sim);
        return st;
    }
    if ((st = sim_evaluate_pass(sim, PASS_MOMENTUM))) {
        body_stages_free(bs, small);
        leapfrog_undo(sim);
        return st;
    }

    /* kick; rotating particles take the velocity of their new position */
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(min : bad, wild)
    for (long a = 0; a < n; ++a) {
        const body_stage *b = &bs[body_of[a]];
        double *va = v + a * dim;
        double ok = 1.0;
        if (b->integrate)
            for (int i = 0; i < dim; ++i)
                va[i] += 0.5 * dt * sim->dv_dt[a * dim + i];
        else if (b->rotate)
            rotation_velocity(dim, b->omega, b->c, x + a * dim, va);
        for (int i = 0; i < dim; ++i)
            ok *= isfinite(va[i]);
        if (!ok) {
            if (a < bad)
                bad = a;
        } else if (watchdog_trips(dim, va, rho[a], b->vmax2, b->rho_lo, b->rho_hi) && a < wild) {
            wild = a;
        }
    }
    body_stages_free(bs, small);
    if (bad < n || wild < n) {
        st = step_failure(sim, dt, bad < n ? bad : -1, wild < n ? wild : -1);
        leapfrog_undo(sim);
        return st;
    }
    *moved = max_moved;
    return SPH_OK;
}

/* Linear stability of the scheme: velocity Verlet is stable for
 * dt omega_max < 2.  Linearised about a lattice at rest, the SPH gradient of
 * a plane wave exp(i k.x) is i g(k) with g(k) = sum_b V_b sin(k.r_ab)
 * grad W(r_ab), for the velocity gradient and the momentum equation alike,
 * so omega(k) = c_p |g(k)| for the fastest (longitudinal) wave and
 * dt < 2 / (c_p max_k |g(k)|).  On the square lattice max |g| h = 1.07 for
 * the cubic spline and 1.10 for Wendland C2 at h/dx = 1.2, 1.07 and 1.13 at
 * h/dx = 1.5 (docs/library.md); the factor below, 2 / 1.13 rounded down,
 * covers both kernels and ratios, with |v| added to c_p as for Improved
 * Euler. */
const integrator integrator_leapfrog = INTEGRATOR_RECORD(
    "leapfrog",
    "kick-drift-kick leapfrog (velocity Verlet), density and stress advanced with the half-step "
    "velocity: symplectic, one evaluation's pair work per step (continuity pass at the half "
    "step, momentum pass at the end), stable without viscosity up to 1.75 h/(c_p + |v|), with "
    "artificial viscosity alpha up to that / (1 + kappa alpha) of the kernel (cubic_o4: 0.85)",
    /* evaluations */ 1, /* stable */ 1.75, /* default */ 1.0, /* viscosity shortens step */ 1,
    leapfrog_saved_values, leapfrog_step, /* carries rates */ 1);

/* ------------------------------------------------ stages on caller arrays */

static sph_status leapfrog_args(sph_sim *sim, size_t n, double dt, size_t stride, const void *a,
                                const void *b, const void *c, const void *d, const void *e)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(dt > 0.0) || !isfinite(dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "dt=%g: must be finite and > 0", dt);
    if (stride < (size_t)sim->dim)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "stride=%zu is smaller than the dimension %d",
                        stride, sim->dim);
    if (n > 0 && (!a || !b || !c || !d || !e))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "leapfrog stage: an array argument is NULL");
    return SPH_OK;
}

/* Whether a particle of material `m` trips the watchdog: its density
 * bounds, and with a velocity v its speed too. */
static int trips(const sph_sim *sim, int m, int integrate, const double *v, double rho)
{
    double vmax2, lo, hi;
    watchdog_bounds(sim, &sim->materials[m], integrate, &vmax2, &lo, &hi);
    return v ? watchdog_trips(sim->dim, v, rho, vmax2, lo, hi) : rho < lo || rho > hi;
}

/* The watchdog's verdict on particle a after a stage: the first particle
 * with a non-finite value (bad) or past a bound (wild), lowest index wins. */
static void watch(const sph_sim *sim, long a, double ok, int m, int integrate, const double *v,
                  double rho, long *bad, long *wild)
{
    if (!ok) {
        if (a < *bad)
            *bad = a;
    } else if (a < *wild && trips(sim, m, integrate, v, rho)) {
        *wild = a;
    }
}

sph_status sph_leapfrog_begin_strided(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                      size_t stride, double *rho, double *S, const sph_rates *r,
                                      const unsigned char *integrate_motion, double *saved)
{
    sph_status st = leapfrog_args(sim, n, dt, stride, x, v, rho, S, saved);
    if (st ||
        (n > 0 && (st = leapfrog_args(sim, n, dt, stride, r, r->dv_dt, r->drho_dt, r->dS_dt, r))))
        return st;
    const int dim = sim->dim, nc = sim->ncomp;
    double *x_n = saved, *rho_n = saved + n * dim, *S_n = rho_n + n;
    const long nn = (long)n;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim))
    for (long a = 0; a < nn; ++a) {
        const int integrate = integrate_motion ? integrate_motion[a] : 1;
        double *xa = x + a * stride, *va = v + a * stride;
        for (int i = 0; i < dim; ++i) {
            x_n[a * dim + i] = xa[i];
            if (integrate)
                va[i] += 0.5 * dt * r->dv_dt[a * dim + i];
            xa[i] += 0.5 * dt * va[i];
        }
        rho_n[a] = rho[a];
        rho[a] += 0.5 * dt * r->drho_dt[a];
        for (int c = 0; c < nc; ++c) {
            S_n[a * nc + c] = S[a * nc + c];
            S[a * nc + c] += 0.5 * dt * r->dS_dt[a * nc + c];
        }
    }
    return SPH_OK;
}

sph_status sph_leapfrog_drift_strided(sph_sim *sim, size_t n, double dt, double *x, const double *v,
                                      size_t stride, double *rho, double *S, const sph_rates *r,
                                      const unsigned char *integrate_motion, const double *saved,
                                      const int *material_of, long *particle)
{
    if (particle)
        *particle = -1;
    sph_status st = leapfrog_args(sim, n, dt, stride, x, v, rho, S, saved);
    if (st || (n > 0 &&
               (st = leapfrog_args(sim, n, dt, stride, r, r->drho_dt, r->dS_dt, material_of, r))))
        return st;
    const int dim = sim->dim, nc = sim->ncomp;
    const double *x_n = saved, *rho_n = saved + n * dim, *S_n = rho_n + n;
    const long nn = (long)n;
    long bad = nn, wild = nn;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(min : bad, wild)
    for (long a = 0; a < nn; ++a) {
        const int integrate = integrate_motion ? integrate_motion[a] : 1;
        const double *u = integrate && r->dx_dt ? r->dx_dt + a * dim : v + a * stride;
        double *xa = x + a * stride, ok = 1.0;
        for (int i = 0; i < dim; ++i) {
            /* the caller moves the others (from x_n, as they were) */
            xa[i] = integrate ? x_n[a * dim + i] + dt * u[i] : x_n[a * dim + i];
            ok *= isfinite(xa[i]);
        }
        ok *= drift_state(nc, dt, rho_n[a], S_n + a * nc, r->drho_dt[a], r->dS_dt + a * nc, rho + a,
                          S + a * nc);
        watch(sim, a, ok, material_of[a], integrate, NULL, rho[a], &bad, &wild);
    }
    const stage_arrays out = {v, stride, rho, material_of, integrate_motion};
    return stage_outcome(sim,
                         "leapfrog drift produced a non-finite value (or non-positive density)", nn,
                         bad, wild, particle, &out);
}

sph_status sph_leapfrog_end_strided(sph_sim *sim, size_t n, double dt, double *v, size_t stride,
                                    const double *rho, const double *dv_dt,
                                    const unsigned char *integrate_motion, const int *material_of,
                                    long *particle)
{
    if (particle)
        *particle = -1;
    sph_status st = leapfrog_args(sim, n, dt, stride, v, rho, dv_dt, material_of, v);
    if (st)
        return st;
    const int dim = sim->dim;
    const long nn = (long)n;
    long bad = nn, wild = nn;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(min : bad, wild)
    for (long a = 0; a < nn; ++a) {
        const int integrate = integrate_motion ? integrate_motion[a] : 1;
        double *va = v + a * stride, ok = 1.0;
        if (integrate)
            for (int i = 0; i < dim; ++i)
                va[i] += 0.5 * dt * dv_dt[a * dim + i];
        for (int i = 0; i < dim; ++i)
            ok *= isfinite(va[i]);
        watch(sim, a, ok, material_of[a], integrate, va, rho[a], &bad, &wild);
    }
    const stage_arrays out = {v, stride, rho, material_of, integrate_motion};
    return stage_outcome(sim, "leapfrog kick produced a non-finite velocity", nn, bad, wild,
                         particle, &out);
}
