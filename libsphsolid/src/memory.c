/* Memory held by a handle. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"
#include "sim.h"

size_t sph_memory_bytes(const sph_sim *sim)
{
    if (!sim)
        return 0;
    const size_t cap = sim->capacity, n = sim->n;
    const size_t dim = (size_t)sim->dim, nc = (size_t)sim->ncomp, ns = (size_t)sim->nsym;
    size_t bytes = sizeof *sim;
    bytes += cap * (2 * dim + 1 + nc + 1) * sizeof(double) + cap * 2 * sizeof(int);
    if (sim->saved)
        bytes += n * sim->saved_per * sizeof(double);
    if (sim->x_saved)
        bytes += n * dim * sizeof(double);
    if (sim->dv_dt)
        bytes += n * (dim + 1 + nc) * sizeof(double);
    if (sim->dx_dt)
        bytes += n * dim * sizeof(double);
    bytes += sim->scratch_n * (ns + 2) * sizeof(double);
    if (sim->stress_R)
        bytes += sim->scratch_n * ns * sizeof(double);
    bytes += sim->sum_scratch_n * sizeof(double) + rates_far_bytes(sim);
    if (sim->nl.offsets)
        bytes += (sim->nl.n + 1) * sizeof(size_t) + sim->nl.capacity * sizeof(int);
    bytes += (size_t)sim->n_materials * sizeof(material) + (size_t)sim->n_bodies * sizeof(body) +
             (size_t)sim->n_probes * sizeof(probe);
    return bytes;
}
