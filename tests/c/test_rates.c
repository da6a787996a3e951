/* Whole rate evaluations: velocity gradient exactness, Jaumann
 * objectivity, conservation of momentum and energy. */
#define _POSIX_C_SOURCE 200112L /* setenv */
#include "helpers.h"

#include "physics/kernel.h"
#include "core/sim.h"

typedef struct rates_buf {
    double *dv, *drho, *dS;
} rates_buf;

/* The simulation's own (half) list made full: each pair in both rows,
 * rows sorted (the entries b < a of the handle's list, the far pairs it
 * lists in both rows, are taken from the other row). */
static void full_list(const sph_sim *sim, size_t **offsets, int **indices)
{
    const size_t n = sim->n;
    size_t *off = calloc(n + 1, sizeof *off);
    for (size_t a = 0; a < n; ++a)
        for (size_t k = neighbour_row(&sim->nl, a); k < neighbour_row(&sim->nl, a + 1); ++k) {
            if ((size_t)sim->nl.indices[k] < a)
                continue;
            off[a + 1]++;
            off[(size_t)sim->nl.indices[k] + 1]++;
        }
    for (size_t a = 0; a < n; ++a)
        off[a + 1] += off[a];
    int *idx = malloc((off[n] + 1) * sizeof *idx);
    size_t *fill = malloc(n * sizeof *fill);
    memcpy(fill, off, n * sizeof *fill);
    for (size_t a = 0; a < n; ++a) /* a ascending: rows stay sorted */
        for (size_t k = neighbour_row(&sim->nl, a); k < neighbour_row(&sim->nl, a + 1); ++k) {
            const int b = sim->nl.indices[k];
            if ((size_t)b > a)
                idx[fill[b]++] = (int)a;
        }
    for (size_t a = 0; a < n; ++a)
        for (size_t k = neighbour_row(&sim->nl, a); k < neighbour_row(&sim->nl, a + 1); ++k)
            if ((size_t)sim->nl.indices[k] > a)
                idx[fill[a]++] = sim->nl.indices[k];
    free(fill);
    *offsets = off;
    *indices = idx;
}

/* The simulation's own list as a caller's half list: each pair once, in
 * the row of its smaller index (the second listing of its far pairs left
 * out). */
static sph_neighbours half_list(const sph_sim *sim, size_t **offsets, int **indices)
{
    const size_t n = sim->n;
    size_t *off = calloc(n + 1, sizeof *off);
    int *idx = malloc((neighbour_row(&sim->nl, n) + 1) * sizeof *idx);
    for (size_t a = 0; a < n; ++a) {
        off[a + 1] = off[a];
        for (size_t k = neighbour_row(&sim->nl, a); k < neighbour_row(&sim->nl, a + 1); ++k)
            if ((size_t)sim->nl.indices[k] > a)
                idx[off[a + 1]++] = sim->nl.indices[k];
    }
    *offsets = off;
    *indices = idx;
    return (sph_neighbours){.offsets = off, .indices = idx};
}

/* The handle's own particles as caller-owned ones (no ghosts). */
static sph_particles handle_particles(const sph_sim *sim)
{
    return (sph_particles){.n_local = sim->n,
                           .n_total = sim->n,
                           .x = sim->x,
                           .v = sim->v,
                           .rho = sim->rho,
                           .S = sim->S,
                           .mass = sim->mass,
                           .material = sim->material_of};
}

/* Evaluate the rates of the current state through the public low-level
 * entry point, with the full list made from the simulation's own. */
static rates_buf evaluate(sph_sim *sim)
{
    check(sim, sph_run(sim, 0));
    rates_buf r;
    const size_t n = sim->n;
    r.dv = calloc(n * sim->dim, sizeof(double));
    r.drho = calloc(n, sizeof(double));
    r.dS = calloc(n * sim->ncomp, sizeof(double));
    size_t *offsets;
    int *indices;
    full_list(sim, &offsets, &indices);
    sph_particles p = handle_particles(sim);
    sph_neighbours nb = {.offsets = offsets, .indices = indices};
    sph_rates out = {.dv_dt = r.dv, .drho_dt = r.drho, .dS_dt = r.dS};
    check(sim, sph_rates_evaluate(sim, &p, &nb, &out));
    free(offsets);
    free(indices);
    return r;
}

static void free_rates(rates_buf r)
{
    free(r.dv);
    free(r.drho);
    free(r.dS);
}

/* Expected 2D plane-strain stress rate for velocity gradient L (2x2) and
 * stress S = (xx, yy, zz, xy), written out from paper eqs (6)-(8). */
static void expected_stress_rate(double mu, const double L[2][2], const double *S, double *dS)
{
    const double exx = L[0][0], eyy = L[1][1], exy = 0.5 * (L[0][1] + L[1][0]);
    const double w = 0.5 * (L[0][1] - L[1][0]); /* Omega_xy = -Omega_yx */
    const double tr = exx + eyy;
    /* S Omega^T + Omega S with Omega = [[0, w], [-w, 0]] */
    dS[0] = 2 * mu * (exx - tr / 3) + 2 * w * S[3];
    dS[1] = 2 * mu * (eyy - tr / 3) - 2 * w * S[3];
    dS[2] = 2 * mu * (-tr / 3);
    dS[3] = 2 * mu * exy + w * (S[1] - S[0]);
}

/* Lattice moment m = sum_b V_b (x_b - x_a) dW/dx_a for an interior site
 * of a square lattice of spacing dx (kernel gradient checked in
 * test_kernel): the SPH gradient of a linear field on the lattice is m
 * times the exact one. */
static double lattice_moment(double dx, double h)
{
    const double norm = kernel_cubic_sigma(2) / pow(h, 4);
    double m = 0.0;
    for (int i = -3; i <= 3; ++i)
        for (int j = -3; j <= 3; ++j) {
            const double rx = -i * dx, ry = -j * dx; /* r_ab = x_a - x_b */
            const double r = sqrt(rx * rx + ry * ry);
            if (r == 0.0)
                continue;
            const double gx = kernel_cubic_f(2, r / h) * norm * rx;
            m += dx * dx * (-rx) * gx;
        }
    return m;
}

static void set_linear_field(sph_sim *sim, const double L[2][2], const double S0[4])
{
    double *x = field_ptr(sim, SPH_FIELD_POSITION), *v = field_ptr(sim, SPH_FIELD_VELOCITY);
    double *S = field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS);
    for (size_t a = 0; a < sph_particle_count(sim); ++a) {
        v[2 * a] = L[0][0] * x[2 * a] + L[0][1] * x[2 * a + 1] + 0.3;
        v[2 * a + 1] = L[1][0] * x[2 * a] + L[1][1] * x[2 * a + 1] - 0.1;
        memcpy(S + 4 * a, S0, 4 * sizeof(double));
    }
}

static void velocity_gradient_exact_for_linear_field(void **state)
{
    (void)state;
    const double dx = 1e-3;
    const double L[2][2] = {{3.0, -1.5}, {2.5, -0.7}}; /* 1/s, not symmetric */
    const double S0[4] = {1e5, -3e5, 2e5, 4e5};
    double expected[4], m_expected[4];
    expected_stress_rate(PAPER_MU, L, S0, expected);

    /* Without correction: interior particles see m L exactly. */
    sph_sim *sim = free_block_2d(24, 20, dx);
    set_linear_field(sim, L, S0);
    const double m = lattice_moment(dx, 1.2 * dx);
    const double Lm[2][2] = {{m * L[0][0], m * L[0][1]}, {m * L[1][0], m * L[1][1]}};
    expected_stress_rate(PAPER_MU, Lm, S0, m_expected);
    rates_buf r = evaluate(sim);
    int checked = 0;
    for (size_t a = 0; a < sim->n; ++a) {
        if (!interior(sim->x + 2 * a, 12 * dx, 10 * dx, 2.5 * dx))
            continue;
        for (int c = 0; c < 4; ++c)
            assert_close(r.dS[4 * a + c], m_expected[c], 1e-9 * PAPER_MU * 3.0, "interior dS/dt");
        ++checked;
    }
    assert_true(checked > 100);
    /* the lattice moment is close to one: the plain SPH gradient is
     * consistent to first order in the interior */
    assert_close(m, 1.0, 0.02, "lattice moment");
    free_rates(r);

    /* With kernel_correction: exact at every particle, edges included. */
    check(sim, sph_effect(sim, "kernel_correction", NULL));
    r = evaluate(sim);
    for (size_t a = 0; a < sim->n; ++a)
        for (int c = 0; c < 4; ++c)
            assert_close(r.dS[4 * a + c], expected[c], 1e-8 * PAPER_MU * 3.0, "corrected dS/dt");
    free_rates(r);
    sph_destroy(sim);
}

static void rigid_rotation_builds_no_stress(void **state)
{
    (void)state;
    const double dx = 1e-3, omega = 50.0; /* rad/s */
    const double L[2][2] = {{0.0, -omega}, {omega, 0.0}};
    const double zero[4] = {0, 0, 0, 0};
    sph_sim *sim = free_block_2d(20, 20, dx);
    set_linear_field(sim, L, zero);
    rates_buf r = evaluate(sim);
    const double scale = PAPER_MU * omega; /* a stress rate one rotation would build */
    for (size_t a = 0; a < sim->n; ++a) {
        assert_close(r.drho[a], 0.0, 1e-12 * PAPER_RHO0 * omega, "drho/dt under rotation");
        if (interior(sim->x + 2 * a, 10 * dx, 10 * dx, 2.5 * dx))
            for (int c = 0; c < 4; ++c)
                assert_close(r.dS[4 * a + c], 0.0, 1e-12 * scale, "interior dS/dt under rotation");
    }
    free_rates(r);
    /* with the gradient correction no particle builds stress */
    check(sim, sph_effect(sim, "kernel_correction", NULL));
    r = evaluate(sim);
    for (size_t a = 0; a < sim->n * 4; ++a)
        assert_close(r.dS[a], 0.0, 1e-10 * scale, "dS/dt under rotation, corrected");
    free_rates(r);
    sph_destroy(sim);
}

static void jaumann_rate_keeps_stress_magnitude_under_rotation(void **state)
{
    (void)state;
    const double dx = 1e-3, omega = 50.0;
    const double L[2][2] = {{0.0, -omega}, {omega, 0.0}};
    const double S0[4] = {2e6, -5e5, -1.5e6, 7e5};
    sph_sim *sim = free_block_2d(16, 16, dx);
    check(sim, sph_effect(sim, "kernel_correction", NULL));
    set_linear_field(sim, L, S0);
    rates_buf r = evaluate(sim);
    for (size_t a = 0; a < sim->n; ++a) {
        const double *dS = r.dS + 4 * a;
        /* d(S:S)/dt = 2 S:dS/dt = 0 for a co-rotating stress */
        const double dSS = 2 * (S0[0] * dS[0] + S0[1] * dS[1] + S0[2] * dS[2] + 2 * S0[3] * dS[3]);
        assert_close(dSS, 0.0, 1e-9 * 2e6 * 2e6 * omega, "d(S:S)/dt");
        /* and the rate is the rotation of S: dS_xy = omega (S_xx - S_yy) */
        assert_close(dS[3], omega * (S0[0] - S0[1]), 1e-9 * 2e6 * omega, "dS_xy/dt");
    }
    free_rates(r);
    sph_destroy(sim);
}

