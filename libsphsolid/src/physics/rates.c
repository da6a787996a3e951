/*
 * The rate engine: one evaluation of drho/dt, dv/dt and dS/dt (and the
 * XSPH velocity) for a set of particles.  All rates depend only on the
 * current state, so one pass over the pairs computes them together; or,
 * for an integrator that needs them at different states (the leapfrog),
 * one of two passes: the continuity pass (drho/dt, the velocity gradient
 * and kernel-correction matrix, dS/dt, XSPH) or the momentum pass (dv/dt:
 * stress, artificial viscosity and stress, gravity, damping).  A pass is a
 * compile-time parameter of the pair loop: each computes and sums only its
 * own terms (both compute the distance and kernel gradient), and the two
 * at one state give bitwise the rates of the whole evaluation.
 *
 * Passes (OpenMP only here):
 *   1. per particle: sigma/rho^2 and, if on, the artificial stress R (over
 *      local and ghost particles; the volumes m/rho are computed per pair);
 *   2. the pair pass over a half list (each pair once): for every pair the
 *      symmetric terms (continuity, velocity gradient, momentum with
 *      viscosity and artificial stress, the kernel-correction matrix M,
 *      XSPH) are computed once and added to both particles (Newton's third
 *      law), into per-particle sums;
 *   3. the finish per particle: L M^-1, the Jaumann stress rate, gravity,
 *      damping and the XSPH velocity v + u.
 *
 * Deterministic threading.  The rows of the list are cut into chunks whose
 * size depends only on the number of particles, never on the threads.  A
 * chunk adds the terms of its pairs directly to the sums of particles in
 * itself and the next chunk; chunks of even index run together, then those
 * of odd index, so no two running chunks write the same particle.  A pair
 * of local particles further apart (at least two chunks) is listed in both
 * rows when the list allows it (the handle's own list, built so by
 * neighbour.c, and any full list): each row computes the pair and adds the
 * terms of its own particle only, so nothing is stored, at the price of
 * computing such pairs twice (the terms are odd or even in r_ab and v_ab,
 * so both rows compute them bitwise alike and Newton's third law holds to
 * the bit).  Otherwise (a caller's half list, a ghost) the terms for the
 * other particle are appended to the chunk's "far" list and added after the
 * pass, in chunk order.  Every sum therefore runs in an order fixed by the
 * list and the chunk bounds alone: results are bitwise the same on any
 * number of threads.  Rows are sorted by index, and the listed pairs beyond
 * the kernel's support (the skin's) are skipped at the gather: all their
 * terms are exact zeros (of either sign), and adding a zero never changes
 * a sum that starts from +0 (round to nearest gives -0 only for -0 + -0),
 * so skipping them gives the same bits and results do not depend on when
 * the list was rebuilt.
 *
 * The pair loop (rate_loop.h) is compiled in one variant per (dimension,
 * kernel, pass, sums layout) and instruction-set path, each path in a file
 * of its own (rates_base.c, rates_avx2.c, rates_avx512.c: the three
 * compile side by side).  The pairs of a chunk are taken
 * row after row in blocks of PAIR_BLOCK (a block runs across rows, so its
 * vectors are full): gathered into structure-of-arrays form, then every
 * pair term (physics.h, effects.h; one function each, the only place its
 * equation is written) runs over the block in a short loop that
 * vectorises; effects are runtime switches tested once per block.  The
 * terms come out as rows (one per component, over the block's pairs) and
 * are turned, four pairs at a time, into one record per pair (4x4
 * transposes of vectors of four doubles), which one scatter (add_record)
 * adds to a particle's sums wherever they are kept: the engine's own sums
 * are packed records of whole vectors of 4 doubles per particle (zero
 * padded), so a's row sum and b's sums take a record in one or a few
 * vector adds, lane by lane, the same additions in the same order as one
 * by one; a caller's partial-sum buffer takes it sum by sum.  The finish
 * reads the records and writes the rates.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "physics/rate_loop.h"

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

/* Rows per chunk: from the particle count and dimension only (never the
 * threads), about 64 chunks, and at least a few lattice rows (2D) or
 * planes (3D) of a block built in index order, so that most pairs of a
 * chunk stay within it and the next one. */
size_t rates_chunk_rows(int dim, size_t n)
{
    const size_t least = dim == 2 ? 256 : 4096;
    size_t c = (n + 63) / 64;
    return c > least ? c : least;
}

/* Append one far record (the terms for particle b, `record` <= f->record
 * doubles); on allocation failure the list is marked and the pass reports
 * it. */
