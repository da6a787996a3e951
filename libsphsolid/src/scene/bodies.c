/* Bodies: particles on lattices or given points, their motions and lookup. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "physics/kernel.h"
#include "core/sim.h"

/* ---------------------------------------------------------------- bodies */

double sim_support(const sph_sim *sim) { return kernel_support(sim->kernel) * sim->h; }

static sph_status grow_particles(sph_sim *sim, size_t n)
{
    if (n <= sim->capacity)
        return SPH_OK;
    size_t cap = sim->capacity ? sim->capacity : 1024;
    while (cap < n)
        cap *= 2;
    const int dim = sim->dim, nc = sim->ncomp;
#define GROW(ptr, count)                                                                \
    do {                                                                                \
        void *p_ = realloc(ptr, (count) * sizeof *(ptr));                               \
        if (!p_)                                                                        \
            return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %zu particles", cap); \
        ptr = p_;                                                                       \
    } while (0)
    GROW(sim->x, cap * dim);
    GROW(sim->v, cap * dim);
    GROW(sim->rho, cap);
    GROW(sim->S, cap * nc);
    GROW(sim->mass, cap);
    GROW(sim->material_of, cap);
    GROW(sim->body_of, cap);
#undef GROW
    sim->capacity = cap;
    return SPH_OK;
}

/* Release the spare capacity left by growing (called before a run). */
void sim_shrink_to_fit(sph_sim *sim)
{
    if (sim->capacity <= sim->n || sim->n == 0)
        return;
    const size_t n = sim->n;
    const int dim = sim->dim, nc = sim->ncomp;
    void *p;
    if ((p = realloc(sim->x, n * dim * sizeof(double))))
        sim->x = p;
    if ((p = realloc(sim->v, n * dim * sizeof(double))))
        sim->v = p;
    if ((p = realloc(sim->rho, n * sizeof(double))))
        sim->rho = p;
    if ((p = realloc(sim->S, n * nc * sizeof(double))))
        sim->S = p;
    if ((p = realloc(sim->mass, n * sizeof(double))))
        sim->mass = p;
    if ((p = realloc(sim->material_of, n * sizeof(int))))
        sim->material_of = p;
    if ((p = realloc(sim->body_of, n * sizeof(int))))
        sim->body_of = p;
    sim->capacity = n;
}

static sph_status check_name(sph_sim *sim, const char *name)
{
    if (!name || !*name)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body name is empty");
    if (strlen(name) >= SPH_NAME_SIZE)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body name '%s' is longer than %d characters", name,
                        SPH_NAME_SIZE - 1);
    for (int i = 0; i < sim->n_bodies; ++i)
        if (strcmp(sim->bodies[i].name, name) == 0)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "body name '%s' is already used", name);
    return SPH_OK;
}

/* The new particles must keep at least half a spacing from every particle
 * of the other bodies. */
static sph_status check_overlap(sph_sim *sim, const char *name, size_t n, const double *pos,
                                double spacing)
{
    const int dim = sim->dim;
    double lo[3], hi[3];
    for (int i = 0; i < dim; ++i) {
        lo[i] = INFINITY;
        hi[i] = -INFINITY;
    }
    for (size_t k = 0; k < n; ++k)
        for (int i = 0; i < dim; ++i) {
            if (pos[k * dim + i] < lo[i])
                lo[i] = pos[k * dim + i];
            if (pos[k * dim + i] > hi[i])
                hi[i] = pos[k * dim + i];
        }
    for (size_t a = 0; a < sim->n; ++a) {
        const double *xa = sim->x + a * dim;
        const double tol = 0.5 * fmin(spacing, sim->bodies[sim->body_of[a]].spacing);
        int near = 1;
        for (int i = 0; i < dim; ++i)
            near &= xa[i] > lo[i] - tol && xa[i] < hi[i] + tol;
        if (!near)
            continue;
        for (size_t k = 0; k < n; ++k) {
            double r2 = 0.0;
            for (int i = 0; i < dim; ++i) {
                const double d = xa[i] - pos[k * dim + i];
                r2 += d * d;
            }
            if (r2 < tol * tol * (1.0 - 1e-9))
                return sph_fail(sim, SPH_ERR_ARGUMENT,
                                "body '%s' overlaps body '%s': its particle %zu at (%g, %g%s%.0g) "
                                "is %g m from particle %zu (closer than half a spacing, %g m)",
                                name, sim->bodies[sim->body_of[a]].name, k, pos[k * dim],
                                pos[k * dim + 1], dim == 3 ? ", " : "",
                                dim == 3 ? pos[k * dim + 2] : 0.0, sqrt(r2), a, tol);
        }
    }
    return SPH_OK;
}

