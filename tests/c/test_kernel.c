/* Kernels: normalisation, gradient against finite differences, compact
 * support. */
#include "helpers.h"

#include "kernel.h"

/* Integral of W over the plane/space by the midpoint rule on a fine grid;
 * must be 1 by the normalisation sigma_d / h^d. */
static double integral(int kernel, int dim, double h)
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
                sum += kernel_w(kernel, sqrt(x * x + y * y + z * z) / h) * norm;
            }
    return sum * pow(d, dim);
}

static void kernels_integrate_to_one(void **state)
{
    (void)state;
    for (int kernel = 0; sph_kernel_name((sph_kernel)kernel); ++kernel)
        for (int dim = 2; dim <= 3; ++dim)
            /* midpoint rule error is O(d^2) ~ 1e-5 (2D), 1e-3 (3D) */
            assert_close(integral(kernel, dim, 1.3e-3), 1.0, dim == 2 ? 1e-4 : 2e-3, "kernel integral");
}

/* The 1D cubic spline normalisation 2/3: integral over the line. */
static void cubic_spline_1d_normalisation(void **state)
{
    (void)state;
    const int n = 200000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double q = -2.0 + (i + 0.5) * 4.0 / n;
        sum += kernel_cubic_w(fabs(q));
    }
    assert_close(sum * 4.0 / n * kernel_cubic_sigma(1), 1.0, 1e-9, "1D cubic spline integral");
}

static void gradient_matches_finite_differences(void **state)
{
    (void)state;
    const double e = 1e-6;
    for (int kernel = 0; sph_kernel_name((sph_kernel)kernel); ++kernel)
        for (double q = 0.05; q < kernel_support(kernel); q += 0.0731) {
            /* dw/dq = q f(q) */
            const double fd = (kernel_w(kernel, q + e) - kernel_w(kernel, q - e)) / (2 * e);
            assert_close(q * kernel_f(kernel, q), fd, 1e-7, "dw/dq");
        }
}

static void kernels_vanish_outside_support(void **state)
{
    (void)state;
    for (int kernel = 0; sph_kernel_name((sph_kernel)kernel); ++kernel) {
        const double s = kernel_support(kernel);
        assert_true(kernel_w(kernel, s) == 0.0);
        assert_true(kernel_w(kernel, 1.25 * s) == 0.0);
        assert_true(kernel_f(kernel, s) == 0.0);
        assert_true(kernel_f(kernel, 1.5 * s) == 0.0);
        /* continuous at the support edge */
        assert_close(kernel_w(kernel, s - 1e-9), 0.0, 1e-12, "w at the support");
        assert_true(kernel_w(kernel, s - 1e-3) > 0.0);
    }
    /* cubic spline continuous at q = 1 */
    assert_close(kernel_cubic_w(1.0 - 1e-12), kernel_cubic_w(1.0), 1e-9, "w at q = 1");
    assert_close(kernel_cubic_f(1.0 - 1e-12), kernel_cubic_f(1.0), 1e-9, "f at q = 1");
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
        for (int i = 1; i < N; ++i)   /* trapezoid rule, O(dq^2) */
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
        cmocka_unit_test(public_kernel_names_and_values_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
