/*
 * The pair loop of the rate engine (rates.c), as inline functions: the
 * engine, the sums and the blocks of pairs, and chunk_rows, the rows of
 * one chunk with the dimension, kernel, sums and pass as compile-time
 * constants.  Each instruction-set path is its own translation unit
 * (rates_base.c, rates_avx2.c, rates_avx512.c) that instantiates every
 * variant of chunk_rows for its path with RATE_CHUNK_VARIANTS and lists
 * them in a table (rates_chunks_PATH) that rates.c dispatches to: the
 * three compile in parallel.
 */
#ifndef SPHSOLID_RATE_LOOP_H
#define SPHSOLID_RATE_LOOP_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "effects/damage.h"
#include "physics/kernel.h"
#include "core/sim.h"

/* The per-particle sums of the pair pass, one after the other in a record
 * per particle, each at `offset` (the velocity gradient L, dim x dim,
 * row-major, is one sum): in the engine's own packed records (a whole
 * number of vectors of 4 doubles per particle, zero-padded), in a row of a
 * caller's partial-sum buffer, and in a far-list record. */
enum { SUM_RHO, SUM_DV, SUM_L, SUM_M, SUM_U, N_SUMS };

typedef struct sums {
    double *p[N_SUMS];
    size_t stride[N_SUMS];
    int width[N_SUMS]; /* components; 0: not summed */
    int offset[N_SUMS];
    int record; /* doubles of all sums of one particle */
    int nv;     /* vectors of 4 doubles that hold a record (zero-padded) */
    /* the engine's own sums: records of 4 nv doubles, particle b's at
     * packed + 4 nv b, each added a whole vector at a time; NULL for a
     * caller's buffer of `record` doubles per particle */
    double *packed;
} sums;

typedef struct engine {
    int dim, ncomp, nsym, threads;
    size_t n_local, n_total;
    const double *x, *v, *rho, *S, *mass;
    size_t xs; /* doubles between particles in x and v */
    const int *material_of;
    const material *materials;
    const uint32_t *offsets32;
    const size_t *offsets;
    const int *indices;
    const int *const *lists;
    const int *counts;
    const double *pair_data; /* pstride doubles: sigma/rho^2, c0 (if not the
                                same for every material) */
    int pstride;
    double c0_all;   /* the sound speed of every material, or 0 */
    const double *R; /* nsym per particle, or NULL */
    /* D per particle (effect damage), or NULL */
    const double *damage;
    double h, inv_h, w_norm, f_norm;
    /* pairs with |r_ab|^2 > cut2 are beyond the kernel's support: every
     * term of theirs is an exact zero (not computed) */
    double cut2;
    double box[3], half_box[3];
    int periodic_axis[3];
    int periodic; /* some axis is periodic */
    effects fx;
    double inv_W_dx;
    int pass; /* PASS_CONTINUITY | PASS_MOMENTUM */
    int path; /* RATE_PATH_*: the instruction set of the pair loop */
    /* pair pass */
    int full;       /* full list: a pair with b < a is skipped unless far */
    int reverse;    /* a far pair of locals is in both rows (no far records) */
    int ghost_sums; /* keep the terms of ghosts (b >= n_local) */
    int split;      /* the sums in a caller's buffer (else packed records) */
    int sorted;     /* each row's indices ascending, none repeated */
    size_t chunk;   /* rows per chunk */
    long n_chunks;
    sums acc;
    far_list *far; /* one per chunk */
    /* finish */
    double *dv_dt, *drho_dt, *dS_dt, *dx_dt;
} engine;

#if defined(__GNUC__)
#define ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE inline
#endif

static ALWAYS_INLINE void neighbours_of(const engine *e, size_t a, const int **list, int *count)
{
    if (e->offsets32) {
        *list = e->indices + e->offsets32[a];
        *count = (int)(e->offsets32[a + 1] - e->offsets32[a]);
    } else if (e->offsets) {
        *list = e->indices + e->offsets[a];
        *count = (int)(e->offsets[a + 1] - e->offsets[a]);
    } else {
        *list = e->lists[a];
        *count = e->counts[a];
    }
}

/* rates.c: appends one far record (the terms for particle b, `record` <=
 * f->record doubles); on allocation failure the list is marked and the
 * pass reports it. */
void rates_far_append(far_list *f, int record, size_t b, const double *terms);

