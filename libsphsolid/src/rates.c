/*
 * The rate engine: one evaluation of drho/dt, dv/dt and dS/dt for a set of
 * particles.  All three rates depend only on the current state, so one pass
 * over the pairs computes them together.
 *
 * Passes, each over particles (OpenMP only here):
 *   1. per particle: volume m/rho, sigma/rho^2 and, if on, the artificial
 *      stress R (over local and ghost particles);
 *   2. the pair loop: continuity, velocity gradient (with kernel_correction
 *      also the correction matrix M over the same pairs, then L M^-1),
 *      momentum, and the pair terms of the effects that are on, then the
 *      Jaumann stress rate;
 *   3. if xsph is on: the XSPH velocity;
 *   4. if gravity or damping is on: body forces.
 * The pair loop is compiled in one variant per (dimension, kernel, kernel
 * correction, viscosity, artificial stress: off, exponent 4, any
 * exponent), so an effect that is off has no branch in it.  Each particle gathers from its full neighbour list in
 * a fixed order, so results do not depend on the number of threads.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "kernel.h"
#include "sim.h"

typedef struct engine {
    int dim, ncomp, nsym, stride, threads;
    size_t n_local, n_total;
    const double *x, *v, *rho, *S, *mass;
    size_t xs;                  /* doubles between particles in x and v */
    const int *material_of;
    const material *materials;
    const size_t *offsets;
    const int *indices;
    const int *const *lists;
    const int *counts;
    const double *pair_data;    /* stride doubles: volume, sigma/rho^2 */
    const double *R;            /* nsym per particle, or NULL */
    double h, inv_h, support2, w_norm, f_norm;
    double box[3], half_box[3];
    int periodic_axis[3];
    int periodic;               /* some axis is periodic */
    effects fx;
    double inv_W_dx;
    double *dv_dt, *drho_dt, *dS_dt, *dx_dt;
} engine;

int sim_threads(const sph_sim *sim)
{
#ifdef _OPENMP
    return sim->threads > 0 ? sim->threads : omp_get_max_threads();
#else
    (void)sim;
    return 1;
#endif
}

/* This thread's contiguous block of [0, n). */
static void thread_block(long n, long *begin, long *end)
{
#ifdef _OPENMP
    const long t = omp_get_thread_num(), nt = omp_get_num_threads();
#else
    const long t = 0, nt = 1;
#endif
    const long base = n / nt, extra = n % nt;
    *begin = t * base + (t < extra ? t : extra);
    *end = *begin + base + (t < extra ? 1 : 0);
}

static inline void neighbours_of(const engine *e, size_t a, const int **list,
                                 int *count)
{
    if (e->offsets) {
        *list = e->indices + e->offsets[a];
        *count = (int)(e->offsets[a + 1] - e->offsets[a]);
    } else {
        *list = e->lists[a];
        *count = e->counts[a];
    }
}

/* r_ab = x_a - x_b, with the minimum image along periodic axes. */
static inline double separation(const engine *e, const double *xa, size_t b,
                                const int dim, const int periodic, double *r_ab)
{
    const double *xb = e->x + b * e->xs;
    double r2 = 0.0;
    for (int i = 0; i < dim; ++i) {
        double d = xa[i] - xb[i];
        if (periodic && e->periodic_axis[i]) {
            if (d > e->half_box[i])
                d -= e->box[i];
            else if (d < -e->half_box[i])
                d += e->box[i];
        }
        r_ab[i] = d;
        r2 += d * d;
    }
    return r2;
}

#if defined(__GNUC__)
#define ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE inline
#endif

/* Pass 3 for one particle.  Neighbours are taken in blocks: their data are
 * gathered into short arrays, every pair term is computed in a loop without
 * branches (which the compiler vectorises), and the terms are then summed in
 * neighbour order.  Pairs beyond the support have zero kernel gradient and
 * contribute exact zeros. */
#define PAIR_BLOCK 32

