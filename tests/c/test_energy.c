/* sph_energy_fields() gives the per-particle terms that sph_energy() sums. */
#include "helpers.h"

#include "core/sim.h"

static void fields_sum_to_the_elastic_energy(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(8, 6, 1e-3);
    const size_t n = sph_particle_count(sim);
    /* a non-trivial state: compressed by 0.1 % to 0.4 %, with shear */
    for (size_t a = 0; a < n; ++a) {
        sim->rho[a] = PAPER_RHO0 * (1.0 + 1e-3 * (1.0 + (double)(a % 4)));
        for (int c = 0; c < 4; ++c)
            sim->S[a * 4 + c] = 1e5 * (double)((a + (size_t)c) % 5) - 2e5;
    }
    int *material = calloc(n, sizeof *material);
    double *energy = malloc(n * sizeof *energy);
    check(sim, sph_energy_fields(sim, n, sim->mass, sim->rho, sim->S, material, energy));
    sph_energy_info info;
    check(sim, sph_energy(sim, 1, &info));
    double sum = 0.0;
    for (size_t a = 0; a < n; ++a) {
        assert_true(energy[a] > 0.0);
        sum += energy[a];
    }
    assert_close(sum, info.elastic, 1e-12 * info.elastic, "sum of per-particle elastic energies");

    /* pure compression, no shear: m c0^2 (ln(rho/rho0) + rho0/rho - 1) */
    double S0[4] = {0.0, 0.0, 0.0, 0.0};
    double rho = PAPER_RHO0 * 1.002, m = 2.3e-3, e = 0.0;
    int mat = 0;
    check(sim, sph_energy_fields(sim, 1, &m, &rho, S0, &mat, &e));
    const double c0sq = PAPER_K / PAPER_RHO0;
    assert_close(e, m * c0sq * (log(1.002) + 1.0 / 1.002 - 1.0), 1e-12 * e, "volumetric energy");

    /* bad input names the particle */
    mat = 3;
    assert_int_equal(sph_energy_fields(sim, 1, &m, &rho, S0, &mat, &e), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "material 3"));
    mat = 0;
    rho = 0.0;
    assert_int_equal(sph_energy_fields(sim, 1, &m, &rho, S0, &mat, &e), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "density 0"));
    free(material);
    free(energy);
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fields_sum_to_the_elastic_energy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