/* The largest record of sums: drho (1), dv (3), L (9), M (6), u (3), and
 * the vectors of 4 doubles that hold it. */
#define MAX_RECORD (1 + 3 + 9 + 6 + 3)
#define MAX_NV     ((MAX_RECORD + 3) / 4)

static inline int vectors_of(int record) { return (record + 3) / 4; }

/* Four doubles added lane by lane: the same additions as four scalar ones,
 * bitwise, in one vector instruction where the path has them.  V4_LOAD and
 * V4_STORE take any double pointer (any alignment). */
#if defined(__GNUC__)
typedef double v4d __attribute__((vector_size(32)));
typedef double v4d_any __attribute__((vector_size(32), aligned(8), may_alias));
#define V4_LOAD(p)     ((v4d)(*(const v4d_any *)(const void *)(p)))
#define V4_STORE(p, v) (*(v4d_any *)(void *)(p) = (v))
#define V4_ADD(x, y)   ((x) + (y))
#define V4_ZERO        ((v4d){0.0, 0.0, 0.0, 0.0})
#if defined(__clang__)
#define V4_SHUFFLE(x, y, i, j, k, l) __builtin_shufflevector(x, y, i, j, k, l)
#else
typedef long long v4i __attribute__((vector_size(32)));
#define V4_SHUFFLE(x, y, i, j, k, l) __builtin_shuffle(x, y, (v4i){i, j, k, l})
#endif
/* c[j][i] = r[i][j]: the rows of four sums over four pairs turned into the
 * four pairs' records. */
static ALWAYS_INLINE void v4_transpose(const v4d r[4], v4d c[4])
{
    const v4d t0 = V4_SHUFFLE(r[0], r[1], 0, 4, 2, 6), t1 = V4_SHUFFLE(r[0], r[1], 1, 5, 3, 7);
    const v4d t2 = V4_SHUFFLE(r[2], r[3], 0, 4, 2, 6), t3 = V4_SHUFFLE(r[2], r[3], 1, 5, 3, 7);
    c[0] = V4_SHUFFLE(t0, t2, 0, 1, 4, 5);
    c[1] = V4_SHUFFLE(t1, t3, 0, 1, 4, 5);
    c[2] = V4_SHUFFLE(t0, t2, 2, 3, 6, 7);
    c[3] = V4_SHUFFLE(t1, t3, 2, 3, 6, 7);
}
#else
typedef struct v4d {
    double d[4];
} v4d;
static inline v4d v4_load(const double *p)
{
    v4d v;
    memcpy(&v, p, sizeof v);
    return v;
}
static inline v4d v4_add(v4d x, v4d y)
{
    for (int i = 0; i < 4; ++i)
        x.d[i] += y.d[i];
    return x;
}
static inline v4d v4_zero(void)
{
    v4d v = {{0.0, 0.0, 0.0, 0.0}};
    return v;
}
#define V4_LOAD(p)     v4_load(p)
#define V4_STORE(p, v) memcpy(p, &(v), sizeof(v4d))
#define V4_ADD(x, y)   v4_add(x, y)
#define V4_ZERO        v4_zero()
static inline void v4_transpose(const v4d r[4], v4d c[4])
{
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            c[j].d[i] = r[i].d[j];
}
#endif

/* Adds a record of terms t (4 s->nv doubles, in the order of the sums'
 * offsets) to particle b's sums.  The one scatter of the pair pass: own
 * rows, partners and far records; packed records (s->packed) a vector at
 * a time, a caller's buffer sum by sum. */
static ALWAYS_INLINE void add_record(const sums *s, size_t b, const double *restrict t,
                                     const int packed)
{
    if (packed) {
        double *restrict dst = s->packed + b * (size_t)(4 * s->nv);
        for (int j = 0; j < s->nv; ++j) {
            const v4d sum = V4_ADD(V4_LOAD(dst + 4 * j), V4_LOAD(t + 4 * j));
            V4_STORE(dst + 4 * j, sum);
        }
        return;
    }
#pragma GCC unroll 6
    for (int q = 0; q < N_SUMS; ++q) {
        if (!s->width[q])
            continue;
        double *restrict dst = s->p[q] + b * s->stride[q];
        for (int i = 0; i < s->width[q]; ++i) {
            const int c = s->offset[q] + i;
            dst[i] += t[c];
        }
    }
}

/* The engine's sums with what the variant fixes at compile time: the
 * widths of the pass and, without effect sums, the record's length. */