void rates_far_append(far_list *f, int record, size_t b, const double *terms)
{
    if (f->failed)
        return;
    if (f->count == f->capacity) {
        const size_t cap = f->capacity ? 2 * f->capacity : 32;
        int *t = realloc(f->target, cap * sizeof *t);
        if (t)
            f->target = t;
        double *v = t ? realloc(f->terms, cap * (size_t)f->record * sizeof *v) : NULL;
        if (!t || !v) {
            f->failed = 1;
            return;
        }
        f->terms = v;
        f->capacity = cap;
    }
    f->target[f->count] = (int)b;
    memcpy(f->terms + f->count * (size_t)record, terms, (size_t)record * sizeof *terms);
    f->count++;
}

/* [path - 1]: the paths' tables of chunk functions (rate_loop.h). */
static const chunk_fn (*const chunk_variants[])[3][2][2] = {
    rates_chunks_base,
#if RATE_WIDE_PATHS
    rates_chunks_avx2,
    rates_chunks_avx512,
#endif
};
int rates_path(int wanted)
{
#if RATE_WIDE_PATHS
    __builtin_cpu_init();
    int widest = RATE_PATH_BASELINE;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
        widest = RATE_PATH_AVX2;
    if (widest == RATE_PATH_AVX2 && __builtin_cpu_supports("avx512f") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512dq"))
        widest = RATE_PATH_AVX512;
    return wanted == RATE_PATH_AUTO || wanted > widest ? widest : wanted;
#else
    (void)wanted;
    return RATE_PATH_BASELINE;
#endif
}

static const char *const path_names[] = {"baseline", "avx2", "avx512"};

sph_status rates_path_from_environment(sph_sim *sim, int *path)
{
    *path = RATE_PATH_AUTO;
    const char *name = getenv("SPHSOLID_RATE_PATH");
    if (!name || !*name)
        return SPH_OK;
    int wanted = 0;
    for (int k = 0; k < 3; ++k)
        if (!strcmp(name, path_names[k]))
            wanted = RATE_PATH_BASELINE + k;
    char shown[SPH_CLIP_SIZE];
    if (!wanted)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "SPHSOLID_RATE_PATH='%s': not a path of the pair loop (baseline, avx2, "
                        "avx512; unset: the widest the CPU has)",
                        sph_clip(shown, name));
    const int taken = rates_path(wanted);
    if (taken != wanted)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "SPHSOLID_RATE_PATH='%s': this build on this CPU has no wider path than "
                        "'%s'",
                        sph_clip(shown, name), path_names[taken - RATE_PATH_BASELINE]);
    *path = wanted;
    return SPH_OK;
}

/* Pass 2: the pair sums.  Even chunks, then odd chunks, then the far
 * records in chunk order (each thread adds those of its own particles). */
static void pass_pairs(const engine *e, int kernel, size_t n_sums)
{
    const chunk_fn run = chunk_variants[e->path - 1][kernel][e->pass - 1][e->split][e->dim - 2];
    const long n_chunks = e->n_chunks;
#pragma omp parallel num_threads(e->threads)
    {
        for (int phase = 0; phase < 2; ++phase) {
#pragma omp for schedule(dynamic, 1)
            for (long c = phase; c < n_chunks; c += 2)
                run(e, c);
        }
        long begin, end;
        thread_block((long)n_sums, &begin, &end);
        const size_t record = 4 * (size_t)e->acc.nv;
        for (long c = 0; c < n_chunks; ++c) {
            const far_list *f = &e->far[c];
            for (size_t k = 0; k < f->count; ++k) {
                const long b = f->target[k];
                if (b < begin || b >= end)
                    continue;
                add_record(&e->acc, (size_t)b, f->terms + k * record, !e->split);
            }
        }
    }
}

/* Pass 3 for one particle: the rates from its sums (the dimension a
 * constant of each caller below). */
static ALWAYS_INLINE void finish_particle(const engine *e, size_t a, const int dim)
{
    const sums *s = &e->acc;
    if (e->pass & PASS_MOMENTUM) {
        double *dv = e->dv_dt + a * (size_t)dim;
        const double *sv = s->p[SUM_DV] + a * s->stride[SUM_DV];
        for (int i = 0; i < dim; ++i) {
            double acc = sv[i];
            if (e->fx.gravity)
                acc += e->fx.g[i];
            if (e->fx.damping)
                acc -= e->fx.damping_rate * e->v[a * e->xs + (size_t)i];
            dv[i] = acc;
        }
    }
    if (!(e->pass & PASS_CONTINUITY))
        return;
    e->drho_dt[a] = s->p[SUM_RHO][a * s->stride[SUM_RHO]];
    double grad_v[3][3] = {{0.0}};
    for (int c = 0; c < dim * dim; ++c)
        grad_v[c / dim][c % dim] = s->p[SUM_L][a * s->stride[SUM_L] + (size_t)c];
    if (s->width[SUM_M]) {
        double Mc[6];
        for (int c = 0; c < e->nsym; ++c)
            Mc[c] = s->p[SUM_M][a * s->stride[SUM_M] + (size_t)c];
        correct_velocity_gradient(dim, Mc, grad_v);
    }
    jaumann_stress_rate(dim, e->materials[e->material_of[a]].mu, grad_v,
                        e->S + a * (size_t)e->ncomp, e->dS_dt + a * (size_t)e->ncomp);
    if (s->width[SUM_U] && e->dx_dt) {
        const double *su = s->p[SUM_U] + a * s->stride[SUM_U];
        const double *va = e->v + a * e->xs;
        double u[3];
        for (int i = 0; i < dim; ++i)
            u[i] = su[i];
        for (int i = 0; i < dim; ++i)
            e->dx_dt[a * (size_t)dim + (size_t)i] = va[i] + u[i];
    }
}

