/* The scene: handle, materials, bodies, domain, kernel, time step, fields. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernel.h"
#include "sim.h"

/* ---------------------------------------------------------------- handle */

sph_status sph_create(int dimension, sph_sim **out)
{
    if (!out)
        return SPH_ERR_ARGUMENT;
    sph_sim *sim = calloc(1, sizeof *sim);
    *out = sim;
    if (!sim)
        return SPH_ERR_MEMORY;
    sim->dim = dimension == 3 ? 3 : 2;
    sim->ncomp = SPH_STRESS_COMPONENTS(sim->dim);
    sim->nsym = sim->dim == 2 ? 3 : 6;
    sim->h_over_dx = 1.2;
    sim->kernel = SPH_KERNEL_CUBIC_SPLINE;
    sim->progress_interval = 0;
    sim->watch_speed = 1.0;
    sim->watch_rho_min = 0.5;
    sim->watch_rho_max = 2.0;
    if (dimension != 2 && dimension != 3) {
        sim->failed = -1;
        return sph_fail(sim, SPH_ERR_ARGUMENT, "dimension=%d: must be 2 or 3", dimension);
    }
    return SPH_OK;
}

void sph_destroy(sph_sim *sim)
{
    if (!sim)
        return;
    output_free(sim);
    free(sim->materials);
    free(sim->bodies);
    free(sim->probes);
    free(sim->x); free(sim->v); free(sim->rho); free(sim->S); free(sim->mass);
    free(sim->material_of); free(sim->body_of);
    free(sim->saved);
    free(sim->x_saved);
    free(sim->dv_dt); free(sim->drho_dt); free(sim->dS_dt); free(sim->dx_dt);
    free(sim->pair_data); free(sim->stress_R);
    neighbour_free(&sim->nl);
    free(sim);
}

int sph_dimension(const sph_sim *sim) { return sim ? sim->dim : 0; }

sph_status sph_set_threads(sph_sim *sim, int threads)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (threads < 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "threads=%d: must be >= 0 (0 = OpenMP default)", threads);
    sim->threads = threads;
    return sph_ok(sim);
}

sph_status sph_set_watchdog(sph_sim *sim, double max_speed_over_cp,
                            double min_density_ratio, double max_density_ratio)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(max_speed_over_cp >= 0.0) || !isfinite(max_speed_over_cp))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "watchdog max_speed_over_cp=%g: must be finite and >= 0", max_speed_over_cp);
    if (!(min_density_ratio >= 0.0 && min_density_ratio < 1.0))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "watchdog min_density_ratio=%g: must be in [0, 1)", min_density_ratio);
    if (!(max_density_ratio == 0.0 || (max_density_ratio > 1.0 && isfinite(max_density_ratio))))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "watchdog max_density_ratio=%g: must be 0 (off) or > 1", max_density_ratio);
    sim->watch_speed = max_speed_over_cp;
    sim->watch_rho_min = min_density_ratio;
    sim->watch_rho_max = max_density_ratio;
    return sph_ok(sim);
}

/* ------------------------------------------------------------- materials */

static sph_status add_material(sph_sim *sim, double K, double mu, double rho0,
                               int *id)
{
    if (!(K > 0.0) || !isfinite(K))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "bulk modulus K=%g: must be finite and > 0", K);
    if (!(mu >= 0.0) || !isfinite(mu))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "shear modulus mu=%g: must be finite and >= 0", mu);
    if (!(rho0 > 0.0) || !isfinite(rho0))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "reference density rho0=%g: must be finite and > 0", rho0);
    material *m = realloc(sim->materials, (size_t)(sim->n_materials + 1) * sizeof *m);
    if (!m)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate a material");
    sim->materials = m;
    material *mat = &m[sim->n_materials];
    mat->K = K;
    mat->mu = mu;
    mat->rho0 = rho0;
    mat->c0_squared = K / rho0;
    mat->c0 = sqrt(mat->c0_squared);
    mat->c_p = sqrt((K + 4.0 * mu / 3.0) / rho0);
    if (id)
        *id = sim->n_materials;
    sim->n_materials++;
    return sph_ok(sim);
}

static sph_status check_poisson(sph_sim *sim, double nu)
{
    if (!(nu > -1.0 && nu < 0.5))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "Poisson ratio nu=%g: must be in (-1, 0.5)", nu);
    return SPH_OK;
}

