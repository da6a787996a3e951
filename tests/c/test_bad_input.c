/*
 * Bad input to the C API: each call fails with its status and a message
 * naming the bad value (or, where the documented behaviour is to go on,
 * goes on without undefined behaviour; the suite also runs under ASan and
 * UBSan).
 */
#define _POSIX_C_SOURCE 200112L /* setenv */
#include "helpers.h"

#include "core/sim.h"

#ifdef _OPENMP
#include <omp.h>
#endif

/* status and message of a call that must be refused */
#define refused(sim, call, status, text)                                                        \
    do {                                                                                        \
        strcpy((sim)->errmsg, "stale message");                                                 \
        const sph_status st_ = (call);                                                          \
        if (st_ != (status) || !strstr(sph_errmsg(sim), (text))) {                              \
            print_error("%s: status %d, message '%s'; expected %d and '%s'\n", #call, (int)st_, \
                        sph_errmsg(sim), (int)(status), (text));                                \
            fail();                                                                             \
        }                                                                                       \
    } while (0)

static sph_sim *block(void) { return free_block_2d(12, 12, 1e-3); }

/* the file cases need a library built with HDF5 */
#define needs_hdf5()                        \
    do {                                    \
        if (!strstr(sph_version(), "hdf5")) \
            skip();                         \
    } while (0)

/* ------------------------------------------------------------- handle */

/* More threads than SPH_THREADS_PER_CORE per core are refused, naming the
 * cores (100000 crashed the OpenMP runtime in the neighbour build); the
 * bound itself is taken and runs. */
static void threads_beyond_the_cores(void **state)
{
    (void)state;
    sph_sim *sim = block();
#ifdef _OPENMP
    const int most = SPH_THREADS_PER_CORE * omp_get_num_procs();
    refused(sim, sph_set_threads(sim, most + 1), SPH_ERR_ARGUMENT, "per core of the");
    refused(sim, sph_set_threads(sim, 100000), SPH_ERR_ARGUMENT, "threads=100000");
    check(sim, sph_set_threads(sim, most));
    check(sim, sph_run(sim, 1));
#endif
    check(sim, sph_set_threads(sim, 1));
    sph_destroy(sim);
}

/* A caller's text quoted in a message is cut at SPH_CLIP characters with
 * its length said: a 5000-character SPHSOLID_RATE_PATH is not echoed. */
static void long_rate_path_is_clipped(void **state)
{
    (void)state;
    char value[5001];
    memset(value, 'x', 5000);
    value[5000] = '\0';
    assert_int_equal(setenv("SPHSOLID_RATE_PATH", value, 1), 0);
    sph_sim *sim = NULL;
    assert_int_equal(sph_create(2, &sim), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "... (5000 characters)"));
    assert_true(strlen(sph_errmsg(sim)) < 200);
    sph_destroy(sim);
    assert_int_equal(setenv("SPHSOLID_RATE_PATH", "avx2 ", 1), 0);
    assert_int_equal(sph_create(2, &sim), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "SPHSOLID_RATE_PATH='avx2 '"));
    sph_destroy(sim);
    assert_int_equal(unsetenv("SPHSOLID_RATE_PATH"), 0);
}

/* ------------------------------------------------------------ materials */

/* The registry of material keys is the setter's list: each key is taken
 * at its default and at its bounds, refused beyond them and when not
 * finite, and an unknown key's message lists exactly the registry's keys
 * (a key sph_material_set learns must be added to material_keys.c). */
