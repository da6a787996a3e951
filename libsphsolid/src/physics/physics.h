/*
 * The elastic-solid SPH model: one small function per term.
 *
 * Storage of symmetric tensors:
 *   - deviatoric stress S (full 3x3, plane strain keeps S_zz):
 *       2D (xx, yy, zz, xy), 3D (xx, yy, zz, xy, xz, yz)
 *   - in-plane pair tensors T (sigma/rho^2, artificial stress R):
 *       2D (xx, yy, xy),     3D (xx, yy, zz, xy, xz, yz)
 * Vectors hold `dim` entries.  The velocity gradient is a full 3x3 array
 * L[i][j] = dv^i/dx^j whose out-of-plane entries stay zero in 2D.
 */
#ifndef SPHSOLID_PHYSICS_H
#define SPHSOLID_PHYSICS_H

#include <math.h>

/* Number of in-plane symmetric components. */
static inline int pair_tensor_components(int dim) { return dim == 2 ? 3 : 6; }

/* Index of T^ij in the in-plane compact storage. */
static inline int pair_tensor_index(int dim, int i, int j)
{
    if (i == j)
        return i;
    if (dim == 2)
        return 2;
    return i + j + 2; /* (0,1)->3, (0,2)->4, (1,2)->5 */
}

/* Index of S^ij in the deviatoric stress storage (i, j < 3). */
static inline int stress_index(int dim, int i, int j)
{
    if (i == j)
        return i;
    if (dim == 2)
        return 3; /* only xy is stored off the diagonal in 2D */
    return i + j + 2;
}

/* Equation of state, paper eq. (9): P = c0^2 (rho - rho0). */
static inline double eos_pressure(double c0_squared, double rho, double rho0)
{
    return c0_squared * (rho - rho0);
}

/* In-plane sigma/rho^2 with sigma = -P I + S (paper eq. 5), the per-particle
 * factor of the symmetric momentum equation. */
static inline void stress_over_rho2(int dim, const double *S, double P, double rho, double *T)
{
    const double inv_rho2 = 1.0 / (rho * rho);
    for (int i = 0; i < dim; ++i)
        T[i] = (S[i] - P) * inv_rho2;
    if (dim == 2) {
        T[2] = S[3] * inv_rho2;
    } else {
        T[3] = S[3] * inv_rho2;
        T[4] = S[4] * inv_rho2;
        T[5] = S[5] * inv_rho2;
    }
}

/*
 * Pair terms over a block of pairs (a_k, b_k), k < PAIR_BLOCK: the inputs
 * in structure-of-arrays form (one short array per quantity, so that the
 * loops over k vectorise), filled by the pair pass (rates.c); a block may
 * hold the pairs of several rows a.  Each term writes, for every pair, the
 * contribution to particle a (ta, partner weight m_b or V_b) and to
 * particle b (tb, weight m_a or V_a) as rows ta[c][k] of its components c.
 * Swapping a and b maps r_ab, v_ab and grad_a W_ab to their negatives: a
 * term even in them gives b the same unweighted value, an odd one its
 * negative; written out so, the one-sided form (the pair seen from b) gives
 * b's contribution to the bit.  The loops run over all PAIR_BLOCK lanes (a
 * fixed trip count: whole vectors, no remainder); lanes from n on hold
 * finite filler whose terms nobody reads.
 */
#define PAIR_BLOCK 32

typedef struct pair_block {
    int n;                                   /* pairs in the block */
    double r[3][PAIR_BLOCK];                 /* r_ab = x_a - x_b */
    double v[3][PAIR_BLOCK];                 /* v_ab = v_a - v_b */
    double r2[PAIR_BLOCK];                   /* |r_ab|^2 */
    double gW[3][PAIR_BLOCK];                /* grad_a W_ab */
    double W[PAIR_BLOCK];                    /* W_ab (with artificial stress or XSPH) */
    double m_a[PAIR_BLOCK], V_a[PAIR_BLOCK]; /* mass and volume m/rho of a */
    double m_b[PAIR_BLOCK], V_b[PAIR_BLOCK];
    double rho_mean[PAIR_BLOCK], c_mean[PAIR_BLOCK]; /* (rho_a + rho_b)/2, same for c0 */
    /* momentum: T_ab = sigma_a/rho_a^2 + sigma_b/rho_b^2 (+ effect terms),
     * in-plane compact storage; R_a + R_b of the artificial stress */
    double T[6][PAIR_BLOCK];
    double R[6][PAIR_BLOCK];
} pair_block;

typedef double pair_rows[PAIR_BLOCK];

/* Continuity, paper eq. (3): drho_a/dt += m_b v_ab . grad_a W_ab (even:
 * b gets m_a times the same).  1 component. */
