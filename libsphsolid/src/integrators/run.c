/*
 * The run driver: storage for the handle's integrator, one rate evaluation
 * with the bodies' motions applied, and the loop of steps (landing exactly
 * on a time, periodic wrap and domain check, neighbour list upkeep, output,
 * progress, undo of a failed step).  The step itself is the integrator's
 * (integrator.h).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/integrator.h"

sph_status sim_prepare(sph_sim *sim)
{
    if (sim->failed == -1)
        return sph_fail(sim, SPH_ERR_STATE,
                        "this handle's creation failed (sph_create: an invalid dimension or "
                        "SPHSOLID_RATE_PATH)");
    if (sim->n == 0)
        return sph_fail(sim, SPH_ERR_STATE, "the simulation has no particles: add a body first");
    sph_status checked = state_check(sim);
    if (checked)
        return checked;
    if (!sim->dt_set)
        sim->dt = sph_default_dt(sim);
    sim_shrink_to_fit(sim);
    const size_t n = sim->n;
    const int dim = sim->dim, nc = sim->ncomp;
    const size_t saved_per = sim_integrator(sim)->saved_values(dim, nc, sim->fx.xsph);
    /* every buffer of the run follows the particle count: bodies may have
     * been added since the last run */
    double *saved = realloc(sim->saved, n * saved_per * sizeof(double));
    double *dv = realloc(sim->dv_dt, n * dim * sizeof(double));
    double *dr = realloc(sim->drho_dt, n * sizeof(double));
    double *dS = realloc(sim->dS_dt, n * nc * sizeof(double));
    double *xs = realloc(sim->x_saved, n * dim * sizeof(double));
    if (xs)
        sim->x_saved = xs;
    if (saved) {
        sim->saved = saved;
        sim->saved_per = saved_per;
    }
    if (dv)
        sim->dv_dt = dv;
    if (dr)
        sim->drho_dt = dr;
    if (dS)
        sim->dS_dt = dS;
    if (!saved || !dv || !dr || !dS || !xs)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate integrator storage for %zu particles",
                        n);
    if (sim->fx.xsph) {
        if (!sim->dx_dt)
            sim->carry_valid = 0;
        double *dx = realloc(sim->dx_dt, n * dim * sizeof(double));
        if (!dx)
            return sph_fail(sim, SPH_ERR_MEMORY,
                            "cannot allocate XSPH velocities for %zu particles", n);
        sim->dx_dt = dx;
    } else {
        free(sim->dx_dt);
        sim->dx_dt = NULL;
    }
    for (int k = 0; k < sim->n_bodies; ++k)
        for (int i = 0; i < dim && sim->bodies[k].motion == SPH_MOTION_ROTATION; ++i)
            if (sim->has_domain && sim->periodic[i])
                return sph_fail(sim, SPH_ERR_STATE,
                                "body '%s' rotates (sph_set_rotation), which needs a domain "
                                "without periodic axes (%c is periodic)",
                                sim->bodies[k].name, "xyz"[i]);
    sim->nl.skin = 0.25 * sim->h;
    const double rc = 2.0 * sim->h + sim->nl.skin;
    for (int i = 0; i < dim; ++i)
        if (sim->has_domain && sim->periodic[i] && sim->hi[i] - sim->lo[i] < 2.0 * rc)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "periodic length along %c is %g m, shorter than twice the neighbour "
                            "cutoff 2h + skin = %g m",
                            "xyz"[i], sim->hi[i] - sim->lo[i], rc);
    if (!sim->nl.valid || sim->nl.n != n) {
        sph_status st = neighbour_build(sim);
        if (st)
            return st;
        sim->nl_builds++;
    }
    return damage_prepare(sim);
}

/* The neighbour list stays valid while every particle moved less than
 * skin/2 since it was built; `extra` is a bound of a displacement about to
 * be made on top of the recorded one. */
sph_status sim_ensure_neighbours(sph_sim *sim, double extra)
{
    if (sim->nl.displacement_bound + extra > 0.5 * sim->nl.skin) {
        sim->nl_builds++;
        return neighbour_build(sim);
    }
    return SPH_OK;
}

sph_status sim_evaluate(sph_sim *sim) { return sim_evaluate_pass(sim, PASS_ALL); }

sph_status sim_evaluate_pass(sph_sim *sim, int pass)
{
    sph_status st = rates_of_handle(sim, pass);
    if (st || !(pass & PASS_MOMENTUM))
        return st;
    if (sim->energy_account) /* before the prescribed motions override dv/dt */
        energy_account_evaluation(sim);
    /* Prescribed motions: no acceleration; force-driven bodies translate
     * rigidly under the applied force plus the SPH forces on them. */
    const int dim = sim->dim;
    for (int k = 0; k < sim->n_bodies; ++k) {
        const body *b = &sim->bodies[k];
        if (b->motion == SPH_MOTION_FIXED || b->motion == SPH_MOTION_VELOCITY) {
            double *F = sim->bodies[k].reaction; /* the force the motion overrides */
            F[0] = F[1] = F[2] = 0.0;
            for (size_t a = b->first; a < b->first + b->count; ++a)
                for (int i = 0; i < dim; ++i)
                    F[i] += sim->mass[a] * sim->dv_dt[a * dim + i];
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
                                "step %ld (t = %.9g s): particle %zu of body '%s' left the domain "
                                "along %c (%c=%g, domain [%g, %g])",
                                sim->step, sim->t, a, sim->bodies[sim->body_of[a]].name, "xyz"[i],
                                "xyz"[i], *xi, sim->lo[i], sim->hi[i]);
            }
        }
    return SPH_OK;
}