static void material_key_registry_is_the_setters(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int id = -1;
    check(sim, sph_add_material_K_mu(sim, 12.2e9, 2.67e9, 2300, &id));
    const int count = sph_material_key_count();
    assert_true(count >= 2);
    char known[512] = "(known: ";
    for (int k = 0; k < count; ++k) {
        sph_material_key_info info;
        assert_int_equal(sph_material_key_get(k, &info), SPH_OK);
        assert_non_null(info.key);
        assert_non_null(info.unit);
        assert_true(info.description && *info.description);
        assert_true(info.min <= info.default_value && info.default_value <= info.max);
        check(sim, sph_material_set(sim, id, info.key, info.default_value));
        check(sim, sph_material_set(sim, id, info.key, info.min));
        if (isfinite(info.max))
            check(sim, sph_material_set(sim, id, info.key, info.max));
        const double below = info.min - fmax(1.0, fabs(info.min));
        refused(sim, sph_material_set(sim, id, info.key, below), SPH_ERR_ARGUMENT, info.key);
        if (isfinite(info.max)) {
            const double above = info.max + fmax(1.0, fabs(info.max));
            refused(sim, sph_material_set(sim, id, info.key, above), SPH_ERR_ARGUMENT, info.key);
        }
        refused(sim, sph_material_set(sim, id, info.key, NAN), SPH_ERR_ARGUMENT, info.key);
        if (k)
            strcat(known, ", ");
        strcat(known, info.key);
    }
    strcat(known, ")");
    refused(sim, sph_material_set(sim, id, "no_such_key", 1.0), SPH_ERR_ARGUMENT, known);
    sph_material_key_info info;
    assert_int_equal(sph_material_key_get(count, &info), SPH_ERR_ARGUMENT);
    assert_int_equal(sph_material_key_get(-1, &info), SPH_ERR_ARGUMENT);
    assert_int_equal(sph_material_key_get(0, NULL), SPH_ERR_ARGUMENT);
    sph_destroy(sim);
}

static void material_overflowing_constants(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    refused(sim, sph_add_material_K_mu(sim, 1e300, 1e300, 1000, NULL), SPH_ERR_ARGUMENT, "E=inf");
    refused(sim, sph_add_material_K_mu(sim, 1e300, 1e300, 1000, NULL), SPH_ERR_ARGUMENT,
            "K=1e+300");
    sph_destroy(sim);
}

static void material_nan_bulk_modulus(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    refused(sim, sph_add_material_K_mu(sim, NAN, 1e9, 1000, NULL), SPH_ERR_ARGUMENT, "K=nan");
    sph_destroy(sim);
}

static void material_poisson_one_half(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    refused(sim, sph_add_material_E_nu(sim, 1e9, 0.5, 1000, NULL), SPH_ERR_ARGUMENT, "nu=0.5");
    sph_destroy(sim);
}

static void material_zero_density(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    refused(sim, sph_add_material_K_mu(sim, 1e9, 1e9, 0.0, NULL), SPH_ERR_ARGUMENT, "rho0=0");
    sph_destroy(sim);
}

static void material_info_null(void **state)
{
    (void)state;
    sph_sim *sim = block();
    refused(sim, sph_material_info_get(sim, 0, NULL), SPH_ERR_ARGUMENT, "info is NULL");
    sph_destroy(sim);
}

/* --------------------------------------------------------------- bodies */

static void particles_infinite_volume(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double pos[4] = {0, 0, 1e-3, 0}, vol[2] = {1e-6, INFINITY};
    refused(sim, sph_add_particles(sim, "b", mat, 2, pos, vol, 1e-3, NULL), SPH_ERR_ARGUMENT,
            "volume inf");
    sph_destroy(sim);
}

static void particles_volume_overflowing_mass(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double pos[2] = {0, 0}, vol[1] = {1e306};
    refused(sim, sph_add_particles(sim, "b", mat, 1, pos, vol, 1e-3, NULL), SPH_ERR_ARGUMENT,
            "volume 1e+306");
    sph_destroy(sim);
}

static void particles_negative_volume(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double pos[2] = {0, 0}, vol[1] = {-1.0};
    refused(sim, sph_add_particles(sim, "b", mat, 1, pos, vol, 1e-3, NULL), SPH_ERR_ARGUMENT,
            "volume -1");
    sph_destroy(sim);
}

static void particles_nan_position(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double pos[4] = {0, 0, NAN, 0};
    refused(sim, sph_add_particles(sim, "b", mat, 2, pos, NULL, 1e-3, NULL), SPH_ERR_ARGUMENT,
            "particle 1");
    sph_destroy(sim);
}

static void block_zero_spacing(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 0};
    refused(sim, sph_add_block(sim, "b", mat, lo, hi, 0.0, NULL), SPH_ERR_ARGUMENT, "dx=0");
    sph_destroy(sim);
}

/* The paper's specimen at dx = 3 um: 1.3e9 particles do not fit; refused
 * before anything is allocated, with the bytes needed and available. */