static double uniform(unsigned *seed)
{
    *seed = *seed * 1103515245u + 12345u;
    return ((*seed >> 8) & 0xffffff) / (double)0x1000000 - 0.5;
}

static void perturb(sph_sim *sim, unsigned seed)
{
    double *v = field_ptr(sim, SPH_FIELD_VELOCITY), *rho = field_ptr(sim, SPH_FIELD_DENSITY);
    double *S = field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS);
    for (size_t a = 0; a < sph_particle_count(sim); ++a) {
        v[2 * a] = 0.1 * uniform(&seed);
        v[2 * a + 1] = 0.1 * uniform(&seed);
        rho[a] = PAPER_RHO0 * (1.0 + 1e-4 * uniform(&seed));
        for (int c = 0; c < 4; ++c)
            S[4 * a + c] = 1e5 * uniform(&seed);
    }
}

static void momentum_of_isolated_body_is_conserved(void **state)
{
    (void)state;
    const char *effects[][2] = {{NULL, NULL},
                                {"artificial_viscosity", "alpha=1 beta=2"},
                                {"artificial_stress", "epsilon=0.3 n=4"},
                                {"artificial_stress", "epsilon=0.3 n=2.5"}};
    for (int k = 0; k < 4; ++k) {
        sph_sim *sim = free_block_2d(18, 14, 1e-3);
        if (effects[k][0])
            check(sim, sph_effect(sim, effects[k][0], effects[k][1]));
        perturb(sim, 7u + k);
        /* the pair forces cancel: sum m dv/dt = 0 to round-off */
        rates_buf r = evaluate(sim);
        double F[2] = {0, 0}, Fabs = 0;
        for (size_t a = 0; a < sim->n; ++a)
            for (int i = 0; i < 2; ++i) {
                F[i] += sim->mass[a] * r.dv[2 * a + i];
                Fabs += fabs(sim->mass[a] * r.dv[2 * a + i]);
            }
        free_rates(r);
        assert_close(F[0], 0.0, 1e-13 * Fabs, "total force x");
        assert_close(F[1], 0.0, 1e-13 * Fabs, "total force y");
        /* and over a run */
        sph_energy_info e0, e1;
        check(sim, sph_energy(sim, 1, &e0));
        check(sim, sph_run(sim, 200));
        check(sim, sph_energy(sim, 1, &e1));
        double pabs = 0;
        for (size_t a = 0; a < sim->n; ++a)
            pabs += sim->mass[a] * (fabs(sim->v[2 * a]) + fabs(sim->v[2 * a + 1]));
        assert_close(e1.momentum[0], e0.momentum[0], 1e-12 * pabs, "momentum x after 200 steps");
        assert_close(e1.momentum[1], e0.momentum[1], 1e-12 * pabs, "momentum y after 200 steps");
        sph_destroy(sim);
    }
}

/* The rates of the handle's own particles, copied out. */
static rates_buf handle_rates(sph_sim *sim)
{
    check(sim, sph_run(sim, 0));
    check(sim, rates_of_handle(sim, PASS_ALL));
    const size_t n = sim->n;
    rates_buf r = {malloc(2 * n * sizeof(double)), malloc(n * sizeof(double)),
                   malloc(4 * n * sizeof(double))};
    memcpy(r.dv, sim->dv_dt, 2 * n * sizeof(double));
    memcpy(r.drho, sim->drho_dt, n * sizeof(double));
    memcpy(r.dS, sim->dS_dt, 4 * n * sizeof(double));
    return r;
}

static double largest(const double *a, size_t n)
{
    double m = 0.0;
    for (size_t k = 0; k < n; ++k)
        m = fmax(m, fabs(a[k]));
    return m;
}

/* A block numbered at random: most of its pairs lie in chunks of the pair
 * pass at least two apart, which the handle's list holds in both rows, each
 * row adding its own particle's terms.  Its rates are those of the same
 * block numbered in lattice order (where few pairs are that far apart) to
 * round-off, particle by particle; bitwise those of a full list through the
 * public entry point; to round-off those of a half list (whose far terms are
 * stored and added after the pass), as partial sums or finished in one call
 * (sph_rates_pass_half); the pair forces cancel; 1 and 2 threads
 * agree bitwise. */
static void far_pairs_are_computed_in_both_rows(void **state)
{
    (void)state;
    const int nx = 40, ny = 30;
    const size_t n = (size_t)nx * (size_t)ny;
    const double dx = 1e-3;
    const char *effects[][2] = {{"kernel_correction", ""},
                                {"artificial_viscosity", "alpha=1 beta=2"},
                                {"artificial_stress", "epsilon=0.3 n=4"}};
    sph_sim *ref = free_block_2d(nx, ny, dx);
    for (int k = 0; k < 3; ++k)
        check(ref, sph_effect(ref, effects[k][0], effects[k][1]));
    perturb(ref, 17u);
    /* the same particles in a random order */
    size_t *perm = malloc(n * sizeof *perm);
    unsigned seed = 5u;
    for (size_t k = 0; k < n; ++k)
        perm[k] = k;
    for (size_t k = n - 1; k > 0; --k) {
        const size_t j = (size_t)(uniform(&seed) * (double)(k + 1)) % (k + 1);
        const size_t t = perm[k];
        perm[k] = perm[j];
        perm[j] = t;
    }
    double *pos = malloc(2 * n * sizeof *pos);
    for (size_t k = 0; k < n; ++k)
        memcpy(pos + 2 * k, ref->x + 2 * perm[k], 2 * sizeof(double));
    sph_sim *sim = new_sim(2);
    int mat, body;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    check(sim, sph_add_particles(sim, "shuffled", mat, n, pos, NULL, dx, &body));
    for (int k = 0; k < 3; ++k)
        check(sim, sph_effect(sim, effects[k][0], effects[k][1]));
    for (size_t k = 0; k < n; ++k) {
        const size_t a = perm[k];
        memcpy(sim->v + 2 * k, ref->v + 2 * a, 2 * sizeof(double));
        memcpy(sim->S + 4 * k, ref->S + 4 * a, 4 * sizeof(double));
        sim->rho[k] = ref->rho[a];
        assert_true(sim->mass[k] == ref->mass[a]);
    }
    check(sim, sph_set_threads(sim, 1));
    rates_buf one = handle_rates(sim);
    size_t twice = 0;
    for (size_t a = 0; a < n; ++a)
        for (size_t k = neighbour_row(&sim->nl, a); k < neighbour_row(&sim->nl, a + 1); ++k)
            twice += (size_t)sim->nl.indices[k] < a;
    assert_true(twice > neighbour_row(&sim->nl, n) / 4); /* most pairs are far */

    /* the lattice order, particle by particle */
    rates_buf lattice = handle_rates(ref);
    const double sv = largest(lattice.dv, 2 * n), sr = largest(lattice.drho, n),
                 sS = largest(lattice.dS, 4 * n);
    for (size_t k = 0; k < n; ++k) {
        const size_t a = perm[k];
        for (int i = 0; i < 2; ++i)
            assert_close(one.dv[2 * k + i], lattice.dv[2 * a + i], 1e-12 * sv, "dv/dt");
        assert_close(one.drho[k], lattice.drho[a], 1e-12 * sr, "drho/dt");
        for (int c = 0; c < 4; ++c)
            assert_close(one.dS[4 * k + c], lattice.dS[4 * a + c], 1e-12 * sS, "dS/dt");
    }
    /* the pair forces cancel */
    double F[2] = {0, 0}, Fabs = 0;
    for (size_t a = 0; a < n; ++a)
        for (int i = 0; i < 2; ++i) {
            F[i] += sim->mass[a] * one.dv[2 * a + i];
            Fabs += fabs(sim->mass[a] * one.dv[2 * a + i]);
        }
    assert_close(F[0], 0.0, 1e-13 * Fabs, "total force x");
    assert_close(F[1], 0.0, 1e-13 * Fabs, "total force y");
    /* a full list: bitwise */
    rates_buf full = evaluate(sim);
    assert_memory_equal(full.dv, one.dv, 2 * n * sizeof(double));
    assert_memory_equal(full.drho, one.drho, n * sizeof(double));
    assert_memory_equal(full.dS, one.dS, 4 * n * sizeof(double));
    /* a half list (far records): to round-off */
    size_t *half_offsets;
    int *half_indices;
    sph_neighbours half = half_list(sim, &half_offsets, &half_indices);
    sph_particles all = handle_particles(sim);
    double *partial = calloc(n * sph_rates_partial_size(sim), sizeof *partial);
    rates_buf h = {calloc(2 * n, sizeof(double)), calloc(n, sizeof(double)),
                   calloc(4 * n, sizeof(double))};
    sph_rates hr = {.dv_dt = h.dv, .drho_dt = h.drho, .dS_dt = h.dS};
    check(sim, sph_rates_pairs(sim, &all, &half, partial));
    check(sim, sph_rates_finish(sim, &all, partial, &hr));
    for (size_t k = 0; k < 2 * n; ++k)
        assert_close(h.dv[k], one.dv[k], 1e-12 * sv, "dv/dt, half list");
    for (size_t k = 0; k < 4 * n; ++k)
        assert_close(h.dS[k], one.dS[k], 1e-12 * sS, "dS/dt, half list");
    /* the half list finished in one call (sph_rates_pass_half): the same */
    check(sim, sph_rates_pass_half(sim, SPH_RATES_ALL, &all, &half, &hr));
    for (size_t k = 0; k < 2 * n; ++k)
        assert_close(h.dv[k], one.dv[k], 1e-12 * sv, "dv/dt, sph_rates_pass_half");
    for (size_t k = 0; k < n; ++k)
        assert_close(h.drho[k], one.drho[k], 1e-12 * sr, "drho/dt, sph_rates_pass_half");
    for (size_t k = 0; k < 4 * n; ++k)
        assert_close(h.dS[k], one.dS[k], 1e-12 * sS, "dS/dt, sph_rates_pass_half");
    /* 2 threads: bitwise */
    check(sim, sph_set_threads(sim, 2));
    rates_buf two = handle_rates(sim);
    assert_memory_equal(two.dv, one.dv, 2 * n * sizeof(double));
    assert_memory_equal(two.drho, one.drho, n * sizeof(double));
    assert_memory_equal(two.dS, one.dS, 4 * n * sizeof(double));
    free_rates(one);
    free_rates(two);
    free_rates(full);
    free_rates(h);
    free_rates(lattice);
    free(partial);
    free(half_offsets);
    free(half_indices);
    free(perm);
    free(pos);
    sph_destroy(sim);
    sph_destroy(ref);
}

/* The pair loop has the usual exponent n = 4 compiled in and takes any
 * other n through pow: n = 4 and n = 4 (1 + 1e-12) give the same rates to
 * a few 1e-12. */
/* The instruction-set paths of the pair loop (baseline, AVX2, AVX-512;
 * those the build and CPU have) add the same terms in the same order; they
 * may differ where the compiler fuses a multiply and an add (FMA), which
 * rounds once instead of twice: by a few units in the last place of the
 * terms, far below 1e-12 of each rate's largest value.  Each path gives
 * bitwise the same rates on 1, 2 and 3 threads. */
