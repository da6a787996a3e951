/*
 * Effects a scene switches on: their parameters and their terms.
 * A pair term is a function over a block of pairs (physics.h's pair_block)
 * called by the pair pass (rate_loop.h, pair_terms) when its switch is on; the
 * switches are tested once per block.  Per-particle terms run in the
 * passes before (the pair data) and after (the finish) the pair pass.  The
 * table of names and parameter parsing is in effects.c.
 */
#ifndef SPHSOLID_EFFECTS_H
#define SPHSOLID_EFFECTS_H

#include <math.h>

#include "physics/physics.h"

/* Each effect's switch is named as the effect in the registry (effects.c)
 * and each parameter <effect>_<key> (gravity's gx, gy, gz: the vector g). */
typedef struct effects {
    /* artificial_viscosity: Monaghan (1992) */
    int artificial_viscosity;
    double artificial_viscosity_alpha, artificial_viscosity_beta;
    /* artificial_stress: Gray, Monaghan & Swift (2001) */
    int artificial_stress;
    double artificial_stress_epsilon, artificial_stress_n;
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
    double damage_seed, damage_flaws, damage_member;
    /* drucker_prager: pressure-dependent strength, plasticity.h */
    int drucker_prager;
    double drucker_prager_cohesion, drucker_prager_friction_angle;
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

/* The artificial viscosity's term: T_ab -= Pi_ab I for every pair (even in
 * r_ab and v_ab, so symmetric in a and b). */
static inline void artificial_viscosity_term(int dim, double alpha, double beta, double h,
                                             pair_block *p)
{
    for (int k = 0; k < PAIR_BLOCK; ++k) {
        double v_dot_r = 0.0;
        for (int i = 0; i < dim; ++i)
            v_dot_r += p->v[i][k] * p->r[i][k];
        const double Pi =
            viscosity_pair(alpha, beta, h, v_dot_r, p->r2[k], p->c_mean[k], p->rho_mean[k]);
        for (int i = 0; i < dim; ++i)
            p->T[i][k] -= Pi;
    }
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

/* The artificial stress's term, Gray et al. (2001) eq. (23):
 * T_ab += f_ab^n (R_a + R_b) (symmetric in a and b). */
static inline void artificial_stress_term(int dim, double inv_W_dx, double n,
                                          pair_block *restrict p)
{
    const int nsym = pair_tensor_components(dim);
    if (n == 4.0)
        for (int k = 0; k < PAIR_BLOCK; ++k) {
            const double fn = artificial_stress_factor_4(p->W[k], inv_W_dx);
            for (int c = 0; c < nsym; ++c)
                p->T[c][k] += p->R[c][k] * fn;
        }
    else
        for (int k = 0; k < PAIR_BLOCK; ++k) {
            const double fn = artificial_stress_factor(p->W[k], inv_W_dx, n);
            for (int c = 0; c < nsym; ++c)
                p->T[c][k] += p->R[c][k] * fn;
        }
}

/* Gray et al. (2001) eqs (24)-(26): per-particle artificial stress R_a.
 * In the principal frame of the in-plane stress, R'_ii = -epsilon
 * sigma'_ii / rho^2 where sigma'_ii > 0 (tension), else 0; rotated back.
 * R is in-plane compact storage. */
void artificial_stress_tensor(int dim, const double *S, double P, double rho, double epsilon,
                              double *R);

/* Monaghan (1989) XSPH: dx_a/dt += epsilon (m_b / rho_ab) (v_b - v_a) W_ab
 * (odd: b gets -m_a times the same).  dim components. */
static inline void xsph_term(int dim, double epsilon, const pair_block *restrict p,
                             pair_rows *restrict ta, pair_rows *restrict tb)
{
    for (int k = 0; k < PAIR_BLOCK; ++k) {
        const double s = epsilon / p->rho_mean[k] * p->W[k];
        for (int i = 0; i < dim; ++i) {
            const double t = -(s * p->v[i][k]);
            ta[i][k] = p->m_b[k] * t;
            tb[i][k] = -(p->m_a[k] * t);
        }
    }
}

/* Kernel-gradient correction matrix, Bonet & Lok (1999): the term of b in
 * M_a = sum_b V_b (r_b - r_a) (x) grad_a W_ab, a symmetric tensor since
 * grad_a W_ab is parallel to r_ab (even: b gets V_a times the same); nsym
 * components in the compact order of pair_tensor_index (xx yy xy, or xx
 * yy zz xy xz yz). */
static inline void correction_moment_term(int dim, const pair_block *restrict p,
                                          pair_rows *restrict ta, pair_rows *restrict tb)
{
    const int nsym = pair_tensor_components(dim);
    for (int k = 0; k < PAIR_BLOCK; ++k) {
        double H[6];
        H[0] = -p->r[0][k] * p->gW[0][k];
        H[1] = -p->r[1][k] * p->gW[1][k];
        if (dim == 2) {
            H[2] = -p->r[0][k] * p->gW[1][k];
        } else {
            H[2] = -p->r[2][k] * p->gW[2][k];
            H[3] = -p->r[0][k] * p->gW[1][k];
            H[4] = -p->r[0][k] * p->gW[2][k];
            H[5] = -p->r[1][k] * p->gW[2][k];
        }
        for (int c = 0; c < nsym; ++c) {
            ta[c][k] = p->V_b[k] * H[c];
            tb[c][k] = p->V_a[k] * H[c];
        }
    }
}

/* Replace L by L M^-1 (M in-plane compact).  Returns 0 if M is singular
 * (an isolated particle), leaving L unchanged. */
int correct_velocity_gradient(int dim, const double *M, double L[3][3]);

#endif
