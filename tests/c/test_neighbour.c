/* The cell-list neighbour search finds exactly the pairs a brute-force
 * search finds, each once (in the row of its smaller index) and a pair
 * whose particles lie in chunks of the pair pass at least two apart in the
 * row of its larger index too, on random and lattice sets, with and
 * without periodic axes, in 2D and 3D. */
#include "helpers.h"

#include "core/sim.h"

static double uniform(unsigned *seed)
{
    *seed = *seed * 1103515245u + 12345u;
    return ((*seed >> 8) & 0xffffff) / (double)0x1000000;
}

/* Compare the built list with all pairs closer than 2h + skin; returns
 * the number of pairs listed in both rows. */
static size_t compare_with_brute_force(sph_sim *sim)
{
    check(sim, sph_run(sim, 0)); /* builds the list */
    const neighbour_list *nl = &sim->nl;
    const int dim = sim->dim;
    const double rc = 2.0 * sim->h + nl->skin;
    const size_t chunk = rates_chunk_rows(dim, sim->n);
    assert_int_equal(nl->chunk, chunk);
    size_t pairs = 0, twice = 0;
    char *seen = calloc(sim->n, 1);
    for (size_t a = 0; a < sim->n; ++a) {
        memset(seen, 0, sim->n);
        for (size_t k = neighbour_row(nl, a); k < neighbour_row(nl, a + 1); ++k) {
            const int b = nl->indices[k];
            assert_true(b >= 0 && (size_t)b < sim->n && (size_t)b != a);
            assert_false(seen[b]); /* no duplicates */
            seen[b] = 1;
            if (k > neighbour_row(nl, a))
                assert_true(nl->indices[k - 1] < b); /* sorted */
        }
        for (size_t b = 0; b < sim->n; ++b) {
            if (b == a)
                continue;
            const int listed = b > a || a / chunk >= b / chunk + 2;
            double r2 = 0.0;
            for (int i = 0; i < dim; ++i) {
                double d = sim->x[a * dim + i] - sim->x[b * dim + i];
                if (sim->has_domain && sim->periodic[i]) {
                    const double L = sim->hi[i] - sim->lo[i];
                    d -= L * round(d / L);
                }
                r2 += d * d;
            }
            const int within = r2 < rc * rc && listed;
            if (within != seen[b]) {
                print_error("pair (%zu, %zu) at distance %g: brute force says %d, list says %d\n",
                            a, b, sqrt(r2), within, seen[b]);
                fail();
            }
            pairs += within && b > a;
            twice += within && b < a;
        }
    }
    free(seen);
    assert_true(pairs > 0);
    return twice;
}

static sph_sim *random_set(int dim, size_t n, double box, unsigned seed, int periodic)
{
    sph_sim *sim = new_sim(dim);
    int mat, body;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    if (periodic) {
        const double lo[3] = {0, 0, 0}, hi[3] = {box, box, box};
        const int per[3] = {1, periodic > 1, 1};
        check(sim, sph_set_domain(sim, lo, hi, per));
    }
    double *pos = malloc(n * dim * sizeof *pos);
    for (size_t k = 0; k < n * dim; ++k)
        pos[k] = box * uniform(&seed);
    /* nominal spacing from the number density */
    const double spacing = pow(pow(box, dim) / n, 1.0 / dim);
    check(sim, sph_add_particles(sim, "cloud", mat, n, pos, NULL, spacing, &body));
    free(pos);
    return sim;
}

static void random_2d_matches_brute_force(void **state)
{
    (void)state;
    sph_sim *sim = random_set(2, 700, 0.02, 1u, 0);
    /* numbered at random over three chunks: the first and last chunks'
     * pairs are in both rows */
    assert_true(compare_with_brute_force(sim) > 0);
    sph_destroy(sim);
}

static void random_2d_periodic_matches_brute_force(void **state)
{
    (void)state;
    sph_sim *sim = random_set(2, 700, 0.02, 2u, 1);
    compare_with_brute_force(sim);
    sph_destroy(sim);
    sim = random_set(2, 700, 0.02, 3u, 2); /* periodic in x and y */
    compare_with_brute_force(sim);
    sph_destroy(sim);
}

static void random_3d_matches_brute_force(void **state)
{
    (void)state;
    sph_sim *sim = random_set(3, 900, 0.01, 4u, 0);
    compare_with_brute_force(sim);
    sph_destroy(sim);
    sim = random_set(3, 900, 0.01, 5u, 1);
    compare_with_brute_force(sim);
    sph_destroy(sim);
}

static void lattice_matches_brute_force_and_has_20_neighbours(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(20, 16, 1e-3);
    compare_with_brute_force(sim);
    /* An interior particle of a square lattice with h = 1.2 dx and cutoff
     * 2h + skin = 2.7 dx sees the 20 sites with i^2 + j^2 <= 5. */
    const size_t a = 8 * 20 + 10;
    /* half of them in the row of a (the 10 of larger index) */
    assert_int_equal(neighbour_row(&sim->nl, a + 1) - neighbour_row(&sim->nl, a), 10);
    sph_destroy(sim);
}

static void narrow_periodic_strip_matches_brute_force(void **state)
{
    (void)state;
    /* 6 particles across: fewer than 3 cells along the periodic axis. */
    sph_sim *sim = new_sim(2);
    int mat, body;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {0, 0, 0}, hi[3] = {6e-3, 20e-3, 0};
    const int per[3] = {1, 0, 0};
    check(sim, sph_set_domain(sim, lo, hi, per));
    check(sim, sph_add_block(sim, "strip", mat, lo, hi, 1e-3, &body));
    compare_with_brute_force(sim);
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(random_2d_matches_brute_force),
        cmocka_unit_test(random_2d_periodic_matches_brute_force),
        cmocka_unit_test(random_3d_matches_brute_force),
        cmocka_unit_test(lattice_matches_brute_force_and_has_20_neighbours),
        cmocka_unit_test(narrow_periodic_strip_matches_brute_force),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