static void rate_paths_agree(void **state)
{
    (void)state;
    const int nx = 40, ny = 30;
    const size_t n = (size_t)nx * (size_t)ny;
    sph_sim *sim = free_block_2d(nx, ny, 1e-3);
    check(sim, sph_effect(sim, "kernel_correction", ""));
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=2"));
    check(sim, sph_effect(sim, "artificial_stress", "epsilon=0.3 n=4"));
    perturb(sim, 23u);
    sim->rate_path = RATE_PATH_BASELINE;
    check(sim, sph_set_threads(sim, 1));
    rates_buf base = handle_rates(sim);
    const double sv = largest(base.dv, 2 * n), sr = largest(base.drho, n),
                 sS = largest(base.dS, 4 * n);
    int paths = 0;
    for (int path = RATE_PATH_BASELINE; path <= RATE_PATH_AVX512; ++path) {
        if (rates_path(path) != path)
            continue; /* not in this build or on this CPU */
        paths++;
        sim->rate_path = path;
        check(sim, sph_set_threads(sim, 1));
        rates_buf one = handle_rates(sim);
        for (int threads = 2; threads <= 3; ++threads) {
            check(sim, sph_set_threads(sim, threads));
            rates_buf r = handle_rates(sim);
            assert_memory_equal(r.dv, one.dv, 2 * n * sizeof(double));
            assert_memory_equal(r.drho, one.drho, n * sizeof(double));
            assert_memory_equal(r.dS, one.dS, 4 * n * sizeof(double));
            free_rates(r);
        }
        for (size_t a = 0; a < n; ++a) {
            for (int i = 0; i < 2; ++i)
                assert_close(one.dv[2 * a + i], base.dv[2 * a + i], 1e-12 * sv, "dv/dt");
            assert_close(one.drho[a], base.drho[a], 1e-12 * sr, "drho/dt");
            for (int c = 0; c < 4; ++c)
                assert_close(one.dS[4 * a + c], base.dS[4 * a + c], 1e-12 * sS, "dS/dt");
        }
        free_rates(one);
    }
    assert_true(paths >= 1);
    free_rates(base);
    sph_destroy(sim);
}

/* In the handle's sorted rows, RUN consecutive neighbours (a lattice in
 * index order) are gathered as a run without the support test: a run's
 * pairs beyond 2h add exact zeros, so the rates are bitwise those of the
 * pair-by-pair gather, on every path.  At h = 1.5 dx the lattice's
 * neighbours at (3, 1) dx are listed (2h + skin = 3.375 dx) but beyond the
 * support (3.16 dx > 2h), inside the runs of 7 of the next row. */
static sph_sim *runs_scene(void)
{
    const int nx = 30, ny = 20;
    const double dx = 1e-3;
    const size_t n = (size_t)nx * (size_t)ny;
    sph_sim *sim = free_block_2d(nx, ny, dx);
    check(sim, sph_set_smoothing_ratio(sim, 1.5));
    check(sim, sph_effect(sim, "kernel_correction", ""));
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=2"));
    check(sim, sph_effect(sim, "artificial_stress", "epsilon=0.3 n=4"));
    check(sim, sph_effect(sim, "xsph", "epsilon=0.5"));
    perturb(sim, 31u);
    unsigned seed = 5u;
    double *x = field_ptr(sim, SPH_FIELD_POSITION);
    for (size_t k = 0; k < 2 * n; ++k)
        x[k] += 0.02 * dx * uniform(&seed);
    check(sim, sph_run(sim, 0));
    return sim;
}

static void runs_keep_the_bits(void **state)
{
    (void)state;
    sph_sim *sim = runs_scene();
    const size_t n = sim->n;
    const double *x = field_ptr(sim, SPH_FIELD_POSITION); /* the run may have moved them */
    /* listed pairs beyond the support, in runs of 4 consecutive indices */
    const double h = sph_smoothing_length(sim);
    size_t beyond = 0;
    for (size_t a = 0; a < n; ++a)
        for (uint32_t k = sim->nl.offsets32[a]; k < sim->nl.offsets32[a + 1]; ++k) {
            const size_t b = (size_t)sim->nl.indices[k];
            const double r2 = (x[2 * a] - x[2 * b]) * (x[2 * a] - x[2 * b]) +
                              (x[2 * a + 1] - x[2 * b + 1]) * (x[2 * a + 1] - x[2 * b + 1]);
            beyond += r2 > 4.0 * h * h && k + 1 < sim->nl.offsets32[a + 1] &&
                      (size_t)sim->nl.indices[k + 1] == b + 1;
        }
    assert_true(beyond > n / 2);
    for (int path = RATE_PATH_BASELINE; path <= RATE_PATH_AVX512; ++path) {
        if (rates_path(path) != path)
            continue;
        sim->rate_path = path;
        sim->no_runs = 1;
        rates_buf single = handle_rates(sim);
        double *u_single = malloc(2 * n * sizeof(double));
        memcpy(u_single, sim->dx_dt, 2 * n * sizeof(double));
        sim->no_runs = 0;
        rates_buf runs = handle_rates(sim);
        assert_memory_equal(runs.dv, single.dv, 2 * n * sizeof(double));
        assert_memory_equal(runs.drho, single.drho, n * sizeof(double));
        assert_memory_equal(runs.dS, single.dS, 4 * n * sizeof(double));
        assert_memory_equal(sim->dx_dt, u_single, 2 * n * sizeof(double));
        free(u_single);
        free_rates(single);
        free_rates(runs);
    }
    sph_destroy(sim);
}

/* sph_rates_pass_half's rates of every particle in one array: dv/dt,
 * drho/dt, dS/dt and the XSPH velocity (9 doubles per particle in 2D). */
static double *half_rates(sph_sim *sim, const sph_particles *p, const sph_neighbours *nb)
{
    const size_t n = p->n_local;
    double *r = calloc(9 * n, sizeof *r);
    sph_rates out = {.dv_dt = r, .drho_dt = r + 2 * n, .dS_dt = r + 3 * n, .dx_dt = r + 7 * n};
    check(sim, sph_rates_pass_half(sim, SPH_RATES_ALL, p, nb, &out));
    return r;
}

/* A caller's half list takes the runs where its rows are ascending,
 * which each call tests.  Sorted rows give the pair-by-pair gather's bits,
 * with the positions dim doubles apart and with LAMMPS's 2D stride of 3
 * (copied dim apart for the pass); rows where an entry between a run's
 * first and fourth is swapped with another of the row (the fourth still
 * three above the first: not a run) are gathered pair by pair, bitwise
 * again.  Both forms of sph_neighbours. */
static void caller_rows_take_runs_when_sorted(void **state)
{
    (void)state;
    sph_sim *sim = runs_scene();
    const size_t n = sim->n;
    size_t *off;
    int *idx;
    const sph_neighbours sorted = half_list(sim, &off, &idx);
    int *mixed = malloc((off[n] + 1) * sizeof *mixed);
    memcpy(mixed, idx, off[n] * sizeof *mixed);
    size_t swapped = 0;
    for (size_t a = 0; a < n; ++a)
        for (size_t i = off[a]; i + 3 < off[a + 1]; ++i)
            if (mixed[i + 3] == mixed[i] + 3 && off[a + 1] - off[a] > 4) {
                const size_t j = i + 4 < off[a + 1] ? i + 4 : i - 1;
                const int t = mixed[i + 1];
                mixed[i + 1] = mixed[j];
                mixed[j] = t;
                ++swapped;
                break;
            }
    assert_true(swapped > n / 2);
    const int **lists = malloc(n * sizeof *lists);
    int *counts = malloc(n * sizeof *counts);
    for (size_t a = 0; a < n; ++a) {
        lists[a] = mixed + off[a];
        counts[a] = (int)(off[a + 1] - off[a]);
    }
    const sph_neighbours mixed_rows = {.offsets = off, .indices = mixed};
    const sph_neighbours mixed_lists = {.lists = lists, .counts = counts};
    sph_particles p2 = handle_particles(sim), p3 = p2;
    double *x3 = calloc(3 * n, sizeof *x3), *v3 = calloc(3 * n, sizeof *v3);
    for (size_t a = 0; a < n; ++a)
        for (int i = 0; i < 2; ++i) {
            x3[3 * a + i] = sim->x[2 * a + i];
            v3[3 * a + i] = sim->v[2 * a + i];
        }
    p3.x = x3;
    p3.v = v3;
    p3.stride = 3;
    const size_t bytes = 9 * n * sizeof(double);
    for (int path = RATE_PATH_BASELINE; path <= RATE_PATH_AVX512; ++path) {
        if (rates_path(path) != path)
            continue;
        sim->rate_path = path;
        sim->no_runs = 1;
        double *single = half_rates(sim, &p2, &sorted);
        double *single_mixed = half_rates(sim, &p2, &mixed_rows);
        sim->no_runs = 0;
        double *runs2 = half_rates(sim, &p2, &sorted);
        double *runs3 = half_rates(sim, &p3, &sorted);
        double *mixed3 = half_rates(sim, &p3, &mixed_rows);
        double *mixed_l = half_rates(sim, &p3, &mixed_lists);
        assert_memory_equal(runs2, single, bytes);
        assert_memory_equal(runs3, single, bytes);
        assert_memory_equal(mixed3, single_mixed, bytes);
        assert_memory_equal(mixed_l, single_mixed, bytes);
        free(single);
        free(single_mixed);
        free(runs2);
        free(runs3);
        free(mixed3);
        free(mixed_l);
    }
    free(x3);
    free(v3);
    free(lists);
    free(counts);
    free(mixed);
    free(off);
    free(idx);
    sph_destroy(sim);
}

/* In 3D a caller's positions and velocities more than 3 doubles apart
 * (here 4, the fourth a NaN the pass must not read) are copied 3 apart for
 * the pass, as in 2D: the rates are bitwise those of the dense arrays, on
 * every path.  A perturbed, moving block, so that every component of x and
 * v enters the rates. */
