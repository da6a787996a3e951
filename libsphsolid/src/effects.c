/* The table of effects: names, parameters, switches, and the per-particle
 * terms that do not fit a one-line inline function. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim.h"

/* ------------------------------------------------------ per-particle terms */

static void principal_2d(double sxx, double syy, double sxy, double *c,
                         double *s, double *s1, double *s2)
{
    const double theta = 0.5 * atan2(2.0 * sxy, sxx - syy);
    *c = cos(theta);
    *s = sin(theta);
    const double cc = *c * *c, ss = *s * *s, cs = *c * *s;
    *s1 = cc * sxx + 2.0 * cs * sxy + ss * syy;
    *s2 = ss * sxx - 2.0 * cs * sxy + cc * syy;
}

/* Cyclic Jacobi eigen-decomposition of a symmetric 3x3 matrix: A = Q D Q^T,
 * eigenvectors in the columns of Q. */
static void jacobi_3x3(double A[3][3], double Q[3][3])
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            Q[i][j] = i == j;
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = A[0][1] * A[0][1] + A[0][2] * A[0][2] + A[1][2] * A[1][2];
        const double diag = A[0][0] * A[0][0] + A[1][1] * A[1][1] + A[2][2] * A[2][2];
        if (off <= 1e-30 * diag || off == 0.0)
            return;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (A[p][q] == 0.0)
                    continue;
                const double theta = (A[q][q] - A[p][p]) / (2.0 * A[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) /
                                 (fabs(theta) + sqrt(theta * theta + 1.0));
                const double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {
                    const double akp = A[k][p], akq = A[k][q];
                    A[k][p] = c * akp - s * akq;
                    A[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double apk = A[p][k], aqk = A[q][k];
                    A[p][k] = c * apk - s * aqk;
                    A[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double qkp = Q[k][p], qkq = Q[k][q];
                    Q[k][p] = c * qkp - s * qkq;
                    Q[k][q] = s * qkp + c * qkq;
                }
            }
    }
}

void artificial_stress_tensor(int dim, const double *S, double P, double rho,
                              double epsilon, double *R)
{
    const double scale = -epsilon / (rho * rho);
    if (dim == 2) {
        double c, s, s1, s2;
        principal_2d(S[0] - P, S[1] - P, S[3], &c, &s, &s1, &s2);
        const double r1 = s1 > 0.0 ? scale * s1 : 0.0;
        const double r2 = s2 > 0.0 ? scale * s2 : 0.0;
        R[0] = c * c * r1 + s * s * r2;
        R[1] = s * s * r1 + c * c * r2;
        R[2] = c * s * (r1 - r2);
        return;
    }
    double A[3][3] = {{S[0] - P, S[3], S[4]},
                      {S[3], S[1] - P, S[5]},
                      {S[4], S[5], S[2] - P}};
    double Q[3][3];
    jacobi_3x3(A, Q);
    double r[3];
    for (int k = 0; k < 3; ++k)
        r[k] = A[k][k] > 0.0 ? scale * A[k][k] : 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) {
            double sum = 0.0;
            for (int k = 0; k < 3; ++k)
                sum += Q[i][k] * r[k] * Q[j][k];
            R[pair_tensor_index(3, i, j)] = sum;
        }
}

int correct_velocity_gradient(int dim, const double *M, double L[3][3])
{
    double inv[3][3];
    if (dim == 2) {
        const double a = M[0], d = M[1], b = M[2];
        const double det = a * d - b * b;
        if (!(fabs(det) > 1e-12 * (a * a + d * d)))
            return 0;
        inv[0][0] = d / det; inv[1][1] = a / det;
        inv[0][1] = inv[1][0] = -b / det;
    } else {
        const double a = M[0], e = M[1], i9 = M[2], b = M[3], c = M[4], f = M[5];
        /* [[a b c][b e f][c f i]] */
        const double A0 = e * i9 - f * f, B0 = c * f - b * i9, C0 = b * f - c * e;
        const double det = a * A0 + b * B0 + c * C0;
        if (!(fabs(det) > 1e-12 * fabs(a * e * i9)))
            return 0;
        inv[0][0] = A0 / det; inv[0][1] = B0 / det; inv[0][2] = C0 / det;
        inv[1][1] = (a * i9 - c * c) / det;
        inv[1][2] = (b * c - a * f) / det;
        inv[2][2] = (a * e - b * b) / det;
        inv[1][0] = inv[0][1]; inv[2][0] = inv[0][2]; inv[2][1] = inv[1][2];
    }
    double out[3][3] = {{0}};
    for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
            double s = 0.0;
            for (int k = 0; k < dim; ++k)
                s += L[i][k] * inv[k][j];
            out[i][j] = s;
        }
    for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
            L[i][j] = out[i][j];
    return 1;
}