static void block_that_cannot_fit_in_memory(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {-0.043, 0, 0}, hi[3] = {0.043, 0.140, 0};
    refused(sim, sph_add_block(sim, "specimen", mat, lo, hi, 3e-6, NULL), SPH_ERR_MEMORY,
            "are available");
    assert_non_null(strstr(sph_errmsg(sim), "need about"));
    assert_non_null(strstr(sph_errmsg(sim), "specimen"));
    assert_int_equal(sph_particle_count(sim), 0);
    sph_destroy(sim);
}

static void memory_check_of_a_huge_count(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(3);
    refused(sim, sph_memory_check(sim, 1e15), SPH_ERR_MEMORY, "1e+15 particles");
    refused(sim, sph_memory_check(sim, NAN), SPH_ERR_ARGUMENT, "particles=nan");
    check(sim, sph_memory_check(sim, 1000));
    sph_destroy(sim);
}

static void block_null_corners(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    refused(sim, sph_add_block(sim, "b", 0, NULL, NULL, 1e-3, NULL), SPH_ERR_ARGUMENT, "lo and hi");
    sph_destroy(sim);
}

static void body_info_null(void **state)
{
    (void)state;
    sph_sim *sim = block();
    refused(sim, sph_body_info_get(sim, 0, NULL), SPH_ERR_ARGUMENT, "info is NULL");
    refused(sim, sph_body_find(sim, "block", NULL), SPH_ERR_ARGUMENT, "id is NULL");
    sph_destroy(sim);
}

/* -------------------------------------------------------------- effects */

static void effect_parameter_given_twice(void **state)
{
    (void)state;
    sph_sim *sim = block();
    refused(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 alpha=2"), SPH_ERR_ARGUMENT,
            "'alpha' is given twice");
    assert_int_equal(sph_effect_is_on(sim, "artificial_viscosity"), 0);
    sph_destroy(sim);
}

static void effect_nan_parameter(void **state)
{
    (void)state;
    sph_sim *sim = block();
    refused(sim, sph_effect(sim, "artificial_viscosity", "alpha=nan"), SPH_ERR_ARGUMENT,
            "alpha='nan'");
    refused(sim, sph_effect(sim, "artificial_viscosity", "alpha=inf"), SPH_ERR_ARGUMENT,
            "alpha='inf'");
    sph_destroy(sim);
}

static void effect_negative_viscosity(void **state)
{
    (void)state;
    sph_sim *sim = block();
    refused(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=-1"), SPH_ERR_ARGUMENT,
            "beta=-1");
    sph_destroy(sim);
}

/* --------------------------------------------------------------- fields */

static void field_copy_to_null(void **state)
{
    (void)state;
    sph_sim *sim = block();
    refused(sim, sph_field_copy(sim, SPH_FIELD_PRESSURE, NULL), SPH_ERR_ARGUMENT, "out is NULL");
    refused(sim, sph_field(sim, SPH_FIELD_DENSITY, NULL, NULL, NULL), SPH_ERR_ARGUMENT,
            "data is NULL");
    sph_destroy(sim);
}

static void energy_into_null(void **state)
{
    (void)state;
    sph_sim *sim = block();
    refused(sim, sph_energy(sim, 1, NULL), SPH_ERR_ARGUMENT, "sph_energy: info is NULL");
    sph_destroy(sim);
}

/* A density of 0 set on one particle is reported as itself before the run,
 * not as a neighbour's runaway velocity. */
static void zero_density_on_one_particle(void **state)
{
    (void)state;
    sph_sim *sim = block();
    field_ptr(sim, SPH_FIELD_DENSITY)[37] = 0.0;
    refused(sim, sph_run(sim, 3), SPH_ERR_ARGUMENT, "particle 37 of body 'block' has density 0");
    assert_int_equal(sph_step_count(sim), 0);
    sph_destroy(sim);
}

static void negative_mass_on_one_particle(void **state)
{
    (void)state;
    sph_sim *sim = block();
    field_ptr(sim, SPH_FIELD_MASS)[5] = -1.0;
    refused(sim, sph_run(sim, 1), SPH_ERR_ARGUMENT, "particle 5 of body 'block' has mass -1");
    sph_destroy(sim);
}

