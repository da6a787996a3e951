/* The table of effects: names, parameters, switches, and the per-particle
 * terms that do not fit a one-line inline function. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim.h"

/* ------------------------------------------------------ per-particle terms */

static void principal_2d(double sxx, double syy, double sxy, double *c, double *s, double *s1,
                         double *s2)
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
                const double t =
                    (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
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

void artificial_stress_tensor(int dim, const double *S, double P, double rho, double epsilon,
                              double *R)
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
    double A[3][3] = {{S[0] - P, S[3], S[4]}, {S[3], S[1] - P, S[5]}, {S[4], S[5], S[2] - P}};
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
        inv[0][0] = d / det;
        inv[1][1] = a / det;
        inv[0][1] = inv[1][0] = -b / det;
    } else {
        const double a = M[0], e = M[1], i9 = M[2], b = M[3], c = M[4], f = M[5];
        /* [[a b c][b e f][c f i]] */
        const double A0 = e * i9 - f * f, B0 = c * f - b * i9, C0 = b * f - c * e;
        const double det = a * A0 + b * B0 + c * C0;
        if (!(fabs(det) > 1e-12 * fabs(a * e * i9)))
            return 0;
        inv[0][0] = A0 / det;
        inv[0][1] = B0 / det;
        inv[0][2] = C0 / det;
        inv[1][1] = (a * i9 - c * c) / det;
        inv[1][2] = (b * c - a * f) / det;
        inv[2][2] = (a * e - b * b) / det;
        inv[1][0] = inv[0][1];
        inv[2][0] = inv[0][2];
        inv[2][1] = inv[1][2];
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

/* ------------------------------------------------------------ the registry */

/* One parameter of an effect: its key, what it means, its default (NAN:
 * must be given), its allowed range and where its value lives. */
typedef struct parameter_def {
    const char *key;
    const char *unit; /* "" when dimensionless */
    const char *description;
    double fallback; /* the default; NAN when it must be given */
    double min, max; /* allowed range (+-HUGE_VAL: unbounded) */
    int min_inclusive, max_inclusive;
    size_t offset; /* of the double in struct effects */
} parameter_def;

#define FX(field)    offsetof(effects, field)
#define ANY          -HUGE_VAL, HUGE_VAL, 0, 0 /* any finite value */
#define NON_NEGATIVE 0.0, HUGE_VAL, 1, 0       /* [0, inf) */
#define POSITIVE     0.0, HUGE_VAL, 0, 0       /* (0, inf) */
#define FRACTION     0.0, 1.0, 0, 1            /* (0, 1] */

static const parameter_def viscosity_parameters[] = {
    {"alpha", "", "linear (bulk) coefficient", 1.0, NON_NEGATIVE, FX(artificial_viscosity_alpha)},
    {"beta", "", "quadratic (von Neumann-Richtmyer) coefficient", 0.0, NON_NEGATIVE,
     FX(artificial_viscosity_beta)},
};
static const parameter_def artificial_stress_parameters[] = {
    {"epsilon", "", "strength of the repulsion", 0.3, FRACTION, FX(artificial_stress_epsilon)},
    {"n", "", "exponent of the pair factor (W_ab / W(dx))^n", 4.0, POSITIVE,
     FX(artificial_stress_n)},
};
static const parameter_def gravity_parameters[] = {
    {"gx", "m/s^2", "acceleration along x", 0.0, ANY, FX(g) + 0 * sizeof(double)},
    {"gy", "m/s^2", "acceleration along y", -9.81, ANY, FX(g) + 1 * sizeof(double)},
    {"gz", "m/s^2", "acceleration along z (0 in 2D)", 0.0, ANY, FX(g) + 2 * sizeof(double)},
};
static const parameter_def damping_parameters[] = {
    {"rate", "1/s", "damping rate", NAN, POSITIVE, FX(damping_rate)},
};
static const parameter_def xsph_parameters[] = {
    {"epsilon", "", "fraction of the neighbours' mean velocity difference", 0.5, FRACTION,
     FX(xsph_epsilon)},
};

static const parameter_def damage_parameters[] = {
    {"seed", "", "seed of the flaw draw (an integer below 2^53)", 1.0, NON_NEGATIVE,
     FX(damage_seed)},
    {"flaws", "", "expected flaws per particle: the draw keeps those with k V eps^m <= flaws", 10.0,
     POSITIVE, FX(damage_flaws)},
    {"member", "",
     "ensemble member: its flaws are drawn from hash(seed, member); 0 is the seed's own draw "
     "(an integer below 2^53)",
     0.0, NON_NEGATIVE, FX(damage_member)},
};

static const parameter_def drucker_prager_parameters[] = {
    {"cohesion", "Pa", "Mohr-Coulomb cohesion c", NAN, NON_NEGATIVE, FX(drucker_prager_cohesion)},
    {"friction_angle", "deg", "Mohr-Coulomb friction angle phi, in [0, 90)", 30.0, 0.0, 90.0, 1, 0,
     FX(drucker_prager_friction_angle)},
};

/* Rules beyond the ranges (values in the order of the parameters). */
static sph_status gravity_rule(sph_sim *sim, const double *g)
{
    if (sim->dim == 2 && g[2] != 0.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "gravity: gz=%g in a 2D simulation", g[2]);
    return SPH_OK;
}

static sph_status damage_rule(sph_sim *sim, const double *values)
{
    if (values[0] != floor(values[0]) || values[0] >= 9007199254740992.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "damage: seed=%.17g must be an integer below 2^53",
                        values[0]);
    if (values[2] != floor(values[2]) || values[2] >= 9007199254740992.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "damage: member=%.17g must be an integer below 2^53",
                        values[2]);
    if (values[1] > 1e6)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "damage: flaws=%g per particle is more than the 1e6 the draw allows",
                        values[1]);
    return SPH_OK;
}

