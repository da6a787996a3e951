/*
 * The energy account's pieces on a caller's particles (sph_energy_power,
 * sph_energy_sums, sph_energy_released: the LAMMPS plugin's account), on
 * small arrays whose answers follow from their definitions: kinetic energy
 * sum m v^2 / 2, elastic energy the sum of sph_energy_fields, the work
 * rate of an extra uniform acceleration g sum m g . v, the viscous heat
 * the kinetic energy that the viscous accelerations of the rate engine
 * take, the energy a stage releases the elastic energy it took.
 */
#include "helpers.h"

#include "core/sim.h"

/* status and message of a call that must be refused */
#define refused(sim, call, text)                                                                \
    do {                                                                                        \
        strcpy((sim)->errmsg, "stale message");                                                 \
        const sph_status st_ = (call);                                                          \
        if (st_ != SPH_ERR_ARGUMENT || !strstr(sph_errmsg(sim), (text))) {                      \
            print_error("%s: status %d, message '%s'; expected %d and '%s'\n", #call, (int)st_, \
                        sph_errmsg(sim), (int)SPH_ERR_ARGUMENT, (text));                        \
            fail();                                                                             \
        }                                                                                       \
    } while (0)

enum { N = 5, NC = 4 };

/* Five 2D particles of the paper material: masses, velocities 3 doubles
 * apart (LAMMPS's layout), densities in tension (a < 2) and compression,
 * deviators with shear. */
typedef struct state {
    double mass[N], v[3 * N], rho[N], S[NC * N];
    int material[N];
} state;

static state five_particles(void)
{
    state s;
    for (int a = 0; a < N; ++a) {
        s.mass[a] = 2.3e-3 * (1.0 + 0.1 * a);
        s.v[3 * a] = 0.3 * a - 0.5;
        s.v[3 * a + 1] = 0.7 - 0.2 * a * a;
        s.v[3 * a + 2] = 1e3; /* not a 2D component: must not count */
        s.rho[a] = PAPER_RHO0 * (1.0 + 1e-3 * (a - 2));
        for (int c = 0; c < NC; ++c)
            s.S[NC * a + c] = 1e5 * ((a + c) % 3) - 1.2e5 + 3e4 * c;
        s.material[a] = 0;
    }
    return s;
}

/* ------------------------------------------------------ sph_energy_sums */

