/*
 * Smoothing kernels, support 2h.  Each returns W(q) and the gradient factor
 * F(q) = (dW/dr) / r, both before the normalisation sigma_d / h^d (for W)
 * and sigma_d / h^(d+2) (for F), so that
 *
 *   W_ab      = sigma_d / h^d       w(q)
 *   grad_a W  = sigma_d / h^(d+2)   f(q) r_ab,     q = |r_ab| / h.
 *
 * Writing the gradient as f(q) r_ab avoids a division by r in the inner
 * shell of the cubic spline and everywhere for Wendland C2.
 */
#ifndef SPHSOLID_KERNEL_H
#define SPHSOLID_KERNEL_H

#include <math.h>

#include "sphsolid.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Cubic B-spline, Monaghan (1992) eq. (2.6):
 *   w(q) = 1 - 3/2 q^2 + 3/4 q^3   for 0 <= q < 1
 *        = 1/4 (2 - q)^3           for 1 <= q < 2
 * sigma_d = 2/3, 10/(7 pi), 1/pi in 1, 2, 3 dimensions. */
static inline double kernel_cubic_sigma(int dim)
{
    return dim == 1 ? 2.0 / 3.0 : dim == 2 ? 10.0 / (7.0 * M_PI) : 1.0 / M_PI;
}

/* The kernels are written without branches (both pieces computed, one
 * selected), so that the pair loop vectorises. */
static inline double kernel_cubic_w(int dim, double q)
{
    (void)dim;
    const double t = 2.0 - q > 0.0 ? 2.0 - q : 0.0;
    const double inner = 1.0 - 1.5 * q * q + 0.75 * q * q * q;
    const double outer = 0.25 * t * t * t;
    return q < 1.0 ? inner : outer;
}

/* f(q) = w'(q) / q. */
static inline double kernel_cubic_f(int dim, double q)
{
    (void)dim;
    const double t = 2.0 - q > 0.0 ? 2.0 - q : 0.0;
    const double inner = -3.0 + 2.25 * q;
    const double outer = -0.75 * t * t / (q > 1.0 ? q : 1.0);
    return q < 1.0 ? inner : outer;
}

/* Wendland C2 with support 2h (Wendland 1995; Dehnen & Aly 2012):
 *   w(q) = (1 - q/2)^4 (2q + 1)  for 0 <= q < 2
 * sigma_d = 7/(4 pi) in 2D, 21/(16 pi) in 3D (1D: 3/4 for the C2 form
 * (1 - q/2)^3 (3q/2 + 1) is a different function; only 2D/3D here). */
static inline double kernel_wendland_sigma(int dim)
{
    return dim == 2 ? 7.0 / (4.0 * M_PI) : 21.0 / (16.0 * M_PI);
}

static inline double kernel_wendland_w(int dim, double q)
{
    (void)dim;
    const double t = 1.0 - 0.5 * q > 0.0 ? 1.0 - 0.5 * q : 0.0;
    const double t2 = t * t;
    return t2 * t2 * (2.0 * q + 1.0);
}

/* w'(q) = -5 q (1 - q/2)^3, so f(q) = -5 (1 - q/2)^3. */
static inline double kernel_wendland_f(int dim, double q)
{
    (void)dim;
    const double t = 1.0 - 0.5 * q > 0.0 ? 1.0 - 0.5 * q : 0.0;
    return -5.0 * t * t * t;
}

/* Fourth-order (dispersion-reduced) cubic spline: the extrapolation of
 * Monaghan (1985), a Richardson combination of two cubic splines whose
 * second moments cancel,
 *   W4(r; h) = a W(r; h/s) - b W(r; h),  a = s^2/(s^2 - 1), b = 1/(s^2 - 1),
 * with s = 3/2 (a = 9/5, b = 4/5).  It keeps the cubic's normalisation
 * (a - b = 1) and support 2h, has zero second moment, so the SPH gradient
 * of a smooth field is exact to fourth order in the continuum instead of
 * second, and has a negative outer lobe.  In units of q = r/h, in d
 * dimensions:
 *   w4(q) = a s^d w(s q) - b w(q),  f4(q) = a s^(d+2) f(s q) - b f(q).
 * On the square lattice at h/dx = 1.65 (inner h 1.1 dx) the gradient
 * moment is 1.0008 and plane waves at 10 particles per wavelength run
 * 0.4 % slow, against 8.5 % for the cubic spline at h/dx = 1.2.  Its time
 * step is that of a cubic spline at the inner length h/s. */
#define KERNEL_O4_S 1.5
#define KERNEL_O4_A (KERNEL_O4_S * KERNEL_O4_S / (KERNEL_O4_S * KERNEL_O4_S - 1.0))
#define KERNEL_O4_B (1.0 / (KERNEL_O4_S * KERNEL_O4_S - 1.0))