static void nan_position_before_a_run(void **state)
{
    (void)state;
    sph_sim *sim = block();
    field_ptr(sim, SPH_FIELD_POSITION)[2 * 9 + 1] = NAN;
    refused(sim, sph_run(sim, 1), SPH_ERR_NONFINITE,
            "particle 9 (body 'block') has a non-finite position y=nan");
    sph_destroy(sim);
}

/* ------------------------------------------------------ neighbour search */

/* Coordinates are limited to 1e6 spacings from the origin (a double
 * rounds a position there to 2.2e-10 dx; at 11,000 km with dx = 1 mm to
 * 2e-6 dx, as much as a slow body moves in a step).  Two 3D blocks
 * 11,000 km apart: the far one is refused, naming it, its coordinate and
 * the limit; a block just inside the limit is accepted. */
static void far_apart_blocks_in_3d(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(3);
    int mat;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {0, 0, 0}, hi[3] = {4e-3, 4e-3, 4e-3};
    const double lo2[3] = {1.1e7, 1.1e7, 1.1e7},
                 hi2[3] = {1.1e7 + 4e-3, 1.1e7 + 4e-3, 1.1e7 + 4e-3};
    check(sim, sph_add_block(sim, "near", mat, lo, hi, 1e-3, NULL));
    refused(sim, sph_add_block(sim, "far", mat, lo2, hi2, 1e-3, NULL), SPH_ERR_ARGUMENT,
            "body 'far': particle 0 at x=1.1e+07 m lies 1.1e+10 spacings (dx=0.001 m) from the "
            "origin; coordinates are limited to 1e+06 spacings (|x| <= 1000 m)");
    assert_int_equal(sph_body_count(sim), 1);
    assert_int_equal(sph_particle_count(sim), 64);
    /* 996 m from the origin: inside the limit of 1000 m */
    const double lo3[3] = {996.0, 0, 0}, hi3[3] = {996.0 + 4e-3, 4e-3, 4e-3};
    check(sim, sph_add_block(sim, "inside", mat, lo3, hi3, 1e-3, NULL));
    check(sim, sph_run(sim, 1));
    sph_destroy(sim);
}

/* A particle at x = 1e300 in 2D is refused when added. */
static void particle_at_1e300_in_2d(void **state)
{
    (void)state;
    sph_sim *sim = block();
    const double pos[2] = {1e300, 0.0};
    refused(sim, sph_add_particles(sim, "far", 0, 1, pos, NULL, 1e-3, NULL), SPH_ERR_ARGUMENT,
            "body 'far': particle 0 at x=1e+300 m");
    assert_int_equal(sph_body_count(sim), 1);
    sph_destroy(sim);
}

/* Positions written through sph_field beyond the limit (here -1e308, whose
 * extent with another at 1e308 overflows a double) are refused before the
 * run, naming the particle and value. */
static void extent_that_overflows(void **state)
{
    (void)state;
    sph_sim *sim = block();
    double *x = field_ptr(sim, SPH_FIELD_POSITION);
    x[2 * 5] = -1e308;
    x[2 * 7 + 1] = 1e308;
    refused(sim, sph_run(sim, 1), SPH_ERR_ARGUMENT, "body 'block': particle 5 at x=-1e+308 m");
    assert_int_equal(sph_step_count(sim), 0);
    sph_destroy(sim);
}

/* A piston moves down at its speed: a negative speed is refused. */
static void piston_with_negative_speed(void **state)
{
    (void)state;
    sph_sim *sim = block();
    refused(sim, sph_add_piston(sim, "piston", -1, 0, 0, -1.5e-3, NULL), SPH_ERR_ARGUMENT,
            "piston 'piston': speed=-0.0015 m/s must be finite and >= 0");
    refused(sim, sph_add_piston(sim, "piston", -1, 0, 0, NAN, NULL), SPH_ERR_ARGUMENT, "speed=nan");
    assert_int_equal(sph_body_count(sim), 1);
    check(sim, sph_add_piston(sim, "piston", -1, 0, 0, 0.0, NULL));
    sph_destroy(sim);
}

/* A 1 km cylinder at dx = 1 mm (2.4e15 particles) is refused before its
 * cross-section is built, naming the particle count. */
