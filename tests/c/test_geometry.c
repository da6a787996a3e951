/* Specimen geometry: cylinder, prism and platens against any body. */
#include "helpers.h"

/* Lattice points of one cylinder cross-section, counted in integers: with
 * n = round(2R/dx) and s = 2R/n, the point (i, k) sits at
 * ((2i + 1 - n) s/2, (2k + 1 - n) s/2) from the axis and R = n s/2, so it is
 * inside iff (2i+1-n)^2 + (2k+1-n)^2 < n^2. */
static size_t disc_count(long n)
{
    size_t count = 0;
    for (long i = 0; i < n; ++i)
        for (long k = 0; k < n; ++k) {
            const long a = 2 * i + 1 - n, b = 2 * k + 1 - n;
            count += a * a + b * b < n * n;
        }
    return count;
}

static sph_sim *cylinder_sim(double radius, double length, double dx, int *mat, int *body)
{
    sph_sim *sim = new_sim(3);
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, mat));
    const double base[3] = {0.001, 0.0, -0.002};
    check(sim, sph_add_cylinder(sim, "specimen", *mat, base, radius, length, dx, body));
    return sim;
}

static void cylinder_holds_the_lattice_points_inside_its_radius(void **state)
{
    (void)state;
    const double R = 0.027, L = 0.135, dx = 0.003;
    int mat, body;
    sph_sim *sim = cylinder_sim(R, L, dx, &mat, &body);
    const long n = lround(2 * R / dx), ny = lround(L / dx);
    const size_t expected = disc_count(n) * (size_t)ny;
    assert_int_equal(sph_particle_count(sim), expected);
    const double *x = field_ptr(sim, SPH_FIELD_POSITION), *m = field_ptr(sim, SPH_FIELD_MASS);
    const double s = 2 * R / n, sy = L / ny, cell = s * s * sy;
    double centroid[3] = {0, 0, 0}, mass = 0;
    for (size_t a = 0; a < expected; ++a) {
        const double px = x[3 * a] - 0.001, pz = x[3 * a + 2] + 0.002;
        assert_true(px * px + pz * pz < R * R);
        assert_true(x[3 * a + 1] > 0 && x[3 * a + 1] < L);
        for (int i = 0; i < 3; ++i)
            centroid[i] += x[3 * a + i];
        mass += m[a];
        assert_close(m[a], PAPER_RHO0 * cell, 1e-12 * PAPER_RHO0 * cell, "particle mass");
    }
    /* the lattice is symmetric about the axis and the mid-plane */
    assert_close(centroid[0] / expected, 0.001, 1e-12, "centroid x");
    assert_close(centroid[1] / expected, 0.5 * L, 1e-12, "centroid y");
    assert_close(centroid[2] / expected, -0.002, 1e-12, "centroid z");
    /* the cells cut by the surface lie within sqrt(2) s of it */
    const double volume = M_PI * R * R * L;
    assert_true(fabs(mass / PAPER_RHO0 - volume) <= 2 * M_PI * R * sqrt(2.0) * s * L);
    double lo[3], hi[3], step[3];
    check(sim, sph_body_extent(sim, body, lo, hi, step));
    assert_close(lo[0], 0.001 - R, 1e-15, "extent lo x");
    assert_close(hi[1], L, 1e-15, "extent hi y");
    assert_close(step[1], sy, 1e-15, "step y");
    sph_destroy(sim);
}

/* The plate lies under the cylinder's base with the cylinder's columns,
 * ceil(2h/dy) layers, its top layer one dy below the bottom one; the piston
 * mirrors it above and moves down. */
