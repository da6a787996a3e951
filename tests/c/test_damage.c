/* The damage effect (Benz & Asphaug): the flaw draw, the growth law, the
 * strain rule of activation, determinism and the cost of leaving it off. */
#include "helpers.h"

#include "effects/damage.h"

/* A periodic block of n^dim particles of spacing dx (paper material),
 * which stays uniform under a uniform state. */
static sph_sim *periodic_block(int dim, int n, double dx, int *material)
{
    sph_sim *sim = new_sim(dim);
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, material));
    const double L = n * dx;
    const double lo[3] = {0, 0, 0}, hi[3] = {L, L, dim == 3 ? L : 0};
    const int periodic[3] = {1, 1, dim == 3};
    check(sim, sph_set_domain(sim, lo, hi, periodic));
    int body;
    check(sim, sph_add_block(sim, "block", *material, lo, hi, dx, &body));
    return sim;
}

/* Sets every particle to the stress sigma = S - P I (P from the equation
 * of state through rho), at rest. */
static void set_uniform_stress(sph_sim *sim, double P, const double *S)
{
    sph_material_info info;
    check(sim, sph_material_info_get(sim, 0, &info));
    size_t n = 0, nc = 0;
    double *rho, *dev;
    check(sim, sph_field(sim, SPH_FIELD_DENSITY, &rho, &n, NULL));
    check(sim, sph_field(sim, SPH_FIELD_DEVIATORIC_STRESS, &dev, NULL, &nc));
    for (size_t a = 0; a < n; ++a) {
        rho[a] = info.rho0 + P / (info.c0 * info.c0); /* P = c0^2 (rho - rho0) */
        for (size_t c = 0; c < nc; ++c)
            dev[a * nc + c] = S[c];
    }
}

static double *copy_field(sph_sim *sim, sph_field_id f, size_t n)
{
    double *out = malloc(n * sizeof *out);
    assert_non_null(out);
    check(sim, sph_field_copy(sim, f, out));
    return out;
}

/* The draw: the flaws active at a strain eps, summed over all particles,
 * number k V eps^m (V the total volume), a power law of slope m. */
