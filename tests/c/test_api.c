/* The public API: bad input is refused with a message naming the value;
 * runs stop on non-finite values with step, particle and quantity;
 * results do not depend on the number of threads. */
#include "helpers.h"

/* The call must fail with `status` and a message containing `needle`. */
#define assert_refused(sim, call, status, needle)                                               \
    do {                                                                                        \
        const sph_status st_ = (call);                                                          \
        if (st_ != (status) || !strstr(sph_errmsg(sim), (needle))) {                            \
            print_error("%s: status %d (%s), message '%s'; expected %d and '%s'\n", #call, st_, \
                        sph_status_name(st_), sph_errmsg(sim), (status), (needle));             \
            fail();                                                                             \
        }                                                                                       \
    } while (0)

static void bad_materials_are_refused(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int m;
    assert_refused(sim, sph_add_material_K_mu(sim, -1e9, 1e9, 2300, &m), SPH_ERR_ARGUMENT,
                   "K=-1e+09");
    assert_refused(sim, sph_add_material_K_mu(sim, 0.0, 1e9, 2300, &m), SPH_ERR_ARGUMENT, "K=0");
    assert_refused(sim, sph_add_material_K_mu(sim, 1e9, -2e9, 2300, &m), SPH_ERR_ARGUMENT,
                   "mu=-2e+09");
    assert_refused(sim, sph_add_material_K_mu(sim, 1e9, 1e9, -5, &m), SPH_ERR_ARGUMENT, "rho0=-5");
    assert_refused(sim, sph_add_material_E_nu(sim, 1e9, 0.5, 2300, &m), SPH_ERR_ARGUMENT, "nu=0.5");
    assert_refused(sim, sph_add_material_E_nu(sim, 1e9, -1.0, 2300, &m), SPH_ERR_ARGUMENT, "nu=-1");
    assert_refused(sim, sph_add_material_K_nu(sim, 1e9, 0.7, 2300, &m), SPH_ERR_ARGUMENT, "nu=0.7");
    assert_refused(sim, sph_add_material_E_nu(sim, -3.0, 0.3, 2300, &m), SPH_ERR_ARGUMENT, "E=-3");
    /* a handle without bodies (for external particles) knows its step once
     * the spacing is set: 0.5 h / c0 */
    assert_true(sph_default_dt(sim) == 0.0);
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &m));
    check(sim, sph_set_spacing(sim, 1e-3));
    assert_close(sph_default_dt(sim), 0.5 * 1.2e-3 / sqrt(PAPER_K / PAPER_RHO0), 1e-18,
                 "default dt without bodies");
    /* a valid (E, nu) pair gives back nu by eq. (10) */
    check(sim, sph_add_material_E_nu(sim, 70e9, 0.33, 2700, &m));
    sph_material_info info;
    check(sim, sph_material_info_get(sim, m, &info));
    assert_close(info.poisson_ratio, 0.33, 1e-12, "nu from eq. (10)");
    assert_close(info.youngs_modulus, 70e9, 1e-3, "E back");
    sph_destroy(sim);
}