/* ------------------------------------------------------------ the table */

typedef struct parameter {
    const char *key;
    double value;
    int given;
} parameter;

/* Parse "key=value key=value" against the allowed keys. */
static sph_status parse_parameters(sph_sim *sim, const char *effect,
                                   const char *text, parameter *params,
                                   int nparams)
{
    if (!text)
        return SPH_OK;
    const char *p = text;
    while (*p) {
        while (*p == ' ' || *p == '\t' || *p == ',')
            ++p;
        if (!*p)
            break;
        const char *eq = strchr(p, '=');
        const char *end = p + strcspn(p, " \t,");
        if (!eq || eq > end)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "effect '%s': parameter '%.*s' is not of the form key=value",
                            effect, (int)(end - p), p);
        const size_t klen = (size_t)(eq - p);
        int found = -1;
        for (int i = 0; i < nparams; ++i)
            if (strlen(params[i].key) == klen && strncmp(params[i].key, p, klen) == 0)
                found = i;
        if (found < 0) {
            char known[256] = "";
            for (int i = 0; i < nparams; ++i) {
                strncat(known, params[i].key, sizeof known - strlen(known) - 2);
                if (i + 1 < nparams)
                    strncat(known, ", ", sizeof known - strlen(known) - 1);
            }
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "effect '%s': unknown parameter '%.*s' (known: %s)",
                            effect, (int)klen, p, nparams ? known : "none");
        }
        char *stop;
        char number[64];
        const size_t vlen = (size_t)(end - eq - 1);
        if (vlen == 0 || vlen >= sizeof number)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "effect '%s': parameter '%s' has no valid value",
                            effect, params[found].key);
        memcpy(number, eq + 1, vlen);
        number[vlen] = '\0';
        const double value = strtod(number, &stop);
        if (*stop != '\0' || !isfinite(value))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "effect '%s': parameter %s='%s' is not a finite number",
                            effect, params[found].key, number);
        params[found].value = value;
        params[found].given = 1;
        p = end;
    }
    return SPH_OK;
}

static sph_status set_viscosity(sph_sim *sim, const char *text)
{
    parameter p[] = {{"alpha", 1.0, 0}, {"beta", 0.0, 0}};
    sph_status st = parse_parameters(sim, "artificial_viscosity", text, p, 2);
    if (st)
        return st;
    if (p[0].value < 0.0 || p[1].value < 0.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "artificial_viscosity: alpha=%g and beta=%g must be >= 0",
                        p[0].value, p[1].value);
    sim->fx.viscosity = 1;
    sim->fx.alpha = p[0].value;
    sim->fx.beta = p[1].value;
    return SPH_OK;
}

static sph_status set_artificial_stress(sph_sim *sim, const char *text)
{
    parameter p[] = {{"epsilon", 0.3, 0}, {"n", 4.0, 0}};
    sph_status st = parse_parameters(sim, "artificial_stress", text, p, 2);
    if (st)
        return st;
    if (p[0].value <= 0.0 || p[0].value > 1.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "artificial_stress: epsilon=%g must be in (0, 1]", p[0].value);
    if (p[1].value <= 0.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "artificial_stress: n=%g must be > 0", p[1].value);
    sim->fx.artificial_stress = 1;
    sim->fx.stress_epsilon = p[0].value;
    sim->fx.stress_exponent = p[1].value;
    return SPH_OK;
}

static sph_status set_gravity(sph_sim *sim, const char *text)
{
    parameter p[] = {{"gx", 0.0, 0}, {"gy", -9.81, 0}, {"gz", 0.0, 0}};
    sph_status st = parse_parameters(sim, "gravity", text, p, 3);
    if (st)
        return st;
    if (sim->dim == 2 && p[2].value != 0.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "gravity: gz=%g in a 2D simulation", p[2].value);
    sim->fx.gravity = 1;
    for (int i = 0; i < 3; ++i)
        sim->fx.g[i] = p[i].value;
    return SPH_OK;
}