static ALWAYS_INLINE sums loop_sums(const engine *e, const int dim, const int pass, const int plain)
{
    sums s = e->acc;
    if (plain) { /* no sums of effects (M, u): the record's length is fixed */
        s.width[SUM_M] = s.width[SUM_U] = 0;
        s.record = (pass & PASS_CONTINUITY ? 1 + dim * dim : 0) + (pass & PASS_MOMENTUM ? dim : 0);
        s.nv = vectors_of(s.record);
    }
    const int cont = (pass & PASS_CONTINUITY) != 0, mom = (pass & PASS_MOMENTUM) != 0;
    s.width[SUM_RHO] = cont;
    s.width[SUM_DV] = mom ? dim : 0;
    s.width[SUM_L] = cont ? dim * dim : 0;
    s.offset[SUM_DV] = cont;
    s.offset[SUM_L] = cont + s.width[SUM_DV];
    return s;
}

/* A block of pairs being filled row after row: the terms' inputs (those of
 * a per pair too, since the pairs may come from several rows), which
 * particles each pair joins, and what the gather leaves to vector loops. */
typedef struct row_block {
    pair_block p;
    int a[PAIR_BLOCK], b[PAIR_BLOCK];
    double rho_a[PAIR_BLOCK], rho_b[PAIR_BLOCK];
} row_block;

/* Lanes of every input set to finite filler (a pair at rest at zero
 * distance, unit densities), so that the fixed-length loops never meet
 * uninitialised or denormal values past the block's pairs. */
static ALWAYS_INLINE void block_filler(row_block *k)
{
    memset(k, 0, sizeof *k);
    for (int i = 0; i < PAIR_BLOCK; ++i)
        k->rho_a[i] = k->rho_b[i] = 1.0;
}

/* Per row a: what every pair of the row takes from a, copied into the
 * row's own variables once per row. */
typedef struct row_data {
    double x[3], v[3], P[6];
    double m, V, rho;
} row_data;

static ALWAYS_INLINE void row_of(const engine *e, size_t a, const int dim, const int pass,
                                 row_data *r)
{
    const int nsym = dim == 2 ? 3 : 6;
    const int mom = pass & PASS_MOMENTUM;
    const double *P = e->pair_data + a * (size_t)e->pstride;
    for (int i = 0; i < dim; ++i) {
        r->x[i] = e->x[a * e->xs + (size_t)i];
        r->v[i] = e->v[a * e->xs + (size_t)i];
    }
    if (mom)
        for (int c = 0; c < nsym; ++c)
            r->P[c] = P[c];
    r->m = e->mass[a];
    r->rho = e->rho[a];
    r->V = r->m / r->rho;
}

/* What the gather reads of the engine, copied once per chunk into a local
 * (the block's stores cannot alias it, so nothing is reloaded per pair). */
typedef struct gather_src {
    const double *x, *v, *mass, *rho, *pair_data, *R;
    size_t xs;
    double cut2; /* e->cut2 */
    /* the periodic axes (e->periodic_axis, box, half_box) */
    int periodic, periodic_axis[3];
    double box[3], half_box[3];
    size_t pstride;
    int c_per_pair; /* the sound speeds differ: c_mean per pair */
    int sorted;     /* e->sorted */
} gather_src;

static ALWAYS_INLINE gather_src gather_src_of(const engine *e, const int pass)
{
    const int mom = pass & PASS_MOMENTUM;
    gather_src g = {.x = e->x,
                    .v = e->v,
                    .mass = e->mass,
                    .rho = e->rho,
                    .pair_data = e->pair_data,
                    .R = mom ? e->R : NULL,
                    .xs = e->xs,
                    .pstride = (size_t)e->pstride};
    g.c_per_pair = mom && e->fx.artificial_viscosity && !(e->c0_all > 0.0);
    g.cut2 = e->cut2;
    g.sorted = e->sorted;
    g.periodic = e->periodic;
    for (int i = 0; i < 3; ++i) {
        g.periodic_axis[i] = e->periodic_axis[i];
        g.box[i] = e->box[i];
        g.half_box[i] = e->half_box[i];
    }
    return g;
}

/* r_ab = x_a - x_b, with the minimum image along periodic axes (if the
 * compile-time `periodic`); returns |r_ab|^2. */
