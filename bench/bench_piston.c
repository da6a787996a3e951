/*
 * Benchmark of the library on the paper's uniaxial piston scene.
 *
 *   bench_piston [--repeats N] [--quick]
 *   bench_piston --throughput [--repeats N]
 *
 * (a) particle-steps per second (all particles, piston and plate included,
 *     times steps) over 200 steps at dx = 1 mm, with 1 and 2 threads, per
 *     wall second and per CPU second of the process (the second is less
 *     sensitive to other load on the machine), and pair interactions per
 *     second (pairs closer than the support 2h, each counted once, times
 *     the rate evaluations' worth of pair work of a step: 2 for Improved
 *     Euler, 1 for the leapfrog's continuity and momentum passes);
 * (b) time to solution: wall seconds to simulate 0.3 ms at dx = 2 mm and
 *     1 mm (artificial viscosity alpha = 1), 1 and 2 threads;
 * (a) and (b) for each integrator (Improved Euler, the paper's default, and
 * the leapfrog, each at its default step);
 * (c) bytes per particle held by the library, by part (sph_memory_parts),
 *     for the 2D paper scene and a 3D block.
 * Medians over the repeats, side by side; every figure comes from this one
 * run.  With --throughput only one-thread pair throughput: the paper scene
 * (dx = 1 mm, 300 steps) with each integrator and the 3D cylinder (dx =
 * 3 mm, 60 steps), pair
 * interactions per wall and CPU second and the share of one core's
 * double-precision peak they make (flops per pair: docs/performance.md,
 * "Pair throughput and peak"); scripts/compare_throughput.sh runs it
 * against another commit's library, interleaved.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_timing.h"
#include "sphsolid.h"

/* CPU seconds of the whole process (all threads). */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Pairs closer than 2h, each once (a cell sort along x, then a sweep). */
static int compare_x(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double interacting_pairs(sph_sim *sim)
{
    double *x = NULL;
    size_t n = 0, dim = 0;
    if (sph_field(sim, SPH_FIELD_POSITION, &x, &n, &dim))
        return 0.0;
    double *p = malloc(n * 3 * sizeof *p);
    for (size_t a = 0; a < n; ++a)
        for (size_t i = 0; i < 3; ++i)
            p[3 * a + i] = i < dim ? x[a * dim + i] : 0.0;
    qsort(p, n, 3 * sizeof *p, compare_x);
    const double rc = 2.0 * sph_smoothing_length(sim), rc2 = rc * rc;
    double pairs = 0.0;
    for (size_t a = 0; a < n; ++a)
        for (size_t b = a + 1; b < n && p[3 * b] - p[3 * a] < rc; ++b) {
            double r2 = 0.0;
            for (int i = 0; i < 3; ++i)
                r2 += (p[3 * a + i] - p[3 * b + i]) * (p[3 * a + i] - p[3 * b + i]);
            pairs += r2 < rc2;
        }
    free(p);
    return pairs;
}

static void print_memory(sph_sim *sim, const char *what)
{
    const char *names[SPH_MEMORY_PARTS];
    size_t bytes[SPH_MEMORY_PARTS];
    const int parts = sph_memory_parts(sim, names, bytes, SPH_MEMORY_PARTS);
    const double n = (double)sph_particle_count(sim);
    printf("  %s: %zu particles, %.0f bytes/particle\n", what, sph_particle_count(sim),
           (double)sph_memory_bytes(sim) / n);
    for (int k = 0; k < parts; ++k)
        printf("    %-24s %7.1f bytes/particle\n", names[k], (double)bytes[k] / n);
}

static const char *integrator = "improved_euler";

/* Flops per pair interaction (docs/performance.md, "Pair throughput and
 * peak"; artificial viscosity on, cubic spline): [dimension - 2][leapfrog]. */
static const double flops_per_pair[2][2] = {{84.0, 102.0}, {140.0, 163.0}};

/* One core's double-precision peak [flop/s]: the clock of /proc/cpuinfo
 * times 16 flops per cycle with AVX2 or AVX-512 (two 256-bit FMA pipes, as
 * on AMD Zen 4; Intel server cores with two 512-bit pipes have 32), else
 * 4 (SSE2: one 2-wide add and one 2-wide multiply).  0 if unknown. */
static double core_peak(const char **what)
{
    double mhz = 0.0;
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, "cpu MHz", 7) && sscanf(strchr(line, ':') + 1, "%lf", &mhz) == 1)
            break;
    if (f)
        fclose(f);
    double per_cycle = 4.0;
    *what = "SSE2, 4 flops/cycle";
#if defined(__GNUC__) && defined(__x86_64__)
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        per_cycle = 16.0;
        *what = "AVX2/AVX-512 with FMA, 16 flops/cycle";
    }
