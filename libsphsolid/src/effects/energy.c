/*
 * Energy: the totals of a simulation's own bodies (sph_energy) and the
 * per-particle elastic energy of external particles (sph_energy_fields, the
 * LAMMPS plugin's compute sphsolid/energy/atom), both from the one
 * elastic_energy_per_mass(); and the energy account
 * (sph_set_energy_account): the work done on the particles by prescribed
 * motions and applied forces and the energy dissipated by damage, the
 * drucker_prager return and artificial viscosity, integrated over the
 * rate evaluations of each step.  The same account's pieces on a caller's
 * particles (sph_energy_power, sph_energy_sums, sph_energy_released: the
 * LAMMPS plugin's energy_account and compute sphsolid/energy) come from the
 * same per-pair and per-particle terms.
 */
#include <math.h>
#include <string.h>

#include "effects/effects.h"
#include "physics/kernel.h"
#include "physics/physics.h"
#include "core/sim.h"

/* The elastic energy per mass of a particle damaged by D (damage.h): the
 * energy whose rate is the power of the damaged stress, (1 - D) times the
 * shear part and, in tension (rho < rho0, P < 0), the volumetric part. */
static double damaged_energy_per_mass(int dim, const material *m, double rho, const double *S,
                                      double D)
{
    const double keep = 1.0 - D;
    double u = m->c0_squared * (log(rho / m->rho0) + m->rho0 / rho - 1.0);
    if (rho < m->rho0)
        u *= keep;
    if (m->mu > 0.0)
        u += keep * stress_double_dot(dim, S) / (4.0 * m->mu * rho);
    return u;
}

double energy_damage_released(const sph_sim *sim, size_t a, double D_before, double D_after)
{
    const material *m = &sim->materials[sim->material_of[a]];
    const double *S = sim->S + a * (size_t)sim->ncomp;
    return sim->mass[a] * (damaged_energy_per_mass(sim->dim, m, sim->rho[a], S, D_before) -
                           damaged_energy_per_mass(sim->dim, m, sim->rho[a], S, D_after));
}

/* The heat rate of one approaching pair (v_dot_r < 0) under artificial
 * viscosity: m_a m_b Pi_ab v_ab . grad_a W_ab (Monaghan 1992: the thermal
 * energy equation's viscous term), f_norm the kernel's sigma / h^(dim+2). */
static double viscous_heat_pair(const sph_sim *sim, double f_norm, double inv_h, double r2,
                                double v_dot_r, const material *ma, const material *mb,
                                double rho_a, double rho_b, double mass_a, double mass_b)
{
    const double F = kernel_f(sim->kernel, sim->dim, sqrt(r2) * inv_h) * f_norm;
    const double c = 0.5 * (ma->c0 + mb->c0);
    const double Pi =
        viscosity_pair(sim->fx.artificial_viscosity_alpha, sim->fx.artificial_viscosity_beta,
                       sim->h, v_dot_r, r2, c, 0.5 * (rho_a + rho_b));
    return mass_a * mass_b * Pi * F * v_dot_r;
}

/* The rate at which artificial viscosity turns kinetic energy into heat:
 * the sum of viscous_heat_pair over pairs, each pair once. */
static double viscous_dissipation_rate(const sph_sim *sim)
{
    const int dim = sim->dim;
    const double h = sim->h, inv_h = 1.0 / h;
    const double f_norm = kernel_sigma(sim->kernel, dim) / pow(h, dim + 2);
    const long n = (long)sim->n;
    double rate = 0.0;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(+ : rate)
    for (long a = 0; a < n; ++a) {
        const size_t end = neighbour_row(&sim->nl, (size_t)a + 1);
        const material *ma = &sim->materials[sim->material_of[a]];
        for (size_t k = neighbour_row(&sim->nl, (size_t)a); k < end; ++k) {
            const size_t b = (size_t)sim->nl.indices[k];
            if (b <= (size_t)a) /* each pair once: the row of its first particle */
                continue;
            double r2 = 0.0, v_dot_r = 0.0;
            for (int i = 0; i < dim; ++i) {
                double d = sim->x[a * dim + i] - sim->x[b * dim + i];
                if (sim->has_domain && sim->periodic[i])
                    d = nearest_image(d, sim->hi[i] - sim->lo[i], 0.5 * (sim->hi[i] - sim->lo[i]));
                r2 += d * d;
                v_dot_r += d * (sim->v[a * dim + i] - sim->v[b * dim + i]);
            }
            if (!(v_dot_r < 0.0))
                continue;
            rate += viscous_heat_pair(sim, f_norm, inv_h, r2, v_dot_r, ma,
                                      &sim->materials[sim->material_of[b]], sim->rho[a],
                                      sim->rho[b], sim->mass[a], sim->mass[b]);
        }
    }
    return rate;
}

