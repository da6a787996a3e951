/*
 * Effects a scene switches on: their parameters and their terms.
 * Pair terms are called only from rate-loop variants compiled with the
 * effect on; per-particle terms run in passes that exist only when on.
 * The table of names and parameter parsing is in effects.c.
 */
#ifndef SPHSOLID_EFFECTS_H
#define SPHSOLID_EFFECTS_H

#include <math.h>

#include "physics.h"

typedef struct effects {
    /* artificial_viscosity: Monaghan (1992) */
    int viscosity;
    double alpha, beta;
    /* artificial_stress: Gray, Monaghan & Swift (2001) */
    int artificial_stress;
    double stress_epsilon, stress_exponent;
    /* gravity */
    int gravity;
    double g[3];
    /* damping: dv/dt -= rate v (quasi-static loading) */
    int damping;
    double damping_rate;
    /* xsph: Monaghan (1989) */
    int xsph;
    double xsph_epsilon;
    /* kernel_correction: Randles & Libersky (1996) / Bonet & Lok (1999)
     * gradient correction of the velocity gradient */
    int kernel_correction;
    /* damage: Benz & Asphaug (1994, 1995), damage.h */
    int damage;
    double damage_seed, damage_flaws;
} effects;

/* Monaghan (1992) eqs (4.1)-(4.2): the artificial viscosity
 *   Pi_ab = (-alpha c_ab mu_ab + beta mu_ab^2) / rho_ab,  v_ab.r_ab < 0
 *   mu_ab = h v_ab.r_ab / (r_ab^2 + 0.01 h^2)
 * It acts as an extra pressure: T_ab -= Pi_ab I in the momentum sum. */
static inline double viscosity_pair(double alpha, double beta, double h, double v_dot_r, double r2,
                                    double c_mean, double rho_mean)
{
    /* one division: with d = r^2 + 0.01 h^2, mu = h v.r / d and
     * Pi = mu (-alpha c + beta mu) / rho = h v.r (-alpha c d + beta h v.r) / (d^2 rho);
     * computed for every pair and selected, so the pair loop vectorises */
    const double d = r2 + 0.01 * h * h;
    const double hvr = h * v_dot_r;
    const double Pi = hvr * (beta * hvr - alpha * c_mean * d) / (d * d * rho_mean);
    return v_dot_r < 0.0 ? Pi : 0.0;
}

/* Gray et al. (2001) eq. (22): the pair factor f_ab^n, f_ab = W_ab/W(dx). */
static inline double artificial_stress_factor(double W_ab, double inv_W_dx, double exponent)
{
    return pow(W_ab * inv_W_dx, exponent);
}

/* The same for the usual exponent n = 4, without pow (vectorises). */
static inline double artificial_stress_factor_4(double W_ab, double inv_W_dx)
{
    const double f = W_ab * inv_W_dx, f2 = f * f;
    return f2 * f2;
}

/* Gray et al. (2001) eqs (24)-(26): per-particle artificial stress R_a.
 * In the principal frame of the in-plane stress, R'_ii = -epsilon
 * sigma'_ii / rho^2 where sigma'_ii > 0 (tension), else 0; rotated back.
 * R is in-plane compact storage. */
void artificial_stress_tensor(int dim, const double *S, double P, double rho, double epsilon,
                              double *R);

/* Monaghan (1989): XSPH velocity correction contribution of b,
 * epsilon (m_b / rho_ab) (v_b - v_a) W_ab. */
static inline void xsph_pair(int dim, double epsilon, double m_b, double rho_mean,
                             const double *v_ab, double W_ab, double *dx_dt)
{
    const double s = epsilon * m_b / rho_mean * W_ab;
    for (int i = 0; i < dim; ++i)
        dx_dt[i] -= s * v_ab[i];
}

/* Kernel-gradient correction matrix, Bonet & Lok (1999): the term of b in
 * M_a = sum_b V_b (r_b - r_a) (x) grad_a W_ab, a symmetric tensor since
 * grad_a W_ab is parallel to r_ab; written to term[] in the compact order
 * of pair_tensor_index (xx yy xy, or xx yy zz xy xz yz).  Straight-line
 * code, so that the pair loop around it vectorises. */
static inline void correction_matrix_pair(int dim, double volume_b, const double *r_ab,
                                          const double *grad_W, double *term)
{
    const double s = -volume_b;
    term[0] = s * r_ab[0] * grad_W[0];
    term[1] = s * r_ab[1] * grad_W[1];
    if (dim == 2) {
        term[2] = s * r_ab[0] * grad_W[1];
    } else {
        term[2] = s * r_ab[2] * grad_W[2];
        term[3] = s * r_ab[0] * grad_W[1];
        term[4] = s * r_ab[0] * grad_W[2];
        term[5] = s * r_ab[1] * grad_W[2];
    }
}

/* Replace L by L M^-1 (M in-plane compact).  Returns 0 if M is singular
 * (an isolated particle), leaving L unchanged. */
int correct_velocity_gradient(int dim, const double *M, double L[3][3]);

#endif