sph_status sph_add_material_K_mu(sph_sim *sim, double K, double mu, double rho0, int *id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    return add_material(sim, K, mu, rho0, id);
}

sph_status sph_add_material_E_nu(sph_sim *sim, double E, double nu, double rho0, int *id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(E > 0.0) || !isfinite(E))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "Young's modulus E=%g: must be finite and > 0", E);
    if (check_poisson(sim, nu))
        return SPH_ERR_ARGUMENT;
    return add_material(sim, E / (3.0 * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu)), rho0, id);
}

sph_status sph_add_material_K_nu(sph_sim *sim, double K, double nu, double rho0, int *id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(K > 0.0) || !isfinite(K))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "bulk modulus K=%g: must be finite and > 0", K);
    if (check_poisson(sim, nu))
        return SPH_ERR_ARGUMENT;
    /* isotropic elasticity: mu = 3K (1 - 2 nu) / (2 (1 + nu)) */
    return add_material(sim, K, 3.0 * K * (1.0 - 2.0 * nu) / (2.0 * (1.0 + nu)), rho0, id);
}

sph_status sph_material_info_get(sph_sim *sim, int id, sph_material_info *info)
{
    if (!sim || !info)
        return SPH_ERR_ARGUMENT;
    if (id < 0 || id >= sim->n_materials)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "material=%d: %d materials are defined", id, sim->n_materials);
    const material *m = &sim->materials[id];
    info->bulk_modulus = m->K;
    info->shear_modulus = m->mu;
    info->rho0 = m->rho0;
    /* eq. (10) of the paper prints (3K/mu + 2) in the denominator; the
     * isotropic-elasticity relation that (E, nu) -> (K, mu) inverts is
     * nu = (3K - 2mu) / (2 (3K + mu)) = (3K/mu - 2) / (2 (3K/mu + 1)). */
    info->poisson_ratio = (3.0 * m->K - 2.0 * m->mu) / (2.0 * (3.0 * m->K + m->mu));
    info->youngs_modulus = 9.0 * m->K * m->mu / (3.0 * m->K + m->mu);
    info->c0 = m->c0;
    info->c_p = m->c_p;
    return SPH_OK;
}

/* ---------------------------------------------------------------- bodies */

double sim_support(const sph_sim *sim) { return 2.0 * sim->h; }

static sph_status grow_particles(sph_sim *sim, size_t n)
{
    if (n <= sim->capacity)
        return SPH_OK;
    size_t cap = sim->capacity ? sim->capacity : 1024;
    while (cap < n)
        cap *= 2;
    const int dim = sim->dim, nc = sim->ncomp;
#define GROW(ptr, count)                                                       \
    do {                                                                       \
        void *p_ = realloc(ptr, (count) * sizeof *(ptr));                      \
        if (!p_)                                                               \
            return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %zu particles", cap); \
        ptr = p_;                                                              \
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
    if ((p = realloc(sim->x, n * dim * sizeof(double)))) sim->x = p;
    if ((p = realloc(sim->v, n * dim * sizeof(double)))) sim->v = p;
    if ((p = realloc(sim->rho, n * sizeof(double)))) sim->rho = p;
    if ((p = realloc(sim->S, n * nc * sizeof(double)))) sim->S = p;
    if ((p = realloc(sim->mass, n * sizeof(double)))) sim->mass = p;
    if ((p = realloc(sim->material_of, n * sizeof(int)))) sim->material_of = p;
    if ((p = realloc(sim->body_of, n * sizeof(int)))) sim->body_of = p;
    sim->capacity = n;
}

static sph_status check_name(sph_sim *sim, const char *name)
{
    if (!name || !*name)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body name is empty");
    if (strlen(name) >= SPH_NAME_SIZE)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body name '%s' is longer than %d characters", name, SPH_NAME_SIZE - 1);
    for (int i = 0; i < sim->n_bodies; ++i)
        if (strcmp(sim->bodies[i].name, name) == 0)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "body name '%s' is already used", name);
    return SPH_OK;
}

/* The new particles must keep at least half a spacing from every particle
 * of the other bodies. */
