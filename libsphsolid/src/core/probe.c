/* Probes: Shepard-normalised kernel interpolation at points,
 *   A(p) = sum_b V_b A_b W(p - r_b) / sum_b V_b W(p - r_b),  V_b = m_b/rho_b
 * (paper eq. 1, normalised by the interpolated unity). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "physics/kernel.h"
#include "core/sim.h"

/* Minimum-image squared distance between a point and a position xb. */
static double distance2(const sph_sim *sim, const double *point, const double *xb)
{
    double r2 = 0.0;
    for (int i = 0; i < sim->dim; ++i) {
        double d = point[i] - xb[i];
        if (sim->has_domain && sim->periodic[i]) {
            const double L = sim->hi[i] - sim->lo[i];
            d = nearest_image(d, L, 0.5 * L);
        }
        r2 += d * d;
    }
    return r2;
}

/* Add the kernel-weighted contributions of particles [0, n) at `point`:
 * sums = (sum w, sum w vm, sum w P, sum w S...), w = V_b W(p - r_b). */
static void probe_accumulate(const sph_sim *sim, size_t n, const double *x, size_t stride,
                             const double *rho, const double *S, const double *mass,
                             const int *material_of, const double *point, double *sums)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const double h = sim->h, support2 = 4.0 * h * h;
    const double norm = kernel_sigma(sim->kernel, dim) / pow(h, dim);
    for (size_t b = 0; b < n; ++b) {
        const double r2 = distance2(sim, point, x + b * stride);
        if (r2 >= support2)
            continue;
        const material *m = &sim->materials[material_of[b]];
        const double w = mass[b] / rho[b] * kernel_w(sim->kernel, dim, sqrt(r2) / h) * norm;
        const double *Sb = S + b * nc;
        sums[0] += w;
        sums[1] += w * von_mises_stress(dim, Sb);
        sums[2] += w * eos_pressure(m->c0_squared, rho[b], m->rho0);
        for (int c = 0; c < nc; ++c)
            sums[3 + c] += w * Sb[c];
    }
}

/* Shepard normalisation of the sums; NAN where no particle is in range. */
static void probe_finish(const sph_sim *sim, const double *sums, double *values)
{
    const int nc = sim->ncomp;
    if (!(sums[0] > 0.0)) {
        for (int k = 0; k < 2 + nc; ++k)
            values[k] = NAN;
        return;
    }
    values[0] = sums[1] / sums[0];
    values[1] = sums[2] / sums[0];
    for (int c = 0; c < nc; ++c)
        values[2 + c] = sums[3 + c] / sums[0] - (c < 3 ? values[1] : 0.0);
}

/* The particles that can be within 2h of p's point while the current
 * neighbour list is valid: those within 2h + skin now.  Every particle
 * moves less than skin/2 during the list's life (the run driver rebuilds
 * it before), so one within 2h later is within 2h + skin/2 now.  0 when
 * there is no valid list or no memory (then every particle is visited). */
static int probe_near(sph_sim *sim, probe *p)
{
    if (!sim->nl.valid || sim->nl.n != sim->n || sim->nl_builds == 0)
        return 0;
    if (p->near_list == sim->nl_builds)
        return 1;
    const double reach = 2.0 * sim->h + sim->nl.skin, reach2 = reach * reach;
    p->n_near = 0;
    p->near_list = 0;
    for (size_t b = 0; b < sim->n; ++b) {
        if (!(distance2(sim, p->point, sim->x + b * (size_t)sim->dim) < reach2))
            continue;
        if (p->n_near == p->near_capacity) {
            const size_t cap = p->near_capacity ? 2 * p->near_capacity : 64;
            int *grown = realloc(p->near, cap * sizeof *grown);
            if (!grown)
                return 0;
            p->near = grown;
            p->near_capacity = cap;
        }
        p->near[p->n_near++] = (int)b;
    }
    p->near_list = sim->nl_builds;
    return 1;
}

void probes_free(sph_sim *sim)
{
    for (int k = 0; k < sim->n_probes; ++k)
        free(sim->probes[k].near);
    free(sim->probes);
}

/* Samples probe p; outside every body: NaN, and SPH_ERR_DOMAIN unless the
 * handle asked for NaN (sph_set_probe_outside).  In a run (in_run: the
 * positions are the library's own since the neighbour list was built) only
 * the particles near the point are visited, in index order: the sums add
 * the same terms in the same order as a visit of all particles, whose
 * others add nothing. */
