/* Time steps: stable and default step, the clock. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/integrator.h"
#include "physics/kernel.h"
#include "core/sim.h"

/* ------------------------------------------------------------ time steps */

/* Largest P-wave speed plus particle speed; with no particles (a handle for
 * external particles) the largest P-wave speed of the materials. */
static double signal_speed(const sph_sim *sim)
{
    double speed = 0.0;
    if (sim->n == 0) {
        for (int m = 0; m < sim->n_materials; ++m)
            speed = fmax(speed, sim->materials[m].c_p);
        return speed;
    }
    for (size_t a = 0; a < sim->n; ++a) {
        double v2 = 0.0;
        for (int i = 0; i < sim->dim; ++i)
            v2 += sim->v[a * sim->dim + i] * sim->v[a * sim->dim + i];
        speed = fmax(speed, sim->materials[sim->material_of[a]].c_p + sqrt(v2));
    }
    return speed;
}

/* What artificial viscosity divides the stable step by: 1 + kappa alpha
 * (kernel.h) for an integrator whose stable factor was measured without
 * it, else 1. */
static double viscous_divisor(const sph_sim *sim)
{
    if (!sim_integrator(sim)->viscosity_shortens_step || !sim->fx.artificial_viscosity)
        return 1.0;
    return 1.0 + kernel_viscous_kappa(sim->kernel) * sim->fx.artificial_viscosity_alpha;
}

/* The default step keeps this share of a stable step that viscosity
 * shortened (the measured limit is an edge, not a margin). */
#define VISCOUS_DEFAULT_SHARE 0.8

double sph_stable_dt(const sph_sim *sim)
{
    if (!sim || sim->h <= 0.0)
        return 0.0;
    const double speed = signal_speed(sim);
    return speed > 0.0 ? sim_integrator(sim)->stable_factor * sim->h *
                             kernel_step_length(sim->kernel) / (speed * viscous_divisor(sim))
                       : 0.0;
}

double sph_default_dt(const sph_sim *sim)
{
    if (!sim || sim->h <= 0.0)
        return 0.0;
    /* the bodies' materials, or every material of a handle without bodies */
    double c0 = 0.0;
    for (int b = 0; b < sim->n_bodies; ++b)
        c0 = fmax(c0, sim->materials[sim->bodies[b].material].c0);
    if (sim->n_bodies == 0)
        for (int m = 0; m < sim->n_materials; ++m)
            c0 = fmax(c0, sim->materials[m].c0);
    if (c0 <= 0.0)
        return 0.0;
    const double dt =
        sim_integrator(sim)->default_factor * sim->h * kernel_step_length(sim->kernel) / c0;
    double stable = sph_stable_dt(sim);
    if (viscous_divisor(sim) > 1.0)
        stable *= VISCOUS_DEFAULT_SHARE;
    return dt < stable ? dt : stable;
}

sph_status sph_set_dt(sph_sim *sim, double dt, int allow_unstable)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(dt > 0.0) || !isfinite(dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "dt=%g: must be finite and > 0", dt);
    const double stable = sph_stable_dt(sim);
    if (stable <= 0.0)
        return sph_fail(sim, SPH_ERR_STATE, "dt=%g: add bodies before setting the time step", dt);
    if (dt > stable && !allow_unstable) {
        const double divisor = viscous_divisor(sim);
        return sph_fail(
            sim, SPH_ERR_ARGUMENT,
            "dt=%g s exceeds the stability limit %g h/(c_p + |v|max) = %g s of "
            "integrator '%s'%s; pass allow_unstable to force it",
            dt, sim_integrator(sim)->stable_factor * kernel_step_length(sim->kernel) / divisor,
            stable, sim_integrator(sim)->name, divisor > 1.0 ? " with artificial viscosity" : "");
    }
    sim->dt = dt;
    sim->dt_set = 1;
    return sph_ok(sim);
}

double sph_dt(const sph_sim *sim)
{
    if (!sim)
        return 0.0;
    return sim->dt_set ? sim->dt : sph_default_dt(sim);
}
double sph_time(const sph_sim *sim) { return sim ? sim->t : 0.0; }
long sph_step_count(const sph_sim *sim) { return sim ? sim->step : 0; }

sph_status sph_set_time(sph_sim *sim, double t, long step)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!isfinite(t) || t < 0.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "time t=%g s: must be finite and >= 0", t);
    if (step < 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "step=%ld: must be >= 0", step);
    sim->t = t;
    sim->step = step;
    sim->rates_valid = 0;
    return sph_ok(sim);
}