static ALWAYS_INLINE double separation(const gather_src *g, const double *xb, const double *xa,
                                       const int dim, const int periodic, double *r_ab)
{
    double r2 = 0.0;
    for (int i = 0; i < dim; ++i) {
        double d = xa[i] - xb[i];
        if (periodic && g->periodic_axis[i])
            d = nearest_image(d, g->box[i], g->half_box[i]);
        r_ab[i] = d;
        r2 += d * d;
    }
    return r2;
}

/* Lane k of the block: b's side of the pair (a, b) at separation r_ab,
 * gathered in structure-of-arrays form with the per-pair factors of the
 * pass (a's values: row_lanes). */
static ALWAYS_INLINE void gather_pair(const gather_src *g, const row_data *ra, size_t b,
                                      const double *r_ab, const int dim, const int pass,
                                      const int fast, row_block *blk, int k)
{
    const int nsym = dim == 2 ? 3 : 6;
    const size_t xs = fast ? (size_t)dim : g->xs, pstride = fast ? (size_t)nsym : g->pstride;
    const int mom = pass & PASS_MOMENTUM;
    pair_block *p = &blk->p;
    blk->b[k] = (int)b;
    const double *vb = g->v + b * xs;
    const double *Pb = g->pair_data + b * pstride;
    for (int i = 0; i < dim; ++i) {
        p->r[i][k] = r_ab[i];
        p->v[i][k] = ra->v[i] - vb[i];
    }
    p->m_b[k] = g->mass[b];
    blk->rho_b[k] = g->rho[b];
    if (mom) /* the per-particle stress factors (pass_pair_data) */
        for (int c = 0; c < nsym; ++c)
            p->T[c][k] = ra->P[c] + Pb[c];
}

/* A run: lanes [k, k + RUN) of the block, the pairs of a with the RUN
 * consecutive particles from b on, in the handle's sorted rows (`fast`),
 * each quantity loaded RUN values at a time.  A run is taken without the
 * support test: a pair beyond the support adds exact zeros (every
 * kernel's w and f are zero there), so every sum keeps the bits it has
 * with the pair skipped.  It gathers what gather_pair does, in loops of
 * its own: gather_pair written as a run of length 1 over shared loops
 * measured 1-2 % slower for the leapfrog and 5 % for Improved Euler,
 * most of what the runs gain; runs_keep_the_bits holds the two to the
 * same quantities. */
enum { RUN = 4 };

static ALWAYS_INLINE void gather_run(const gather_src *g, const row_data *ra, size_t b,
                                     const int dim, const int pass, row_block *blk, int k)
{
    const int nsym = dim == 2 ? 3 : 6;
    const double *xb = g->x + b * (size_t)dim, *vb = g->v + b * (size_t)dim;
    pair_block *p = &blk->p;
    for (int j = 0; j < RUN; ++j)
        blk->b[k + j] = (int)b + j;
    for (int i = 0; i < dim; ++i)
        for (int j = 0; j < RUN; ++j) {
            p->r[i][k + j] = ra->x[i] - xb[j * dim + i];
            p->v[i][k + j] = ra->v[i] - vb[j * dim + i];
        }
    for (int j = 0; j < RUN; ++j) {
        p->m_b[k + j] = g->mass[b + (size_t)j];
        blk->rho_b[k + j] = g->rho[b + (size_t)j];
    }
    if (pass & PASS_MOMENTUM) {
        const double *Pb = g->pair_data + b * (size_t)nsym;
        for (int c = 0; c < nsym; ++c)
            for (int j = 0; j < RUN; ++j)
                p->T[c][k + j] = ra->P[c] + Pb[j * nsym + c];
    }
}

/* Lanes [first, n) of the block hold pairs of row a: a's values, filled
 * once per row. */
static ALWAYS_INLINE void row_lanes(const row_data *ra, size_t a, const int pass, row_block *blk,
                                    int first, int n)
{
    pair_block *p = &blk->p;
    for (int k = first; k < n; ++k) {
        blk->a[k] = (int)a;
        p->m_a[k] = ra->m;
        blk->rho_a[k] = ra->rho;
    }
    if (pass & PASS_CONTINUITY)
        for (int k = first; k < n; ++k)
            p->V_a[k] = ra->V;
}

/* The effects' per-pair inputs of the block, pair by pair from the
 * particles a and b the gather recorded (one test per block). */
