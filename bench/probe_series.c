/*
 * Probe series for comparing two builds of the library bit for bit.
 *
 *   probe_series [--threads N] [--steps N]
 *
 * Runs the paper scene (2D, dx = 4 mm, piston) for every integrator,
 * every kernel and a set of effect combinations, and the 3D cylinder
 * (dx = 9 mm) for every integrator, and prints after every few steps the
 * probe values and a checksum of the state as hexadecimal floats (%a), so
 * that two outputs are equal exactly when the runs agree to the bit.
 * scripts/compare_probes.sh builds this program against another commit and
 * compares the two outputs.  Uses the public API only.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sphsolid.h"

static int fail(sph_sim *sim, const char *what)
{
    fprintf(stderr, "probe_series: %s: %s\n", what, sim ? sph_errmsg(sim) : "");
    sph_destroy(sim);
    return 1;
}

/* Sum and sum of |.| weighted by position in the array: a checksum that
 * changes when any value changes. */
static void print_state(sph_sim *sim)
{
    const sph_field_id fields[4] = {SPH_FIELD_POSITION, SPH_FIELD_VELOCITY, SPH_FIELD_DENSITY,
                                    SPH_FIELD_DEVIATORIC_STRESS};
    for (int f = 0; f < 4; ++f) {
        double *d = NULL;
        size_t rows = 0, cols = 0;
        if (sph_field(sim, fields[f], &d, &rows, &cols))
            continue;
        double s = 0.0, w = 0.0;
        for (size_t k = 0; k < rows * cols; ++k) {
            s += d[k];
            w += d[k] * (double)(k % 1021 + 1);
        }
        printf(" %a %a", s, w);
    }
}

static void print_probes(sph_sim *sim)
{
    for (int p = 0; p < sph_probe_count(sim); ++p) {
        double v[SPH_PROBE_VALUES(3)];
        if (sph_probe_sample(sim, p, v))
            continue;
        for (int k = 0; k < SPH_PROBE_VALUES(sph_dimension(sim)); ++k)
            printf(" %a", v[k]);
    }
}

static int series(sph_sim *sim, const char *label, long steps)
{
    for (long s = 0; s < steps; s += 10) {
        if (sph_run(sim, 10)) { /* a failed run (watchdog) is part of the series */
            printf("%s step %ld: stopped: %s\n", label, s + 10, sph_errmsg(sim));
            break;
        }
        printf("%s step %ld:", label, s + 10);
        print_probes(sim);
        print_state(sim);
        printf("\n");
    }
    sph_destroy(sim);
    return 0;
}

static int paper(const char *integrator, const char *kernel, const char *effects[][2], int threads,
                 long steps)
{
    sph_sim *sim = NULL;
    sph_paper_scene scene;
    if (sph_create(2, &sim) || sph_set_threads(sim, threads) ||
        sph_set_kernel_by_name(sim, kernel) || sph_build_paper_scene(sim, 4e-3, 0.3, 0, &scene) ||
        sph_set_integrator(sim, integrator))
        return fail(sim, "paper scene");
    char label[256];
    snprintf(label, sizeof label, "paper %s %s", integrator, kernel);
    for (int k = 0; effects[k][0]; ++k) {
        if (sph_effect(sim, effects[k][0], effects[k][1]))
            return fail(sim, effects[k][0]);
        strncat(label, " ", sizeof label - strlen(label) - 1);
        strncat(label, effects[k][0], sizeof label - strlen(label) - 1);
    }
    if (sph_set_dt(sim, 0.5 * sph_stable_dt(sim), 0))
        return fail(sim, "dt");
    return series(sim, label, steps);
}

static int cylinder(const char *integrator, int threads, long steps)
{
    sph_sim *sim = NULL;
    int rock, specimen, plate, piston;
    const double D = 0.054, L = 0.135, base[3] = {0.0, 0.0, 0.0};
    if (sph_create(3, &sim) || sph_set_threads(sim, threads) ||
        sph_add_material_K_mu(sim, 12.2e9, 2.67e9, 2300.0, &rock) ||
        sph_add_cylinder(sim, "specimen", rock, base, 0.5 * D, L, 9e-3, &specimen) ||
        sph_add_plate(sim, "plate", -1, specimen, 0, &plate) ||
        sph_add_piston(sim, "piston", -1, specimen, 0, 0.3, &piston) ||
        sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0") ||
        sph_set_integrator(sim, integrator))
        return fail(sim, "cylinder");
    const double points[2][3] = {{0.0, 0.5 * L, 0.0}, {0.25 * D, 0.75 * L, 0.0}};
    for (int k = 0; k < 2; ++k)
        if (sph_add_probe(sim, k ? "B" : "A", points[k], NULL))
            return fail(sim, "probe");
    char label[128];
    snprintf(label, sizeof label, "cylinder %s", integrator);
    return series(sim, label, steps);
}

int main(int argc, char **argv)
{
    int threads = 1;
    long steps = 40;
    for (int k = 1; k + 1 < argc; k += 2) {
        if (!strcmp(argv[k], "--threads"))
            threads = atoi(argv[k + 1]);
        else if (!strcmp(argv[k], "--steps"))
            steps = atol(argv[k + 1]);
    }
    /* effect combinations: none, the dissipative and tensile ones, and the
     * continuity-side ones */
    const char *none[][2] = {{NULL, NULL}};
    const char *momentum[][2] = {{"artificial_viscosity", "alpha=1 beta=2"},
                                 {"artificial_stress", "epsilon=0.3 n=4"},
                                 {"gravity", ""},
                                 {NULL, NULL}};
    const char *stress_n[][2] = {{"artificial_stress", "epsilon=0.2 n=2"}, {NULL, NULL}};
    const char *continuity[][2] = {{"kernel_correction", ""},
                                   {"xsph", "epsilon=0.5"},
                                   {"damping", "rate=100"},
                                   {"artificial_viscosity", "alpha=1 beta=0"},
                                   {NULL, NULL}};
    const char *(*combos[])[2] = {none, momentum, stress_n, continuity};
    char names[256];
    snprintf(names, sizeof names, "%s", sph_integrator_names());
    char knames[256];
    snprintf(knames, sizeof knames, "%s", sph_kernel_names());
    for (char *in = strtok(names, " "); in; in = strtok(NULL, " ")) {
        char integrator[64];
        snprintf(integrator, sizeof integrator, "%s", in);
        char *save = NULL, kn[256];
        snprintf(kn, sizeof kn, "%s", knames);
        for (char *kernel = strtok_r(kn, " ", &save); kernel; kernel = strtok_r(NULL, " ", &save))
            for (size_t c = 0; c < sizeof combos / sizeof combos[0]; ++c)
                if (paper(integrator, kernel, combos[c], threads, steps))
                    return 1;
    }
    snprintf(names, sizeof names, "%s", sph_integrator_names());
    for (char *in = strtok(names, " "); in; in = strtok(NULL, " ")) {
        char integrator[64];
        snprintf(integrator, sizeof integrator, "%s", in);
        if (cylinder(integrator, threads, steps))
            return 1;
    }
    return 0;
}