static void bad_bodies_are_refused(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int m, b;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &m));
    const double lo[3] = {0, 0, 0}, hi[3] = {0.01, 0.01, 0};
    assert_refused(sim, sph_add_block(sim, "a", m, lo, hi, -1e-3, &b), SPH_ERR_ARGUMENT,
                   "dx=-0.001");
    assert_refused(sim, sph_add_block(sim, "a", m, lo, hi, 0.0, &b), SPH_ERR_ARGUMENT, "dx=0");
    assert_refused(sim, sph_add_block(sim, "a", 3, lo, hi, 1e-3, &b), SPH_ERR_ARGUMENT,
                   "material=3");
    assert_refused(sim, sph_add_particles(sim, "empty", m, 0, lo, NULL, 1e-3, &b), SPH_ERR_ARGUMENT,
                   "empty");
    check(sim, sph_add_block(sim, "a", m, lo, hi, 1e-3, &b));
    /* a second block over the first */
    const double lo2[3] = {0.005, 0.005, 0}, hi2[3] = {0.015, 0.015, 0};
    assert_refused(sim, sph_add_block(sim, "b", m, lo2, hi2, 1e-3, &b), SPH_ERR_ARGUMENT,
                   "overlaps body 'a'");
    assert_refused(sim, sph_add_block(sim, "a", m, lo2, hi2, 1e-3, &b), SPH_ERR_ARGUMENT,
                   "'a' is already used");
    assert_int_equal(sph_body_count(sim), 1);
    /* touching but not overlapping is fine */
    const double lo3[3] = {0.01, 0, 0}, hi3[3] = {0.02, 0.01, 0};
    check(sim, sph_add_block(sim, "b", m, lo3, hi3, 1e-3, &b));
    /* a domain that leaves particles out */
    const double dlo[3] = {0, 0, 0}, dhi[3] = {0.015, 0.01, 0};
    assert_refused(sim, sph_set_domain(sim, dlo, dhi, NULL), SPH_ERR_ARGUMENT,
                   "leaves out particle");
    /* rotations: about z in 2D, finite, set by sph_set_rotation, not periodic */
    const double c[3] = {0.005, 0.005, 0}, about_x[3] = {3.0, 0, 0}, about_z[3] = {0, 0, 3.0};
    const double bad_c[3] = {NAN, 0, 0}, bad_w[3] = {0, 0, INFINITY};
    assert_refused(sim, sph_set_rotation(sim, b, c, about_x), SPH_ERR_ARGUMENT, "omega_x=3");
    assert_refused(sim, sph_set_rotation(sim, b, bad_c, about_z), SPH_ERR_ARGUMENT, "centre x=nan");
    assert_refused(sim, sph_set_rotation(sim, b, c, bad_w), SPH_ERR_ARGUMENT, "omega_z=inf");
    assert_refused(sim, sph_set_motion(sim, b, SPH_MOTION_ROTATION, about_z), SPH_ERR_ARGUMENT,
                   "sph_set_rotation");
    check(sim, sph_set_rotation(sim, b, c, about_z));
    assert_refused(sim, sph_set_body_velocity(sim, b, about_z), SPH_ERR_STATE, "prescribed motion");
    const double plo[3] = {-0.1, -0.1, 0}, phi[3] = {0.1, 0.1, 0};
    const int periodic[3] = {0, 1, 0};
    check(sim, sph_set_domain(sim, plo, phi, periodic));
    assert_refused(sim, sph_run(sim, 1), SPH_ERR_STATE, "y is periodic");
    sph_destroy(sim);

    sph_sim *bad = NULL;
    assert_int_equal(sph_create(4, &bad), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(bad), "dimension=4"));
    sph_destroy(bad);
}

static void bad_effects_and_time_steps_are_refused(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(10, 10, 1e-3);
    assert_refused(sim, sph_effect(sim, "viscosity", "alpha=1"), SPH_ERR_ARGUMENT,
                   "unknown effect 'viscosity'");
    assert_refused(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 gamma=2"),
                   SPH_ERR_ARGUMENT, "unknown parameter 'gamma'");
    assert_refused(sim, sph_effect(sim, "artificial_viscosity", "alpha=-1"), SPH_ERR_ARGUMENT,
                   "alpha=-1");
    assert_refused(sim, sph_effect(sim, "artificial_viscosity", "alpha=x"), SPH_ERR_ARGUMENT,
                   "alpha='x'");
    assert_refused(sim, sph_effect(sim, "damping", ""), SPH_ERR_ARGUMENT, "rate=");
    assert_int_equal(sph_effect_is_on(sim, "artificial_viscosity"), 0);
    assert_int_equal(sph_effect_is_on(sim, "nonsense"), -1);
    /* a step above the stability limit needs the override */
    const double limit = sph_stable_dt(sim);
    assert_true(limit > sph_default_dt(sim));
    assert_refused(sim, sph_set_dt(sim, 1.5 * limit, 0), SPH_ERR_ARGUMENT,
                   "exceeds the stability limit");
    check(sim, sph_set_dt(sim, 1.5 * limit, 1));
    assert_refused(sim, sph_set_dt(sim, -1e-7, 1), SPH_ERR_ARGUMENT, "dt=-1e-07");
    assert_refused(sim, sph_run(sim, -3), SPH_ERR_ARGUMENT, "steps=-3");
    assert_refused(sim, sph_run_until(sim, -1.0), SPH_ERR_ARGUMENT, "t=-1");
    sph_destroy(sim);
}