static void sums_are_kinetic_and_elastic_energy(void **state_)
{
    (void)state_;
    int mat;
    sph_sim *sim = external_particles_2d(&mat);
    state s = five_particles();
    double kinetic = 0.0;
    for (int a = 0; a < N; ++a)
        kinetic += 0.5 * s.mass[a] * (s.v[3 * a] * s.v[3 * a] + s.v[3 * a + 1] * s.v[3 * a + 1]);
    double fields[N], elastic = 0.0;
    check(sim, sph_energy_fields(sim, N, s.mass, s.rho, s.S, s.material, fields));
    for (int a = 0; a < N; ++a)
        elastic += fields[a];

    double energy[2] = {0.0, 0.0};
    check(sim, sph_energy_sums(sim, N, s.mass, s.v, 3, s.rho, s.S, NULL, s.material, NULL, energy));
    assert_close(energy[0], kinetic, 1e-15 * kinetic, "kinetic energy");
    assert_close(energy[1], elastic, 1e-13 * elastic, "elastic energy");
    /* added to what energy[] holds */
    check(sim, sph_energy_sums(sim, N, s.mass, s.v, 3, s.rho, s.S, NULL, s.material, NULL, energy));
    assert_close(energy[0], 2.0 * kinetic, 2e-15 * kinetic, "kinetic energy, added");
    assert_close(energy[1], 2.0 * elastic, 2e-13 * elastic, "elastic energy, added");

    /* undamaged D = 0 is no damage; member selects */
    const double D0[N] = {0.0, 0.0, 0.0, 0.0, 0.0};
    const unsigned char member[N] = {1, 0, 1, 0, 0};
    double with_d[2] = {0.0, 0.0}, some[2] = {0.0, 0.0};
    check(sim, sph_energy_sums(sim, N, s.mass, s.v, 3, s.rho, s.S, D0, s.material, NULL, with_d));
    assert_close(with_d[1], elastic, 1e-13 * elastic, "elastic energy at D = 0");
    check(sim, sph_energy_sums(sim, N, s.mass, s.v, 3, s.rho, s.S, NULL, s.material, member, some));
    const double k_some = 0.5 * s.mass[0] * (0.25 + 0.49) +
                          0.5 * s.mass[2] * (0.1 * 0.1 + 0.1 * 0.1); /* v = (0.1, -0.1) */
    assert_close(some[0], k_some, 1e-15 * k_some, "kinetic energy of the members");
    assert_close(some[1], fields[0] + fields[2], 1e-13 * elastic, "elastic energy of the members");

    /* damage D: in tension (rho < rho0, particles 0 and 1) the whole
     * energy times 1 - D; in compression (3, 4) the volumetric part
     * stays, the shear part times 1 - D */
    const double D[N] = {0.3, 1.0, 0.0, 0.5, 1.0};
    double damaged[2] = {0.0, 0.0};
    check(sim, sph_energy_sums(sim, N, s.mass, s.v, 3, s.rho, s.S, D, s.material, NULL, damaged));
    const double zero[NC * N] = {0.0};
    double volumetric[N];
    check(sim, sph_energy_fields(sim, N, s.mass, s.rho, zero, s.material, volumetric));
    double expected = 0.7 * fields[0] + 0.0 * fields[1] + fields[2];
    expected += volumetric[3] + 0.5 * (fields[3] - volumetric[3]);
    expected += volumetric[4];
    assert_true(volumetric[4] > 0.0 && fields[4] > volumetric[4]);
    assert_close(damaged[1], expected, 1e-13 * elastic, "damaged elastic energy");
    assert_close(damaged[0], kinetic, 1e-15 * kinetic, "kinetic energy with damage");
    sph_destroy(sim);
}

/* ----------------------------------------------------- sph_energy_power */

/* the caller's particles of five_particles() (no ghosts) */
static sph_particles as_particles(const state *s, const double *x)
{
    return (sph_particles){.n_local = N,
                           .n_total = N,
                           .x = x,
                           .v = s->v,
                           .rho = s->rho,
                           .S = s->S,
                           .mass = s->mass,
                           .material = s->material,
                           .stride = 3};
}

static void power_of_a_uniform_acceleration(void **state_)
{
    (void)state_;
    int mat;
    sph_sim *sim = external_particles_2d(&mat);
    state s = five_particles();
    const sph_particles p = as_particles(&s, NULL);
    const sph_neighbours none = {0};
    /* dv_dt = dv_sph + g: the work rate of g, sum m g . v */
    const double g[2] = {0.4, -9.81};
    double dv_sph[2 * N], dv_dt[2 * N], expected = 0.0;
    for (int a = 0; a < N; ++a)
        for (int i = 0; i < 2; ++i) {
            dv_sph[2 * a + i] = 1e3 * (a - 2.0) + 7.0 * i;
            dv_dt[2 * a + i] = dv_sph[2 * a + i] + g[i];
            expected += s.mass[a] * g[i] * s.v[3 * a + i];
        }
    double power[2] = {-1.0, -1.0};
    check(sim, sph_energy_power(sim, &p, &none, 0, dv_sph, dv_dt, NULL, power));
    assert_close(power[0], expected, 1e-9 * fabs(expected), "work rate of g");
    assert_true(power[1] == 0.0); /* no artificial viscosity */

    /* a prescribed particle does not accelerate: its motion does the work
     * -m dv_sph . v, whatever dv_dt says */
    const unsigned char integrate[N] = {1, 1, 0, 1, 1};
    double prescribed = 0.0;
    for (int a = 0; a < N; ++a)
        for (int i = 0; i < 2; ++i)
            prescribed += a == 2 ? -s.mass[a] * dv_sph[2 * a + i] * s.v[3 * a + i]
                                 : s.mass[a] * g[i] * s.v[3 * a + i];
    check(sim, sph_energy_power(sim, &p, &none, 0, dv_sph, dv_dt, integrate, power));
    assert_close(power[0], prescribed, 1e-12 * fabs(prescribed), "work rate, one prescribed");

    /* no particles: nothing, and no arrays needed */
    sph_particles empty = {0};
    power[0] = power[1] = 5.0;
    check(sim, sph_energy_power(sim, &empty, &none, 0, NULL, NULL, NULL, power));
    assert_true(power[0] == 0.0 && power[1] == 0.0);
    sph_destroy(sim);
}