static void kilometre_cylinder_names_its_particle_count(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(3);
    int mat;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double base[3] = {0, 0, 0};
    refused(sim, sph_add_cylinder(sim, "rock", mat, base, 500.0, 1000.0, 1e-3, NULL),
            SPH_ERR_MEMORY, "cylinder 'rock' (dx=0.001 m): 7.854e+17 particles");
    assert_int_equal(sph_particle_count(sim), 0);
    sph_destroy(sim);
}

/* Runs may take half of the available memory, all of it when allowed:
 * counts at 0.4, 0.75 and 1.5 times what the memory available holds (the
 * bytes per particle and the memory available read from the message of a
 * refused huge count). */
static void large_runs_need_to_be_allowed(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(3);
    assert_int_equal(sph_allow_large(sim), 0);
    refused(sim, sph_memory_check(sim, 1e15), SPH_ERR_MEMORY, "bytes each");
    const char *msg = sph_errmsg(sim);
    double per = 0, avail = 0;
    char unit[8] = "";
    const char *at = strstr(msg, "bytes each");
    while (at > msg && at[-1] != '(')
        --at;
    assert_int_equal(sscanf(at, "%lf", &per), 1);
    at = strstr(msg, "but ");
    assert_non_null(at);
    assert_int_equal(sscanf(at, "but %lf %7s are available", &avail, unit), 2);
    const char *units[] = {"B", "kB", "MB", "GB", "TB", "PB"};
    for (int k = 0; k < 6; ++k)
        if (strcmp(unit, units[k]) == 0)
            avail *= pow(1000.0, k);
    const double holds = avail / per;
    check(sim, sph_memory_check(sim, 0.4 * holds));
    refused(sim, sph_memory_check(sim, 0.75 * holds), SPH_ERR_MEMORY, "more than 0.5 of the");
    assert_non_null(strstr(sph_errmsg(sim), "sph_set_allow_large"));
    check(sim, sph_set_allow_large(sim, 1));
    assert_int_equal(sph_allow_large(sim), 1);
    check(sim, sph_memory_check(sim, 0.75 * holds));
    refused(sim, sph_memory_check(sim, 1.5 * holds), SPH_ERR_MEMORY, "are available");
    sph_destroy(sim);
}

/* --------------------------------------------------------------- probes */

static void probe_outside_every_body(void **state)
{
    (void)state;
    sph_sim *sim = block();
    const double p[3] = {1.0, 1.0, 0};
    int id;
    check(sim, sph_add_probe(sim, "far", p, &id));
    double values[SPH_PROBE_VALUES(2)];
    refused(sim, sph_probe_sample(sim, id, values), SPH_ERR_DOMAIN,
            "probe 'far' at (1, 1) m is outside every body");
    assert_true(isnan(values[0]));
    sph_destroy(sim);
}

static void probe_outside_as_nan_when_asked(void **state)
{
    (void)state;
    sph_sim *sim = block();
    const double p[3] = {1.0, 1.0, 0};
    int id;
    check(sim, sph_add_probe(sim, "far", p, &id));
    check(sim, sph_set_probe_outside(sim, SPH_PROBE_OUTSIDE_NAN));
    double values[SPH_PROBE_VALUES(2)];
    check(sim, sph_probe_sample(sim, id, values));
    assert_true(isnan(values[0]) && isnan(values[1]));
    refused(sim, sph_set_probe_outside(sim, (sph_probe_outside)7), SPH_ERR_ARGUMENT, "mode=7");
    sph_destroy(sim);
}

static void probe_finish_outside(void **state)
{
    (void)state;
    sph_sim *sim = block();
    double sums[9] = {0}, values[SPH_PROBE_VALUES(2)];
    refused(sim, sph_probe_finish(sim, sums, values), SPH_ERR_DOMAIN, "outside every body");
    sph_destroy(sim);
}

/* A probe that the material leaves stops a run writing probe samples. */
static void probe_outside_during_output(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    const double p[3] = {0.5, 0.5, 0};
    check(sim, sph_add_probe(sim, "away", p, NULL));
    refused(sim, sph_output_open(sim, "test_bad_input_probe.h5", 1, 1), SPH_ERR_DOMAIN,
            "probe 'away'");
    if (sim->out)
        sph_output_close(sim);
    sph_destroy(sim);
    remove("test_bad_input_probe.h5");
    remove("test_bad_input_probe.xmf");
}

