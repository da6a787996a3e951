/*
 * Pieces of a time step shared by every integrator: rigid bodies under an
 * applied force (sph_rigid_force_sum/_apply), the watchdog (bounds, report,
 * sph_watchdog_check on caller arrays), per-body constants of a step,
 * prescribed rotations on exact arcs, and the report of a failed step.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/integrator.h"

sph_status sph_rigid_force_sum(sph_sim *sim, size_t n, const double *mass, const double *dv_dt,
                               const unsigned char *member, double *sums)
{
    sph_status st = sph_need(sim, sums, "sph_rigid_force_sum", "sums");
    if (st)
        return st;
    if (n > 0 && (!mass || !dv_dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_rigid_force_sum: mass and dv_dt must not be NULL");
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

sph_status sph_rigid_force_apply(sph_sim *sim, size_t n, const double *applied, const double *sums,
                                 const unsigned char *member, double *dv_dt)
{
    sph_status st = sph_need(sim, applied, "sph_rigid_force_apply", "applied");
    if (st || (st = sph_need(sim, sums, "sph_rigid_force_apply", "sums")))
        return st;
    if (n > 0 && !dv_dt)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rigid_force_apply: dv_dt must not be NULL");
    if (!(sums[0] > 0.0) || !isfinite(sums[0]))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_rigid_force_apply: total mass %g of the body must be finite and > 0",
                        sums[0]);
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

/* ------------------------------------------------------------- watchdog */

/* The watchdog's report for particle a of external arrays, which tripped
 * it: its speed if that is above the bound, else its density ratio. */
sph_status watchdog_report(sph_sim *sim, long a, int dim, const double *v_a, double rho_a,
                           const material *m, int integrate)
{
    double vmax2, rho_lo, rho_hi, v2 = 0.0;
    watchdog_bounds(sim, m, integrate, &vmax2, &rho_lo, &rho_hi);
    for (int i = 0; i < dim; ++i)
        v2 += v_a[i] * v_a[i];
    if (v2 > vmax2)
        return sph_fail(
            sim, SPH_ERR_UNSTABLE,
            "particle %ld moves at %g m/s, more than %g times the P-wave speed %g m/s (watchdog)",
            a, sqrt(v2), sim->watch_speed, m->c_p);
    return sph_fail(sim, SPH_ERR_UNSTABLE,
                    "particle %ld has density ratio rho/rho0 = %g outside [%g, %g] (watchdog)", a,
                    rho_a / m->rho0, sim->watch_rho_min, sim->watch_rho_max);
}

sph_status stage_outcome(sph_sim *sim, const char *failure, long n, long bad, long wild,
                         long *particle, const stage_arrays *a)
{
    if (particle)
        *particle = bad < n ? bad : wild < n ? wild : -1;
    if (bad < n)
        return sph_fail(sim, SPH_ERR_NONFINITE, "%s at particle %ld", failure, bad);
    if (wild < n)
        return watchdog_report(sim, wild, sim->dim, a->v + wild * (long)a->stride, a->rho[wild],
                               &sim->materials[a->material_of[wild]],
                               a->integrate_motion ? a->integrate_motion[wild] : 1);
    return SPH_OK;
}

sph_status sph_watchdog_check(sph_sim *sim, size_t n, const double *v, const double *rho,
                              const int *material_of, const unsigned char *integrate_motion,
                              long *particle)
{
    sph_status st = sph_need(sim, particle, "sph_watchdog_check", "particle");
    if (st)
        return st;
    *particle = -1;
    const void *const arrays[] = {v, rho, material_of};
    if ((st = caller_arrays(sim, "sph_watchdog_check", n, material_of, "v, rho and material",
                            arrays, 3)))
        return st;
    const int dim = sim->dim;
    for (size_t a = 0; a < n; ++a) {
        const material *m = &sim->materials[material_of[a]];
        double vmax2, rho_lo, rho_hi;
        watchdog_bounds(sim, m, integrate_motion ? integrate_motion[a] : 1, &vmax2, &rho_lo,
                        &rho_hi);
        if (!watchdog_trips(dim, v + a * dim, rho[a], vmax2, rho_lo, rho_hi))
            continue;
        *particle = (long)a;
        return watchdog_report(sim, (long)a, dim, v + a * dim, rho[a], m,
                               integrate_motion ? integrate_motion[a] : 1);
    }
    return SPH_OK;
}

/* --------------------------------------------------- bodies in a step */

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

void body_stage_rotation(body_stage *b, double dt)
{
    if (b->rotate)
        rotation_matrix(b->omega, dt, b->R);
}

sph_status body_stages_make(sph_sim *sim, double dt_rotation, body_stage *small, body_stage **out)
{
    body_stage *bs = sim->n_bodies <= 8 ? small : malloc((size_t)sim->n_bodies * sizeof *bs);
    *out = bs;
    if (!bs)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %d body records", sim->n_bodies);
    for (int k = 0; k < sim->n_bodies; ++k) {
        const body *b = &sim->bodies[k];
        const material *m = &sim->materials[b->material];
        bs[k].integrate = b->motion == SPH_MOTION_FREE || b->motion == SPH_MOTION_FORCE;
        bs[k].rotate = b->motion == SPH_MOTION_ROTATION;
        bs[k].omega = b->vector;
        memcpy(bs[k].c, b->centre, sizeof bs[k].c);
        body_stage_rotation(&bs[k], dt_rotation);
        watchdog_bounds(sim, m, bs[k].integrate, &bs[k].vmax2, &bs[k].rho_lo, &bs[k].rho_hi);
    }
    return SPH_OK;
}

void body_stages_free(body_stage *bs, const body_stage *small)
{
    if (bs != small)
        free(bs);
}

/* A particle of a rotating body: x = c + R (x_n - c) (the exact arc) and
 * v = omega x (x - c).  Returns the distance moved from x_n. */
double rotate_particle(int dim, const body_stage *b, const double *x_n, double *x, double *v)
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

sph_status step_failure(sph_sim *sim, double dt, long first_bad, long first_wild)
{
    const int dim = sim->dim;
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
        return sph_fail(
            sim, SPH_ERR_NONFINITE, "step %ld (t = %.9g s): particle %ld of body '%s' has a %s %s",
            sim->fail_step, sim->t + dt, sim->fail_particle, sim->bodies[sim->fail_body].name,
            what[0] == 'd' && what[1] == 'e' && what[2] == 'n' ? "non-positive or non-finite"
                                                               : "non-finite",
            what);
    }
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
                        "step %ld (t = %.9g s): particle %ld of body '%s' moves at %g m/s, more "
                        "than %g times the P-wave speed %g m/s (watchdog; see sph_set_watchdog)",
                        sim->fail_step, sim->t + dt, sim->fail_particle,
                        sim->bodies[sim->fail_body].name, sqrt(v2), sim->watch_speed, m->c_p);
    return sph_fail(sim, SPH_ERR_UNSTABLE,
                    "step %ld (t = %.9g s): particle %ld of body '%s' has density ratio rho/rho0 = "
                    "%g outside [%g, %g] (watchdog; see sph_set_watchdog)",
                    sim->fail_step, sim->t + dt, sim->fail_particle,
                    sim->bodies[sim->fail_body].name, sim->rho[a] / m->rho0, sim->watch_rho_min,
                    sim->watch_rho_max);
}
