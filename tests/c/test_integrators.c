/*
 * Time integrators through the registry: selection and errors, the steps
 * that land on a time, and the leapfrog's properties against derived
 * truths: second order in time, total energy of an undamped vibration
 * kept (symplectic), Improved Euler's growing without viscosity, a failed
 * step undone, prescribed motions exact, stress turned objectively with a
 * rotation to second order.
 */
#include "helpers.h"

#define assert_refused(sim, call, status, needle)                                               \
    do {                                                                                        \
        const sph_status st_ = (call);                                                          \
        if (st_ != (status) || !strstr(sph_errmsg(sim), (needle))) {                            \
            print_error("%s: status %d (%s), message '%s'; expected %d and '%s'\n", #call, st_, \
                        sph_status_name(st_), sph_errmsg(sim), (status), (needle));             \
            fail();                                                                             \
        }                                                                                       \
    } while (0)

static void registry_selects_and_describes_integrators(void **state)
{
    (void)state;
    assert_string_equal(sph_integrator_names(), "improved_euler leapfrog");
    sph_sim *sim = free_block_2d(8, 8, 1e-3);
    assert_string_equal(sph_integrator_name(sim), "improved_euler");
    const double stable_ie = sph_stable_dt(sim), default_ie = sph_default_dt(sim);
    assert_refused(sim, sph_set_integrator(sim, "verlet"), SPH_ERR_ARGUMENT,
                   "integrator 'verlet' is unknown; known: improved_euler leapfrog");
    assert_refused(sim, sph_set_integrator(sim, NULL), SPH_ERR_ARGUMENT, "(null)");
    assert_string_equal(sph_integrator_name(sim), "improved_euler");

    sph_integrator_info ie, lf;
    check(sim, sph_integrator_info_get(sim, NULL, &ie));
    check(sim, sph_integrator_info_get(sim, "leapfrog", &lf));
    assert_string_equal(ie.name, "improved_euler");
    assert_int_equal(ie.evaluations, 2);
    assert_int_equal(ie.saved_values, 2 + 1 + 4); /* v, rho, S in 2D */
    assert_int_equal(lf.carries_rates, 1);
    check(sim, sph_effect(sim, "xsph", "epsilon=0.5"));
    check(sim, sph_integrator_info_get(sim, NULL, &ie));
    assert_int_equal(ie.saved_values, 2 + 1 + 4 + 2); /* and the XSPH velocity */

    /* the stable and default steps are the integrator's */
    check(sim, sph_set_integrator(sim, "leapfrog"));
    assert_string_equal(sph_integrator_name(sim), "leapfrog");
    assert_close(sph_stable_dt(sim), lf.stable_factor * stable_ie, 1e-15 * stable_ie,
                 "leapfrog stable step");
    assert_close(sph_default_dt(sim), lf.default_factor / ie.default_factor * default_ie,
                 1e-15 * default_ie, "leapfrog default step");
    /* a step set for the leapfrog above Improved Euler's limit blocks going back */
    check(sim, sph_set_dt(sim, 1.5 * stable_ie, 0));
    assert_refused(sim, sph_set_integrator(sim, "improved_euler"), SPH_ERR_STATE,
                   "exceeds its stability limit");
    assert_string_equal(sph_integrator_name(sim), "leapfrog");
    sph_destroy(sim);
}

static void steps_until_describes_run_until(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(6, 6, 1e-3);
    check(sim, sph_set_dt(sim, 1e-7, 0));
    long whole;
    double last;
    check(sim, sph_steps_until(sim, 1.05e-6, &whole, &last));
    assert_int_equal(whole, 10);
    assert_close(last, 0.05e-6, 1e-18, "last step");
    check(sim, sph_run_until(sim, 1.05e-6));
    assert_int_equal(sph_step_count(sim), 11);
    assert_true(sph_time(sim) == 1.05e-6);
    /* three steps' worth: the third may be a step of dt up to rounding */
    check(sim, sph_steps_until(sim, sph_time(sim) + 3e-7, &whole, &last));
    assert_int_equal(whole + (last > 0.0), 3);
    assert_true(last == 0.0 || fabs(last - 1e-7) < 1e-15);
    check(sim, sph_steps_until(sim, sph_time(sim), &whole, &last));
    assert_int_equal(whole, 0);
    assert_true(last == 0.0);
    assert_refused(sim, sph_steps_until(sim, 0.0, &whole, &last), SPH_ERR_ARGUMENT, "until t=0");
    sph_destroy(sim);
}

