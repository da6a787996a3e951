/*
 * The registry of time integrators: one line per integrator (its record is
 * defined in its own file), and the calls that select and describe them.
 */
#include <string.h>

#include "integrators/integrator.h"

static const integrator *const registry[] = {
    &integrator_improved_euler, /* the default: the paper's scheme */
    &integrator_leapfrog,
};
#define N_INTEGRATORS (sizeof registry / sizeof registry[0])

const integrator *integrator_find(const char *name)
{
    for (size_t k = 0; name && k < N_INTEGRATORS; ++k)
        if (strcmp(registry[k]->name, name) == 0)
            return registry[k];
    return NULL;
}

const integrator *sim_integrator(const sph_sim *sim)
{
    return sim->integ ? sim->integ : registry[0];
}

const char *sph_integrator_names(void)
{
    static char names[256];
    if (!names[0])
        for (size_t k = 0; k < N_INTEGRATORS; ++k) {
            if (k)
                strcat(names, " ");
            strcat(names, registry[k]->name);
        }
    return names;
}

static sph_status unknown(sph_sim *sim, const char *name)
{
    return sph_fail(sim, SPH_ERR_ARGUMENT, "integrator '%s' is unknown; known: %s",
                    name ? name : "(null)", sph_integrator_names());
}

sph_status sph_set_integrator(sph_sim *sim, const char *name)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    const integrator *in = integrator_find(name);
    if (!in)
        return unknown(sim, name);
    const integrator *old = sim_integrator(sim);
    sim->integ = in;
    if (sim->dt_set) {
        const double stable = sph_stable_dt(sim);
        if (stable > 0.0 && sim->dt > stable) {
            sim->integ = old;
            return sph_fail(sim, SPH_ERR_STATE,
                            "integrator '%s': the time step dt=%g s set for '%s' exceeds its "
                            "stability limit %g s; set a smaller step first",
                            name, sim->dt, old->name, stable);
        }
    }
    if (in != old) {
        sim->rates_valid = 0;
        sim->carry_valid = 0;
        sim->power_carry_valid = 0;
    }
    return sph_ok(sim);
}

const char *sph_integrator_name(const sph_sim *sim)
{
    return sim ? sim_integrator(sim)->name : NULL;
}

sph_status sph_integrator_info_get(sph_sim *sim, const char *name, sph_integrator_info *info)
{
    sph_status st = sph_need(sim, info, "sph_integrator_info_get", "info");
    if (st)
        return st;
    const integrator *in = name ? integrator_find(name) : sim_integrator(sim);
    if (!in)
        return unknown(sim, name);
    info->name = in->name;
    info->description = in->description;
    info->evaluations = in->evaluations;
    info->stable_factor = in->stable_factor;
    info->default_factor = in->default_factor;
    info->saved_values = in->saved_values(sim->dim, sim->ncomp, sim->fx.xsph);
    info->carries_rates = in->carries_rates;
    return sph_ok(sim);
}

/* --------------------------------------------- rates carried across runs */

/* FNV-1a over 64-bit words in four interleaved lanes (a byte-wise FNV of
 * the state cost as much as a sixth of a leapfrog step when runs are one
 * step long); a trailing partial word is taken byte by byte. */
static unsigned long long fnv1a(unsigned long long h, const void *data, size_t bytes)
{
    const unsigned long long prime = 1099511628211ULL;
    const unsigned char *p = data;
    const size_t words = bytes / 8;
    unsigned long long lane[4] = {h, h ^ 1ULL, h ^ 2ULL, h ^ 3ULL};
    size_t k = 0;
    for (; k + 4 <= words; k += 4)
        for (int j = 0; j < 4; ++j) {
            unsigned long long w;
            memcpy(&w, p + 8 * (k + (size_t)j), 8);
            lane[j] = (lane[j] ^ w) * prime;
        }
    for (; k < words; ++k) {
        unsigned long long w;
        memcpy(&w, p + 8 * k, 8);
        lane[0] = (lane[0] ^ w) * prime;
    }
    for (size_t i = 8 * words; i < bytes; ++i)
        lane[0] = (lane[0] ^ p[i]) * prime;
    for (int j = 1; j < 4; ++j)
        lane[0] = (lane[0] ^ lane[j]) * prime;
    return lane[0];
}

/* Everything the rates depend on: the state arrays, the model (materials,
 * kernel, smoothing length, effects) and the bodies' motions. */
unsigned long long state_fingerprint(const sph_sim *sim)
{
    const size_t n = sim->n, dim = (size_t)sim->dim;
    unsigned long long h = 14695981039346656037ULL;
    h = fnv1a(h, sim->x, n * dim * sizeof(double));
    h = fnv1a(h, sim->v, n * dim * sizeof(double));
    h = fnv1a(h, sim->rho, n * sizeof(double));
    h = fnv1a(h, sim->S, n * (size_t)sim->ncomp * sizeof(double));
    h = fnv1a(h, sim->mass, n * sizeof(double));
    h = fnv1a(h, &sim->fx, sizeof sim->fx);
    h = fnv1a(h, sim->materials, (size_t)sim->n_materials * sizeof *sim->materials);
    h = fnv1a(h, &sim->h, sizeof sim->h);
    h = fnv1a(h, &sim->kernel, sizeof sim->kernel);
    for (int k = 0; k < sim->n_bodies; ++k) {
        h = fnv1a(h, &sim->bodies[k].motion, sizeof sim->bodies[k].motion);
        h = fnv1a(h, sim->bodies[k].vector, sizeof sim->bodies[k].vector);
        h = fnv1a(h, sim->bodies[k].centre, sizeof sim->bodies[k].centre);
    }
    return h;
}

void carried_rates_set(sph_sim *sim)
{
    sim->carry_print = state_fingerprint(sim);
    sim->carry_valid = 1;
}

int carried_rates_valid(const sph_sim *sim)
{
    return sim->carry_valid && sim->dv_dt && sim->carry_print == state_fingerprint(sim);
}