static sph_status check_overlap(sph_sim *sim, const char *name, size_t n,
                                const double *pos, double spacing)
{
    const int dim = sim->dim;
    double lo[3], hi[3];
    for (int i = 0; i < dim; ++i) {
        lo[i] = INFINITY;
        hi[i] = -INFINITY;
    }
    for (size_t k = 0; k < n; ++k)
        for (int i = 0; i < dim; ++i) {
            if (pos[k * dim + i] < lo[i]) lo[i] = pos[k * dim + i];
            if (pos[k * dim + i] > hi[i]) hi[i] = pos[k * dim + i];
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
                                "body '%s' overlaps body '%s': its particle %zu at (%g, %g%s%.0g) is %g m from particle %zu (closer than half a spacing, %g m)",
                                name, sim->bodies[sim->body_of[a]].name, k, pos[k * dim], pos[k * dim + 1],
                                dim == 3 ? ", " : "", dim == 3 ? pos[k * dim + 2] : 0.0,
                                sqrt(r2), a, tol);
        }
    }
    return SPH_OK;
}

sph_status sph_add_particles(sph_sim *sim, const char *name, int material_id,
                             size_t n, const double *pos, const double *volumes,
                             double spacing, int *body_id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    sph_status st = check_name(sim, name);
    if (st)
        return st;
    if (material_id < 0 || material_id >= sim->n_materials)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': material=%d, but %d materials are defined",
                        name, material_id, sim->n_materials);
    if (n == 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s' is empty (0 particles)", name);
    if (!pos)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': positions are NULL", name);
    if (!(spacing > 0.0) || !isfinite(spacing))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': spacing dx=%g must be finite and > 0", name, spacing);
    const int dim = sim->dim;
    for (size_t k = 0; k < n; ++k) {
        for (int i = 0; i < dim; ++i) {
            const double xi = pos[k * dim + i];
            if (!isfinite(xi))
                return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': particle %zu has a non-finite coordinate %d", name, k, i);
            if (sim->has_domain && (xi < sim->lo[i] || xi > sim->hi[i]))
                return sph_fail(sim, SPH_ERR_ARGUMENT,
                                "body '%s': particle %zu at coordinate %c=%g lies outside the domain [%g, %g]",
                                name, k, "xyz"[i], xi, sim->lo[i], sim->hi[i]);
        }
        if (volumes && !(volumes[k] > 0.0))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': particle %zu has volume %g (must be > 0)", name, k, volumes[k]);
    }
    st = check_overlap(sim, name, n, pos, spacing);
    if (st)
        return st;
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
    sim->nl.valid = 0;
    sim->rates_valid = 0;
    return sph_ok(sim);
}

