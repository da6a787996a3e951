/* The kernel registry seen from outside: names and values of the kernels
 * listed in kernel.h. */
#include <math.h>
#include <string.h>

#include "physics/kernel.h"
#include "core/sim.h"

#define KERNEL_WORD(id, name, prefix, support, step, viscous) " " #name
const char *sph_kernel_names(void) { return SPH_KERNELS(KERNEL_WORD) + 1; }
#undef KERNEL_WORD

const char *sph_kernel_name(sph_kernel kernel)
{
#define KERNEL_CASE_NAME(id, name, prefix, support, step, viscous) \
    case id: return #name;
    switch (kernel) {
        SPH_KERNELS(KERNEL_CASE_NAME)
    }
    return NULL;
#undef KERNEL_CASE_NAME
}

int sph_kernel_from_name(const char *name)
{
    if (!name)
        return -1;
#define KERNEL_MATCH(id, kname, prefix, support, step, viscous) \
    if (strcmp(name, #kname) == 0)                              \
        return id;
    SPH_KERNELS(KERNEL_MATCH)
#undef KERNEL_MATCH
    return -1;
}

sph_status sph_set_kernel_by_name(sph_sim *sim, const char *name)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    const int kernel = sph_kernel_from_name(name);
    if (kernel < 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "unknown kernel '%s' (known: %s)",
                        name ? name : "(null)", sph_kernel_names());
    return sph_set_kernel(sim, (sph_kernel)kernel);
}

sph_status sph_kernel_values(sph_sim *sim, size_t n, const double *q, double *w, double *dw_dq)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (n > 0 && !q)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_kernel_values: q must not be NULL");
    for (size_t i = 0; i < n; ++i)
        if (!(q[i] >= 0.0) || !isfinite(q[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "sph_kernel_values: q[%zu]=%g must be finite and >= 0", i, q[i]);
    const double sigma = kernel_sigma(sim->kernel, sim->dim);
    for (size_t i = 0; i < n; ++i) {
        if (w)
            w[i] = sigma * kernel_w(sim->kernel, sim->dim, q[i]);
        if (dw_dq) /* dw/dq = q f(q) */
            dw_dq[i] = sigma * q[i] * kernel_f(sim->kernel, sim->dim, q[i]);
    }
    return sph_ok(sim);
}

double sph_support_radius(const sph_sim *sim)
{
    return sim ? kernel_support(sim->kernel) * sim->h : 0.0;
}

int sph_support_layers(const sph_sim *sim, double spacing)
{
    const double support = sph_support_radius(sim);
    if (!(support > 0.0) || !(spacing > 0.0) || !isfinite(spacing))
        return 0;
    /* the tolerance keeps an exact multiple (2h = 3 dx) at that many rows */
    return (int)ceil(support / spacing - 1e-9);
}

double sph_kernel_negative_from(sph_kernel kernel, int dim)
{
    if (!sph_kernel_name(kernel) || dim < 2 || dim > 3)
        return -1.0;
    /* sampled finely enough for a lobe a few hundredths of h wide, then
     * bisected to the sign change */
    enum { SAMPLES = 256 };
    const double support = kernel_support(kernel);
    for (int i = 1; i < SAMPLES; ++i) {
        const double q = support * i / SAMPLES;
        if (kernel_w(kernel, dim, q) < 0.0) {
            double lo = support * (i - 1) / SAMPLES, hi = q;
            for (int k = 0; k < 50; ++k) {
                const double mid = 0.5 * (lo + hi);
                if (kernel_w(kernel, dim, mid) < 0.0)
                    hi = mid;
                else
                    lo = mid;
            }
            return hi;
        }
    }
    return 0.0;
}

const char *kernel_names_non_negative(int dim, char *buf, size_t size)
{
    buf[0] = '\0';
#define KERNEL_IF_NON_NEGATIVE(id, name, prefix, support, step, viscous) \
    if (sph_kernel_negative_from(id, dim) == 0.0) {                      \
        if (buf[0])                                                      \
            strncat(buf, ", ", size - strlen(buf) - 1);                  \
        strncat(buf, #name, size - strlen(buf) - 1);                     \
    }
    SPH_KERNELS(KERNEL_IF_NON_NEGATIVE)
#undef KERNEL_IF_NON_NEGATIVE
    return buf;
}
