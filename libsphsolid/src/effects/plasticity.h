/*
 * Pressure-dependent strength: the `drucker_prager` effect's terms.  The
 * stage that applies them after each step is in plasticity.c.
 *
 * Yield surface (Drucker & Prager 1952), P the pressure (compression
 * positive) and J2 = S:S/2 the second invariant of the deviator:
 *
 *     sqrt(J2) <= A + B P
 *
 * fitted to the Mohr-Coulomb surface of cohesion c and friction angle phi
 * on its compression meridian (the cone through the outer corners of the
 * Mohr-Coulomb pyramid, triaxial compression sigma_1 > sigma_2 = sigma_3):
 *
 *     A = 6 c cos(phi) / (sqrt(3) (3 - sin(phi)))
 *     B = 6 sin(phi)  / (sqrt(3) (3 - sin(phi)))
 *
 * (the usual sqrt(J2) + alpha I1 = k with I1 = -3P: B = 3 alpha, A = k).
 * On that meridian the cone is Mohr-Coulomb's, so the uniaxial compressive
 * strength is 2 c cos(phi) / (1 - sin(phi)) and under a confining
 * pressure p the axial strength rises as sigma_1 = UCS + p (1 + sin(phi)) /
 * (1 - sin(phi)).
 *
 * Return (perfectly plastic, no dilatancy): a deviator outside the cone is
 * scaled back onto it at the same pressure (radial return); where A + B P
 * <= 0 (tension past the apex) the deviator is zeroed and the pressure
 * keeps its equation-of-state value.  With damage on, the limit acts on
 * the damaged stress: (1 - D) sqrt(J2(S)) <= A + B P_d, P_d = P for P >= 0
 * and (1 - D) P in tension (damage.h).
 */
#ifndef SPHSOLID_PLASTICITY_H
#define SPHSOLID_PLASTICITY_H

#include <math.h>

/* A [Pa] and B [-] of the compression-meridian fit (angle in degrees). */
static inline void drucker_prager_constants(double cohesion, double friction_deg, double *A,
                                            double *B)
{
    const double phi = friction_deg * (3.14159265358979323846 / 180.0);
    const double s = sin(phi), d = sqrt(3.0) * (3.0 - s);
    *A = 6.0 * cohesion * cos(phi) / d;
    *B = 6.0 * s / d;
}

/* The return of one particle's deviator S (ncomp components: xx yy zz xy
 * [xz yz]) at pressure P (of the equation of state, compression positive)
 * and damage D (0 without the damage effect).  Returns the factor S was
 * scaled by (1: inside the cone, unchanged). */
static inline double drucker_prager_return(int ncomp, double A, double B, double P, double D,
                                           double *S)
{
    if (D >= 1.0)
        return 1.0; /* the damaged deviator is zero already */
    const double keep = 1.0 - D, Pd = P < 0.0 ? keep * P : P;
    double SS = S[0] * S[0] + S[1] * S[1] + S[2] * S[2] + 2.0 * S[3] * S[3];
    if (ncomp == 6)
        SS += 2.0 * (S[4] * S[4] + S[5] * S[5]);
    const double limit = A + B * Pd, now = keep * sqrt(0.5 * SS);
    if (now <= limit)
        return 1.0;
    const double scale = limit > 0.0 ? limit / now : 0.0;
    for (int c = 0; c < ncomp; ++c)
        S[c] *= scale;
    return scale;
}

#endif