static void wider_stride_in_3d_keeps_the_bits(void **state)
{
    (void)state;
    const double dx = 1e-3;
    sph_sim *sim = free_block(6, 5, 4, dx);
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=2"));
    check(sim, sph_effect(sim, "xsph", "epsilon=0.5"));
    const size_t n = sph_particle_count(sim);
    double *x = field_ptr(sim, SPH_FIELD_POSITION), *v = field_ptr(sim, SPH_FIELD_VELOCITY);
    double *rho = field_ptr(sim, SPH_FIELD_DENSITY);
    double *S = field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS);
    unsigned seed = 7u;
    for (size_t a = 0; a < n; ++a) {
        for (int i = 0; i < 3; ++i) {
            x[3 * a + i] += 0.02 * dx * uniform(&seed);
            v[3 * a + i] = 0.1 * uniform(&seed);
        }
        rho[a] = PAPER_RHO0 * (1.0 + 1e-4 * uniform(&seed));
        for (int c = 0; c < 6; ++c)
            S[6 * a + c] = 1e5 * uniform(&seed);
    }
    check(sim, sph_run(sim, 0));
    size_t *off;
    int *idx;
    const sph_neighbours nb = half_list(sim, &off, &idx);
    sph_particles p3 = handle_particles(sim), p4 = p3;
    double *x4 = malloc(4 * n * sizeof *x4), *v4 = malloc(4 * n * sizeof *v4);
    for (size_t a = 0; a < n; ++a) {
        for (int i = 0; i < 3; ++i) {
            x4[4 * a + i] = sim->x[3 * a + i];
            v4[4 * a + i] = sim->v[3 * a + i];
        }
        x4[4 * a + 3] = v4[4 * a + 3] = NAN;
    }
    p4.x = x4;
    p4.v = v4;
    p4.stride = 4;
    const size_t per = 3 + 1 + 6 + 3, bytes = per * n * sizeof(double);
    double *dense = calloc(per * n, sizeof *dense), *wide = calloc(per * n, sizeof *wide);
    for (int path = RATE_PATH_BASELINE; path <= RATE_PATH_AVX512; ++path) {
        if (rates_path(path) != path)
            continue;
        sim->rate_path = path;
        const struct {
            const sph_particles *p;
            double *r;
        } runs[2] = {{&p3, dense}, {&p4, wide}};
        for (int k = 0; k < 2; ++k) {
            double *r = runs[k].r;
            sph_rates out = {
                .dv_dt = r, .drho_dt = r + 3 * n, .dS_dt = r + 4 * n, .dx_dt = r + 10 * n};
            check(sim, sph_rates_pass_half(sim, SPH_RATES_ALL, runs[k].p, &nb, &out));
        }
        assert_memory_equal(wide, dense, bytes);
        double largest = 0.0;
        for (size_t k = 0; k < 3 * n; ++k)
            largest = fmax(largest, fabs(dense[k]));
        assert_true(largest > 0.0);
    }
    free(dense);
    free(wide);
    free(x4);
    free(v4);
    free(off);
    free(idx);
    sph_destroy(sim);
}

/* The row test of a caller's list agrees with a row-by-row check on random
 * lists: rows empty or not, sorted or with one pair swapped or repeated,
 * offsets that start past the array's first entry, and the lists+counts
 * form.  A row's descent at its start (where the previous row ends
 * higher) is no descent of the row. */
static void row_test_matches_each_row(void **state)
{
    (void)state;
    unsigned seed = 11u;
    int ascending = 0, unsorted = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const size_t n_rows = (size_t)((uniform(&seed) + 0.5) * 12.0), base = trial % 3;
        size_t off[13];
        int idx[3 + 12 * 8] = {7, -1, 3}, *lists[12], counts[12];
        off[0] = base;
        int expect = 1;
        for (size_t a = 0; a < n_rows; ++a) {
            const int len = (int)((uniform(&seed) + 0.5) * 8.0);
            int *row = idx + off[a], v = (int)((uniform(&seed) + 0.5) * 20.0);
            for (int k = 0; k < len; ++k) {
                row[k] = v;
                v += 1 + (int)((uniform(&seed) + 0.5) * 3.0);
            }
            const double what = (uniform(&seed) + 0.5);
            if (len >= 2 && what < 0.1) { /* two neighbours swapped */
                const int k = (int)((uniform(&seed) + 0.5) * (len - 1));
                const int t = row[k];
                row[k] = row[k + 1];
                row[k + 1] = t;
            } else if (len >= 2 && what < 0.15) { /* one repeated */
                const int k = (int)((uniform(&seed) + 0.5) * (len - 1));
                row[k + 1] = row[k];
            }
            for (int k = 1; k < len; ++k)
                expect &= row[k] > row[k - 1];
            off[a + 1] = off[a] + (size_t)len;
            lists[a] = row;
            counts[a] = len;
        }
        const sph_neighbours csr = {.offsets = off, .indices = idx};
        const sph_neighbours per_row = {.lists = (const int *const *)lists, .counts = counts};
        assert_int_equal(rates_rows_ascending(n_rows, &csr, 1), expect);
        assert_int_equal(rates_rows_ascending(n_rows, &per_row, 1), expect);
        ascending += expect;
        unsorted += !expect;
    }
    assert_true(ascending > 1000 && unsorted > 1000);

    /* a long list, counted in blocks of 2^16 entries on 1 and 3 threads:
     * rows of 5 that each start below the last one's end; then one descent
     * inside a row, at the first entry of the second block */
    const size_t rows = 50000, len = 5;
    size_t *off = malloc((rows + 1) * sizeof *off);
    int *idx = malloc(rows * len * sizeof *idx);
    for (size_t a = 0; a <= rows; ++a)
        off[a] = a * len;
    for (size_t k = 0; k < rows * len; ++k)
        idx[k] = (int)(k % len);
    const sph_neighbours long_list = {.offsets = off, .indices = idx};
    for (int threads = 1; threads <= 3; threads += 2)
        assert_int_equal(rates_rows_ascending(rows, &long_list, threads), 1);
    const size_t k = (size_t)1 << 16; /* inside a row: k % 5 == 1 */
    assert_true(k % len != 0);
    idx[k] = idx[k - 1];
    for (int threads = 1; threads <= 3; threads += 2)
        assert_int_equal(rates_rows_ascending(rows, &long_list, threads), 0);
    free(off);
    free(idx);
}

/* One process's particles (n_local owned, then ghosts) for the split-pass
 * tests. */
static sph_particles process_particles(size_t n_local, size_t n_total, const double *x,
                                       const double *v, const double *rho, const double *S,
                                       const double *mass, const int *material)
{
    return (sph_particles){.n_local = n_local,
                           .n_total = n_total,
                           .x = x,
                           .v = v,
                           .rho = rho,
                           .S = S,
                           .mass = mass,
                           .material = material};
}

/* A public call's particle check on an array long enough to count on the
 * pair pass's threads names the first wrong particle. */
static void particle_check_names_the_particle(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(4, 4, 1e-3);
    check(sim, sph_run(sim, 0));
    check(sim, sph_set_threads(sim, 3));
    const size_t n = 30000;
    double *x = calloc(2 * n, sizeof *x), *v = calloc(2 * n, sizeof *v);
    double *rho = malloc(n * sizeof *rho), *S = calloc(4 * n, sizeof *S);
    double *mass = malloc(n * sizeof *mass), *out = calloc(9 * n, sizeof *out);
    int *material = calloc(n, sizeof *material), index = 0;
    size_t *off = calloc(n + 1, sizeof *off);
    for (size_t a = 0; a < n; ++a) {
        rho[a] = 2300.0;
        mass[a] = 1e-3;
    }
    material[25000] = 7;
    material[26000] = -1;
    const sph_particles p = process_particles(n, n, x, v, rho, S, mass, material);
    const sph_neighbours nb = {.offsets = off, .indices = &index};
    sph_rates r = {
        .dv_dt = out, .drho_dt = out + 2 * n, .dS_dt = out + 3 * n, .dx_dt = out + 7 * n};
    assert_int_equal(sph_rates_pass_half(sim, SPH_RATES_ALL, &p, &nb, &r), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "particle 25000 has material 7"));
    material[25000] = 0;
    material[26000] = 0;
    rho[29999] = -1.0;
    assert_int_equal(sph_rates_pass_half(sim, SPH_RATES_ALL, &p, &nb, &r), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "particle 29999 has density rho=-1"));
    rho[29999] = 2300.0;
    check(sim, sph_rates_pass_half(sim, SPH_RATES_ALL, &p, &nb, &r));
    free(x);
    free(v);
    free(rho);
    free(S);
    free(mass);
    free(out);
    free(material);
    free(off);
    sph_destroy(sim);
}

/* SPHSOLID_RATE_PATH picks the path of every handle created while it is
 * set: a path the build and CPU have is taken (the baseline always is),
 * and a name that is not a path, or a path they lack, fails sph_create
 * with the value named; the handle then refuses to run. */
static void rate_path_from_the_environment(void **state)
{
    (void)state;
    sph_sim *sim = NULL;
    assert_int_equal(setenv("SPHSOLID_RATE_PATH", "baseline", 1), 0);
    assert_int_equal(sph_create(2, &sim), SPH_OK);
    assert_int_equal(sim->rate_path, RATE_PATH_BASELINE);
    sph_destroy(sim);
    assert_int_equal(setenv("SPHSOLID_RATE_PATH", "sse9", 1), 0);
    assert_int_equal(sph_create(2, &sim), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "SPHSOLID_RATE_PATH='sse9'"));
    sph_destroy(sim);
    if (rates_path(RATE_PATH_AUTO) < RATE_PATH_AVX512) { /* a path this CPU lacks */
        assert_int_equal(setenv("SPHSOLID_RATE_PATH", "avx512", 1), 0);
        assert_int_equal(sph_create(3, &sim), SPH_ERR_ARGUMENT);
        assert_non_null(strstr(sph_errmsg(sim), "no wider path than"));
        sph_destroy(sim);
    } else {
        assert_int_equal(setenv("SPHSOLID_RATE_PATH", "avx512", 1), 0);
        assert_int_equal(sph_create(3, &sim), SPH_OK);
        assert_int_equal(sim->rate_path, RATE_PATH_AVX512);
        sph_destroy(sim);
    }
    assert_int_equal(unsetenv("SPHSOLID_RATE_PATH"), 0);
    assert_int_equal(sph_create(2, &sim), SPH_OK);
    assert_int_equal(sim->rate_path, RATE_PATH_AUTO);
    sph_destroy(sim);
}

/* ------------------------------------------- pair terms: one-sided forms */

/* A block of pairs (a, b_k) with random inputs, seen from a. */
static pair_block random_block(int dim, unsigned seed)
{
    pair_block p;
    memset(&p, 0, sizeof p);
    p.n = 7;
    const double m_a = 1.0 + uniform(&seed), V_a = 1e-3 * (1.0 + uniform(&seed));
    for (int k = 0; k < p.n; ++k) {
        p.m_a[k] = m_a;
        p.V_a[k] = V_a;
        const double F = -1.0 - uniform(&seed); /* W'(r)/r < 0 */
        p.r2[k] = 0.0;
        for (int i = 0; i < dim; ++i) {
            p.r[i][k] = uniform(&seed);
            p.v[i][k] = uniform(&seed);
            p.r2[k] += p.r[i][k] * p.r[i][k];
            p.gW[i][k] = F * p.r[i][k];
        }
        p.W[k] = 0.5 + uniform(&seed);
        p.m_b[k] = 1.0 + uniform(&seed);
        p.V_b[k] = 1e-3 * (1.0 + uniform(&seed));
        p.rho_mean[k] = 2000.0 + 100.0 * uniform(&seed);
        p.c_mean[k] = 3000.0 + 100.0 * uniform(&seed);
        for (int c = 0; c < 6; ++c) {
            p.T[c][k] = uniform(&seed);
            p.R[c][k] = -0.5 + uniform(&seed); /* tension: R < 0 */
        }
    }
    return p;
}

/* Pair k of p seen from b: a and b swapped, r, v and grad W negated; the
 * symmetric pair factors (T, R, means) the same. */
