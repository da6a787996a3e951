/*
 * Neighbour search: a cell list with cells at least as wide as the cutoff
 * 2h + skin, turned into a half neighbour list in CSR form (O(N)): row a
 * holds the neighbours b > a, so each pair is listed once, and in addition
 * the neighbours b < a at least two chunks of the pair pass before a
 * (rates_chunk_rows): such a pair is computed in both rows, each for its
 * own particle, so that the pair pass stores no terms for particles it
 * cannot write at once (rates.c).  Each row is sorted by index so the
 * order of the pair sums, and with it every rounding, does not depend on
 * when the list was built or on the threads.  The list is rebuilt when any
 * particle may have moved more than skin/2.
 */
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim.h"

typedef struct grid {
    int dim;
    double lo[3], width[3];
    long ncell[3];
    int periodic[3];
    double box[3];
    size_t *start; /* ncells + 1 */
    int *members;  /* particles sorted by cell */
} grid;

static long cell_coord(const grid *g, int axis, double x)
{
    long c = (long)floor((x - g->lo[axis]) / g->width[axis]);
    if (g->periodic[axis]) {
        c %= g->ncell[axis];
        if (c < 0)
            c += g->ncell[axis];
    } else if (c < 0) {
        c = 0;
    } else if (c >= g->ncell[axis]) {
        c = g->ncell[axis] - 1;
    }
    return c;
}

static size_t cell_of(const grid *g, const double *x)
{
    size_t key = 0;
    for (int i = g->dim - 1; i >= 0; --i)
        key = key * (size_t)g->ncell[i] + (size_t)cell_coord(g, i, x[i]);
    return key;
}

/* Neighbouring cell coordinates along one axis, without repeats. */
static int axis_neighbours(const grid *g, int axis, long c, long out[3])
{
    int n = 0;
    for (long d = -1; d <= 1; ++d) {
        long k = c + d;
        if (g->periodic[axis]) {
            k = (k % g->ncell[axis] + g->ncell[axis]) % g->ncell[axis];
        } else if (k < 0 || k >= g->ncell[axis]) {
            continue;
        }
        int seen = 0;
        for (int j = 0; j < n; ++j)
            seen |= out[j] == k;
        if (!seen)
            out[n++] = k;
    }
    return n;
}