sph_status sph_add_block(sph_sim *sim, const char *name, int material_id,
                         const double lo[3], const double hi[3], double dx,
                         int *body_id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!lo || !hi)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "block '%s': lo and hi must not be NULL", name ? name : "");
    if (!(dx > 0.0) || !isfinite(dx))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "block '%s': dx=%g must be finite and > 0", name ? name : "", dx);
    const int dim = sim->dim;
    long count[3] = {1, 1, 1};
    double step[3] = {0, 0, 0};
    size_t n = 1;
    for (int i = 0; i < dim; ++i) {
        const double L = hi[i] - lo[i];
        if (!(L > 0.0) || !isfinite(L))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "block '%s': extent along %c is hi-lo=%g (must be > 0)",
                            name ? name : "", "xyz"[i], L);
        count[i] = lround(L / dx);
        if (count[i] < 1)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "block '%s': extent %g along %c is less than half of dx=%g",
                            name ? name : "", L, "xyz"[i], dx);
        step[i] = L / (double)count[i];
        n *= (size_t)count[i];
    }
    if (n > (size_t)1 << 31)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "block '%s': %zu particles is too many", name ? name : "", n);
    double *pos = malloc(n * (size_t)dim * sizeof *pos);
    double *vol = malloc(n * sizeof *vol);
    if (!pos || !vol) {
        free(pos); free(vol);
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %zu block particles", n);
    }
    const double volume = step[0] * step[1] * (dim == 3 ? step[2] : 1.0);
    size_t k = 0;
    for (long iz = 0; iz < count[2]; ++iz)
        for (long iy = 0; iy < count[1]; ++iy)
            for (long ix = 0; ix < count[0]; ++ix, ++k) {
                pos[k * dim + 0] = lo[0] + (ix + 0.5) * step[0];
                pos[k * dim + 1] = lo[1] + (iy + 0.5) * step[1];
                if (dim == 3)
                    pos[k * dim + 2] = lo[2] + (iz + 0.5) * step[2];
                vol[k] = volume;
            }
    sph_status st = sph_add_particles(sim, name, material_id, n, pos, vol, dx, body_id);
    free(pos);
    free(vol);
    return st;
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
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': a rotation needs its centre; use sph_set_rotation", b->name);
    if (motion < SPH_MOTION_FREE || motion > SPH_MOTION_FORCE)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': motion=%d is not a sph_motion", b->name, (int)motion);
    double vec[3] = {0, 0, 0};
    if (motion == SPH_MOTION_VELOCITY || motion == SPH_MOTION_FORCE) {
        if (!vector)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': motion needs a %s vector", b->name,
                            motion == SPH_MOTION_VELOCITY ? "velocity" : "force");
        for (int i = 0; i < sim->dim; ++i) {
            if (!isfinite(vector[i]))
                return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': motion vector component %c=%g is not finite",
                                b->name, "xyz"[i], vector[i]);
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
void rotation_velocity(int dim, const double *omega, const double *centre, const double *x, double *v)
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
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': rotation needs a centre and an angular velocity", b->name);
    const int dim = sim->dim;
    double c[3] = {0, 0, 0};
    for (int i = 0; i < dim; ++i) {
        if (!isfinite(centre[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': rotation centre %c=%g is not finite", b->name, "xyz"[i], centre[i]);
        c[i] = centre[i];
    }
    for (int i = 0; i < 3; ++i) {
        if (!isfinite(omega[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': angular velocity omega_%c=%g is not finite", b->name, "xyz"[i], omega[i]);
        if (dim == 2 && i < 2 && omega[i] != 0.0)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "body '%s': omega_%c=%g; in 2D the rotation is about z (only omega_z may be non-zero)",
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
    if (b->motion == SPH_MOTION_FIXED || b->motion == SPH_MOTION_VELOCITY || b->motion == SPH_MOTION_ROTATION)
        return sph_fail(sim, SPH_ERR_STATE, "body '%s' has a prescribed motion; use sph_set_motion", b->name);
    for (int i = 0; i < sim->dim; ++i)
        if (!isfinite(v[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "body '%s': velocity component %c=%g is not finite", b->name, "xyz"[i], v[i]);
    for (size_t a = b->first; a < b->first + b->count; ++a)
        memcpy(sim->v + a * sim->dim, v, (size_t)sim->dim * sizeof(double));
    sim->rates_valid = 0;
    return sph_ok(sim);
}

size_t sph_particle_count(const sph_sim *sim) { return sim ? sim->n : 0; }
int sph_body_count(const sph_sim *sim) { return sim ? sim->n_bodies : 0; }

sph_status sph_body_info_get(sph_sim *sim, int id, sph_body_info *info)
{
    if (!sim || !info)
        return SPH_ERR_ARGUMENT;
    if (check_body(sim, id))
        return SPH_ERR_ARGUMENT;
    const body *b = &sim->bodies[id];
    info->name = b->name;
    info->material = b->material;
    info->motion = b->motion;
    info->first = b->first;
    info->count = b->count;
    info->spacing = b->spacing;
    return SPH_OK;
}

sph_status sph_body_find(sph_sim *sim, const char *name, int *id)
{
    if (!sim || !id)
        return SPH_ERR_ARGUMENT;
    for (int i = 0; i < sim->n_bodies; ++i)
        if (name && strcmp(sim->bodies[i].name, name) == 0) {
            *id = i;
            return SPH_OK;
        }
    return sph_fail(sim, SPH_ERR_ARGUMENT, "no body named '%s'", name ? name : "(null)");
}

/* ----------------------------------------------------- domain and kernel */

sph_status sph_set_domain(sph_sim *sim, const double lo[3], const double hi[3], const int periodic[3])
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!lo || !hi)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "domain: lo and hi must not be NULL");
    for (int i = 0; i < sim->dim; ++i)
        if (!(hi[i] > lo[i]) || !isfinite(lo[i]) || !isfinite(hi[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "domain along %c: [%g, %g] is empty or not finite", "xyz"[i], lo[i], hi[i]);
    for (size_t a = 0; a < sim->n; ++a)
        for (int i = 0; i < sim->dim; ++i) {
            const double xi = sim->x[a * sim->dim + i];
            if (xi < lo[i] || xi > hi[i])
                return sph_fail(sim, SPH_ERR_ARGUMENT,
                                "domain along %c: [%g, %g] leaves out particle %zu of body '%s' at %g",
                                "xyz"[i], lo[i], hi[i], a, sim->bodies[sim->body_of[a]].name, xi);
        }
    sim->has_domain = 1;
    for (int i = 0; i < 3; ++i) {
        sim->lo[i] = i < sim->dim ? lo[i] : 0.0;
        sim->hi[i] = i < sim->dim ? hi[i] : 0.0;
        sim->periodic[i] = i < sim->dim && periodic ? periodic[i] != 0 : 0;
    }
    sim->nl.valid = 0;
    return sph_ok(sim);
}

sph_status sph_set_kernel(sph_sim *sim, sph_kernel kernel)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (kernel != SPH_KERNEL_CUBIC_SPLINE && kernel != SPH_KERNEL_WENDLAND_C2)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "kernel=%d: not a sph_kernel", (int)kernel);
    sim->kernel = kernel;
    sim->rates_valid = 0;
    return sph_ok(sim);
}

sph_status sph_set_smoothing_ratio(sph_sim *sim, double ratio)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(ratio >= 0.5 && ratio <= 4.0))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "smoothing ratio h/dx=%g: must be in [0.5, 4]", ratio);
    sim->h_over_dx = ratio;
    if (sim->dx_ref > 0.0)
        sim->h = ratio * sim->dx_ref;
    sim->nl.valid = 0;
    sim->rates_valid = 0;
    if (!sim->dt_set)
        sim->dt = 0.0;
    return sph_ok(sim);
}

double sph_smoothing_length(const sph_sim *sim) { return sim ? sim->h : 0.0; }

sph_status sph_set_spacing(sph_sim *sim, double dx)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(dx > 0.0) || !isfinite(dx))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "spacing dx=%g: must be finite and > 0", dx);
    sim->dx_ref = dx;
    sim->h = sim->h_over_dx * dx;
    sim->nl.valid = 0;
    sim->rates_valid = 0;
    if (!sim->dt_set)
        sim->dt = 0.0;
    return sph_ok(sim);
}