void energy_account_evaluation(sph_sim *sim)
{
    const int dim = sim->dim;
    double power = 0.0;
    for (int k = 0; k < sim->n_bodies; ++k) {
        const body *b = &sim->bodies[k];
        if (b->motion == SPH_MOTION_FREE)
            continue;
        if (b->motion == SPH_MOTION_FORCE) { /* the applied force on the rigid body */
            if (b->count > 0)
                for (int i = 0; i < dim; ++i)
                    power += b->vector[i] * sim->v[b->first * dim + i];
            continue;
        }
        /* a prescribed motion overrides the SPH force on its particles: it
         * does work -m a . v on each */
        for (size_t a = b->first; a < b->first + b->count; ++a)
            for (int i = 0; i < dim; ++i)
                power -= sim->mass[a] * sim->dv_dt[a * dim + i] * sim->v[a * dim + i];
    }
    const double heat = sim->fx.artificial_viscosity ? viscous_dissipation_rate(sim) : 0.0;
    sim->power_sum[0] += power;
    sim->power_sum[1] += heat;
    sim->power_evals++;
    /* the powers of the rates the next step may start from */
    sim->power_carry[0] = power;
    sim->power_carry[1] = heat;
    sim->power_carry_valid = 1;
}

void energy_account_open(sph_sim *sim, int carried)
{
    sim->power_sum[0] = sim->power_sum[1] = 0.0;
    sim->power_evals = 0;
    if (carried && sim->power_carry_valid) {
        sim->power_sum[0] = sim->power_carry[0];
        sim->power_sum[1] = sim->power_carry[1];
        sim->power_evals = 1;
    }
}

void energy_account_step(sph_sim *sim, double dt)
{
    if (sim->power_evals > 0) {
        for (int k = 0; k < 2; ++k) {
            sim->power_last[k] = sim->power_sum[k] / sim->power_evals;
            sim->power_sum[k] = 0.0;
        }
        sim->power_evals = 0;
    }
    /* the trapezoid of the step's evaluations: Improved Euler's two
     * stages; the leapfrog's start powers (carried from the last step's
     * momentum pass, or of the rates evaluated again at its start) and its
     * momentum pass */
    sim->work_boundary += dt * sim->power_last[0];
    sim->dissipated_viscosity += dt * sim->power_last[1];
}

sph_status sph_set_energy_account(sph_sim *sim, int on)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    sim->energy_account = on != 0;
    sim->work_boundary = sim->dissipated_damage = 0.0;
    sim->dissipated_plastic = sim->dissipated_viscosity = 0.0;
    sim->power_sum[0] = sim->power_sum[1] = sim->power_last[0] = sim->power_last[1] = 0.0;
    sim->power_evals = 0;
    sim->power_carry_valid = 0; /* evaluations while off left no powers */
    sim->rates_valid = 0;       /* the next step evaluates its rates, and their power */
    return sph_ok(sim);
}

int sph_energy_account(const sph_sim *sim) { return sim ? sim->energy_account : 0; }

sph_status sph_energy_fields(sph_sim *sim, size_t n, const double *mass, const double *rho,
                             const double *S, const int *material_of, double *energy)
{
    const void *const arrays[] = {mass, rho, S, material_of, energy};
    sph_status st = caller_arrays(sim, "sph_energy_fields", n, material_of,
                                  "mass, rho, S, material and energy", arrays, 5);
    if (st)
        return st;
    const int dim = sim->dim, nc = sim->ncomp;
    for (size_t a = 0; a < n; ++a) {
        const material *m = &sim->materials[material_of[a]];
        if (!(rho[a] > 0.0))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "sph_energy_fields: particle %zu has density %g (must be > 0)", a,
                            rho[a]);
        energy[a] = mass[a] * elastic_energy_per_mass(dim, m->c0_squared, m->rho0, m->mu, rho[a],
                                                      S + (size_t)a * nc);
    }
    return SPH_OK;
}