#define PARAMETERS(array) array, (int)(sizeof array / sizeof array[0])
#define NO_PARAMETERS     NULL, 0

/* The effects: one row each, the only place an effect is named.
 *   X(name (also its switch in struct effects), parameters, extra rule or NULL,
 *     one-line description with its reference)
 * The names list, describe text (HDF5 attribute), parsing, range checks
 * and the public sph_effect_info_get()/sph_effect_parameter_get() all come
 * from it. */
#define SPH_EFFECTS(X)                                                                         \
    X(artificial_viscosity, PARAMETERS(viscosity_parameters), NULL,                            \
      "Monaghan (1992) artificial viscosity: a pressure Pi_ab between approaching "            \
      "pairs; damps the high-frequency modes Improved Euler amplifies")                        \
    X(artificial_stress, PARAMETERS(artificial_stress_parameters), NULL,                       \
      "Gray, Monaghan & Swift (2001) artificial stress: a repulsion between particles "        \
      "in tension, against the tensile instability")                                           \
    X(gravity, PARAMETERS(gravity_parameters), gravity_rule, "uniform body force: dv/dt += g") \
    X(damping, PARAMETERS(damping_parameters), NULL,                                           \
      "velocity damping dv/dt -= rate v, for reaching a static state fast")                    \
    X(xsph, PARAMETERS(xsph_parameters), NULL,                                                 \
      "Monaghan (1989) XSPH: particles move with a velocity smoothed over their "              \
      "neighbours")                                                                            \
    X(kernel_correction, NO_PARAMETERS, NULL,                                                  \
      "Bonet & Lok (1999) kernel-gradient correction of the velocity gradient: exact "         \
      "for linear fields, also at free surfaces")                                              \
    X(damage, PARAMETERS(damage_parameters), damage_rule,                                      \
      "Benz & Asphaug (1994, 1995) brittle damage: Weibull flaws (material keys weibull_k, "   \
      "weibull_m) activated by tensile strain grow D, which removes tension and shear")        \
    X(drucker_prager, PARAMETERS(drucker_prager_parameters), NULL,                             \
      "Drucker & Prager (1952) pressure-dependent strength: the deviator is returned onto "    \
      "sqrt(J2) <= A + B P (Mohr-Coulomb's compression meridian) after each step")

typedef struct effect_def {
    const char *name;
    size_t switch_offset; /* of the int switch in struct effects */
    const parameter_def *parameters;
    int n_parameters;
    sph_status (*rule)(sph_sim *sim, const double *values);
    const char *description;
} effect_def;

#define EFFECT_ROW(name, parameters, rule, text) {#name, FX(name), parameters, rule, text},
static const effect_def registry[] = {SPH_EFFECTS(EFFECT_ROW)};
#undef EFFECT_ROW
#define N_EFFECTS      ((int)(sizeof registry / sizeof registry[0]))
#define MAX_PARAMETERS EFFECTS_MAX_PARAMETERS