static pair_block mirrored(int dim, const pair_block *p, int k)
{
    pair_block m;
    memset(&m, 0, sizeof m);
    m.n = 1;
    m.m_a[0] = p->m_b[k];
    m.V_a[0] = p->V_b[k];
    m.m_b[0] = p->m_a[k];
    m.V_b[0] = p->V_a[k];
    for (int i = 0; i < dim; ++i) {
        m.r[i][0] = -p->r[i][k];
        m.v[i][0] = -p->v[i][k];
        m.gW[i][0] = -p->gW[i][k];
    }
    m.r2[0] = p->r2[k];
    m.W[0] = p->W[k];
    m.rho_mean[0] = p->rho_mean[k];
    m.c_mean[0] = p->c_mean[k];
    for (int c = 0; c < 6; ++c) {
        m.T[c][0] = p->T[c][k];
        m.R[c][0] = p->R[c][k];
    }
    return m;
}

/* The pair terms, each as the pair pass calls it (the effects on the pair
 * tensor followed by the momentum term they act through). */
typedef void (*term_call)(int dim, pair_block *p, pair_rows *ta, pair_rows *tb);
static void call_continuity(int dim, pair_block *p, pair_rows *ta, pair_rows *tb)
{
    continuity_term(dim, p, ta, tb);
}
static void call_velocity_gradient(int dim, pair_block *p, pair_rows *ta, pair_rows *tb)
{
    velocity_gradient_term(dim, p, ta, tb);
}
static void call_momentum(int dim, pair_block *p, pair_rows *ta, pair_rows *tb)
{
    momentum_term(dim, p, ta, tb);
}
static void call_viscosity(int dim, pair_block *p, pair_rows *ta, pair_rows *tb)
{
    artificial_viscosity_term(dim, 1.0, 2.0, 0.3, p);
    momentum_term(dim, p, ta, tb);
}
static void call_stress(int dim, pair_block *p, pair_rows *ta, pair_rows *tb)
{
    artificial_stress_term(dim, 1.3, 4.0, p);
    momentum_term(dim, p, ta, tb);
}
static void call_stress_pow(int dim, pair_block *p, pair_rows *ta, pair_rows *tb)
{
    artificial_stress_term(dim, 1.3, 2.5, p);
    momentum_term(dim, p, ta, tb);
}
static void call_xsph(int dim, pair_block *p, pair_rows *ta, pair_rows *tb)
{
    xsph_term(dim, 0.5, p, ta, tb);
}
static void call_correction(int dim, pair_block *p, pair_rows *ta, pair_rows *tb)
{
    correction_moment_term(dim, p, ta, tb);
}

/* The symmetric form (one call per pair, terms for a and b) against the
 * one-sided form (the pair computed from b's side): b's terms bitwise
 * equal, and a's. */
static void check_one_sided(const char *name, term_call call, int components2, int components3)
{
    for (int dim = 2; dim <= 3; ++dim) {
        const int nc = dim == 2 ? components2 : components3;
        const pair_block p = random_block(dim, 11u + (unsigned)dim);
        pair_block q = p;
        pair_rows ta[9], tb[9];
        call(dim, &q, ta, tb);
        for (int k = 0; k < p.n; ++k) {
            pair_block m = mirrored(dim, &p, k);
            pair_rows ma[9], mb[9];
            call(dim, &m, ma, mb);
            for (int c = 0; c < nc; ++c)
                if (memcmp(&ma[c][0], &tb[c][k], sizeof(double)) ||
                    memcmp(&mb[c][0], &ta[c][k], sizeof(double)))
                    fail_msg("%s, %dD, pair %d, component %d: b's term %.17g one-sided %.17g, "
                             "a's %.17g one-sided %.17g",
                             name, dim, k, c, tb[c][k], ma[c][0], ta[c][k], mb[c][0]);
        }
    }
}

static void one_sided_continuity(void **state)
{
    (void)state;
    check_one_sided("continuity", call_continuity, 1, 1);
}
static void one_sided_velocity_gradient(void **state)
{
    (void)state;
    check_one_sided("velocity gradient", call_velocity_gradient, 4, 9);
}
static void one_sided_momentum(void **state)
{
    (void)state;
    check_one_sided("momentum", call_momentum, 2, 3);
}
static void one_sided_artificial_viscosity(void **state)
{
    (void)state;
    check_one_sided("artificial viscosity", call_viscosity, 2, 3);
}
static void one_sided_artificial_stress(void **state)
{
    (void)state;
    check_one_sided("artificial stress (n = 4)", call_stress, 2, 3);
    check_one_sided("artificial stress (n = 2.5)", call_stress_pow, 2, 3);
}
static void one_sided_xsph(void **state)
{
    (void)state;
    check_one_sided("xsph", call_xsph, 2, 3);
}
static void one_sided_correction_moment(void **state)
{
    (void)state;
    check_one_sided("kernel-correction moment", call_correction, 3, 6);
}

/* The pair-tensor effects push a pair apart (Monaghan 1992; Gray et al.
 * 2001): viscosity when approaching, artificial stress in tension.  With
 * either on, a's momentum term gains a part along r_ab = x_a - x_b. */
static void pair_tensor_effects_repel(void **state)
{
    (void)state;
    for (int dim = 2; dim <= 3; ++dim)
        for (int effect = 0; effect < 2; ++effect) {
            pair_block p = random_block(dim, 3u);
            for (int k = 0; k < p.n; ++k) { /* approaching: v_ab = -r_ab */
                for (int i = 0; i < dim; ++i)
                    p.v[i][k] = -p.r[i][k];
                for (int c = 0; c < 6; ++c)
                    p.R[c][k] = c < dim ? -0.25 : 0.0; /* tension in every direction */
            }
            pair_block q = p;
            pair_rows ta0[3], tb0[3], ta[3], tb[3];
            momentum_term(dim, &p, ta0, tb0);
            if (effect == 0)
                artificial_viscosity_term(dim, 1.0, 0.0, 0.3, &q);
            else
                artificial_stress_term(dim, 1.3, 4.0, &q);
            momentum_term(dim, &q, ta, tb);
            for (int k = 0; k < p.n; ++k) {
                double push = 0.0;
                for (int i = 0; i < dim; ++i)
                    push += (ta[i][k] - ta0[i][k]) * p.r[i][k];
                if (!(push > 0.0))
                    fail_msg("%s, %dD, pair %d: push along r_ab %g, not > 0",
                             effect ? "artificial stress" : "artificial viscosity", dim, k, push);
            }
        }
}

static void artificial_stress_exponent_paths_agree(void **state)
{
    (void)state;
    rates_buf r[2];
    const char *params[2] = {"epsilon=0.3 n=4", "epsilon=0.3 n=4.000000000004"};
    for (int k = 0; k < 2; ++k) {
        sph_sim *sim = free_block_2d(12, 10, 1e-3);
        check(sim, sph_effect(sim, "artificial_stress", params[k]));
        perturb(sim, 11u);
        r[k] = evaluate(sim);
        sph_destroy(sim);
    }
    double scale = 0.0, diff = 0.0;
    for (size_t a = 0; a < 120 * 2; ++a) {
        scale = fmax(scale, fabs(r[0].dv[a]));
        diff = fmax(diff, fabs(r[0].dv[a] - r[1].dv[a]));
    }
    assert_true(scale > 0.0);
    assert_close(diff / scale, 0.0, 1e-10, "dv/dt of the two artificial stress paths");
    free_rates(r[0]);
    free_rates(r[1]);
}

/* Artificial stress needs a kernel that is non-negative over its support:
 * sph_kernel_negative_from finds the sign change of each kernel's values
 * (sph_kernel_values) in 2D and 3D, and a run with the effect and a kernel
 * that changes sign stops before its first step with an error naming
 * both; with a non-negative kernel it runs. */
static void artificial_stress_needs_a_non_negative_kernel(void **state)
{
    (void)state;
    int refused = 0;
    for (int kernel = 0; sph_kernel_name((sph_kernel)kernel); ++kernel)
        for (int dim = 2; dim <= 3; ++dim) {
            const double q0 = sph_kernel_negative_from((sph_kernel)kernel, dim);
            sph_sim *sim = new_sim(dim);
            check(sim, sph_set_kernel(sim, (sph_kernel)kernel));
            /* the kernel's values on a fine grid over its support (2h) */
            enum { N = 4001 };
            double *q = malloc(N * sizeof *q), *w = malloc(N * sizeof *w);
            for (int i = 0; i < N; ++i)
                q[i] = 2.0 * i / (N - 1);
            check(sim, sph_kernel_values(sim, N, q, w, NULL));
            int first = -1;
            for (int i = 0; i < N && first < 0; ++i)
                if (w[i] < 0.0)
                    first = i;
            if (first < 0) {
                assert_true(q0 == 0.0);
            } else {
                /* the sign change lies between the grid's last non-negative
                 * point and its first negative one, and w changes sign there */
                assert_true(q0 > q[first - 1] && q0 <= q[first]);
                double at[2] = {q0 * (1.0 - 1e-9), q0 * (1.0 + 1e-9)}, wv[2];
                check(sim, sph_kernel_values(sim, 2, at, wv, NULL));
                assert_true(wv[0] >= 0.0 && wv[1] < 0.0);
            }
            free(q);
            free(w);
            sph_destroy(sim);
            if (dim == 3)
                continue;
            sim = free_block_2d(8, 6, 1e-3);
            check(sim, sph_set_kernel(sim, (sph_kernel)kernel));
            check(sim, sph_effect(sim, "artificial_stress", "epsilon=0.3 n=4"));
            const sph_status st = sph_run(sim, 1);
            if (q0 > 0.0) {
                ++refused;
                assert_int_equal(st, SPH_ERR_ARGUMENT);
                assert_non_null(strstr(sph_errmsg(sim), "artificial_stress"));
                assert_non_null(strstr(sph_errmsg(sim), sph_kernel_name((sph_kernel)kernel)));
                assert_int_equal(sph_step_count(sim), 0);
            } else {
                check(sim, st);
            }
            sph_destroy(sim);
        }
    assert_true(refused > 0); /* cubic_o4 changes sign past q = 0.91 */
    assert_true(sph_kernel_negative_from((sph_kernel)99, 2) < 0.0);
    assert_true(sph_kernel_negative_from(SPH_KERNEL_CUBIC_SPLINE, 4) < 0.0);
}

/* The low-level entry points on arrays 3 doubles apart (LAMMPS's layout in
 * 2D) give the rates and Improved Euler stages of the dense arrays, to the
 * bit; the strided stages leave the x and v of prescribed particles to the
 * caller, and their corrector applies the watchdog. */
