/*
 * Per-particle elastic energy of external particles (the LAMMPS plugin's
 * compute sphsolid/energy/atom): the same elastic_energy_per_mass() that
 * sph_energy() sums over a simulation's own particles.
 */
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