#endif
    return mhz * 1e6 * per_cycle;
}

static sph_sim *cylinder_scene(double dx)
{
    sph_sim *sim = NULL;
    int rock, specimen, plate, piston;
    const double base[3] = {0.0, 0.0, 0.0};
    if (sph_create(3, &sim) || sph_set_threads(sim, 1) || sph_set_integrator(sim, integrator) ||
        sph_add_material_K_mu(sim, 12.2e9, 2.67e9, 2300.0, &rock) ||
        sph_add_cylinder(sim, "specimen", rock, base, 0.027, 0.135, dx, &specimen) ||
        sph_add_plate(sim, "plate", -1, specimen, 0, &plate) ||
        sph_add_piston(sim, "piston", -1, specimen, 0, 1.5e-3, &piston) ||
        sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0")) {
        fprintf(stderr, "bench_piston: %s\n", sph_errmsg(sim));
        exit(1);
    }
    return sim;
}

static sph_sim *scene(double dx, int threads)
{
    sph_sim *sim = NULL;
    if (sph_create(2, &sim) || sph_set_threads(sim, threads) ||
        sph_set_integrator(sim, integrator) || sph_build_paper_scene(sim, dx, 1.5e-3, 0, NULL) ||
        sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0")) {
        fprintf(stderr, "bench_piston: %s\n", sph_errmsg(sim));
        exit(1);
    }
    return sim;
}

/* Wall seconds of `steps` steps (or until t_end if steps < 0), after one
 * warm-up step that builds the neighbour list; the process's CPU seconds
 * and the interacting pairs at the start if asked. */