static void platens_sit_against_a_cylinder_at_least_one_support_thick(void **state)
{
    (void)state;
    const double R = 0.01, L = 0.03, dx = 0.002, speed = 1.5e-3;
    int mat, body, plate, piston;
    sph_sim *sim = cylinder_sim(R, L, dx, &mat, &body);
    check(sim, sph_add_plate(sim, "plate", -1, body, 0, &plate));
    check(sim, sph_add_piston(sim, "piston", -1, body, 0, speed, &piston));
    const double h = sph_smoothing_length(sim), dy = L / lround(L / dx);
    const long layers = (long)ceil(2 * h / dy - 1e-9);
    const long n = lround(2 * R / dx);
    sph_body_info sp, pl, pi;
    check(sim, sph_body_info_get(sim, body, &sp));
    check(sim, sph_body_info_get(sim, plate, &pl));
    check(sim, sph_body_info_get(sim, piston, &pi));
    assert_int_equal(pl.count, (size_t)(n * n * layers));
    assert_int_equal(pi.count, pl.count);
    assert_int_equal(pl.motion, SPH_MOTION_FIXED);
    assert_int_equal(pi.motion, SPH_MOTION_VELOCITY);
    assert_true(layers * dy >= 2 * h);
    const double *x = field_ptr(sim, SPH_FIELD_POSITION), *v = field_ptr(sim, SPH_FIELD_VELOCITY);
    double plate_top = -INFINITY, piston_bottom = INFINITY, plate_bottom = INFINITY;
    for (size_t a = pl.first; a < pl.first + pl.count; ++a) {
        plate_top = fmax(plate_top, x[3 * a + 1]);
        plate_bottom = fmin(plate_bottom, x[3 * a + 1]);
    }
    for (size_t a = pi.first; a < pi.first + pi.count; ++a) {
        piston_bottom = fmin(piston_bottom, x[3 * a + 1]);
        assert_close(v[3 * a + 1], -speed, 0, "piston velocity");
    }
    assert_close(plate_top, -0.5 * dy, 1e-15, "plate's top layer");
    assert_close(plate_bottom, -(layers - 0.5) * dy, 1e-15, "plate's bottom layer");
    assert_close(piston_bottom, L + 0.5 * dy, 1e-15, "piston's bottom layer");
    /* every column of the cylinder's bottom layer has a plate particle
     * straight under it */
    for (size_t a = sp.first; a < sp.first + sp.count; ++a) {
        if (x[3 * a + 1] > dy)
            continue;
        int found = 0;
        for (size_t b = pl.first; b < pl.first + pl.count && !found; ++b)
            found = fabs(x[3 * b] - x[3 * a]) < 1e-12 &&
                    fabs(x[3 * b + 2] - x[3 * a + 2]) < 1e-12 &&
                    fabs(x[3 * b + 1] - plate_top) < 1e-12;
        assert_true(found);
    }
    sph_destroy(sim);
}

static void a_platen_thinner_than_the_support_is_refused(void **state)
{
    (void)state;
    int mat, body, plate;
    sph_sim *sim = cylinder_sim(0.01, 0.03, 0.002, &mat, &body);
    assert_int_equal(sph_add_plate(sim, "plate", -1, body, 2, &plate), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "layers=2"));
    assert_int_equal(sph_add_piston(sim, "piston", -1, 7, 0, 1.0, &plate), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "body=7"));
    assert_int_equal(sph_body_count(sim), 1);
    sph_destroy(sim);
}

/* A 2D disc given as points (the cross-section of a one-layer 3D cylinder,
 * x and z as the disc's x and y): the plate spans its width and touches it. */
