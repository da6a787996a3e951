/*
 * Cost of each effect: the paper's piston scene with no effect, then with
 * each effect switched on alone, then probe sampling and HDF5 output.
 *
 *   bench_effects [--dx METRES] [--steps N] [--repeats N] [--threads N]
 *                 [--h5 PATH]
 *
 * Prints wall and process CPU milliseconds per Improved Euler step (median
 * of the repeats, after one warm-up step that builds the neighbour list)
 * and the ratio of CPU time to the scene with no effect.  The repeats are
 * interleaved (every case once, then again), so a machine whose load
 * changes during the run weighs on every case alike; with one thread the
 * CPU time is the one to compare on a shared machine.  Effects that are off
 * cost nothing in the pair loop; this shows what each one costs when on.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_timing.h"
#include "sphsolid.h"

typedef struct bench_case {
    const char *label;
    const char *effect; /* NULL: none */
    const char *parameters;
    int probes;                  /* sample A, B, C after every step */
    int output;                  /* HDF5 snapshot every 10 steps */
    double weibull_k, weibull_m; /* the specimen's flaws (damage) */
    int account;                 /* the energy account on (sph_set_energy_account) */
} bench_case;

static const bench_case CASES[] = {
    {"none", NULL, NULL, 0, 0, 0, 0, 0},
    {"artificial_viscosity", "artificial_viscosity", "alpha=1 beta=0", 0, 0, 0, 0, 0},
    {"artificial_stress", "artificial_stress", "epsilon=0.3 n=4", 0, 0, 0, 0, 0},
    {"xsph", "xsph", "epsilon=0.5", 0, 0, 0, 0, 0},
    {"kernel_correction", "kernel_correction", "", 0, 0, 0, 0, 0},
    {"gravity", "gravity", "gx=0 gy=-9.81", 0, 0, 0, 0, 0},
    {"damping", "damping", "rate=1000", 0, 0, 0, 0, 0},
    /* damage: flaws that this run's strains (below 1e-6) never reach,
     * then the ~10 flaws of every particle below 1e-7 (k V = 1e66): the
     * particles strained at all (1,280 of 12,040 after 50 steps) count
     * their active flaws again each step and grow D */
    {"damage (no flaw active)", "damage", "seed=1", 0, 0, 1e28, 9.0, 0},
    {"damage (flaws active)", "damage", "seed=1", 0, 0, 1e72, 9.0, 0},
    /* drucker_prager: a cone no stress of this run reaches, then one that
     * the strained particles leave (cohesion 1 Pa, no friction: 6,998 of
     * the 12,040 return to a nearly zero deviator at step 101) */
    {"drucker_prager (elastic)", "drucker_prager", "cohesion=1e9 friction_angle=30", 0, 0, 0, 0, 0},
    {"drucker_prager (returning)", "drucker_prager", "cohesion=1 friction_angle=0", 0, 0, 0, 0, 0},
    /* the energy account: a pass over the prescribed particles per rate
     * evaluation, and with viscosity on one over the pairs */
    {"energy account", NULL, NULL, 0, 0, 0, 0, 1},
    {"artificial_viscosity + energy account", "artificial_viscosity", "alpha=1 beta=0", 0, 0, 0, 0,
     1},
    {"probes A, B, C every step", NULL, NULL, 1, 0, 0, 0, 0},
    {"HDF5 snapshot every 10 steps", NULL, NULL, 0, 1, 0, 0, 0},
};

static void fail(sph_sim *sim, const char *what)
{
    fprintf(stderr, "bench_effects: %s: %s\n", what, sph_errmsg(sim));
    exit(1);
}

/* Process CPU time [s]. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Wall seconds per step of one case (its CPU seconds in *cpu), or a
 * negative value if unsupported. */