#define EFFECT_WORD(name, parameters, rule, text) " " #name
const char *sph_effect_names(void) { return SPH_EFFECTS(EFFECT_WORD) + 1; }
#undef EFFECT_WORD

int sph_effect_count(void) { return N_EFFECTS; }

sph_status sph_effect_info_get(int effect, sph_effect_info *info)
{
    if (effect < 0 || effect >= N_EFFECTS || !info)
        return SPH_ERR_ARGUMENT;
    const effect_def *e = &registry[effect];
    info->name = e->name;
    info->description = e->description;
    info->parameter_count = e->n_parameters;
    return SPH_OK;
}

sph_status sph_effect_parameter_get(int effect, int parameter, sph_effect_parameter *info)
{
    if (effect < 0 || effect >= N_EFFECTS || !info || parameter < 0 ||
        parameter >= registry[effect].n_parameters)
        return SPH_ERR_ARGUMENT;
    const parameter_def *p = &registry[effect].parameters[parameter];
    info->key = p->key;
    info->unit = p->unit;
    info->description = p->description;
    info->default_value = p->fallback;
    info->required = isnan(p->fallback);
    info->min = p->min;
    info->max = p->max;
    info->min_inclusive = p->min_inclusive;
    info->max_inclusive = p->max_inclusive;
    return SPH_OK;
}

static double *value_at(effects *fx, size_t offset) { return (double *)((char *)fx + offset); }
static int *switch_at(effects *fx, size_t offset) { return (int *)((char *)fx + offset); }

/* Parse "key=value key=value" (also separated by commas) into values[],
 * which hold the defaults on entry. */
static sph_status parse_parameters(sph_sim *sim, const effect_def *e, const char *text,
                                   double *values, int *given)
{
    for (const char *p = text ? text : ""; *p;) {
        while (*p == ' ' || *p == '\t' || *p == ',')
            ++p;
        if (!*p)
            break;
        const char *eq = strchr(p, '=');
        const char *end = p + strcspn(p, " \t,");
        if (!eq || eq > end)
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "effect '%s': parameter '%.*s%s' is not of the form key=value", e->name,
                            end - p > SPH_CLIP ? SPH_CLIP : (int)(end - p), p,
                            end - p > SPH_CLIP ? "..." : "");
        const size_t klen = (size_t)(eq - p);
        int found = -1;
        for (int i = 0; i < e->n_parameters; ++i)
            if (strlen(e->parameters[i].key) == klen && strncmp(e->parameters[i].key, p, klen) == 0)
                found = i;
        if (found < 0) {
            char known[256] = "";
            for (int i = 0; i < e->n_parameters; ++i) {
                strncat(known, e->parameters[i].key, sizeof known - strlen(known) - 3);
                if (i + 1 < e->n_parameters)
                    strncat(known, ", ", sizeof known - strlen(known) - 1);
            }
            /* a long key is cut (its list of the known ones is the help) */
            const int shown = klen > SPH_CLIP ? SPH_CLIP : (int)klen;
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "effect '%s': unknown parameter '%.*s%s' (known: %s)", e->name, shown,
                            p, (int)klen > shown ? "..." : "", e->n_parameters ? known : "none");
        }
        const char *key = e->parameters[found].key;
        char number[64], *stop;
        const size_t vlen = (size_t)(end - eq - 1);
        if (vlen == 0 || vlen >= sizeof number)
            return sph_fail(sim, SPH_ERR_ARGUMENT, "effect '%s': parameter '%s' has no valid value",
                            e->name, key);
        memcpy(number, eq + 1, vlen);
        number[vlen] = '\0';
        const double value = strtod(number, &stop);
        if (*stop != '\0' || !isfinite(value))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "effect '%s': parameter %s='%s' is not a finite number", e->name, key,
                            number);
        if (given[found])
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "effect '%s': parameter '%s' is given twice (%s=%g, then %s=%s)",
                            e->name, key, key, values[found], key, number);
        values[found] = value;
        given[found] = 1;
        p = end;
    }
    return SPH_OK;
}