/* A doubly periodic box of n x m particles, spacing dx, with the
 * longitudinal standing-wave velocity v_x = V sin(2 pi x / L), L = n dx. */
static sph_sim *periodic_wave_box(int n, int m, double dx, double V, const char *integrator)
{
    sph_sim *sim = new_sim(2);
    const double L = n * dx;
    const double lo[3] = {0, 0, 0}, hi[3] = {L, m * dx, 0};
    const int periodic[3] = {1, 1, 0};
    int mat, body;
    check(sim, sph_set_domain(sim, lo, hi, periodic));
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    check(sim, sph_add_block(sim, "box", mat, lo, hi, dx, &body));
    check(sim, sph_set_integrator(sim, integrator));
    check(sim, sph_set_threads(sim, 1)); /* small: one thread is fastest */
    double *x = field_ptr(sim, SPH_FIELD_POSITION), *v = field_ptr(sim, SPH_FIELD_VELOCITY);
    for (size_t a = 0; a < sph_particle_count(sim); ++a)
        v[2 * a] = V * sin(2.0 * M_PI * x[2 * a] / L);
    return sim;
}

static sph_sim *periodic_wave(int n, double dx, double V, const char *integrator)
{
    return periodic_wave_box(n, n, dx, V, integrator);
}

static double total_energy(sph_sim *sim)
{
    sph_energy_info e;
    check(sim, sph_energy(sim, 1, &e));
    return e.kinetic + e.elastic;
}

static void leapfrog_is_second_order_in_time(void **state)
{
    (void)state;
    const int n = 12;
    const double dx = 1e-3, V = 1e-2;
    sph_sim *probe = periodic_wave(n, dx, V, "leapfrog");
    const double dt0 = 0.5 * sph_default_dt(probe), t_end = 48 * dt0;
    sph_destroy(probe);
    double *ref = NULL, err[3];
    const int refine[4] = {64, 1, 2, 4};
    size_t count = 0;
    for (int k = 0; k < 4; ++k) {
        sph_sim *sim = periodic_wave(n, dx, V, "leapfrog");
        check(sim, sph_set_dt(sim, dt0 / refine[k], 0));
        check(sim, sph_run_until(sim, t_end));
        count = sph_particle_count(sim);
        double *v = field_ptr(sim, SPH_FIELD_VELOCITY);
        if (k == 0) {
            ref = malloc(2 * count * sizeof(double));
            memcpy(ref, v, 2 * count * sizeof(double));
        } else {
            double e2 = 0.0;
            for (size_t i = 0; i < 2 * count; ++i)
                e2 += (v[i] - ref[i]) * (v[i] - ref[i]);
            err[k - 1] = sqrt(e2 / (double)count);
        }
        sph_destroy(sim);
    }
    free(ref);
    const double order1 = log2(err[0] / err[1]), order2 = log2(err[1] / err[2]);
    print_message("leapfrog velocity error vs dt/64: %.3g %.3g %.3g (orders %.2f %.2f)\n", err[0],
                  err[1], err[2], order1, order2);
    assert_close(order1, 2.0, 0.2, "order of the leapfrog (dt vs dt/2)");
    assert_close(order2, 2.0, 0.2, "order of the leapfrog (dt/2 vs dt/4)");
}

static void leapfrog_keeps_the_energy_of_an_undamped_vibration(void **state)
{
    (void)state;
    /* a strip 64 dx long, periodic both ways: the wave's period L / c_p is
     * about 47 default steps; 100 periods without any dissipation */
    const int n = 64, m = 6;
    const double dx = 1e-3, V = 1e-2;
    sph_sim *sim = periodic_wave_box(n, m, dx, V, "leapfrog");
    sph_material_info mat;
    check(sim, sph_material_info_get(sim, 0, &mat));
    const double period = n * dx / mat.c_p;
    const double E0 = total_energy(sim);
    double worst = 0.0;
    for (int p = 1; p <= 100; ++p) {
        check(sim, sph_run_until(sim, p * period));
        worst = fmax(worst, fabs(total_energy(sim) / E0 - 1.0));
    }
    print_message("leapfrog: %ld steps, 100 periods, largest |E/E0 - 1| = %.3g\n",
                  sph_step_count(sim), worst);
    assert_true(worst < 0.01);
    sph_destroy(sim);

    /* Improved Euler without viscosity at its own default step: the energy
     * grows (the reason it needs artificial viscosity) */
    sim = periodic_wave_box(n, m, dx, V, "improved_euler");
    const sph_status st = sph_run_until(sim, 100 * period);
    const double growth = total_energy(sim) / E0 - 1.0;
    print_message("improved_euler: %ld steps, E/E0 - 1 = %.3g (%s)\n", sph_step_count(sim), growth,
                  st ? sph_errmsg(sim) : "ran 100 periods");
    assert_true(st == SPH_ERR_UNSTABLE || growth > 0.01);
    sph_destroy(sim);
}