static ALWAYS_INLINE void gather_effects(const gather_src *g, row_block *blk, const int dim)
{
    const int nsym = dim == 2 ? 3 : 6, n = blk->p.n;
    if (g->c_per_pair)
        for (int k = 0; k < n; ++k) {
            const double *Pa = g->pair_data + (size_t)blk->a[k] * g->pstride;
            const double *Pb = g->pair_data + (size_t)blk->b[k] * g->pstride;
            blk->p.c_mean[k] = 0.5 * (Pa[nsym] + Pb[nsym]);
        }
    if (g->R)
        for (int k = 0; k < n; ++k) {
            const double *Ra = g->R + (size_t)blk->a[k] * (size_t)nsym;
            const double *Rb = g->R + (size_t)blk->b[k] * (size_t)nsym;
            for (int c = 0; c < nsym; ++c)
                blk->p.R[c][k] = Ra[c] + Rb[c];
        }
}

/* The rest of the block's inputs, in loops over all lanes without
 * branches (they vectorise): volumes, means, the kernel and its gradient. */
static ALWAYS_INLINE void block_inputs(const engine *e, row_block *blk, const int dim,
                                       const int kernel, const int pass)
{
    pair_block *p = &blk->p;
    const int cont = pass & PASS_CONTINUITY, mom = pass & PASS_MOMENTUM;
    const int viscosity = mom && e->fx.artificial_viscosity, stress = mom && e->R;
    const int xsph = cont && e->acc.width[SUM_U] > 0;
    if (cont) /* volumes m/rho (rounded as when they were stored) */
        for (int k = 0; k < PAIR_BLOCK; ++k)
            p->V_b[k] = p->m_b[k] / blk->rho_b[k];
    if (viscosity || xsph)
        for (int k = 0; k < PAIR_BLOCK; ++k)
            p->rho_mean[k] = 0.5 * (blk->rho_a[k] + blk->rho_b[k]);
    double q[PAIR_BLOCK];
    for (int k = 0; k < PAIR_BLOCK; ++k) {
        double q2 = 0.0;
        for (int i = 0; i < dim; ++i)
            q2 += p->r[i][k] * p->r[i][k];
        p->r2[k] = q2;
        q[k] = sqrt(q2) * e->inv_h;
    }
    for (int k = 0; k < PAIR_BLOCK; ++k) {
        const double F = kernel_f(kernel, dim, q[k]) * e->f_norm;
        for (int i = 0; i < dim; ++i)
            p->gW[i][k] = F * p->r[i][k];
    }
    if (stress || xsph)
        for (int k = 0; k < PAIR_BLOCK; ++k)
            p->W[k] = kernel_w(kernel, dim, q[k]) * e->w_norm;
}

/* The terms of a block: every pair term of the pass whose switch is on,
 * written to the rows of its sums in the record (ta for a, tb for b). */
static ALWAYS_INLINE void pair_terms(const engine *e, pair_block *p, const sums *s, const int dim,
                                     const int pass, pair_rows *ta, pair_rows *tb)
{
    if (pass & PASS_MOMENTUM) {
        const effects *fx = &e->fx;
        if (fx->artificial_viscosity)
            artificial_viscosity_term(dim, fx->artificial_viscosity_alpha,
                                      fx->artificial_viscosity_beta, e->h, p);
        if (e->R)
            artificial_stress_term(dim, e->inv_W_dx, fx->artificial_stress_n, p);
        momentum_term(dim, p, ta + s->offset[SUM_DV], tb + s->offset[SUM_DV]);
    }
    if (pass & PASS_CONTINUITY) {
        continuity_term(dim, p, ta + s->offset[SUM_RHO], tb + s->offset[SUM_RHO]);
        velocity_gradient_term(dim, p, ta + s->offset[SUM_L], tb + s->offset[SUM_L]);
        if (s->width[SUM_M])
            correction_moment_term(dim, p, ta + s->offset[SUM_M], tb + s->offset[SUM_M]);
        if (s->width[SUM_U])
            xsph_term(dim, e->fx.xsph_epsilon, p, ta + s->offset[SUM_U], tb + s->offset[SUM_U]);
    }
}

/* The rows of a chunk being summed: a's terms are summed in neighbour order
 * (from zero, in acc) and added to a's sums when its row ends, every row in
 * turn, so each sum runs in the order of the rows and their lists. */
typedef struct row_sum {
    size_t a;        /* the row being summed */
    v4d acc[MAX_NV]; /* its record */
} row_sum;