static void plate_sits_under_a_disc_in_2d(void **state)
{
    (void)state;
    const double R = 0.01, dx = 0.001, centre[3] = {0.0, 0.0, 0.0};
    const long n = lround(2 * R / dx);
    int mat, disc, plate;
    sph_sim *cyl = new_sim(3);
    check(cyl, sph_add_material_K_mu(cyl, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    check(cyl, sph_add_cylinder(cyl, "layer", mat, centre, R, dx, dx, &disc));
    const size_t count = sph_particle_count(cyl);
    const double *x3 = field_ptr(cyl, SPH_FIELD_POSITION);
    double *pts = malloc(count * 2 * sizeof *pts);
    for (size_t a = 0; a < count; ++a) {
        pts[2 * a] = x3[3 * a];
        pts[2 * a + 1] = x3[3 * a + 2];
    }
    sph_destroy(cyl);
    sph_sim *sim = new_sim(2);
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    check(sim, sph_add_particles(sim, "disc", mat, count, pts, NULL, dx, &disc));
    free(pts);
    check(sim, sph_add_plate(sim, "plate", -1, disc, 0, &plate));
    sph_body_info pl;
    check(sim, sph_body_info_get(sim, plate, &pl));
    const double *x = field_ptr(sim, SPH_FIELD_POSITION);
    double top = -INFINITY, xmin = INFINITY, xmax = -INFINITY;
    for (size_t a = pl.first; a < pl.first + pl.count; ++a) {
        top = fmax(top, x[2 * a + 1]);
        xmin = fmin(xmin, x[2 * a]);
        xmax = fmax(xmax, x[2 * a]);
    }
    /* the disc's lowest particle is at -R + dx/2: one dx above the plate */
    assert_close(top, -R - 0.5 * dx, 1e-15, "plate's top layer");
    assert_close(xmin, -R + 0.5 * dx, 1e-15, "plate's first column");
    assert_close(xmax, R - 0.5 * dx, 1e-15, "plate's last column");
    assert_int_equal(pl.count, (size_t)(n * 3));
    sph_destroy(sim);
}

static void prism_is_a_block_standing_on_its_base(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(3);
    int mat, body;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double base[3] = {0.0, 0.01, 0.0};
    check(sim, sph_add_prism(sim, "prism", mat, base, 0.01, 0.006, 0.02, 0.001, &body));
    assert_int_equal(sph_particle_count(sim), 10 * 6 * 20);
    double lo[3], hi[3];
    check(sim, sph_body_extent(sim, body, lo, hi, NULL));
    assert_close(lo[0], -0.005, 1e-15, "prism lo x");
    assert_close(lo[1], 0.01, 1e-15, "prism lo y");
    assert_close(hi[1], 0.03, 1e-15, "prism hi y");
    assert_close(hi[2], 0.003, 1e-15, "prism hi z");
    sph_destroy(sim);
}

static void bad_geometry_is_refused_naming_the_value(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat, body;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double base[3] = {0, 0, 0};
    assert_int_equal(sph_add_cylinder(sim, "c", mat, base, 0.01, 0.02, 0.001, &body),
                     SPH_ERR_STATE);
    assert_non_null(strstr(sph_errmsg(sim), "3D"));
    sph_destroy(sim);
    sim = new_sim(3);
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    assert_int_equal(sph_add_cylinder(sim, "c", mat, base, -0.01, 0.02, 0.001, &body),
                     SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "radius=-0.01"));
    assert_int_equal(sph_add_cylinder(sim, "c", mat, base, 0.01, 0.02, 0.05, &body),
                     SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "dx=0.05"));
    assert_int_equal(sph_add_prism(sim, "p", mat, base, 0.01, 0.0, 0.02, 0.001, &body),
                     SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "depth=0"));
    assert_int_equal(sph_body_count(sim), 0);
    sph_destroy(sim);
}

/* sph_block_lattice gives the lattice sph_add_block lays (n = round(L/dx)
 * per axis, step L/n), lays nothing, and refuses what sph_add_block
 * refuses with the same message. */
static void block_lattice_is_the_lattice_of_the_block(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat, body;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.0104, 0.0026, 0.0};
    long count[3];
    double step[3];
    check(sim, sph_block_lattice(sim, "b", lo, hi, 1e-3, count, step));
    assert_int_equal(sph_body_count(sim), 0);
    assert_int_equal(count[0], 10); /* round(10.4) */
    assert_int_equal(count[1], 3);  /* round(2.6) */
    assert_int_equal(count[2], 1);
    assert_close(step[0], 0.0104 / 10, 1e-15, "step x");
    assert_close(step[1], 0.0026 / 3, 1e-15, "step y");
    check(sim, sph_add_block(sim, "b", mat, lo, hi, 1e-3, &body));
    double blo[3], bhi[3], bstep[3];
    check(sim, sph_body_extent(sim, body, blo, bhi, bstep));
    assert_close(bstep[0], step[0], 0.0, "block step x");
    assert_close(bstep[1], step[1], 0.0, "block step y");
    assert_int_equal(sph_particle_count(sim), (size_t)(count[0] * count[1]));
    const char *bad[][2] = {{"-0.001", "dx=-0.001"}, {"0.1", "less than half of dx=0.1"}};
    for (int k = 0; k < 2; ++k) {
        const double dx = atof(bad[k][0]);
        assert_int_equal(sph_block_lattice(sim, "b", lo, hi, dx, count, step), SPH_ERR_ARGUMENT);
        const char *message = sph_errmsg(sim);
        assert_non_null(strstr(message, bad[k][1]));
        assert_int_equal(sph_add_block(sim, "c", mat, lo, hi, dx, &body), SPH_ERR_ARGUMENT);
        assert_non_null(strstr(sph_errmsg(sim), bad[k][1]));
    }
    const double flat[3] = {0.0104, 0.0, 0.0};
    assert_int_equal(sph_block_lattice(sim, "b", lo, flat, 1e-3, NULL, NULL), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "extent along y is hi-lo=0"));
    /* a kilometre block at 1 mm: refused for its memory, nothing laid */
    const double huge[3] = {1000.0, 1000.0, 0.0};
    assert_int_equal(sph_block_lattice(sim, "b", lo, huge, 1e-3, NULL, NULL), SPH_ERR_MEMORY);
    assert_int_equal(sph_body_count(sim), 1);
    sph_destroy(sim);
}