static void non_finite_value_stops_run_with_step_particle_and_quantity(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(10, 10, 1e-3);
    check(sim, sph_run(sim, 3));
    double *S = field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS);
    S[4 * 0 + 3] = NAN; /* particle 0, the lowest index, goes bad first */
    assert_refused(sim, sph_run(sim, 5), SPH_ERR_NONFINITE, "step 4");
    long step, particle;
    int body;
    const char *quantity;
    check(sim, sph_failure(sim, &step, &particle, &body, &quantity));
    assert_int_equal(step, 4);
    assert_int_equal(particle, 0);
    assert_int_equal(body, 0);
    assert_non_null(strstr(sph_errmsg(sim), "particle 0 of body 'block'"));
    assert_non_null(strstr(sph_errmsg(sim), quantity));
    assert_int_equal(sph_step_count(sim), 3); /* the bad step was not counted */
    sph_destroy(sim);

    /* a real blow-up, twenty times the stable step: the watchdog stops it
     * on a runaway speed or density before anything overflows */
    for (int watchdog = 1; watchdog >= 0; --watchdog) {
        sim = free_block_2d(10, 10, 1e-3);
        if (!watchdog)
            check(sim, sph_set_watchdog(sim, 0.0, 0.0, 0.0));
        double *rho = field_ptr(sim, SPH_FIELD_DENSITY);
        rho[0] *= 1.01;
        check(sim, sph_set_dt(sim, 20 * sph_stable_dt(sim), 1));
        const sph_status st = sph_run(sim, 5000);
        assert_int_equal(st, watchdog ? SPH_ERR_UNSTABLE : SPH_ERR_NONFINITE);
        check(sim, sph_failure(sim, &step, &particle, &body, &quantity));
        assert_true(step >= 1 && step <= 5000);
        assert_true(particle >= 0 && particle < 100);
        if (watchdog)
            assert_true(!strcmp(quantity, "speed") || !strcmp(quantity, "density ratio"));
        assert_non_null(strstr(sph_errmsg(sim), quantity));
        /* the failed step was undone: the state is the one after step - 1,
         * bit for bit the same as a run stopped there */
        assert_int_equal(sph_step_count(sim), step - 1);
        sph_sim *ref = free_block_2d(10, 10, 1e-3);
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
    sim = free_block_2d(4, 4, 1e-3);
    assert_refused(sim, sph_set_watchdog(sim, 1.0, 1.5, 2.0), SPH_ERR_ARGUMENT,
                   "min_density_ratio=1.5");
    sph_destroy(sim);
}

static void particle_leaving_the_domain_stops_the_run(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(6, 6, 1e-3);
    const double lo[3] = {-0.004, -0.004, 0}, hi[3] = {0.004, 0.004, 0};
    check(sim, sph_set_domain(sim, lo, hi, NULL));
    const double v[2] = {100.0, 0.0};
    check(sim, sph_set_body_velocity(sim, 0, v));
    assert_refused(sim, sph_run(sim, 1000), SPH_ERR_DOMAIN, "left the domain along x");
    sph_destroy(sim);
}

/* A force-driven rigid body summed in parts (as over MPI ranks): every
 * member gets one acceleration, and the body's momentum changes by the
 * applied force plus the forces on its members (Newton's second law). */
static void rigid_force_body_obeys_newton_in_parts(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    const double mass[5] = {1.0, 2.0, 3.0, 4.0, 5.0};
    const double dv0[10] = {1.0, -2.0, 0.5, 4.0, -3.0, 1.0, 7.0, 7.0, 2.0, 0.25};
    double dv[10];
    memcpy(dv, dv0, sizeof dv);
    const unsigned char member[5] = {1, 1, 0, 1, 1};
    const double applied[2] = {10.0, -20.0};
    double sums[3] = {0.0, 0.0, 0.0};
    check(sim, sph_rigid_force_sum(sim, 2, mass, dv, member, sums));             /* "rank 0" */
    check(sim, sph_rigid_force_sum(sim, 3, mass + 2, dv + 4, member + 2, sums)); /* "rank 1" */
    assert_close(sums[0], 12.0, 0.0, "member mass");
    check(sim, sph_rigid_force_apply(sim, 2, applied, sums, member, dv));
    check(sim, sph_rigid_force_apply(sim, 3, applied, sums, member + 2, dv + 4));
    for (int i = 0; i < 2; ++i) {
        double before = applied[i], after = 0.0;
        for (int a = 0; a < 5; ++a) {
            if (!member[a])
                continue;
            before += mass[a] * dv0[2 * a + i];
            after += mass[a] * dv[2 * a + i];
            assert_close(dv[2 * a + i], dv[i], 0.0, "one acceleration");
        }
        assert_close(after, before, 1e-13 * fabs(before), "momentum balance");
    }
    assert_close(dv[4], dv0[4], 0.0, "non-member untouched");
    assert_close(dv[5], dv0[5], 0.0, "non-member untouched");
    const double none[3] = {0.0, 0.0, 0.0};
    assert_refused(sim, sph_rigid_force_apply(sim, 2, applied, none, member, dv), SPH_ERR_ARGUMENT,
                   "total mass 0");
    sph_destroy(sim);
}