static inline void continuity_term(int dim, const pair_block *restrict p, pair_rows *restrict ta,
                                   pair_rows *restrict tb)
{
    for (int k = 0; k < PAIR_BLOCK; ++k) {
        double s = 0.0;
        for (int i = 0; i < dim; ++i)
            s += p->v[i][k] * p->gW[i][k];
        ta[0][k] = p->m_b[k] * s;
        tb[0][k] = p->m_a[k] * s;
    }
}

/* Velocity gradient: (dv^i/dx^j)_a += V_b (v_b^i - v_a^i) dW_ab/dx_a^j
 * = -V_b v_ab^i (grad_a W_ab)^j (even).  dim x dim components, row-major. */
static inline void velocity_gradient_term(int dim, const pair_block *restrict p,
                                          pair_rows *restrict ta, pair_rows *restrict tb)
{
    for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
            for (int k = 0; k < PAIR_BLOCK; ++k) {
                ta[i * dim + j][k] = -(p->V_b[k] * p->v[i][k] * p->gW[j][k]);
                tb[i * dim + j][k] = -(p->V_a[k] * p->v[i][k] * p->gW[j][k]);
            }
}

/* Symmetric momentum equation, Gray, Monaghan & Swift (2001) eq. (29):
 * dv_a/dt += m_b T_ab . grad_a W_ab (odd: b gets -m_a times the same).
 * T_ab is built from a per-particle stress factor (sigma/rho^2, made in
 * the pair pass's first pass) and the effect terms.  dim components. */
static inline void momentum_term(int dim, const pair_block *restrict p, pair_rows *restrict ta,
                                 pair_rows *restrict tb)
{
    for (int i = 0; i < dim; ++i)
        for (int k = 0; k < PAIR_BLOCK; ++k) {
            double s = 0.0;
            for (int j = 0; j < dim; ++j)
                s += p->T[pair_tensor_index(dim, i, j)][k] * p->gW[j][k];
            ta[i][k] = p->m_b[k] * s;
            tb[i][k] = -(p->m_a[k] * s);
        }
}

/* Deviatoric stress rate, paper eqs. (6)-(8) (Jaumann rate, Hooke):
 *   dS/dt = 2 mu (eps_dot - tr(eps_dot)/3 I) + S Omega^T + Omega S
 * with eps_dot = (L + L^T)/2 (eq. 7) and Omega = (L - L^T)/2 (eq. 8).
 * In 2D (plane strain) eps_dot_zz = 0 and dS_zz/dt = -2 mu tr/3. */
static inline void jaumann_stress_rate(int dim, double mu, const double L[3][3], const double *S,
                                       double *dS_dt)
{
    double eps[3][3], omega[3][3], s[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            eps[i][j] = 0.5 * (L[i][j] + L[j][i]);
            omega[i][j] = 0.5 * (L[i][j] - L[j][i]);
            s[i][j] = (dim == 3 || (i < 2 && j < 2) || i == j) ? S[stress_index(dim, i, j)] : 0.0;
        }
    const double trace = eps[0][0] + eps[1][1] + eps[2][2];
    const int ncomp = dim == 2 ? 4 : 6;
    for (int c = 0; c < ncomp; ++c) {
        int i, j;
        if (c < 3) {
            i = j = c;
        } else if (dim == 2) {
            i = 0;
            j = 1;
        } else {
            i = c == 5 ? 1 : 0;
            j = c == 3 ? 1 : 2;
        }
        double rotation = 0.0;
        for (int k = 0; k < 3; ++k)
            rotation += s[i][k] * omega[j][k] + omega[i][k] * s[k][j];
        dS_dt[c] = 2.0 * mu * (eps[i][j] - (i == j ? trace / 3.0 : 0.0)) + rotation;
    }
}

/* S:S over the full 3x3 tensor. */
static inline double stress_double_dot(int dim, const double *S)
{
    double s = S[0] * S[0] + S[1] * S[1] + S[2] * S[2] + 2.0 * S[3] * S[3];
    if (dim == 3)
        s += 2.0 * (S[4] * S[4] + S[5] * S[5]);
    return s;
}

/* von Mises stress of the full 3D Cauchy stress: sqrt(3/2 S:S). */
static inline double von_mises_stress(int dim, const double *S)
{
    return sqrt(1.5 * stress_double_dot(dim, S));
}

/* Elastic energy per unit mass: volumetric part integrating P/rho^2 along
 * the equation of state, c0^2 (ln(rho/rho0) + rho0/rho - 1), plus the
 * shear part S:S / (4 mu rho). */
static inline double elastic_energy_per_mass(int dim, double c0_squared, double rho0, double mu,
                                             double rho, const double *S)
{
    double u = c0_squared * (log(rho / rho0) + rho0 / rho - 1.0);
    if (mu > 0.0)
        u += stress_double_dot(dim, S) / (4.0 * mu * rho);
    return u;
}

#endif
