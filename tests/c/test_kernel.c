/* Kernels: normalisation, gradient against finite differences, compact
 * support. */
#include "helpers.h"

#include "kernel.h"

/* Integral of W over the plane/space by the midpoint rule on a fine grid;
 * must be 1 by the normalisation sigma_d / h^d. */
static double integral(int kernel, int dim, double h)
{
    const int n = dim == 2 ? 801 : 121;
    const double L = 2.0 * h, d = 2.0 * L / n;
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
    for (int kernel = 0; kernel < 2; ++kernel)
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
    for (int kernel = 0; kernel < 2; ++kernel)
        for (double q = 0.05; q < 2.0; q += 0.0731) {
            /* dw/dq = q f(q) */
            const double fd = (kernel_w(kernel, q + e) - kernel_w(kernel, q - e)) / (2 * e);
            assert_close(q * kernel_f(kernel, q), fd, 1e-7, "dw/dq");
        }
}

static void kernels_vanish_outside_support(void **state)
{
    (void)state;
    for (int kernel = 0; kernel < 2; ++kernel) {
        assert_true(kernel_w(kernel, 2.0) == 0.0);
        assert_true(kernel_w(kernel, 2.5) == 0.0);
        assert_true(kernel_f(kernel, 2.0) == 0.0);
        assert_true(kernel_f(kernel, 3.0) == 0.0);
        /* continuous at the support edge */
        assert_close(kernel_w(kernel, 2.0 - 1e-9), 0.0, 1e-12, "w at 2h");
        assert_true(kernel_w(kernel, 1.999) > 0.0);
    }
    /* cubic spline continuous at q = 1 */
    assert_close(kernel_cubic_w(1.0 - 1e-12), kernel_cubic_w(1.0), 1e-9, "w at q = 1");
    assert_close(kernel_cubic_f(1.0 - 1e-12), kernel_cubic_f(1.0), 1e-9, "f at q = 1");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(kernels_integrate_to_one),
        cmocka_unit_test(cubic_spline_1d_normalisation),
        cmocka_unit_test(gradient_matches_finite_differences),
        cmocka_unit_test(kernels_vanish_outside_support),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