/* The paper scene after `steps` steps on `threads` threads; with
 * `rebuild_at` > 0 the neighbour list is also rebuilt after that many
 * steps (access to the positions for writing invalidates it).  Returns x and S. */
static size_t paper_state(const char *integrator, int threads, long steps, long rebuild_at,
                          double **x, double **S)
{
    sph_sim *sim = new_sim(2);
    check(sim, sph_set_threads(sim, threads));
    check(sim, sph_set_integrator(sim, integrator));
    check(sim, sph_build_paper_scene(sim, 4e-3, 1.5e-3, 0, NULL));
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0"));
    const size_t n = sph_particle_count(sim);
    *x = malloc(n * 2 * sizeof(double));
    *S = malloc(n * 4 * sizeof(double));
    if (rebuild_at > 0) {
        double *pos;
        check(sim, sph_run(sim, rebuild_at));
        check(sim, sph_field(sim, SPH_FIELD_POSITION, &pos, NULL, NULL)); /* list rebuilt */
        steps -= rebuild_at;
    }
    check(sim, sph_run(sim, steps));
    check(sim, sph_field_copy(sim, SPH_FIELD_POSITION, *x));
    check(sim, sph_field_copy(sim, SPH_FIELD_DEVIATORIC_STRESS, *S));
    sph_destroy(sim);
    return n;
}

static void threads_and_rebuilds_agree(const char *integrator)
{
    double *x0, *S0;
    const size_t n = paper_state(integrator, 1, 60, 0, &x0, &S0);
    double smax = 0;
    for (size_t i = 0; i < 4 * n; ++i)
        smax = fmax(smax, fabs(S0[i]));
    assert_true(smax > 0);
    for (int variant = 0; variant < 3; ++variant) {
        double *x, *S;
        const int threads = variant == 0 ? 2 : variant == 1 ? 3 : 1;
        paper_state(integrator, threads, 60, variant == 2 ? 23 : 0, &x, &S);
        assert_memory_equal(x, x0, 2 * n * sizeof(double));
        assert_memory_equal(S, S0, 4 * n * sizeof(double));
        free(x);
        free(S);
    }
    free(x0);
    free(S0);
}

/* Bitwise the same results on 1, 2 and 3 threads (the pair pass sums in an
 * order fixed by the particle count alone), and whenever the neighbour list
 * is rebuilt (pairs of the skin add exact zeros), with either integrator
 * (the leapfrog's continuity and momentum passes alike). */
static void results_do_not_depend_on_threads_or_rebuilds(void **state)
{
    for (int k = 0; k < 2; ++k)
        threads_and_rebuilds_agree(k ? "leapfrog" : "improved_euler");
    (void)state;
}

static int stop_at_five(const sph_sim *sim, void *user)
{
    ++*(int *)user;
    return sph_step_count(sim) >= 5;
}

/* Calls on external arrays take a writable handle and leave their message
 * on it like every other call. */
static void failing_low_level_calls_leave_a_message(void **state)
{
    (void)state;
    int m;
    sph_sim *sim = external_particles_2d(&m);
    double x[2] = {0}, v[2] = {0}, rho = PAPER_RHO0, S[4] = {0}, saved[7];
    double dv[2] = {0}, drho = 0, dS[4] = {0};
    sph_rates r = {.dv_dt = dv, .drho_dt = &drho, .dS_dt = dS, .dx_dt = NULL};
    assert_refused(sim, sph_improved_euler_predict(sim, 1, -1.0, x, v, &rho, S, &r, NULL, saved),
                   SPH_ERR_ARGUMENT, "dt=-1");
    assert_refused(sim,
                   sph_improved_euler_correct_strided(sim, 1, 1e-7, x, v, 1, &rho, S, &r, NULL, &m,
                                                      saved, NULL),
                   SPH_ERR_ARGUMENT, "stride=1");
    const int bad_material = 5;
    assert_refused(sim, sph_derived_fields(sim, 1, &rho, S, &bad_material, NULL, NULL, NULL),
                   SPH_ERR_ARGUMENT, "material 5");
    sph_material_info info;
    assert_refused(sim, sph_material_info_get(sim, 3, &info), SPH_ERR_ARGUMENT, "material=3");
    assert_refused(sim, sph_body_find(sim, "anvil", &m), SPH_ERR_ARGUMENT, "'anvil'");
    double lo[3] = {0, 0, 0}, hi[3] = {2e-3, 2e-3, 0};
    int body;
    check(sim, sph_add_block(sim, "block", m, lo, hi, 1e-3, &body));
    assert_refused(sim, sph_body_ids(sim, NULL), SPH_ERR_ARGUMENT, "out");
    sph_destroy(sim);
}

