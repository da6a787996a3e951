/* The drucker_prager effect: the cone's strengths against Mohr-Coulomb's
 * (uniaxial compression, confinement), the return of a homogeneous patch
 * onto the cone with the energy it dissipates, the limit on the damaged
 * stress, external particles and bad input. */
#include "helpers.h"

#include "effects/plasticity.h"

/* sqrt(J2) of a deviator of 6 components (xx yy zz xy xz yz). */
static double root_J2(const double *S)
{
    return sqrt(0.5 * (S[0] * S[0] + S[1] * S[1] + S[2] * S[2] +
                       2.0 * (S[3] * S[3] + S[4] * S[4] + S[5] * S[5])));
}

/* Whether the triaxial compression state (axial stress -axial, lateral
 * -lateral, compression positive in the arguments) lies inside the cone
 * (the return leaves it unchanged). */
static int inside(double A, double B, double axial, double lateral)
{
    const double P = (axial + 2.0 * lateral) / 3.0, q = axial - lateral;
    double S[6] = {q / 3.0, q / 3.0, -2.0 * q / 3.0, 0, 0, 0}; /* z axial */
    return drucker_prager_return(6, A, B, P, 0.0, S) == 1.0;
}

/* The largest axial compression the cone allows at a lateral pressure, by
 * bisection of the return's own verdict. */