static void strided_entry_points_match_the_dense_ones(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(8, 6, 1e-3);
    perturb(sim, 5u);
    check(sim, sph_run(sim, 0));
    const size_t n = sim->n;
    double *x3 = calloc(3 * n, sizeof *x3), *v3 = calloc(3 * n, sizeof *v3);
    for (size_t a = 0; a < n; ++a)
        for (int i = 0; i < 2; ++i) {
            x3[3 * a + i] = sim->x[2 * a + i];
            v3[3 * a + i] = sim->v[2 * a + i];
        }
    rates_buf dense = evaluate(sim);
    double *dv = calloc(2 * n, sizeof *dv), *drho = calloc(n, sizeof *drho),
           *dS = calloc(4 * n, sizeof *dS);
    size_t *offsets;
    int *indices;
    full_list(sim, &offsets, &indices);
    sph_particles p = {.n_local = n,
                       .n_total = n,
                       .x = x3,
                       .v = v3,
                       .rho = sim->rho,
                       .S = sim->S,
                       .mass = sim->mass,
                       .material = sim->material_of,
                       .stride = 3};
    sph_neighbours nb = {.offsets = offsets, .indices = indices};
    sph_rates r3 = {dv, drho, dS, NULL};
    check(sim, sph_rates_evaluate(sim, &p, &nb, &r3));
    assert_memory_equal(dv, dense.dv, 2 * n * sizeof *dv);
    assert_memory_equal(dS, dense.dS, 4 * n * sizeof *dS);

    /* stages: particle 0 prescribed (another code moves it) */
    unsigned char *integrate = malloc(n);
    memset(integrate, 1, n);
    integrate[0] = 0;
    double *x2 = malloc(2 * n * sizeof *x2), *v2 = malloc(2 * n * sizeof *v2);
    double *rho2 = malloc(n * sizeof *rho2), *S2 = malloc(4 * n * sizeof *S2);
    double *rho3 = malloc(n * sizeof *rho3), *S3 = malloc(4 * n * sizeof *S3);
    memcpy(x2, sim->x, 2 * n * sizeof *x2);
    memcpy(v2, sim->v, 2 * n * sizeof *v2);
    memcpy(rho2, sim->rho, n * sizeof *rho2);
    memcpy(rho3, sim->rho, n * sizeof *rho3);
    memcpy(S2, sim->S, 4 * n * sizeof *S2);
    memcpy(S3, sim->S, 4 * n * sizeof *S3);
    double *saved2 = malloc(7 * n * sizeof *saved2), *saved3 = malloc(7 * n * sizeof *saved3);
    const double dt = 1e-8;
    sph_rates rd = {.dv_dt = dense.dv, .drho_dt = dense.drho, .dS_dt = dense.dS};
    check(sim, sph_improved_euler_predict(sim, n, dt, x2, v2, rho2, S2, &rd, integrate, saved2));
    check(sim, sph_improved_euler_predict_strided(sim, n, dt, x3, v3, 3, rho3, S3, &rd, integrate,
                                                  saved3));
    long bad = 0;
    check(sim, sph_improved_euler_correct(sim, n, dt, x2, v2, rho2, S2, &rd, integrate, saved2));
    check(sim, sph_improved_euler_correct_strided(sim, n, dt, x3, v3, 3, rho3, S3, &rd, integrate,
                                                  sim->material_of, saved3, &bad));
    assert_int_equal(bad, -1);
    for (size_t a = 0; a < n; ++a) {
        for (int i = 0; i < 2; ++i) {
            if (a == 0) { /* left to the caller by the strided stages */
                assert_true(x3[i] == sim->x[i] && v3[i] == sim->v[i]);
                assert_true(x2[i] != sim->x[i]); /* the dense ones advance it */
            } else {
                assert_true(x3[3 * a + i] == x2[2 * a + i]);
                assert_true(v3[3 * a + i] == v2[2 * a + i]);
            }
        }
        assert_true(rho3[a] == rho2[a]);
    }
    assert_memory_equal(S3, S2, 4 * n * sizeof *S2);
    /* the watchdog: an integrated particle at 5 c_p is named */
    check(sim, sph_improved_euler_predict_strided(sim, n, dt, x3, v3, 3, rho3, S3, &rd, integrate,
                                                  saved3));
    v3[3 * 7] = 5.0 * sqrt((PAPER_K + 4.0 * PAPER_MU / 3.0) / PAPER_RHO0);
    assert_int_equal(sph_improved_euler_correct_strided(sim, n, dt, x3, v3, 3, rho3, S3, &rd,
                                                        integrate, sim->material_of, saved3, &bad),
                     SPH_ERR_UNSTABLE);
    assert_int_equal(bad, 7);
    assert_non_null(strstr(sph_errmsg(sim), "particle 7"));
    /* the same test on dense arrays, on its own */
    check(sim, sph_watchdog_check(sim, n, v2, rho2, sim->material_of, integrate, &bad));
    assert_int_equal(bad, -1);
    v2[2 * 7 + 1] = v3[3 * 7];
    assert_int_equal(sph_watchdog_check(sim, n, v2, rho2, sim->material_of, integrate, &bad),
                     SPH_ERR_UNSTABLE);
    assert_int_equal(bad, 7);
    v2[2 * 0 + 1] = v3[3 * 7]; /* a prescribed particle is not held to the speed */
    v2[2 * 7 + 1] = 0.0;
    check(sim, sph_watchdog_check(sim, n, v2, rho2, sim->material_of, integrate, &bad));
    assert_int_equal(
        sph_improved_euler_predict_strided(sim, n, dt, x3, v3, 1, rho3, S3, &rd, integrate, saved3),
        SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "stride=1"));
    free(x3);
    free(v3);
    free(dv);
    free(drho);
    free(dS);
    free(indices);
    free(offsets);
    free(integrate);
    free(x2);
    free(v2);
    free(rho2);
    free(S2);
    free(rho3);
    free(S3);
    free(saved2);
    free(saved3);
    free_rates(dense);
    sph_destroy(sim);
}

/* Total energy drift of a free block vibrating in its lowest mode
 * (v_x = V sin(pi x / L)) after `duration`, integrated with time step dt. */
static double energy_drift(double dt_factor, double duration, double *kinetic_share)
{
    sph_sim *sim = free_block_2d(20, 20, 1e-3);
    double *x = field_ptr(sim, SPH_FIELD_POSITION), *v = field_ptr(sim, SPH_FIELD_VELOCITY);
    for (size_t a = 0; a < sph_particle_count(sim); ++a)
        v[2 * a] = 0.1 * sin(M_PI * x[2 * a] / 0.02);
    check(sim, sph_set_dt(sim, dt_factor * sph_default_dt(sim), 0));
    sph_energy_info e0, e;
    check(sim, sph_energy(sim, 1, &e0));
    const double E0 = e0.kinetic + e0.elastic;
    check(sim, sph_run_until(sim, duration));
    check(sim, sph_energy(sim, 1, &e));
    *kinetic_share = e.kinetic / E0;
    sph_destroy(sim);
    return fabs(e.kinetic + e.elastic - E0) / E0;
}

/* The split evaluation (sph_rates_pairs, sum the ghosts' partial sums into
 * their owners, sph_rates_finish) over two "processes", each owning half the
 * particles and seeing the others as ghosts, with every pair listed once
 * over both: the rates of the one-process full-list evaluation, to
 * round-off.  On one process with the half list it is the same computation
 * as sph_rates_evaluate with the full list, to the bit.  Kernel correction
 * and XSPH on, so every partial sum is exercised; the block spans several
 * chunks of the pair pass. */

