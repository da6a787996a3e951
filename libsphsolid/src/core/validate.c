/*
 * Checks made before work starts: the state a run begins from, and whether
 * the memory a number of particles needs is available.  Each failure names
 * the particle, quantity and value, or the bytes needed and available.
 */
#define _POSIX_C_SOURCE 200809L /* sysconf */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "core/sim.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Every particle's density and mass must be finite and positive before a
 * run: the rates divide by them, so a bad value set through sph_field()
 * would otherwise surface as a neighbour's runaway velocity.  (Non-finite
 * positions, velocities and stresses are caught where they first act, with
 * the step: the neighbour search and the watchdog.) */
sph_status coordinate_check(sph_sim *sim, const char *body_name, size_t particle, int axis,
                            double x, double spacing)
{
    if (fabs(x) <= SPH_COORDINATE_LIMIT * spacing)
        return SPH_OK;
    return sph_fail(sim, SPH_ERR_ARGUMENT,
                    "body '%s': particle %zu at %c=%g m lies %.3g spacings (dx=%g m) from the "
                    "origin; coordinates are limited to %g spacings (|%c| <= %g m), beyond which "
                    "a double rounds positions to more than %.2g dx: place the scene near the "
                    "origin",
                    body_name, particle, "xyz"[axis], x, fabs(x) / spacing, spacing,
                    SPH_COORDINATE_LIMIT, "xyz"[axis], SPH_COORDINATE_LIMIT * spacing,
                    SPH_COORDINATE_LIMIT * DBL_EPSILON);
}

sph_status state_check(sph_sim *sim)
{
    const int dim = sim->dim;
    for (size_t a = 0; a < sim->n; ++a) {
        const body *b = &sim->bodies[sim->body_of[a]];
        for (int i = 0; i < dim; ++i) {
            const double x = sim->x[a * dim + i];
            sph_status st;
            if (isfinite(x) &&
                (st = coordinate_check(sim, b->name, a - b->first, i, x, b->spacing)))
                return st;
        }
    }
    for (size_t a = 0; a < sim->n; ++a) {
        const char *what = NULL;
        double value = 0.0;
        if (!(sim->rho[a] > 0.0) || !isfinite(sim->rho[a]))
            what = "density", value = sim->rho[a];
        else if (!(sim->mass[a] > 0.0) || !isfinite(sim->mass[a]))
            what = "mass", value = sim->mass[a];
        if (what)
            return sph_fail(
                sim, SPH_ERR_ARGUMENT,
                "particle %zu of body '%s' has %s %g before the run (must be finite and > 0)", a,
                sim->bodies[sim->body_of[a]].name, what, value);
    }
    return SPH_OK;
}

/* Bytes one particle takes during a run: state, integrator copies, rates,
 * rate scratch and its share of the neighbour list (neighbours within
 * 2h + skin at the lattice spacing) and of the cell list built for it. */
static double bytes_per_particle(const sph_sim *sim)
{
    const double dim = sim->dim, nc = sim->ncomp, ns = sim->nsym;
    const double doubles = (2 * dim + 1 + nc + 1)  /* x, v, rho, S, mass */
                           + (2 * dim + 1 + nc)    /* saved state + xsph */
                           + dim                   /* x_saved */
                           + (2 * dim + 1 + nc)    /* rates */
                           + (2 * ns + 1)          /* pair data (+ artificial stress) */
                           + (dim == 3 ? 3 : 0);   /* pair sums of L (3D) */
    const double r = 2.0 * 1.125 * sim->h_over_dx; /* (2h + skin)/dx */
    const double neighbours = sim->dim == 2 ? M_PI * r * r : 4.0 / 3.0 * M_PI * r * r * r;
    return doubles * sizeof(double) + 2 * sizeof(int)        /* body, material */
           + 0.5 * neighbours * sizeof(int) + sizeof(size_t) /* half neighbour list */
           + 3 * sizeof(size_t) + sizeof(int);               /* cell list build */
}

/* Memory this process may still use: MemAvailable (Linux), else the free
 * physical pages, bounded by RLIMIT_AS and RLIMIT_DATA when set. */
static double available_bytes(const char **source)
{
    double bytes = -1.0;
    *source = "MemAvailable in /proc/meminfo";
    FILE *f = fopen("/proc/meminfo", "r");
    if (f) {
        char line[256];
        while (fgets(line, sizeof line, f)) {
            unsigned long long kb;
            if (sscanf(line, "MemAvailable: %llu kB", &kb) == 1) {
                bytes = (double)kb * 1024.0;
                break;
            }
        }
        fclose(f);
    }
#ifdef _SC_AVPHYS_PAGES
    if (bytes < 0.0) {
        const long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
        if (pages > 0 && size > 0) {
            bytes = (double)pages * (double)size;
            *source = "free physical memory";
        }
    }
#endif
    const int limits[2] = {RLIMIT_AS, RLIMIT_DATA};
    const char *names[2] = {"RLIMIT_AS", "RLIMIT_DATA"};
    for (int k = 0; k < 2; ++k) {
        struct rlimit r;
        if (getrlimit(limits[k], &r) == 0 && r.rlim_cur != RLIM_INFINITY &&
            (bytes < 0.0 || (double)r.rlim_cur < bytes)) {
            bytes = (double)r.rlim_cur;
            *source = names[k];
        }
    }
    return bytes;
}

static void human(double bytes, char *out, size_t size)
{
    const char *unit[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
    int k = 0;
    while (bytes >= 1000.0 && k < 6) {
        bytes /= 1000.0;
        ++k;
    }
    snprintf(out, size, "%.3g %s", bytes, unit[k]);
}

sph_status memory_check(sph_sim *sim, double particles, const char *what)
{
    const double per = bytes_per_particle(sim);
    const double needed = (particles + (double)sim->n) * per;
    const char *source = "";
    const double available = available_bytes(&source);
    const double limit = sim->allow_large ? available : SPH_LARGE_FRACTION * available;
    if (available < 0.0 || needed <= limit)
        return SPH_OK;
    char need[32], have[32];
    human(needed, need, sizeof need);
    human(available, have, sizeof have);
    if (needed <= available)
        return sph_fail(sim, SPH_ERR_MEMORY,
                        "%s: %.4g particles (%zu already in the scene) need about %s for a run "
                        "(%.0f bytes each), more than %g of the %s available (%s): a run this "
                        "large is refused unless allowed (sph_set_allow_large), or use a coarser "
                        "spacing",
                        what, particles, sim->n, need, per, SPH_LARGE_FRACTION, have, source);
    return sph_fail(
        sim, SPH_ERR_MEMORY,
        "%s: %.4g particles (%zu already in the scene) need about %s for a run (%.0f bytes each), "
        "but %s are available (%s): use a coarser spacing or a machine with more memory",
        what, particles, sim->n, need, per, have, source);
}

sph_status sph_set_allow_large(sph_sim *sim, int allow)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    sim->allow_large = allow != 0;
    return sph_ok(sim);
}

int sph_allow_large(const sph_sim *sim) { return sim ? sim->allow_large : 0; }

sph_status sph_memory_check(sph_sim *sim, double particles)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(particles >= 0.0) || !isfinite(particles))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "sph_memory_check: particles=%g must be finite and >= 0", particles);
    const sph_status st = memory_check(sim, particles, "sph_memory_check");
    return st ? st : sph_ok(sim);
}
