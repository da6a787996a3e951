/* Kernels: normalisation, gradient against finite differences, compact
 * support. */
#include "helpers.h"

#include "physics/kernel.h"

/* Integral of W over the plane/space by the midpoint rule on a fine grid;
 * must be 1 by the normalisation sigma_d / h^d. */
static double moment(int kernel, int dim, double h, int power)
{
    const int n = dim == 2 ? 801 : 121;
    const double L = kernel_support(kernel) * h, d = 2.0 * L / n;
    const double norm = kernel_sigma(kernel, dim) / pow(h, dim);
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < (dim == 3 ? n : 1); ++k) {
                const double x = -L + (i + 0.5) * d, y = -L + (j + 0.5) * d;
                const double z = dim == 3 ? -L + (k + 0.5) * d : 0.0;
                const double r = sqrt(x * x + y * y + z * z);
                sum += pow(r / h, power) * kernel_w(kernel, dim, r / h) * norm;
            }
    return sum * pow(d, dim);
}

static double integral(int kernel, int dim, double h) { return moment(kernel, dim, h, 0); }

static void kernels_integrate_to_one(void **state)
{
    (void)state;
    for (int kernel = 0; sph_kernel_name((sph_kernel)kernel); ++kernel)
        for (int dim = 2; dim <= 3; ++dim)
            /* midpoint rule error is O(d^2) ~ 1e-5 (2D), 1e-3 (3D) */
            assert_close(integral(kernel, dim, 1.3e-3), 1.0, dim == 2 ? 1e-4 : 2e-3,
                         "kernel integral");
}

/* The 1D cubic spline normalisation 2/3: integral over the line. */
static void cubic_spline_1d_normalisation(void **state)
{
    (void)state;
    const int n = 200000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double q = -2.0 + (i + 0.5) * 4.0 / n;
        sum += kernel_cubic_w(1, fabs(q));
    }
    assert_close(sum * 4.0 / n * kernel_cubic_sigma(1), 1.0, 1e-9, "1D cubic spline integral");
}

static void gradient_matches_finite_differences(void **state)
{
    (void)state;
    const double e = 1e-6;
    for (int kernel = 0; sph_kernel_name((sph_kernel)kernel); ++kernel)
        for (int dim = 2; dim <= 3; ++dim)
            for (double q = 0.05; q < kernel_support(kernel); q += 0.0731) {
                /* dw/dq = q f(q) */
                const double fd =
                    (kernel_w(kernel, dim, q + e) - kernel_w(kernel, dim, q - e)) / (2 * e);
                assert_close(q * kernel_f(kernel, dim, q), fd, 1e-6, "dw/dq");
            }
}

/* The fourth-order cubic has a vanishing second moment (what makes the
 * SPH gradient fourth-order in the continuum); the cubic's is positive. */
static void fourth_order_kernel_has_zero_second_moment(void **state)
{
    (void)state;
    for (int dim = 2; dim <= 3; ++dim) {
        assert_close(moment(SPH_KERNEL_CUBIC_O4, dim, 1.0, 2), 0.0, dim == 2 ? 2e-4 : 3e-3,
                     "second moment of the fourth-order cubic");
        assert_true(moment(SPH_KERNEL_CUBIC_SPLINE, dim, 1.0, 2) > 0.1);
    }
}

/* The SPH gradient of sin(k y) on the square lattice (spacing 1, h/dx =
 * ratio) is G(k) cos(k y), G(k) = -sum_b V y_b sin(k y_b) F(r_b): G/k is
 * the factor on the wave speed.  At k -> 0 it is the gradient moment M.
 * The fourth-order cubic at h/dx = 1.65 has M = 1.0008 and keeps a sine
 * of 10 particles per wavelength within 0.5 % of M; the cubic spline at
 * 1.2 loses 8.5 % there. */
static double lattice_symbol(int kernel, double ratio, double kdx)
{
    const int n = (int)ceil(kernel_support(kernel) * ratio) + 1;
    const double fnorm = kernel_sigma(kernel, 2) / pow(ratio, 4);
    double g = 0.0;
    for (int i = -n; i <= n; ++i)
        for (int j = -n; j <= n; ++j) {
            const double r = sqrt((double)(i * i + j * j));
            if (r > 0.0)
                g -= fnorm * kernel_f(kernel, 2, r / ratio) * j * sin(kdx * j);
        }
    return g;
}