sph_status sph_add_particles(sph_sim *sim, const char *name, int material_id, size_t n,
                             const double *pos, const double *volumes, double spacing, int *body_id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    sph_status st = check_name(sim, name);
    if (st)
        return st;
    if (sim->out)
        return sph_fail(sim, SPH_ERR_STATE,
                        "body '%s': add bodies before opening the output file (its frames would "
                        "hold only the earlier particles)",
                        name);
    if (material_id < 0 || material_id >= sim->n_materials)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "body '%s': material=%d, but %d materials are defined", name, material_id,
                        sim->n_materials);
    if (n == 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s' is empty (0 particles)", name);
    if (!pos)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': positions are NULL", name);
    if (!(spacing > 0.0) || !isfinite(spacing))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': spacing dx=%g must be finite and > 0",
                        name, spacing);
    const int dim = sim->dim;
    for (size_t k = 0; k < n; ++k) {
        for (int i = 0; i < dim; ++i) {
            const double xi = pos[k * dim + i];
            if (!isfinite(xi))
                return sph_fail(sim, SPH_ERR_ARGUMENT,
                                "body '%s': particle %zu has a non-finite coordinate %d", name, k,
                                i);
            if ((st = coordinate_check(sim, name, k, i, xi, spacing)))
                return st;
            if (sim->has_domain && (xi < sim->lo[i] || xi > sim->hi[i]))
                return sph_fail(
                    sim, SPH_ERR_ARGUMENT,
                    "body '%s': particle %zu at coordinate %c=%g lies outside the domain [%g, %g]",
                    name, k, "xyz"[i], xi, sim->lo[i], sim->hi[i]);
        }
        if (volumes && (!(volumes[k] > 0.0) || !isfinite(volumes[k]) ||
                        !isfinite(volumes[k] * sim->materials[material_id].rho0)))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "body '%s': particle %zu has volume %g (must be finite and > 0)", name,
                            k, volumes[k]);
    }
    st = check_overlap(sim, name, n, pos, spacing);
    if (st)
        return st;
    {
        char what[SPH_NAME_SIZE + 16];
        snprintf(what, sizeof what, "body '%s'", name);
        if ((st = memory_check(sim, (double)n, what)))
            return st;
    }
    if ((st = grow_particles(sim, sim->n + n)))
        return st;
    body *b = realloc(sim->bodies, (size_t)(sim->n_bodies + 1) * sizeof *b);
    if (!b)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate a body");
    sim->bodies = b;
    body *nb = &b[sim->n_bodies];
    memset(nb, 0, sizeof *nb);
    strcpy(nb->name, name);
    nb->material = material_id;
    nb->motion = SPH_MOTION_FREE;
    nb->first = sim->n;
    nb->count = n;
    nb->spacing = spacing;
    for (int i = 0; i < dim; ++i) {
        nb->extent_lo[i] = INFINITY;
        nb->extent_hi[i] = -INFINITY;
        for (size_t k = 0; k < n; ++k) {
            nb->extent_lo[i] = fmin(nb->extent_lo[i], pos[k * dim + i]);
            nb->extent_hi[i] = fmax(nb->extent_hi[i], pos[k * dim + i]);
        }
    }
    const material *m = &sim->materials[material_id];
    const double default_volume = pow(spacing, dim);
    for (size_t k = 0; k < n; ++k) {
        const size_t a = sim->n + k;
        memcpy(sim->x + a * dim, pos + k * dim, (size_t)dim * sizeof(double));
        memset(sim->v + a * dim, 0, (size_t)dim * sizeof(double));
        memset(sim->S + a * sim->ncomp, 0, (size_t)sim->ncomp * sizeof(double));
        sim->rho[a] = m->rho0;
        sim->mass[a] = m->rho0 * (volumes ? volumes[k] : default_volume);
        nb->total_mass += sim->mass[a];
        sim->material_of[a] = material_id;
        sim->body_of[a] = sim->n_bodies;
    }
    sim->n += n;
    if (sim->n_bodies == 0) {
        sim->dx_ref = spacing;
        sim->h = sim->h_over_dx * spacing;
    }
    if (body_id)
        *body_id = sim->n_bodies;
    sim->n_bodies++;
    body_extent_from_particles(sim, sim->n_bodies - 1);
    sim->nl.valid = 0;
    sim->rates_valid = 0;
    sim->power_carry_valid = 0;
    return sph_ok(sim);
}