sph_status probe_sample_point(sph_sim *sim, probe *p, double *values, int in_run)
{
    double sums[3 + 6] = {0};
    if (in_run && probe_near(sim, p)) {
        const size_t dim = (size_t)sim->dim, nc = (size_t)sim->ncomp;
        for (size_t k = 0; k < p->n_near; ++k) {
            const size_t b = (size_t)p->near[k];
            probe_accumulate(sim, 1, sim->x + b * dim, dim, sim->rho + b, sim->S + b * nc,
                             sim->mass + b, sim->material_of + b, p->point, sums);
        }
    } else {
        probe_accumulate(sim, sim->n, sim->x, (size_t)sim->dim, sim->rho, sim->S, sim->mass,
                         sim->material_of, p->point, sums);
    }
    probe_finish(sim, sums, values);
    if (sums[0] > 0.0 || sim->probe_outside_nan)
        return SPH_OK;
    char at[96];
    if (sim->dim == 3)
        snprintf(at, sizeof at, "(%g, %g, %g)", p->point[0], p->point[1], p->point[2]);
    else
        snprintf(at, sizeof at, "(%g, %g)", p->point[0], p->point[1]);
    return sph_fail(
        sim, SPH_ERR_DOMAIN,
        "probe '%s' at %s m is outside every body: no particle within 2h = %g m at t = %g s "
        "(sph_set_probe_outside(SPH_PROBE_OUTSIDE_NAN) records NaN instead)",
        p->name, at, 2.0 * sim->h, sim->t);
}

sph_status sph_set_probe_outside(sph_sim *sim, sph_probe_outside mode)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (mode != SPH_PROBE_OUTSIDE_ERROR && mode != SPH_PROBE_OUTSIDE_NAN)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_set_probe_outside: mode=%d is not SPH_PROBE_OUTSIDE_ERROR (0) or "
                        "SPH_PROBE_OUTSIDE_NAN (1)",
                        (int)mode);
    sim->probe_outside_nan = mode == SPH_PROBE_OUTSIDE_NAN;
    return sph_ok(sim);
}

sph_status sph_probe_accumulate(sph_sim *sim, const sph_particles *p, const double *point,
                                double *sums)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!p || !point || !sums)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_probe_accumulate: particles, point and sums must not be NULL");
    if (sim->h <= 0.0)
        return sph_fail(sim, SPH_ERR_STATE,
                        "sph_probe_accumulate: the smoothing length is not set (sph_set_spacing)");
    if (p->n_local > 0 && (!p->x || !p->rho || !p->S || !p->mass || !p->material))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_probe_accumulate: a particle array is NULL");
    for (size_t b = 0; b < p->n_local; ++b)
        if (p->material[b] < 0 || p->material[b] >= sim->n_materials)
            return sph_fail(
                sim, SPH_ERR_ARGUMENT,
                "sph_probe_accumulate: particle %zu has material %d, but %d materials are defined",
                b, p->material[b], sim->n_materials);
    const size_t stride = p->stride ? p->stride : (size_t)sim->dim;
    if (stride < (size_t)sim->dim)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_probe_accumulate: stride=%zu is smaller than the dimension %d", stride,
                        sim->dim);
    probe_accumulate(sim, p->n_local, p->x, stride, p->rho, p->S, p->mass, p->material, point,
                     sums);
    return SPH_OK;
}

sph_status sph_probe_finish(sph_sim *sim, const double *sums, double *values)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!sums || !values)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_probe_finish: sums and values must not be NULL");
    probe_finish(sim, sums, values);
    if (!(sums[0] > 0.0) && !sim->probe_outside_nan)
        return sph_fail(sim, SPH_ERR_DOMAIN,
                        "the point is outside every body: no particle within 2h = %g m "
                        "(SPH_PROBE_OUTSIDE_NAN records NaN instead)",
                        2.0 * sim->h);
    return SPH_OK;
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
            return sph_fail(sim, SPH_ERR_ARGUMENT, "probe '%s': coordinate %c=%g is not finite",
                            name, "xyz"[i], point[i]);
    for (int k = 0; k < sim->n_probes; ++k)
        if (strcmp(sim->probes[k].name, name) == 0)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "probe name '%s' is already used", name);
    if (sim->out)
        return sph_fail(sim, SPH_ERR_STATE, "probe '%s': add probes before opening the output file",
                        name);
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
        return sph_fail(sim, SPH_ERR_ARGUMENT, "probe=%d: %d probes are defined", id,
                        sim->n_probes);
    if (!values)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "probe '%s': values is NULL", sim->probes[id].name);
    if (sim->n == 0 || sim->h <= 0.0)
        return sph_fail(sim, SPH_ERR_STATE, "probe '%s': the simulation has no particles",
                        sim->probes[id].name);
    const sph_status st = probe_sample_point(sim, &sim->probes[id], values, 0);
    return st ? st : sph_ok(sim);
}