/* The parameter's range as text: ">= 0", "> 0", "in (0, 1]". */
static void range_text(const parameter_def *p, char *buf, size_t size)
{
    if (p->max == HUGE_VAL)
        snprintf(buf, size, "%s %g", p->min_inclusive ? ">=" : ">", p->min);
    else if (p->min == -HUGE_VAL)
        snprintf(buf, size, "%s %g", p->max_inclusive ? "<=" : "<", p->max);
    else
        snprintf(buf, size, "in %c%g, %g%c", p->min_inclusive ? '[' : '(', p->min, p->max,
                 p->max_inclusive ? ']' : ')');
}

static sph_status check_range(sph_sim *sim, const effect_def *e, const parameter_def *p,
                              double value, int given)
{
    char range[64];
    range_text(p, range, sizeof range);
    const char *unit = p->unit[0] ? p->unit : NULL;
    if (!given && isnan(value))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: %s=<value> must be given, %s%s%s%s", e->name,
                        p->key, range, unit ? " [" : "", unit ? unit : "", unit ? "]" : "");
    const int below = p->min_inclusive ? value < p->min : value <= p->min;
    const int above = p->max_inclusive ? value > p->max : value >= p->max;
    if (below || above)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: %s=%g must be %s%s%s%s", e->name, p->key, value,
                        range, unit ? " [" : "", unit ? unit : "", unit ? "]" : "");
    return SPH_OK;
}

static const effect_def *find_effect(const char *name)
{
    if (!name)
        return NULL;
    for (int i = 0; i < N_EFFECTS; ++i)
        if (strcmp(registry[i].name, name) == 0)
            return &registry[i];
    return NULL;
}

static sph_status unknown_effect(sph_sim *sim, const char *name)
{
    char shown[SPH_CLIP_SIZE];
    return sph_fail(sim, SPH_ERR_ARGUMENT, "unknown effect '%s' (known: %s)",
                    name ? sph_clip(shown, name) : "(null)", sph_effect_names());
}

sph_status effects_set(sph_sim *sim, const char *name, const char *parameters)
{
    const effect_def *e = find_effect(name);
    if (!e)
        return unknown_effect(sim, name);
    double values[MAX_PARAMETERS];
    int given[MAX_PARAMETERS] = {0};
    for (int i = 0; i < e->n_parameters; ++i)
        values[i] = e->parameters[i].fallback;
    sph_status st = parse_parameters(sim, e, parameters, values, given);
    for (int i = 0; i < e->n_parameters && !st; ++i)
        st = check_range(sim, e, &e->parameters[i], values[i], given[i]);
    if (!st && e->rule)
        st = e->rule(sim, values);
    if (st)
        return st;
    for (int i = 0; i < e->n_parameters; ++i)
        *value_at(&sim->fx, e->parameters[i].offset) = values[i];
    *switch_at(&sim->fx, e->switch_offset) = 1;
    return SPH_OK;
}

sph_status effects_off(sph_sim *sim, const char *name)
{
    const effect_def *e = find_effect(name);
    if (!e)
        return unknown_effect(sim, name);
    *switch_at(&sim->fx, e->switch_offset) = 0;
    return SPH_OK;
}

int effects_is_on(const effects *fx, const char *name)
{
    const effect_def *e = find_effect(name);
    if (!e)
        return -1;
    return *(const int *)((const char *)fx + e->switch_offset) != 0;
}

int effects_values(const effects *fx, int effect, double *values)
{
    const effect_def *e = &registry[effect];
    for (int k = 0; k < e->n_parameters; ++k)
        values[k] = *(const double *)((const char *)fx + e->parameters[k].offset);
    return *(const int *)((const char *)fx + e->switch_offset) != 0;
}

void effects_describe(const effects *fx, char *buf, size_t size)
{
    buf[0] = '\0';
    size_t used = 0;
    for (int i = 0; i < N_EFFECTS && used < size; ++i) {
        const effect_def *e = &registry[i];
        if (!effects_is_on(fx, e->name))
            continue;
        used += (size_t)snprintf(buf + used, size - used, "%s", e->name);
        for (int k = 0; k < e->n_parameters && used < size; ++k)
            used += (size_t)snprintf(buf + used, size - used, " %s=%.17g", e->parameters[k].key,
                                     *(const double *)((const char *)fx + e->parameters[k].offset));
        if (used < size)
            used += (size_t)snprintf(buf + used, size - used, "; ");
    }
}