static void flaw_counts_follow_k_V_eps_to_the_m(void **state)
{
    (void)state;
    const double dx = 1e-3, k = 1e12, m = 6.0;
    int mat;
    sph_sim *sim = periodic_block(2, 200, dx, &mat);
    check(sim, sph_material_set(sim, mat, "weibull_k", k));
    check(sim, sph_material_set(sim, mat, "weibull_m", m));
    check(sim, sph_effect(sim, "damage", "seed=7 flaws=100"));
    const double V = 200 * dx * 200 * dx; /* m / rho0 summed: the block's area */
    /* expected counts 1e3 .. 1e5 (per particle 0.025 .. 2.5, far below the
     * cut at 100 flaws) */
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const int points = 5;
    for (int i = 0; i < points; ++i) {
        const double expected = 1e3 * pow(10.0, 2.0 * i / (points - 1));
        const double eps = pow(expected / (k * V), 1.0 / m);
        double count;
        check(sim, sph_flaws_active_at(sim, eps, &count));
        /* Poisson: within 5 standard deviations */
        assert_close(count, expected, 5.0 * sqrt(expected), "flaws active at eps");
        const double x = log(eps), y = log(count);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    const double slope = (points * sxy - sx * sy) / (points * sxx - sx * sx);
    assert_close(slope, m, 0.02 * m, "log-log slope of the flaw count");
    /* each particle's count is Poisson(flaws) (at least 1): mean 100 */
    double *count = copy_field(sim, SPH_FIELD_FLAWS, 40000);
    double mean = 0;
    for (int a = 0; a < 40000; ++a)
        mean += count[a] / 40000.0;
    assert_close(mean, 100.0, 5.0 * sqrt(100.0 / 40000.0), "mean flaws per particle");
    free(count);
    sph_destroy(sim);
}

/* The weakest flaw is the first arrival of the Poisson process: the share
 * of particles whose weakest strain is below eps is 1 - exp(-k V eps^m). */
static void weakest_flaws_follow_the_first_arrival_law(void **state)
{
    (void)state;
    const double dx = 1e-3, k = 1e10, m = 9.0;
    int mat;
    sph_sim *sim = periodic_block(2, 200, dx, &mat);
    check(sim, sph_material_set(sim, mat, "weibull_k", k));
    check(sim, sph_material_set(sim, mat, "weibull_m", m));
    check(sim, sph_effect(sim, "damage", NULL));
    double *weakest = copy_field(sim, SPH_FIELD_FLAW_STRAIN, 40000);
    const double kV = k * dx * dx;
    for (int i = 1; i <= 3; ++i) {
        const double share = 0.25 * i, eps = pow(-log(1.0 - share) / kV, 1.0 / m);
        int below = 0;
        for (int a = 0; a < 40000; ++a)
            below += weakest[a] <= eps;
        /* binomial: 5 standard deviations */
        assert_close(below / 40000.0, share, 5.0 * sqrt(share * (1 - share) / 40000.0),
                     "share of weakest flaws below eps");
    }
    free(weakest);
    sph_destroy(sim);
}

/* Pearson's correlation of x and y over n values. */
static double correlation(const double *x, const double *y, size_t n)
{
    double mx = 0, my = 0;
    for (size_t a = 0; a < n; ++a) {
        mx += x[a] / (double)n;
        my += y[a] / (double)n;
    }
    double sxy = 0, sxx = 0, syy = 0;
    for (size_t a = 0; a < n; ++a) {
        sxy += (x[a] - mx) * (y[a] - my);
        sxx += (x[a] - mx) * (x[a] - mx);
        syy += (y[a] - my) * (y[a] - my);
    }
    return sxy / sqrt(sxx * syy);
}

static int compare_doubles(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* How many values of x also occur in y (n each). */
static int values_in_common(const double *x, const double *y, size_t n)
{
    double *sx = malloc(2 * n * sizeof *sx), *sy = sx + n;
    assert_non_null(sx);
    memcpy(sx, x, n * sizeof *sx);
    memcpy(sy, y, n * sizeof *sy);
    qsort(sx, n, sizeof *sx, compare_doubles);
    qsort(sy, n, sizeof *sy, compare_doubles);
    int common = 0;
    for (size_t i = 0, j = 0; i < n && j < n;) {
        if (sx[i] < sy[j])
            ++i;
        else if (sy[j] < sx[i])
            ++j;
        else {
            ++common;
            ++i;
            ++j;
        }
    }
    free(sx);
    return common;
}

/* The flaw field (weakest strain, or flaw count) of ensemble member
 * `member` drawn with seed 5; member < 0: the parameter left at its
 * default. */
static double *member_field(int member, sph_field_id f)
{
    int mat;
    sph_sim *sim = periodic_block(2, 200, 1e-3, &mat);
    check(sim, sph_material_set(sim, mat, "weibull_k", 1e10));
    check(sim, sph_material_set(sim, mat, "weibull_m", 9.0));
    char text[64];
    if (member >= 0)
        snprintf(text, sizeof text, "seed=5 member=%d", member);
    else
        snprintf(text, sizeof text, "seed=5");
    check(sim, sph_effect(sim, "damage", text));
    double *out = copy_field(sim, f, 40000);
    sph_destroy(sim);
    return out;
}

/* Ensemble members draw from hash(seed, member): consecutive members'
 * flaw fields are uncorrelated (|r| < 0.05; the sampling spread of r over
 * 40,000 independent pairs is 1/sqrt(40000) = 0.005), member 0 is the
 * seed's own draw (the default), and every member still follows the
 * first-arrival law (checked in weakest_flaws_follow_the_first_arrival_law
 * for member 0; here its median). */
static void ensemble_members_draw_independent_flaws(void **state)
{
    (void)state;
    const sph_field_id fields[2] = {SPH_FIELD_FLAW_STRAIN, SPH_FIELD_FLAWS};
    for (int f = 0; f < 2; ++f) {
        double *plain = member_field(-1, fields[f]);
        double *prev = member_field(0, fields[f]);
        assert_memory_equal(plain, prev, 40000 * sizeof(double));
        for (int member = 1; member <= 4; ++member) {
            double *next = member_field(member, fields[f]);
            const double r = correlation(prev, next, 40000);
            if (!(fabs(r) < 0.05))
                fail_msg("members %d and %d: flaw field correlation %g", member - 1, member, r);
            if (f == 0) /* continuous draws: no strain of one member recurs in the next
                           (a permutation of the same draws would correlate as little) */
                assert_int_equal(values_in_common(prev, next, 40000), 0);
            free(prev);
            prev = next;
        }
        free(plain);
        free(prev);
    }
    /* a member's weakest strains keep the law: half below the median
     * (-ln(1/2) / kV)^(1/m) */
    double *weakest = member_field(3, SPH_FIELD_FLAW_STRAIN);
    const double median = pow(log(2.0) / (1e10 * 1e-6), 1.0 / 9.0);
    int below = 0;
    for (int a = 0; a < 40000; ++a)
        below += weakest[a] <= median;
    assert_close(below / 40000.0, 0.5, 5.0 * sqrt(0.25 / 40000.0), "member 3: share below median");
    free(weakest);
}

/* One active flaw (flaws per particle cut to 1, strain above it): D^(1/3)
 * grows at 0.4 c_l / (k_R h) each step until D = 1. */
static void one_active_flaw_grows_cube_root_of_damage_linearly(void **state)
{
    (void)state;
    const double dx = 1e-3;
    int mat;
    sph_sim *sim = periodic_block(2, 12, dx, &mat);
    /* k V = 1e12 * 1e-6, m = 2: weakest strains ~ 1e-3 sqrt(u), u ~ 1 */
    check(sim, sph_material_set(sim, mat, "weibull_k", 1e12));
    check(sim, sph_material_set(sim, mat, "weibull_m", 2.0));
    check(sim, sph_effect(sim, "damage", "flaws=1e-9"));
    /* uniform tension: eps = -P / (3K) = 0.01 in every direction */
    const double S0[4] = {0, 0, 0, 0};
    set_uniform_stress(sim, -0.03 * PAPER_K, S0);
    double *flaws = copy_field(sim, SPH_FIELD_FLAWS, 144);
    double *weakest = copy_field(sim, SPH_FIELD_FLAW_STRAIN, 144);
    for (int a = 0; a < 144; ++a) {
        assert_int_equal((int)flaws[a], 1);
        assert_true(weakest[a] < 0.01);
    }
    sph_material_info info;
    check(sim, sph_material_info_get(sim, mat, &info));
    const double h = sph_smoothing_length(sim), dt = sph_dt(sim);
    const double rate = 0.4 * info.c_p / (2.0 * h); /* k_R = 2 */
    double *D = NULL;
    for (int step = 1; step <= 40; ++step) {
        check(sim, sph_run(sim, 1));
        D = field_ptr(sim, SPH_FIELD_DAMAGE);
        const double expected = step * dt * rate;
        for (int a = 0; a < 144; a += 13)
            if (expected < 1.0)
                assert_close(cbrt(D[a]), expected, 1e-12 * step, "D^(1/3) after the steps");
            else
                assert_close(D[a], 1.0, 0.0, "D once D^(1/3) reached 1");
    }
    assert_true(40 * dt * rate > 1.0); /* the run reached full damage */
    free(flaws);
    free(weakest);
    sph_destroy(sim);
}

/* D^(1/3) stops at (n_active / n_total)^(1/3). */
static void damage_is_capped_by_the_active_share_of_flaws(void **state)
{
    (void)state;
    const double dx = 1e-3;
    int mat;
    sph_sim *sim = periodic_block(2, 12, dx, &mat);
    check(sim, sph_material_set(sim, mat, "weibull_k", 1e12));
    check(sim, sph_material_set(sim, mat, "weibull_m", 2.0));
    check(sim, sph_effect(sim, "damage", "flaws=20"));
    /* eps = 1.5e-3: u = k V eps^2 = 2.25, about 2 of some 20 flaws active */
    const double S0[4] = {0, 0, 0, 0};
    set_uniform_stress(sim, -3.0 * PAPER_K * 1.5e-3, S0);
    double *active = copy_field(sim, SPH_FIELD_ACTIVE_FLAWS, 144);
    double *total = copy_field(sim, SPH_FIELD_FLAWS, 144);
    double *x0 = copy_field(sim, SPH_FIELD_POSITION, 288);
    /* particles of unlike D push each other: the state is put back before
     * each step, so the strain stays the one the flaws were counted at */
    for (int step = 0; step < 30; ++step) { /* D^(1/3) passes 1 in ~10 */
        set_uniform_stress(sim, -3.0 * PAPER_K * 1.5e-3, S0);
        memcpy(field_ptr(sim, SPH_FIELD_POSITION), x0, 288 * sizeof(double));
        memset(field_ptr(sim, SPH_FIELD_VELOCITY), 0, 288 * sizeof(double));
        check(sim, sph_run(sim, 1));
        /* the cap is that of the step's end state, and D never falls */
        double *now = copy_field(sim, SPH_FIELD_ACTIVE_FLAWS, 144);
        for (int a = 0; a < 144; ++a)
            active[a] = fmax(active[a], now[a]);
        free(now);
    }
    free(x0);
    double *D = field_ptr(sim, SPH_FIELD_DAMAGE);
    int partial = 0;
    for (int a = 0; a < 144; ++a) {
        assert_close(D[a], active[a] / total[a], 1e-12, "capped damage n_active / n_total");
        partial += active[a] > 0 && active[a] < total[a];
    }
    assert_true(partial > 100);
    free(active);
    free(total);
    sph_destroy(sim);
}

/* Uniaxial compression sigma_yy = -s (3D): the lateral strain is nu s / E,
 * so the weakest flaw activates at s = E eps_min / nu, and a particle is
 * damaged after a step exactly when its weakest strain is below nu s / E. */
static void damage_onset_in_uniaxial_compression_at_E_eps_min_over_nu(void **state)
{
    (void)state;
    const double dx = 2e-3;
    double onset = 0;
    for (int trial = 0; trial < 2; ++trial) {
        int mat;
        sph_sim *sim = periodic_block(3, 6, dx, &mat);
        check(sim, sph_material_set(sim, mat, "weibull_k", 1e30));
        check(sim, sph_material_set(sim, mat, "weibull_m", 9.0));
        check(sim, sph_effect(sim, "damage", "seed=3"));
        sph_material_info info;
        check(sim, sph_material_info_get(sim, mat, &info));
        double *weakest = copy_field(sim, SPH_FIELD_FLAW_STRAIN, 216);
        double eps_min = INFINITY;
        for (int a = 0; a < 216; ++a)
            eps_min = fmin(eps_min, weakest[a]);
        onset = info.youngs_modulus * eps_min / info.poisson_ratio;
        const double s = trial == 0 ? 0.99 * onset : 1.01 * onset;
        const double S[6] = {s / 3, -2 * s / 3, s / 3, 0, 0, 0}; /* P = s/3 */
        set_uniform_stress(sim, s / 3, S);
        check(sim, sph_set_dt(sim, 1e-3 * sph_dt(sim), 0));
        check(sim, sph_run(sim, 1));
        const double *D = field_ptr(sim, SPH_FIELD_DAMAGE);
        const double lateral = info.poisson_ratio * s / info.youngs_modulus;
        int damaged = 0;
        for (int a = 0; a < 216; ++a) {
            if (fabs(weakest[a] - lateral) < 1e-6 * lateral)
                continue; /* too close to call */
            assert_int_equal(D[a] > 0.0, weakest[a] < lateral);
            damaged += D[a] > 0.0;
        }
        assert_int_equal(damaged > 0, trial == 1);
        free(weakest);
        sph_destroy(sim);
    }
    assert_true(onset > 0);
}

/* A free block released from tension cracks from its flaws; the damage
 * field is bitwise the same on 1 and 2 threads, and after a checkpoint. */
static sph_sim *tension_block(int threads)
{
    sph_sim *sim = free_block_2d(40, 40, 1e-3);
    check(sim, sph_set_threads(sim, threads));
    /* k V eps^m = 0.64 at eps = 2e-3: about half the particles active */
    check(sim, sph_material_set(sim, 0, "weibull_k", 1e22));
    check(sim, sph_material_set(sim, 0, "weibull_m", 6.0));
    check(sim, sph_effect(sim, "damage", "seed=11"));
    check(sim, sph_effect(sim, "artificial_viscosity", NULL));
    const double S0[4] = {0, 0, 0, 0};
    set_uniform_stress(sim, -3.0 * PAPER_K * 2e-3, S0); /* eps = 2e-3 */
    return sim;
}

static void damage_field_is_bitwise_the_same_on_1_and_2_threads(void **state)
{
    (void)state;
    sph_sim *one = tension_block(1), *two = tension_block(2);
    check(one, sph_run(one, 150));
    check(two, sph_run(two, 150));
    const double *D1 = field_ptr(one, SPH_FIELD_DAMAGE), *D2 = field_ptr(two, SPH_FIELD_DAMAGE);
    int grown = 0, whole = 0;
    for (int a = 0; a < 1600; ++a) {
        assert_memory_equal(&D1[a], &D2[a], sizeof(double));
        grown += D1[a] > 0.0;
        whole += D1[a] == 0.0;
    }
    assert_true(grown > 0 && whole > 0); /* a field worth comparing */
    assert_memory_equal(field_ptr(one, SPH_FIELD_POSITION), field_ptr(two, SPH_FIELD_POSITION),
                        1600 * 2 * sizeof(double));
    sph_destroy(one);
    sph_destroy(two);
}

/* The calls on external particles (sph_damage_flaws, _grow, _active),
 * given the handle's own particles with id = index, are the handle's
 * damage stage bitwise: the same flaws, the same D after a step, the
 * same active flaws; other ids draw other flaws. */
static void external_particles_damage_as_the_handle_does(void **state)
{
    (void)state;
    sph_sim *sim = tension_block(1);
    check(sim, sph_run(sim, 20));
    const size_t n = 1600;
    uint64_t *id = malloc(n * sizeof *id);
    int *material = calloc(n, sizeof *material), *count = malloc(n * sizeof *count);
    double *strain = malloc(n * sizeof *strain), *active = malloc(n * sizeof *active);
    assert_true(id && material && count && strain && active);
    for (size_t a = 0; a < n; ++a)
        id[a] = a;
    const double *mass = field_ptr(sim, SPH_FIELD_MASS);
    check(sim, sph_damage_flaws(sim, n, id, mass, material, NULL, count, strain));
    double *flaws = copy_field(sim, SPH_FIELD_FLAWS, n);
    double *weakest = copy_field(sim, SPH_FIELD_FLAW_STRAIN, n);
    for (size_t a = 0; a < n; ++a) {
        assert_true((double)count[a] == flaws[a]);
        assert_memory_equal(&strain[a], &weakest[a], sizeof(double));
    }
    double *D = copy_field(sim, SPH_FIELD_DAMAGE, n);
    check(sim, sph_run(sim, 1));
    const double *rho = field_ptr(sim, SPH_FIELD_DENSITY);
    const double *S = field_ptr(sim, SPH_FIELD_DEVIATORIC_STRESS);
    int changed = 0;
    check(sim, sph_damage_grow(sim, n, sph_dt(sim), id, mass, material, rho, S, count, strain, D,
                               &changed));
    const double *D_handle = field_ptr(sim, SPH_FIELD_DAMAGE);
    double *active_handle = copy_field(sim, SPH_FIELD_ACTIVE_FLAWS, n);
    check(sim, sph_damage_active(sim, n, id, mass, material, rho, S, count, strain, active));
    int grown = 0;
    for (size_t a = 0; a < n; ++a) {
        assert_memory_equal(&D[a], &D_handle[a], sizeof(double));
        assert_true(active[a] == active_handle[a]);
        grown += D[a] > 0.0;
    }
    assert_true(changed && grown > 0 && grown < (int)n); /* a step that damages */
    /* ids one higher: another draw; flawed = 0: no flaws */
    unsigned char *flawed = calloc(n, 1);
    assert_non_null(flawed);
    for (size_t a = 0; a < n; ++a)
        id[a] = a + 1;
    check(sim, sph_damage_flaws(sim, n, id, mass, material, NULL, count, strain));
    int same = 0;
    for (size_t a = 0; a < n; ++a)
        same += strain[a] == weakest[a];
    assert_true(same < 5);
    check(sim, sph_damage_flaws(sim, n, id, mass, material, flawed, count, strain));
    for (size_t a = 0; a < n; ++a)
        assert_true(count[a] == 0 && isinf(strain[a]));
    /* bad input names the value; off: a state error */
    material[7] = 3;
    assert_int_equal(sph_damage_flaws(sim, n, id, mass, material, NULL, count, strain),
                     SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "material[7]=3"));
    check(sim, sph_effect_off(sim, "damage"));
    assert_int_equal(
        sph_damage_grow(sim, n, 1e-7, id, mass, material, rho, S, count, strain, D, &changed),
        SPH_ERR_STATE);
    free(flawed);
    free(active_handle);
    free(D);
    free(weakest);
    free(flaws);
    free(active);
    free(strain);
    free(count);
    free(material);
    free(id);
    sph_destroy(sim);
}

/* The paper scene (coarse), its probe series after `steps`. */
static void paper_probes(int damage, int toggle, double *out, int steps, size_t *bytes)
{
    sph_sim *sim = new_sim(2);
    sph_paper_scene s;
    check(sim, sph_build_paper_scene(sim, 4e-3, 1.5, 0, &s));
    check(sim, sph_effect(sim, "artificial_viscosity", NULL));
    if (damage || toggle) {
        /* flaws that no strain of this run reaches: eps_min ~ 1e4 */
        check(sim, sph_material_set(sim, s.material, "weibull_k", 1.0));
        check(sim, sph_material_set(sim, s.material, "weibull_m", 1.0));
        check(sim, sph_effect(sim, "damage", NULL));
        check(sim, sph_run(sim, 1));
    }
    if (toggle)
        check(sim, sph_effect_off(sim, "damage"));
    if (!(damage || toggle))
        check(sim, sph_run(sim, 1));
    const double per = SPH_PROBE_VALUES(2);
    for (int k = 0; k < steps; ++k) {
        check(sim, sph_run(sim, 1));
        for (int p = 0; p < 3; ++p)
            check(sim, sph_probe_sample(sim, p, out + (size_t)(k * 3 + p) * (size_t)per));
    }
    *bytes = sph_memory_bytes(sim);
    sph_destroy(sim);
}

/* Damage that never activates multiplies the stress by exactly 1: the
 * probe series is bitwise that of the run without the effect; switched
 * off again, the effect leaves no memory behind. */
static void damage_without_active_flaws_leaves_the_paper_series_bitwise(void **state)
{
    (void)state;
    const int steps = 200, per = SPH_PROBE_VALUES(2);
    double *off = malloc(sizeof(double) * steps * 3 * per);
    double *on = malloc(sizeof(double) * steps * 3 * per);
    double *toggled = malloc(sizeof(double) * steps * 3 * per);
    size_t bytes_off, bytes_on, bytes_toggled;
    paper_probes(0, 0, off, steps, &bytes_off);
    paper_probes(1, 0, on, steps, &bytes_on);
    paper_probes(0, 1, toggled, steps, &bytes_toggled);
    assert_memory_equal(off, on, sizeof(double) * steps * 3 * per);
    assert_memory_equal(off, toggled, sizeof(double) * steps * 3 * per);
    assert_true(bytes_on > bytes_off);
    assert_int_equal(bytes_toggled, bytes_off);
    free(off);
    free(on);
    free(toggled);
}

/* The damaged stress: tension leaves the pressure, the deviator scales. */
static void damaged_stress_keeps_compression_and_scales_the_deviator(void **state)
{
    (void)state;
    const double S[4] = {1, -2, 1, 3};
    double Sd[4], P = -10.0;
    damaged_stress(4, 0.25, S, &P, Sd);
    assert_close(P, -7.5, 0, "tension * (1 - D)");
    for (int c = 0; c < 4; ++c)
        assert_close(Sd[c], 0.75 * S[c], 0, "deviator * (1 - D)");
    P = 10.0;
    damaged_stress(4, 1.0, S, &P, Sd);
    assert_close(P, 10.0, 0, "compression kept at D = 1");
    assert_close(Sd[3], 0.0, 0, "no shear at D = 1");
}

/* The largest principal strain of a known tensor: a rotated diagonal. */
static void largest_principal_strain_of_a_rotated_tensor(void **state)
{
    (void)state;
    const double K = 10.0, mu = 4.0, P = 3.0;
    /* deviator with eigenvalues (5, -1, -4) rotated by 30 degrees about z */
    const double c = cos(M_PI / 6), s = sin(M_PI / 6);
    const double S3[6] = {5 * c * c - s * s, 5 * s * s - c * c, -4, 6 * c * s, 0, 0};
    const double expected = 5.0 / (2 * mu) - P / (3 * K);
    assert_close(largest_principal_strain(3, S3, P, K, mu), expected, 1e-14,
                 "3D largest principal strain");
    const double S2[4] = {S3[0], S3[1], S3[2], S3[3]};
    assert_close(largest_principal_strain(2, S2, P, K, mu), expected, 1e-14,
                 "2D largest principal strain");
}

/* A free 21 x 10 block (1 mm) with the damage effect and flaws too few to
 * activate: its damage field is the test's to set. */
static sph_sim *flawless_damaged_block(void)
{
    sph_sim *sim = free_block_2d(21, 10, 1e-3);
    check(sim, sph_material_set(sim, 0, "weibull_k", 1.0));
    check(sim, sph_material_set(sim, 0, "weibull_m", 1.0));
    check(sim, sph_effect(sim, "damage", NULL));
    return sim;
}

/* Fragments: a block cut by three fully damaged columns (wider than the
 * kernel support 2h = 2.4 dx) is two fragments; barely intact, one. */
static void a_fully_damaged_band_splits_a_block_into_two_fragments(void **state)
{
    (void)state;
    for (int trial = 0; trial < 2; ++trial) {
        sph_sim *sim = flawless_damaged_block();
        /* a copy: the run's preparation may move the arrays */
        double *x = copy_field(sim, SPH_FIELD_POSITION, 420);
        double *D = field_ptr(sim, SPH_FIELD_DAMAGE);
        for (int a = 0; a < 210; ++a)
            if (fabs(x[2 * a]) < 2e-3)
                D[a] = trial == 0 ? 1.0 : 0.999;
        double fragment[210];
        check(sim, sph_field_copy(sim, SPH_FIELD_FRAGMENT, fragment));
        double top = -1;
        for (int a = 0; a < 210; ++a) {
            top = fmax(top, fragment[a]);
            if (trial == 0 && fabs(x[2 * a]) < 2e-3)
                assert_close(fragment[a], -1.0, 0, "fragment of a D = 1 particle");
            else if (trial == 0)
                assert_close(fragment[a], x[2 * a] < 0 ? 0.0 : 1.0, 0, "fragment by side");
        }
        assert_close(top + 1, trial == 0 ? 2.0 : 1.0, 0, "number of fragments");
        free(x);
        sph_destroy(sim);
    }
}

/* The labelling of caller-owned particles (sph_damage_fragment_labels)
 * gives each fragment of SPH_FIELD_FRAGMENT the least label of its
 * particles: with labels index + 1, fragment f's first index + 1; the same
 * with a full list and with each pair once; -1 where the field has -1. */
static void fragment_labels_of_external_particles_match_the_field(void **state)
{
    (void)state;
    sph_sim *sim = flawless_damaged_block();
    double *x = copy_field(sim, SPH_FIELD_POSITION, 420);
    double *D = field_ptr(sim, SPH_FIELD_DAMAGE);
    for (int a = 0; a < 210; ++a)
        if (fabs(x[2 * a]) < 2e-3 || a == 17 || a == 150) /* a band and two holes */
            D[a] = 1.0;
    double fragment[210], first[210];
    check(sim, sph_field_copy(sim, SPH_FIELD_FRAGMENT, fragment));
    for (int f = 0; f < 210; ++f)
        first[f] = -1.0;
    for (int a = 209; a >= 0; --a)
        if (fragment[a] >= 0)
            first[(int)fragment[a]] = a;
    /* every pair within 3 dx: full rows, and each pair once */
    static int full[210 * 210], half[210 * 210];
    size_t full_rows[211], half_rows[211], nf = 0, nh = 0;
    for (int a = 0; a < 210; ++a) {
        full_rows[a] = nf;
        half_rows[a] = nh;
        for (int b = 0; b < 210; ++b) {
            const double dx = x[2 * a] - x[2 * b], dy = x[2 * a + 1] - x[2 * b + 1];
            if (b == a || dx * dx + dy * dy > 9e-6)
                continue;
            full[nf++] = b;
            if (b > a)
                half[nh++] = b;
        }
    }
    full_rows[210] = nf;
    half_rows[210] = nh;
    unsigned char member[210];
    memset(member, 1, sizeof member);
    const double *mass = field_ptr(sim, SPH_FIELD_MASS);
    for (int list = 0; list < 2; ++list) {
        sph_particles p = {0};
        p.n_local = p.n_total = 210;
        p.x = x;
        p.mass = mass;
        p.damage = D;
        sph_neighbours nb = {0};
        nb.offsets = list ? half_rows : full_rows;
        nb.indices = list ? half : full;
        double label[210];
        for (int a = 0; a < 210; ++a)
            label[a] = a + 1;
        int changed = 0, fragments = 0;
        check(sim, sph_damage_fragment_labels(sim, &p, &nb, member, label, &changed));
        assert_true(changed);
        for (int a = 0; a < 210; ++a) {
            const double expected = fragment[a] < 0 ? -1.0 : first[(int)fragment[a]] + 1;
            assert_close(label[a], expected, 0, "fragment label");
            fragments += label[a] == a + 1;
        }
        assert_int_equal(fragments, 2);
        /* a second round changes nothing */
        check(sim, sph_damage_fragment_labels(sim, &p, &nb, member, label, &changed));
        assert_false(changed);
    }
    free(x);
    sph_destroy(sim);
}

/* Newton's third law: the platens' reactions and the SPH forces on the
 * specimen sum to zero (no gravity). */
static void platen_reactions_balance_the_forces_on_the_specimen(void **state)
{
    (void)state;
    sph_sim *sim = new_sim(2);
    sph_paper_scene s;
    check(sim, sph_build_paper_scene(sim, 4e-3, 1.5, 0, &s));
    check(sim, sph_run(sim, 300));
    double a[2 * 2000], piston[3], plate[3], sum[2] = {0, 0};
    size_t n = 0;
    double *mass;
    check(sim, sph_field(sim, SPH_FIELD_MASS, &mass, &n, NULL));
    assert_true(n <= 2000);
    check(sim, sph_field_copy(sim, SPH_FIELD_ACCELERATION, a));
    int *body = malloc(n * sizeof *body);
    check(sim, sph_body_ids(sim, body));
    for (size_t k = 0; k < n; ++k)
        for (int i = 0; i < 2 && body[k] == s.specimen; ++i)
            sum[i] += mass[k] * a[2 * k + i];
    free(body);
    check(sim, sph_body_reaction(sim, s.piston, piston));
    check(sim, sph_body_reaction(sim, s.plate, plate));
    assert_true(piston[1] > 0.0 && plate[1] < 0.0); /* the specimen pushes them apart */
    for (int i = 0; i < 2; ++i)
        assert_close(piston[i] + plate[i] + sum[i], 0.0, 1e-9 * fabs(piston[1]),
                     "reactions + specimen forces");
    assert_int_equal(sph_body_reaction(sim, 7, piston), SPH_ERR_ARGUMENT);
    sph_destroy(sim);
}

static void bad_damage_input_names_the_value(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(4, 4, 1e-3);
    assert_int_equal(sph_material_set(sim, 0, "weibull_q", 1.0), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "weibull_q"));
    assert_int_equal(sph_material_set(sim, 0, "weibull_k", -1.0), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "weibull_k=-1"));
    assert_int_equal(sph_effect(sim, "damage", "seed=1.5"), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "seed=1.5"));
    assert_int_equal(sph_effect(sim, "damage", "member=2.5"), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "member=2.5"));
    assert_int_equal(sph_effect(sim, "damage", "member=-1"), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "member=-1"));
    check(sim, sph_effect(sim, "damage", NULL));
    assert_int_equal(sph_run(sim, 1), SPH_ERR_STATE); /* no material has flaws */
    assert_non_null(strstr(sph_errmsg(sim), "weibull_k"));
    check(sim, sph_effect_off(sim, "damage"));
    double out[16];
    assert_int_equal(sph_field_copy(sim, SPH_FIELD_DAMAGE, out), SPH_ERR_STATE);
    assert_non_null(strstr(sph_errmsg(sim), "damage"));
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(flaw_counts_follow_k_V_eps_to_the_m),
        cmocka_unit_test(weakest_flaws_follow_the_first_arrival_law),
        cmocka_unit_test(ensemble_members_draw_independent_flaws),
        cmocka_unit_test(one_active_flaw_grows_cube_root_of_damage_linearly),
        cmocka_unit_test(damage_is_capped_by_the_active_share_of_flaws),
        cmocka_unit_test(damage_onset_in_uniaxial_compression_at_E_eps_min_over_nu),
        cmocka_unit_test(damage_field_is_bitwise_the_same_on_1_and_2_threads),
        cmocka_unit_test(external_particles_damage_as_the_handle_does),
        cmocka_unit_test(damage_without_active_flaws_leaves_the_paper_series_bitwise),
        cmocka_unit_test(damaged_stress_keeps_compression_and_scales_the_deviator),
        cmocka_unit_test(largest_principal_strain_of_a_rotated_tensor),
        cmocka_unit_test(a_fully_damaged_band_splits_a_block_into_two_fragments),
        cmocka_unit_test(fragment_labels_of_external_particles_match_the_field),
        cmocka_unit_test(platen_reactions_balance_the_forces_on_the_specimen),
        cmocka_unit_test(bad_damage_input_names_the_value),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