/* The effect registry: every listed effect switches on with its defaults
 * (or fails naming its required parameter), is reported by
 * sph_effect_names() and the describe text, and refuses a value just
 * outside each bounded range, naming the key. */
static void every_registered_effect_honours_its_ranges(void **state)
{
    (void)state;
    const int count = sph_effect_count();
    assert_true(count >= 6);
    size_t names_length = 0;
    for (int e = 0; e < count; ++e) {
        sph_effect_info info;
        check(NULL, sph_effect_info_get(e, &info));
        assert_non_null(strstr(sph_effect_names(), info.name));
        names_length += strlen(info.name) + 1;
        assert_true(strlen(info.description) > 10);
        /* every parameter at an accepted value, and the same without key k */
        char defaults[256] = "", others[8][256];
        for (int k = 0; k < info.parameter_count && k < 8; ++k)
            others[k][0] = '\0';
        for (int k = 0; k < info.parameter_count; ++k) {
            sph_effect_parameter p;
            check(NULL, sph_effect_parameter_get(e, k, &p));
            const double ok =
                p.required ? (isfinite(p.max) ? p.max : p.min + 1.0) : p.default_value;
            char word[64];
            snprintf(word, sizeof word, "%s=%.17g ", p.key, ok);
            strcat(defaults, word);
            for (int j = 0; j < info.parameter_count && j < 8; ++j)
                if (j != k)
                    strcat(others[j], word);
        }
        assert_true(info.parameter_count <= 8);
        for (int k = 0; k < info.parameter_count; ++k) {
            sph_effect_parameter p;
            check(NULL, sph_effect_parameter_get(e, k, &p));
            sph_sim *sim = new_sim(3);
            char text[2400], needle[64];
            if (p.required)
                assert_refused(sim, sph_effect(sim, info.name, others[k]), SPH_ERR_ARGUMENT, p.key);
            /* just outside each bound: the bound itself when open, a step past it when closed */
            const double outside[2] = {p.min_inclusive ? p.min - 1e-3 : p.min,
                                       p.max_inclusive ? p.max + 1e-3 : p.max};
            for (int side = 0; side < 2; ++side) {
                if (!isfinite(outside[side]))
                    continue;
                snprintf(text, sizeof text, "%s %s=%.17g", others[k], p.key, outside[side]);
                snprintf(needle, sizeof needle, "%s=%g must be", p.key, outside[side]);
                assert_refused(sim, sph_effect(sim, info.name, text), SPH_ERR_ARGUMENT, needle);
                assert_int_equal(sph_effect_is_on(sim, info.name), 0);
            }
            sph_destroy(sim);
        }
        sph_sim *sim = new_sim(3);
        check(sim, sph_effect(sim, info.name, defaults));
        assert_int_equal(sph_effect_is_on(sim, info.name), 1);
        check(sim, sph_effect_off(sim, info.name));
        assert_int_equal(sph_effect_is_on(sim, info.name), 0);
        sph_destroy(sim);
    }
    assert_int_equal(strlen(sph_effect_names()) + 1, names_length);
    sph_effect_info info;
    assert_int_equal(sph_effect_info_get(count, &info), SPH_ERR_ARGUMENT);
    sph_effect_parameter p;
    assert_int_equal(sph_effect_parameter_get(0, 99, &p), SPH_ERR_ARGUMENT);
}