/* Quasi-static stiffness of a laterally periodic strip (uniaxial strain)
 * of `rows` lattice rows between a plate and a piston: the piston moves in
 * by delta, stops, and damping brings the strip to rest.  Returns the
 * stress sigma_yy in the middle over the continuum's -M delta / L,
 * M = K + 4 mu / 3. */
static double strip_static_stiffness(const char *kernel, double ratio, double inset, int rows)
{
    const double dx = 1e-3, L = rows * dx, half = 4 * dx;
    sph_sim *sim = new_sim(2);
    check(sim, sph_set_kernel_by_name(sim, kernel));
    check(sim, sph_set_smoothing_ratio(sim, ratio));
    check(sim, sph_set_integrator(sim, "leapfrog"));
    const double dlo[3] = {-half, -0.02, 0}, dhi[3] = {half, L + 0.02, 0};
    const int periodic[3] = {1, 0, 0};
    check(sim, sph_set_domain(sim, dlo, dhi, periodic));
    int mat, strip, plate, piston;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {-half, 0, 0}, hi[3] = {half, L, 0};
    check(sim, sph_add_block(sim, "strip", mat, lo, hi, dx, &strip));
    check(sim, sph_set_platen_inset(sim, inset));
    check(sim, sph_add_plate(sim, "plate", -1, strip, 0, &plate));
    const double speed = 0.05;
    check(sim, sph_add_piston(sim, "piston", -1, strip, 0, speed, &piston));
    const double M = PAPER_K + 4.0 * PAPER_MU / 3.0, cp = sqrt(M / PAPER_RHO0);
    const double t_load = L / cp;
    check(sim, sph_run_until(sim, t_load));
    const double delta = speed * sph_time(sim);
    check(sim, sph_set_motion(sim, piston, SPH_MOTION_FIXED, NULL));
    char rate[64];
    snprintf(rate, sizeof rate, "rate=%.17g", M_PI * cp / L);
    check(sim, sph_effect(sim, "damping", rate));
    check(sim, sph_run_until(sim, t_load + 16.0 * L / (M_PI * cp)));
    double *sigma = malloc(sph_particle_count(sim) * 4 * sizeof *sigma);
    assert_non_null(sigma);
    check(sim, sph_field_copy(sim, SPH_FIELD_STRESS, sigma));
    const double *x = field_ptr(sim, SPH_FIELD_POSITION);
    const double *v = field_ptr(sim, SPH_FIELD_VELOCITY);
    sph_body_info info;
    check(sim, sph_body_info_get(sim, strip, &info));
    double sum = 0.0, vmax = 0.0;
    int count = 0;
    for (size_t a = info.first; a < info.first + info.count; ++a) {
        vmax = fmax(vmax, fabs(v[2 * a + 1]));
        if (fabs(x[2 * a + 1] - 0.5 * L) < 1.01 * dx) {
            sum += sigma[4 * a + 1];
            ++count;
        }
    }
    assert_true(count > 0);
    free(sigma);
    assert_true(vmax < 1e-3 * speed); /* at rest */
    sph_destroy(sim);
    return sum / count / (-M * delta / L);
}

