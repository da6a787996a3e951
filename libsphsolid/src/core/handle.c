/* The simulation handle: create, destroy, threads, watchdog. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "physics/kernel.h"
#include "core/sim.h"

/* ---------------------------------------------------------------- handle */

sph_status sph_create(int dimension, sph_sim **out)
{
    if (!out)
        return SPH_ERR_ARGUMENT;
    sph_sim *sim = calloc(1, sizeof *sim);
    *out = sim;
    if (!sim)
        return SPH_ERR_MEMORY;
    sim->dim = dimension == 3 ? 3 : 2;
    sim->ncomp = SPH_STRESS_COMPONENTS(sim->dim);
    sim->nsym = sim->dim == 2 ? 3 : 6;
    sim->h_over_dx = 1.2;
    sim->kernel = SPH_KERNEL_CUBIC_SPLINE;
    sim->progress_interval = 0;
    sim->watch_speed = 1.0;
    sim->watch_rho_min = 0.5;
    sim->watch_rho_max = 2.0;
    if (dimension != 2 && dimension != 3) {
        sim->failed = -1;
        return sph_fail(sim, SPH_ERR_ARGUMENT, "dimension=%d: must be 2 or 3", dimension);
    }
    const sph_status st = rates_path_from_environment(sim, &sim->rate_path);
    if (st)
        sim->failed = -1;
    return st;
}

void sph_destroy(sph_sim *sim)
{
    if (!sim)
        return;
    output_free(sim);
    free(sim->materials);
    free(sim->bodies);
    probes_free(sim);
    free(sim->x);
    free(sim->v);
    free(sim->rho);
    free(sim->S);
    free(sim->mass);
    free(sim->material_of);
    free(sim->body_of);
    free(sim->saved);
    free(sim->x_saved);
    free(sim->dv_dt);
    free(sim->drho_dt);
    free(sim->dS_dt);
    free(sim->dx_dt);
    free(sim->pair_data);
    free(sim->stress_R);
    free(sim->sum_scratch);
    free(sim->motion_scratch);
    for (size_t c = 0; c < sim->n_far; ++c) {
        free(sim->far[c].target);
        free(sim->far[c].terms);
    }
    free(sim->far);
    neighbour_free(&sim->nl);
    damage_free(sim);
    free(sim);
}

int sph_dimension(const sph_sim *sim) { return sim ? sim->dim : 0; }

sph_status sph_set_threads(sph_sim *sim, int threads)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (threads < 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "threads=%d: must be >= 0 (0 = OpenMP default)",
                        threads);
#ifdef _OPENMP
    /* more threads than cores only slow a run down; far more exhaust the
     * OpenMP runtime (100000 threads crash it inside the neighbour build) */
    const int cores = omp_get_num_procs();
    if (threads > SPH_THREADS_PER_CORE * cores)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "threads=%d: more than %d per core of the %d core%s this process may use "
                        "(at most %d; the fastest is usually one per core)",
                        threads, SPH_THREADS_PER_CORE, cores, cores == 1 ? "" : "s",
                        SPH_THREADS_PER_CORE * cores);
#endif
    sim->threads = threads;
    return sph_ok(sim);
}

sph_status sph_set_watchdog(sph_sim *sim, double max_speed_over_cp, double min_density_ratio,
                            double max_density_ratio)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(max_speed_over_cp >= 0.0) || !isfinite(max_speed_over_cp))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "watchdog max_speed_over_cp=%g: must be finite and >= 0",
                        max_speed_over_cp);
    if (!(min_density_ratio >= 0.0 && min_density_ratio < 1.0))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "watchdog min_density_ratio=%g: must be in [0, 1)",
                        min_density_ratio);
    if (!(max_density_ratio == 0.0 || (max_density_ratio > 1.0 && isfinite(max_density_ratio))))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "watchdog max_density_ratio=%g: must be 0 (off) or > 1", max_density_ratio);
    sim->watch_speed = max_speed_over_cp;
    sim->watch_rho_min = min_density_ratio;
    sim->watch_rho_max = max_density_ratio;
    return sph_ok(sim);
}