static void fourth_order_kernel_lattice_dispersion(void **state)
{
    (void)state;
    const double M = lattice_symbol(SPH_KERNEL_CUBIC_O4, 1.65, 1e-6) / 1e-6;
    assert_close(M, 1.0008, 2e-4, "gradient moment, fourth-order cubic at h/dx 1.65");
    const double k = 2.0 * M_PI / 10.0;
    assert_close(lattice_symbol(SPH_KERNEL_CUBIC_O4, 1.65, k) / (k * M), 1.0, 5e-3,
                 "phase speed at 10 particles per wavelength, fourth-order cubic");
    const double Mc = lattice_symbol(SPH_KERNEL_CUBIC_SPLINE, 1.2, 1e-6) / 1e-6;
    assert_close(Mc, 0.9908, 2e-4, "gradient moment, cubic spline at h/dx 1.2");
    assert_true(lattice_symbol(SPH_KERNEL_CUBIC_SPLINE, 1.2, k) / (k * Mc) < 0.92);
}

static void kernels_vanish_outside_support(void **state)
{
    (void)state;
    for (int kernel = 0; sph_kernel_name((sph_kernel)kernel); ++kernel) {
        const double s = kernel_support(kernel);
        assert_true(kernel_w(kernel, 2, s) == 0.0);
        assert_true(kernel_w(kernel, 2, 1.25 * s) == 0.0);
        assert_true(kernel_f(kernel, 2, s) == 0.0);
        assert_true(kernel_f(kernel, 2, 1.5 * s) == 0.0);
        /* continuous at the support edge */
        assert_close(kernel_w(kernel, 2, s - 1e-9), 0.0, 1e-12, "w at the support");
        /* positive inside, except the fourth-order cubic's negative outer lobe */
        if (kernel == SPH_KERNEL_CUBIC_O4)
            assert_true(kernel_w(kernel, 2, s - 1e-3) < 0.0);
        else
            assert_true(kernel_w(kernel, 2, s - 1e-3) > 0.0);
    }
    /* cubic spline continuous at q = 1 */
    assert_close(kernel_cubic_w(2, 1.0 - 1e-12), kernel_cubic_w(2, 1.0), 1e-9, "w at q = 1");
    assert_close(kernel_cubic_f(2, 1.0 - 1e-12), kernel_cubic_f(2, 1.0), 1e-9, "f at q = 1");
}

/* The public names and values: every kernel number has a name that maps
 * back to it; sph_kernel_values() gives sigma_d w(q) and its q-derivative
 * (checked against a centred difference of the values themselves), and
 * its 2D values integrate to one: 2 pi int_0^s w(q) q dq = 1. */
static void public_kernel_names_and_values_agree(void **state)
{
    (void)state;
    int count = 0;
    for (int k = 0; sph_kernel_name((sph_kernel)k); ++k, ++count)
        assert_int_equal(sph_kernel_from_name(sph_kernel_name((sph_kernel)k)), k);
    assert_true(count >= 2);
    assert_int_equal(sph_kernel_from_name("gaussian"), -1);
    assert_null(sph_kernel_name((sph_kernel)count));
    for (int k = 0; k < count; ++k) {
        sph_sim *sim = new_sim(2);
        check(sim, sph_set_kernel_by_name(sim, sph_kernel_name((sph_kernel)k)));
        enum { N = 4001 };
        static double q[N], w[N], dw[N];
        const double s = kernel_support(k), dq = s / (N - 1);
        for (int i = 0; i < N; ++i)
            q[i] = i * dq;
        check(sim, sph_kernel_values(sim, N, q, w, dw));
        double integral = 0.0;
        for (int i = 1; i < N; ++i) /* trapezoid rule, O(dq^2) */
            integral += 0.5 * dq * (w[i] * q[i] + w[i - 1] * q[i - 1]);
        assert_close(2.0 * M_PI * integral, 1.0, 1e-6, "2D integral of the public kernel");
        for (int i = 1; i + 1 < N; i += 97)
            assert_close(dw[i], (w[i + 1] - w[i - 1]) / (2.0 * dq), 1e-5, "dw/dq");
        const double bad = -1.0;
        assert_int_equal(sph_kernel_values(sim, 1, &bad, w, dw), SPH_ERR_ARGUMENT);
        assert_non_null(strstr(sph_errmsg(sim), "q[0]=-1"));
        assert_int_equal(sph_set_kernel_by_name(sim, "gaussian"), SPH_ERR_ARGUMENT);
        assert_non_null(strstr(sph_errmsg(sim), "unknown kernel 'gaussian'"));
        sph_destroy(sim);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(kernels_integrate_to_one),
        cmocka_unit_test(cubic_spline_1d_normalisation),
        cmocka_unit_test(gradient_matches_finite_differences),
        cmocka_unit_test(kernels_vanish_outside_support),
        cmocka_unit_test(fourth_order_kernel_has_zero_second_moment),
        cmocka_unit_test(fourth_order_kernel_lattice_dispersion),
        cmocka_unit_test(public_kernel_names_and_values_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
