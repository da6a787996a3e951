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
    const void *const arrays[] = {mass, rho, S, material_of, energy};
    sph_status st = caller_arrays(sim, "sph_energy_fields", n, material_of,
                                  "mass, rho, S, material and energy", arrays, 5);
    if (st)
        return st;
    const int dim = sim->dim, nc = sim->ncomp;
    for (size_t a = 0; a < n; ++a) {
        const material *m = &sim->materials[material_of[a]];
        if (!(rho[a] > 0.0))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "sph_energy_fields: particle %zu has density %g (must be > 0)", a,
                            rho[a]);
        energy[a] = mass[a] * elastic_energy_per_mass(dim, m->c0_squared, m->rho0, m->mu, rho[a],
                                                      S + (size_t)a * nc);
    }
    return SPH_OK;
}

sph_status sph_energy(sph_sim *sim, int all_bodies, sph_energy_info *info)
{
    sph_status st = sph_need(sim, info, "sph_energy", "info");
    if (st)
        return st;
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
