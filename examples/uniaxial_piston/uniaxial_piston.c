/*
 * The paper's uniaxial piston test (Das & Cleary): a 86 x 140 mm specimen
 * squeezed by a piston moving down at 1.5 mm/s against a fixed plate.
 *
 *   uniaxial_piston [--dx MM] [--until MS] [--out FILE.h5] [--csv FILE.csv]
 *                   [--threads N] [--alpha A] [--snapshots N]
 *                   [--integrator NAME] [--quiet]
 *
 * Defaults: dx = 2 mm, until = 0.3 ms, out = uniaxial_piston.h5, csv next
 * to it, artificial viscosity alpha = 1 (the documented default for wave
 * problems; --alpha 0 switches it off), 10 snapshots, the library's default
 * integrator (improved_euler; --integrator leapfrog for the symplectic one,
 * at its own default step).
 */
#define _POSIX_C_SOURCE 199309L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "sphsolid.h"

typedef struct progress {
    double t_end, wall_start;
    int quiet, tty;
    long every;
} progress;

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int report(const sph_sim *sim, void *user)
{
    const progress *p = user;
    if (!p->quiet) {
        const double t = sph_time(sim), wall = wall_seconds() - p->wall_start;
        const double eta = t > 0.0 ? wall * (p->t_end - t) / t : 0.0;
        fprintf(stderr, "%s  t = %8.4f ms  (%5.1f %%)  step %ld  wall %.1f s  eta %.1f s   %s",
                p->tty ? "\r" : "", t * 1e3, 100.0 * t / p->t_end, sph_step_count(sim), wall, eta,
                p->tty ? "" : "\n");
        fflush(stderr);
    }
    return 0;
}

static int fail(sph_sim *sim, sph_status st, const char *what)
{
    fprintf(stderr, "uniaxial_piston: %s: %s (%s)\n", what, sph_errmsg(sim), sph_status_name(st));
    sph_destroy(sim);
    return 1;
}

static double number(const char *flag, const char *text)
{
    char *end;
    const double v = strtod(text, &end);
    if (*end || end == text || !isfinite(v)) {
        fprintf(stderr, "uniaxial_piston: %s expects a finite number, got '%s'\n", flag, text);
        exit(2);
    }
    return v;
}

/* A whole number in [lo, hi] for an option that counts something. */
static long count(const char *flag, const char *text, long lo, long hi)
{
    const double v = number(flag, text);
    if (v != floor(v) || v < (double)lo || v > (double)hi) {
        fprintf(stderr, "uniaxial_piston: %s expects a whole number in [%ld, %ld], got '%s'\n",
                flag, lo, hi, text);
        exit(2);
    }
    return (long)v;
}

