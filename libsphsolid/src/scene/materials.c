/* Materials: linear elastic solids, their moduli and wave speeds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "physics/kernel.h"
#include "core/sim.h"

/* ------------------------------------------------------------- materials */

static sph_status add_material(sph_sim *sim, double K, double mu, double rho0, int *id)
{
    if (!(K > 0.0) || !isfinite(K))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "bulk modulus K=%g: must be finite and > 0", K);
    if (!(mu >= 0.0) || !isfinite(mu))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "shear modulus mu=%g: must be finite and >= 0", mu);
    if (!(rho0 > 0.0) || !isfinite(rho0))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "reference density rho0=%g: must be finite and > 0",
                        rho0);
    {
        /* derived constants must be finite too (K = mu = 1e300 gives E = inf) */
        const double E = 9.0 * K * mu / (3.0 * K + mu), c_p2 = (K + 4.0 * mu / 3.0) / rho0;
        if (!isfinite(E) || !isfinite(c_p2) || !isfinite(K / rho0))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "K=%g, mu=%g, rho0=%g: the derived constants overflow (Young's modulus "
                            "E=%g, c_p^2=%g m^2/s^2)",
                            K, mu, rho0, E, c_p2);
    }
    material *m = realloc(sim->materials, (size_t)(sim->n_materials + 1) * sizeof *m);
    if (!m)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate a material");
    sim->materials = m;
    material *mat = &m[sim->n_materials];
    mat->K = K;
    mat->mu = mu;
    mat->rho0 = rho0;
    mat->c0_squared = K / rho0;
    mat->c0 = sqrt(mat->c0_squared);
    mat->c_p = sqrt((K + 4.0 * mu / 3.0) / rho0);
    mat->weibull_k = mat->weibull_m = 0.0;
    if (id)
        *id = sim->n_materials;
    sim->n_materials++;
    return sph_ok(sim);
}

/* The modulus of an (X, nu) pair must be finite and > 0, nu in (-1, 0.5). */
static sph_status check_pair(sph_sim *sim, const char *modulus, double value, double nu)
{
    if (!(value > 0.0) || !isfinite(value))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s=%g: must be finite and > 0", modulus, value);
    if (!(nu > -1.0 && nu < 0.5))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "Poisson ratio nu=%g: must be in (-1, 0.5)", nu);
    return SPH_OK;
}

sph_status sph_add_material_K_mu(sph_sim *sim, double K, double mu, double rho0, int *id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    return add_material(sim, K, mu, rho0, id);
}

sph_status sph_add_material_E_nu(sph_sim *sim, double E, double nu, double rho0, int *id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    const sph_status st = check_pair(sim, "Young's modulus E", E, nu);
    /* isotropic elasticity: K = E / (3 (1 - 2 nu)), mu = E / (2 (1 + nu)) */
    return st ? st
              : add_material(sim, E / (3.0 * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu)), rho0, id);
}

sph_status sph_add_material_K_nu(sph_sim *sim, double K, double nu, double rho0, int *id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    const sph_status st = check_pair(sim, "bulk modulus K", K, nu);
    /* isotropic elasticity: mu = 3K (1 - 2 nu) / (2 (1 + nu)) */
    return st ? st
              : add_material(sim, K, 3.0 * K * (1.0 - 2.0 * nu) / (2.0 * (1.0 + nu)), rho0, id);
}

sph_status caller_pairs(sph_sim *sim, const char *fn, const sph_particles *particles,
                        const sph_neighbours *neighbours, const void *out, const char *out_name)
{
    sph_status st = sph_need(sim, particles, fn, "particles");
    if (!st)
        st = sph_need(sim, neighbours, fn, "neighbours");
    return st ? st : sph_need(sim, out, fn, out_name);
}

sph_status caller_arrays(sph_sim *sim, const char *fn, size_t n, const int *material_of,
                         const char *names, const void *const *arrays, int count)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    for (int k = 0; k < count && n > 0; ++k)
        if (!arrays[k])
            return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: %s must not be NULL", fn, names);
    for (size_t a = 0; a < n; ++a)
        if (material_of[a] < 0 || material_of[a] >= sim->n_materials)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "%s: particle %zu has material %d, but %d materials are defined", fn, a,
                            material_of[a], sim->n_materials);
    return SPH_OK;
}

/* Material `id` for the public call `fn`, whose argument `name` (p) must
 * not be NULL; an error names the id when there is no such material. */
sph_status material_of_call(sph_sim *sim, const char *fn, const char *name, const void *p, int id,
                            material **m)
{
    const sph_status st = sph_need(sim, p, fn, name);
    if (st)
        return st;
    if (id < 0 || id >= sim->n_materials)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "material=%d: %d materials are defined", id,
                        sim->n_materials);
    *m = &sim->materials[id];
    return SPH_OK;
}

sph_status sph_material_info_get(sph_sim *sim, int id, sph_material_info *info)
{
    material *m = NULL;
    const sph_status st = material_of_call(sim, "sph_material_info_get", "info", info, id, &m);
    if (st)
        return st;
    info->bulk_modulus = m->K;
    info->shear_modulus = m->mu;
    info->rho0 = m->rho0;
    /* eq. (10) of the paper prints (3K/mu + 2) in the denominator; the
     * isotropic-elasticity relation that (E, nu) -> (K, mu) inverts is
     * nu = (3K - 2mu) / (2 (3K + mu)) = (3K/mu - 2) / (2 (3K/mu + 1)). */
    info->poisson_ratio = (3.0 * m->K - 2.0 * m->mu) / (2.0 * (3.0 * m->K + m->mu));
    info->youngs_modulus = 9.0 * m->K * m->mu / (3.0 * m->K + m->mu);
    info->c0 = m->c0;
    info->c_p = m->c_p;
    info->weibull_k = m->weibull_k;
    info->weibull_m = m->weibull_m;
    return SPH_OK;
}