/* Ends the rows before `until`: their sums (zero for a row without pairs)
 * added to the particles'. */
static ALWAYS_INLINE void rows_end(const sums *s, row_sum *rs, size_t until, const int packed)
{
    while (rs->a < until) {
        add_record(s, rs->a, (const double *)rs->acc, packed);
        for (int j = 0; j < s->nv; ++j)
            rs->acc[j] = V4_ZERO;
        rs->a++;
    }
}

/* The block's n pairs: their terms, turned into one record per pair (four
 * pairs at a time), then in pair order a's added to the row's record, b's
 * added to b's sums (direct targets [b0, dend)), or left to b's row (a far
 * pair listed in both rows), or appended to the chunk's far records. */
static ALWAYS_INLINE void block_sums(const engine *e, const sums *s, row_block *blk, size_t b0,
                                     size_t dend, far_list *far, row_sum *rs, const int dim,
                                     const int kernel, const int pass, const int packed)
{
    const int record = s->record, nv = s->nv;
    pair_rows ta[MAX_RECORD], tb[MAX_RECORD];
    block_inputs(e, blk, dim, kernel, pass);
    pair_terms(e, &blk->p, s, dim, pass, ta, tb);
    const int n = blk->p.n;
    v4d rec_a[PAIR_BLOCK][MAX_NV], rec_b[PAIR_BLOCK][MAX_NV];
    for (int k0 = 0; k0 < n; k0 += 4)
        for (int j = 0; j < nv; ++j) {
            v4d ra[4], rb[4], ca[4], cb[4];
            for (int i = 0; i < 4; ++i) {
                const int c = 4 * j + i;
                ra[i] = c < record ? V4_LOAD(ta[c] + k0) : V4_ZERO;
                rb[i] = c < record ? V4_LOAD(tb[c] + k0) : V4_ZERO;
            }
            v4_transpose(ra, ca);
            v4_transpose(rb, cb);
            for (int i = 0; i < 4; ++i) {
                rec_a[k0 + i][j] = ca[i];
                rec_b[k0 + i][j] = cb[i];
            }
        }
    const size_t direct = dend - b0;
    for (int k = 0; k < n; ++k) {
        const size_t a = (size_t)blk->a[k], b = (size_t)blk->b[k];
        if (a != rs->a)
            rows_end(s, rs, a, packed);
        for (int j = 0; j < nv; ++j)
            rs->acc[j] = V4_ADD(rs->acc[j], rec_a[k][j]);
        if (b - b0 < direct) {
            add_record(s, b, (const double *)rec_b[k], packed);
        } else if (e->reverse && b < e->n_local) {
            /* a far pair listed in both rows: b's row adds b's terms */
        } else if (b < e->n_local || e->ghost_sums) {
            rates_far_append(far, 4 * nv, b, (const double *)rec_b[k]);
        }
    }
    blk->p.n = 0;
}

/* Where the gather stands in a chunk's rows: row a, its neighbours from kk
 * on still to be gathered; a neighbour b in [lo, a) is skipped (a full
 * list's pair that b's row computes; lo = a, nothing skipped, for a half
 * list). */
typedef struct row_cursor {
    size_t a, lo;
    int kk, count;
    const int *list;
    row_data ra;
} row_cursor;

static ALWAYS_INLINE void cursor_row(const engine *e, row_cursor *cur, size_t a, size_t far_below,
                                     const int dim, const int pass)
{
    cur->a = a;
    cur->kk = 0;
    neighbours_of(e, a, &cur->list, &cur->count);
    cur->lo = e->full && far_below < a ? far_below : a;
    row_of(e, a, dim, pass, &cur->ra);
}

/* Fills the block from the cursor on, row after row, until it holds
 * PAIR_BLOCK pairs or the rows before b1 end; a single pair beyond the
 * support is not taken (every term of its an exact zero).  `fast`, a
 * compile-time constant of each of the two calls, is the handle's usual
 * case: a half list, no periodic axis, positions and velocities dim
 * doubles apart and the pair data without sound speeds (nsym doubles
 * apart); there, in sorted rows, RUN consecutive neighbours (a row of a
 * lattice in index order) are gathered as a run. */