sph_status sph_derived_fields(sph_sim *sim, size_t n, const double *rho,
                              const double *S, const int *material_of,
                              double *pressure, double *stress, double *von_mises)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (n > 0 && (!rho || !S || !material_of))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_derived_fields: rho, S and material must not be NULL");
    const int dim = sim->dim, nc = sim->ncomp;
    for (size_t a = 0; a < n; ++a) {
        if (material_of[a] < 0 || material_of[a] >= sim->n_materials)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_derived_fields: particle %zu has material %d, but %d materials are defined",
                            a, material_of[a], sim->n_materials);
        const material *m = &sim->materials[material_of[a]];
        const double P = eos_pressure(m->c0_squared, rho[a], m->rho0);
        if (pressure)
            pressure[a] = P;
        if (stress)
            for (int c = 0; c < nc; ++c)
                stress[a * nc + c] = S[a * nc + c] - (c < 3 ? P : 0.0);
        if (von_mises)
            von_mises[a] = von_mises_stress(dim, S + a * nc);
    }
    return SPH_OK;
}

/* --------------------------------------------------------------- effects */

sph_status sph_effect(sph_sim *sim, const char *name, const char *parameters)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    sph_status st = effects_set(sim, name, parameters);
    if (st)
        return st;
    sim->rates_valid = 0;
    return sph_ok(sim);
}

sph_status sph_effect_off(sph_sim *sim, const char *name)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    sph_status st = effects_off(sim, name);
    if (st)
        return st;
    sim->rates_valid = 0;
    return sph_ok(sim);
}

int sph_effect_is_on(const sph_sim *sim, const char *name)
{
    return sim ? effects_is_on(&sim->fx, name) : -1;
}

/* ------------------------------------------------------------ time steps */

/* Largest P-wave speed plus particle speed; with no particles (a handle for
 * external particles) the largest P-wave speed of the materials. */
