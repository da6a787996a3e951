/*
 * sphsolid/fields.h - fields and probes: the particles' state and derived quantities.
 * Part of the public API of libsphsolid: include <sphsolid.h>, which
 * includes every part in order (its conventions hold for all).
 */
#ifndef SPHSOLID_PUBLIC_FIELDS_H
#define SPHSOLID_PUBLIC_FIELDS_H

#include "sphsolid/integrators.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------- fields */

typedef enum sph_field_id {
    SPH_FIELD_POSITION = 0,          /* n x dim   (state, writable) */
    SPH_FIELD_VELOCITY = 1,          /* n x dim   (state, writable) */
    SPH_FIELD_DENSITY = 2,           /* n         (state, writable) */
    SPH_FIELD_DEVIATORIC_STRESS = 3, /* n x ncomp (state, writable) */
    SPH_FIELD_MASS = 4,              /* n         (writable) */
    SPH_FIELD_PRESSURE = 5,          /* n         (derived) */
    SPH_FIELD_VON_MISES = 6,         /* n         (derived) */
    SPH_FIELD_STRESS = 7,            /* n x ncomp full Cauchy sigma (derived) */
    SPH_FIELD_ACCELERATION = 8,      /* n x dim   (derived: dv/dt at the current
                                        state, the integrator's if it has
                                        them, else evaluated on demand) */
    /* effect damage (an error while it is off): */
    SPH_FIELD_DAMAGE = 9,       /* n  damage D in [0, 1] (state, writable) */
    SPH_FIELD_FRAGMENT = 10,    /* n  fragment id: connected regions of
                                   free-body particles with D < 1 within the
                                   kernel support, numbered 0.. in particle
                                   order; -1 for D = 1 and other bodies */
    SPH_FIELD_FLAWS = 11,       /* n  number of flaws of each particle */
    SPH_FIELD_FLAW_STRAIN = 12, /* n  its weakest activation strain (inf
                                   without flaws) */
    SPH_FIELD_ACTIVE_FLAWS = 13 /* n  flaws active at its current largest
                                   principal strain */
} sph_field_id;

/* Pointer to stored state (fields 0..4), with its shape. */
SPH_API sph_status sph_field(sph_sim *sim, sph_field_id field, double **data, size_t *rows,
                             size_t *cols);
/* Copy any field (stored or derived) into `out` (rows*cols doubles). */
SPH_API sph_status sph_field_copy(sph_sim *sim, sph_field_id field, double *out);
/* Body index of each particle (n ints). */
SPH_API sph_status sph_body_ids(sph_sim *sim, int *out);

/* von Mises stress of one full 3D Cauchy stress from deviatoric stress:
 * sqrt(3/2 S:S). */
SPH_API double sph_von_mises(int dimension, const double *S);

typedef struct sph_energy_info {
    double kinetic;     /* sum m v^2 / 2 */
    double elastic;     /* sum m (u_vol(rho) + S:S/(4 mu rho)); with effect damage the
                           energy of the damaged stress: (1 - D) times the shear part
                           and, in tension (rho < rho0), the volumetric part */
    double momentum[3]; /* sum m v */
    /* the energy account (sph_set_energy_account; 0 while it is off), over
     * all bodies, since it was switched on: */
    double work;                 /* done on the particles by prescribed motions (-m a.v of
                                    the SPH force each overrides) and applied forces */
    double dissipated_damage;    /* elastic energy released as damage grew */
    double dissipated_plastic;   /* removed by the drucker_prager return */
    double dissipated_viscosity; /* turned into heat by artificial viscosity */
} sph_energy_info;

/* Energy and momentum of the free bodies (or of all bodies if
 * `all_bodies` is non-zero), and the energy account's totals.  With the
 * account on and no gravity or damping, an undamped run keeps
 *   kinetic + elastic + dissipated_* - work
 * of all bodies at its value when the account was switched on, up to the
 * discretisation's own error (docs/fracture.md). */
