/* Fields: stored state, derived quantities (pressure, stress, von Mises). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/integrator.h"
#include "physics/kernel.h"
#include "core/sim.h"

/* ---------------------------------------------------------------- fields */

/* The damage arrays, drawn if need be; an error naming `fn` while the
 * effect is off. */
static sph_status damage_ready(sph_sim *sim, const char *fn)
{
    if (!sim->fx.damage)
        return sph_fail(sim, SPH_ERR_STATE,
                        "%s: the damage fields exist while effect damage is on (sph_effect)", fn);
    if (sim->n == 0)
        return sph_fail(sim, SPH_ERR_STATE, "%s: the simulation has no particles", fn);
    return damage_prepare(sim);
}

/* Pressure (equation of state), Cauchy stress sigma = S - P I and von Mises
 * stress of one particle, each written where its pointer is not NULL. */
static void derived_at(const material *m, int dim, int nc, double rho, const double *S,
                       double *pressure, double *stress, double *von_mises)
{
    const double P = eos_pressure(m->c0_squared, rho, m->rho0);
    if (pressure)
        *pressure = P;
    if (stress)
        for (int c = 0; c < nc; ++c)
            stress[c] = S[c] - (c < 3 ? P : 0.0);
    if (von_mises)
        *von_mises = von_mises_stress(dim, S);
}

sph_status sph_field(sph_sim *sim, sph_field_id field, double **data, size_t *rows, size_t *cols)
{
    sph_status st = sph_need(sim, data, "sph_field", "data");
    if (st)
        return st;
    size_t c = 1;
    double *p = NULL;
    switch (field) {
    case SPH_FIELD_POSITION:
        p = sim->x;
        c = sim->dim;
        break;
    case SPH_FIELD_VELOCITY:
        p = sim->v;
        c = sim->dim;
        break;
    case SPH_FIELD_DENSITY: p = sim->rho; break;
    case SPH_FIELD_DEVIATORIC_STRESS:
        p = sim->S;
        c = sim->ncomp;
        break;
    case SPH_FIELD_MASS: p = sim->mass; break;
    case SPH_FIELD_DAMAGE:
        if ((st = damage_ready(sim, "sph_field")))
            return st;
        p = sim->damage;
        break;
    default:
        return sph_fail(sim, SPH_ERR_ARGUMENT, "field=%d is derived or unknown; use sph_field_copy",
                        (int)field);
    }
    *data = p;
    if (rows)
        *rows = sim->n;
    if (cols)
        *cols = c;
    sim->rates_valid = 0; /* the caller may write through the pointer */
    sim->nl.valid = sim->nl.valid && field != SPH_FIELD_POSITION;
    return sph_ok(sim);
}

sph_status sph_field_copy(sph_sim *sim, sph_field_id field, double *out)
{
    sph_status st = sph_need(sim, out, "sph_field_copy", "out");
    if (st)
        return st;
    const int dim = sim->dim, nc = sim->ncomp;
    const size_t n = sim->n;
    switch (field) {
    case SPH_FIELD_POSITION: memcpy(out, sim->x, n * dim * sizeof(double)); break;
    case SPH_FIELD_VELOCITY: memcpy(out, sim->v, n * dim * sizeof(double)); break;
    case SPH_FIELD_DENSITY: memcpy(out, sim->rho, n * sizeof(double)); break;
    case SPH_FIELD_DEVIATORIC_STRESS: memcpy(out, sim->S, n * nc * sizeof(double)); break;
    case SPH_FIELD_MASS: memcpy(out, sim->mass, n * sizeof(double)); break;
    case SPH_FIELD_PRESSURE:
    case SPH_FIELD_VON_MISES:
    case SPH_FIELD_STRESS:
        for (size_t a = 0; a < n; ++a)
            derived_at(&sim->materials[sim->material_of[a]], dim, nc, sim->rho[a], sim->S + a * nc,
                       field == SPH_FIELD_PRESSURE ? out + a : NULL,
                       field == SPH_FIELD_STRESS ? out + a * nc : NULL,
                       field == SPH_FIELD_VON_MISES ? out + a : NULL);
        break;
    case SPH_FIELD_ACCELERATION:
        /* the integrator's rates of this state, else evaluated now */
        if (!(sim->rates_valid || carried_rates_valid(sim))) {
            if ((st = sim_prepare(sim)) || (st = sim_evaluate(sim)))
                return st;
            sim->rates_valid = 1;
            sim->carry_valid = 0;
        }
        memcpy(out, sim->dv_dt, n * dim * sizeof(double));
        break;
    case SPH_FIELD_DAMAGE:
    case SPH_FIELD_FRAGMENT:
    case SPH_FIELD_FLAWS:
    case SPH_FIELD_FLAW_STRAIN:
    case SPH_FIELD_ACTIVE_FLAWS:
        if ((st = damage_ready(sim, "sph_field_copy")))
            return st;
        if (field == SPH_FIELD_FRAGMENT && (st = damage_fragments(sim, out, NULL)))
            return st;
        if (field == SPH_FIELD_FRAGMENT)
            break;
        for (size_t a = 0; a < n; ++a)
            out[a] = field == SPH_FIELD_DAMAGE        ? sim->damage[a]
                     : field == SPH_FIELD_FLAWS       ? (double)sim->flaw_count[a]
                     : field == SPH_FIELD_FLAW_STRAIN ? sim->flaw_strain[a]
                                                      : (double)damage_active_flaws(sim, a);
        break;
    default: return sph_fail(sim, SPH_ERR_ARGUMENT, "field=%d is not a sph_field_id", (int)field);
    }
    return sph_ok(sim);
}

sph_status sph_body_ids(sph_sim *sim, int *out)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!out && sim->n > 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_body_ids: out must not be NULL");
    if (sim->n == 0)
        return SPH_OK;
    memcpy(out, sim->body_of, sim->n * sizeof(int));
    return SPH_OK;
}

double sph_von_mises(int dimension, const double *S)
{
    return S ? von_mises_stress(dimension == 3 ? 3 : 2, S) : 0.0;
}

sph_status sph_derived_fields(sph_sim *sim, size_t n, const double *rho, const double *S,
                              const int *material_of, double *pressure, double *stress,
                              double *von_mises)
{
    const void *const arrays[] = {rho, S, material_of};
    sph_status st =
        caller_arrays(sim, "sph_derived_fields", n, material_of, "rho, S and material", arrays, 3);
    if (st)
        return st;
    const int dim = sim->dim, nc = sim->ncomp;
    for (size_t a = 0; a < n; ++a) {
        const material *m = &sim->materials[material_of[a]];
        derived_at(m, dim, nc, rho[a], S + a * nc, pressure ? pressure + a : NULL,
                   stress ? stress + a * nc : NULL, von_mises ? von_mises + a : NULL);
    }
    return SPH_OK;
}