static void split_evaluation_over_two_processes(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(40, 30, 1e-3);
    check(sim, sph_effect(sim, "kernel_correction", ""));
    check(sim, sph_effect(sim, "xsph", "epsilon=0.5"));
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=2"));
    perturb(sim, 11u);
    check(sim, sph_run(sim, 0));
    const size_t n = sim->n, P = sph_rates_partial_size(sim);
    assert_int_equal(P, 1 + 2 + 4 + 3 + 2);
    /* reference: one process, full list */
    double *dv = calloc(2 * n, sizeof *dv), *drho = calloc(n, sizeof *drho);
    double *dS = calloc(4 * n, sizeof *dS), *u = calloc(2 * n, sizeof *u);
    size_t *offsets;
    int *indices;
    full_list(sim, &offsets, &indices);
    sph_particles all = handle_particles(sim);
    sph_neighbours full = {.offsets = offsets, .indices = indices};
    sph_rates ref = {.dv_dt = dv, .drho_dt = drho, .dS_dt = dS, .dx_dt = u};
    check(sim, sph_rates_evaluate(sim, &all, &full, &ref));

    /* one process, half list: bitwise the same */
    double *partial = calloc(n * P, sizeof *partial);
    double *dv1 = calloc(2 * n, sizeof *dv1), *drho1 = calloc(n, sizeof *drho1);
    double *dS1 = calloc(4 * n, sizeof *dS1), *u1 = calloc(2 * n, sizeof *u1);
    size_t *half_offsets;
    int *half_indices;
    sph_neighbours half = half_list(sim, &half_offsets, &half_indices);
    sph_rates one = {.dv_dt = dv1, .drho_dt = drho1, .dS_dt = dS1, .dx_dt = u1};
    check(sim, sph_rates_pairs(sim, &all, &half, partial));
    check(sim, sph_rates_finish(sim, &all, partial, &one));
    assert_memory_equal(dv1, dv, 2 * n * sizeof *dv);
    assert_memory_equal(drho1, drho, n * sizeof *drho);
    assert_memory_equal(dS1, dS, 4 * n * sizeof *dS);
    assert_memory_equal(u1, u, 2 * n * sizeof *u);

    /* two processes: k owns the particles with owner[a] == k (alternate
     * bands of 5 lattice rows), then holds every other particle as a ghost;
     * a pair is listed by the owner of its smaller index */
    int *owner = malloc(n * sizeof *owner);
    for (size_t a = 0; a < n; ++a)
        owner[a] = (int)((a / 200) % 2);
    size_t *local_of = malloc(n * sizeof *local_of);
    double *got_dv = calloc(2 * n, sizeof *got_dv), *got_drho = calloc(n, sizeof *got_drho);
    double *got_dS = calloc(4 * n, sizeof *got_dS), *got_u = calloc(2 * n, sizeof *got_u);
    double *part[2];
    size_t *global[2], nloc[2];
    double *px[2], *pv[2], *prho[2], *pS[2], *pm[2];
    int *pmat[2];
    size_t *poff[2];
    int *pidx[2];
    for (int k = 0; k < 2; ++k) {
        global[k] = malloc(n * sizeof(size_t));
        size_t m = 0;
        for (size_t a = 0; a < n; ++a)
            if (owner[a] == k)
                global[k][m++] = a;
        nloc[k] = m;
        for (size_t a = 0; a < n; ++a)
            if (owner[a] != k)
                global[k][m++] = a;
        for (size_t l = 0; l < n; ++l)
            local_of[global[k][l]] = l;
        px[k] = malloc(2 * n * sizeof(double));
        pv[k] = malloc(2 * n * sizeof(double));
        prho[k] = malloc(n * sizeof(double));
        pS[k] = malloc(4 * n * sizeof(double));
        pm[k] = malloc(n * sizeof(double));
        pmat[k] = malloc(n * sizeof(int));
        for (size_t l = 0; l < n; ++l) {
            const size_t a = global[k][l];
            memcpy(px[k] + 2 * l, sim->x + 2 * a, 2 * sizeof(double));
            memcpy(pv[k] + 2 * l, sim->v + 2 * a, 2 * sizeof(double));
            memcpy(pS[k] + 4 * l, sim->S + 4 * a, 4 * sizeof(double));
            prho[k][l] = sim->rho[a];
            pm[k][l] = sim->mass[a];
            pmat[k][l] = sim->material_of[a];
        }
        /* rows of the locals: pairs whose smaller index this process owns */
        poff[k] = calloc(nloc[k] + 1, sizeof(size_t));
        pidx[k] = malloc((half_offsets[n] + 1) * sizeof(int));
        size_t e = 0;
        for (size_t l = 0; l < nloc[k]; ++l) {
            const size_t a = global[k][l];
            for (size_t q = half_offsets[a]; q < half_offsets[a + 1]; ++q)
                pidx[k][e++] = (int)local_of[half_indices[q]];
            poff[k][l + 1] = e;
        }
        part[k] = calloc(n * P, sizeof(double));
        const sph_particles pk =
            process_particles(nloc[k], n, px[k], pv[k], prho[k], pS[k], pm[k], pmat[k]);
        sph_neighbours hk = {.offsets = poff[k], .indices = pidx[k]};
        check(sim, sph_rates_pairs(sim, &pk, &hk, part[k]));
    }
    /* the "reverse communication": ghosts' sums to their owners */
    for (int k = 0; k < 2; ++k)
        for (size_t l = nloc[k]; l < n; ++l) {
            const size_t a = global[k][l];
            const int o = owner[a];
            size_t lo = 0;
            while (global[o][lo] != a)
                ++lo;
            for (size_t c = 0; c < P; ++c)
                part[o][lo * P + c] += part[k][l * P + c];
        }
    for (int k = 0; k < 2; ++k) {
        double *rdv = malloc(2 * n * sizeof(double)), *rdrho = malloc(n * sizeof(double));
        double *rdS = malloc(4 * n * sizeof(double)), *ru = malloc(2 * n * sizeof(double));
        const sph_particles pk =
            process_particles(nloc[k], n, px[k], pv[k], prho[k], pS[k], pm[k], pmat[k]);
        sph_rates rk = {.dv_dt = rdv, .drho_dt = rdrho, .dS_dt = rdS, .dx_dt = ru};
        check(sim, sph_rates_finish(sim, &pk, part[k], &rk));
        for (size_t l = 0; l < nloc[k]; ++l) {
            const size_t a = global[k][l];
            memcpy(got_dv + 2 * a, rdv + 2 * l, 2 * sizeof(double));
            memcpy(got_u + 2 * a, ru + 2 * l, 2 * sizeof(double));
            memcpy(got_dS + 4 * a, rdS + 4 * l, 4 * sizeof(double));
            got_drho[a] = rdrho[l];
        }
        free(rdv);
        free(rdrho);
        free(rdS);
        free(ru);
    }
    const double *want[4] = {dv, drho, dS, u}, *got[4] = {got_dv, got_drho, got_dS, got_u};
    const size_t len[4] = {2 * n, n, 4 * n, 2 * n};
    const char *name[4] = {"dv/dt", "drho/dt", "dS/dt", "XSPH velocity"};
    for (int q = 0; q < 4; ++q) {
        double scale = 0.0, diff = 0.0;
        for (size_t i = 0; i < len[q]; ++i) {
            scale = fmax(scale, fabs(want[q][i]));
            diff = fmax(diff, fabs(want[q][i] - got[q][i]));
        }
        assert_true(scale > 0.0);
        if (diff > 1e-12 * scale)
            print_error("%s: two processes differ by %g of the largest value\n", name[q],
                        diff / scale);
        assert_true(diff <= 1e-12 * scale);
    }

    /* sph_rates_pass_half: each process lists its local pairs once and
     * every pair of a local and a ghost in the local's row (the pair is
     * listed by both processes), and drops the ghosts' terms: the same
     * rates with no sums exchanged, whole or in its two passes. */
    for (int k = 0; k < 2; ++k) {
        for (size_t l = 0; l < n; ++l)
            local_of[global[k][l]] = l;
        size_t *hoff = calloc(nloc[k] + 1, sizeof *hoff);
        for (int fill = 0; fill < 2; ++fill) {
            size_t *at = fill ? calloc(nloc[k], sizeof *at) : NULL;
            for (size_t a = 0; a < n; ++a)
                for (size_t q = half_offsets[a]; q < half_offsets[a + 1]; ++q) {
                    const size_t b = (size_t)half_indices[q];
                    const size_t la = local_of[a], lb = local_of[b];
                    const int mine_a = owner[a] == k, mine_b = owner[b] == k;
                    size_t row[2];
                    size_t other[2];
                    int rows = 0;
                    if (mine_a && mine_b) {
                        row[rows] = la < lb ? la : lb;
                        other[rows++] = la < lb ? lb : la;
                    } else if (mine_a || mine_b) {
                        row[rows] = mine_a ? la : lb;
                        other[rows++] = mine_a ? lb : la;
                    }
                    for (int r = 0; r < rows; ++r) {
                        if (fill)
                            pidx[k][hoff[row[r]] + at[row[r]]++] = (int)other[r];
                        else
                            hoff[row[r] + 1]++;
                    }
                }
            if (!fill)
                for (size_t l = 0; l < nloc[k]; ++l)
                    hoff[l + 1] += hoff[l];
            free(at);
        }
        const sph_particles pk =
            process_particles(nloc[k], n, px[k], pv[k], prho[k], pS[k], pm[k], pmat[k]);
        sph_neighbours hk = {.offsets = hoff, .indices = pidx[k]};
        double *rdv = malloc(2 * n * sizeof(double)), *rdrho = malloc(n * sizeof(double));
        double *rdS = malloc(4 * n * sizeof(double)), *ru = malloc(2 * n * sizeof(double));
        for (int passes = 0; passes < 2; ++passes) {
            if (passes) {
                sph_rates cont = {.drho_dt = rdrho, .dS_dt = rdS, .dx_dt = ru};
                sph_rates mom = {.dv_dt = rdv};
                check(sim, sph_rates_pass_half(sim, SPH_RATES_CONTINUITY, &pk, &hk, &cont));
                check(sim, sph_rates_pass_half(sim, SPH_RATES_MOMENTUM, &pk, &hk, &mom));
            } else {
                sph_rates rk = {.dv_dt = rdv, .drho_dt = rdrho, .dS_dt = rdS, .dx_dt = ru};
                check(sim, sph_rates_pass_half(sim, SPH_RATES_ALL, &pk, &hk, &rk));
            }
            const double *mine[4] = {rdv, rdrho, rdS, ru};
            const size_t width[4] = {2, 1, 4, 2};
            for (int q = 0; q < 4; ++q) {
                double scale = 0.0, diff = 0.0;
                for (size_t l = 0; l < nloc[k]; ++l)
                    for (size_t c = 0; c < width[q]; ++c) {
                        const double w = want[q][global[k][l] * width[q] + c];
                        scale = fmax(scale, fabs(w));
                        diff = fmax(diff, fabs(w - mine[q][l * width[q] + c]));
                    }
                assert_true(scale > 0.0);
                if (diff > 1e-12 * scale)
                    print_error("%s: process %d, sph_rates_pass_half (%s) differs by %g of the "
                                "largest value\n",
                                name[q], k, passes ? "two passes" : "whole", diff / scale);
                assert_true(diff <= 1e-12 * scale);
            }
        }
        free(rdv);
        free(rdrho);
        free(rdS);
        free(ru);
        free(hoff);
    }
    /* one process: the half list through sph_rates_pass_half gives the
     * rates of the full-list evaluation */
    {
        sph_rates rk = {.dv_dt = dv1, .drho_dt = drho1, .dS_dt = dS1, .dx_dt = u1};
        check(sim, sph_rates_pass_half(sim, SPH_RATES_ALL, &all, &half, &rk));
        const double *got1[4] = {dv1, drho1, dS1, u1};
        for (int q = 0; q < 4; ++q) {
            double scale = 0.0, diff = 0.0;
            for (size_t i = 0; i < len[q]; ++i) {
                scale = fmax(scale, fabs(want[q][i]));
                diff = fmax(diff, fabs(want[q][i] - got1[q][i]));
            }
            assert_true(diff <= 1e-12 * scale);
        }
    }
    for (int k = 0; k < 2; ++k) {
        free(global[k]);
        free(px[k]);
        free(pv[k]);
        free(prho[k]);
        free(pS[k]);
        free(pm[k]);
        free(pmat[k]);
        free(poff[k]);
        free(pidx[k]);
        free(part[k]);
    }
    free(owner);
    free(half_offsets);
    free(half_indices);
    free(local_of);
    free(got_dv);
    free(got_drho);
    free(got_dS);
    free(got_u);
    free(dv);
    free(drho);
    free(dS);
    free(u);
    free(dv1);
    free(drho1);
    free(dS1);
    free(u1);
    free(partial);
    free(offsets);
    free(indices);
    sph_destroy(sim);
}

/* The continuity and momentum passes (each over the half list, each with
 * only its own partial sums) give bitwise the rates of the whole
 * evaluation, every pair effect on; a pass leaves the other pass's rate
 * arrays alone. */
static void passes_add_up_to_the_whole_evaluation(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(24, 18, 1e-3);
    check(sim, sph_effect(sim, "kernel_correction", ""));
    check(sim, sph_effect(sim, "xsph", "epsilon=0.5"));
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=2"));
    check(sim, sph_effect(sim, "artificial_stress", "epsilon=0.3 n=4"));
    check(sim, sph_effect(sim, "gravity", "gy=-9.81"));
    check(sim, sph_effect(sim, "damping", "rate=1000"));
    perturb(sim, 3u);
    check(sim, sph_run(sim, 0));
    const size_t n = sim->n;
    const size_t P = sph_rates_pass_size(sim, SPH_RATES_ALL);
    const size_t Pc = sph_rates_pass_size(sim, SPH_RATES_CONTINUITY);
    const size_t Pm = sph_rates_pass_size(sim, SPH_RATES_MOMENTUM);
    assert_int_equal(P, sph_rates_partial_size(sim));
    assert_int_equal(Pc, 1 + 4 + 3 + 2); /* drho, L, M, XSPH */
    assert_int_equal(Pm, 2);             /* dv */
    assert_int_equal(Pc + Pm, P);
    assert_int_equal(sph_rates_pass_size(sim, 0), 0);
    sph_particles all = handle_particles(sim);
    size_t *half_offsets;
    int *half_indices;
    sph_neighbours half = half_list(sim, &half_offsets, &half_indices);
    double *partial = calloc(n * P, sizeof *partial);
    double *buf[2][4];
    for (int k = 0; k < 2; ++k) {
        buf[k][0] = calloc(2 * n, sizeof(double));
        buf[k][1] = calloc(n, sizeof(double));
        buf[k][2] = calloc(4 * n, sizeof(double));
        buf[k][3] = calloc(2 * n, sizeof(double));
    }
    sph_rates whole = {buf[0][0], buf[0][1], buf[0][2], buf[0][3]};
    check(sim, sph_rates_pass_pairs(sim, SPH_RATES_ALL, &all, &half, partial));
    check(sim, sph_rates_pass_finish(sim, SPH_RATES_ALL, &all, partial, &whole));
    /* the momentum pass needs only dv_dt, the continuity pass the rest */
    sph_rates mom = {.dv_dt = buf[1][0]};
    sph_rates cont = {.drho_dt = buf[1][1], .dS_dt = buf[1][2], .dx_dt = buf[1][3]};
    for (size_t a = 0; a < n; ++a)
        buf[1][1][a] = -7.0; /* must survive the momentum pass */
    check(sim, sph_rates_pass_pairs(sim, SPH_RATES_MOMENTUM, &all, &half, partial));
    check(sim, sph_rates_pass_finish(sim, SPH_RATES_MOMENTUM, &all, partial, &mom));
    assert_true(buf[1][1][n / 2] == -7.0);
    check(sim, sph_rates_pass_pairs(sim, SPH_RATES_CONTINUITY, &all, &half, partial));
    check(sim, sph_rates_pass_finish(sim, SPH_RATES_CONTINUITY, &all, partial, &cont));
    assert_memory_equal(buf[1][0], buf[0][0], 2 * n * sizeof(double));
    assert_memory_equal(buf[1][1], buf[0][1], n * sizeof(double));
    assert_memory_equal(buf[1][2], buf[0][2], 4 * n * sizeof(double));
    assert_memory_equal(buf[1][3], buf[0][3], 2 * n * sizeof(double));
    /* the rates are not trivial: gravity, stress and flow all show */
    double amax = 0.0, rmax = 0.0;
    for (size_t a = 0; a < n; ++a) {
        amax = fmax(amax, fabs(buf[0][0][2 * a]));
        rmax = fmax(rmax, fabs(buf[0][1][a]));
    }
    assert_true(amax > 0.0 && rmax > 0.0);
    /* a pass outside 1..3 is refused by name */
    assert_int_equal(sph_rates_pass_pairs(sim, 4, &all, &half, partial), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "pass=4"));
    /* the momentum pass refuses a missing dv_dt */
    assert_int_equal(sph_rates_pass_finish(sim, SPH_RATES_MOMENTUM, &all, partial, &cont),
                     SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "dv_dt"));
    /* a missing partial-sum buffer is refused, naming it and its size */
    assert_int_equal(sph_rates_pass_pairs(sim, SPH_RATES_ALL, &all, &half, NULL), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "sph_rates_pairs: partial is NULL; it holds n_total"));
    assert_int_equal(sph_rates_pass_finish(sim, SPH_RATES_ALL, &all, NULL, &whole),
                     SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "sph_rates_finish: partial is NULL; it holds n_local"));
    for (int k = 0; k < 2; ++k)
        for (int q = 0; q < 4; ++q)
            free(buf[k][q]);
    free(partial);
    free(half_offsets);
    free(half_indices);
    sph_destroy(sim);
}