static void leapfrog_undoes_a_failed_step(void **state)
{
    (void)state;
    for (int watchdog = 1; watchdog >= 0; --watchdog) {
        sph_sim *sim = free_block_2d(10, 10, 1e-3);
        check(sim, sph_set_integrator(sim, "leapfrog"));
        if (!watchdog)
            check(sim, sph_set_watchdog(sim, 0.0, 0.0, 0.0));
        field_ptr(sim, SPH_FIELD_DENSITY)[0] *= 1.01;
        check(sim, sph_set_dt(sim, 1.5 * sph_stable_dt(sim), 1));
        const sph_status st = sph_run(sim, 5000);
        assert_int_equal(st, watchdog ? SPH_ERR_UNSTABLE : SPH_ERR_NONFINITE);
        long step, particle;
        int body;
        const char *quantity;
        check(sim, sph_failure(sim, &step, &particle, &body, &quantity));
        assert_true(step >= 1 && particle >= 0 && particle < 100);
        assert_non_null(strstr(sph_errmsg(sim), quantity));
        assert_int_equal(sph_step_count(sim), step - 1);
        /* bit for bit the state of a run stopped before the failed step */
        sph_sim *ref = free_block_2d(10, 10, 1e-3);
        check(ref, sph_set_integrator(ref, "leapfrog"));
        if (!watchdog)
            check(ref, sph_set_watchdog(ref, 0.0, 0.0, 0.0));
        field_ptr(ref, SPH_FIELD_DENSITY)[0] *= 1.01;
        check(ref, sph_set_dt(ref, sph_dt(sim), 1));
        check(ref, sph_run(ref, step - 1));
        const size_t n = sph_particle_count(sim);
        const sph_field_id fields[4] = {SPH_FIELD_POSITION, SPH_FIELD_VELOCITY, SPH_FIELD_DENSITY,
                                        SPH_FIELD_DEVIATORIC_STRESS};
        double *got = malloc(4 * n * sizeof(double)), *want = malloc(4 * n * sizeof(double));
        for (int f = 0; f < 4; ++f) {
            check(sim, sph_field_copy(sim, fields[f], got));
            check(ref, sph_field_copy(ref, fields[f], want));
            const size_t count = n * (f == 2 ? 1 : f == 3 ? 4 : 2);
            assert_memory_equal(got, want, count * sizeof(double));
        }
        free(got);
        free(want);
        sph_destroy(ref);
        sph_destroy(sim);
    }
}

/* Runs split at any point give the same state as one run (the rates carried
 * from one run to the next are those of the state), and writing a field
 * makes the next run start afresh from it. */
static void leapfrog_runs_split_anywhere(void **state)
{
    (void)state;
    sph_sim *one = periodic_wave(12, 1e-3, 1e-2, "leapfrog");
    sph_sim *split = periodic_wave(12, 1e-3, 1e-2, "leapfrog");
    check(one, sph_effect(one, "artificial_viscosity", "alpha=1 beta=0"));
    check(split, sph_effect(split, "artificial_viscosity", "alpha=1 beta=0"));
    check(one, sph_run(one, 30));
    check(split, sph_run(split, 7));
    (void)field_ptr(split, SPH_FIELD_VELOCITY); /* a pointer handed out, nothing written */
    check(split, sph_run(split, 23));
    const size_t n = sph_particle_count(one);
    assert_memory_equal(field_ptr(one, SPH_FIELD_VELOCITY), field_ptr(split, SPH_FIELD_VELOCITY),
                        2 * n * sizeof(double));
    assert_memory_equal(field_ptr(one, SPH_FIELD_DEVIATORIC_STRESS),
                        field_ptr(split, SPH_FIELD_DEVIATORIC_STRESS), 4 * n * sizeof(double));
    sph_destroy(one);
    sph_destroy(split);
}