/* A free block with artificial viscosity, its particles unstressed at
 * rho0 (no pressure, no deviator): the rate engine's accelerations are the
 * viscous ones only. */
static sph_sim *viscous_block(void)
{
    sph_sim *sim = free_block_2d(6, 5, 1e-3);
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=2"));
    check(sim, sph_run(sim, 0)); /* the neighbour list */
    for (size_t a = 0; a < sim->n; ++a) {
        sim->rho[a] = PAPER_RHO0;
        for (int c = 0; c < sim->ncomp; ++c)
            sim->S[a * sim->ncomp + c] = 0.0;
    }
    return sim;
}

/* The handle's list as rows of a caller's list: `full` each pair in both
 * rows (sph_rates_evaluate), else each pair once, in its smaller index's
 * row (sph_energy_power). */
static void caller_list(const sph_sim *sim, int full, size_t **offsets, int **indices)
{
    const size_t n = sim->n;
    size_t *off = calloc(n + 1, sizeof *off);
    int *idx = malloc((2 * neighbour_row(&sim->nl, n) + 1) * sizeof *idx);
    for (size_t a = 0; a < n; ++a) {
        off[a + 1] = off[a];
        for (size_t b = 0; b < n; ++b) {
            if (b == a || (!full && b < a))
                continue;
            int listed = 0; /* the handle lists the pair in either row */
            for (size_t k = neighbour_row(&sim->nl, a); k < neighbour_row(&sim->nl, a + 1); ++k)
                listed |= (size_t)sim->nl.indices[k] == b;
            for (size_t k = neighbour_row(&sim->nl, b); k < neighbour_row(&sim->nl, b + 1); ++k)
                listed |= (size_t)sim->nl.indices[k] == a;
            if (listed)
                idx[off[a + 1]++] = (int)b;
        }
    }
    *offsets = off;
    *indices = idx;
}

/* heat of the velocities sim->v: sph_energy_power's power[1], and the
 * kinetic energy the rate engine's accelerations take, -sum m a . v */
static void heat_of(sph_sim *sim, double *heat, double *taken)
{
    const size_t n = sim->n;
    size_t *full_off, *half_off;
    int *full_idx, *half_idx;
    caller_list(sim, 1, &full_off, &full_idx);
    caller_list(sim, 0, &half_off, &half_idx);
    const sph_particles p = {.n_local = n,
                             .n_total = n,
                             .x = sim->x,
                             .v = sim->v,
                             .rho = sim->rho,
                             .S = sim->S,
                             .mass = sim->mass,
                             .material = sim->material_of};
    double *dv = calloc(n * 2, sizeof *dv), *drho = calloc(n, sizeof *drho),
           *dS = calloc(n * sim->ncomp, sizeof *dS);
    sph_rates rates = {.dv_dt = dv, .drho_dt = drho, .dS_dt = dS};
    const sph_neighbours full = {.offsets = full_off, .indices = full_idx};
    const sph_neighbours half = {.offsets = half_off, .indices = half_idx};
    check(sim, sph_rates_evaluate(sim, &p, &full, &rates));
    double power[2];
    check(sim, sph_energy_power(sim, &p, &half, 0, dv, dv, NULL, power));
    assert_true(power[0] == 0.0); /* only SPH forces: no work */
    *heat = power[1];
    *taken = 0.0;
    for (size_t a = 0; a < n; ++a)
        for (int i = 0; i < 2; ++i)
            *taken -= sim->mass[a] * dv[a * 2 + i] * sim->v[a * 2 + i];
    free(dv);
    free(drho);
    free(dS);
    free(full_off);
    free(full_idx);
    free(half_off);
    free(half_idx);
}

