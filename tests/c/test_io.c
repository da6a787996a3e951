/* HDF5 output read back exactly; checkpoints resume bit for bit. */
#include "helpers.h"

#include "core/sim.h"

static sph_sim *paper(double dx)
{
    sph_sim *sim = new_sim(2);
    check(sim, sph_build_paper_scene(sim, dx, 1.5e-3, 0, NULL));
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0"));
    return sim;
}

static int same(const double *a, const double *b, size_t n)
{
    return memcmp(a, b, n * sizeof(double)) == 0;
}

static void snapshots_read_back_exactly(void **state)
{
    (void)state;
    const char *path = "test_io_snapshots.h5";
    sph_sim *sim = paper(4e-3);
    check(sim, sph_output_open(sim, path, 10, 5));
    check(sim, sph_run(sim, 30));
    check(sim, sph_output_close(sim));
    long frames;
    check(sim, sph_read_frame_count(sim, path, &frames));
    assert_int_equal(frames, 4); /* steps 0, 10, 20, 30 */

    sph_sim *back = paper(4e-3);
    check(back, sph_read_frame(back, path, -1));
    const size_t n = sph_particle_count(sim);
    assert_true(same(back->x, sim->x, 2 * n));
    assert_true(same(back->v, sim->v, 2 * n));
    assert_true(same(back->rho, sim->rho, n));
    assert_true(same(back->S, sim->S, 4 * n));
    assert_int_equal(sph_step_count(back), 30);
    assert_true(sph_time(back) == sph_time(sim));
    /* a frame that does not exist, a file that is not there */
    assert_int_equal(sph_read_frame(back, path, 9), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(back), "frame=9"));
    assert_int_equal(sph_read_frame(back, "no/such/file.h5", 0), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(back), "no/such/file.h5"));
    sph_destroy(back);
    sph_destroy(sim);
    remove(path);
}

static void checkpoint_resumes_bit_identically(void **state)
{
    (void)state;
    const char *path = "test_io_checkpoint.h5";
    sph_sim *straight = paper(4e-3);
    check(straight, sph_run(straight, 40));
    check(straight, sph_checkpoint_write(straight, path));
    check(straight, sph_run(straight, 60));

    sph_sim *resumed = paper(4e-3);
    check(resumed, sph_checkpoint_read(resumed, path));
    assert_int_equal(sph_step_count(resumed), 40);
    check(resumed, sph_run(resumed, 60));
    const size_t n = sph_particle_count(straight);
    assert_true(same(resumed->x, straight->x, 2 * n));
    assert_true(same(resumed->v, straight->v, 2 * n));
    assert_true(same(resumed->rho, straight->rho, n));
    assert_true(same(resumed->S, straight->S, 4 * n));
    assert_true(sph_time(resumed) == sph_time(straight));

    /* a checkpoint of another scene is refused */
    sph_sim *other = paper(5e-3);
    assert_int_equal(sph_checkpoint_read(other, path), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(other), "particles"));
    sph_destroy(other);
    sph_destroy(resumed);
    sph_destroy(straight);
    remove(path);
}

/* The leapfrog carries the rates of the state from step to step: a
 * checkpoint holds them (and the integrator's name), so the resumed run is
 * bit for bit the straight one. */
static void leapfrog_checkpoint_resumes_bit_identically(void **state)
{
    (void)state;
    const char *path = "test_io_checkpoint_leapfrog.h5";
    sph_sim *straight = paper(4e-3);
    check(straight, sph_set_integrator(straight, "leapfrog"));
    check(straight, sph_run(straight, 40));
    check(straight, sph_checkpoint_write(straight, path));
    check(straight, sph_run(straight, 60));

    sph_sim *resumed = paper(4e-3); /* Improved Euler until the checkpoint says otherwise */
    check(resumed, sph_checkpoint_read(resumed, path));
    assert_string_equal(sph_integrator_name(resumed), "leapfrog");
    check(resumed, sph_run(resumed, 60));
    const size_t n = sph_particle_count(straight);
    assert_true(same(resumed->x, straight->x, 2 * n));
    assert_true(same(resumed->v, straight->v, 2 * n));
    assert_true(same(resumed->rho, straight->rho, n));
    assert_true(same(resumed->S, straight->S, 4 * n));
    assert_true(sph_time(resumed) == sph_time(straight));
    sph_destroy(resumed);
    sph_destroy(straight);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(snapshots_read_back_exactly),
        cmocka_unit_test(checkpoint_resumes_bit_identically),
        cmocka_unit_test(leapfrog_checkpoint_resumes_bit_identically),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