static double timed_run(double dx, int threads, long steps, double t_end, size_t *particles,
                        size_t *bytes, double *cpu, double *pairs)
{
    sph_sim *sim = scene(dx, threads);
    if (sph_run(sim, 1)) {
        fprintf(stderr, "bench_piston: %s\n", sph_errmsg(sim));
        exit(1);
    }
    if (pairs)
        *pairs = interacting_pairs(sim);
    const double c0 = cpu_now(), t0 = bench_now();
    const sph_status st = steps >= 0 ? sph_run(sim, steps) : sph_run_until(sim, t_end);
    const double wall = bench_now() - t0;
    if (cpu)
        *cpu = cpu_now() - c0;
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

/* One thread's pair interactions per wall and CPU second, medians. */
static void throughput(int repeats)
{
    const char *what = "";
    const double peak = core_peak(&what);
    printf("libsphsolid %s, 1 thread, medians of %d runs; peak of one core %.3g Gflop/s (%s)\n",
           sph_version(), repeats, peak * 1e-9, what);
    static const char *const integrators[2] = {"improved_euler", "leapfrog"};
    double *w = malloc((size_t)repeats * sizeof *w), *c = malloc((size_t)repeats * sizeof *c);
    for (int dim = 2; dim <= 3; ++dim)
        for (int q = 0; q < 2; ++q) {
            integrator = integrators[q];
            /* about a second per case: shorter runs let the host's
             * moments decide single repeats */
            const long steps = dim == 2 ? 300 : 60;
            double pairs = 0.0, ev = 0.0;
            size_t n = 0;
            for (int r = 0; r < repeats; ++r) {
                sph_sim *sim = dim == 2 ? scene(1e-3, 1) : cylinder_scene(3e-3);
                sph_integrator_info info;
                if (sph_integrator_info_get(sim, NULL, &info) || sph_run(sim, 1)) {
                    fprintf(stderr, "bench_piston: %s\n", sph_errmsg(sim));
                    exit(1);
                }
                ev = info.evaluations;
                pairs = interacting_pairs(sim);
                n = sph_particle_count(sim);
                const double c0 = cpu_now(), t0 = bench_now();
                if (sph_run(sim, steps)) {
                    fprintf(stderr, "bench_piston: %s\n", sph_errmsg(sim));
                    exit(1);
                }
                w[r] = bench_now() - t0;
                c[r] = cpu_now() - c0;
                sph_destroy(sim);
            }
            const double m = bench_median(w, repeats), mc = bench_median(c, repeats);
            const double rate = ev * pairs * (double)steps / m;
            const double flops = flops_per_pair[dim - 2][q == 1];
            printf("%s %-14s %6zu particles: %.4g pair interactions/s (CPU: %.4g), %.0f "
                   "flops/pair: %.3g Gflop/s, %.1f %% of peak\n",
                   dim == 2 ? "paper 2D  " : "cylinder 3D", integrator, n, rate,
                   ev * pairs * (double)steps / mc, flops, rate * flops * 1e-9,
                   peak > 0.0 ? 100.0 * rate * flops / peak : 0.0);
        }
    free(w);
    free(c);
}

int main(int argc, char **argv)
{
    int repeats = 5, quick = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--repeats") && i + 1 < argc)
            repeats = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--quick"))
            quick = 1;
        else if (!strcmp(argv[i], "--throughput"))
            quick = 2;
        else {
            fprintf(stderr, "usage: bench_piston [--repeats N] [--quick | --throughput]\n");
            return 2;
        }
    }
    if (repeats < 1)
        repeats = 1;
    if (quick == 2) {
        throughput(repeats);
        return 0;
    }
    double *w = malloc((size_t)repeats * sizeof *w), *c = malloc((size_t)repeats * sizeof *c);
    double pairs = 0.0;
    size_t n = 0, bytes = 0;
    printf("libsphsolid %s, paper piston scene, artificial viscosity alpha = 1; medians of %d "
           "runs\n",
           sph_version(), repeats);
    static const char *const integrators[2] = {"improved_euler", "leapfrog"};
    const long steps = quick ? 50 : 200;
    for (int q = 0; q < 2; ++q) {
        integrator = integrators[q];
        sph_sim *probe = scene(1e-3, 1);
        sph_integrator_info info;
        if (sph_integrator_info_get(probe, NULL, &info)) {
            fprintf(stderr, "bench_piston: %s\n", sph_errmsg(probe));
            return 1;
        }
        printf("\n%s: step %.3g s at dx = 1 mm, %d evaluation%s' worth of pair work per step\n",
               integrator, sph_dt(probe), info.evaluations, info.evaluations > 1 ? "s" : "");
        sph_destroy(probe);
        const double ev = info.evaluations;
        printf("(a) throughput, %ld steps at dx = 1 mm (wall; per CPU second of the process)\n",
               steps);
        double rate[3] = {0, 0, 0};
        for (int threads = 1; threads <= 2; ++threads) {
            for (int r = 0; r < repeats; ++r)
                w[r] = timed_run(1e-3, threads, steps, 0.0, &n, &bytes, &c[r], &pairs);
            const double m = bench_median(w, repeats), mc = bench_median(c, repeats);
            rate[threads] = (double)n * (double)steps / m;
            printf("  %d thread%s: %.3f s, %.3g particle-steps/s, %.3g pair interactions/s; "
                   "CPU %.3f s: %.3g particle-steps/CPU-s, %.3g pair interactions/CPU-s\n",
                   threads, threads > 1 ? "s" : " ", m, rate[threads],
                   ev * pairs * (double)steps / m, mc, (double)n * (double)steps / mc,
                   ev * pairs * (double)steps / mc);
        }
        printf("  (%zu particles, %.0f interacting pairs, %.2f per particle)\n", n, pairs,
               pairs / (double)n);
        printf("  speed-up on 2 threads: %.2fx\n", rate[2] / rate[1]);

        printf("(b) time to solution, 0.3 ms of simulated time\n");
        const double dxs[2] = {2e-3, 1e-3};
        for (int k = 0; k < (quick ? 1 : 2); ++k)
            for (int threads = 1; threads <= 2; ++threads) {
                for (int r = 0; r < repeats; ++r)
                    w[r] = timed_run(dxs[k], threads, -1, 0.3e-3, &n, NULL, NULL, NULL);
                printf("  dx = %g mm, %d thread%s: %.3f s (%zu particles)\n", dxs[k] * 1e3, threads,
                       threads > 1 ? "s" : " ", bench_median(w, repeats), n);
            }
    }
    integrator = integrators[0];

    printf("\n(c) memory after one step\n");
    sph_sim *sim = scene(1e-3, 1);
    if (sph_run(sim, 1)) {
        fprintf(stderr, "bench_piston: %s\n", sph_errmsg(sim));
        return 1;
    }
    print_memory(sim, "2D paper scene, dx = 1 mm, artificial viscosity");
    sph_destroy(sim);
    /* 3D: a free block of 24^3 particles, h = 1.3 dx, same material */
    sph_sim *s3 = NULL;
    int mat, body;
    const double lo[3] = {0, 0, 0}, hi[3] = {0.024, 0.024, 0.024};
    if (sph_create(3, &s3) || sph_set_threads(s3, 1) ||
        sph_add_material_K_mu(s3, 7.8e9, 2.9e9, 2700.0, &mat) ||
        sph_add_block(s3, "block", mat, lo, hi, 1e-3, &body) ||
        sph_effect(s3, "artificial_viscosity", "alpha=1 beta=0") || sph_run(s3, 1)) {
        fprintf(stderr, "bench_piston: %s\n", sph_errmsg(s3));
        return 1;
    }
    print_memory(s3, "3D block 24^3, dx = 1 mm, artificial viscosity");
    sph_destroy(s3);
    (void)bytes;
    free(w);
    free(c);
    return 0;
}
