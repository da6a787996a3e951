/*
 * Benchmark of the library on the paper's uniaxial piston scene.
 *
 *   bench_piston [--repeats N] [--quick]
 *
 * (a) particle-steps per second (all particles, piston and plate included,
 *     times steps) over 200 steps at dx = 1 mm, with 1 and 2 threads;
 * (b) time to solution: wall seconds to simulate 0.3 ms at dx = 2 mm and
 *     1 mm (artificial viscosity alpha = 1), 1 and 2 threads;
 * (c) bytes per particle held by the library.
 * Medians over the repeats; every figure comes from this one run.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_timing.h"
#include "sphsolid.h"




static sph_sim *scene(double dx, int threads)
{
    sph_sim *sim = NULL;
    if (sph_create(2, &sim) || sph_set_threads(sim, threads) ||
        sph_build_paper_scene(sim, dx, 1.5e-3, 0, NULL) ||
        sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0")) {
        fprintf(stderr, "bench_piston: %s\n", sph_errmsg(sim));
        exit(1);
    }
    return sim;
}

/* Wall seconds of `steps` steps (or until t_end if steps < 0), after one
 * warm-up step that builds the neighbour list. */
static double timed_run(double dx, int threads, long steps, double t_end, size_t *particles,
                        size_t *bytes)
{
    sph_sim *sim = scene(dx, threads);
    if (sph_run(sim, 1)) {
        fprintf(stderr, "bench_piston: %s\n", sph_errmsg(sim));
        exit(1);
    }
    const double t0 = bench_now();
    const sph_status st = steps >= 0 ? sph_run(sim, steps) : sph_run_until(sim, t_end);
    const double wall = bench_now() - t0;
    if (st) {
        fprintf(stderr, "bench_piston: %s\n", sph_errmsg(sim));
        exit(1);
    }
    if (particles)
        *particles = sph_particle_count(sim);
    if (bytes)
        *bytes = sph_memory_bytes(sim);
    sph_destroy(sim);
    return wall;
}

int main(int argc, char **argv)
{
    int repeats = 5, quick = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--repeats") && i + 1 < argc)
            repeats = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--quick"))
            quick = 1;
        else {
            fprintf(stderr, "usage: bench_piston [--repeats N] [--quick]\n");
            return 2;
        }
    }
    if (repeats < 1)
        repeats = 1;
    double *w = malloc((size_t)repeats * sizeof *w);
    size_t n = 0, bytes = 0;
    printf("libsphsolid %s, paper piston scene, Improved Euler (2 rate evaluations/step), "
           "artificial viscosity alpha = 1; medians of %d runs\n\n", sph_version(), repeats);

    printf("(a) throughput, 200 steps at dx = 1 mm\n");
    double rate[3] = {0, 0, 0};
    for (int threads = 1; threads <= 2; ++threads) {
        for (int r = 0; r < repeats; ++r)
            w[r] = timed_run(1e-3, threads, quick ? 50 : 200, 0.0, &n, &bytes);
        const double m = bench_median(w, repeats);
        rate[threads] = (double)n * (quick ? 50 : 200) / m;
        printf("  %d thread%s: %.3f s, %.3g particle-steps/s (%zu particles)\n", threads,
               threads > 1 ? "s" : " ", m, rate[threads], n);
    }
    printf("  speed-up on 2 threads: %.2fx\n\n", rate[2] / rate[1]);

    printf("(b) time to solution, 0.3 ms of simulated time\n");
    const double dxs[2] = {2e-3, 1e-3};
    for (int k = 0; k < (quick ? 1 : 2); ++k)
        for (int threads = 1; threads <= 2; ++threads) {
            for (int r = 0; r < repeats; ++r)
                w[r] = timed_run(dxs[k], threads, -1, 0.3e-3, &n, NULL);
            printf("  dx = %g mm, %d thread%s: %.3f s (%zu particles)\n", dxs[k] * 1e3, threads,
                   threads > 1 ? "s" : " ", bench_median(w, repeats), n);
        }

    timed_run(1e-3, 1, 1, 0.0, &n, &bytes);
    printf("\n(c) memory: %zu bytes for %zu particles = %.0f bytes/particle\n", bytes, n,
           (double)bytes / (double)n);
    free(w);
    return 0;
}