/* The stress of a prestressed body in prescribed rigid rotation turns
 * with it: S(t) = R(t) S_0 R(t)^T, with the velocity gradient exact (kernel
 * correction, linear velocity field) so that only the time integration of
 * the Jaumann rate dS/dt = S W^T + W S errs.  The leapfrog advances S with
 * the rate at the half step, whose stress is predicted from the previous
 * step's rates: second order, where a step without the predictor (S at the
 * start) is first order. */
static double rotated_stress_error(int steps, double angle)
{
    sph_sim *sim = new_sim(2);
    int mat, body;
    check(sim, sph_add_material_K_mu(sim, 2e3, 1e3, 1e3, &mat)); /* soft: long stable steps */
    const double lo[3] = {0, 0, 0}, hi[3] = {6e-3, 6e-3, 0}, centre[3] = {3e-3, 3e-3, 0};
    check(sim, sph_add_block(sim, "turning", mat, lo, hi, 1e-3, &body));
    check(sim, sph_effect(sim, "kernel_correction", ""));
    check(sim, sph_set_integrator(sim, "leapfrog"));
    check(sim, sph_set_threads(sim, 1));
    const double omega[3] = {0, 0, 200.0}, T = angle / omega[2];
    check(sim, sph_set_rotation(sim, body, centre, omega));
    check(sim, sph_set_dt(sim, T / steps, 0));
    const double S0[4] = {3.0, -1.0, -2.0, 1.5}; /* xx, yy, zz, xy (Pa) */
    const size_t n = sph_particle_count(sim);
    double *S = field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS);
    for (size_t a = 0; a < n; ++a)
        memcpy(S + 4 * a, S0, sizeof S0);
    check(sim, sph_run(sim, steps));
    const double c = cos(angle), s = sin(angle);
    const double exact[4] = {c * c * S0[0] + s * s * S0[1] - 2 * s * c * S0[3],
                             s * s * S0[0] + c * c * S0[1] + 2 * s * c * S0[3], S0[2],
                             s * c * (S0[0] - S0[1]) + (c * c - s * s) * S0[3]};
    S = field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS);
    double err = 0.0;
    for (size_t a = 0; a < n; ++a)
        for (int k = 0; k < 4; ++k)
            err = fmax(err, fabs(S[4 * a + k] - exact[k]));
    sph_destroy(sim);
    return err;
}

static void leapfrog_turns_stress_with_a_rotation_to_second_order(void **state)
{
    (void)state;
    const double angle = 1.0;
    double err[3];
    for (int k = 0; k < 3; ++k)
        err[k] = rotated_stress_error(20 << k, angle);
    const double order1 = log2(err[0] / err[1]), order2 = log2(err[1] / err[2]);
    print_message("rotated stress error: %.3g %.3g %.3g Pa (orders %.2f %.2f)\n", err[0], err[1],
                  err[2], order1, order2);
    assert_true(err[0] < 0.05); /* 5 % of the 1-3 Pa components after 1 rad in 20 steps */
    assert_close(order1, 2.0, 0.25, "order of the stress rotation (dt vs dt/2)");
    assert_close(order2, 2.0, 0.25, "order of the stress rotation (dt/2 vs dt/4)");
}

/* Prescribed motions under the leapfrog: a body at a constant velocity
 * moves by exactly v t, a rotating one stays on its arcs, a force-driven
 * free body accelerates as F / M. */