static ALWAYS_INLINE void fill_block(const engine *e, const gather_src *g, row_cursor *cur,
                                     row_block *blk, size_t b1, size_t far_below, const int dim,
                                     const int pass, const int fast)
{
    const size_t xs = fast ? (size_t)dim : g->xs;
    int n = blk->p.n;
    while (cur->a < b1 && n < PAIR_BLOCK) {
        const size_t a = cur->a, lo = cur->lo;
        const int *list = cur->list;
        const int room = PAIR_BLOCK - n;
        const int end = cur->count - cur->kk < room ? cur->count : cur->kk + room;
        int kk = cur->kk;
        const int first = n;
        for (; kk < end; ++kk) {
            const size_t b = (size_t)list[kk];
            /* rows in ascending order without repeats: RUN entries from
             * kk on are consecutive particles if the last is b + RUN - 1 */
            if (fast && g->sorted && kk + RUN <= end && list[kk + RUN - 1] == (int)b + RUN - 1) {
                gather_run(g, &cur->ra, b, dim, pass, blk, n);
                n += RUN;
                kk += RUN - 1;
                continue;
            }
            if (!fast && b - lo < a - lo)
                continue; /* a full list: the pair is computed in b's row */
            double r_ab[3];
            if (separation(g, g->x + b * xs, cur->ra.x, dim, !fast && g->periodic, r_ab) > g->cut2)
                continue; /* beyond the support */
            gather_pair(g, &cur->ra, b, r_ab, dim, pass, fast, blk, n++);
        }
        row_lanes(&cur->ra, a, pass, blk, first, n);
        cur->kk = kk;
        if (kk == cur->count) {
            if (a + 1 < b1)
                cursor_row(e, cur, a + 1, far_below, dim, pass);
            else
                cur->a = b1;
        }
    }
    blk->p.n = n;
}

/* The pair pass for the rows [b0, b1) of a chunk whose direct targets are
 * [b0, dend): the pairs gathered row after row into blocks of PAIR_BLOCK
 * (a block runs across rows, so its vectors are full), each block
 * summed. */
static ALWAYS_INLINE void chunk_sums(const engine *e, size_t b0, size_t b1, size_t dend,
                                     far_list *far, const int dim, const int kernel,
                                     const int split, const int pass, const int plain)
{
    const sums s = loop_sums(e, dim, pass, plain);
    const int packed = !split;
    row_block blk;
    block_filler(&blk);
    if (e->c0_all > 0.0) /* every pair's mean sound speed */
        for (int k = 0; k < PAIR_BLOCK; ++k)
            blk.p.c_mean[k] = e->c0_all;
    row_sum rs;
    rs.a = b0;
    for (int j = 0; j < MAX_NV; ++j)
        rs.acc[j] = V4_ZERO;
    /* a neighbour b < far_below is at least two chunks before a */
    const size_t far_below = b0 >= e->chunk ? b0 - e->chunk : 0;
    const gather_src g = gather_src_of(e, pass);
    const int nsym = dim == 2 ? 3 : 6;
    const int fast = !g.periodic && !e->full && g.xs == (size_t)dim &&
                     (!(pass & PASS_MOMENTUM) || g.pstride == (size_t)nsym);
    row_cursor cur;
    memset(&cur, 0, sizeof cur);
    cur.a = b1;
    if (b0 < b1)
        cursor_row(e, &cur, b0, far_below, dim, pass);
    /* one call of block_sums (each call site is a copy of the whole
     * block's code) */
    while (cur.a < b1) {
        if (fast)
            fill_block(e, &g, &cur, &blk, b1, far_below, dim, pass, 1);
        else
            fill_block(e, &g, &cur, &blk, b1, far_below, dim, pass, 0);
        gather_effects(&g, &blk, dim);
        if (blk.p.n)
            block_sums(e, &s, &blk, b0, dend, far, &rs, dim, kernel, pass, packed);
    }
    rows_end(&s, &rs, b1, packed);
}

