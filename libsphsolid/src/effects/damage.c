/*
 * The `damage` effect: per-particle storage (D, the weakest activation
 * strain, the flaw count), the flaw draw, the stage that activates flaws
 * and grows D after each step, fragments, and the public calls on them.
 * The terms are in damage.h; the rate engine reads D where it forms the
 * stress of the momentum pass (rates.c).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "effects/damage.h"
#include "physics/kernel.h"
#include "core/sim.h"

/* Whether particle a can be damaged: a free body, a material with flaws. */
static int material_has_flaws(const material *m)
{
    return m->weibull_k > 0.0 && m->weibull_m > 0.0;
}

static int has_flaws(const sph_sim *sim, size_t a)
{
    return sim->bodies[sim->body_of[a]].motion == SPH_MOTION_FREE &&
           material_has_flaws(&sim->materials[sim->material_of[a]]);
}

/* k V of a particle of mass `mass`, V = mass / rho0 its volume at rest. */
static double flaw_density_volume_of(const material *m, double mass)
{
    return m->weibull_k * mass / m->rho0;
}

static double flaw_density_volume(const sph_sim *sim, size_t a)
{
    return flaw_density_volume_of(&sim->materials[sim->material_of[a]], sim->mass[a]);
}

/* The key of the run's flaw stream: hash(seed, member) (damage.h). */
static uint64_t stream_of(const sph_sim *sim)
{
    return damage_stream((uint64_t)sim->fx.damage_seed, (uint64_t)sim->fx.damage_member);
}

/* The flaws of the particle of global id `id` and flaw density x volume
 * kV: their number and the weakest activation strain. */
static void draw_flaws_of(const sph_sim *sim, uint64_t id, const material *m, double kV, int *count,
                          double *strain)
{
    const uint64_t seed = stream_of(sim);
    const int below = damage_flaws_below(seed, id, 2000000, sim->fx.damage_flaws);
    *count = below > 0 ? below : 1;
    *strain = pow(damage_gap(seed, id, 0) / kV, 1.0 / m->weibull_m);
}

/* Draws the flaws of particle a: their number and the weakest strain. */
static void draw_flaws(sph_sim *sim, size_t a)
{
    if (!has_flaws(sim, a)) {
        sim->flaw_count[a] = 0;
        sim->flaw_strain[a] = INFINITY;
        return;
    }
    draw_flaws_of(sim, a, &sim->materials[sim->material_of[a]], flaw_density_volume(sim, a),
                  &sim->flaw_count[a], &sim->flaw_strain[a]);
}

void damage_free(sph_sim *sim)
{
    free(sim->damage);
    free(sim->flaw_strain);
    free(sim->flaw_count);
    sim->damage = sim->flaw_strain = NULL;
    sim->flaw_count = NULL;
    sim->damage_n = 0;
}

sph_status damage_prepare(sph_sim *sim)
{
    if (!sim->fx.damage) {
        damage_free(sim);
        return SPH_OK;
    }
    int any = 0;
    for (int k = 0; k < sim->n_bodies && !any; ++k) {
        const material *m = &sim->materials[sim->bodies[k].material];
        any = sim->bodies[k].motion == SPH_MOTION_FREE && material_has_flaws(m);
    }
    if (!any)
        return sph_fail(sim, SPH_ERR_STATE,
                        "effect damage: no free body has a material with flaws; set weibull_k "
                        "[m^-3] and weibull_m > 0 with sph_material_set");
    const size_t n = sim->n, from = sim->damage && sim->damage_n <= n ? sim->damage_n : 0;
    if (sim->damage && from == n)
        return SPH_OK;
    double *D = realloc(sim->damage, n * sizeof *D);
    if (D)
        sim->damage = D;
    double *eps = realloc(sim->flaw_strain, n * sizeof *eps);
    if (eps)
        sim->flaw_strain = eps;
    int *count = realloc(sim->flaw_count, n * sizeof *count);
    if (count)
        sim->flaw_count = count;
    if (!D || !eps || !count) {
        damage_free(sim);
        return sph_fail(sim, SPH_ERR_MEMORY, "effect damage: cannot allocate for %zu particles", n);
    }
    for (size_t a = from; a < n; ++a) {
        D[a] = 0.0;
        draw_flaws(sim, a);
    }
    sim->damage_n = n;
    return SPH_OK;
}