static void leapfrog_moves_prescribed_bodies_exactly(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat, a, b, c;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo1[3] = {0, 0, 0}, hi1[3] = {4e-3, 4e-3, 0};
    const double lo2[3] = {20e-3, 0, 0}, hi2[3] = {24e-3, 4e-3, 0};
    const double lo3[3] = {40e-3, 0, 0}, hi3[3] = {44e-3, 4e-3, 0};
    check(sim, sph_add_block(sim, "moving", mat, lo1, hi1, 1e-3, &a));
    check(sim, sph_add_block(sim, "turning", mat, lo2, hi2, 1e-3, &b));
    check(sim, sph_add_block(sim, "pushed", mat, lo3, hi3, 1e-3, &c));
    const double vel[3] = {0.5, -0.25, 0}, centre[3] = {22e-3, 2e-3, 0}, omega[3] = {0, 0, 40.0};
    const double force[3] = {0, 1e3, 0};
    check(sim, sph_set_motion(sim, a, SPH_MOTION_VELOCITY, vel));
    check(sim, sph_set_rotation(sim, b, centre, omega));
    check(sim, sph_set_motion(sim, c, SPH_MOTION_FORCE, force));
    check(sim, sph_set_integrator(sim, "leapfrog"));
    check(sim, sph_effect(sim, "kernel_correction", ""));
    const size_t n = sph_particle_count(sim);
    double *x0 = malloc(2 * n * sizeof(double));
    memcpy(x0, field_ptr(sim, SPH_FIELD_POSITION), 2 * n * sizeof(double));
    check(sim, sph_run(sim, 50));
    const double t = sph_time(sim);
    const double *x = field_ptr(sim, SPH_FIELD_POSITION), *v = field_ptr(sim, SPH_FIELD_VELOCITY);
    const double mass = PAPER_RHO0 * 16e-6, angle = omega[2] * t;
    for (size_t p = 0; p < 16; ++p) { /* body a: particles 0..15 */
        assert_close(x[2 * p], x0[2 * p] + vel[0] * t, 1e-15, "moving body x");
        assert_close(x[2 * p + 1], x0[2 * p + 1] + vel[1] * t, 1e-15, "moving body y");
    }
    for (size_t p = 16; p < 32; ++p) { /* body b: on the arc */
        const double rx = x0[2 * p] - centre[0], ry = x0[2 * p + 1] - centre[1];
        assert_close(x[2 * p], centre[0] + cos(angle) * rx - sin(angle) * ry, 1e-14,
                     "rotating body x");
        assert_close(x[2 * p + 1], centre[1] + sin(angle) * rx + cos(angle) * ry, 1e-14,
                     "rotating body y");
        assert_close(v[2 * p], -omega[2] * (x[2 * p + 1] - centre[1]), 1e-12, "rotating body vx");
    }
    for (size_t p = 32; p < 48; ++p) { /* body c: v = F/M t, y = F/(2M) t^2 */
        assert_close(v[2 * p + 1], force[1] / mass * t, 1e-9 * force[1] / mass * t,
                     "pushed body vy");
        assert_close(x[2 * p + 1] - x0[2 * p + 1], 0.5 * force[1] / mass * t * t,
                     1e-9 * force[1] / mass * t * t, "pushed body y");
    }
    free(x0);
    sph_destroy(sim);
}

/* The leapfrog's closing kick on caller arrays (the LAMMPS fix's call)
 * applies the watchdog: the lowest particle past a density or speed bound,
 * or with a non-finite velocity, is named. */
static void leapfrog_kick_on_caller_arrays_applies_the_watchdog(void **state)
{
    (void)state;
    int m;
    sph_sim *sim = external_particles_2d(&m);
    check(sim, sph_set_watchdog(sim, 0.1, 0.9, 1.1));
    const int material[3] = {m, m, m};
    for (int kind = 0; kind < 3; ++kind) {
        double v[6] = {0}, dv[6] = {0};
        double rho[3] = {PAPER_RHO0, PAPER_RHO0, PAPER_RHO0};
        int expect = kind == 2 ? 0 : kind + 1;
        if (kind == 0)
            rho[1] = 1.5 * PAPER_RHO0; /* density ratio 1.5 > 1.1 */
        else if (kind == 1)
            v[2 * 2 + 1] = 1e4; /* faster than 0.1 c_p */
        else
            dv[0] = NAN;
        long particle = -7;
        sph_status st =
            sph_leapfrog_end_strided(sim, 3, 1e-7, v, 2, rho, dv, NULL, material, &particle);
        assert_int_equal(st, kind == 2 ? SPH_ERR_NONFINITE : SPH_ERR_UNSTABLE);
        assert_int_equal(particle, expect);
    }
    sph_destroy(sim);
}

/* Two bodies far apart evolve as each would alone: a body added after a
 * run (every buffer of the run grows with the particle count) takes its
 * steps as in a handle of its own, the first body's steps go on as if
 * nothing had been added; for both integrators, with and without XSPH. */