static void pass_finish(const engine *e)
{
    const long n = (long)e->n_local;
#pragma omp parallel for schedule(static) num_threads(e->threads)
    for (long a = 0; a < n; ++a) {
        if (e->dim == 2)
            finish_particle(e, (size_t)a, 2);
        else
            finish_particle(e, (size_t)a, 3);
    }
}

/* The layout of the sums of a pass: widths and offsets in a record. */
static void sums_layout(const sph_sim *sim, int xsph, int pass, sums *s)
{
    const int dim = sim->dim;
    const int cont = (pass & PASS_CONTINUITY) != 0, mom = (pass & PASS_MOMENTUM) != 0;
    memset(s, 0, sizeof *s);
    s->width[SUM_RHO] = cont;
    s->width[SUM_DV] = mom ? dim : 0;
    s->width[SUM_L] = cont ? dim * dim : 0;
    s->width[SUM_M] = cont && sim->fx.kernel_correction ? sim->nsym : 0;
    s->width[SUM_U] = cont && xsph ? dim : 0;
    int o = 0;
    for (int q = 0; q < N_SUMS; ++q) {
        s->offset[q] = o;
        o += s->width[q];
    }
    s->record = o;
    s->nv = vectors_of(o);
}

/* Sums as rows of one buffer: a caller's (`record` doubles per particle)
 * or the engine's packed records (4 nv doubles). */
static void sums_in_buffer(sums *s, double *buffer, int packed)
{
    const size_t stride = (size_t)(packed ? 4 * s->nv : s->record);
    for (int q = 0; q < N_SUMS; ++q) {
        s->p[q] = s->width[q] ? buffer + s->offset[q] : buffer;
        s->stride[q] = stride;
    }
    s->packed = packed ? buffer : NULL;
}
/* Pass 1: per-particle factors of the momentum terms (the continuity pass
 * needs none: the volumes m/rho are computed per pair). */
static void pass_pair_data(const engine *e, double *pair_data, double *R)
{
    const int dim = e->dim, nsym = e->nsym, ncomp = e->ncomp;
    const long n = (long)e->n_total;
    if (!(e->pass & PASS_MOMENTUM))
        return;
#pragma omp parallel for schedule(static) num_threads(e->threads)
    for (long a = 0; a < n; ++a) {
        const material *m = &e->materials[e->material_of[a]];
        const double rho = e->rho[a];
        double P = eos_pressure(m->c0_squared, rho, m->rho0), Sd[6];
        const double *S = e->S + (size_t)a * ncomp;
        if (e->damage) /* the stress damage leaves (damage.h) */
            S = damaged_stress(ncomp, e->damage[a], S, &P, Sd);
        double *pd = pair_data + (size_t)a * (size_t)e->pstride;
        stress_over_rho2(dim, S, P, rho, pd);
        if (e->pstride > nsym)
            pd[nsym] = m->c0;
        if (R)
            artificial_stress_tensor(dim, S, P, rho, e->fx.artificial_stress_epsilon,
                                     R + (size_t)a * nsym);
    }
}

/* The sound speed of every material if they all have the same (then a
 * pair's mean sound speed is it, bitwise, and the pair data need not hold
 * it), else 0. */
static double uniform_c0(const sph_sim *sim)
{
    for (int k = 1; k < sim->n_materials; ++k)
        if (sim->materials[k].c0 != sim->materials[0].c0)
            return 0.0;
    return sim->n_materials > 0 ? sim->materials[0].c0 : 0.0;
}

/* Doubles per particle of the pair data. */
static int pair_data_width(const sph_sim *sim)
{
    return sim->nsym + (uniform_c0(sim) > 0.0 ? 0 : 1);
}

static sph_status grow_scratch(sph_sim *sim, size_t n)
{
    const size_t per = (size_t)pair_data_width(sim);
    if (n <= sim->scratch_n && per <= sim->pair_data_per &&
        (!sim->fx.artificial_stress || sim->stress_R))
        return SPH_OK;
    const size_t cap = n > sim->scratch_n ? n : sim->scratch_n;
    const size_t width = per > sim->pair_data_per ? per : sim->pair_data_per;
    double *pd = realloc(sim->pair_data, cap * width * sizeof(double));
    if (!pd)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate rate scratch for %zu particles", cap);
    sim->pair_data = pd;
    sim->pair_data_per = width;
    if (sim->fx.artificial_stress) {
        double *R = realloc(sim->stress_R, cap * (size_t)sim->nsym * sizeof(double));
        if (!R)
            return sph_fail(sim, SPH_ERR_MEMORY,
                            "cannot allocate artificial stress for %zu particles", cap);
        sim->stress_R = R;
    }
    sim->scratch_n = cap;
    return SPH_OK;
}

