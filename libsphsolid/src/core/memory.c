/* Memory held by a handle. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "physics/kernel.h"
#include "core/sim.h"

int sph_memory_parts(const sph_sim *sim, const char **names, size_t *bytes, int max)
{
    static const char *const part_names[SPH_MEMORY_PARTS] = {
        "particle state", "integrator saved state", "rates", "pair data",
        "pair sums",      "neighbour list",         "model"};
    size_t part[SPH_MEMORY_PARTS] = {0};
    if (sim) {
        const size_t cap = sim->capacity, n = sim->n;
        const size_t dim = (size_t)sim->dim, nc = (size_t)sim->ncomp, ns = (size_t)sim->nsym;
        part[0] = cap * (2 * dim + 1 + nc + 1) * sizeof(double) + cap * 2 * sizeof(int);
        if (sim->damage) /* effect damage: D, weakest strain, flaw count */
            part[0] += sim->damage_n * (2 * sizeof(double) + sizeof(int));
        if (sim->saved)
            part[1] += n * sim->saved_per * sizeof(double);
        if (sim->x_saved)
            part[1] += n * dim * sizeof(double);
        if (sim->dv_dt)
            part[2] += n * (dim + 1 + nc) * sizeof(double);
        if (sim->dx_dt)
            part[2] += n * dim * sizeof(double);
        part[3] = (sim->scratch_n * sim->pair_data_per + sim->motion_scratch_n) * sizeof(double);
        if (sim->stress_R)
            part[3] += sim->scratch_n * ns * sizeof(double);
        part[4] = sim->sum_scratch_n * sizeof(double) + rates_far_bytes(sim);
        if (sim->nl.offsets32 || sim->nl.offsets)
            part[5] = (sim->nl.n + 1) * (sim->nl.offsets32 ? sizeof(uint32_t) : sizeof(size_t)) +
                      sim->nl.capacity * sizeof(int);
        part[6] = sizeof *sim + (size_t)sim->n_materials * sizeof(material) +
                  (size_t)sim->n_bodies * sizeof(body) + (size_t)sim->n_probes * sizeof(probe);
    }
    for (int k = 0; k < max && k < SPH_MEMORY_PARTS; ++k) {
        if (names)
            names[k] = part_names[k];
        if (bytes)
            bytes[k] = part[k];
    }
    return SPH_MEMORY_PARTS;
}

size_t sph_memory_bytes(const sph_sim *sim)
{
    if (!sim)
        return 0;
    size_t part[SPH_MEMORY_PARTS], bytes = 0;
    sph_memory_parts(sim, NULL, part, SPH_MEMORY_PARTS);
    for (int k = 0; k < SPH_MEMORY_PARTS; ++k)
        bytes += part[k];
    return bytes;
}