static void viscous_heat_is_the_kinetic_energy_viscosity_takes(void **state_)
{
    (void)state_;
    sph_sim *sim = viscous_block();
    const size_t n = sim->n;
    double heat, taken;

    /* a rigid translation: no pair approaches, no heat */
    for (size_t a = 0; a < n; ++a) {
        sim->v[2 * a] = 3.0;
        sim->v[2 * a + 1] = -1.5;
    }
    heat_of(sim, &heat, &taken);
    assert_true(heat == 0.0);

    /* compression plus a pattern of velocities: positive, and the kinetic
     * energy the viscous accelerations take (pair terms antisymmetric) */
    for (size_t a = 0; a < n; ++a) {
        sim->v[2 * a] = -20.0 * sim->x[2 * a] + 0.3 * (double)(a % 3);
        sim->v[2 * a + 1] = -10.0 * sim->x[2 * a + 1] - 0.2 * (double)(a % 4);
    }
    heat_of(sim, &heat, &taken);
    assert_true(heat > 0.0);
    assert_close(heat, taken, 1e-9 * heat, "viscous heat vs -sum m a.v");

    /* any velocities: never negative (each approaching pair heats) */
    unsigned int seed = 7;
    for (int trial = 0; trial < 20; ++trial) {
        for (size_t a = 0; a < 2 * n; ++a) {
            seed = seed * 1103515245u + 12345u;
            sim->v[a] = ((double)(seed >> 8) / (double)(1u << 24) - 0.5) * 4.0;
        }
        heat_of(sim, &heat, &taken);
        assert_true(heat >= 0.0);
        assert_close(heat, taken, 1e-9 * fabs(taken) + 1e-18, "viscous heat, random velocities");
    }
    sph_destroy(sim);
}

static void ghost_pairs_shared_count_half(void **state_)
{
    (void)state_;
    sph_sim *sim = viscous_block();
    const size_t n = sim->n;
    for (size_t a = 0; a < n; ++a) {
        sim->v[2 * a] = -20.0 * sim->x[2 * a];
        sim->v[2 * a + 1] = -10.0 * sim->x[2 * a + 1];
    }
    size_t *off;
    int *idx;
    caller_list(sim, 0, &off, &idx);
    sph_particles p = {.n_local = n,
                       .n_total = n,
                       .x = sim->x,
                       .v = sim->v,
                       .rho = sim->rho,
                       .S = sim->S,
                       .mass = sim->mass,
                       .material = sim->material_of};
    const sph_neighbours half = {.offsets = off, .indices = idx};
    double *zero = calloc(2 * n, sizeof *zero);
    double all[2], local[2], shared[2], own[2];
    check(sim, sph_energy_power(sim, &p, &half, 0, zero, zero, NULL, all));
    /* the last particle a ghost (listed in the others' rows only, as the
     * half list puts a pair in its smaller index's row) */
    p.n_local = n - 1;
    check(sim, sph_energy_power(sim, &p, &half, 0, zero, zero, NULL, own));
    check(sim, sph_energy_power(sim, &p, &half, 1, zero, zero, NULL, shared));
    /* its pairs alone: the heat of all pairs less that of the n - 1 */
    p.n_total = n - 1;
    size_t *off_local = malloc(n * sizeof *off_local);
    int *idx_local = malloc((off[n - 1] + 1) * sizeof *idx_local);
    off_local[0] = 0;
    for (size_t a = 0; a + 1 < n; ++a) {
        off_local[a + 1] = off_local[a];
        for (size_t k = off[a]; k < off[a + 1]; ++k)
            if ((size_t)idx[k] < n - 1)
                idx_local[off_local[a + 1]++] = idx[k];
    }
    const sph_neighbours among = {.offsets = off_local, .indices = idx_local};
    check(sim, sph_energy_power(sim, &p, &among, 0, zero, zero, NULL, local));
    const double ghost = all[1] - local[1];
    assert_true(ghost > 0.0);
    assert_close(own[1], all[1], 1e-12 * all[1], "ghost pairs counted whole");
    assert_close(shared[1], local[1] + 0.5 * ghost, 1e-12 * all[1], "ghost pairs counted half");
    free(off);
    free(idx);
    free(off_local);
    free(idx_local);
    free(zero);
    sph_destroy(sim);
}