static void probe_non_finite_point(void **state)
{
    (void)state;
    sph_sim *sim = block();
    const double p[3] = {0.0, INFINITY, 0};
    refused(sim, sph_add_probe(sim, "A", p, NULL), SPH_ERR_ARGUMENT, "y=inf");
    sph_destroy(sim);
}

/* ---------------------------------------------------------------- files */

static void output_negative_interval(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    refused(sim, sph_output_open(sim, "x.h5", -5, 0), SPH_ERR_ARGUMENT, "snapshot -5");
    sph_destroy(sim);
}

/* A probe interval with no probe to sample is refused before the file is
 * created, naming the interval and the missing probes. */
static void output_probe_interval_without_probes(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    remove("test_bad_input_noprobe.h5");
    refused(sim, sph_output_open(sim, "test_bad_input_noprobe.h5", 1, 5), SPH_ERR_ARGUMENT,
            "probe interval 5, but there are no probes");
    assert_null(sim->out);
    FILE *f = fopen("test_bad_input_noprobe.h5", "rb");
    assert_null(f);
    if (f)
        fclose(f);
    /* without a probe interval the same scene opens */
    check(sim, sph_output_open(sim, "test_bad_input_noprobe.h5", 1, 0));
    check(sim, sph_output_close(sim));
    sph_destroy(sim);
    remove("test_bad_input_noprobe.h5");
    remove("test_bad_input_noprobe.xmf");
}

static int never_called(const sph_sim *sim, void *user)
{
    (void)sim;
    (void)user;
    return 0;
}

/* The run and output calls refuse their bad arguments naming them, and
 * leave the handle as it was. */
static void run_and_output_arguments(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    refused(sim, sph_output_open(sim, "", 1, 0), SPH_ERR_ARGUMENT, "output path is empty");
    refused(sim, sph_output_open(sim, NULL, 1, 0), SPH_ERR_ARGUMENT, "output path is empty");
    refused(sim, sph_output_open(sim, "x.h5", 0, -3), SPH_ERR_ARGUMENT, "probe -3");
    assert_null(sim->out);
    refused(sim, sph_run(sim, -1), SPH_ERR_ARGUMENT, "steps=-1");
    refused(sim, sph_run_until(sim, NAN), SPH_ERR_ARGUMENT, "until t=nan");
    check(sim, sph_run(sim, 2));
    refused(sim, sph_run_until(sim, 0.0), SPH_ERR_ARGUMENT, "not before the current time");
    assert_int_equal(sph_step_count(sim), 2);
    refused(sim, sph_set_progress(sim, 0, never_called, NULL), SPH_ERR_ARGUMENT,
            "progress interval=0");
    refused(sim, sph_set_dt(sim, -1e-7, 0), SPH_ERR_ARGUMENT, "dt=-1e-07: must be finite");
    refused(sim, sph_set_dt(sim, 1.0, 0), SPH_ERR_ARGUMENT, "exceeds the stability limit");
    refused(sim, sph_set_integrator(sim, "heun"), SPH_ERR_ARGUMENT, "heun");
    refused(sim, sph_set_watchdog(sim, -1.0, 0.5, 2.0), SPH_ERR_ARGUMENT,
            "watchdog max_speed_over_cp=-1");
    refused(sim, sph_set_watchdog(sim, 1.0, 1.5, 2.0), SPH_ERR_ARGUMENT,
            "watchdog min_density_ratio=1.5");
    assert_string_equal(sph_integrator_name(sim), "improved_euler");
    /* a second file while one is open */
    remove("test_bad_input_twice.h5");
    check(sim, sph_output_open(sim, "test_bad_input_twice.h5", 1, 0));
    refused(sim, sph_output_open(sim, "test_bad_input_other.h5", 1, 0), SPH_ERR_STATE,
            "an output file is already open ('test_bad_input_twice.h5')");
    check(sim, sph_output_close(sim));
    sph_destroy(sim);
    remove("test_bad_input_twice.h5");
    remove("test_bad_input_twice.xmf");
    FILE *f = fopen("test_bad_input_other.h5", "rb");
    assert_null(f);
    if (f)
        fclose(f);
}

static void output_in_missing_directory(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    refused(sim, sph_output_open(sim, "no/such/dir/out.h5", 1, 0), SPH_ERR_IO,
            "no/such/dir/out.h5");
    assert_null(sim->out);
    sph_destroy(sim);
}