static double signal_speed(const sph_sim *sim)
{
    double speed = 0.0;
    if (sim->n == 0) {
        for (int m = 0; m < sim->n_materials; ++m)
            speed = fmax(speed, sim->materials[m].c_p);
        return speed;
    }
    for (size_t a = 0; a < sim->n; ++a) {
        double v2 = 0.0;
        for (int i = 0; i < sim->dim; ++i)
            v2 += sim->v[a * sim->dim + i] * sim->v[a * sim->dim + i];
        speed = fmax(speed, sim->materials[sim->material_of[a]].c_p + sqrt(v2));
    }
    return speed;
}

double sph_stable_dt(const sph_sim *sim)
{
    if (!sim || sim->h <= 0.0)
        return 0.0;
    const double speed = signal_speed(sim);
    return speed > 0.0 ? sim->h / speed : 0.0;
}

double sph_default_dt(const sph_sim *sim)
{
    if (!sim || sim->h <= 0.0)
        return 0.0;
    /* the bodies' materials, or every material of a handle without bodies */
    double c0 = 0.0;
    for (int b = 0; b < sim->n_bodies; ++b)
        c0 = fmax(c0, sim->materials[sim->bodies[b].material].c0);
    if (sim->n_bodies == 0)
        for (int m = 0; m < sim->n_materials; ++m)
            c0 = fmax(c0, sim->materials[m].c0);
    if (c0 <= 0.0)
        return 0.0;
    const double dt = 0.5 * sim->h / c0;
    const double stable = sph_stable_dt(sim);
    return dt < stable ? dt : stable;
}

sph_status sph_set_dt(sph_sim *sim, double dt, int allow_unstable)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(dt > 0.0) || !isfinite(dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "dt=%g: must be finite and > 0", dt);
    const double stable = sph_stable_dt(sim);
    if (stable <= 0.0)
        return sph_fail(sim, SPH_ERR_STATE, "dt=%g: add bodies before setting the time step", dt);
    if (dt > stable && !allow_unstable)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "dt=%g s exceeds the stability limit h/(c_p + |v|max) = %g s; pass allow_unstable to force it",
                        dt, stable);
    sim->dt = dt;
    sim->dt_set = 1;
    return sph_ok(sim);
}

double sph_dt(const sph_sim *sim)
{
    if (!sim)
        return 0.0;
    return sim->dt_set ? sim->dt : sph_default_dt(sim);
}
double sph_time(const sph_sim *sim) { return sim ? sim->t : 0.0; }
long sph_step_count(const sph_sim *sim) { return sim ? sim->step : 0; }

sph_status sph_set_time(sph_sim *sim, double t, long step)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!isfinite(t) || t < 0.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "time t=%g s: must be finite and >= 0", t);
    if (step < 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "step=%ld: must be >= 0", step);
    sim->t = t;
    sim->step = step;
    sim->rates_valid = 0;
    return sph_ok(sim);
}

/* ---------------------------------------------------------------- fields */

sph_status sph_field(sph_sim *sim, sph_field_id field, double **data, size_t *rows, size_t *cols)
{
    if (!sim || !data)
        return SPH_ERR_ARGUMENT;
    size_t c = 1;
    double *p = NULL;
    switch (field) {
    case SPH_FIELD_POSITION: p = sim->x; c = sim->dim; break;
    case SPH_FIELD_VELOCITY: p = sim->v; c = sim->dim; break;
    case SPH_FIELD_DENSITY: p = sim->rho; break;
    case SPH_FIELD_DEVIATORIC_STRESS: p = sim->S; c = sim->ncomp; break;
    case SPH_FIELD_MASS: p = sim->mass; break;
    default:
        return sph_fail(sim, SPH_ERR_ARGUMENT, "field=%d is derived or unknown; use sph_field_copy", (int)field);
    }
    *data = p;
    if (rows) *rows = sim->n;
    if (cols) *cols = c;
    sim->rates_valid = 0; /* the caller may write through the pointer */
    sim->nl.valid = sim->nl.valid && field != SPH_FIELD_POSITION;
    return sph_ok(sim);
}