/* -------------------------------------------------- sph_energy_released */

static void released_is_the_elastic_energy_a_stage_took(void **state_)
{
    (void)state_;
    int mat;
    sph_sim *sim = external_particles_2d(&mat);
    state s = five_particles();
    double fields[N], volumetric[N];
    const double zero[NC * N] = {0.0};
    check(sim, sph_energy_fields(sim, N, s.mass, s.rho, s.S, s.material, fields));
    check(sim, sph_energy_fields(sim, N, s.mass, s.rho, zero, s.material, volumetric));

    /* a stage that changed nothing releases nothing (added to *released) */
    const double D[N] = {0.0, 0.2, 0.5, 0.0, 0.9};
    double released = 0.25;
    check(sim, sph_energy_released(sim, N, s.mass, s.material, s.rho, s.S, D, s.S, D, &released));
    assert_true(released == 0.25);
    released = 0.0;
    check(sim,
          sph_energy_released(sim, N, s.mass, s.material, s.rho, s.S, NULL, s.S, NULL, &released));
    assert_true(released == 0.0);

    /* damage 0 -> 1: in tension (particle 0) all the elastic energy, in
     * compression (particle 4) its shear part */
    const double before[N] = {0.0, 0.0, 0.0, 0.0, 0.0};
    const double after[N] = {1.0, 0.0, 0.0, 0.0, 1.0};
    check(sim, sph_energy_released(sim, N, s.mass, s.material, s.rho, s.S, before, s.S, after,
                                   &released));
    assert_close(released, fields[0] + fields[4] - volumetric[4], 1e-13 * fields[0],
                 "released by damage");
    assert_true(fields[0] > 0.0 && fields[4] - volumetric[4] > 0.0);

    /* the drucker_prager return (D unchanged): the deviator scaled by k
     * releases the shear energy's fraction 1 - k^2 */
    const double k = 0.6;
    double S_after[NC * N];
    for (int c = 0; c < NC * N; ++c)
        S_after[c] = c / NC == 3 ? k * s.S[c] : s.S[c]; /* particle 3 only */
    released = 0.0;
    check(sim, sph_energy_released(sim, N, s.mass, s.material, s.rho, s.S, NULL, S_after, NULL,
                                   &released));
    const double shear3 = fields[3] - volumetric[3];
    assert_close(released, (1.0 - k * k) * shear3, 1e-12 * shear3, "released by the return");
    /* on a damaged particle, the damaged shear energy's share */
    const double D3[N] = {0.0, 0.0, 0.0, 0.5, 0.0};
    released = 0.0;
    check(sim,
          sph_energy_released(sim, N, s.mass, s.material, s.rho, s.S, D3, S_after, D3, &released));
    assert_close(released, 0.5 * (1.0 - k * k) * shear3, 1e-12 * shear3,
                 "released by the return at D = 0.5");
    sph_destroy(sim);
}

/* -------------------------------------------------------- bad arguments */