/* Redraws every particle's flaws (the seed or flaws parameter changed). */
void damage_redraw(sph_sim *sim)
{
    if (!sim->damage)
        return;
    for (size_t a = 0; a < sim->damage_n; ++a)
        draw_flaws(sim, a);
}

/* The flaws active at the largest principal strain of the state (rho, S)
 * of the particle of global id `id` (count flaws, the weakest at
 * `strain`). */
static int active_flaws_of(const sph_sim *sim, uint64_t id, const material *m, double kV,
                           double rho, const double *S, int count, double strain)
{
    if (count == 0)
        return 0;
    const double P = eos_pressure(m->c0_squared, rho, m->rho0);
    const double eps = largest_principal_strain(sim->dim, S, P, m->K, m->mu);
    if (!(eps >= strain))
        return 0;
    const double u = kV * pow(eps, m->weibull_m);
    return damage_flaws_below(stream_of(sim), id, count, u);
}

int damage_active_flaws(const sph_sim *sim, size_t a)
{
    if (sim->flaw_count[a] == 0)
        return 0;
    return active_flaws_of(
        sim, a, &sim->materials[sim->material_of[a]], flaw_density_volume(sim, a), sim->rho[a],
        sim->S + a * (size_t)sim->ncomp, sim->flaw_count[a], sim->flaw_strain[a]);
}

/* One particle: activation by the current strain, growth of *D over dt. */
static int grow_of(const sph_sim *sim, uint64_t id, const material *m, double kV, double rho,
                   const double *S, int count, double strain, double *D, double dt, double rate_h)
{
    if (count == 0 || *D >= 1.0)
        return 0;
    const int active = active_flaws_of(sim, id, m, kV, rho, S, count, strain);
    if (active == 0)
        return 0;
    const double cap = cbrt((double)active / (double)count);
    const double now = cbrt(*D);
    double next = now + dt * DAMAGE_CRACK_SPEED * m->c_p * rate_h;
    if (next > cap)
        next = cap;
    if (!(next > now))
        return 0;
    *D = next >= 1.0 ? 1.0 : next * next * next;
    return 1;
}

static int grow(sph_sim *sim, size_t a, double dt, double rate_h)
{
    if (sim->flaw_count[a] == 0 || sim->damage[a] >= 1.0)
        return 0;
    return grow_of(sim, a, &sim->materials[sim->material_of[a]], flaw_density_volume(sim, a),
                   sim->rho[a], sim->S + a * (size_t)sim->ncomp, sim->flaw_count[a],
                   sim->flaw_strain[a], &sim->damage[a], dt, rate_h);
}

sph_status damage_stage(sph_sim *sim, double dt, int *changed)
{
    *changed = 0;
    if (!sim->damage) {
        sph_status st = damage_prepare(sim);
        if (st)
            return st;
    }
    const double rate_h = 1.0 / (DAMAGE_CRACK_RADIUS * sim->h); /* 1 / (k_R h) */
    const long n = (long)sim->n;
    int grew = 0;
    if (sim->energy_account) { /* the elastic energy the growth releases */
        double released = 0.0;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(| : grew) \
    reduction(+ : released)
        for (long a = 0; a < n; ++a) {
            const double before = sim->damage[a];
            if (grow(sim, (size_t)a, dt, rate_h)) {
                grew = 1;
                released += energy_damage_released(sim, (size_t)a, before, sim->damage[a]);
            }
        }
        sim->dissipated_damage += released;
    } else {
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(| : grew)
        for (long a = 0; a < n; ++a)
            grew |= grow(sim, (size_t)a, dt, rate_h);
    }
    *changed = grew;
    return SPH_OK;
}

/* ------------------------------------------------------------- fragments */

