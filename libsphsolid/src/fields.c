/* Fields: stored state, derived quantities (pressure, stress, von Mises). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "integrator.h"
#include "kernel.h"
#include "sim.h"

/* ---------------------------------------------------------------- fields */

sph_status sph_field(sph_sim *sim, sph_field_id field, double **data, size_t *rows, size_t *cols)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!data)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_field: data is NULL");
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
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!out)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_field_copy: out is NULL");
    const int dim = sim->dim, nc = sim->ncomp;
    const size_t n = sim->n;
    switch (field) {
    case SPH_FIELD_POSITION: memcpy(out, sim->x, n * dim * sizeof(double)); break;
    case SPH_FIELD_VELOCITY: memcpy(out, sim->v, n * dim * sizeof(double)); break;
    case SPH_FIELD_DENSITY: memcpy(out, sim->rho, n * sizeof(double)); break;
    case SPH_FIELD_DEVIATORIC_STRESS: memcpy(out, sim->S, n * nc * sizeof(double)); break;
    case SPH_FIELD_MASS: memcpy(out, sim->mass, n * sizeof(double)); break;
    case SPH_FIELD_PRESSURE:
        for (size_t a = 0; a < n; ++a) {
            const material *m = &sim->materials[sim->material_of[a]];
            out[a] = eos_pressure(m->c0_squared, sim->rho[a], m->rho0);
        }
        break;
    case SPH_FIELD_VON_MISES:
        for (size_t a = 0; a < n; ++a)
            out[a] = von_mises_stress(dim, sim->S + a * nc);
        break;
    case SPH_FIELD_STRESS:
        for (size_t a = 0; a < n; ++a) {
            const material *m = &sim->materials[sim->material_of[a]];
            const double P = eos_pressure(m->c0_squared, sim->rho[a], m->rho0);
            for (int c = 0; c < nc; ++c)
                out[a * nc + c] = sim->S[a * nc + c] - (c < 3 ? P : 0.0);
        }
        break;
    case SPH_FIELD_ACCELERATION:
        /* the integrator's rates of this state, else evaluated now */
        if (!(sim->rates_valid || carried_rates_valid(sim))) {
            sph_status st = sim_prepare(sim);
            if (st || (st = sim_evaluate(sim)))
                return st;
            sim->rates_valid = 1;
            sim->carry_valid = 0;
        }
        memcpy(out, sim->dv_dt, n * dim * sizeof(double));
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
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (n > 0 && (!rho || !S || !material_of))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_derived_fields: rho, S and material must not be NULL");
    const int dim = sim->dim, nc = sim->ncomp;
    for (size_t a = 0; a < n; ++a) {
        if (material_of[a] < 0 || material_of[a] >= sim->n_materials)
            return sph_fail(
                sim, SPH_ERR_ARGUMENT,
                "sph_derived_fields: particle %zu has material %d, but %d materials are defined", a,
                material_of[a], sim->n_materials);
        const material *m = &sim->materials[material_of[a]];
        const double P = eos_pressure(m->c0_squared, rho[a], m->rho0);
        if (pressure)
            pressure[a] = P;
        if (stress)
            for (int c = 0; c < nc; ++c)
                stress[a * nc + c] = S[a * nc + c] - (c < 3 ? P : 0.0);
        if (von_mises)
            von_mises[a] = von_mises_stress(dim, S + a * nc);
    }
    return SPH_OK;
}