static void energy_is_conserved_without_viscosity(void **state)
{
    (void)state;
    /* Without dissipation the semi-discrete SPH equations conserve
     * kinetic + elastic energy; what remains is the time-integration error
     * of Improved Euler, which grows like dt^3 per unit time (its
     * amplification on the imaginary axis is 1 + (omega dt)^4 / 8 per
     * step).  Over 100 default steps (26 us, most of a vibration period)
     * at a quarter of the default step the drift stays below 5e-4, and
     * halving the step reduces it by 2^3 (checked: more than 2^2.5). */
    sph_sim *probe = free_block_2d(20, 20, 1e-3);
    const double duration = 100 * sph_default_dt(probe);
    sph_destroy(probe);
    double share_half, share_quarter;
    const double half = energy_drift(0.5, duration, &share_half);
    const double quarter = energy_drift(0.25, duration, &share_quarter);
    print_message("energy drift over %.1f us: %.3g at dt/2, %.3g at dt/4\n", duration * 1e6, half,
                  quarter);
    assert_true(quarter < 5e-4);
    assert_true(log2(half / quarter) > 2.5);
    /* the energy really moved between its kinetic and elastic forms */
    assert_true(share_quarter < 0.9);
}

static void uniform_translation_changes_nothing(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(12, 12, 1e-3);
    const double v[2] = {3.0, -2.0};
    check(sim, sph_set_body_velocity(sim, 0, v));
    rates_buf r = evaluate(sim);
    for (size_t a = 0; a < sim->n; ++a) {
        assert_close(r.drho[a], 0.0, 1e-9, "drho/dt");
        for (int c = 0; c < 4; ++c)
            assert_close(r.dS[4 * a + c], 0.0, 1e-3, "dS/dt");
        for (int i = 0; i < 2; ++i)
            assert_close(r.dv[2 * a + i], 0.0, 1e-9, "dv/dt");
    }
    free_rates(r);
    sph_destroy(sim);
}

/* XSPH (Monaghan 1989): dx_a/dt = v_a - eps sum_b m_b / rho_ab W_ab v_ab.
 * One particle moving at V among particles at rest, all at rho0: it is
 * slowed to V (1 - eps sum_b V_b W_ab) and each neighbour is carried along
 * at eps V_a W_ab V, with the kernel sums done here from the kernel's
 * formula. */
static void xsph_velocity_of_one_moving_particle(void **state)
{
    (void)state;
    const double eps = 0.5, V = 2.0, dx = 1e-3;
    sph_sim *sim = free_block_2d(9, 9, dx);
    check(sim, sph_effect(sim, "xsph", "epsilon=0.5"));
    check(sim, sph_run(sim, 0));
    const size_t n = sim->n, mover = 40; /* the centre of the 9 x 9 block */
    sim->v[2 * mover] = V;
    double *dv = calloc(2 * n, sizeof *dv), *drho = calloc(n, sizeof *drho);
    double *dS = calloc(4 * n, sizeof *dS), *u = calloc(2 * n, sizeof *u);
    size_t *offsets;
    int *indices;
    full_list(sim, &offsets, &indices);
    sph_particles p = handle_particles(sim);
    sph_neighbours nb = {.offsets = offsets, .indices = indices};
    sph_rates out = {.dv_dt = dv, .drho_dt = drho, .dS_dt = dS, .dx_dt = u};
    check(sim, sph_rates_evaluate(sim, &p, &nb, &out));
    free(offsets);
    free(indices);
    const double h = sim->h, volume = dx * dx;
    const double norm = kernel_cubic_sigma(2) / (h * h);
    double sum = 0.0;
    for (size_t b = 0; b < n; ++b) {
        if (b == mover)
            continue;
        const double r =
            hypot(sim->x[2 * b] - sim->x[2 * mover], sim->x[2 * b + 1] - sim->x[2 * mover + 1]);
        const double W = norm * kernel_cubic_w(2, r / h);
        sum += volume * W;
        assert_close(u[2 * b], eps * volume * W * V, 1e-12 * V, "neighbour carried along");
        assert_close(u[2 * b + 1], 0.0, 1e-15, "neighbour, y");
    }
    assert_true(sum > 0.5);
    assert_close(u[2 * mover], V * (1.0 - eps * sum), 1e-12 * V, "moving particle slowed");
    assert_close(u[2 * mover + 1], 0.0, 1e-15, "moving particle, y");
    free(dv);
    free(drho);
    free(dS);
    free(u);
    sph_destroy(sim);
}

/* 3D: with kernel_correction the velocity gradient of a linear field is
 * exact at every particle, and the stress rate is paper eq. (6) with it,
 * computed here with full 3x3 matrices; both kernels. */
static void velocity_gradient_exact_in_3d_with_correction(void **state)
{
    (void)state;
    const double L[3][3] = {{2.0, -1.0, 0.5}, {1.5, -0.5, 3.0}, {-2.0, 0.7, 1.1}};
    const double S0m[3][3] = {{1e5, 4e5, -2e5}, {4e5, -3e5, 1e5}, {-2e5, 1e5, 2e5}};
    double expected[6];
    {
        double eps[3][3], om[3][3], dS[3][3];
        double tr = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                eps[i][j] = 0.5 * (L[i][j] + L[j][i]);
                om[i][j] = 0.5 * (L[i][j] - L[j][i]);
            }
        for (int i = 0; i < 3; ++i)
            tr += eps[i][i];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double rot = 0;
                for (int k = 0; k < 3; ++k)
                    rot += S0m[i][k] * om[j][k] + om[i][k] * S0m[k][j];
                dS[i][j] = 2 * PAPER_MU * (eps[i][j] - (i == j) * tr / 3) + rot;
            }
        const double e[6] = {dS[0][0], dS[1][1], dS[2][2], dS[0][1], dS[0][2], dS[1][2]};
        memcpy(expected, e, sizeof e);
    }
    for (int kernel = 0; kernel < 2; ++kernel) {
        sph_sim *sim = new_sim(3);
        int mat, body;
        check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
        const double lo[3] = {-4e-3, -4e-3, -4e-3}, hi[3] = {4e-3, 4e-3, 4e-3};
        check(sim, sph_add_block(sim, "cube", mat, lo, hi, 1e-3, &body));
        check(sim, sph_set_kernel(sim, (sph_kernel)kernel));
        check(sim, sph_effect(sim, "kernel_correction", NULL));
        double *x = field_ptr(sim, SPH_FIELD_POSITION), *v = field_ptr(sim, SPH_FIELD_VELOCITY);
        double *S = field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS);
        const double S0[6] = {S0m[0][0], S0m[1][1], S0m[2][2], S0m[0][1], S0m[0][2], S0m[1][2]};
        for (size_t a = 0; a < sim->n; ++a) {
            for (int i = 0; i < 3; ++i) {
                v[3 * a + i] = 0.2 * i;
                for (int j = 0; j < 3; ++j)
                    v[3 * a + i] += L[i][j] * x[3 * a + j];
            }
            memcpy(S + 6 * a, S0, sizeof S0);
        }
        rates_buf r = evaluate(sim);
        for (size_t a = 0; a < sim->n; ++a)
            for (int c = 0; c < 6; ++c)
                assert_close(r.dS[6 * a + c], expected[c], 1e-8 * PAPER_MU * 3.0,
                             "3D corrected dS/dt");
        free_rates(r);
        sph_destroy(sim);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(velocity_gradient_exact_for_linear_field),
        cmocka_unit_test(velocity_gradient_exact_in_3d_with_correction),
        cmocka_unit_test(rigid_rotation_builds_no_stress),
        cmocka_unit_test(jaumann_rate_keeps_stress_magnitude_under_rotation),
        cmocka_unit_test(momentum_of_isolated_body_is_conserved),
        cmocka_unit_test(far_pairs_are_computed_in_both_rows),
        cmocka_unit_test(one_sided_continuity),
        cmocka_unit_test(one_sided_velocity_gradient),
        cmocka_unit_test(one_sided_momentum),
        cmocka_unit_test(one_sided_artificial_viscosity),
        cmocka_unit_test(one_sided_artificial_stress),
        cmocka_unit_test(one_sided_xsph),
        cmocka_unit_test(one_sided_correction_moment),
        cmocka_unit_test(pair_tensor_effects_repel),
        cmocka_unit_test(rate_paths_agree),
        cmocka_unit_test(runs_keep_the_bits),
        cmocka_unit_test(rate_path_from_the_environment),
        cmocka_unit_test(artificial_stress_exponent_paths_agree),
        cmocka_unit_test(artificial_stress_needs_a_non_negative_kernel),
        cmocka_unit_test(strided_entry_points_match_the_dense_ones),
        cmocka_unit_test(caller_rows_take_runs_when_sorted),
        cmocka_unit_test(wider_stride_in_3d_keeps_the_bits),
        cmocka_unit_test(row_test_matches_each_row),
        cmocka_unit_test(particle_check_names_the_particle),
        cmocka_unit_test(split_evaluation_over_two_processes),
        cmocka_unit_test(passes_add_up_to_the_whole_evaluation),
        cmocka_unit_test(energy_is_conserved_without_viscosity),
        cmocka_unit_test(uniform_translation_changes_nothing),
        cmocka_unit_test(xsph_velocity_of_one_moving_particle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