/* Room for `doubles` in the scratch *buf of *have doubles (`what` names
 * it in the error). */
static sph_status grow_doubles(sph_sim *sim, double **buf, size_t *have, size_t doubles,
                               const char *what)
{
    if (doubles <= *have)
        return SPH_OK;
    double *p = realloc(*buf, doubles * sizeof(double));
    if (!p)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %zu doubles of %s", doubles, what);
    *buf = p;
    *have = doubles;
    return SPH_OK;
}

static sph_status grow_sum_scratch(sph_sim *sim, size_t doubles)
{
    return grow_doubles(sim, &sim->sum_scratch, &sim->sum_scratch_n, doubles, "pair sums");
}

/* One far list per chunk, emptied, for records of `record` doubles (a
 * list sized for shorter records, of another pass or other effects, is
 * regrown from empty). */
static sph_status prepare_far(sph_sim *sim, long n_chunks, int record)
{
    if ((size_t)n_chunks > sim->n_far) {
        far_list *f = realloc(sim->far, (size_t)n_chunks * sizeof *f);
        if (!f)
            return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %ld chunk lists", n_chunks);
        memset(f + sim->n_far, 0, ((size_t)n_chunks - sim->n_far) * sizeof *f);
        sim->far = f;
        sim->n_far = (size_t)n_chunks;
    }
    for (size_t c = 0; c < sim->n_far; ++c) {
        far_list *f = &sim->far[c];
        f->count = 0;
        f->failed = 0;
        if (f->record < record) {
            f->capacity = 0; /* the next append reallocates for `record` */
            f->record = record;
        }
    }
    return SPH_OK;
}

size_t rates_far_bytes(const sph_sim *sim)
{
    size_t bytes = sim->n_far * sizeof(far_list);
    for (size_t c = 0; c < sim->n_far; ++c)
        bytes += sim->far[c].capacity * (sizeof(int) + (size_t)sim->far[c].record * sizeof(double));
    return bytes;
}

/* The engine for a call: everything but the sums. */
static sph_status engine_setup(sph_sim *sim, const rate_call *call, engine *e)
{
    if (sim->h <= 0.0)
        return sph_fail(
            sim, SPH_ERR_STATE,
            "smoothing length is not set: add a body or call sph_set_smoothing_ratio after one");
    if (sim->fx.artificial_stress) {
        /* Gray et al.'s factor (W_ab / W(dx))^n is a repulsion that falls
         * off with distance only for a kernel that stays non-negative */
        const double q = sph_kernel_negative_from((sph_kernel)sim->kernel, sim->dim);
        char others[128];
        if (q > 0.0)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "effect artificial_stress needs a kernel that is non-negative over "
                            "its support: %s is negative from q = r/h = %.3g, where the factor "
                            "(W/W(dx))^n has no meaning; use one of: %s",
                            sph_kernel_name((sph_kernel)sim->kernel), q,
                            kernel_names_non_negative(sim->dim, others, sizeof others));
    }
    sph_status st = grow_scratch(sim, call->n_total);
    if (st)
        return st;
    memset(e, 0, sizeof *e);
    e->dim = sim->dim;
    e->ncomp = sim->ncomp;
    e->nsym = sim->nsym;
    e->threads = sim_threads(sim);
    e->n_local = call->n_local;
    e->n_total = call->n_total;
    e->x = call->x;
    e->xs = call->stride;
    e->v = call->v;
    e->rho = call->rho;
    e->S = call->S;
    e->mass = call->mass;
    e->damage = call->damage;
    e->material_of = call->material;
    e->materials = sim->materials;
    if (call->neighbours) {
        e->offsets32 = call->offsets32;
        e->offsets = call->offsets32 ? NULL : call->neighbours->offsets;
        e->indices = call->neighbours->indices;
        e->lists = call->neighbours->lists;
        e->counts = call->neighbours->counts;
    }
    e->h = sim->h;
    e->inv_h = 1.0 / sim->h;
    const double sigma = kernel_sigma(sim->kernel, sim->dim);
    e->w_norm = sigma / pow(sim->h, sim->dim);
    e->f_norm = sigma / pow(sim->h, sim->dim + 2);
    /* (2h)^2 widened by 1e-12: beyond it q = sqrt(r^2) / h rounds to more
     * than 2, where every kernel's w and f are exactly zero */
    const double support = kernel_support(sim->kernel) * sim->h;
    e->cut2 = support * support * (1.0 + 1e-12);
    e->fx = sim->fx;
    e->c0_all = uniform_c0(sim);
    e->pstride = pair_data_width(sim);
    e->inv_W_dx = 1.0 / (kernel_w(sim->kernel, sim->dim, sim->dx_ref / sim->h) * e->w_norm);
    for (int i = 0; i < sim->dim; ++i) {
        e->periodic_axis[i] = call->periodic && sim->periodic[i];
        e->box[i] = sim->hi[i] - sim->lo[i];
        e->half_box[i] = 0.5 * e->box[i];
        e->periodic |= e->periodic_axis[i];
    }
    e->pass = call->pass ? call->pass : PASS_ALL;
    e->path = rates_path(sim->rate_path);
    e->full = !call->half;
    e->reverse = e->full || call->far_in_both_rows;
    e->ghost_sums = call->partial != NULL;
    e->split = call->partial != NULL;
    e->sorted = call->sorted_rows;
    e->chunk = rates_chunk_rows(sim->dim, call->n_local);
    e->n_chunks = (long)((call->n_local + e->chunk - 1) / e->chunk);
    sums largest; /* far lists sized for the records of every pass */
    sums_layout(sim, sim->fx.xsph, PASS_ALL, &largest);
    if ((st = prepare_far(sim, e->n_chunks, 4 * largest.nv)))
        return st;
    e->far = sim->far;
    e->dv_dt = call->dv_dt;
    e->drho_dt = call->drho_dt;
    e->dS_dt = call->dS_dt;
    e->dx_dt = call->dx_dt;
    return SPH_OK;
}

