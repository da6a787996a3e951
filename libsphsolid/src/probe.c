/* Probes: Shepard-normalised kernel interpolation at points,
 *   A(p) = sum_b V_b A_b W(p - r_b) / sum_b V_b W(p - r_b),  V_b = m_b/rho_b
 * (paper eq. 1, normalised by the interpolated unity). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"
#include "sim.h"

void probe_sample_point(sph_sim *sim, const double *point, double *values)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const int nvalues = 2 + nc;
    const double h = sim->h, support2 = 4.0 * h * h;
    double sum_w = 0.0, vm = 0.0, P = 0.0, S[6] = {0};
    for (size_t b = 0; b < sim->n; ++b) {
        double r2 = 0.0;
        for (int i = 0; i < dim; ++i) {
            double d = point[i] - sim->x[b * dim + i];
            if (sim->has_domain && sim->periodic[i]) {
                const double L = sim->hi[i] - sim->lo[i];
                if (d > 0.5 * L) d -= L;
                else if (d < -0.5 * L) d += L;
            }
            r2 += d * d;
        }
        if (r2 >= support2)
            continue;
        const material *m = &sim->materials[sim->material_of[b]];
        const double w = sim->mass[b] / sim->rho[b] * kernel_w(sim->kernel, sqrt(r2) / h);
        const double *Sb = sim->S + b * nc;
        sum_w += w;
        vm += w * von_mises_stress(dim, Sb);
        P += w * eos_pressure(m->c0_squared, sim->rho[b], m->rho0);
        for (int c = 0; c < nc; ++c)
            S[c] += w * Sb[c];
    }
    if (sum_w <= 0.0) {
        for (int k = 0; k < nvalues; ++k)
            values[k] = NAN;
        return;
    }
    values[0] = vm / sum_w;
    values[1] = P / sum_w;
    for (int c = 0; c < nc; ++c)
        values[2 + c] = S[c] / sum_w - (c < 3 ? values[1] : 0.0);
}

sph_status sph_add_probe(sph_sim *sim, const char *name, const double *point, int *id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!name || !*name || strlen(name) >= SPH_NAME_SIZE)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "probe name '%s' must have 1 to %d characters",
                        name ? name : "(null)", SPH_NAME_SIZE - 1);
    if (!point)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "probe '%s': point is NULL", name);
    for (int i = 0; i < sim->dim; ++i)
        if (!isfinite(point[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "probe '%s': coordinate %c=%g is not finite", name, "xyz"[i], point[i]);
    for (int k = 0; k < sim->n_probes; ++k)
        if (strcmp(sim->probes[k].name, name) == 0)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "probe name '%s' is already used", name);
    if (sim->out)
        return sph_fail(sim, SPH_ERR_STATE, "probe '%s': add probes before opening the output file", name);
    probe *p = realloc(sim->probes, (size_t)(sim->n_probes + 1) * sizeof *p);
    if (!p)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate a probe");
    sim->probes = p;
    memset(&p[sim->n_probes], 0, sizeof *p);
    strcpy(p[sim->n_probes].name, name);
    for (int i = 0; i < sim->dim; ++i)
        p[sim->n_probes].point[i] = point[i];
    if (id)
        *id = sim->n_probes;
    sim->n_probes++;
    return sph_ok(sim);
}

int sph_probe_count(const sph_sim *sim) { return sim ? sim->n_probes : 0; }

const char *sph_probe_name(const sph_sim *sim, int id)
{
    if (!sim || id < 0 || id >= sim->n_probes)
        return NULL;
    return sim->probes[id].name;
}

sph_status sph_probe_sample(sph_sim *sim, int id, double *values)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (id < 0 || id >= sim->n_probes)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "probe=%d: %d probes are defined", id, sim->n_probes);
    if (!values)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "probe '%s': values is NULL", sim->probes[id].name);
    if (sim->n == 0 || sim->h <= 0.0)
        return sph_fail(sim, SPH_ERR_STATE, "probe '%s': the simulation has no particles", sim->probes[id].name);
    probe_sample_point(sim, sim->probes[id].point, values);
    return sph_ok(sim);
}