sph_status sph_field_copy(sph_sim *sim, sph_field_id field, double *out)
{
    if (!sim || !out)
        return SPH_ERR_ARGUMENT;
    const int dim = sim->dim, nc = sim->ncomp;
    const size_t n = sim->n;
    switch (field) {
    case SPH_FIELD_POSITION: memcpy(out, sim->x, n * dim * sizeof(double)); break;
    case SPH_FIELD_VELOCITY: memcpy(out, sim->v, n * dim * sizeof(double)); break;
    case SPH_FIELD_DENSITY: memcpy(out, sim->rho, n * sizeof(double)); break;
    case SPH_FIELD_DEVIATORIC_STRESS: memcpy(out, sim->S, n * nc * sizeof(double)); break;
    case SPH_FIELD_MASS: memcpy(out, sim->mass, n * sizeof(double)); break;
    case SPH_FIELD_PRESSURE:
        for (size_t a = 0; a < n; ++a) {
            const material *m = &sim->materials[sim->material_of[a]];
            out[a] = eos_pressure(m->c0_squared, sim->rho[a], m->rho0);
        }
        break;
    case SPH_FIELD_VON_MISES:
        for (size_t a = 0; a < n; ++a)
            out[a] = von_mises_stress(dim, sim->S + a * nc);
        break;
    case SPH_FIELD_STRESS:
        for (size_t a = 0; a < n; ++a) {
            const material *m = &sim->materials[sim->material_of[a]];
            const double P = eos_pressure(m->c0_squared, sim->rho[a], m->rho0);
            for (int c = 0; c < nc; ++c)
                out[a * nc + c] = sim->S[a * nc + c] - (c < 3 ? P : 0.0);
        }
        break;
    case SPH_FIELD_ACCELERATION:
        if (!sim->dv_dt || !sim->rates_valid)
            return sph_fail(sim, SPH_ERR_STATE, "acceleration: no rates evaluated for the current state (run a step first)");
        memcpy(out, sim->dv_dt, n * dim * sizeof(double));
        break;
    default:
        return sph_fail(sim, SPH_ERR_ARGUMENT, "field=%d is not a sph_field_id", (int)field);
    }
    return sph_ok(sim);
}

sph_status sph_body_ids(sph_sim *sim, int *out)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!out && sim->n > 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_body_ids: out must not be NULL");
    if (sim->n == 0)
        return SPH_OK;
    memcpy(out, sim->body_of, sim->n * sizeof(int));
    return SPH_OK;
}

double sph_von_mises(int dimension, const double *S)
{
    return S ? von_mises_stress(dimension == 3 ? 3 : 2, S) : 0.0;
}

sph_status sph_energy(sph_sim *sim, int all_bodies, sph_energy_info *info)
{
    if (!sim || !info)
        return SPH_ERR_ARGUMENT;
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
        info->elastic += sim->mass[a] * elastic_energy_per_mass(dim, m->c0_squared, m->rho0, m->mu,
                                                                sim->rho[a], sim->S + a * sim->ncomp);
    }
    return sph_ok(sim);
}

size_t sph_memory_bytes(const sph_sim *sim)
{
    if (!sim)
        return 0;
    const size_t cap = sim->capacity, n = sim->n;
    const size_t dim = (size_t)sim->dim, nc = (size_t)sim->ncomp, ns = (size_t)sim->nsym;
    size_t bytes = sizeof *sim;
    bytes += cap * (2 * dim + 1 + nc + 1) * sizeof(double) + cap * 2 * sizeof(int);
    if (sim->saved)
        bytes += n * (dim + 1 + nc + (sim->fx.xsph ? dim : 0)) * sizeof(double);
    if (sim->x_saved)
        bytes += n * dim * sizeof(double);
    if (sim->dv_dt)
        bytes += n * (dim + 1 + nc) * sizeof(double);
    if (sim->dx_dt)
        bytes += n * dim * sizeof(double);
    bytes += sim->scratch_n * (ns + 1) * sizeof(double);
    if (sim->stress_R)
        bytes += sim->scratch_n * ns * sizeof(double);
    if (sim->nl.offsets)
        bytes += (sim->nl.n + 1) * sizeof(size_t) + sim->nl.capacity * sizeof(int);
    bytes += (size_t)sim->n_materials * sizeof(material) + (size_t)sim->n_bodies * sizeof(body) +
             (size_t)sim->n_probes * sizeof(probe);
    return bytes;
}