static inline double kernel_cubic_o4_scale(int dim)
{
    const double s = KERNEL_O4_S;
    return dim == 1 ? s : dim == 2 ? s * s : s * s * s;
}

static inline double kernel_cubic_o4_w(int dim, double q)
{
    return KERNEL_O4_A * kernel_cubic_o4_scale(dim) * kernel_cubic_w(dim, KERNEL_O4_S * q) -
           KERNEL_O4_B * kernel_cubic_w(dim, q);
}

static inline double kernel_cubic_o4_f(int dim, double q)
{
    const double s2 = KERNEL_O4_S * KERNEL_O4_S;
    return KERNEL_O4_A * kernel_cubic_o4_scale(dim) * s2 * kernel_cubic_f(dim, KERNEL_O4_S * q) -
           KERNEL_O4_B * kernel_cubic_f(dim, q);
}

static inline double kernel_cubic_o4_sigma(int dim) { return kernel_cubic_sigma(dim); }

/* The kernel registry: one row per kernel, the only place a kernel is
 * named.  Columns: the sph_kernel value, its name, the prefix of its
 * functions (PREFIX_w(dim, q), PREFIX_f(dim, q), PREFIX_sigma(dim) above),
 * its support in units of h, the length its time step scales with in
 * units of h (1, or the inner length of a combined kernel), and kappa: an
 * integrator whose stable step was measured without artificial viscosity
 * (the leapfrog) is stable with it up to that step / (1 + kappa alpha).
 * kappa is measured (docs/stability.md, "Artificial viscosity and the
 * leapfrog's step"): 0 where viscosity leaves the step as it is; the
 * outer ring of cubic_o4, where its gradient points outward, makes the
 * viscosity of approaching pairs there push them together.  The dispatch
 * below, the names the library reports and the rate-loop variants are
 * generated from it. */
#define SPH_KERNELS(X)                                                     \
    X(SPH_KERNEL_CUBIC_SPLINE, cubic_spline, kernel_cubic, 2.0, 1.0, 0.0)  \
    X(SPH_KERNEL_WENDLAND_C2, wendland_c2, kernel_wendland, 2.0, 1.0, 0.0) \
    X(SPH_KERNEL_CUBIC_O4, cubic_o4, kernel_cubic_o4, 2.0, 1.0 / KERNEL_O4_S, 0.85)

/* Dispatch by kernel id over the registry; with a constant id the switch
 * folds away.  KERNEL_SWITCH(kernel, CASE) expands CASE(id, name, prefix,
 * support, step, viscous) for every row as the cases of one switch. */
#define KERNEL_SWITCH(kernel, CASE) \
    switch (kernel) {               \
        SPH_KERNELS(CASE)           \
    }                               \
    return 0.0
#define KERNEL_CASE_W(id, name, prefix, support, step, viscous) \
    case id: return prefix##_w(dim, q);
#define KERNEL_CASE_F(id, name, prefix, support, step, viscous) \
    case id: return prefix##_f(dim, q);
#define KERNEL_CASE_SIGMA(id, name, prefix, support, step, viscous) \
    case id: return prefix##_sigma(dim);
#define KERNEL_CASE_SUPPORT(id, name, prefix, support, step, viscous) \
    case id: return support;
#define KERNEL_CASE_STEP(id, name, prefix, support, step, viscous) \
    case id: return step;
#define KERNEL_CASE_VISCOUS(id, name, prefix, support, step, viscous) \
    case id: return viscous;

static inline double kernel_w(int kernel, int dim, double q)
{
    KERNEL_SWITCH(kernel, KERNEL_CASE_W);
}
static inline double kernel_f(int kernel, int dim, double q)
{
    KERNEL_SWITCH(kernel, KERNEL_CASE_F);
}
static inline double kernel_sigma(int kernel, int dim) { KERNEL_SWITCH(kernel, KERNEL_CASE_SIGMA); }
/* Support radius in units of h. */
static inline double kernel_support(int kernel) { KERNEL_SWITCH(kernel, KERNEL_CASE_SUPPORT); }
/* The length the time step limits scale with, in units of h. */
static inline double kernel_step_length(int kernel) { KERNEL_SWITCH(kernel, KERNEL_CASE_STEP); }
/* The names of the kernels that are non-negative over their support,
 * comma-separated in buf (of `size` bytes); returns buf. */
const char *kernel_names_non_negative(int dim, char *buf, size_t size);
/* kappa of the registry: a viscosity-limited stable step / (1 + kappa alpha). */
static inline double kernel_viscous_kappa(int kernel)
{
    KERNEL_SWITCH(kernel, KERNEL_CASE_VISCOUS);
}

#endif