static ALWAYS_INLINE void particle_rates(const engine *e, size_t a,
                                         const int dim, const int kernel,
                                         const int correct,
                                         const int viscosity,
                                         const int art_stress)
{
    const int periodic = e->periodic;   /* scalar gather only: a runtime flag */
    const int nsym = dim == 2 ? 3 : 6;
    const int stride = nsym + 1;
    const double *xa = e->x + a * e->xs;
    const double *va = e->v + a * e->xs;
    const double *Pa = e->pair_data + a * (size_t)stride;
    const double rho_a = e->rho[a];
    const double c_a = viscosity ? e->materials[e->material_of[a]].c0 : 0.0;
    const double *Ra = art_stress ? e->R + a * (size_t)nsym : NULL;

    double L[3][3] = {{0.0}};
    double M[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    double dv[3] = {0.0, 0.0, 0.0};
    double drho = 0.0;

    const int *list;
    int count;
    neighbours_of(e, a, &list, &count);
    for (int k0 = 0; k0 < count; k0 += PAIR_BLOCK) {
        const int nk = count - k0 < PAIR_BLOCK ? count - k0 : PAIR_BLOCK;
        /* gathered per-pair inputs */
        double r[3][PAIR_BLOCK], vr[3][PAIR_BLOCK], m[PAIR_BLOCK], vol[PAIR_BLOCK];
        double T[6][PAIR_BLOCK], rho_mean[PAIR_BLOCK], c_mean[PAIR_BLOCK];
        /* per-pair terms */
        double t_rho[PAIR_BLOCK], t_L[3][3][PAIR_BLOCK], t_dv[3][PAIR_BLOCK];
        double t_M[6][PAIR_BLOCK];
        for (int k = 0; k < nk; ++k) {
            const size_t b = (size_t)list[k0 + k];
            double r_ab[3];
            separation(e, xa, b, dim, periodic, r_ab);
            const double *vb = e->v + b * e->xs;
            const double *Pb = e->pair_data + b * (size_t)stride;
            for (int i = 0; i < dim; ++i) {
                r[i][k] = r_ab[i];
                vr[i][k] = va[i] - vb[i];
            }
            m[k] = e->mass[b];
            vol[k] = Pb[0];
            for (int c = 0; c < nsym; ++c)
                T[c][k] = Pa[1 + c] + Pb[1 + c];
            if (viscosity) {
                rho_mean[k] = 0.5 * (rho_a + e->rho[b]);
                c_mean[k] = 0.5 * (c_a + e->materials[e->material_of[b]].c0);
            }
        }
        for (int k = 0; k < nk; ++k) {
            double r_ab[3], v_ab[3], grad_W[3], Tk[6], dvk[3] = {0.0, 0.0, 0.0};
            double Lk[3][3] = {{0.0}};
            double r2 = 0.0;
            for (int i = 0; i < dim; ++i) {
                r_ab[i] = r[i][k];
                v_ab[i] = vr[i][k];
                r2 += r_ab[i] * r_ab[i];
            }
            const double q = sqrt(r2) * e->inv_h;
            const double F = kernel_f(kernel, q) * e->f_norm;
            for (int i = 0; i < dim; ++i)
                grad_W[i] = F * r_ab[i];
            t_rho[k] = continuity_pair(dim, m[k], v_ab, grad_W);
            velocity_gradient_pair(dim, vol[k], v_ab, grad_W, Lk);
            for (int i = 0; i < dim; ++i)
                for (int j = 0; j < dim; ++j)
                    t_L[i][j][k] = Lk[i][j];
            if (correct) {
                double Mk[6];
                correction_matrix_pair(dim, vol[k], r_ab, grad_W, Mk);
                for (int c = 0; c < nsym; ++c)
                    t_M[c][k] = Mk[c];
            }
            for (int c = 0; c < nsym; ++c)
                Tk[c] = T[c][k];
            if (viscosity) {
                double v_dot_r = 0.0;
                for (int i = 0; i < dim; ++i)
                    v_dot_r += v_ab[i] * r_ab[i];
                const double Pi = viscosity_pair(e->fx.alpha, e->fx.beta, e->h, v_dot_r, r2,
                                                 c_mean[k], rho_mean[k]);
                for (int i = 0; i < dim; ++i)
                    Tk[i] -= Pi;
            }
            if (art_stress) {
                const double W = kernel_w(kernel, q) * e->w_norm;
                /* art_stress 1: n = 4 compiled in; 2: any n, through pow */
                const double fn = art_stress == 1
                                      ? artificial_stress_factor_4(W, e->inv_W_dx)
                                      : artificial_stress_factor(W, e->inv_W_dx, e->fx.stress_exponent);
                const double *Rb = e->R + (size_t)list[k0 + k] * (size_t)nsym;
                for (int c = 0; c < nsym; ++c)
                    Tk[c] += (Ra[c] + Rb[c]) * fn;
            }
            momentum_pair(dim, m[k], Tk, grad_W, dvk);
            for (int i = 0; i < dim; ++i)
                t_dv[i][k] = dvk[i];
        }
        for (int k = 0; k < nk; ++k) {
            drho += t_rho[k];
            for (int i = 0; i < dim; ++i) {
                dv[i] += t_dv[i][k];
                for (int j = 0; j < dim; ++j)
                    L[i][j] += t_L[i][j][k];
            }
            if (correct)
                for (int c = 0; c < nsym; ++c)
                    M[c] += t_M[c][k];
        }
    }

    e->drho_dt[a] = drho;
    /* L stays in registers through the pair loop only if its address never
     * escapes: the out-of-line correction works on a copy. */
    double grad_v[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            grad_v[i][j] = L[i][j];
    if (correct) {
        double Mc[6];
        for (int c = 0; c < 6; ++c)
            Mc[c] = M[c];
        correct_velocity_gradient(dim, Mc, grad_v);
    }
    const int ncomp = dim == 2 ? 4 : 6;
    jaumann_stress_rate(dim, e->materials[e->material_of[a]].mu, grad_v,
                        e->S + a * (size_t)ncomp, e->dS_dt + a * (size_t)ncomp);
    for (int i = 0; i < dim; ++i)
        e->dv_dt[a * (size_t)dim + i] = dv[i];
}

/* One function per variant of the pair loop.  Each thread takes one
 * contiguous block of particles (the same split as schedule(static)); the
 * block loop is compiled for AVX2+FMA as well as the baseline and picked at
 * load time where the CPU has it. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(SPHSOLID_NO_CLONES)
#define RATE_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define RATE_CLONES
#endif
#define RATE_VARIANT(DIM, KERNEL, CORRECT, VISC, STRESS)                     \
    RATE_CLONES static void block_##DIM##_##KERNEL##_##CORRECT##_##VISC##_##STRESS( \
        const engine *e, long begin, long end)                                 \
    {                                                                          \
        for (long a = begin; a < end; ++a)                                     \
            particle_rates(e, (size_t)a, DIM, KERNEL, CORRECT, VISC, STRESS); \
    }                                                                          \
    static void rates_##DIM##_##KERNEL##_##CORRECT##_##VISC##_##STRESS(       \
        const engine *e)                                                       \
    {                                                                          \
        const long n = (long)e->n_local;                                       \
        _Pragma("omp parallel num_threads(e->threads)")                        \
        {                                                                      \
            long begin, end;                                                   \
            thread_block(n, &begin, &end);                                     \
            block_##DIM##_##KERNEL##_##CORRECT##_##VISC##_##STRESS(e, begin, end); \
        }                                                                      \
    }
#define RATE_VARIANTS_STRESS(DIM, KERNEL, CORRECT, VISC)                      \
    RATE_VARIANT(DIM, KERNEL, CORRECT, VISC, 0)                               \
    RATE_VARIANT(DIM, KERNEL, CORRECT, VISC, 1)                               \
    RATE_VARIANT(DIM, KERNEL, CORRECT, VISC, 2)
#define RATE_VARIANTS_VISC(DIM, KERNEL, CORRECT)                              \
    RATE_VARIANTS_STRESS(DIM, KERNEL, CORRECT, 0)                             \
    RATE_VARIANTS_STRESS(DIM, KERNEL, CORRECT, 1)
#define RATE_VARIANTS_CORRECT(DIM, KERNEL)                                    \
    RATE_VARIANTS_VISC(DIM, KERNEL, 0)                                         \
    RATE_VARIANTS_VISC(DIM, KERNEL, 1)
RATE_VARIANTS_CORRECT(2, 0)
RATE_VARIANTS_CORRECT(2, 1)
RATE_VARIANTS_CORRECT(3, 0)
RATE_VARIANTS_CORRECT(3, 1)

typedef void (*rate_variant)(const engine *);
#define V(D, K, P) {{rates_##D##_##K##_##P##_0_0, rates_##D##_##K##_##P##_0_1,   \
                     rates_##D##_##K##_##P##_0_2},                               \
                    {rates_##D##_##K##_##P##_1_0, rates_##D##_##K##_##P##_1_1,   \
                     rates_##D##_##K##_##P##_1_2}}
static const rate_variant variants[2][2][2][2][3] = {
    {{V(2, 0, 0), V(2, 0, 1)}, {V(2, 1, 0), V(2, 1, 1)}},
    {{V(3, 0, 0), V(3, 0, 1)}, {V(3, 1, 0), V(3, 1, 1)}},
};
#undef V

/* Pass 1: per-particle factors of the pair terms. */
static void pass_pair_data(const engine *e, double *pair_data, double *R)
{
    const int dim = e->dim, nsym = e->nsym, ncomp = e->ncomp;
    const long n = (long)e->n_total;
#pragma omp parallel for schedule(static) num_threads(e->threads)
    for (long a = 0; a < n; ++a) {
        const material *m = &e->materials[e->material_of[a]];
        const double rho = e->rho[a];
        const double P = eos_pressure(m->c0_squared, rho, m->rho0);
        const double *S = e->S + (size_t)a * ncomp;
        double *pd = pair_data + (size_t)a * (nsym + 1);
        pd[0] = e->mass[a] / rho;
        stress_over_rho2(dim, S, P, rho, pd + 1);
        if (R)
            artificial_stress_tensor(dim, S, P, rho, e->fx.stress_epsilon,
                                     R + (size_t)a * nsym);
    }
}

/* Pass 3 for one particle, blocked like the pair loop: neighbour data
 * gathered, the XSPH terms computed without branches (pairs beyond the
 * support have a zero kernel and add exact zeros), then summed in neighbour
 * order. */
static ALWAYS_INLINE void particle_xsph(const engine *e, size_t a, const int dim,
                                        const int kernel)
{
    const double *xa = e->x + a * e->xs;
    const double *va = e->v + a * e->xs;
    const double rho_a = e->rho[a];
    double u[3] = {0.0, 0.0, 0.0};
    const int *list;
    int count;
    neighbours_of(e, a, &list, &count);
    for (int k0 = 0; k0 < count; k0 += PAIR_BLOCK) {
        const int nk = count - k0 < PAIR_BLOCK ? count - k0 : PAIR_BLOCK;
        double r[3][PAIR_BLOCK], vr[3][PAIR_BLOCK], m[PAIR_BLOCK], rho_mean[PAIR_BLOCK];
        double t[3][PAIR_BLOCK];
        for (int k = 0; k < nk; ++k) {
            const size_t b = (size_t)list[k0 + k];
            double r_ab[3];
            separation(e, xa, b, dim, e->periodic, r_ab);
            for (int i = 0; i < dim; ++i) {
                r[i][k] = r_ab[i];
                vr[i][k] = va[i] - e->v[b * e->xs + i];
            }
            m[k] = e->mass[b];
            rho_mean[k] = 0.5 * (rho_a + e->rho[b]);
        }
        for (int k = 0; k < nk; ++k) {
            double v_ab[3], term[3] = {0.0, 0.0, 0.0};
            double r2 = 0.0;
            for (int i = 0; i < dim; ++i) {
                r2 += r[i][k] * r[i][k];
                v_ab[i] = vr[i][k];
            }
            const double W = kernel_w(kernel, sqrt(r2) * e->inv_h) * e->w_norm;
            xsph_pair(dim, e->fx.xsph_epsilon, m[k], rho_mean[k], v_ab, W, term);
            for (int i = 0; i < dim; ++i)
                t[i][k] = term[i];
        }
        for (int k = 0; k < nk; ++k)
            for (int i = 0; i < dim; ++i)
                u[i] += t[i][k];
    }
    for (int i = 0; i < dim; ++i)
        e->dx_dt[a * (size_t)dim + i] = va[i] + u[i];
}

#define XSPH_VARIANT(DIM, KERNEL)                                              \
    RATE_CLONES static void xsph_##DIM##_##KERNEL(const engine *e, long begin, long end) \
    {                                                                          \
        for (long a = begin; a < end; ++a)                                     \
            particle_xsph(e, (size_t)a, DIM, KERNEL);                          \
    }
XSPH_VARIANT(2, 0)
XSPH_VARIANT(2, 1)
XSPH_VARIANT(3, 0)
XSPH_VARIANT(3, 1)

/* Pass 3: XSPH velocities. */
static void pass_xsph(const engine *e, int kernel)
{
    typedef void (*xsph_variant)(const engine *, long, long);
    static const xsph_variant table[2][2] = {{xsph_2_0, xsph_2_1}, {xsph_3_0, xsph_3_1}};
    const xsph_variant f = table[e->dim - 2][kernel];
    const long n = (long)e->n_local;
#pragma omp parallel num_threads(e->threads)
    {
        long begin, end;
        thread_block(n, &begin, &end);
        f(e, begin, end);
    }
}

/* Pass 4: gravity and damping. */
static void pass_body_forces(const engine *e)
{
    const int dim = e->dim;
    const long n = (long)e->n_local;
    const int gravity = e->fx.gravity, damping = e->fx.damping;
#pragma omp parallel for schedule(static) num_threads(e->threads)
    for (long a = 0; a < n; ++a)
        for (int i = 0; i < dim; ++i) {
            double acc = e->dv_dt[(size_t)a * dim + i];
            if (gravity)
                acc += e->fx.g[i];
            if (damping)
                acc -= e->fx.damping_rate * e->v[(size_t)a * e->xs + i];
            e->dv_dt[(size_t)a * dim + i] = acc;
        }
}

static sph_status grow_scratch(sph_sim *sim, size_t n)
{
    if (n <= sim->scratch_n && (!sim->fx.artificial_stress || sim->stress_R))
        return SPH_OK;
    const size_t cap = n > sim->scratch_n ? n : sim->scratch_n;
    double *pd = realloc(sim->pair_data, cap * (size_t)(sim->nsym + 1) * sizeof(double));
    if (!pd)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate rate scratch for %zu particles", cap);
    sim->pair_data = pd;
    if (sim->fx.artificial_stress) {
        double *R = realloc(sim->stress_R, cap * (size_t)sim->nsym * sizeof(double));
        if (!R)
            return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate artificial stress for %zu particles", cap);
        sim->stress_R = R;
    }
    sim->scratch_n = cap;
    return SPH_OK;
}

sph_status rates_run(sph_sim *sim, const rate_call *call)
{
    if (sim->h <= 0.0)
        return sph_fail(sim, SPH_ERR_STATE,
                        "smoothing length is not set: add a body or call sph_set_smoothing_ratio after one");
    sph_status st = grow_scratch(sim, call->n_total);
    if (st)
        return st;

    engine e;
    memset(&e, 0, sizeof e);
    e.dim = sim->dim;
    e.ncomp = sim->ncomp;
    e.nsym = sim->nsym;
    e.stride = sim->nsym + 1;
    e.threads = sim_threads(sim);
    e.n_local = call->n_local;
    e.n_total = call->n_total;
    e.x = call->x;
    e.xs = call->stride;
    e.v = call->v;
    e.rho = call->rho;
    e.S = call->S;
    e.mass = call->mass;
    e.material_of = call->material;
    e.materials = sim->materials;
    e.offsets = call->neighbours->offsets;
    e.indices = call->neighbours->indices;
    e.lists = call->neighbours->lists;
    e.counts = call->neighbours->counts;
    e.h = sim->h;
    e.inv_h = 1.0 / sim->h;
    e.support2 = 4.0 * sim->h * sim->h;
    const double sigma = kernel_sigma(sim->kernel, sim->dim);
    e.w_norm = sigma / pow(sim->h, sim->dim);
    e.f_norm = sigma / pow(sim->h, sim->dim + 2);
    e.fx = sim->fx;
    e.inv_W_dx = 1.0 / (kernel_w(sim->kernel, sim->dx_ref / sim->h) * e.w_norm);
    for (int i = 0; i < sim->dim; ++i) {
        e.periodic_axis[i] = call->periodic && sim->periodic[i];
        e.box[i] = sim->hi[i] - sim->lo[i];
        e.half_box[i] = 0.5 * e.box[i];
        e.periodic |= e.periodic_axis[i];
    }
    e.dv_dt = call->dv_dt;
    e.drho_dt = call->drho_dt;
    e.dS_dt = call->dS_dt;
    e.dx_dt = call->dx_dt;

    pass_pair_data(&e, sim->pair_data, sim->fx.artificial_stress ? sim->stress_R : NULL);
    e.pair_data = sim->pair_data;
    e.R = sim->fx.artificial_stress ? sim->stress_R : NULL;
    const int stress = !sim->fx.artificial_stress ? 0 : sim->fx.stress_exponent == 4.0 ? 1 : 2;
    variants[sim->dim - 2][sim->kernel][sim->fx.kernel_correction != 0][sim->fx.viscosity != 0]
            [stress](&e);
    if (sim->fx.xsph && e.dx_dt)
        pass_xsph(&e, sim->kernel);
    if (sim->fx.gravity || sim->fx.damping)
        pass_body_forces(&e);
    return SPH_OK;
}

sph_status sph_rates_evaluate(sph_sim *sim, const sph_particles *p,
                              const sph_neighbours *nb, sph_rates *rates)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!p || !nb || !rates)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rates_evaluate: particles, neighbours and rates must not be NULL");
    if (p->n_local > p->n_total)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rates_evaluate: n_local=%zu exceeds n_total=%zu",
                        p->n_local, p->n_total);
    const size_t stride = p->stride ? p->stride : (size_t)sim->dim;
    if (stride < (size_t)sim->dim)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rates_evaluate: stride=%zu is smaller than the dimension %d", stride, sim->dim);
    if (p->n_total > 0 && (!p->x || !p->v || !p->rho || !p->S || !p->mass || !p->material))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rates_evaluate: a particle array (x, v, rho, S, mass, material) is NULL");
    if (p->n_local > 0 && (!rates->dv_dt || !rates->drho_dt || !rates->dS_dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rates_evaluate: a rate array (dv_dt, drho_dt, dS_dt) is NULL");
    if (!((nb->offsets && nb->indices) || (nb->lists && nb->counts)) && p->n_local > 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rates_evaluate: give neighbours as offsets+indices or lists+counts");
    if (sim->fx.xsph && !rates->dx_dt && p->n_local > 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rates_evaluate: effect xsph is on but rates->dx_dt is NULL");
    for (size_t i = 0; i < p->n_total; ++i) {
        if (p->material[i] < 0 || p->material[i] >= sim->n_materials)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rates_evaluate: particle %zu has material %d, but %d materials are defined",
                            i, p->material[i], sim->n_materials);
        if (!(p->rho[i] > 0.0))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_rates_evaluate: particle %zu has density rho=%g (must be > 0)", i, p->rho[i]);
    }
    const rate_call call = {.n_local = p->n_local, .n_total = p->n_total,
                            .x = p->x, .v = p->v, .rho = p->rho, .S = p->S, .mass = p->mass,
                            .stride = stride, .material = p->material, .neighbours = nb,
                            .periodic = 0, .dv_dt = rates->dv_dt, .drho_dt = rates->drho_dt,
                            .dS_dt = rates->dS_dt, .dx_dt = rates->dx_dt};
    sph_status st = rates_run(sim, &call);
    return st ? st : sph_ok(sim);
}
