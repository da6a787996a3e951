/* Shared helpers of the C tests. */
#ifndef SPHSOLID_TEST_HELPERS_H
#define SPHSOLID_TEST_HELPERS_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#include "sphsolid.h"

/* |actual - expected| <= tolerance, with a message naming the quantity. */
#define assert_close(actual, expected, tolerance, what)                                          \
    do {                                                                                         \
        const double a_ = (actual), e_ = (expected), t_ = (tolerance);                           \
        if (!(fabs(a_ - e_) <= t_)) {                                                            \
            print_error("%s: got %.12g, expected %.12g (tolerance %.3g, off by %.3g)\n", (what), \
                        a_, e_, t_, fabs(a_ - e_));                                              \
            fail();                                                                              \
        }                                                                                        \
    } while (0)

/* A call that must succeed; on failure print the library's message. */
#define check(sim, call)                                                                       \
    do {                                                                                       \
        sph_status st_ = (call);                                                               \
        if (st_ != SPH_OK) {                                                                   \
            print_error("%s failed: %s (%s)\n", #call, sph_errmsg(sim), sph_status_name(st_)); \
            fail();                                                                            \
        }                                                                                      \
    } while (0)

/* The paper's material. */
#define PAPER_K    12.2e9
#define PAPER_MU   2.67e9
#define PAPER_RHO0 2300.0

static inline sph_sim *new_sim(int dim)
{
    sph_sim *sim = NULL;
    assert_int_equal(sph_create(dim, &sim), SPH_OK);
    assert_non_null(sim);
    return sim;
}

/* A 2D handle for particles held by the caller (the low-level calls on
 * external arrays): the paper material as `*material`, spacing 1 mm. */
static inline sph_sim *external_particles_2d(int *material)
{
    sph_sim *sim = new_sim(2);
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, material));
    check(sim, sph_set_spacing(sim, 1e-3));
    return sim;
}

/* A free block of nx x ny (x nz in 3D: nz > 0) particles of spacing dx
 * centred on the origin, paper material. */
static inline sph_sim *free_block(int nx, int ny, int nz, double dx)
{
    sph_sim *sim = new_sim(nz > 0 ? 3 : 2);
    int mat, body;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {-0.5 * nx * dx, -0.5 * ny * dx, nz > 0 ? -0.5 * nz * dx : 0.0},
                 hi[3] = {0.5 * nx * dx, 0.5 * ny * dx, nz > 0 ? 0.5 * nz * dx : 0.0};
    check(sim, sph_add_block(sim, "block", mat, lo, hi, dx, &body));
    return sim;
}

static inline sph_sim *free_block_2d(int nx, int ny, double dx)
{
    return free_block(nx, ny, 0, dx);
}

static inline double *field_ptr(sph_sim *sim, sph_field_id f)
{
    double *p = NULL;
    check(sim, sph_field(sim, f, &p, NULL, NULL));
    return p;
}

/* Distance of a particle from the block's edge, in units of dx. */
static inline int interior(const double *x, double half_w, double half_h, double margin)
{
    return fabs(x[0]) < half_w - margin && fabs(x[1]) < half_h - margin;
}

#endif