static size_t find_root(size_t *parent, size_t a)
{
    while (parent[a] != a) {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    return a;
}

/* Joins the regions of a and b, the smaller root becoming the parent. */
static void unite(size_t *parent, size_t a, size_t b)
{
    const size_t ra = find_root(parent, a), rb = find_root(parent, b);
    if (ra < rb)
        parent[rb] = ra;
    else if (rb < ra)
        parent[ra] = rb;
}

sph_status damage_fragments(sph_sim *sim, double *out, long *count)
{
    const size_t n = sim->n;
    const int dim = sim->dim;
    sph_status st;
    if (!sim->nl.valid || sim->nl.n != n) {
        if ((st = sim_prepare(sim)))
            return st;
    }
    size_t *parent = malloc((n ? n : 1) * sizeof *parent);
    if (!parent)
        return sph_fail(sim, SPH_ERR_MEMORY, "fragments: cannot allocate for %zu particles", n);
    const double reach = kernel_support(sim->kernel) * sim->h, reach2 = reach * reach;
    for (size_t a = 0; a < n; ++a)
        parent[a] = a;
    for (size_t a = 0; a < n; ++a) {
        const int in_a = sim->bodies[sim->body_of[a]].motion == SPH_MOTION_FREE &&
                         (!sim->damage || sim->damage[a] < 1.0);
        if (!in_a)
            continue;
        const size_t end = neighbour_row(&sim->nl, a + 1);
        for (size_t k = neighbour_row(&sim->nl, a); k < end; ++k) {
            const size_t b = (size_t)sim->nl.indices[k];
            if (sim->bodies[sim->body_of[b]].motion != SPH_MOTION_FREE ||
                (sim->damage && !(sim->damage[b] < 1.0)))
                continue;
            double r2 = 0.0;
            for (int i = 0; i < dim; ++i) {
                double d = sim->x[a * dim + i] - sim->x[b * dim + i];
                if (sim->has_domain && sim->periodic[i])
                    d = nearest_image(d, sim->hi[i] - sim->lo[i], 0.5 * (sim->hi[i] - sim->lo[i]));
                r2 += d * d;
            }
            if (r2 < reach2)
                unite(parent, a, b);
        }
    }
    /* ids in the order of each fragment's first particle */
    long next = 0;
    for (size_t a = 0; a < n; ++a) {
        const int in_a = sim->bodies[sim->body_of[a]].motion == SPH_MOTION_FREE &&
                         (!sim->damage || sim->damage[a] < 1.0);
        if (!in_a) {
            out[a] = -1.0;
            continue;
        }
        const size_t r = find_root(parent, a);
        out[a] = r == a ? (double)next++ : out[r];
    }
    free(parent);
    if (count)
        *count = next;
    return SPH_OK;
}

/* ---------------------------------------------------------- public calls */

sph_status sph_material_set(sph_sim *sim, int id, const char *key, double value)
{
    material *m = NULL;
    const sph_status st = material_of_call(sim, "sph_material_set", "key", key, id, &m);
    if (st)
        return st;
    double *slot = strcmp(key, "weibull_k") == 0   ? &m->weibull_k
                   : strcmp(key, "weibull_m") == 0 ? &m->weibull_m
                                                   : NULL;
    if (!slot)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "material key '%s' is unknown (known: weibull_k, weibull_m)", key);
    if (!(value >= 0.0) || !isfinite(value))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "material %d: %s=%g must be finite and >= 0%s", id,
                        key, value, slot == &m->weibull_k ? " [m^-3]" : "");
    *slot = value;
    damage_redraw(sim);
    sim->rates_valid = 0;
    return sph_ok(sim);
}

sph_status sph_flaws_active_at(sph_sim *sim, double strain, double *count)
{
    sph_status st = sph_need(sim, count, "sph_flaws_active_at", "count");
    if (st)
        return st;
    if (!sim->fx.damage)
        return sph_fail(sim, SPH_ERR_STATE, "sph_flaws_active_at: effect damage is off");
    if (!(strain >= 0.0) || !isfinite(strain))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_flaws_active_at: strain=%g must be finite and >= 0", strain);
    if ((st = damage_prepare(sim)))
        return st;
    double total = 0.0;
    for (size_t a = 0; a < sim->n; ++a) {
        if (sim->flaw_count[a] == 0 || strain < sim->flaw_strain[a])
            continue;
        const material *m = &sim->materials[sim->material_of[a]];
        total += damage_flaws_below(stream_of(sim), a, sim->flaw_count[a],
                                    flaw_density_volume(sim, a) * pow(strain, m->weibull_m));
    }
    *count = total;
    return sph_ok(sim);
}

/* ------------------------------------------- particles of another code */

/* The checks the calls on external particles share: the effect on, the
 * arrays given, each material index defined.  NULL `what` skips one. */