/* One function per (dimension, kernel, sums, pass) and instruction-set
 * path: the rows of one chunk.  The baseline path is compiled for the
 * build's target; on x86-64 with GCC also for x86-64-v3 (AVX2, FMA) and
 * x86-64-v4 (AVX-512, 512-bit vectors), and each call takes the widest
 * path the CPU has (rates_path), unless the handle asks for another.  The
 * paths compute the same sums in the same order; they may differ in the
 * last bits where the compiler fuses a multiply and an add (FMA). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(SPHSOLID_NO_CLONES)
#define RATE_WIDE_PATHS 1
#define TARGET_AVX2     __attribute__((target("arch=x86-64-v3")))
#define TARGET_AVX512   __attribute__((target("arch=x86-64-v4,prefer-vector-width=512")))
#else
#define RATE_WIDE_PATHS 0
#endif

typedef void (*chunk_fn)(const engine *, long);

static ALWAYS_INLINE void chunk_rows(const engine *shared, long c, const int dim, const int kernel,
                                     const int split, const int pass)
{
    const engine *e = shared;
    const size_t b0 = (size_t)c * e->chunk;
    const size_t b1 = b0 + e->chunk < e->n_local ? b0 + e->chunk : e->n_local;
    const size_t dend = b1 + e->chunk < e->n_local ? b1 + e->chunk : e->n_local;
    if (!e->acc.width[SUM_M] && !e->acc.width[SUM_U])
        chunk_sums(e, b0, b1, dend, &e->far[c], dim, kernel, split, pass, 1);
    else
        chunk_sums(e, b0, b1, dend, &e->far[c], dim, kernel, split, pass, 0);
}

/* The chunk functions of one path: the file of the path defines
 * RATE_PATH (its name) and RATE_PATH_ATTR (its instruction set, a
 * function attribute), then instantiates one function per (dimension,
 * kernel, partial-sum buffer, pass) with SPH_KERNELS(CHUNK_VARIANTS_OF_KERNEL)
 * and lists them in its table with SPH_KERNELS(CHUNK_ENTRY). */
#define CHUNK_NAME_(PATH, DIM, KERNEL, SPLIT, PASS) \
    chunk_##PATH##_##DIM##_##KERNEL##_##SPLIT##_##PASS
#define CHUNK_NAME(PATH, DIM, KERNEL, SPLIT, PASS) CHUNK_NAME_(PATH, DIM, KERNEL, SPLIT, PASS)
#define CHUNK_FN(DIM, KERNEL, SPLIT, PASS)                                                      \
    RATE_PATH_ATTR static void CHUNK_NAME(RATE_PATH, DIM, KERNEL, SPLIT, PASS)(const engine *e, \
                                                                               long c)          \
    {                                                                                           \
        chunk_rows(e, c, DIM, KERNEL, SPLIT, PASS);                                             \
    }
#define CHUNK_VARIANTS_OF_PASS(ID, PASS) \
    CHUNK_FN(2, ID, 0, PASS)             \
    CHUNK_FN(3, ID, 0, PASS) CHUNK_FN(2, ID, 1, PASS) CHUNK_FN(3, ID, 1, PASS)
/* generated from the kernel registry (kernel.h), for the passes 1, 2, 3 */
#define CHUNK_VARIANTS_OF_KERNEL(ID, NAME, PREFIX, SUPPORT, STEP, VISCOUS) \
    CHUNK_VARIANTS_OF_PASS(ID, 1) CHUNK_VARIANTS_OF_PASS(ID, 2) CHUNK_VARIANTS_OF_PASS(ID, 3)
#define CHUNK_PASS_ENTRY(ID, PASS)                                                       \
    {                                                                                    \
        {CHUNK_NAME(RATE_PATH, 2, ID, 0, PASS), CHUNK_NAME(RATE_PATH, 3, ID, 0, PASS)},  \
        {                                                                                \
            CHUNK_NAME(RATE_PATH, 2, ID, 1, PASS), CHUNK_NAME(RATE_PATH, 3, ID, 1, PASS) \
        }                                                                                \
    }
#define CHUNK_ENTRY(ID, NAME, PREFIX, SUPPORT, STEP, VISCOUS) \
    [ID] = {CHUNK_PASS_ENTRY(ID, 1), CHUNK_PASS_ENTRY(ID, 2), CHUNK_PASS_ENTRY(ID, 3)},
#define COUNT_KERNEL(ID, NAME, PREFIX, SUPPORT, STEP, VISCOUS) +1
enum { N_KERNELS = 0 SPH_KERNELS(COUNT_KERNEL) };
#undef COUNT_KERNEL

/* Each path's table: [kernel][pass - 1][partial-sum buffer][dimension - 2]
 * (rates_base.c, rates_avx2.c, rates_avx512.c). */
extern const chunk_fn rates_chunks_base[N_KERNELS][3][2][2];
#if RATE_WIDE_PATHS
extern const chunk_fn rates_chunks_avx2[N_KERNELS][3][2][2];
extern const chunk_fn rates_chunks_avx512[N_KERNELS][3][2][2];
#endif

#endif
