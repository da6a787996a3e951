/* The paper's uniaxial piston scene: particle count, time step, and the
 * order in which the first wave reaches the probes. */
#include "helpers.h"

static void paper_scene_has_12040_particles_and_paper_time_step(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    sph_paper_scene s;
    check(sim, sph_build_paper_scene(sim, 1e-3, 1.5e-3, 0, &s));
    sph_body_info specimen, piston, plate;
    check(sim, sph_body_info_get(sim, s.specimen, &specimen));
    check(sim, sph_body_info_get(sim, s.piston, &piston));
    check(sim, sph_body_info_get(sim, s.plate, &plate));
    assert_int_equal(specimen.count, 86 * 140);
    /* piston and plate at least one kernel support 2h = 2.4 dx thick */
    assert_true(piston.count >= 86 * 3 && plate.count >= 86 * 3);
    /* 0.5 h / c0 with h = 1.2 mm, c0 = sqrt(K / rho0): the paper's 0.261 us */
    const double dt = 0.5 * 1.2e-3 / sqrt(PAPER_K / PAPER_RHO0);
    assert_close(sph_dt(sim), dt, 1e-15, "default dt");
    assert_int_equal((long)lround(sph_dt(sim) * 1e9), 261);
    sph_destroy(sim);
}

/* First time the von Mises stress at each probe exceeds half the plane-wave
 * value 2 mu v / c_p (uniaxial strain eps = v / c_p gives
 * sigma_vm = sqrt(3/2 S:S) = 2 mu |eps|). */
static void wave_reaches_B_first_then_A_and_C_together(void **state)
{
    (void)state;
    const double dx = 1e-3, v = 1.5e-3;
    const double c_p = sqrt((PAPER_K + 4.0 * PAPER_MU / 3.0) / PAPER_RHO0);
    const double level = 0.5 * 2.0 * PAPER_MU * v / c_p;
    sph_sim *sim = new_sim(2);
    sph_paper_scene s;
    check(sim, sph_build_paper_scene(sim, dx, v, 0, &s));
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0"));
    double arrival[3] = {NAN, NAN, NAN}, prev[3] = {0, 0, 0}, t_prev = 0;
    const int probe[3] = {s.probe_A, s.probe_B, s.probe_C};
    while (sph_time(sim) < 40e-6) {
        check(sim, sph_run(sim, 1));
        const double t = sph_time(sim);
        for (int k = 0; k < 3; ++k) {
            double vals[8];
            check(sim, sph_probe_sample(sim, probe[k], vals));
            if (isnan(arrival[k]) && vals[0] > level)
                arrival[k] = t_prev + (level - prev[k]) * (t - t_prev) / (vals[0] - prev[k]);
            prev[k] = vals[0];
        }
        t_prev = t;
    }
    print_message("arrivals: A %.2f us, B %.2f us, C %.2f us\n", arrival[0] * 1e6, arrival[1] * 1e6,
                  arrival[2] * 1e6);
    for (int k = 0; k < 3; ++k)
        assert_false(isnan(arrival[k]));
    assert_true(arrival[1] < arrival[0]);
    assert_true(arrival[1] < arrival[2]);
    assert_close(arrival[0], arrival[2], 2e-6, "A and C arrive together");
    /* and at the P-wave speed from the piston face (y = 140 mm) */
    assert_close(arrival[1], (0.140 - 0.1035) / c_p, 0.1 * (0.140 - 0.1035) / c_p, "arrival at B");
    assert_close(arrival[0], (0.140 - 0.070) / c_p, 0.05 * (0.140 - 0.070) / c_p, "arrival at A");
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(paper_scene_has_12040_particles_and_paper_time_step),
        cmocka_unit_test(wave_reaches_B_first_then_A_and_C_together),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