static sph_status external_ready(sph_sim *sim, const char *fn, size_t n, const uint64_t *id,
                                 const double *mass, const int *mat)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!sim->fx.damage)
        return sph_fail(sim, SPH_ERR_STATE, "%s: effect damage is off (sph_effect)", fn);
    if (n == 0)
        return SPH_OK;
    sph_status st;
    if ((st = sph_need(sim, id, fn, "id")) || (st = sph_need(sim, mass, fn, "mass")) ||
        (st = sph_need(sim, mat, fn, "material")))
        return st;
    if (!(sim->h > 0.0))
        return sph_fail(sim, SPH_ERR_STATE, "%s: the smoothing length is not set (sph_set_spacing)",
                        fn);
    for (size_t a = 0; a < n; ++a) {
        if (mat[a] < 0 || mat[a] >= sim->n_materials)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: material[%zu]=%d: %d materials are defined",
                            fn, a, mat[a], sim->n_materials);
        if (!(mass[a] > 0.0) || !isfinite(mass[a]))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: mass[%zu]=%g must be finite and > 0", fn, a,
                            mass[a]);
    }
    return SPH_OK;
}

sph_status sph_damage_flaws(sph_sim *sim, size_t n, const uint64_t *id, const double *mass,
                            const int *mat, const unsigned char *flawed, int *flaw_count,
                            double *flaw_strain)
{
    const char *fn = "sph_damage_flaws";
    sph_status st = external_ready(sim, fn, n, id, mass, mat);
    if (st || n == 0)
        return st ? st : sph_ok(sim);
    if ((st = sph_need(sim, flaw_count, fn, "flaw_count")) ||
        (st = sph_need(sim, flaw_strain, fn, "flaw_strain")))
        return st;
    for (size_t a = 0; a < n; ++a) {
        const material *m = &sim->materials[mat[a]];
        if ((flawed && !flawed[a]) || !material_has_flaws(m)) {
            flaw_count[a] = 0;
            flaw_strain[a] = INFINITY;
            continue;
        }
        draw_flaws_of(sim, id[a], m, flaw_density_volume_of(m, mass[a]), &flaw_count[a],
                      &flaw_strain[a]);
    }
    return sph_ok(sim);
}

/* The arrays of the state the growth and the count read. */
static sph_status external_state(sph_sim *sim, const char *fn, const double *rho, const double *S,
                                 const int *flaw_count, const double *flaw_strain)
{
    sph_status st;
    if ((st = sph_need(sim, rho, fn, "rho")) || (st = sph_need(sim, S, fn, "S")) ||
        (st = sph_need(sim, flaw_count, fn, "flaw_count")) ||
        (st = sph_need(sim, flaw_strain, fn, "flaw_strain")))
        return st;
    return SPH_OK;
}