sph_status sph_energy(sph_sim *sim, int all_bodies, sph_energy_info *info)
{
    sph_status st = sph_need(sim, info, "sph_energy", "info");
    if (st)
        return st;
    memset(info, 0, sizeof *info);
    const int dim = sim->dim;
    for (size_t a = 0; a < sim->n; ++a) {
        const body *b = &sim->bodies[sim->body_of[a]];
        if (!all_bodies && b->motion != SPH_MOTION_FREE && b->motion != SPH_MOTION_FORCE)
            continue;
        const material *m = &sim->materials[sim->material_of[a]];
        double v2 = 0.0;
        for (int i = 0; i < dim; ++i) {
            v2 += sim->v[a * dim + i] * sim->v[a * dim + i];
            info->momentum[i] += sim->mass[a] * sim->v[a * dim + i];
        }
        info->kinetic += 0.5 * sim->mass[a] * v2;
        const double *S = sim->S + a * sim->ncomp;
        info->elastic +=
            sim->mass[a] *
            (sim->damage
                 ? damaged_energy_per_mass(dim, m, sim->rho[a], S, sim->damage[a])
                 : elastic_energy_per_mass(dim, m->c0_squared, m->rho0, m->mu, sim->rho[a], S));
    }
    info->work = sim->work_boundary;
    info->dissipated_damage = sim->dissipated_damage;
    info->dissipated_plastic = sim->dissipated_plastic;
    info->dissipated_viscosity = sim->dissipated_viscosity;
    return sph_ok(sim);
}

/* ------------------------------------------- particles of another code */

sph_status sph_energy_power(sph_sim *sim, const sph_particles *particles,
                            const sph_neighbours *neighbours, int shared_ghost_pairs,
                            const double *dv_sph, const double *dv_dt,
                            const unsigned char *integrate_motion, double *power)
{
    const char *fn = "sph_energy_power";
    sph_status st = caller_pairs(sim, fn, particles, neighbours, power, "power");
    if (st)
        return st;
    power[0] = power[1] = 0.0;
    const size_t n = particles->n_total, n_local = particles->n_local;
    if (n_local == 0)
        return sph_ok(sim);
    if (n_local > n)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: n_local=%zu is more than n_total=%zu", fn,
                        n_local, n);
    const int viscous = sim->fx.artificial_viscosity;
    const void *const arrays[] = {particles->v, particles->mass, particles->material, dv_sph,
                                  dv_dt};
    if ((st = caller_arrays(sim, fn, n_local, particles->material,
                            "particles->v, mass and material, dv_sph and dv_dt", arrays, 5)))
        return st;
    const int by_rows = neighbours->offsets && neighbours->indices;
    if (viscous) {
        if ((st = sph_need(sim, particles->x, fn, "particles->x")) ||
            (st = sph_need(sim, particles->rho, fn, "particles->rho")))
            return st;
        if (!by_rows && !(neighbours->lists && neighbours->counts))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "%s: give neighbours as offsets+indices or lists+counts", fn);
        if (!(sim->h > 0.0))
            return sph_fail(sim, SPH_ERR_STATE,
                            "%s: the smoothing length is not set (sph_set_spacing)", fn);
    }
    const int dim = sim->dim;
    const size_t stride = particles->stride ? particles->stride : (size_t)dim;
    const double *x = particles->x, *v = particles->v, *mass = particles->mass;
    const int *mat = particles->material;

    /* the work rate of what is not an SPH force among the particles: an
     * integrated particle moves with dv_dt, which holds more than its SPH
     * rate (a rigid body's share of its applied force, gravity); a
     * prescribed one does not accelerate: its motion does -m dv_sph . v */
    double work = 0.0;
    for (size_t a = 0; a < n_local; ++a) {
        const int integrate = integrate_motion ? integrate_motion[a] : 1;
        double p = 0.0;
        for (int i = 0; i < dim; ++i)
            p += ((integrate ? dv_dt[a * dim + i] : 0.0) - dv_sph[a * dim + i]) * v[a * stride + i];
        work += mass[a] * p;
    }
    power[0] = work;
    if (!viscous)
        return sph_ok(sim);

    /* the viscous heat over the listed pairs: each pair once, a pair with a
     * ghost that its other process lists too counted half here */
    const double h = sim->h, inv_h = 1.0 / h;
    const double f_norm = kernel_sigma(sim->kernel, dim) / pow(h, dim + 2);
    const double *rho = particles->rho;
    const long count = (long)n_local;
    double heat = 0.0;
    long bad_a = -1, bad_b = -1;
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim)) reduction(+ : heat) \
    reduction(max : bad_a, bad_b)
    for (long a = 0; a < count; ++a) {
        size_t length;
        const int *row = caller_row(neighbours, by_rows, (size_t)a, &length);
        const material *ma = &sim->materials[mat[a]];
        for (size_t k = 0; k < length; ++k) {
            const size_t b = (size_t)row[k];
            if (b >= n || mat[b] < 0 || mat[b] >= sim->n_materials) {
                bad_a = a;
                bad_b = (long)b;
                continue;
            }
            double r2 = 0.0, v_dot_r = 0.0;
            for (int i = 0; i < dim; ++i) {
                const double d = x[a * stride + i] - x[b * stride + i];
                r2 += d * d;
                v_dot_r += d * (v[a * stride + i] - v[b * stride + i]);
            }
            if (!(v_dot_r < 0.0))
                continue;
            const double q =
                viscous_heat_pair(sim, f_norm, inv_h, r2, v_dot_r, ma, &sim->materials[mat[b]],
                                  rho[a], rho[b], mass[a], mass[b]);
            heat += shared_ghost_pairs && b >= n_local ? 0.5 * q : q;
        }
    }
    if (bad_a >= 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "%s: neighbour %ld of particle %ld is not below n_total=%zu or has no "
                        "material",
                        fn, bad_b, bad_a, n);
    power[1] = heat;
    return sph_ok(sim);
}

