/* The output file always ends with the final state, and closing it writes
 * the XDMF companion that points into it. */
#include "helpers.h"

#include "core/sim.h"

static sph_sim *paper(double dx)
{
    sph_sim *sim = new_sim(2);
    check(sim, sph_build_paper_scene(sim, dx, 1.5e-3, 0, NULL));
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0"));
    return sim;
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    const long size = ftell(f);
    rewind(f);
    char *text = malloc((size_t)size + 1);
    assert_non_null(text);
    assert_int_equal(fread(text, 1, (size_t)size, f), (size_t)size);
    text[size] = '\0';
    fclose(f);
    return text;
}

static int count(const char *text, const char *word)
{
    int k = 0;
    for (const char *p = strstr(text, word); p; p = strstr(p + 1, word))
        ++k;
    return k;
}

/* 25 steps with a snapshot every 10: frames at steps 0, 10, 20 and, on
 * close, the final step 25, which reads back bit for bit. */
static void final_state_is_the_last_frame(void **state)
{
    (void)state;
    const char *path = "test_xdmf_final.h5";
    remove("test_xdmf_final.xmf");
    sph_sim *sim = paper(4e-3);
    check(sim, sph_output_open(sim, path, 10, 10));
    check(sim, sph_run(sim, 25));
    check(sim, sph_output_close(sim));
    long frames = 0;
    check(sim, sph_read_frame_count(sim, path, &frames));
    assert_int_equal(frames, 4);

    sph_sim *back = paper(4e-3);
    check(back, sph_read_frame(back, path, -1));
    const size_t n = sph_particle_count(sim);
    assert_int_equal(sph_step_count(back), 25);
    assert_true(sph_time(back) == sph_time(sim));
    assert_memory_equal(back->x, sim->x, 2 * n * sizeof(double));
    assert_memory_equal(back->S, sim->S, 4 * n * sizeof(double));

    /* the companion: one grid per frame, the last at the final time, all
     * pointing into the HDF5 file by its name */
    char *xml = slurp("test_xdmf_final.xmf");
    assert_int_equal(count(xml, "<Grid Name=\"frame "), 4);
    char last[64];
    snprintf(last, sizeof last, "<Time Value=\"%.17g\"/>", sph_time(sim));
    assert_non_null(strstr(xml, last));
    assert_int_equal(count(xml, "test_xdmf_final.h5:/particles/all/position/value"), 4);
    assert_int_equal(count(xml, "Name=\"S_"), 4 * 4);
    free(xml);
    sph_destroy(back);
    sph_destroy(sim);
}

/* Closing right after a snapshot of the same step adds no duplicate. */
static void no_duplicate_final_frame(void **state)
{
    (void)state;
    const char *path = "test_xdmf_even.h5";
    sph_sim *sim = paper(4e-3);
    check(sim, sph_output_open(sim, path, 10, 0));
    check(sim, sph_run(sim, 20));
    check(sim, sph_output_close(sim));
    long frames = 0;
    check(sim, sph_read_frame_count(sim, path, &frames));
    assert_int_equal(frames, 3); /* steps 0, 10, 20 */
    sph_destroy(sim);
}

/* A file that is not there or not an output file: an I/O error naming it,
 * and a previous companion left as it was. */
static void bad_files_are_named(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    assert_int_equal(sph_write_xdmf(sim, "no_such_file.h5"), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), "no_such_file.h5"));
    assert_int_equal(sph_write_xdmf(sim, ""), SPH_ERR_ARGUMENT);
    assert_int_equal(sph_write_xdmf(NULL, "no_such_file.h5"), SPH_ERR_IO);

    sph_sim *other = paper(4e-3);
    check(other, sph_checkpoint_write(other, "test_xdmf_checkpoint.h5"));
    FILE *f = fopen("test_xdmf_checkpoint.xmf", "w");
    fputs("previous", f);
    fclose(f);
    assert_int_equal(sph_write_xdmf(sim, "test_xdmf_checkpoint.h5"), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), "not a libsphsolid output file"));
    char *text = slurp("test_xdmf_checkpoint.xmf");
    assert_string_equal(text, "previous");
    free(text);
    sph_destroy(other);
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(final_state_is_the_last_frame),
        cmocka_unit_test(no_duplicate_final_frame),
        cmocka_unit_test(bad_files_are_named),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