/* Each thread zeroes the sums of its block of particles: a sum whose rows
 * are contiguous (stride = width: the rate arrays) in one memset, a sum in
 * a buffer of records element by element. */
static void zero_sums(const engine *e, size_t n)
{
#pragma omp parallel num_threads(e->threads)
    {
        long begin, end;
        thread_block((long)n, &begin, &end);
        const sums *s = &e->acc;
        const size_t rows = (size_t)(end - begin);
        if (s->packed) { /* whole records, padding included */
            const size_t z = 4 * (size_t)s->nv;
            memset(s->packed + (size_t)begin * z, 0, rows * z * sizeof(double));
        } else
            for (int q = 0; q < N_SUMS; ++q) {
                const size_t w = (size_t)s->width[q], z = s->stride[q];
                if (!w)
                    continue;
                double *p = s->p[q] + (size_t)begin * z;
                if (z == w)
                    memset(p, 0, rows * w * sizeof *p);
                else
                    for (size_t a = 0; a < rows; ++a)
                        for (size_t i = 0; i < w; ++i)
                            p[a * z + i] = 0.0;
            }
    }
}

/* x and v of n particles, xs doubles apart in xc and vc, written d apart
 * (d is 2 or 3).  The loop is written out for the two dimensions: OpenMP
 * outlines it before inlining could make d a constant, and a loop over d
 * per particle took 10 ns per particle in the plugin's 2D runs. */
static void copy_motion(double *x, double *v, const double *xc, const double *vc, long n, size_t d,
                        size_t xs, int threads)
{
    (void)threads; /* used by the OpenMP pragma only */
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long a = 0; a < n; ++a) {
        const size_t i = (size_t)a * xs, o = (size_t)a * d;
        x[o] = xc[i];
        x[o + 1] = xc[i + 1];
        v[o] = vc[i];
        v[o + 1] = vc[i + 1];
        if (d == 3) {
            x[o + 2] = xc[i + 2];
            v[o + 2] = vc[i + 2];
        }
    }
}

/* A caller's positions and velocities more than dim doubles apart
 * (LAMMPS's 3 in 2D) copied dim apart, as the handle keeps them, for a
 * half list without periodic axes: the gather's usual case (fill_block's
 * `fast`, with its runs).  The same values: the same bits. */
static sph_status compact_motion(sph_sim *sim, engine *e)
{
    const size_t n = e->n_total, d = (size_t)e->dim, xs = e->xs;
    if (xs == d || e->full || e->periodic || n == 0)
        return SPH_OK;
    sph_status st = grow_doubles(sim, &sim->motion_scratch, &sim->motion_scratch_n, 2 * n * d,
                                 "compact positions and velocities");
    if (st)
        return st;
    double *x = sim->motion_scratch, *v = x + n * d;
    copy_motion(x, v, e->x, e->v, (long)n, d, xs, e->threads);
    e->x = x;
    e->v = v;
    e->xs = d;
    return SPH_OK;
}