sph_status sph_block_lattice(sph_sim *sim, const char *name, const double lo[3], const double hi[3],
                             double dx, long count[3], double step[3])
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!lo || !hi)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "block '%s': lo and hi must not be NULL",
                        name ? name : "");
    if (!(dx > 0.0) || !isfinite(dx))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "block '%s': dx=%g must be finite and > 0",
                        name ? name : "", dx);
    const int dim = sim->dim;
    long n_axis[3] = {1, 1, 1};
    double h[3] = {0, 0, 0};
    size_t n = 1;
    double cells = 1.0;
    sph_status st;
    for (int i = 0; i < dim; ++i) {
        const double L = hi[i] - lo[i];
        if (!(L > 0.0) || !isfinite(L))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "block '%s': extent along %c is hi-lo=%g (must be > 0)",
                            name ? name : "", "xyz"[i], L);
        if (L / dx > 1e12)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "block '%s': extent %g m along %c is %g spacings dx=%g m: too many",
                            name ? name : "", L, "xyz"[i], L / dx, dx);
        cells *= round(L / dx);
        n_axis[i] = lround(L / dx);
        if (n_axis[i] < 1)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "block '%s': extent %g along %c is less than half of dx=%g",
                            name ? name : "", L, "xyz"[i], dx);
        h[i] = L / (double)n_axis[i];
        n *= (size_t)n_axis[i];
    }
    {
        /* before allocating anything: would a run of this many fit? */
        char what[SPH_NAME_SIZE + 40];
        snprintf(what, sizeof what, "block '%s' (dx=%g m)", name ? name : "", dx);
        if ((st = memory_check(sim, cells, what)))
            return st;
    }
    if (n > (size_t)1 << 31)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "block '%s': %zu particles is too many (at most 2^31)", name ? name : "",
                        n);
    for (int i = 0; i < 3; ++i) {
        if (count)
            count[i] = n_axis[i];
        if (step)
            step[i] = h[i];
    }
    return sph_ok(sim);
}

sph_status sph_add_block(sph_sim *sim, const char *name, int material_id, const double lo[3],
                         const double hi[3], double dx, int *body_id)
{
    long count[3];
    double step[3];
    sph_status st = sph_block_lattice(sim, name, lo, hi, dx, count, step);
    if (st)
        return st;
    int id;
    if ((st = lattice_add(sim, name, material_id, lo, hi, count, step, dx, "block", &id)))
        return st;
    if (body_id)
        *body_id = id;
    return SPH_OK;
}

static sph_status check_body(sph_sim *sim, int id)
{
    if (id < 0 || id >= sim->n_bodies)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body=%d: %d bodies are defined", id, sim->n_bodies);
    return SPH_OK;
}

sph_status sph_set_motion(sph_sim *sim, int id, sph_motion motion, const double *vector)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (check_body(sim, id))
        return SPH_ERR_ARGUMENT;
    body *b = &sim->bodies[id];
    if (motion == SPH_MOTION_ROTATION)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "body '%s': a rotation needs its centre; use sph_set_rotation", b->name);
    if (motion < SPH_MOTION_FREE || motion > SPH_MOTION_FORCE)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': motion=%d is not a sph_motion", b->name,
                        (int)motion);
    double vec[3] = {0, 0, 0};
    if (motion == SPH_MOTION_VELOCITY || motion == SPH_MOTION_FORCE) {
        if (!vector)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': motion needs a %s vector", b->name,
                            motion == SPH_MOTION_VELOCITY ? "velocity" : "force");
        for (int i = 0; i < sim->dim; ++i) {
            if (!isfinite(vector[i]))
                return sph_fail(sim, SPH_ERR_ARGUMENT,
                                "body '%s': motion vector component %c=%g is not finite", b->name,
                                "xyz"[i], vector[i]);
            vec[i] = vector[i];
        }
    }
    b->motion = motion;
    memcpy(b->vector, vec, sizeof vec);
    memset(b->centre, 0, sizeof b->centre);
    const int dim = sim->dim;
    for (size_t a = b->first; a < b->first + b->count; ++a)
        for (int i = 0; i < dim; ++i) {
            if (motion == SPH_MOTION_FIXED)
                sim->v[a * dim + i] = 0.0;
            else if (motion == SPH_MOTION_VELOCITY)
                sim->v[a * dim + i] = vec[i];
        }
    sim->rates_valid = 0;
    return sph_ok(sim);
}

