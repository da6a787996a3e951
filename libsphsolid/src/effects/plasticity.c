/*
 * The `drucker_prager` effect: the return of each free-body particle's
 * deviator onto the Drucker-Prager cone after each step (an operator
 * split, like the damage stage), on the handle's particles and on a
 * caller's arrays.  The terms are in plasticity.h.
 */
#include <math.h>

#include "effects/plasticity.h"
#include "physics/physics.h"
#include "core/sim.h"

/* The energy the return took from one particle's deviatoric part (damaged
 * by D): m (1 - D) S:S (1 - scale^2) / (4 mu rho). */
static double returned_energy(int dim, const material *m, double mass, double rho, double D,
                              const double *S_before, double scale)
{
    if (!(m->mu > 0.0) || D >= 1.0)
        return 0.0;
    return mass * (1.0 - D) * stress_double_dot(dim, S_before) * (1.0 - scale * scale) /
           (4.0 * m->mu * rho);
}

sph_status plastic_stage(sph_sim *sim, int *changed)
{
    *changed = 0;
    double A, B;
    drucker_prager_constants(sim->fx.drucker_prager_cohesion, sim->fx.drucker_prager_friction_angle,
                             &A, &B);
    const int dim = sim->dim, nc = sim->ncomp, account = sim->energy_account;
    const long n = (long)sim->n;
    int returned = 0;
    double released = 0.0;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(| : returned) \
    reduction(+ : released)
    for (long a = 0; a < n; ++a) {
        if (sim->bodies[sim->body_of[a]].motion != SPH_MOTION_FREE)
            continue;
        const material *m = &sim->materials[sim->material_of[a]];
        double *S = sim->S + (size_t)a * (size_t)nc, before[6];
        const double D = sim->damage ? sim->damage[a] : 0.0;
        for (int c = 0; c < nc; ++c)
            before[c] = S[c];
        const double scale = drucker_prager_return(
            nc, A, B, eos_pressure(m->c0_squared, sim->rho[a], m->rho0), D, S);
        if (scale != 1.0) {
            returned = 1;
            if (account)
                released += returned_energy(dim, m, sim->mass[a], sim->rho[a], D, before, scale);
        }
    }
    sim->dissipated_plastic += released;
    *changed = returned;
    return SPH_OK;
}

sph_status sph_drucker_prager_return(sph_sim *sim, size_t n, const int *material_of,
                                     const double *rho, const double *damage,
                                     const unsigned char *member, double *S, int *changed)
{
    const char *fn = "sph_drucker_prager_return";
    sph_status st = sph_need(sim, changed, fn, "changed");
    if (st)
        return st;
    *changed = 0;
    if (!sim->fx.drucker_prager)
        return sph_fail(sim, SPH_ERR_STATE, "%s: effect drucker_prager is off (sph_effect)", fn);
    const void *const arrays[] = {material_of, rho, S};
    if ((st = caller_arrays(sim, fn, n, material_of, "material, rho and S", arrays, 3)))
        return st;
    if (sim->fx.damage && n > 0 && !damage)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: effect damage is on but damage is NULL", fn);
    double A, B;
    drucker_prager_constants(sim->fx.drucker_prager_cohesion, sim->fx.drucker_prager_friction_angle,
                             &A, &B);
    const int nc = sim->ncomp;
    int returned = 0;
    for (size_t a = 0; a < n; ++a) {
        if (member && !member[a])
            continue;
        const material *m = &sim->materials[material_of[a]];
        const double D = sim->fx.damage ? damage[a] : 0.0;
        returned |= drucker_prager_return(nc, A, B, eos_pressure(m->c0_squared, rho[a], m->rho0), D,
                                          S + a * (size_t)nc) != 1.0;
    }
    *changed = returned;
    return sph_ok(sim);
}