/* A failed step has put back the state at its start (the last good state);
 * write it to the output file if one is open. */
static void after_undo(sph_sim *sim)
{
    sim->rates_valid = 0;
    sim->carry_valid = 0;
    sim->power_carry_valid = 0;
    if (sim->out) {
        char message[SPH_ERRMSG_SIZE];
        memcpy(message, sim->errmsg, sizeof message);
        sph_output_snapshot(sim);
        memcpy(sim->errmsg, message, sizeof message);
    }
}

static sph_status one_step(sph_sim *sim, const integrator *in, double dt)
{
    double moved = 0.0;
    /* the powers of this step's evaluations only, opened by those of the
     * rates the step starts from if it does not evaluate them again (the
     * leapfrog: its trapezoid) */
    if (sim->energy_account)
        energy_account_open(sim, in->carries_rates && sim->rates_valid);
    sph_status st = in->step(sim, dt, &moved);
    if (st) {
        after_undo(sim);
        return st;
    }
    sim->rates_valid = in->carries_rates;
    if (sim->fx.damage) {
        /* operator split: flaws activate and D grows on the step's end
         * state; rates carried from before the growth are stale */
        int grew = 0;
        if ((st = damage_stage(sim, dt, &grew)))
            return st;
        if (grew)
            sim->rates_valid = 0;
    }
    if (sim->fx.drucker_prager) {
        /* the same split: the deviator returned onto the cone at the end
         * state (on the damaged stress when damage is on) */
        int returned = 0;
        if ((st = plastic_stage(sim, &returned)))
            return st;
        if (returned)
            sim->rates_valid = 0;
    }
    if (sim->energy_account)
        energy_account_step(sim, dt);
    sim->t += dt;
    sim->step++;
    if ((st = wrap_and_check_domain(sim)))
        return st;
    sim->nl.displacement_bound += moved;
    if ((st = sim_ensure_neighbours(sim, 0.0)))
        return st;
    if (sim->out && (st = output_write_due(sim)))
        return st;
    return SPH_OK;
}

/* Whole steps of dt from the handle's time towards t, and the length of the
 * last, shortened step that lands on t (0: none): the clock of the run,
 * step by step, as run_steps advances it. */
static void steps_until(const sph_sim *sim, double t, double dt, long *whole, double *last)
{
    double now = sim->t;
    long n = 0;
    *last = 0.0;
    for (;;) {
        const double left = t - now;
        if (left <= 1e-12 * dt)
            break;
        if (left < dt * (1.0 + 1e-9)) {
            *last = left;
            break;
        }
        now += dt;
        ++n;
    }
    *whole = n;
}

sph_status sph_steps_until(sph_sim *sim, double t, long *whole, double *last)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!whole)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_steps_until: whole is NULL");
    if (!last)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_steps_until: last is NULL");
    if (!isfinite(t) || t < sim->t)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "until t=%g s: must be finite and not before the current time %g s", t,
                        sim->t);
    const double dt = sph_dt(sim);
    if (!(dt > 0.0))
        return sph_fail(sim, SPH_ERR_STATE,
                        "until t=%g s: the time step is not known yet (add a body)", t);
    steps_until(sim, t, dt, whole, last);
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
    const integrator *in = sim_integrator(sim);
    const double dt = sim->dt;
    double last = 0.0;
    if (steps < 0)
        steps_until(sim, t_end, dt, &steps, &last);
    if (in->carries_rates) {
        sim->rates_valid = carried_rates_valid(sim);
        if (!sim->rates_valid) /* their powers went with them */
            sim->power_carry_valid = 0;
    }
    for (long done = 0; done < steps + (last > 0.0); ++done) {
        const int shortened = done == steps;
        if ((st = one_step(sim, in, shortened ? last : dt)))
            return st;
        if (shortened)
            sim->t = t_end;
        if (sim->progress && sim->progress_interval > 0 &&
            sim->step % sim->progress_interval == 0 && sim->progress(sim, sim->progress_user)) {
            if (in->carries_rates)
                carried_rates_set(sim);
            return sph_fail(sim, SPH_ERR_STOPPED,
                            "stopped by the progress callback at step %ld (t = %.9g s)", sim->step,
                            sim->t);
        }
    }
    if (in->carries_rates && sim->rates_valid)
        carried_rates_set(sim);
    return sph_ok(sim);
}

sph_status sph_body_reaction(sph_sim *sim, int body, double force[3])
{
    sph_status st = sph_need(sim, force, "sph_body_reaction", "force");
    if (st)
        return st;
    if (body < 0 || body >= sim->n_bodies)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_body_reaction: body=%d: %d bodies are defined",
                        body, sim->n_bodies);
    memcpy(force, sim->bodies[body].reaction, 3 * sizeof(double));
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
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "until t=%g s: must be finite and not before the current time %g s", t,
                        sim->t);
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

sph_status sph_failure(const sph_sim *sim, long *step, long *particle, int *body_id,
                       const char **quantity)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (sim->failed != 1)
        return SPH_ERR_STATE;
    if (step)
        *step = sim->fail_step;
    if (particle)
        *particle = sim->fail_particle;
    if (body_id)
        *body_id = sim->fail_body;
    if (quantity)
        *quantity = sim->fail_quantity;
    return SPH_OK;
}