static sph_status pairs_run(sph_sim *sim, engine *e)
{
    sph_status st = compact_motion(sim, e);
    if (st)
        return st;
    double *R = sim->fx.artificial_stress && (e->pass & PASS_MOMENTUM) ? sim->stress_R : NULL;
    pass_pair_data(e, sim->pair_data, R);
    e->pair_data = sim->pair_data;
    e->R = R;
    const size_t n_sums = e->ghost_sums ? e->n_total : e->n_local;
    zero_sums(e, n_sums);
    pass_pairs(e, sim->kernel, n_sums);
    for (long c = 0; c < e->n_chunks; ++c)
        if (e->far[c].failed)
            return sph_fail(sim, SPH_ERR_MEMORY, "cannot grow the list of pair terms of chunk %ld",
                            c);
    return SPH_OK;
}

/* The sums of the locals in the engine's packed records (sum_scratch):
 * whole vectors of 4 doubles per particle, so that a pair's terms are
 * added to them a vector at a time; the finish reads them from there. */
static sph_status sums_in_records(sph_sim *sim, const rate_call *call, sums *acc)
{
    sph_status st = grow_sum_scratch(sim, call->n_local * (size_t)(4 * acc->nv));
    if (st)
        return st;
    sums_in_buffer(acc, sim->sum_scratch, 1);
    return SPH_OK;
}

sph_status rates_run(sph_sim *sim, const rate_call *call)
{
    engine e;
    sph_status st = engine_setup(sim, call, &e);
    if (st)
        return st;
    const int xsph = sim->fx.xsph && (call->dx_dt || call->partial);
    sums_layout(sim, xsph, e.pass, &e.acc);
    if (call->partial) {
        sums_in_buffer(&e.acc, call->partial, 0);
        return pairs_run(sim, &e);
    }
    /* the sums of the locals in packed records (a ghost's terms are
     * dropped: only a partial-sum buffer keeps them) */
    if ((st = sums_in_records(sim, call, &e.acc)) || (st = pairs_run(sim, &e)))
        return st;
    pass_finish(&e);
    return SPH_OK;
}

/* The finish on a caller's partial sums. */
static sph_status finish_run(sph_sim *sim, const rate_call *call, const double *partial)
{
    engine e;
    rate_call c = *call;
    c.partial = NULL;
    sph_status st = engine_setup(sim, &c, &e);
    if (st)
        return st;
    sums_layout(sim, sim->fx.xsph != 0, e.pass, &e.acc);
    sums_in_buffer(&e.acc, (double *)partial, 0);
    pass_finish(&e);
    return SPH_OK;
}

/* ------------------------------------------------------- public entry points */

/* Below this many items a public call's checks run on one thread (a
 * parallel region costs more than the loop). */
#define PER_CALL_SERIAL 20000

static sph_status check_particles(sph_sim *sim, const char *fn, const sph_particles *p,
                                  size_t *stride)
{
    if (p->n_local > p->n_total)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: n_local=%zu exceeds n_total=%zu", fn,
                        p->n_local, p->n_total);
    *stride = p->stride ? p->stride : (size_t)sim->dim;
    if (*stride < (size_t)sim->dim)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: stride=%zu is smaller than the dimension %d",
                        fn, *stride, sim->dim);
    if (p->n_total > 0 && (!p->x || !p->v || !p->rho || !p->S || !p->mass || !p->material))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "%s: a particle array (x, v, rho, S, mass, material) is NULL", fn);
    if (p->n_total > 0 && sim->fx.damage && !p->damage)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "%s: effect damage is on but particles->damage (n_total) is NULL", fn);
    /* one pass that vectorises (and runs on the pair pass's threads), the
     * particle named only if one is wrong */
    size_t wrong = 0;
    const long n = (long)p->n_total;
    const int *material = p->material;
    const double *rho = p->rho;
    const unsigned n_materials = (unsigned)sim->n_materials;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) \
    reduction(+ : wrong) if (n > PER_CALL_SERIAL)
    for (long i = 0; i < n; ++i)
        wrong += ((unsigned)material[i] >= n_materials) | !(rho[i] > 0.0);
    for (size_t i = 0; wrong && i < p->n_total; ++i) {
        if (p->material[i] < 0 || p->material[i] >= sim->n_materials)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "%s: particle %zu has material %d, but %d materials are defined", fn, i,
                            p->material[i], sim->n_materials);
        if (!(p->rho[i] > 0.0))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "%s: particle %zu has density rho=%g (must be > 0)", fn, i, p->rho[i]);
    }
    return SPH_OK;
}

static sph_status check_neighbours(sph_sim *sim, const char *fn, const sph_particles *p,
                                   const sph_neighbours *nb)
{
    if (!((nb->offsets && nb->indices) || (nb->lists && nb->counts)) && p->n_local > 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "%s: give neighbours as offsets+indices or lists+counts", fn);
    return SPH_OK;
}

/* Whether every row of a caller's list is strictly ascending (the pair
 * pass's runs need it: rate_loop.h's fill_block).  For offsets+indices,
 * one pass over the indices that the compiler vectorises: the descents
 * of the whole array, less those where a row starts, are the rows'. */