static int compare_int(const void *a, const void *b)
{
    const int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Visit the neighbours of particle a within rc that its row lists (b > a,
 * or b < a at least two chunks of `chunk` rows before a's); fill `out` if
 * not NULL.  Returns the count. */
static size_t scan(const sph_sim *sim, const grid *g, size_t a, double rc2, size_t chunk, int *out)
{
    const size_t ca = a / chunk;
    const size_t far_below = ca >= 1 ? (ca - 1) * chunk : 0; /* b < far_below: listed */
    const int dim = sim->dim;
    const double *xa = sim->x + a * (size_t)dim;
    long c[3] = {0, 0, 0}, nbr[3][3];
    int nn[3] = {1, 1, 1};
    for (int i = 0; i < dim; ++i) {
        c[i] = cell_coord(g, i, xa[i]);
        nn[i] = axis_neighbours(g, i, c[i], nbr[i]);
    }
    for (int i = dim; i < 3; ++i)
        nbr[i][0] = 0;
    size_t count = 0;
    for (int iz = 0; iz < nn[2]; ++iz)
        for (int iy = 0; iy < nn[1]; ++iy)
            for (int ix = 0; ix < nn[0]; ++ix) {
                size_t key = (size_t)nbr[0][ix];
                if (dim > 1)
                    key += (size_t)g->ncell[0] * (size_t)nbr[1][iy];
                if (dim > 2)
                    key += (size_t)g->ncell[0] * (size_t)g->ncell[1] * (size_t)nbr[2][iz];
                for (size_t m = g->start[key]; m < g->start[key + 1]; ++m) {
                    const size_t b = (size_t)g->members[m];
                    if (b == a || (b < a && b >= far_below))
                        continue;
                    const double *xb = sim->x + b * (size_t)dim;
                    double r2 = 0.0;
                    for (int i = 0; i < dim; ++i) {
                        double d = xa[i] - xb[i];
                        if (g->periodic[i])
                            d = nearest_image(d, g->box[i], 0.5 * g->box[i]);
                        r2 += d * d;
                    }
                    if (r2 < rc2) {
                        if (out)
                            out[count] = (int)b;
                        ++count;
                    }
                }
            }
    if (out)
        qsort(out, count, sizeof *out, compare_int);
    return count;
}

/* The cell grid's size in checked arithmetic: per-axis counts are computed
 * in floating point and the cells of a sparse cloud widened (doubled) until
 * the total is at most `limit`, so that no count is converted, multiplied
 * or allocated before it is known to fit.  Refuses positions that are not
 * finite and extents that overflow, naming the particle and the value. */
static sph_status grid_size(sph_sim *sim, grid *g, const double *lo, const double *hi,
                            const size_t *lo_at, const size_t *hi_at, double rc, size_t limit,
                            size_t *ncells)
{
    const int dim = sim->dim;
    double cells[3] = {1, 1, 1};
    for (int i = 0; i < dim; ++i) {
        if (g->periodic[i]) {
            g->box[i] = sim->hi[i] - sim->lo[i];
            g->lo[i] = sim->lo[i];
            cells[i] = fmax(1.0, floor(g->box[i] / rc));
            if (cells[i] > (double)limit)
                cells[i] = (double)limit;
            g->width[i] = g->box[i] / cells[i];
            continue;
        }
        const double extent = hi[i] - lo[i];
        if (!isfinite(extent))
            return sph_fail(sim, SPH_ERR_NONFINITE,
                            "particles %zu at %c=%g and %zu at %c=%g are too far apart for the "
                            "neighbour search (extent %g m)",
                            lo_at[i], "xyz"[i], lo[i], hi_at[i], "xyz"[i], hi[i], extent);
        g->lo[i] = lo[i];
        g->width[i] = rc;
        cells[i] = floor(extent / rc) + 1.0;
    }
    for (;;) {
        double total = 1.0;
        for (int i = 0; i < dim; ++i)
            total *= cells[i];
        if (total <= (double)limit)
            break;
        int widened = 0;
        for (int i = 0; i < dim; ++i)
            if (!g->periodic[i] && cells[i] > 1.0) {
                g->width[i] *= 2.0;
                cells[i] = floor((hi[i] - lo[i]) / g->width[i]) + 1.0;
                widened = 1;
            }
        if (!widened)
            return sph_fail(sim, SPH_ERR_MEMORY,
                            "the periodic domain needs %g cells, more than %zu", total, limit);
    }
    size_t product = 1;
    for (int i = 0; i < dim; ++i) {
        g->ncell[i] = (long)cells[i];
        product *= (size_t)g->ncell[i];
    }
    *ncells = product;
    return SPH_OK;
}

sph_status neighbour_build(sph_sim *sim)
{
    neighbour_list *nl = &sim->nl;
    const size_t n = sim->n;
    const int dim = sim->dim;
    const double rc = 2.0 * sim->h + nl->skin;
    grid g;
    memset(&g, 0, sizeof g);
    g.dim = dim;

    double lo[3], hi[3];
    size_t lo_at[3] = {0, 0, 0}, hi_at[3] = {0, 0, 0};
    for (int i = 0; i < dim; ++i) {
        lo[i] = INFINITY;
        hi[i] = -INFINITY;
    }
    for (size_t a = 0; a < n; ++a)
        for (int i = 0; i < dim; ++i) {
            const double xi = sim->x[a * dim + i];
            if (!isfinite(xi))
                return sph_fail(sim, SPH_ERR_NONFINITE,
                                "particle %zu (body '%s') has a non-finite position %c=%g", a,
                                sim->bodies[sim->body_of[a]].name, "xyz"[i], xi);
            if (xi < lo[i]) {
                lo[i] = xi;
                lo_at[i] = a;
            }
            if (xi > hi[i]) {
                hi[i] = xi;
                hi_at[i] = a;
            }
        }
    for (int i = 0; i < dim; ++i)
        g.periodic[i] = sim->has_domain && sim->periodic[i];
    /* Keep the grid at most about 2 cells per particle: widen the cells of a
     * sparse cloud (particles flying apart) rather than allocate empty ones. */
    size_t ncells = 1;
    sph_status st = grid_size(sim, &g, lo, hi, lo_at, hi_at, rc, 2 * n + 64, &ncells);
    if (st)
        return st;

    size_t *cell_index = malloc((n ? n : 1) * sizeof *cell_index);
    g.start = calloc(ncells + 1, sizeof *g.start);
    g.members = malloc((n ? n : 1) * sizeof *g.members);
    size_t *counts = malloc((n + 1) * sizeof *counts);
    if (!cell_index || !g.start || !g.members || !counts) {
        free(cell_index);
        free(g.start);
        free(g.members);
        free(counts);
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate the cell list (%zu cells)", ncells);
    }
    for (size_t a = 0; a < n; ++a) {
        cell_index[a] = cell_of(&g, sim->x + a * dim);
        g.start[cell_index[a] + 1]++;
    }
    for (size_t c = 0; c < ncells; ++c)
        g.start[c + 1] += g.start[c];
    {
        size_t *fill = malloc((ncells + 1) * sizeof *fill);
        if (!fill) {
            free(cell_index);
            free(g.start);
            free(g.members);
            free(counts);
            return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate the cell list (%zu cells)",
                            ncells);
        }
        memcpy(fill, g.start, (ncells + 1) * sizeof *fill);
        for (size_t a = 0; a < n; ++a)
            g.members[fill[cell_index[a]]++] = (int)a;
        free(fill);
    }
    free(cell_index);

    const double rc2 = rc * rc;
    const size_t chunk = rates_chunk_rows(dim, n);
    const long nl_n = (long)n;
    const int threads = sim_threads(sim);
    (void)threads; /* unused without OpenMP */
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long a = 0; a < nl_n; ++a)
        counts[a] = scan(sim, &g, (size_t)a, rc2, chunk, NULL);

    /* row starts in 32 bits when the entries allow it (4 bytes a particle
     * less), else in size_t */
    size_t total = 0;
    for (size_t a = 0; a < n; ++a)
        total += counts[a];
    const int narrow = total <= UINT32_MAX;
    void *starts = narrow ? realloc(nl->offsets32, (n + 1) * sizeof(uint32_t))
                          : realloc(nl->offsets, (n + 1) * sizeof(size_t));
    if (!starts) {
        free(g.start);
        free(g.members);
        free(counts);
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate neighbour offsets");
    }
    if (narrow) {
        nl->offsets32 = starts;
        free(nl->offsets);
        nl->offsets = NULL;
        nl->offsets32[0] = 0;
        for (size_t a = 0; a < n; ++a)
            nl->offsets32[a + 1] = nl->offsets32[a] + (uint32_t)counts[a];
    } else {
        nl->offsets = starts;
        free(nl->offsets32);
        nl->offsets32 = NULL;
        nl->offsets[0] = 0;
        for (size_t a = 0; a < n; ++a)
            nl->offsets[a + 1] = nl->offsets[a] + counts[a];
    }
    free(counts);
    if (total > nl->capacity || !nl->indices) {
        /* exact at the first build; room to grow on later ones */
        const size_t cap = nl->indices ? total + total / 16 + 16 : total;
        int *idx = realloc(nl->indices, cap * sizeof *idx);
        if (!idx) {
            free(g.start);
            free(g.members);
            return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %zu neighbour entries", cap);
        }
        nl->indices = idx;
        nl->capacity = cap;
    }
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long a = 0; a < nl_n; ++a)
        scan(sim, &g, (size_t)a, rc2, chunk, nl->indices + neighbour_row(nl, (size_t)a));
    free(g.start);
    free(g.members);
    nl->n = n;
    nl->chunk = chunk;
    nl->displacement_bound = 0.0;
    nl->valid = 1;
    return SPH_OK;
}

void neighbour_free(neighbour_list *nl)
{
    free(nl->offsets32);
    free(nl->offsets);
    free(nl->indices);
    memset(nl, 0, sizeof *nl);
}