static void platen_inset_makes_the_static_stiffness_exact(void **state)
{
    (void)state;
    /* cubic_o4 at h/dx 1.65: bulk lattice moment 1.0008 */
    sph_sim *probe = new_sim(2);
    int mat, body;
    check(probe, sph_set_kernel_by_name(probe, "cubic_o4"));
    check(probe, sph_set_smoothing_ratio(probe, 1.65));
    check(probe, sph_add_material_K_mu(probe, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {-0.003, 0, 0}, hi[3] = {0.003, 0.024, 0};
    check(probe, sph_add_block(probe, "b", mat, lo, hi, 1e-3, &body));
    double inset = -1.0, offset = 0.0;
    check(probe, sph_static_platen_inset(probe, body, &inset, &offset));
    assert_true(fabs(offset) < 1e-6); /* a zero exists for cubic_o4 */
    check(probe, sph_platen_end_offset(probe, body, 0.0, &offset));
    sph_destroy(probe);
    assert_true(inset > 0.0 && inset < 0.5);
    assert_true(offset > 0.3); /* the off setting is softer by 2 offset / rows */
    for (int rows = 24; rows <= 40; rows += 16) {
        const double off = strip_static_stiffness("cubic_o4", 1.65, 0.0, rows);
        const double on = strip_static_stiffness("cubic_o4", 1.65, inset, rows);
        /* L_eff = L + 2 offset dy: the off setting fails the tolerance */
        assert_close(off, 1.0 / (1.0 + 2.0 * offset / rows), 0.003,
                     "stiffness, platens on the extent");
        assert_true(fabs(off - 1.0) > 0.02);
        assert_close(on, 1.0, 0.003, "stiffness, platens at the static inset");
    }
}

static void platen_inset_is_checked_and_moves_the_platens(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    int mat, body, plate, piston;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {0, 0, 0}, hi[3] = {0.01, 0.02, 0};
    check(sim, sph_add_block(sim, "b", mat, lo, hi, 1e-3, &body));
    assert_int_equal(sph_set_platen_inset(sim, 0.5), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "inset=0.5"));
    assert_int_equal(sph_set_platen_inset(sim, -1.0), SPH_ERR_ARGUMENT);
    assert_int_equal(sph_set_platen_inset(sim, NAN), SPH_ERR_ARGUMENT);
    assert_true(sph_platen_inset(sim) == 0.0);
    check(sim, sph_set_platen_inset(sim, 0.25));
    check(sim, sph_add_plate(sim, "plate", -1, body, 0, &plate));
    check(sim, sph_add_piston(sim, "piston", -1, body, 0, 1e-3, &piston));
    double plo[3], phi[3];
    check(sim, sph_body_extent(sim, plate, plo, phi, NULL));
    assert_close(phi[1], 0.25e-3, 1e-15, "plate face");
    check(sim, sph_body_extent(sim, piston, plo, phi, NULL));
    assert_close(plo[1], 0.02 - 0.25e-3, 1e-15, "piston face");
    const double *x = field_ptr(sim, SPH_FIELD_POSITION);
    sph_body_info info;
    check(sim, sph_body_info_get(sim, plate, &info));
    double top = -1.0;
    for (size_t a = info.first; a < info.first + info.count; ++a)
        top = fmax(top, x[2 * a + 1]);
    assert_close(top, -0.25e-3, 1e-15, "plate's nearest row");
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cylinder_holds_the_lattice_points_inside_its_radius),
        cmocka_unit_test(platens_sit_against_a_cylinder_at_least_one_support_thick),
        cmocka_unit_test(a_platen_thinner_than_the_support_is_refused),
        cmocka_unit_test(plate_sits_under_a_disc_in_2d),
        cmocka_unit_test(prism_is_a_block_standing_on_its_base),
        cmocka_unit_test(bad_geometry_is_refused_naming_the_value),
        cmocka_unit_test(block_lattice_is_the_lattice_of_the_block),
        cmocka_unit_test(platen_inset_makes_the_static_stiffness_exact),
        cmocka_unit_test(platen_inset_is_checked_and_moves_the_platens),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