static sph_sim *pushed_block(double x0, double vy, const char *name, int *body)
{
    sph_sim *sim = new_sim(2);
    int mat;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {x0, 0, 0}, hi[3] = {x0 + 6e-3, 5e-3, 0}, v[3] = {0, vy, 0};
    check(sim, sph_add_block(sim, name, mat, lo, hi, 1e-3, body));
    check(sim, sph_set_body_velocity(sim, *body, v));
    return sim;
}

static void body_added_after_a_run_runs_as_alone(void **state)
{
    (void)state;
    static const char *const names[2] = {"improved_euler", "leapfrog"};
    for (int k = 0; k < 4; ++k) {
        const char *integ = names[k % 2];
        const int xsph = k / 2;
        int a, b, a1, b1, mat = 0;
        sph_sim *sim = pushed_block(0.0, -1.0, "first", &a);
        sph_sim *alone_a = pushed_block(0.0, -1.0, "first", &a1);
        sph_sim *alone_b = pushed_block(50e-3, 2.0, "second", &b1);
        sph_sim *all[3] = {sim, alone_a, alone_b};
        for (int s = 0; s < 3; ++s) {
            check(all[s], sph_set_integrator(all[s], integ));
            check(all[s], sph_set_dt(all[s], 2e-8, 0));
            if (xsph)
                check(all[s], sph_effect(all[s], "xsph", "epsilon=0.5"));
        }
        check(sim, sph_run(sim, 5));
        const size_t na = sph_particle_count(sim);
        /* a body 50 mm away: twice the particles the run was sized for */
        const double lo[3] = {50e-3, 0, 0}, hi[3] = {56e-3, 5e-3, 0}, v[3] = {0, 2.0, 0};
        check(sim, sph_add_block(sim, "second", mat, lo, hi, 1e-3, &b));
        check(sim, sph_set_body_velocity(sim, b, v));
        assert_true(sph_particle_count(sim) == 2 * na);
        check(sim, sph_run(sim, 5));
        check(alone_a, sph_run(alone_a, 10));
        check(alone_b, sph_run(alone_b, 5));
        const double *x = field_ptr(sim, SPH_FIELD_POSITION);
        const double *v_all = field_ptr(sim, SPH_FIELD_VELOCITY);
        const double *xa = field_ptr(alone_a, SPH_FIELD_POSITION);
        const double *xb = field_ptr(alone_b, SPH_FIELD_POSITION);
        const double *vb = field_ptr(alone_b, SPH_FIELD_VELOCITY);
        for (size_t p = 0; p < 2 * na; ++p) {
            assert_close(x[p], xa[p], 1e-15, integ);
            assert_close(x[2 * na + p], xb[p], 1e-15, integ);
            assert_close(v_all[2 * na + p], vb[p], 1e-9, integ);
        }
        for (int s = 0; s < 3; ++s)
            sph_destroy(all[s]);
    }
}

/* The deprecated sph_heun_* aliases (removed in 0.3.0) give bit for bit what
 * the sph_improved_euler_* stages they name give, on the same inputs:
 * a pushed 6 x 5 block with given rates, both stages, plain and strided. */