static void checkpoint_in_missing_directory(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    refused(sim, sph_checkpoint_write(sim, "no/such/dir/state.h5"), SPH_ERR_IO,
            "No such file or directory");
    assert_non_null(strstr(sph_errmsg(sim), "no/such/dir/state.h5"));
    sph_destroy(sim);
}

static void checkpoint_empty_path(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    refused(sim, sph_checkpoint_write(sim, ""), SPH_ERR_ARGUMENT, "path is empty");
    refused(sim, sph_checkpoint_read(sim, ""), SPH_ERR_ARGUMENT, "path is empty");
    sph_destroy(sim);
}

static void checkpoint_into_empty_simulation(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    check(sim, sph_checkpoint_write(sim, "test_bad_input_ckpt.h5"));
    sph_sim *empty = new_sim(2);
    refused(empty, sph_checkpoint_read(empty, "test_bad_input_ckpt.h5"), SPH_ERR_STATE,
            "no particles");
    sph_destroy(empty);
    sph_destroy(sim);
    remove("test_bad_input_ckpt.h5");
}

static void frame_count_into_null(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    refused(sim, sph_read_frame_count(sim, "x.h5", NULL), SPH_ERR_ARGUMENT, "frames is NULL");
    sph_destroy(sim);
}

static void frame_of_missing_file(void **state)
{
    (void)state;
    needs_hdf5();
    sph_sim *sim = block();
    refused(sim, sph_read_frame(sim, "no/such/frames.h5", 0), SPH_ERR_IO, "no/such/frames.h5");
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(threads_beyond_the_cores),
        cmocka_unit_test(long_rate_path_is_clipped),
        cmocka_unit_test(material_key_registry_is_the_setters),
        cmocka_unit_test(material_overflowing_constants),
        cmocka_unit_test(material_nan_bulk_modulus),
        cmocka_unit_test(material_poisson_one_half),
        cmocka_unit_test(material_zero_density),
        cmocka_unit_test(material_info_null),
        cmocka_unit_test(particles_infinite_volume),
        cmocka_unit_test(particles_volume_overflowing_mass),
        cmocka_unit_test(particles_negative_volume),
        cmocka_unit_test(particles_nan_position),
        cmocka_unit_test(block_zero_spacing),
        cmocka_unit_test(block_that_cannot_fit_in_memory),
        cmocka_unit_test(memory_check_of_a_huge_count),
        cmocka_unit_test(block_null_corners),
        cmocka_unit_test(body_info_null),
        cmocka_unit_test(effect_parameter_given_twice),
        cmocka_unit_test(effect_nan_parameter),
        cmocka_unit_test(effect_negative_viscosity),
        cmocka_unit_test(field_copy_to_null),
        cmocka_unit_test(energy_into_null),
        cmocka_unit_test(zero_density_on_one_particle),
        cmocka_unit_test(negative_mass_on_one_particle),
        cmocka_unit_test(nan_position_before_a_run),
        cmocka_unit_test(far_apart_blocks_in_3d),
        cmocka_unit_test(piston_with_negative_speed),
        cmocka_unit_test(kilometre_cylinder_names_its_particle_count),
        cmocka_unit_test(large_runs_need_to_be_allowed),
        cmocka_unit_test(particle_at_1e300_in_2d),
        cmocka_unit_test(extent_that_overflows),
        cmocka_unit_test(probe_outside_every_body),
        cmocka_unit_test(probe_outside_as_nan_when_asked),
        cmocka_unit_test(probe_finish_outside),
        cmocka_unit_test(probe_outside_during_output),
        cmocka_unit_test(probe_non_finite_point),
        cmocka_unit_test(output_negative_interval),
        cmocka_unit_test(output_probe_interval_without_probes),
        cmocka_unit_test(run_and_output_arguments),
        cmocka_unit_test(output_in_missing_directory),
        cmocka_unit_test(checkpoint_in_missing_directory),
        cmocka_unit_test(checkpoint_empty_path),
        cmocka_unit_test(checkpoint_into_empty_simulation),
        cmocka_unit_test(frame_count_into_null),
        cmocka_unit_test(frame_of_missing_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