sph_status sph_damage_grow(sph_sim *sim, size_t n, double dt, const uint64_t *id,
                           const double *mass, const int *mat, const double *rho, const double *S,
                           const int *flaw_count, const double *flaw_strain, double *damage,
                           int *changed)
{
    const char *fn = "sph_damage_grow";
    sph_status st = external_ready(sim, fn, n, id, mass, mat);
    if (st)
        return st;
    if ((st = sph_need(sim, changed, fn, "changed")))
        return st;
    *changed = 0;
    if (!(dt >= 0.0) || !isfinite(dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: dt=%g s must be finite and >= 0", fn, dt);
    if (n == 0)
        return sph_ok(sim);
    if ((st = external_state(sim, fn, rho, S, flaw_count, flaw_strain)) ||
        (st = sph_need(sim, damage, fn, "damage")))
        return st;
    const double rate_h = 1.0 / (DAMAGE_CRACK_RADIUS * sim->h); /* 1 / (k_R h) */
    const size_t ncomp = (size_t)sim->ncomp;
    const long count = (long)n;
    int grew = 0;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(| : grew)
    for (long a = 0; a < count; ++a) {
        const material *m = &sim->materials[mat[a]];
        grew |=
            grow_of(sim, id[a], m, flaw_density_volume_of(m, mass[a]), rho[a],
                    S + (size_t)a * ncomp, flaw_count[a], flaw_strain[a], &damage[a], dt, rate_h);
    }
    *changed = grew;
    return sph_ok(sim);
}

sph_status sph_damage_active(sph_sim *sim, size_t n, const uint64_t *id, const double *mass,
                             const int *mat, const double *rho, const double *S,
                             const int *flaw_count, const double *flaw_strain, double *active)
{
    const char *fn = "sph_damage_active";
    sph_status st = external_ready(sim, fn, n, id, mass, mat);
    if (st || n == 0)
        return st ? st : sph_ok(sim);
    if ((st = external_state(sim, fn, rho, S, flaw_count, flaw_strain)) ||
        (st = sph_need(sim, active, fn, "active")))
        return st;
    const size_t ncomp = (size_t)sim->ncomp;
    for (size_t a = 0; a < n; ++a) {
        const material *m = &sim->materials[mat[a]];
        active[a] = (double)active_flaws_of(sim, id[a], m, flaw_density_volume_of(m, mass[a]),
                                            rho[a], S + a * ncomp, flaw_count[a], flaw_strain[a]);
    }
    return sph_ok(sim);
}

sph_status sph_damage_fragment_labels(sph_sim *sim, const sph_particles *particles,
                                      const sph_neighbours *neighbours, const unsigned char *member,
                                      double *label, int *changed)
{
    const char *fn = "sph_damage_fragment_labels";
    sph_status st = caller_pairs(sim, fn, particles, neighbours, changed, "changed");
    if (st)
        return st;
    *changed = 0;
    if (!sim->fx.damage)
        return sph_fail(sim, SPH_ERR_STATE, "%s: effect damage is off (sph_effect)", fn);
    const size_t n = particles->n_total, n_local = particles->n_local;
    if (n == 0)
        return sph_ok(sim);
    if ((st = sph_need(sim, particles->x, fn, "particles->x")) ||
        (st = sph_need(sim, particles->damage, fn, "particles->damage")) ||
        (st = sph_need(sim, member, fn, "member")) || (st = sph_need(sim, label, fn, "label")))
        return st;
    if (n_local > n)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: n_local=%zu is more than n_total=%zu", fn,
                        n_local, n);
    const int by_rows = neighbours->offsets && neighbours->indices;
    if (!by_rows && !(neighbours->lists && neighbours->counts) && n_local > 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "%s: give neighbours as offsets+indices or "
                        "lists+counts",
                        fn);
    if (!(sim->h > 0.0))
        return sph_fail(sim, SPH_ERR_STATE, "%s: the smoothing length is not set (sph_set_spacing)",
                        fn);
    size_t *parent = malloc(n * sizeof *parent);
    double *least = malloc(n * sizeof *least);
    if (!parent || !least) {
        free(parent);
        free(least);
        return sph_fail(sim, SPH_ERR_MEMORY, "%s: cannot allocate for %zu particles", fn, n);
    }
    /* the joining rule of damage_fragments: particles of free bodies
     * (member) with D < 1, closer than the kernel support */
    const int dim = sim->dim;
    const size_t stride = particles->stride ? particles->stride : (size_t)dim;
    const double reach = kernel_support(sim->kernel) * sim->h, reach2 = reach * reach;
    const double *x = particles->x, *D = particles->damage;
    for (size_t a = 0; a < n; ++a)
        parent[a] = a;
    for (size_t a = 0; a < n_local; ++a) {
        if (!member[a] || !(D[a] < 1.0))
            continue;
        size_t count;
        const int *row = caller_row(neighbours, by_rows, a, &count);
        for (size_t k = 0; k < count; ++k) {
            const size_t b = (size_t)row[k];
            if (b >= n) {
                free(parent);
                free(least);
                return sph_fail(sim, SPH_ERR_ARGUMENT,
                                "%s: neighbour %zu of particle %zu is not below n_total=%zu", fn, b,
                                a, n);
            }
            if (!member[b] || !(D[b] < 1.0))
                continue;
            double r2 = 0.0;
            for (int i = 0; i < dim; ++i) {
                const double d = x[a * stride + i] - x[b * stride + i];
                r2 += d * d;
            }
            if (r2 < reach2)
                unite(parent, a, b);
        }
    }
    /* each region's least label, then every member's label */
    for (size_t a = 0; a < n; ++a)
        least[a] = INFINITY;
    for (size_t a = 0; a < n; ++a) {
        if (!member[a] || !(D[a] < 1.0))
            continue;
        const size_t r = find_root(parent, a);
        if (label[a] < least[r])
            least[r] = label[a];
    }
    int moved = 0;
    for (size_t a = 0; a < n; ++a) {
        const double next = member[a] && D[a] < 1.0 ? least[find_root(parent, a)] : -1.0;
        if (a < n_local && next != label[a])
            moved = 1;
        label[a] = next;
    }
    free(parent);
    free(least);
    *changed = moved;
    return sph_ok(sim);
}