static sph_status set_damping(sph_sim *sim, const char *text)
{
    parameter p[] = {{"rate", 0.0, 0}};
    sph_status st = parse_parameters(sim, "damping", text, p, 1);
    if (st)
        return st;
    if (!p[0].given || !(p[0].value > 0.0))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "damping: rate=%g must be given and > 0 [1/s]", p[0].value);
    sim->fx.damping = 1;
    sim->fx.damping_rate = p[0].value;
    return SPH_OK;
}

static sph_status set_xsph(sph_sim *sim, const char *text)
{
    parameter p[] = {{"epsilon", 0.5, 0}};
    sph_status st = parse_parameters(sim, "xsph", text, p, 1);
    if (st)
        return st;
    if (p[0].value <= 0.0 || p[0].value > 1.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "xsph: epsilon=%g must be in (0, 1]", p[0].value);
    sim->fx.xsph = 1;
    sim->fx.xsph_epsilon = p[0].value;
    return SPH_OK;
}

static sph_status set_kernel_correction(sph_sim *sim, const char *text)
{
    sph_status st = parse_parameters(sim, "kernel_correction", text, NULL, 0);
    if (st)
        return st;
    sim->fx.kernel_correction = 1;
    return SPH_OK;
}

typedef struct effect_entry {
    const char *name;
    sph_status (*set)(sph_sim *, const char *);
    size_t switch_offset;   /* offset of the int switch in struct effects */
} effect_entry;

static const effect_entry effect_table[] = {
    {"artificial_viscosity", set_viscosity, offsetof(effects, viscosity)},
    {"artificial_stress", set_artificial_stress, offsetof(effects, artificial_stress)},
    {"gravity", set_gravity, offsetof(effects, gravity)},
    {"damping", set_damping, offsetof(effects, damping)},
    {"xsph", set_xsph, offsetof(effects, xsph)},
    {"kernel_correction", set_kernel_correction, offsetof(effects, kernel_correction)},
};
#define N_EFFECTS (sizeof effect_table / sizeof effect_table[0])

const char *sph_effect_names(void)
{
    return "artificial_viscosity artificial_stress gravity damping xsph kernel_correction";
}

static const effect_entry *find_effect(const char *name)
{
    if (!name)
        return NULL;
    for (size_t i = 0; i < N_EFFECTS; ++i)
        if (strcmp(effect_table[i].name, name) == 0)
            return &effect_table[i];
    return NULL;
}

sph_status effects_set(sph_sim *sim, const char *name, const char *parameters)
{
    const effect_entry *e = find_effect(name);
    if (!e)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "unknown effect '%s' (known: %s)",
                        name ? name : "(null)", sph_effect_names());
    effects saved = sim->fx;
    sph_status st = e->set(sim, parameters);
    if (st)
        sim->fx = saved;
    return st;
}

sph_status effects_off(sph_sim *sim, const char *name)
{
    const effect_entry *e = find_effect(name);
    if (!e)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "unknown effect '%s' (known: %s)",
                        name ? name : "(null)", sph_effect_names());
    *(int *)((char *)&sim->fx + e->switch_offset) = 0;
    return SPH_OK;
}

int effects_is_on(const effects *fx, const char *name)
{
    const effect_entry *e = find_effect(name);
    if (!e)
        return -1;
    return *(const int *)((const char *)fx + e->switch_offset) != 0;
}

void effects_describe(const effects *fx, char *buf, size_t size)
{
    buf[0] = '\0';
    size_t used = 0;
#define APPEND(...) do { if (used < size) used += (size_t)snprintf(buf + used, size - used, __VA_ARGS__); } while (0)
    if (fx->viscosity)
        APPEND("artificial_viscosity alpha=%.17g beta=%.17g; ", fx->alpha, fx->beta);
    if (fx->artificial_stress)
        APPEND("artificial_stress epsilon=%.17g n=%.17g; ", fx->stress_epsilon, fx->stress_exponent);
    if (fx->gravity)
        APPEND("gravity gx=%.17g gy=%.17g gz=%.17g; ", fx->g[0], fx->g[1], fx->g[2]);
    if (fx->damping)
        APPEND("damping rate=%.17g; ", fx->damping_rate);
    if (fx->xsph)
        APPEND("xsph epsilon=%.17g; ", fx->xsph_epsilon);
    if (fx->kernel_correction)
        APPEND("kernel_correction; ");
#undef APPEND
}