SPH_API sph_status sph_energy(sph_sim *sim, int all_bodies, sph_energy_info *info);
/* on != 0: switch the energy account on (its totals start from 0; a pass
 * over the pairs per rate evaluation with artificial viscosity on, a pass
 * over the prescribed particles without); 0: off, nothing is computed.
 * The powers of each step's rate evaluations are integrated as a trapezoid
 * (Improved Euler: its two stages; the leapfrog: the powers of the rates
 * the step starts from, kept from the last step, and of its momentum
 * pass).  The totals are not written to checkpoints; the leapfrog's kept
 * powers are, with its rates, so a resumed run integrates as one run. */
SPH_API sph_status sph_set_energy_account(sph_sim *sim, int on);
SPH_API int sph_energy_account(const sph_sim *sim);

/* Bytes of memory the handle holds (particle state, integrator and rate
 * scratch, neighbour list), for budgeting large runs. */
SPH_API size_t sph_memory_bytes(const sph_sim *sim);
/* SPH_ERR_MEMORY, naming the particle count and the bytes needed and
 * available, when a run with `particles` more particles (at the handle's
 * smoothing ratio) would take more than half of the memory available, or
 * with sph_set_allow_large(sim, 1) more than all of it.  Every builder
 * (blocks, prisms, cylinders, platens, sph_add_particles) calls it with the
 * count it is about to add, before allocating anything. */
SPH_API sph_status sph_memory_check(sph_sim *sim, double particles);
/* allow != 0: runs may take up to all of the memory available instead of
 * half of it (the limit of sph_memory_check and of the builders). */
SPH_API sph_status sph_set_allow_large(sph_sim *sim, int allow);
SPH_API int sph_allow_large(const sph_sim *sim);
/* The same bytes by part: fills up to `max` entries of names (static
 * strings, valid for the life of the program) and bytes, and returns the
 * number of parts (SPH_MEMORY_PARTS); their sum is sph_memory_bytes().
 * Parts: particle state, integrator saved state, rates, pair data (per
 * particle factors of the pair terms; a caller's strided positions and
 * velocities copied dim apart), pair sums (scratch of the pair
 * pass), neighbour list, model (handle, materials, bodies, probes). */
#define SPH_MEMORY_PARTS 7
SPH_API int sph_memory_parts(const sph_sim *sim, const char **names, size_t *bytes, int max);

/* ---------------------------------------------------------------- probes */

/* Number of values one probe reports: von Mises, pressure, then the full
 * Cauchy stress components in the order of the deviatoric stress. */
#define SPH_PROBE_VALUES(dim) (2 + SPH_STRESS_COMPONENTS(dim))

SPH_API sph_status sph_add_probe(sph_sim *sim, const char *name, const double *point, int *probe);
SPH_API int sph_probe_count(const sph_sim *sim);
SPH_API const char *sph_probe_name(const sph_sim *sim, int probe);
/* Shepard-normalised kernel interpolation at the probe point:
 *   A(p) = sum_b V_b A_b W(p - r_b) / sum_b V_b W(p - r_b),  V_b = m_b/rho_b.
 * `values` receives SPH_PROBE_VALUES(dim) doubles.  A point with no particle
 * within 2h (outside every body) is an error by default: SPH_ERR_DOMAIN
 * naming the probe and its point, values set to NaN; the same holds for the
 * probe samples an output file records during a run (the run stops) and
 * for sph_probe_finish().  sph_set_probe_outside(sim, SPH_PROBE_OUTSIDE_NAN)
 * makes such samples NaN with status SPH_OK instead. */
SPH_API sph_status sph_probe_sample(sph_sim *sim, int probe, double *values);

typedef enum sph_probe_outside {
    SPH_PROBE_OUTSIDE_ERROR = 0, /* default */
    SPH_PROBE_OUTSIDE_NAN = 1
} sph_probe_outside;
SPH_API sph_status sph_set_probe_outside(sph_sim *sim, sph_probe_outside mode);

#ifdef __cplusplus
}
#endif

#endif /* SPHSOLID_PUBLIC_FIELDS_H */