/* v = omega x (x - c) for one particle */
void rotation_velocity(int dim, const double *omega, const double *centre, const double *x,
                       double *v)
{
    const double r[3] = {x[0] - centre[0], x[1] - centre[1], dim == 3 ? x[2] - centre[2] : 0.0};
    v[0] = omega[1] * r[2] - omega[2] * r[1];
    v[1] = omega[2] * r[0] - omega[0] * r[2];
    if (dim == 3)
        v[2] = omega[0] * r[1] - omega[1] * r[0];
}

sph_status sph_set_rotation(sph_sim *sim, int id, const double *centre, const double *omega)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (check_body(sim, id))
        return SPH_ERR_ARGUMENT;
    body *b = &sim->bodies[id];
    if (!centre || !omega)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "body '%s': rotation needs a centre and an angular velocity", b->name);
    const int dim = sim->dim;
    double c[3] = {0, 0, 0};
    for (int i = 0; i < dim; ++i) {
        if (!isfinite(centre[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': rotation centre %c=%g is not finite",
                            b->name, "xyz"[i], centre[i]);
        c[i] = centre[i];
    }
    for (int i = 0; i < 3; ++i) {
        if (!isfinite(omega[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "body '%s': angular velocity omega_%c=%g is not finite", b->name,
                            "xyz"[i], omega[i]);
        if (dim == 2 && i < 2 && omega[i] != 0.0)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "body '%s': omega_%c=%g; in 2D the rotation is about z (only omega_z "
                            "may be non-zero)",
                            b->name, "xyz"[i], omega[i]);
    }
    b->motion = SPH_MOTION_ROTATION;
    memcpy(b->vector, omega, 3 * sizeof(double));
    memcpy(b->centre, c, sizeof c);
    for (size_t a = b->first; a < b->first + b->count; ++a)
        rotation_velocity(dim, b->vector, b->centre, sim->x + a * dim, sim->v + a * dim);
    sim->rates_valid = 0;
    return sph_ok(sim);
}

sph_status sph_set_body_velocity(sph_sim *sim, int id, const double *v)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (check_body(sim, id))
        return SPH_ERR_ARGUMENT;
    body *b = &sim->bodies[id];
    if (!v)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': velocity is NULL", b->name);
    if (b->motion == SPH_MOTION_FIXED || b->motion == SPH_MOTION_VELOCITY ||
        b->motion == SPH_MOTION_ROTATION)
        return sph_fail(sim, SPH_ERR_STATE, "body '%s' has a prescribed motion; use sph_set_motion",
                        b->name);
    for (int i = 0; i < sim->dim; ++i)
        if (!isfinite(v[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "body '%s': velocity component %c=%g is not finite", b->name, "xyz"[i],
                            v[i]);
    for (size_t a = b->first; a < b->first + b->count; ++a)
        memcpy(sim->v + a * sim->dim, v, (size_t)sim->dim * sizeof(double));
    sim->rates_valid = 0;
    return sph_ok(sim);
}

size_t sph_particle_count(const sph_sim *sim) { return sim ? sim->n : 0; }
int sph_body_count(const sph_sim *sim) { return sim ? sim->n_bodies : 0; }

sph_status sph_body_info_get(sph_sim *sim, int id, sph_body_info *info)
{
    sph_status st = sph_need(sim, info, "sph_body_info_get", "info");
    if (st)
        return st;
    if (check_body(sim, id))
        return SPH_ERR_ARGUMENT;
    const body *b = &sim->bodies[id];
    *info = (sph_body_info){.name = b->name,
                            .material = b->material,
                            .motion = b->motion,
                            .first = b->first,
                            .count = b->count,
                            .spacing = b->spacing};
    return SPH_OK;
}

sph_status sph_body_find(sph_sim *sim, const char *name, int *id)
{
    sph_status st = sph_need(sim, id, "sph_body_find", "id");
    if (st)
        return st;
    for (int i = 0; i < sim->n_bodies; ++i)
        if (name && strcmp(sim->bodies[i].name, name) == 0) {
            *id = i;
            return SPH_OK;
        }
    return sph_fail(sim, SPH_ERR_ARGUMENT, "no body named '%s'", name ? name : "(null)");
}
