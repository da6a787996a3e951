/*
 * The 3D uniaxial compression test of a laboratory cylinder: D = 54 mm,
 * L = 135 mm (2.5 diameters, ISRM / ASTM D7012) of the paper's material,
 * axis along y, between a fixed plate and a piston moving down at 1.5 mm/s
 * (particle platens, bonded ends), built with the library's geometry
 * builders alone.
 *
 *   uniaxial_cylinder [--dx MM] [--until MS] [--out FILE.h5] [--csv FILE.csv]
 *                     [--threads N] [--alpha A] [--snapshots N] [--quiet]
 *
 * Defaults: dx = 3 mm, until = 0.1 ms, out = uniaxial_cylinder.h5, csv
 * next to it, artificial viscosity alpha = 1, 4 snapshots.  Probes: A at
 * the centre and D at 3/4 of the length on the axis; B (3/4 of the length)
 * and C (mid-length) a quarter diameter off it.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sphsolid.h"

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int fail(sph_sim *sim, sph_status st, const char *what)
{
    fprintf(stderr, "uniaxial_cylinder: %s: %s (%s)\n", what, sph_errmsg(sim), sph_status_name(st));
    sph_destroy(sim);
    return 1;
}

static double number(const char *flag, const char *text)
{
    char *end;
    const double v = strtod(text, &end);
    if (*end || end == text) {
        fprintf(stderr, "uniaxial_cylinder: %s expects a number, got '%s'\n", flag, text);
        exit(2);
    }
    return v;
}

int main(int argc, char **argv)
{
    double dx_mm = 3.0, until_ms = 0.1, alpha = 1.0;
    long snapshots = 4;
    int threads = 0, quiet = 0;
    const char *out = "uniaxial_cylinder.h5", *csv = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *next = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--quiet")) {
            quiet = 1;
            continue;
        }
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            printf("usage: %s [--dx MM] [--until MS] [--out FILE.h5] [--csv FILE.csv] "
                   "[--threads N] [--alpha A] [--snapshots N] [--quiet]\n",
                   argv[0]);
            return 0;
        }
        if (!next) {
            fprintf(stderr, "uniaxial_cylinder: unknown or incomplete option '%s' (try --help)\n",
                    a);
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
            threads = (int)number(a, next);
        else if (!strcmp(a, "--alpha"))
            alpha = number(a, next);
        else if (!strcmp(a, "--snapshots"))
            snapshots = (long)number(a, next);
        else {
            fprintf(stderr, "uniaxial_cylinder: unknown option '%s' (try --help)\n", a);
            return 2;
        }
        ++i;
    }
    if (!(until_ms > 0.0)) {
        fprintf(stderr, "uniaxial_cylinder: --until %g ms must be > 0\n", until_ms);
        return 2;
    }
    char csv_path[1024];
    if (!csv) {
        snprintf(csv_path, sizeof csv_path, "%s", out);
        char *dot = strrchr(csv_path, '.');
        if (dot && !strchr(dot, '/'))
            *dot = '\0';
        strncat(csv_path, "_probes.csv", sizeof csv_path - strlen(csv_path) - 1);
        csv = csv_path;
    }

    const double D = 0.054, L = 0.135, speed = 1.5e-3, dx = dx_mm * 1e-3;
    sph_sim *sim = NULL;
    sph_status st = sph_create(3, &sim);
    if (st)
        return fail(sim, st, "create");
    if ((st = sph_set_threads(sim, threads)))
        return fail(sim, st, "--threads");
    int rock, specimen, plate, piston;
    if ((st = sph_add_material_K_mu(sim, 12.2e9, 2.67e9, 2300.0, &rock)))
        return fail(sim, st, "material");
    const double base[3] = {0.0, 0.0, 0.0};
    if ((st = sph_add_cylinder(sim, "specimen", rock, base, 0.5 * D, L, dx, &specimen)))
        return fail(sim, st, "--dx");
    /* layers = 0: the least number of layers that is 2h thick */
    if ((st = sph_add_plate(sim, "plate", -1, specimen, 0, &plate)) ||
        (st = sph_add_piston(sim, "piston", -1, specimen, 0, speed, &piston)))
        return fail(sim, st, "platens");
    if (alpha > 0.0) {
        char params[64];
        snprintf(params, sizeof params, "alpha=%.17g beta=0", alpha);
        if ((st = sph_effect(sim, "artificial_viscosity", params)))
            return fail(sim, st, "--alpha");
    }
    const char *names[4] = {"A", "B", "C", "D"};
    const double points[4][3] = {{0.0, 0.5 * L, 0.0},
                                 {0.25 * D, 0.75 * L, 0.0},
                                 {0.25 * D, 0.5 * L, 0.0},
                                 {0.0, 0.75 * L, 0.0}};
    for (int k = 0; k < 4; ++k)
        if ((st = sph_add_probe(sim, names[k], points[k], NULL)))
            return fail(sim, st, "probe");

    sph_body_info info;
    sph_body_info_get(sim, specimen, &info);
    const double dt = sph_dt(sim), t_end = until_ms * 1e-3;
    const long steps = (long)(t_end / dt + 0.999999);
    printf("uniaxial cylinder: D = 54 mm, L = 135 mm, dx = %g mm, h = %g mm\n", dx_mm,
           sph_smoothing_length(sim) * 1e3);
    printf("specimen particles: %zu (with plate and piston: %zu), %.1f MB\n", info.count,
           sph_particle_count(sim), sph_memory_bytes(sim) / 1e6);
    printf("time step: %.3f us, %ld steps to %g ms\n", dt * 1e6, steps, until_ms);

    const long probe_every = steps / 500 > 0 ? steps / 500 : 1;
    const long snap_every = snapshots > 0 ? (steps / snapshots > 0 ? steps / snapshots : 1) : 0;
    if ((st = sph_output_open(sim, out, snap_every, probe_every)) && st != SPH_ERR_UNSUPPORTED)
        return fail(sim, st, "--out");
    const int have_output = st == SPH_OK;
    FILE *f = fopen(csv, "w");
    if (!f) {
        fprintf(stderr, "uniaxial_cylinder: cannot write '%s'\n", csv);
        sph_destroy(sim);
        return 1;
    }
    fprintf(f, "time_s");
    for (int k = 0; k < 4; ++k)
        fprintf(f, ",vm_%s_Pa,syy_%s_Pa", names[k], names[k]);
    fprintf(f, "\n");
    const double t0 = wall_seconds();
    long done = 0;
    double v[SPH_PROBE_VALUES(3)];
    for (;;) {
        fprintf(f, "%.9e", sph_time(sim));
        for (int k = 0; k < 4; ++k) {
            sph_probe_sample(sim, k, v);
            fprintf(f, ",%.9e,%.9e", v[0], v[3]); /* von Mises, sigma_yy */
        }
        fprintf(f, "\n");
        if (done >= steps)
            break;
        const long chunk = steps - done < probe_every ? steps - done : probe_every;
        const double t_next = done + chunk >= steps ? t_end : (double)(done + chunk) * dt;
        if ((st = sph_run_until(sim, t_next))) {
            fclose(f);
            return fail(sim, st, "run");
        }
        done += chunk;
        if (!quiet && done % (probe_every * 50) == 0)
            fprintf(stderr, "t = %.4f ms, step %ld, wall %.1f s\n", sph_time(sim) * 1e3,
                    sph_step_count(sim), wall_seconds() - t0);
    }
    const double wall = wall_seconds() - t0;
    fclose(f);
    if (have_output) {
        sph_output_snapshot(sim);
        sph_output_close(sim);
    }
    sph_probe_sample(sim, 0, v);
    printf("t = %g ms: centre (A) von Mises %.4g Pa, sigma_yy %.4g Pa\n", sph_time(sim) * 1e3, v[0],
           v[3]);
    printf("wall time %.2f s, %.3g particle-steps/s\n", wall,
           (double)sph_particle_count(sim) * (double)steps / wall);
    printf("wrote %s%s%s\n", have_output ? out : "", have_output ? " and " : "", csv);
    sph_destroy(sim);
    return 0;
}