static double per_step(const bench_case *c, double dx, long steps, int threads, const char *h5,
                       size_t *particles, double *cpu)
{
    sph_sim *sim = NULL;
    sph_paper_scene paper;
    if (sph_create(2, &sim) || sph_set_threads(sim, threads) ||
        sph_build_paper_scene(sim, dx, 1.5e-3, 0, &paper))
        fail(sim, "scene");
    if (c->weibull_k > 0.0 && (sph_material_set(sim, paper.material, "weibull_k", c->weibull_k) ||
                               sph_material_set(sim, paper.material, "weibull_m", c->weibull_m)))
        fail(sim, c->label);
    if (c->effect && sph_effect(sim, c->effect, c->parameters))
        fail(sim, c->label);
    if (c->account && sph_set_energy_account(sim, 1))
        fail(sim, c->label);
    if (c->output && sph_output_open(sim, h5, 10, 0)) {
        sph_destroy(sim);
        return -1.0; /* library built without HDF5 */
    }
    if (sph_run(sim, 1))
        fail(sim, "warm-up");
    double values[16];
    const double t0 = bench_now(), c0 = cpu_now();
    if (c->probes) {
        for (long s = 0; s < steps; ++s)
            if (sph_run(sim, 1) || sph_probe_sample(sim, paper.probe_A, values) ||
                sph_probe_sample(sim, paper.probe_B, values) ||
                sph_probe_sample(sim, paper.probe_C, values))
                fail(sim, c->label);
    } else if (sph_run(sim, steps)) {
        fail(sim, c->label);
    }
    const double wall = (bench_now() - t0) / (double)steps;
    *cpu = (cpu_now() - c0) / (double)steps;
    if (c->output)
        sph_output_close(sim);
    *particles = sph_particle_count(sim);
    sph_destroy(sim);
    return wall;
}

int main(int argc, char **argv)
{
    double dx = 1e-3;
    long steps = 100;
    int repeats = 3, threads = 1;
    const char *h5 = "bench_effects.h5";
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--dx") && i + 1 < argc)
            dx = atof(argv[++i]);
        else if (!strcmp(argv[i], "--steps") && i + 1 < argc)
            steps = atol(argv[++i]);
        else if (!strcmp(argv[i], "--repeats") && i + 1 < argc)
            repeats = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc)
            threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--h5") && i + 1 < argc)
            h5 = argv[++i];
        else {
            fprintf(stderr, "usage: bench_effects [--dx METRES] [--steps N] "
                            "[--repeats N] [--threads N] [--h5 PATH]\n");
            return 2;
        }
    }
    if (dx <= 0 || steps < 1 || repeats < 1 || threads < 1) {
        fprintf(stderr, "bench_effects: dx, steps, repeats and threads must be positive\n");
        return 2;
    }
    enum { N_CASES = sizeof CASES / sizeof CASES[0] };
    double *w = malloc((size_t)repeats * N_CASES * sizeof *w);
    double *cpu = malloc((size_t)repeats * N_CASES * sizeof *cpu);
    size_t n = 0;
    double base = 0.0;
    printf("libsphsolid %s, paper piston scene, dx = %g mm, %d thread%s, %ld steps, "
           "median of %d\n\n",
           sph_version(), dx * 1e3, threads, threads > 1 ? "s" : "", steps, repeats);
    printf("| effect alone | wall ms per step | CPU ms per step | CPU relative to none |\n"
           "|---|---|---|---|\n");
    for (int r = 0; r < repeats; ++r)
        for (size_t k = 0; k < N_CASES; ++k)
            w[k * (size_t)repeats + (size_t)r] = per_step(&CASES[k], dx, steps, threads, h5, &n,
                                                          &cpu[k * (size_t)repeats + (size_t)r]);
    for (size_t k = 0; k < N_CASES; ++k) {
        const double m = bench_median(w + k * (size_t)repeats, repeats);
        const double mc = bench_median(cpu + k * (size_t)repeats, repeats);
        if (m < 0) {
            printf("| %s | (no HDF5) | | |\n", CASES[k].label);
            continue;
        }
        if (k == 0)
            base = mc;
        printf("| %s | %.3f | %.3f | %.2f |\n", CASES[k].label, m * 1e3, mc * 1e3, mc / base);
    }
    printf("\n%zu particles\n", n);
    remove(h5);
    free(w);
    free(cpu);
    return 0;
}