#if defined(__GNUC__) || defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
static void heun_aliases_equal_improved_euler_stages(void **state)
{
    (void)state;
    int body;
    sph_sim *sim = pushed_block(0.0, -1.0, "block", &body);
    const size_t n = sph_particle_count(sim);
    assert_int_equal(n, 30);
    /* rates of any finite values: the stages integrate what they are given */
    double *dv = malloc(2 * n * sizeof *dv), *drho = malloc(n * sizeof *drho),
           *dS = malloc(4 * n * sizeof *dS);
    for (size_t k = 0; k < 4 * n; ++k) {
        if (k < 2 * n)
            dv[k] = 1e3 * sin((double)k);
        if (k < n)
            drho[k] = 1e2 * cos((double)k);
        dS[k] = 1e6 * sin(2.0 * (double)k + 1.0);
    }
    sph_rates r = {.dv_dt = dv, .drho_dt = drho, .dS_dt = dS, .dx_dt = NULL};
    int *mat = calloc(n, sizeof *mat);
    const int *material = mat;
    for (int stride = 2; stride <= 3; ++stride) {
        /* a: new names, b: deprecated aliases */
        double *xa = calloc(3 * n, sizeof *xa), *va = calloc(3 * n, sizeof *va);
        double *xb = calloc(3 * n, sizeof *xb), *vb = calloc(3 * n, sizeof *vb);
        double *rhoa = malloc(n * sizeof *rhoa), *rhob = malloc(n * sizeof *rhob);
        double *Sa = malloc(4 * n * sizeof *Sa), *Sb = malloc(4 * n * sizeof *Sb);
        double *sa = malloc(7 * n * sizeof *sa), *sb = malloc(7 * n * sizeof *sb);
        const double *x0 = field_ptr(sim, SPH_FIELD_POSITION),
                     *v0 = field_ptr(sim, SPH_FIELD_VELOCITY);
        for (size_t a = 0; a < n; ++a)
            for (int i = 0; i < 2; ++i) {
                xa[a * stride + i] = xb[a * stride + i] = x0[2 * a + i];
                va[a * stride + i] = vb[a * stride + i] = v0[2 * a + i];
            }
        memcpy(rhoa, field_ptr(sim, SPH_FIELD_DENSITY), n * sizeof *rhoa);
        memcpy(rhob, rhoa, n * sizeof *rhob);
        memcpy(Sa, field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS), 4 * n * sizeof *Sa);
        memcpy(Sb, Sa, 4 * n * sizeof *Sb);
        long pa = 0, pb = 0;
        if (stride == 2) {
            check(sim, sph_improved_euler_predict(sim, n, 1e-8, xa, va, rhoa, Sa, &r, NULL, sa));
            check(sim, sph_heun_predict(sim, n, 1e-8, xb, vb, rhob, Sb, &r, NULL, sb));
            check(sim, sph_improved_euler_correct(sim, n, 1e-8, xa, va, rhoa, Sa, &r, NULL, sa));
            check(sim, sph_heun_correct(sim, n, 1e-8, xb, vb, rhob, Sb, &r, NULL, sb));
        } else {
            check(sim, sph_improved_euler_predict_strided(sim, n, 1e-8, xa, va, 3, rhoa, Sa, &r,
                                                          NULL, sa));
            check(sim, sph_heun_predict_strided(sim, n, 1e-8, xb, vb, 3, rhob, Sb, &r, NULL, sb));
            check(sim, sph_improved_euler_correct_strided(sim, n, 1e-8, xa, va, 3, rhoa, Sa, &r,
                                                          NULL, material, sa, &pa));
            check(sim, sph_heun_correct_strided(sim, n, 1e-8, xb, vb, 3, rhob, Sb, &r, NULL,
                                                material, sb, &pb));
            assert_int_equal(pa, pb);
        }
        assert_memory_equal(xa, xb, 3 * n * sizeof *xa);
        assert_memory_equal(va, vb, 3 * n * sizeof *va);
        assert_memory_equal(rhoa, rhob, n * sizeof *rhoa);
        assert_memory_equal(Sa, Sb, 4 * n * sizeof *Sa);
        /* the stages moved the block: the comparison is not of untouched arrays */
        assert_true(xa[1] != x0[1]);
        free(xa), free(va), free(xb), free(vb), free(rhoa), free(rhob);
        free(Sa), free(Sb), free(sa), free(sb);
    }
    free(mat);
    free(dv), free(drho), free(dS);
    sph_destroy(sim);
}
#if defined(__GNUC__) || defined(__clang__)
#pragma GCC diagnostic pop
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(registry_selects_and_describes_integrators),
        cmocka_unit_test(steps_until_describes_run_until),
        cmocka_unit_test(leapfrog_is_second_order_in_time),
        cmocka_unit_test(leapfrog_keeps_the_energy_of_an_undamped_vibration),
        cmocka_unit_test(leapfrog_undoes_a_failed_step),
        cmocka_unit_test(leapfrog_runs_split_anywhere),
        cmocka_unit_test(leapfrog_moves_prescribed_bodies_exactly),
        cmocka_unit_test(leapfrog_turns_stress_with_a_rotation_to_second_order),
        cmocka_unit_test(leapfrog_kick_on_caller_arrays_applies_the_watchdog),
        cmocka_unit_test(body_added_after_a_run_runs_as_alone),
        cmocka_unit_test(heun_aliases_equal_improved_euler_stages),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
