/*
 * Energy: the totals of a simulation's own bodies (sph_energy) and the
 * per-particle elastic energy of external particles (sph_energy_fields, the
 * LAMMPS plugin's compute sphsolid/energy/atom), both from the one
 * elastic_energy_per_mass().
 */
#include <string.h>

#include "physics.h"
#include "sim.h"

sph_status sph_energy_fields(sph_sim *sim, size_t n, const double *mass, const double *rho,
                             const double *S, const int *material_of, double *energy)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (n > 0 && (!mass || !rho || !S || !material_of || !energy))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_energy_fields: mass, rho, S, material and energy must not be NULL");
    const int dim = sim->dim, nc = sim->ncomp;
    for (size_t a = 0; a < n; ++a) {
        if (material_of[a] < 0 || material_of[a] >= sim->n_materials)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "sph_energy_fields: particle %zu has material %d, but %d materials are "
                            "defined",
                            a, material_of[a], sim->n_materials);
        if (!(rho[a] > 0.0))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "sph_energy_fields: particle %zu has density %g (must be > 0)", a,
                            rho[a]);
        const material *m = &sim->materials[material_of[a]];
        energy[a] = mass[a] * elastic_energy_per_mass(dim, m->c0_squared, m->rho0, m->mu, rho[a],
                                                      S + (size_t)a * nc);
    }
    return SPH_OK;
}

sph_status sph_energy(sph_sim *sim, int all_bodies, sph_energy_info *info)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!info)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_energy: info is NULL");
    memset(info, 0, sizeof *info);
    const int dim = sim->dim;
    for (size_t a = 0; a < sim->n; ++a) {
        const body *b = &sim->bodies[sim->body_of[a]];
        if (!all_bodies && b->motion != SPH_MOTION_FREE && b->motion != SPH_MOTION_FORCE)
            continue;
        const material *m = &sim->materials[sim->material_of[a]];
        double v2 = 0.0;
        for (int i = 0; i < dim; ++i) {
            v2 += sim->v[a * dim + i] * sim->v[a * dim + i];
            info->momentum[i] += sim->mass[a] * sim->v[a * dim + i];
        }
        info->kinetic += 0.5 * sim->mass[a] * v2;
        info->elastic +=
            sim->mass[a] * elastic_energy_per_mass(dim, m->c0_squared, m->rho0, m->mu, sim->rho[a],
                                                   sim->S + a * sim->ncomp);
    }
    return sph_ok(sim);
}
