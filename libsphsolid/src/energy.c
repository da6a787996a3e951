/*
 * Energy: the totals of a simulation's own bodies (sph_energy) and the
 * per-particle elastic energy of external particles (sph_energy_fields, the
 * LAMMPS plugin's compute sphsolid/energy/atom), both from the one
 * elastic_energy_per_mass(); and the energy account
 * (sph_set_energy_account): the work done on the particles by prescribed
 * motions and applied forces and the energy dissipated by damage, the
 * drucker_prager return and artificial viscosity, integrated over the
 * rate evaluations of each step.
 */
#include <math.h>
#include <string.h>

#include "effects.h"
#include "kernel.h"
#include "physics.h"
#include "sim.h"

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

/* The rate at which artificial viscosity turns kinetic energy into heat:
 * sum over pairs of m_a m_b Pi_ab v_ab . grad_a W_ab (Monaghan 1992: the
 * thermal energy equation's viscous term), each pair once. */
static double viscous_dissipation_rate(const sph_sim *sim)
{
    const int dim = sim->dim, kernel = sim->kernel;
    const double h = sim->h, inv_h = 1.0 / h;
    const double f_norm = kernel_sigma(kernel, dim) / pow(h, dim + 2);
    const double alpha = sim->fx.artificial_viscosity_alpha;
    const double beta = sim->fx.artificial_viscosity_beta;
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
            const double F = kernel_f(kernel, dim, sqrt(r2) * inv_h) * f_norm;
            const double c = 0.5 * (ma->c0 + sim->materials[sim->material_of[b]].c0);
            const double Pi =
                viscosity_pair(alpha, beta, h, v_dot_r, r2, c, 0.5 * (sim->rho[a] + sim->rho[b]));
            rate += sim->mass[a] * sim->mass[b] * Pi * F * v_dot_r;
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
    sim->power_sum[0] += power;
    if (sim->fx.artificial_viscosity)
        sim->power_sum[1] += viscous_dissipation_rate(sim);
    sim->power_evals++;
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
    /* the trapezoid of the step's evaluations (Improved Euler: its two
     * stages; rates carried from the last step: their power) */
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
    sim->rates_valid = 0; /* the next step evaluates its rates, and their power */
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