sph_status sph_energy_sums(sph_sim *sim, size_t n, const double *mass, const double *v,
                           size_t stride, const double *rho, const double *S, const double *damage,
                           const int *material_of, const unsigned char *member, double *energy)
{
    const char *fn = "sph_energy_sums";
    sph_status st = sph_need(sim, energy, fn, "energy");
    if (st)
        return st;
    const void *const arrays[] = {mass, v, rho, S, material_of};
    if ((st = caller_arrays(sim, fn, n, material_of, "mass, v, rho, S and material", arrays, 5)))
        return st;
    const int dim = sim->dim, nc = sim->ncomp;
    const size_t vs = stride ? stride : (size_t)dim;
    double kinetic = 0.0, elastic = 0.0;
    for (size_t a = 0; a < n; ++a) {
        if (member && !member[a])
            continue;
        if (!(rho[a] > 0.0))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: particle %zu has density %g (must be > 0)",
                            fn, a, rho[a]);
        const material *m = &sim->materials[material_of[a]];
        double v2 = 0.0;
        for (int i = 0; i < dim; ++i)
            v2 += v[a * vs + i] * v[a * vs + i];
        kinetic += 0.5 * mass[a] * v2;
        const double *Sa = S + a * (size_t)nc;
        elastic += mass[a] * (damage ? damaged_energy_per_mass(dim, m, rho[a], Sa, damage[a])
                                     : elastic_energy_per_mass(dim, m->c0_squared, m->rho0, m->mu,
                                                               rho[a], Sa));
    }
    energy[0] += kinetic;
    energy[1] += elastic;
    return sph_ok(sim);
}

sph_status sph_energy_released(sph_sim *sim, size_t n, const double *mass, const int *material_of,
                               const double *rho, const double *S_before,
                               const double *damage_before, const double *S, const double *damage,
                               double *released)
{
    const char *fn = "sph_energy_released";
    sph_status st = sph_need(sim, released, fn, "released");
    if (st)
        return st;
    const void *const arrays[] = {mass, rho, S_before, S, material_of};
    if ((st = caller_arrays(sim, fn, n, material_of, "mass, rho, S_before, S and material", arrays,
                            5)))
        return st;
    if (n > 0 && !damage_before != !damage)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s: give both damage_before and damage, or neither",
                        fn);
    const int dim = sim->dim, nc = sim->ncomp;
    double total = 0.0;
    for (size_t a = 0; a < n; ++a) {
        const double *Sb = S_before + a * (size_t)nc, *Sa = S + a * (size_t)nc;
        const double Db = damage ? damage_before[a] : 0.0, Da = damage ? damage[a] : 0.0;
        int same = Db == Da;
        for (int c = 0; c < nc && same; ++c)
            same = Sb[c] == Sa[c];
        if (same) /* the stage left the particle alone */
            continue;
        const material *m = &sim->materials[material_of[a]];
        total += mass[a] * (damaged_energy_per_mass(dim, m, rho[a], Sb, Db) -
                            damaged_energy_per_mass(dim, m, rho[a], Sa, Da));
    }
    *released += total;
    return sph_ok(sim);
}
