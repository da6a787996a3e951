/* Domain, kernel and smoothing length. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "physics/kernel.h"
#include "core/sim.h"

/* ----------------------------------------------------- domain and kernel */

sph_status sph_set_domain(sph_sim *sim, const double lo[3], const double hi[3],
                          const int periodic[3])
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!lo || !hi)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "domain: lo and hi must not be NULL");
    for (int i = 0; i < sim->dim; ++i)
        if (!(hi[i] > lo[i]) || !isfinite(lo[i]) || !isfinite(hi[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "domain along %c: [%g, %g] is empty or not finite", "xyz"[i], lo[i],
                            hi[i]);
    for (size_t a = 0; a < sim->n; ++a)
        for (int i = 0; i < sim->dim; ++i) {
            const double xi = sim->x[a * sim->dim + i];
            if (xi < lo[i] || xi > hi[i])
                return sph_fail(
                    sim, SPH_ERR_ARGUMENT,
                    "domain along %c: [%g, %g] leaves out particle %zu of body '%s' at %g",
                    "xyz"[i], lo[i], hi[i], a, sim->bodies[sim->body_of[a]].name, xi);
        }
    sim->has_domain = 1;
    for (int i = 0; i < 3; ++i) {
        sim->lo[i] = i < sim->dim ? lo[i] : 0.0;
        sim->hi[i] = i < sim->dim ? hi[i] : 0.0;
        sim->periodic[i] = i < sim->dim && periodic ? periodic[i] != 0 : 0;
    }
    sim->nl.valid = 0;
    return sph_ok(sim);
}

sph_status sph_set_kernel(sph_sim *sim, sph_kernel kernel)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!sph_kernel_name(kernel))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "kernel=%d: not a sph_kernel (known: %s)",
                        (int)kernel, sph_kernel_names());
    sim->kernel = kernel;
    sim->rates_valid = 0;
    return sph_ok(sim);
}

sph_status sph_set_smoothing_ratio(sph_sim *sim, double ratio)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(ratio >= 0.5 && ratio <= 4.0))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "smoothing ratio h/dx=%g: must be in [0.5, 4]",
                        ratio);
    sim->h_over_dx = ratio;
    if (sim->dx_ref > 0.0)
        sim->h = ratio * sim->dx_ref;
    sim->nl.valid = 0;
    sim->rates_valid = 0;
    if (!sim->dt_set)
        sim->dt = 0.0;
    return sph_ok(sim);
}

double sph_smoothing_length(const sph_sim *sim) { return sim ? sim->h : 0.0; }

sph_status sph_set_spacing(sph_sim *sim, double dx)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(dx > 0.0) || !isfinite(dx))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "spacing dx=%g: must be finite and > 0", dx);
    sim->dx_ref = dx;
    sim->h = sim->h_over_dx * dx;
    sim->nl.valid = 0;
    sim->rates_valid = 0;
    if (!sim->dt_set)
        sim->dt = 0.0;
    return sph_ok(sim);
}