int rates_rows_ascending(size_t n_rows, const sph_neighbours *nb, int threads)
{
    (void)threads; /* used by the OpenMP pragmas only */
    if (!nb->offsets || !nb->indices) {
        for (size_t a = 0; a < n_rows; ++a)
            for (int k = 1; k < nb->counts[a]; ++k)
                if (nb->lists[a][k] <= nb->lists[a][k - 1])
                    return 0;
        return 1;
    }
    const size_t *off = nb->offsets;
    const int *idx = nb->indices + off[0];
    const size_t total = off[n_rows] - off[0];
    /* entries [1, total) in blocks of 2^16, whose 32-bit counts vectorise */
    const long blocks = (long)((total + 0xffff) >> 16);
    size_t descents = 0;
#pragma omp parallel for schedule(static) num_threads(threads) \
    reduction(+ : descents) if (total > PER_CALL_SERIAL)
    for (long c = 0; c < blocks; ++c) {
        const size_t k0 = c ? (size_t)c << 16 : 1;
        const size_t k1 = total - ((size_t)c << 16) > 0x10000 ? ((size_t)c + 1) << 16 : total;
        uint32_t d = 0;
        for (size_t k = k0; k < k1; ++k)
            d += idx[k] <= idx[k - 1];
        descents += d;
    }
    if (!descents)
        return 1;
    /* the rows' starts after the first entry (without branches: a row that
     * starts nothing reads entries 1 and 0, and counts nothing) */
    size_t starts = 0;
#pragma omp parallel for schedule(static) num_threads(threads) \
    reduction(+ : starts) if (n_rows > PER_CALL_SERIAL)
    for (long a = 1; a < (long)n_rows; ++a) {
        const size_t s = off[a] - off[0], e = off[a + 1] - off[0];
        const int start = s > 0 && s < e;
        const size_t j = start ? s : 1;
        starts += (size_t)(start & (idx[j] <= idx[j - 1]));
    }
    return descents == starts;
}

static sph_status check_rates(sph_sim *sim, const char *fn, int pass, const sph_particles *p,
                              const sph_rates *rates)
{
    if (p->n_local == 0)
        return SPH_OK;
    if ((pass & PASS_MOMENTUM) && !rates->dv_dt)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: rates->dv_dt is NULL", fn);
    if ((pass & PASS_CONTINUITY) && (!rates->drho_dt || !rates->dS_dt))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: a rate array (drho_dt, dS_dt) is NULL", fn);
    if ((pass & PASS_CONTINUITY) && sim->fx.xsph && !rates->dx_dt)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: effect xsph is on but rates->dx_dt is NULL",
                        fn);
    return SPH_OK;
}

static sph_status check_pass(sph_sim *sim, const char *fn, int pass)
{
    if (pass < SPH_RATES_CONTINUITY || pass > SPH_RATES_ALL)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "%s: pass=%d is not SPH_RATES_CONTINUITY (1), SPH_RATES_MOMENTUM (2) or "
                        "SPH_RATES_ALL (3)",
                        fn, pass);
    return SPH_OK;
}

/* A call on arrays of particle state: {x, v, rho, S, mass}. */
static rate_call call_on(size_t n_local, size_t n_total, const double *const state[5],
                         size_t stride, const int *material, int pass)
{
    return (rate_call){.n_local = n_local,
                       .n_total = n_total,
                       .x = state[0],
                       .v = state[1],
                       .rho = state[2],
                       .S = state[3],
                       .mass = state[4],
                       .stride = stride,
                       .material = material,
                       .pass = pass};
}

static void rates_into(rate_call *call, const sph_rates *rates)
{
    call->dv_dt = rates->dv_dt;
    call->drho_dt = rates->drho_dt;
    call->dS_dt = rates->dS_dt;
    call->dx_dt = rates->dx_dt;
}

sph_status rates_of_handle(sph_sim *sim, int pass)
{
    const sph_neighbours nb = {.offsets = sim->nl.offsets, .indices = sim->nl.indices};
    const double *const state[5] = {sim->x, sim->v, sim->rho, sim->S, sim->mass};
    rate_call call = call_on(sim->n, sim->n, state, (size_t)sim->dim, sim->material_of, pass);
    const sph_rates r = {sim->dv_dt, sim->drho_dt, sim->dS_dt, sim->fx.xsph ? sim->dx_dt : NULL};
    rates_into(&call, &r);
    call.neighbours = &nb;
    call.offsets32 = sim->nl.offsets32;
    call.periodic = 1;
    call.half = 1;
    call.far_in_both_rows = 1;
    call.sorted_rows = !sim->no_runs;
    call.damage = sim->damage;
    if (sim->nl.chunk != rates_chunk_rows(sim->dim, sim->n))
        return sph_fail(sim, SPH_ERR_STATE,
                        "the neighbour list was built for chunks of %zu rows, the pair pass "
                        "uses %zu",
                        sim->nl.chunk, rates_chunk_rows(sim->dim, sim->n));
    return rates_run(sim, &call);
}

