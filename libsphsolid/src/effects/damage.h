/*
 * Brittle damage (Grady & Kipp 1980; Benz & Asphaug 1994, 1995): the
 * per-particle terms of the `damage` effect.  The stage that applies them
 * and the storage are in damage.c.
 *
 * Flaws.  The activation strains of a particle of volume V are the arrival
 * points of a unit-rate Poisson process in u = k V eps^m (k = weibull_k
 * [m^-3], m = weibull_m), so that the expected number of flaws active at a
 * strain eps is k V eps^m (Weibull's law as
 * Benz & Asphaug 1995 use it).
 * The gaps are exponential draws of a counter-based hash of (seed, ensemble
 * member, particle id, flaw index): any flaw of any particle is computed
 * again from those numbers, so no random state is stored and the draw does not depend
 * on threads, ranks or restarts.  A particle holds the flaws with
 * u <= `flaws` (the effect's parameter, the expected count), and at least
 * one.
 *
 * Growth.  Benz & Asphaug (1994, after Grady & Kipp 1980): dD^(1/3)/dt = c_g / R_s with the
 * crack speed c_g = 0.4 c_l (c_l the longitudinal wave speed) and R_s the
 * radius the crack runs across; here R_s = k_R h with k_R = 2, the kernel's
 * support in units of h (Spheral's DamageModel divides by the kernel
 * extent the same way).  D^(1/3) is capped by (n_active / n_total)^(1/3)
 * (Benz & Asphaug 1995): a particle with few of its flaws active
 * cannot fail completely.
 *
 * Damaged stress (Benz & Asphaug 1995): the pressure keeps
 * compression, loses tension, P <- (1 - D) P for P < 0, and the deviator
 * is scaled by (1 - D); a particle with D = 1 carries compression only.
 */
#ifndef SPHSOLID_DAMAGE_H
#define SPHSOLID_DAMAGE_H

#include <math.h>
#include <stdint.h>

/* The crack length in units of h (k_R) and the crack speed over c_l. */
#define DAMAGE_CRACK_RADIUS 2.0
#define DAMAGE_CRACK_SPEED  0.4

/* splitmix64's finaliser (Steele, Lea & Flood 2014): a bijection of 64-bit
 * words whose outputs pass BigCrush for consecutive inputs. */
static inline uint64_t damage_mix(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* The key of the flaw stream of ensemble member `member` drawn with `seed`:
 * hash(seed, member), counter-based like the draws, so member i of an
 * ensemble is the same run whichever process or job draws it.  Member 0 is
 * the seed's own stream (the draw of a single run). */
static inline uint64_t damage_stream(uint64_t seed, uint64_t member)
{
    const uint64_t key = damage_mix(seed);
    return member == 0 ? key : damage_mix(key ^ damage_mix(member));
}

/* A uniform number in (0, 1) from (stream key, particle id, flaw index). */
static inline double damage_uniform(uint64_t stream, uint64_t id, uint64_t flaw)
{
    const uint64_t z = damage_mix(damage_mix(stream ^ id) ^ flaw);
    return ((double)(z >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

/* The gap to the next flaw in u = k V eps^m: an exponential draw. */
static inline double damage_gap(uint64_t stream, uint64_t id, uint64_t flaw)
{
    return -log(damage_uniform(stream, id, flaw));
}

/* Flaws with u <= u_max among the first `total` of a particle (counted in
 * order; u_max < the first gives 0). */
static inline int damage_flaws_below(uint64_t stream, uint64_t id, int total, double u_max)
{
    double u = 0.0;
    int n = 0;
    while (n < total) {
        u += damage_gap(stream, id, (uint64_t)n);
        if (u > u_max)
            break;
        ++n;
    }
    return n;
}

/* The damaged stress: P <- (1 - D) P for P < 0, S <- (1 - D) S (ncomp
 * components into Sd).  Returns Sd. */
static inline const double *damaged_stress(int ncomp, double D, const double *S, double *P,
                                           double *Sd)
{
    const double keep = 1.0 - D;
    for (int c = 0; c < ncomp; ++c)
        Sd[c] = keep * S[c];
    if (*P < 0.0)
        *P *= keep;
    return Sd;
}

/* The largest principal strain of the elastic state (stress S - P I of the
 * undamaged material, that is the damaged stress divided by 1 - D): Hooke's
 * law inverted, eps = S / (2 mu) - P / (3 K) I.  In 2D the out-of-plane
 * strain (S_zz / (2 mu) - P / (3 K), zero in plane strain up to rounding)
 * is a candidate as well. */
static inline double largest_principal_strain(int dim, const double *S, double P, double K,
                                              double mu)
{
    const double vol = -P / (3.0 * K), shear = mu > 0.0 ? 0.5 / mu : 0.0;
    if (dim == 2) {
        const double a = S[0] * shear, b = S[1] * shear, c = S[3] * shear;
        const double mean = 0.5 * (a + b), radius = sqrt(0.25 * (a - b) * (a - b) + c * c);
        const double in_plane = mean + radius, zz = S[2] * shear;
        return vol + (in_plane > zz ? in_plane : zz);
    }
    /* the largest eigenvalue of the symmetric deviator (trigonometric
     * solution of the characteristic cubic, Smith 1961) */
    const double a = S[0] * shear, b = S[1] * shear, c = S[2] * shear;
    const double d = S[3] * shear, e = S[4] * shear, f = S[5] * shear;
    const double p1 = d * d + e * e + f * f;
    const double q = (a + b + c) / 3.0;
    const double p2 = (a - q) * (a - q) + (b - q) * (b - q) + (c - q) * (c - q) + 2.0 * p1;
    if (!(p2 > 0.0))
        return vol + q;
    const double p = sqrt(p2 / 6.0);
    const double A = (a - q) / p, B = (b - q) / p, C = (c - q) / p, Dd = d / p, E = e / p,
                 F = f / p;
    const double r = 0.5 * (A * (B * C - F * F) - Dd * (Dd * C - F * E) + E * (Dd * F - B * E));
    const double phi = r <= -1.0 ? 1.0471975511965976 /* pi/3 */ : r >= 1.0 ? 0.0 : acos(r) / 3.0;
    return vol + q + 2.0 * p * cos(phi);
}

#endif