static void bad_arguments_are_named(void **state_)
{
    (void)state_;
    int mat;
    sph_sim *sim = external_particles_2d(&mat);
    state s = five_particles();
    double e[2] = {0.0, 0.0}, power[2], released = 0.0;
    double dv[2 * N] = {0.0};
    sph_particles p = as_particles(&s, NULL);
    const sph_neighbours none = {0};

    /* sph_energy_power */
    assert_int_equal(sph_energy_power(NULL, &p, &none, 0, dv, dv, NULL, power), SPH_ERR_ARGUMENT);
    refused(sim, sph_energy_power(sim, NULL, &none, 0, dv, dv, NULL, power),
            "sph_energy_power: particles is NULL");
    refused(sim, sph_energy_power(sim, &p, NULL, 0, dv, dv, NULL, power),
            "sph_energy_power: neighbours is NULL");
    refused(sim, sph_energy_power(sim, &p, &none, 0, dv, dv, NULL, NULL),
            "sph_energy_power: power is NULL");
    refused(sim, sph_energy_power(sim, &p, &none, 0, NULL, dv, NULL, power),
            "dv_sph and dv_dt must not be NULL");
    p.n_total = 3; /* fewer particles than the local ones */
    refused(sim, sph_energy_power(sim, &p, &none, 0, dv, dv, NULL, power),
            "n_local=5 is more than n_total=3");
    p.n_total = N;
    s.material[4] = 2;
    refused(sim, sph_energy_power(sim, &p, &none, 0, dv, dv, NULL, power),
            "particle 4 has material 2, but 1 materials are defined");
    s.material[4] = 0;
    /* with viscosity: positions, densities and rows needed, indices checked */
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0"));
    refused(sim, sph_energy_power(sim, &p, &none, 0, dv, dv, NULL, power), "particles->x is NULL");
    double x[3 * N] = {0.0};
    for (int a = 0; a < N; ++a)
        x[3 * a] = 1e-3 * a;
    p.x = x;
    refused(sim, sph_energy_power(sim, &p, &none, 0, dv, dv, NULL, power),
            "give neighbours as offsets+indices or lists+counts");
    const size_t off[N + 1] = {0, 1, 1, 1, 1, 1};
    const int idx[1] = {7};
    const sph_neighbours bad = {.offsets = off, .indices = idx};
    refused(sim, sph_energy_power(sim, &p, &bad, 0, dv, dv, NULL, power),
            "neighbour 7 of particle 0 is not below n_total=5");

    /* sph_energy_sums */
    assert_int_equal(
        sph_energy_sums(NULL, N, s.mass, s.v, 3, s.rho, s.S, NULL, s.material, NULL, e),
        SPH_ERR_ARGUMENT);
    refused(sim, sph_energy_sums(sim, N, s.mass, s.v, 3, s.rho, s.S, NULL, s.material, NULL, NULL),
            "sph_energy_sums: energy is NULL");
    refused(sim, sph_energy_sums(sim, N, s.mass, NULL, 3, s.rho, s.S, NULL, s.material, NULL, e),
            "sph_energy_sums: mass, v, rho, S and material must not be NULL");
    s.rho[2] = 0.0;
    refused(sim, sph_energy_sums(sim, N, s.mass, s.v, 3, s.rho, s.S, NULL, s.material, NULL, e),
            "particle 2 has density 0");
    s.rho[2] = PAPER_RHO0;
    s.material[1] = -1;
    refused(sim, sph_energy_sums(sim, N, s.mass, s.v, 3, s.rho, s.S, NULL, s.material, NULL, e),
            "particle 1 has material -1");
    s.material[1] = 0;
    assert_true(e[0] == 0.0 && e[1] == 0.0); /* refused calls add nothing */

    /* sph_energy_released */
    const double D[N] = {0.0};
    assert_int_equal(
        sph_energy_released(NULL, N, s.mass, s.material, s.rho, s.S, D, s.S, D, &released),
        SPH_ERR_ARGUMENT);
    refused(sim, sph_energy_released(sim, N, s.mass, s.material, s.rho, s.S, D, s.S, D, NULL),
            "sph_energy_released: released is NULL");
    refused(sim, sph_energy_released(sim, N, s.mass, s.material, s.rho, NULL, D, s.S, D, &released),
            "mass, rho, S_before, S and material must not be NULL");
    refused(sim,
            sph_energy_released(sim, N, s.mass, s.material, s.rho, s.S, D, s.S, NULL, &released),
            "give both damage_before and damage, or neither");
    s.material[0] = 1;
    refused(sim, sph_energy_released(sim, N, s.mass, s.material, s.rho, s.S, D, s.S, D, &released),
            "particle 0 has material 1");
    assert_true(released == 0.0);
    sph_destroy(sim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sums_are_kinetic_and_elastic_energy),
        cmocka_unit_test(power_of_a_uniform_acceleration),
        cmocka_unit_test(viscous_heat_is_the_kinetic_energy_viscosity_takes),
        cmocka_unit_test(ghost_pairs_shared_count_half),
        cmocka_unit_test(released_is_the_elastic_energy_a_stage_took),
        cmocka_unit_test(bad_arguments_are_named),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