/* The public calls on caller arrays: one evaluation (rates from
 * neighbours), the pair pass (partial sums from a half list) and the
 * finish (rates from the partial sums). */
enum { CALL_EVALUATE, CALL_PAIRS, CALL_FINISH, CALL_HALF };

/* Checks the handle and the arguments of call `kind` (each pointer it uses
 * must be given), sets up the call on the caller's particles and runs it.
 * `sums` is the pair pass's output, `sums_in` the finish's input. */
static sph_status public_call(sph_sim *sim, int kind, int pass, const sph_particles *p,
                              const sph_neighbours *nb, const sph_rates *rates, double *sums,
                              const double *sums_in)
{
    static const char *const names[] = {"sph_rates_evaluate", "sph_rates_pairs", "sph_rates_finish",
                                        "sph_rates_pass_half"};
    static const char *const needs[] = {"particles, neighbours and rates",
                                        "particles and neighbours", "particles and rates",
                                        "particles, neighbours and rates"};
    const char *fn = names[kind];
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!p || (kind != CALL_FINISH && !nb) || (kind != CALL_PAIRS && !rates))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: %s must not be NULL", fn, needs[kind]);
    size_t stride = 0;
    sph_status st;
    if ((st = check_pass(sim, fn, pass)) || (st = check_particles(sim, fn, p, &stride)) ||
        (kind != CALL_FINISH && (st = check_neighbours(sim, fn, p, nb))) ||
        (kind != CALL_PAIRS && (st = check_rates(sim, fn, pass, p, rates))))
        return st;
    if ((kind == CALL_PAIRS || kind == CALL_FINISH) &&
        (kind == CALL_PAIRS ? p->n_total : p->n_local) > 0 &&
        !(kind == CALL_PAIRS ? (const double *)sums : sums_in))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "%s: partial is NULL; it holds %s * sph_rates_pass_size() doubles", fn,
                        kind == CALL_PAIRS ? "n_total" : "n_local");
    const double *const state[5] = {p->x, p->v, p->rho, p->S, p->mass};
    rate_call call = call_on(p->n_local, p->n_total, state, stride, p->material, pass);
    call.neighbours = nb;
    call.half = kind != CALL_EVALUATE;
    call.sorted_rows = (kind == CALL_HALF || kind == CALL_PAIRS) && !sim->no_runs &&
                       rates_rows_ascending(p->n_local, nb, sim_threads(sim));
    call.partial = sums;
    call.damage = sim->fx.damage ? p->damage : NULL;
    if (rates)
        rates_into(&call, rates);
    st = kind == CALL_FINISH ? finish_run(sim, &call, sums_in) : rates_run(sim, &call);
    return st ? st : sph_ok(sim);
}

sph_status sph_rates_pass_half(sph_sim *sim, int pass, const sph_particles *p,
                               const sph_neighbours *half, sph_rates *rates)
{
    return public_call(sim, CALL_HALF, pass, p, half, rates, NULL, NULL);
}

sph_status sph_rates_evaluate(sph_sim *sim, const sph_particles *p, const sph_neighbours *nb,
                              sph_rates *rates)
{
    return public_call(sim, CALL_EVALUATE, PASS_ALL, p, nb, rates, NULL, NULL);
}

size_t sph_rates_pass_size(const sph_sim *sim, int pass)
{
    if (!sim || pass < SPH_RATES_CONTINUITY || pass > SPH_RATES_ALL)
        return 0;
    sums s;
    sums_layout(sim, sim->fx.xsph != 0, pass, &s);
    return (size_t)s.record;
}

size_t sph_rates_partial_size(const sph_sim *sim)
{
    return sph_rates_pass_size(sim, SPH_RATES_ALL);
}

sph_status sph_rates_pass_pairs(sph_sim *sim, int pass, const sph_particles *p,
                                const sph_neighbours *half, double *partial)
{
    return public_call(sim, CALL_PAIRS, pass, p, half, NULL, partial, NULL);
}

sph_status sph_rates_pass_finish(sph_sim *sim, int pass, const sph_particles *p,
                                 const double *partial, sph_rates *rates)
{
    return public_call(sim, CALL_FINISH, pass, p, NULL, rates, NULL, partial);
}

/* The same for the whole evaluation (both passes at once). */
sph_status sph_rates_pairs(sph_sim *sim, const sph_particles *p, const sph_neighbours *half,
                           double *partial)
{
    return sph_rates_pass_pairs(sim, SPH_RATES_ALL, p, half, partial);
}

sph_status sph_rates_finish(sph_sim *sim, const sph_particles *p, const double *partial,
                            sph_rates *rates)
{
    return sph_rates_pass_finish(sim, SPH_RATES_ALL, p, partial, rates);
}