/* sph_version() starts with the version the header's macros give. */
static void version_string_matches_the_header(void **state)
{
    (void)state;
    char expected[64];
    snprintf(expected, sizeof expected, "%d.%d.%d", SPHSOLID_VERSION_MAJOR, SPHSOLID_VERSION_MINOR,
             SPHSOLID_VERSION_PATCH);
    assert_string_equal(expected, SPHSOLID_VERSION_STRING);
    assert_int_equal(strncmp(sph_version(), expected, strlen(expected)), 0);
    const char next = sph_version()[strlen(expected)];
    assert_true(next == '\0' || next == ' ');
}

static void run_until_lands_on_time_and_callback_can_stop(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(8, 8, 1e-3);
    const double dt = sph_dt(sim);
    check(sim, sph_run_until(sim, 7.3 * dt));
    assert_true(sph_time(sim) == 7.3 * dt);
    assert_int_equal(sph_step_count(sim), 8);
    int calls = 0;
    check(sim, sph_set_progress(sim, 1, stop_at_five, &calls));
    sph_sim *fresh = free_block_2d(8, 8, 1e-3);
    check(fresh, sph_set_progress(fresh, 1, stop_at_five, &calls));
    assert_refused(fresh, sph_run(fresh, 100), SPH_ERR_STOPPED, "step 5");
    assert_int_equal(sph_step_count(fresh), 5);
    assert_int_equal(calls, 5);
    sph_destroy(fresh);
    sph_destroy(sim);
}

/* Derived fields against their definitions: P = c0^2 (rho - rho0) with
 * c0^2 = K / rho0, sigma = S - P I (zz included in plane strain) and the von
 * Mises stress sqrt(3/2 S:S) of a pure-shear-plus-normal state; the copies
 * of the handle's state and sph_derived_fields on caller arrays agree. */
static void derived_fields_follow_the_equation_of_state(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(2, 1, 1e-3);
    double *rho = field_ptr(sim, SPH_FIELD_DENSITY),
           *S = field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS);
    const double strain = 1e-3, s = 2e6, tau = 3e6;
    rho[0] = PAPER_RHO0 * (1.0 + strain);
    const double S0[4] = {s, -s, 0.0, tau};
    memcpy(S, S0, sizeof S0);
    const double P = PAPER_K * strain, vm = sqrt(1.5 * (2.0 * s * s + 2.0 * tau * tau));
    const double sigma[4] = {s - P, -s - P, -P, tau};
    double pressure[2], stress[8], von_mises[2], p2[2], st2[8], vm2[2];
    check(sim, sph_field_copy(sim, SPH_FIELD_PRESSURE, pressure));
    check(sim, sph_field_copy(sim, SPH_FIELD_STRESS, stress));
    check(sim, sph_field_copy(sim, SPH_FIELD_VON_MISES, von_mises));
    const int material[2] = {0, 0};
    check(sim, sph_derived_fields(sim, 2, rho, S, material, p2, st2, vm2));
    assert_close(pressure[0], P, 1e-9 * P, "pressure");
    assert_close(pressure[1], 0.0, 1e-9 * P, "pressure at rho0");
    assert_close(von_mises[0], vm, 1e-12 * vm, "von Mises");
    for (int c = 0; c < 4; ++c) {
        assert_close(stress[c], sigma[c], 1e-9 * P, "Cauchy stress");
        assert_close(stress[4 + c], 0.0, 1e-9 * P, "Cauchy stress at rest");
    }
    for (int k = 0; k < 8; ++k)
        assert_true(st2[k] == stress[k]);
    for (int a = 0; a < 2; ++a)
        assert_true(p2[a] == pressure[a] && vm2[a] == von_mises[a]);
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bad_materials_are_refused),
        cmocka_unit_test(bad_bodies_are_refused),
        cmocka_unit_test(bad_effects_and_time_steps_are_refused),
        cmocka_unit_test(non_finite_value_stops_run_with_step_particle_and_quantity),
        cmocka_unit_test(particle_leaving_the_domain_stops_the_run),
        cmocka_unit_test(rigid_force_body_obeys_newton_in_parts),
        cmocka_unit_test(results_do_not_depend_on_threads_or_rebuilds),
        cmocka_unit_test(run_until_lands_on_time_and_callback_can_stop),
        cmocka_unit_test(failing_low_level_calls_leave_a_message),
        cmocka_unit_test(every_registered_effect_honours_its_ranges),
        cmocka_unit_test(version_string_matches_the_header),
        cmocka_unit_test(derived_fields_follow_the_equation_of_state),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
