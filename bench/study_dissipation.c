/*
 * How much dissipation does the paper's piston scene need at the paper's
 * time step, and what does it cost in accuracy?
 *
 *   study_dissipation --dx MM --until MS --alpha A [--alpha A ...] [--threads N]
 *
 * For each Monaghan viscosity alpha (beta = 0) it runs the scene, samples the
 * probes every microsecond, and prints: whether the run finished or where it
 * blew up, the probe von Mises stresses at the end, the roughness of probe
 * A's time series (mean |second difference| over mean |first difference|:
 * about 0 for a smooth curve, 2 for a sign-alternating one), and the wall
 * time.  Runs to 100 ms at 2 mm take minutes each.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_timing.h"
#include "sphsolid.h"

int main(int argc, char **argv)
{
    double dx = 2e-3, until = 100e-3, alphas[32];
    int n_alpha = 0, threads = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--dx"))
            dx = atof(argv[i + 1]) * 1e-3;
        else if (!strcmp(argv[i], "--until"))
            until = atof(argv[i + 1]) * 1e-3;
        else if (!strcmp(argv[i], "--alpha") && n_alpha < 32)
            alphas[n_alpha++] = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--threads"))
            threads = atoi(argv[i + 1]);
        else {
            fprintf(stderr,
                    "usage: study_dissipation --dx MM --until MS --alpha A [...] [--threads N]\n");
            return 2;
        }
    }
    if (n_alpha == 0) {
        const double defaults[] = {0.0, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0};
        n_alpha = 7;
        memcpy(alphas, defaults, sizeof defaults);
    }
    printf("paper piston scene, dx = %g mm, to %g ms, dt = 0.5 h/c0\n", dx * 1e3, until * 1e3);
    printf("%6s  %-24s  %12s %12s %12s  %9s  %8s\n", "alpha", "outcome", "vm_A [Pa]", "vm_B [Pa]",
           "vm_C [Pa]", "roughness", "wall [s]");
    for (int k = 0; k < n_alpha; ++k) {
        sph_sim *sim = NULL;
        sph_create(2, &sim);
        sph_set_threads(sim, threads);
        sph_paper_scene s;
        if (sph_build_paper_scene(sim, dx, 1.5e-3, 0, &s)) {
            fprintf(stderr, "%s\n", sph_errmsg(sim));
            return 1;
        }
        if (alphas[k] > 0.0) {
            char p[64];
            snprintf(p, sizeof p, "alpha=%g beta=0", alphas[k]);
            sph_effect(sim, "artificial_viscosity", p);
        }
        const double sample = 1e-6;
        double prev = NAN, prev2 = NAN, d1 = 0, d2 = 0, vals[3][8];
        char outcome[64] = "finished";
        const double t0 = bench_now();
        while (sph_time(sim) < until * (1 - 1e-12)) {
            const sph_status st = sph_run_until(sim, fmin(until, sph_time(sim) + sample));
            if (st) {
                snprintf(outcome, sizeof outcome, "blew up at %.3f ms", sph_time(sim) * 1e3);
                break;
            }
            sph_probe_sample(sim, s.probe_A, vals[0]);
            const double a = vals[0][0];
            if (!isnan(prev2)) {
                d1 += fabs(a - prev);
                d2 += fabs(a - 2 * prev + prev2);
            }
            prev2 = prev;
            prev = a;
        }
        const double wall = bench_now() - t0;
        sph_probe_sample(sim, s.probe_A, vals[0]);
        sph_probe_sample(sim, s.probe_B, vals[1]);
        sph_probe_sample(sim, s.probe_C, vals[2]);
        printf("%6.3g  %-24s  %12.5g %12.5g %12.5g  %9.3g  %8.1f\n", alphas[k], outcome, vals[0][0],
               vals[1][0], vals[2][0], d1 > 0 ? d2 / d1 : NAN, wall);
        fflush(stdout);
        sph_destroy(sim);
    }
    return 0;
}
