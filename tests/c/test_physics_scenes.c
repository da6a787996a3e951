/* Whole scenes against exact solutions: a plane P-wave behind a piston in
 * a laterally periodic strip, and a periodic column settling under
 * gravity. */
#include "helpers.h"

/* Plane-strain P-wave speed, derived from the moduli. */
static double p_wave_speed(void)
{
    return sqrt((PAPER_K + 4.0 * PAPER_MU / 3.0) / PAPER_RHO0);
}

/* A strip periodic along x of width 10 dx, a fixed plate of 3 layers below,
 * and on top either a piston of 3 layers moving down at `speed` or
 * nothing. */
static sph_sim *periodic_strip(double dx, double height, double speed, int with_piston)
{
    sph_sim *sim = new_sim(2);
    int mat, specimen, plate, piston;
    const double w = 10 * dx;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double dlo[3] = {-0.5 * w, -0.5 * height, 0}, dhi[3] = {0.5 * w, 1.5 * height, 0};
    const int per[3] = {1, 0, 0};
    check(sim, sph_set_domain(sim, dlo, dhi, per));
    const double lo[3] = {-0.5 * w, 0, 0}, hi[3] = {0.5 * w, height, 0};
    check(sim, sph_add_block(sim, "specimen", mat, lo, hi, dx, &specimen));
    const double plo[3] = {-0.5 * w, -3 * dx, 0}, phi[3] = {0.5 * w, 0, 0};
    check(sim, sph_add_block(sim, "plate", mat, plo, phi, dx, &plate));
    check(sim, sph_set_motion(sim, plate, SPH_MOTION_FIXED, NULL));
    if (with_piston) {
        const double tlo[3] = {-0.5 * w, height, 0}, thi[3] = {0.5 * w, height + 3 * dx, 0};
        const double v[3] = {0, -speed, 0};
        check(sim, sph_add_block(sim, "piston", mat, tlo, thi, dx, &piston));
        check(sim, sph_set_motion(sim, piston, SPH_MOTION_VELOCITY, v));
    }
    return sim;
}

/* Time at which sigma_yy at a probe first falls below `level`, linearly
 * interpolated between steps; NAN if never. */
static double crossing(double t0, double s0, double t1, double s1, double level)
{
    return t0 + (level - s0) * (t1 - t0) / (s1 - s0);
}

static void front_speed_and_stress_jump_match_plane_wave(void **state)
{
    (void)state;
    const double dx = 1e-3, H = 0.1, v = 0.1;
    const double c_p = p_wave_speed();
    const double jump = -PAPER_RHO0 * c_p * v; /* sigma_yy behind the front */
    sph_sim *sim = periodic_strip(dx, H, v, 1);
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0"));
    const double y1 = 0.08, y2 = 0.04;
    const double p1[2] = {0.0, y1}, p2[2] = {0.0, y2};
    int k1, k2;
    check(sim, sph_add_probe(sim, "upper", p1, &k1));
    check(sim, sph_add_probe(sim, "lower", p2, &k2));
    double vals[8], prev[2] = {0, 0}, t_prev = 0, arrival[2] = {NAN, NAN};
    double plateau = 0;
    const double t_end = 0.9 * H / c_p; /* before the front reaches the plate */
    while (sph_time(sim) < t_end) {
        check(sim, sph_run(sim, 1));
        const double t = sph_time(sim);
        for (int k = 0; k < 2; ++k) {
            check(sim, sph_probe_sample(sim, k, vals));
            const double syy = vals[3];
            if (isnan(arrival[k]) && syy < 0.5 * jump)
                arrival[k] = crossing(t_prev, prev[k], t, syy, 0.5 * jump);
            prev[k] = syy;
        }
        /* the upper probe long after the front: the plateau */
        if (t > (H - y1) / c_p + 0.4 * (y1 - y2) / c_p && t < (H - y2) / c_p)
            plateau = prev[0];
        t_prev = t;
    }
    assert_false(isnan(arrival[0]));
    assert_false(isnan(arrival[1]));
    const double speed = (y1 - y2) / (arrival[1] - arrival[0]);
    print_message("front speed %.1f m/s (c_p = %.1f m/s), plateau %.4g Pa (rho0 c_p v = %.4g Pa)\n",
                  speed, c_p, plateau, jump);
    assert_close(speed, c_p, 0.03 * c_p, "front speed");
    assert_close(plateau, jump, 0.05 * fabs(jump), "stress jump behind the front");
    sph_destroy(sim);
}

static void periodic_column_settles_to_static_gravity_field(void **state)
{
    (void)state;
    const double dx = 1e-3, H = 0.04, g = 9.81;
    sph_sim *sim = periodic_strip(dx, H, 0.0, 0);
    check(sim, sph_effect(sim, "gravity", "gy=-9.81"));
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0"));
    /* damping near critical for the lowest mode omega_1 = pi c_p / (2H) */
    const double omega1 = M_PI * p_wave_speed() / (2 * H);
    char damping[64];
    snprintf(damping, sizeof damping, "rate=%.6g", 2.0 * omega1);
    check(sim, sph_effect(sim, "damping", damping));
    int probes[7];
    for (int k = 0; k < 7; ++k) {
        const double p[2] = {0.0, (0.2 + 0.1 * k) * H};
        char name[8];
        snprintf(name, sizeof name, "y%d", k);
        check(sim, sph_add_probe(sim, name, p, &probes[k]));
    }
    /* 40 lowest-mode periods */
    check(sim, sph_run_until(sim, 40 * 2 * M_PI / omega1));
    for (int k = 0; k < 7; ++k) {
        double vals[8];
        check(sim, sph_probe_sample(sim, probes[k], vals));
        const double y = (0.2 + 0.1 * k) * H;
        const double exact = -PAPER_RHO0 * g * (H - y); /* static column */
        assert_close(vals[3], exact, 0.03 * fabs(exact), "sigma_yy of the settled column");
    }
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(front_speed_and_stress_jump_match_plane_wave),
        cmocka_unit_test(periodic_column_settles_to_static_gravity_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