static double axial_strength(double A, double B, double lateral)
{
    double lo = lateral, hi = lateral + 1e12;
    for (int k = 0; k < 200; ++k) {
        const double mid = 0.5 * (lo + hi);
        if (inside(A, B, mid, lateral))
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Uniaxial compression: the compression-meridian cone is Mohr-Coulomb's
 * there, UCS = 2 c cos(phi) / (1 - sin(phi)); under a confining pressure p
 * the axial strength rises as UCS + p (1 + sin(phi)) / (1 - sin(phi)), and
 * sqrt(J2) at the limit rises with P at slope B. */
static void strengths_are_mohr_coulomb_on_the_compression_meridian(void **state)
{
    (void)state;
    const double c = 4e6, angles[] = {0.0, 15.0, 30.0, 45.0};
    for (int i = 0; i < 4; ++i) {
        const double phi = angles[i] * M_PI / 180.0, s = sin(phi);
        double A, B;
        drucker_prager_constants(c, angles[i], &A, &B);
        const double ucs = 2.0 * c * cos(phi) / (1.0 - s);
        assert_close(axial_strength(A, B, 0.0), ucs, 1e-9 * ucs, "UCS");
        const double kp = (1.0 + s) / (1.0 - s);
        for (int k = 1; k <= 3; ++k) {
            const double p = 10e6 * k, limit = axial_strength(A, B, p);
            assert_close(limit, ucs + kp * p, 1e-9 * limit, "axial strength under confinement");
            /* on the cone: sqrt(J2) = (limit - p)/sqrt(3) = A + B P */
            const double P = (limit + 2.0 * p) / 3.0;
            assert_close((limit - p) / sqrt(3.0), A + B * P, 1e-9 * limit, "sqrt(J2) = A + B P");
        }
        /* the slope of the limit in (P, sqrt(J2)) between two confinements */
        const double p1 = 5e6, p2 = 50e6, l1 = axial_strength(A, B, p1),
                     l2 = axial_strength(A, B, p2);
        const double slope =
            ((l2 - p2) - (l1 - p1)) / sqrt(3.0) / ((l2 + 2 * p2) / 3.0 - (l1 + 2 * p1) / 3.0);
        assert_close(slope, B, 1e-7 * (B + 1.0), "slope d sqrt(J2) / dP");
    }
}

/* A return scales the deviator radially onto the cone (its direction kept);
 * past the apex (A + B P <= 0) it zeroes it; with damage D the damaged
 * deviator (1 - D) S meets the cone at the damaged pressure. */
static void the_return_is_radial_and_acts_on_the_damaged_stress(void **state)
{
    (void)state;
    double A, B;
    drucker_prager_constants(2e6, 35.0, &A, &B);
    const double S0[6] = {12e6, -5e6, -7e6, 3e6, -2e6, 4e6};
    for (int k = 0; k < 3; ++k) {
        const double P = k == 0 ? 5e6 : k == 1 ? -1e6 : -A / B * 2.0; /* the last: past the apex */
        const double D = k == 1 ? 0.5 : 0.0;
        double S[6];
        memcpy(S, S0, sizeof S);
        const double scale = drucker_prager_return(6, A, B, P, D, S);
        const double Pd = P < 0 ? (1 - D) * P : P, limit = A + B * Pd;
        if (limit <= 0) {
            assert_true(scale == 0.0);
            for (int c = 0; c < 6; ++c)
                assert_true(S[c] == 0.0);
            continue;
        }
        assert_true(scale < 1.0);
        assert_close((1 - D) * root_J2(S), limit, 1e-12 * limit, "damaged sqrt(J2) on the cone");
        for (int c = 0; c < 6; ++c)
            assert_close(S[c], scale * S0[c], 1e-12 * fabs(S0[c]), "radial return");
    }
    /* a fully damaged particle: nothing to limit */
    double S[6];
    memcpy(S, S0, sizeof S);
    assert_true(drucker_prager_return(6, A, B, 0.0, 1.0, S) == 1.0);
    assert_memory_equal(S, S0, sizeof S);
}

/* A periodic block of 6^3 particles under a uniform uniaxial compression of
 * 1.5 x its UCS: one step returns every particle onto the cone (sqrt(J2)
 * = A + B P, the pressure unchanged), and the energy account's plastic
 * dissipation is the shear energy removed, m (S:S - S':S') / (4 mu rho)
 * summed.  Inside the cone (0.9 x UCS) nothing is returned. */
static void a_homogeneous_patch_saturates_at_the_cone(void **state)
{
    (void)state;
    const double dx = 2e-3, c = 3e6, phi_deg = 30.0, phi = phi_deg * M_PI / 180.0;
    const double ucs = 2.0 * c * cos(phi) / (1.0 - sin(phi));
    double A, B;
    drucker_prager_constants(c, phi_deg, &A, &B);
    for (int trial = 0; trial < 2; ++trial) {
        sph_sim *sim = new_sim(3);
        int mat, body;
        check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
        const double L = 6 * dx, lo[3] = {0, 0, 0}, hi[3] = {L, L, L};
        const int periodic[3] = {1, 1, 1};
        check(sim, sph_set_domain(sim, lo, hi, periodic));
        check(sim, sph_add_block(sim, "block", mat, lo, hi, dx, &body));
        char text[96];
        snprintf(text, sizeof text, "cohesion=%.17g friction_angle=%g", c, phi_deg);
        check(sim, sph_effect(sim, "drucker_prager", text));
        check(sim, sph_set_energy_account(sim, 1));
        sph_material_info info;
        check(sim, sph_material_info_get(sim, mat, &info));
        const double s = (trial == 0 ? 1.5 : 0.9) * ucs, P = s / 3.0;
        const double S0[6] = {s / 3, s / 3, -2 * s / 3, 0, 0, 0};
        size_t n = 0, nc = 0;
        double *rho, *dev;
        check(sim, sph_field(sim, SPH_FIELD_DENSITY, &rho, &n, NULL));
        check(sim, sph_field(sim, SPH_FIELD_DEVIATORIC_STRESS, &dev, NULL, &nc));
        for (size_t a = 0; a < n; ++a) {
            rho[a] = info.rho0 + P / (info.c0 * info.c0);
            memcpy(dev + a * nc, S0, sizeof S0);
        }
        check(sim, sph_set_dt(sim, 1e-3 * sph_dt(sim), 0));
        check(sim, sph_run(sim, 1));
        check(sim, sph_field(sim, SPH_FIELD_DENSITY, &rho, &n, NULL));
        check(sim, sph_field(sim, SPH_FIELD_DEVIATORIC_STRESS, &dev, NULL, &nc));
        const double *mass = field_ptr(sim, SPH_FIELD_MASS);
        double expected = 0.0;
        for (size_t a = 0; a < n; ++a) {
            const double Pa = info.c0 * info.c0 * (rho[a] - info.rho0);
            assert_close(Pa, P, 1e-9 * P, "pressure kept (no dilatancy)");
            if (trial == 1) { /* elastic: only the rates' round-off moves it */
                for (size_t k = 0; k < nc; ++k)
                    assert_close(dev[a * nc + k], S0[k], 1e-9 * s, "stress inside the cone");
                continue;
            }
            assert_close(root_J2(dev + a * nc), A + B * Pa, 1e-9 * A, "sqrt(J2) on the cone");
            const double SS0 = 2.0 * root_J2(S0) * root_J2(S0);
            const double SS = 2.0 * root_J2(dev + a * nc) * root_J2(dev + a * nc);
            expected += mass[a] * (SS0 - SS) / (4.0 * info.shear_modulus * rho[a]);
        }
        sph_energy_info e;
        check(sim, sph_energy(sim, 1, &e));
        if (trial == 0)
            assert_close(e.dissipated_plastic, expected, 1e-9 * expected, "plastic dissipation");
        else
            assert_true(e.dissipated_plastic == 0.0);
        sph_destroy(sim);
    }
}

/* The call on a caller's arrays returns as the handle's stage does. */
static void external_particles_return_as_the_handle_does(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(6, 6, 1e-3);
    check(sim, sph_effect(sim, "drucker_prager", "cohesion=1e6 friction_angle=25"));
    size_t n = 0, nc = 0;
    double *rho, *dev;
    check(sim, sph_field(sim, SPH_FIELD_DENSITY, &rho, &n, NULL));
    check(sim, sph_field(sim, SPH_FIELD_DEVIATORIC_STRESS, &dev, NULL, &nc));
    for (size_t a = 0; a < n; ++a) {
        rho[a] *= 1.0 + 1e-4 * (double)(a % 5) - 2e-4;
        for (size_t k = 0; k < nc; ++k)
            dev[a * nc + k] = 1e6 * sin(1.0 + (double)(a * nc + k));
    }
    double *S = malloc(n * nc * sizeof *S), *r = malloc(n * sizeof *r);
    int *mat = calloc(n, sizeof *mat);
    memcpy(S, dev, n * nc * sizeof *S);
    memcpy(r, rho, n * sizeof *r);
    int changed = 0;
    check(sim, sph_drucker_prager_return(sim, n, mat, r, NULL, NULL, S, &changed));
    assert_int_equal(changed, 1);
    check(sim, sph_set_dt(sim, 1e-9, 0)); /* a step that barely moves */
    check(sim, sph_run(sim, 1));
    check(sim, sph_field(sim, SPH_FIELD_DENSITY, &rho, &n, NULL));
    check(sim, sph_field(sim, SPH_FIELD_DEVIATORIC_STRESS, &dev, NULL, &nc));
    double A, B;
    drucker_prager_constants(1e6, 25.0, &A, &B);
    for (size_t a = 0; a < n; ++a) {
        const double full[6] = {
            dev[a * nc], dev[a * nc + 1], dev[a * nc + 2], dev[a * nc + 3], 0, 0};
        const double P = PAPER_K * (rho[a] / PAPER_RHO0 - 1.0);
        assert_true(root_J2(full) <= (A + B * P) * (1 + 1e-12) || A + B * P <= 0);
        for (size_t k = 0; k < nc; ++k)
            assert_close(dev[a * nc + k], S[a * nc + k], 1e-3 * (A + fabs(B * P)),
                         "external return");
    }
    free(S);
    free(r);
    free(mat);
    sph_destroy(sim);
}

static void bad_drucker_prager_input_names_the_value(void **state)
{
    (void)state;
    sph_sim *sim = free_block_2d(4, 4, 1e-3);
    assert_int_equal(sph_effect(sim, "drucker_prager", NULL), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "cohesion"));
    assert_int_equal(sph_effect(sim, "drucker_prager", "cohesion=1e6 friction_angle=90"),
                     SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "friction_angle"));
    assert_int_equal(sph_effect(sim, "drucker_prager", "cohesion=-1"), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "cohesion"));
    int changed = 1, mat = 0;
    double rho = PAPER_RHO0, S[4] = {0};
    assert_int_equal(sph_drucker_prager_return(sim, 1, &mat, &rho, NULL, NULL, S, &changed),
                     SPH_ERR_STATE);
    assert_non_null(strstr(sph_errmsg(sim), "drucker_prager is off"));
    check(sim, sph_effect(sim, "drucker_prager", "cohesion=1e6"));
    mat = 3;
    assert_int_equal(sph_drucker_prager_return(sim, 1, &mat, &rho, NULL, NULL, S, &changed),
                     SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(sim), "material 3"));
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(strengths_are_mohr_coulomb_on_the_compression_meridian),
        cmocka_unit_test(the_return_is_radial_and_acts_on_the_damaged_stress),
        cmocka_unit_test(a_homogeneous_patch_saturates_at_the_cone),
        cmocka_unit_test(external_particles_return_as_the_handle_does),
        cmocka_unit_test(bad_drucker_prager_input_names_the_value),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