int main(int argc, char **argv)
{
    double dx_mm = 2.0, until_ms = 0.3, alpha = 1.0;
    long snapshots = 10;
    int threads = 0, quiet = 0;
    const char *out = "uniaxial_piston.h5", *csv = NULL, *integrator = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *next = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--quiet")) {
            quiet = 1;
            continue;
        }
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            printf("usage: %s [--dx MM] [--until MS] [--out FILE.h5] [--csv FILE.csv] "
                   "[--threads N] [--alpha A] [--snapshots N] [--integrator %s] [--quiet]\n",
                   argv[0], sph_integrator_names());
            return 0;
        }
        if (!next) {
            fprintf(stderr, "uniaxial_piston: unknown or incomplete option '%s' (try --help)\n", a);
            return 2;
        }
        if (!strcmp(a, "--dx"))
            dx_mm = number(a, next);
        else if (!strcmp(a, "--until"))
            until_ms = number(a, next);
        else if (!strcmp(a, "--out"))
            out = next;
        else if (!strcmp(a, "--csv"))
            csv = next;
        else if (!strcmp(a, "--threads"))
            threads = (int)count(a, next, 0, 4096);
        else if (!strcmp(a, "--alpha"))
            alpha = number(a, next);
        else if (!strcmp(a, "--snapshots"))
            snapshots = count(a, next, 0, 1000000);
        else if (!strcmp(a, "--integrator"))
            integrator = next;
        else {
            fprintf(stderr, "uniaxial_piston: unknown option '%s' (try --help)\n", a);
            return 2;
        }
        ++i;
    }
    if (alpha < 0.0) {
        fprintf(stderr, "uniaxial_piston: --alpha %g must be >= 0 (0 switches the viscosity off)\n",
                alpha);
        return 2;
    }
    if (!(dx_mm > 0.0) || !(until_ms > 0.0)) {
        fprintf(stderr, "uniaxial_piston: --dx %g mm and --until %g ms must be > 0\n", dx_mm,
                until_ms);
        return 2;
    }
    char *csv_path = NULL; /* any length: derived from --out */
    if (!csv) {
        csv_path = malloc(strlen(out) + sizeof "_probes.csv");
        if (!csv_path) {
            fprintf(stderr, "uniaxial_piston: out of memory\n");
            return 1;
        }
        strcpy(csv_path, out);
        char *dot = strrchr(csv_path, '.');
        if (dot && !strchr(dot, '/'))
            *dot = '\0';
        strcat(csv_path, "_probes.csv");
        csv = csv_path;
    }

    sph_sim *sim = NULL;
    sph_status st = sph_create(2, &sim);
    if (st)
        return fail(sim, st, "create");
    if ((st = sph_set_threads(sim, threads)))
        return fail(sim, st, "--threads");
    sph_paper_scene scene;
    if ((st = sph_build_paper_scene(sim, dx_mm * 1e-3, 1.5e-3, 0, &scene)))
        return fail(sim, st, "--dx");
    if (integrator && (st = sph_set_integrator(sim, integrator)))
        return fail(sim, st, "--integrator");
    if (alpha > 0.0) {
        char params[64];
        snprintf(params, sizeof params, "alpha=%.17g beta=0", alpha);
        if ((st = sph_effect(sim, "artificial_viscosity", params)))
            return fail(sim, st, "--alpha");
    }
    sph_body_info specimen;
    sph_body_info_get(sim, scene.specimen, &specimen);
    const double dt = sph_dt(sim), t_end = until_ms * 1e-3;
    if (!(t_end > 0.0)) {
        fprintf(stderr, "uniaxial_piston: --until %g ms must be > 0\n", until_ms);
        return 2;
    }
    const long steps = (long)(t_end / dt + 0.999999);
    printf("uniaxial piston test: dx = %g mm, h = %g mm\n", dx_mm, sph_smoothing_length(sim) * 1e3);
    printf("specimen particles: %zu (all particles incl. piston and plate: %zu)\n", specimen.count,
           sph_particle_count(sim));
    printf("time step: %.3f us, %ld steps to %g ms\n", dt * 1e6, steps, until_ms);
    printf("integrator: %s\n", sph_integrator_name(sim));
    printf("effects: %s\n", alpha > 0.0 ? "artificial_viscosity" : "none");

    const long probe_every = steps / 2000 > 0 ? steps / 2000 : 1;
    const long snap_every = snapshots > 0 ? (steps / snapshots > 0 ? steps / snapshots : 1) : 0;
    if ((st = sph_output_open(sim, out, snap_every, probe_every)) && st != SPH_ERR_UNSUPPORTED)
        return fail(sim, st, "--out");
    const int have_output = st == SPH_OK;
    if (!have_output)
        fprintf(stderr, "uniaxial_piston: built without HDF5; writing only %s\n", csv);

    FILE *f = fopen(csv, "w");
    if (!f) {
        fprintf(stderr, "uniaxial_piston: cannot write '%s': %s\n", csv, strerror(errno));
        sph_destroy(sim);
        return 1;
    }
    fprintf(f, "time_s,vm_A_Pa,vm_B_Pa,vm_C_Pa,syy_A_Pa,syy_B_Pa,syy_C_Pa\n");
    progress p = {t_end, wall_seconds(), quiet, isatty(2), 0};
    p.every = p.tty ? 20 : 200;
    const int nv = SPH_PROBE_VALUES(2);
    const double t0 = wall_seconds();
    long done = 0;
    while (done < steps) {
        double vals[3][SPH_PROBE_VALUES(3)];
        for (int k = 0; k < 3; ++k)
            if ((st = sph_probe_sample(sim, k, vals[k]))) {
                fclose(f);
                return fail(sim, st, "probe");
            }
        fprintf(f, "%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e\n", sph_time(sim), vals[0][0], vals[1][0],
                vals[2][0], vals[0][3], vals[1][3], vals[2][3]);
        (void)nv;
        const long chunk = steps - done < probe_every ? steps - done : probe_every;
        const double t_next = done + chunk >= steps ? t_end : (double)(done + chunk) * dt;
        if ((st = sph_run_until(sim, t_next))) {
            fclose(f);
            if (have_output)
                sph_output_snapshot(sim);
            return fail(sim, st, "run");
        }
        done += chunk;
        if (!quiet && (done % (probe_every * p.every) == 0 || done == steps))
            report(sim, &p);
    }
    const double wall = wall_seconds() - t0;
    const int csv_bad = ferror(f) != 0;
    if (fclose(f) != 0 || csv_bad) {
        fprintf(stderr, "uniaxial_piston: writing '%s' failed: %s\n", csv, strerror(errno));
        sph_destroy(sim);
        return 1;
    }
    if (!quiet && p.tty)
        fprintf(stderr, "\n");
    if (have_output && ((st = sph_output_snapshot(sim)) || (st = sph_output_close(sim))))
        return fail(sim, st, "--out");
    double a[SPH_PROBE_VALUES(3)], b[SPH_PROBE_VALUES(3)], c[SPH_PROBE_VALUES(3)];
    sph_probe_sample(sim, scene.probe_A, a);
    sph_probe_sample(sim, scene.probe_B, b);
    sph_probe_sample(sim, scene.probe_C, c);
    printf("t = %g ms: von Mises A = %.4g Pa, B = %.4g Pa, C = %.4g Pa\n", sph_time(sim) * 1e3,
           a[0], b[0], c[0]);
    printf("wall time %.2f s, %.3g particle-steps/s\n", wall,
           (double)sph_particle_count(sim) * (double)steps / wall);
    if (have_output)
        printf("wrote %s and %s\n", out, csv);
    else
        printf("wrote %s\n", csv);
    free(csv_path);
    sph_destroy(sim);
    return 0;
}
