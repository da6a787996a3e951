/*
 * sphsolid.h - SPH for elastic solids (public API of libsphsolid).
 *
 * The model is the one of Das & Cleary, "Uniaxial compression test and
 * stress wave propagation modelling using SPH" (eqs 1-10), with the
 * symmetric momentum equation of Gray, Monaghan & Swift (2001):
 *
 *   drho_a/dt = sum_b m_b v_ab . grad_a W_ab                      (eq. 3)
 *   dv_a/dt   = sum_b m_b (sigma_a/rho_a^2 + sigma_b/rho_b^2) . grad_a W_ab + g
 *   dS/dt     = 2 mu (eps_dot - tr(eps_dot)/3 I) + S Omega^T + Omega S   (eq. 6)
 *   P         = c0^2 (rho - rho0),  c0^2 = K / rho0                 (eq. 9)
 *
 * integrated by Improved Euler (Heun).  SI units throughout.
 *
 * Conventions
 *  - Every function returns an sph_status; SPH_OK is zero.  On failure the
 *    handle keeps a message naming the bad value: sph_errmsg().
 *  - The library never prints and never exits.
 *  - Particle data are structures of arrays owned by the handle:
 *    positions and velocities hold `dim` doubles per particle, the deviatoric
 *    stress SPH_STRESS_COMPONENTS(dim) doubles per particle in the order
 *    (xx, yy, zz, xy) in 2D and (xx, yy, zz, xy, xz, yz) in 3D.  In 2D the
 *    model is plane strain: eps_dot_zz = 0 while S_zz evolves.
 *  - A function taking `const sph_sim *` only reads the handle and never
 *    sets its message; every call that can fail takes `sph_sim *`.
 *  - Lifetime of returned pointers:
 *      sph_field():                    until a body is added or the handle
 *                                      is destroyed;
 *      sph_errmsg():                   until the next call on the handle;
 *      sph_body_info_get() name:       until a body is added or the handle
 *                                      is destroyed;
 *      sph_probe_name():               until a probe is added or the handle
 *                                      is destroyed;
 *      sph_failure() quantity, sph_status_name(), sph_version(),
 *      sph_effect_names() and every other name the library returns:
 *                                      static, valid for the whole program.
 */
#ifndef SPHSOLID_H
#define SPHSOLID_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(SPHSOLID_BUILDING) && defined(__GNUC__)
#define SPH_API __attribute__((visibility("default")))
#else
#define SPH_API
#endif
/* Marks a deprecated alias: compilers warn where it is used. */
#if defined(__GNUC__) || defined(__clang__)
#define SPH_DEPRECATED(replacement) __attribute__((deprecated("use " replacement)))
#else
#define SPH_DEPRECATED(replacement)
#endif

/* SPHSOLID_VERSION_MAJOR/_MINOR/_PATCH and SPHSOLID_VERSION_STRING, as
 * sph_version() reports them. */
#include "sphsolid_version.h"

/* Number of stored deviatoric stress components per particle. */
#define SPH_STRESS_COMPONENTS(dim) ((dim) == 2 ? 4 : 6)

typedef enum sph_status {
    SPH_OK = 0,
    SPH_ERR_ARGUMENT = 1,    /* a bad value was passed; the message names it */
    SPH_ERR_MEMORY = 2,      /* allocation failed */
    SPH_ERR_STATE = 3,       /* call not valid in the current state */
    SPH_ERR_IO = 4,          /* file could not be read or written */
    SPH_ERR_NONFINITE = 5,   /* the run produced a non-finite value */
    SPH_ERR_UNSUPPORTED = 6, /* feature not compiled in (e.g. HDF5) */
    SPH_ERR_STOPPED = 7,     /* a progress callback asked the run to stop */
    SPH_ERR_DOMAIN = 8,      /* a particle left the domain */
    SPH_ERR_UNSTABLE = 9     /* the watchdog saw a runaway speed or density */
} sph_status;

typedef struct sph_sim sph_sim;

/* ---------------------------------------------------------------- handle */

/* Create a simulation in `dimension` (2 or 3) dimensions.  On a bad
 * dimension *sim still receives a handle that carries the message (like
 * sqlite3_open); destroy it with sph_destroy().  *sim is NULL only when
 * memory ran out. */
SPH_API sph_status sph_create(int dimension, sph_sim **sim);
SPH_API void sph_destroy(sph_sim *sim);

/* Message for the last failed call on this handle ("" after success). */
SPH_API const char *sph_errmsg(const sph_sim *sim);
/* Static name of a status code. */
SPH_API const char *sph_status_name(sph_status status);
/* The version and the compiled-in options, e.g. "0.2.0 openmp hdf5". */
SPH_API const char *sph_version(void);

SPH_API int sph_dimension(const sph_sim *sim);

/* Number of OpenMP threads used by this handle (0 = OpenMP default).
 * Results do not depend on it. */
SPH_API sph_status sph_set_threads(sph_sim *sim, int threads);

/* ------------------------------------------------------------- materials */

/* Linear elastic material; any consistent pair defines it.  rho0 is the
 * reference density [kg/m^3], moduli in Pa.  K > 0, mu >= 0,
 * -1 < nu < 0.5.  *material receives the material index. */
SPH_API sph_status sph_add_material_K_mu(sph_sim *sim, double bulk_modulus, double shear_modulus,
                                         double rho0, int *material);
SPH_API sph_status sph_add_material_E_nu(sph_sim *sim, double youngs_modulus, double poisson_ratio,
                                         double rho0, int *material);
SPH_API sph_status sph_add_material_K_nu(sph_sim *sim, double bulk_modulus, double poisson_ratio,
                                         double rho0, int *material);

typedef struct sph_material_info {
    double bulk_modulus;   /* K [Pa] */
    double shear_modulus;  /* mu [Pa] */
    double rho0;           /* reference density [kg/m^3] */
    double poisson_ratio;  /* (3K - 2mu) / (2 (3K + mu)) */
    double youngs_modulus; /* 9 K mu / (3 K + mu) */
    double c0;             /* bulk sound speed sqrt(K/rho0) [m/s] */
    double c_p;            /* plane/3D P-wave speed sqrt((K + 4mu/3)/rho0) */
    double weibull_k;      /* flaws per volume [m^-3] (effect damage) */
    double weibull_m;      /* Weibull exponent (effect damage) */
} sph_material_info;

SPH_API sph_status sph_material_info_get(sph_sim *sim, int material, sph_material_info *info);

/* Set a material key: "weibull_k" [m^-3] and "weibull_m" [-], the Weibull
 * flaw law n(eps) = k V eps^m of the effect damage (0, the default: no
 * flaws, the material is not damaged).  Values finite and >= 0. */
SPH_API sph_status sph_material_set(sph_sim *sim, int material, const char *key, double value);

/* Effect damage: the number of flaws of all particles that a uniform
 * largest principal strain `strain` would activate (a check of the draw,
 * whose expectation is sum_a k V_a strain^m below the per-particle cut). */
SPH_API sph_status sph_flaws_active_at(sph_sim *sim, double strain, double *count);

/* ---------------------------------------------------------------- bodies */

typedef enum sph_motion {
    SPH_MOTION_FREE = 0,     /* integrated by the SPH equations */
    SPH_MOTION_FIXED = 1,    /* does not move */
    SPH_MOTION_VELOCITY = 2, /* moves at a prescribed constant velocity */
    SPH_MOTION_FORCE = 3,    /* rigid translation under a constant applied
                                force plus the SPH forces on it */
    SPH_MOTION_ROTATION = 4  /* prescribed rigid rotation at a constant
                                angular velocity (sph_set_rotation) */
} sph_motion;

/* A block of particles on a lattice over [lo, hi] (only the first `dim`
 * entries are read).  Per axis n = round((hi - lo)/dx) particles with
 * centres at lo + (i + 1/2) (hi - lo)/n.  The body's nominal spacing is dx.
 * Fails if a particle would overlap (closer than dx/2 to) another body. */
SPH_API sph_status sph_add_block(sph_sim *sim, const char *name, int material, const double lo[3],
                                 const double hi[3], double dx, int *body);

/* The lattice sph_add_block would lay, without laying it: particles per
 * axis (count, 1 beyond dim) and lattice step per axis [m] (0 beyond dim),
 * after the same checks (dx, extents, the memory a run of that many
 * particles needs).  `name` only labels the messages; either output may be
 * NULL. */
SPH_API sph_status sph_block_lattice(sph_sim *sim, const char *name, const double lo[3],
                                     const double hi[3], double dx, long count[3], double step[3]);

/* A body from given particle centres (n * dim doubles) and volumes (n
 * doubles, or NULL for spacing^dim each).  `spacing` is the body's nominal
 * particle spacing. */
SPH_API sph_status sph_add_particles(sph_sim *sim, const char *name, int material, size_t n,
                                     const double *positions, const double *volumes, double spacing,
                                     int *body);

/* Specimen geometry (geometry.c).  The loading axis is y in every builder:
 * a specimen stands on a plate and a piston presses on it from above.
 *
 * sph_add_prism: a rectangular prism (3D) of `width` along x, `height`
 * along y and `depth` along z whose base (its face of least y) is centred
 * on base_centre; the lattice of sph_add_block.
 *
 * sph_add_cylinder: a circular cylinder (3D), axis along y, base centred on
 * base_centre, radius and length in m.  Lattice: n_y = round(length/dx)
 * layers with centres at y0 + (j + 1/2) length/n_y; in each layer the
 * points of the square lattice over the bounding square, n = round(2 R/dx)
 * per side with centres at xc - R + (i + 1/2) 2R/n (likewise z), that lie
 * strictly inside the circle (distance from the axis < R).  Each particle
 * has the volume of its lattice cell, (2R/n)^2 length/n_y, so the body's
 * volume is that of the lattice cells inside the circle (it differs from
 * pi R^2 L by the staircase of the surface, less than 1 % at D/dx >= 27). */
SPH_API sph_status sph_add_prism(sph_sim *sim, const char *name, int material,
                                 const double base_centre[3], double width, double depth,
                                 double height, double dx, int *body);
SPH_API sph_status sph_add_cylinder(sph_sim *sim, const char *name, int material,
                                    const double base_centre[3], double radius, double length,
                                    double dx, int *body);

/* Platens against any body (2D and 3D): sph_add_plate lays a fixed plate
 * under the body (against its face of least y), sph_add_piston a piston on
 * top of it moving down (-y) at `speed` [m/s], finite and >= 0.
 * Layer rule: a platen is `layers` lattice layers thick, spaced by the
 * body's lattice step dy along y, and covers the body's extent across y
 * (x in 2D, x and z in 3D) with round(extent / step) columns per axis, the
 * body's own columns for blocks, prisms and cylinders (a square slab under
 * a cylinder, a strip under a disc).  layers = 0 picks the least number
 * that is at least one kernel support thick, ceil(2h/dy) (3 at
 * h = 1.2 dx); fewer than both ceil(2h/dy) and ceil(2h/dx), dx the body's
 * nominal spacing (they differ only where the lattice step is rounded to
 * the body's extent), is an error.  Its face touches the body's extent, so
 * its nearest layer is one dy from the body's extreme layer.  material < 0
 * takes the body's material.  Motion is prescribed; density and deviatoric
 * stress evolve as for the specimen (SPEC: bonded ends).  Add the body
 * first: the smoothing length h comes from the first body. */
/* The force [N; N per metre of depth in 2D] the SPH equations put on a
 * fixed or velocity-driven body (a plate, a piston) at the last rate
 * evaluation, which its prescribed motion overrides: the load a platen
 * carries (gravity on it included when on).  Zero for other bodies. */
SPH_API sph_status sph_body_reaction(sph_sim *sim, int body, double force[3]);
SPH_API sph_status sph_add_plate(sph_sim *sim, const char *name, int material, int body, int layers,
                                 int *plate);
SPH_API sph_status sph_add_piston(sph_sim *sim, const char *name, int material, int body,
                                  int layers, double speed, int *piston);

/* End placement.  By default (inset 0) a platen's face lies on the body's
 * extent, as the continuum's loaded face: its nearest particle row is one
 * lattice step dy from the body's extreme row, and the body's kernel-summed
 * density drops to half exactly there.  The SPH platen, whose rows carry
 * stress, is nevertheless softer than a rigid face on it: a body of length
 * L between a plate and a piston answers quasi-statically as if it were
 * longer by about one step (2 x 0.55 dy for the cubic spline at h/dy 1.2,
 * 2 x 0.6 for cubic_o4 at 1.65), and waves reflect late by the same amount.
 * sph_set_platen_inset(sim, s) makes sph_add_plate and sph_add_piston (and
 * sph_build_paper_scene) called after it lay their platens s steps (s dy)
 * closer to the body, s in (-1, 0.5); a negative s opens a gap.  The
 * setting only moves particles when a platen is laid: 0 costs nothing.
 *
 * sph_static_platen_inset: for the handle's kernel and h and the lattice
 * steps of `body`, the inset at which the quasi-static stiffness of the body
 * between two platens is exact (M/L for a laterally uniform lattice of P-wave
 * modulus M, up to the lattice gradient moment of the bulk), and the end
 * offset (L_eff - L)/2 in steps left at that inset: 0 where such an inset
 * exists in [-0.5, 0.49] (the first above 0 if several), else the inset
 * of least offset and that offset (cubic spline at h/dy 1.5: 1.08 steps at
 * 0.25, against 1.49 at 0).  It solves the static problem of one lattice
 * column stack (each row a full layer, platen rows carrying stress, no
 * kernel correction): the SPH strain of every row, the state that zeroes
 * the force on the body's rows, the strain in the middle.  Either output
 * may be NULL.  sph_platen_end_offset: the same problem's end offset
 * (L_eff - L)/2 in steps at a given inset. */
SPH_API sph_status sph_set_platen_inset(sph_sim *sim, double inset);
SPH_API double sph_platen_inset(const sph_sim *sim);
SPH_API sph_status sph_static_platen_inset(sph_sim *sim, int body, double *inset, double *offset);
SPH_API sph_status sph_platen_end_offset(sph_sim *sim, int body, double inset, double *offset);

/* Extent of a body's lattice cells [lo, hi] and its lattice step per axis
 * (blocks, prisms, cylinders and platens: exact; bodies from
 * sph_add_particles: particle extent plus half a spacing each side, step =
 * spacing).  Entries past the dimension are 0; any output may be NULL. */
SPH_API sph_status sph_body_extent(sph_sim *sim, int body, double lo[3], double hi[3],
                                   double step[3]);

/* Prescribe a body's motion.  `vector` (dim entries) is the velocity for
 * SPH_MOTION_VELOCITY, the applied total force [N per unit depth in 2D]
 * for SPH_MOTION_FORCE, and is ignored (may be NULL) otherwise.
 * SPH_MOTION_ROTATION is set with sph_set_rotation(). */
SPH_API sph_status sph_set_motion(sph_sim *sim, int body, sph_motion motion, const double *vector);

/* Prescribe a rigid rotation of a body about the fixed point `centre` (dim
 * entries) at the constant angular velocity `omega` [rad/s]: 3 entries, the
 * rotation vector (in 2D only omega[2], about z, may be non-zero).  Each
 * step moves every particle exactly along its arc,
 *   x_{n+1} = c + R(omega dt) (x_n - c),   v = omega x (x - c),
 * for both Heun stages (a prescribed velocity would be advanced on straight
 * lines); density and stress evolve through the SPH equations, so a body
 * whose velocity gradient is computed exactly (kernel_correction) stays
 * unstrained.  Sets the particles' velocities now.  Not with periodic
 * axes. */
SPH_API sph_status sph_set_rotation(sph_sim *sim, int body, const double *centre,
                                    const double *omega);

/* Give every particle of a body the velocity `v` (dim entries). */
SPH_API sph_status sph_set_body_velocity(sph_sim *sim, int body, const double *v);

SPH_API size_t sph_particle_count(const sph_sim *sim);
SPH_API int sph_body_count(const sph_sim *sim);

typedef struct sph_body_info {
    const char *name;
    int material;
    sph_motion motion;
    size_t first; /* particles [first, first + count) belong to it */
    size_t count;
    double spacing;
} sph_body_info;

SPH_API sph_status sph_body_info_get(sph_sim *sim, int body, sph_body_info *info);
/* Body index by name, or a SPH_ERR_ARGUMENT naming the unknown name. */
SPH_API sph_status sph_body_find(sph_sim *sim, const char *name, int *body);

/* ----------------------------------------------------- domain and kernel */

/* Bounding box of the simulation.  Periodic axes wrap; along other axes
 * a particle leaving [lo, hi] stops the run with SPH_ERR_DOMAIN.  Without a
 * domain the space is unbounded.  Must be set before bodies are added if
 * bodies are checked against it, or any time before the first step. */
SPH_API sph_status sph_set_domain(sph_sim *sim, const double lo[3], const double hi[3],
                                  const int periodic[3]);

/* Kernels are numbered from 0 without gaps; their names come from
 * sph_kernel_name() (the registry is in the library, kernel.h). */
typedef enum sph_kernel {
    SPH_KERNEL_CUBIC_SPLINE = 0, /* "cubic_spline": Monaghan (1992), support 2h (default) */
    SPH_KERNEL_WENDLAND_C2 = 1,  /* "wendland_c2": Wendland (1995) C2, support 2h */
    SPH_KERNEL_CUBIC_O4 = 2      /* "cubic_o4": fourth-order extrapolation of two cubic
                                    splines (zero second moment, negative outer lobe),
                                    support 2h, time step of h/1.5; for waves at
                                    h/dx = 1.65 */
} sph_kernel;

SPH_API sph_status sph_set_kernel(sph_sim *sim, sph_kernel kernel);
/* The same by name; an unknown name is an error listing the known ones. */
SPH_API sph_status sph_set_kernel_by_name(sph_sim *sim, const char *name);
/* Static name of a kernel, or NULL if `kernel` is not one. */
SPH_API const char *sph_kernel_name(sph_kernel kernel);
/* Kernel of that name, or -1 if there is none. */
SPH_API int sph_kernel_from_name(const char *name);
/* Space-separated list of kernel names, in the order of their numbers. */
SPH_API const char *sph_kernel_names(void);
/* The smallest q = r/h at which the kernel is negative in `dim`
 * dimensions (to 1e-12), 0 for a kernel that is non-negative over its
 * support, -1 for an unknown kernel or dimension.  The artificial_stress
 * effect needs 0: its factor (W/W(dx))^n falls off with distance only
 * for a non-negative kernel, and a run with it and a kernel that changes
 * sign stops at its first rate evaluation with an error. */
SPH_API double sph_kernel_negative_from(sph_kernel kernel, int dim);
/* The handle's kernel in the dimensionless form used by the rate engine:
 * at n values of q = r/h, w = h^dim W(r) and dw_dq = h^(dim+1) dW/dr
 * (either output may be NULL).  q must be finite and >= 0. */
SPH_API sph_status sph_kernel_values(sph_sim *sim, size_t n, const double *q, double *w,
                                     double *dw_dq);
/* Smoothing length as a multiple of the first body's spacing (default 1.2). */
SPH_API sph_status sph_set_smoothing_ratio(sph_sim *sim, double h_over_dx);
SPH_API double sph_smoothing_length(const sph_sim *sim);
/* Support radius of the kernel [m] (2h for the kernels so far); 0 while
 * h is unknown. */
SPH_API double sph_support_radius(const sph_sim *sim);
/* Rows of particles `spacing` apart that make a wall (plate, piston) at
 * least one kernel support thick: ceil(support / spacing); 0 while h is
 * unknown or for a spacing that is not > 0. */
SPH_API int sph_support_layers(const sph_sim *sim, double spacing);
/* Set the reference particle spacing (normally the first body's): h is
 * h_over_dx times it, and the artificial stress normalises by W(dx).  For
 * handles that evaluate rates of external particles and have no bodies. */
SPH_API sph_status sph_set_spacing(sph_sim *sim, double dx);

/* --------------------------------------------------------------- effects */

/* Switch an effect on, with its parameters as "key=value" words, e.g.
 *   sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0").
 * The effects, their parameters, defaults and ranges are listed by
 * sph_effect_count() / sph_effect_info_get() / sph_effect_parameter_get()
 * (the table in docs/library.md is checked against them).  Unknown effects
 * or keys, values out of range and missing required values are errors;
 * the message names them.  A parameter not given takes its default.
 * Off (the default), an effect costs nothing in the pair loop. */
SPH_API sph_status sph_effect(sph_sim *sim, const char *name, const char *parameters);
SPH_API sph_status sph_effect_off(sph_sim *sim, const char *name);
/* 1 if on, 0 if off, -1 if the name is unknown. */
SPH_API int sph_effect_is_on(const sph_sim *sim, const char *name);
/* Space-separated list of known effect names. */
SPH_API const char *sph_effect_names(void);

/* The effect registry.  Effects are numbered 0 .. sph_effect_count() - 1;
 * the queries take no handle and return SPH_ERR_ARGUMENT (with no message)
 * for an index out of range or a NULL output. */
typedef struct sph_effect_info {
    const char *name;
    const char *description; /* one line, with its reference */
    int parameter_count;
} sph_effect_info;

typedef struct sph_effect_parameter {
    const char *key;
    const char *unit; /* SI, "" when dimensionless */
    const char *description;
    double default_value; /* NAN when the value must be given */
    int required;         /* 1 when there is no default */
    double min, max;      /* allowed range, +-HUGE_VAL when unbounded */
    int min_inclusive, max_inclusive;
} sph_effect_parameter;

SPH_API int sph_effect_count(void);
SPH_API sph_status sph_effect_info_get(int effect, sph_effect_info *info);
SPH_API sph_status sph_effect_parameter_get(int effect, int parameter, sph_effect_parameter *info);

/* ------------------------------------------------------------ time steps */

/* Time integrators, selected by name (default "improved_euler"):
 *   "improved_euler"  Heun, two rate evaluations per step; the paper's
 *                     scheme; wave problems need artificial viscosity
 *   "leapfrog"        kick-drift-kick (velocity Verlet) with density and
 *                     stress advanced by the half-step velocity: symplectic,
 *                     stable without viscosity, one evaluation's pair work
 *                     per step (continuity pass at the half step, momentum
 *                     pass at the end) at a step up to 1.75 times Improved
 *                     Euler's limit
 * The stable and default steps below are the integrator's.  Selecting an
 * integrator keeps a step set with sph_set_dt() if it is within the new
 * integrator's stability limit, else fails (SPH_ERR_STATE). */
SPH_API sph_status sph_set_integrator(sph_sim *sim, const char *name);
/* Name of the handle's integrator (static storage). */
SPH_API const char *sph_integrator_name(const sph_sim *sim);
/* Space-separated list of known integrator names (static storage). */
SPH_API const char *sph_integrator_names(void);

typedef struct sph_integrator_info {
    const char *name;        /* static storage */
    const char *description; /* one line, static storage */
    int evaluations;         /* rate evaluations per step */
    double stable_factor;    /* stable step = stable_factor h / max(c_p + |v|) */
    double default_factor;   /* default step = default_factor h / max(c0),
                                  capped at the stable step */
    size_t saved_values;     /* doubles per particle of the `saved` buffer of
                                  its low-level stages, for this handle's
                                  dimension and effects */
    int carries_rates;       /* 1: the rates at the end of a step start the
                                  next (kept across runs and in checkpoints) */
} sph_integrator_info;

/* Describe integrator `name` (NULL: the handle's). */
SPH_API sph_status sph_integrator_info_get(sph_sim *sim, const char *name,
                                           sph_integrator_info *info);

/* Largest stable step of the handle's integrator,
 * stable_factor h / max(c_p + |v|) over the particles (over the
 * materials for a handle without particles; 0 while h is unknown). */
SPH_API double sph_stable_dt(const sph_sim *sim);
/* Default step default_factor h / max(c0) (bodies' materials, or all
 * materials of a handle without bodies), capped at sph_stable_dt(): for
 * Improved Euler 0.5 h/c0, the paper's 0.261 us at dx = 1 mm. */
SPH_API double sph_default_dt(const sph_sim *sim);
/* Set the step.  A step above sph_stable_dt() is refused unless
 * `allow_unstable` is non-zero. */
SPH_API sph_status sph_set_dt(sph_sim *sim, double dt, int allow_unstable);
SPH_API double sph_dt(const sph_sim *sim);
SPH_API double sph_time(const sph_sim *sim);
/* Set the clock (time [s] and step count), e.g. when the state was advanced
 * by another engine and is copied back into this handle. */
SPH_API sph_status sph_set_time(sph_sim *sim, double t, long step);
SPH_API long sph_step_count(const sph_sim *sim);

/* Called every `interval` steps during sph_run*() (and after the last);
 * a non-zero return stops the run with SPH_ERR_STOPPED after a
 * completed step. */
typedef int (*sph_progress_fn)(const sph_sim *sim, void *user);
SPH_API sph_status sph_set_progress(sph_sim *sim, long interval, sph_progress_fn fn, void *user);

/* Advance by n steps of the handle's integrator. */
SPH_API sph_status sph_run(sph_sim *sim, long steps);
/* Advance until time t (the last step is shortened to land on t). */
SPH_API sph_status sph_run_until(sph_sim *sim, double t);
/* How sph_run_until(sim, t) gets there from the current time with the
 * current step dt: *whole steps of dt, then, if *last > 0, one shortened
 * step of *last seconds that lands exactly on t. */
SPH_API sph_status sph_steps_until(sph_sim *sim, double t, long *whole, double *last);

/* The watchdog stops a run (SPH_ERR_UNSTABLE) when a particle of a free
 * body moves faster than `max_speed_over_cp` times its material's P-wave
 * speed, or its density leaves [min_density_ratio, max_density_ratio] times
 * rho0.  Defaults 1, 0.5, 2: a solid beyond them is no longer described by
 * the linear model.  A zero switches that check off. */
SPH_API sph_status sph_set_watchdog(sph_sim *sim, double max_speed_over_cp,
                                    double min_density_ratio, double max_density_ratio);

/* The watchdog's test on external arrays (n particles, material indices of
 * sim; integrate_motion as for sph_improved_euler_correct, NULL for all): returns
 * SPH_ERR_UNSTABLE, with *particle the lowest offending index and a message
 * naming speed or density ratio, or SPH_OK (*particle = -1). */
SPH_API sph_status sph_watchdog_check(sph_sim *sim, size_t n, const double *v, const double *rho,
                                      const int *material, const unsigned char *integrate_motion,
                                      long *particle);

/* A step that goes non-finite or trips the watchdog is undone: the state is
 * left as it was at the start of that step (the last good state), and is
 * written as a snapshot if an output file is open.
 *
 * Where a run stopped on a non-finite value or a domain exit: step, global
 * particle index, body and quantity name ("position", "velocity",
 * "density", "deviatoric stress", "speed", "density ratio").  Returns
 * SPH_ERR_STATE if the last run did not fail that way; either way the
 * handle's message (the failed run's) is left as it is. */
SPH_API sph_status sph_failure(const sph_sim *sim, long *step, long *particle, int *body,
                               const char **quantity);

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

/* ---------------------------------------------------------------- output */

/* Open an HDF5 output file (layout in docs/hdf5_layout.md).  Particle
 * snapshots are written every `snapshot_interval` steps (0: none but the
 * first) and probe samples every `probe_interval` steps (0: none; > 0
 * needs at least one probe, SPH_ERR_ARGUMENT otherwise).  The current state
 * is written as frame 0 at once. */
SPH_API sph_status sph_output_open(sph_sim *sim, const char *path, long snapshot_interval,
                                   long probe_interval);
/* Write a snapshot of the current state now. */
SPH_API sph_status sph_output_snapshot(sph_sim *sim);
/* Close the output file.  The state at closing is written first as a last
 * frame (and a last probe sample) unless the current step is already in
 * the file, so the file always ends with the final state; then the XDMF
 * companion is written beside it (sph_write_xdmf). */
SPH_API sph_status sph_output_close(sph_sim *sim);

/* Write the XDMF companion of an output file for ParaView and VTK:
 * `run.h5` -> `run.xmf` in the same folder (one grid per frame: positions,
 * velocity, density, pressure, von Mises, deviatoric stress components,
 * body), pointing into the HDF5 file.  `sim` only receives the error
 * message and may be NULL. */
SPH_API sph_status sph_write_xdmf(sph_sim *sim, const char *h5_path);

/* The version of the file format this library writes (the root attribute
 * `sphsolid_format`).  Outputs of every version from 1 (libsphsolid 0.1.0
 * and 0.2.0, written before the version was recorded) up to this one are
 * read; checkpoints of this version only. */
SPH_API int sph_output_format_version(void);

/* Number of snapshot frames in a file written by sph_output_open() (of any
 * format up to sph_output_format_version()). */
SPH_API sph_status sph_read_frame_count(sph_sim *sim, const char *path, long *frames);
/* Load frame `frame` (negative counts from the end) of a file into the
 * state of a simulation whose particles match it (same count and bodies):
 * positions, velocities, density, deviatoric stress, time and step. */
SPH_API sph_status sph_read_frame(sph_sim *sim, const char *path, long frame);

/* Write everything needed to continue the run bit for bit (state, time,
 * step, dt, motions).  Resume with sph_checkpoint_read() into a simulation
 * built the same way. */
SPH_API sph_status sph_checkpoint_write(sph_sim *sim, const char *path);
SPH_API sph_status sph_checkpoint_read(sph_sim *sim, const char *path);

/* ---------------------------------------------------------------- scenes */

/* The paper's uniaxial compression test (Das & Cleary), 2D plane strain:
 * specimen x in [-43, 43] mm, y in [0, 140] mm on a lattice of spacing dx
 * (86 x 140 = 12,040 particles at dx = 1 mm); K = 12.2 GPa, mu = 2.67 GPa,
 * rho0 = 2300 kg/m^3; a fixed plate below and a piston above, each
 * ceil(2h/dx) layers (at least one kernel support) of the specimen's
 * width and material, the piston moving down at `piston_speed` [m/s]
 * (the paper: 1.5e-3); probes A (0, 70) mm, B (21.5, 103.5) mm,
 * C (21.5, 70) mm.  With piston_speed = 0 and gravity_only non-zero the
 * piston is left out and gravity (g = 9.81 m/s^2) loads the specimen
 * resting on the plate (the paper's gravity case).  No dissipation is
 * switched on: the caller chooses (docs: artificial_viscosity alpha=1 is
 * the default for wave problems). */
typedef struct sph_paper_scene {
    int specimen, piston, plate; /* body indices (piston -1 if none) */
    int material;
    int probe_A, probe_B, probe_C;
} sph_paper_scene;

SPH_API sph_status sph_build_paper_scene(sph_sim *sim, double dx, double piston_speed,
                                         int gravity_only, sph_paper_scene *scene);

/* ------------------------------------------------- low-level rate engine */
/*
 * For codes that own their particles and neighbour lists (the LAMMPS
 * plugin): evaluate the rates of particles [0, n_local) of arrays laid out as
 * above, with neighbours drawn from [0, n_total).  Materials, kernel,
 * smoothing length and effects are those of `sim`, which needs no bodies.
 * Neighbours are given either as CSR (offsets, n_local + 1 entries, and
 * indices) or as one pointer and count per particle (lists, counts).
 *
 * Two ways to call it:
 *  - sph_rates_evaluate: one call, a full list (b in list(a) iff a in
 *    list(b) for local a and b; a ghost b is listed in a's row only).  Each
 *    pair of locals is still computed once, except a pair whose indices are
 *    far apart (in chunks of the pair pass at least two apart; a chunk is
 *    n_local/64 rows, at least 256 in 2D and 4096 in 3D): each of its rows
 *    computes it for its own particle, so that no pair terms are stored.
 *  - sph_rates_pairs, then sph_rates_finish: for Newton's third law across
 *    processes (LAMMPS newton_pair on).  sph_rates_pairs takes a half list
 *    (every pair at most once over all rows and all processes; rows sorted
 *    by index and local pairs listed in the row of the smaller index run
 *    fastest) and writes partial sums for all n_total particles, ghosts
 *    included: sph_rates_partial_size(sim) doubles per particle.  The caller
 *    adds each ghost's partial sums to its owner's (a reverse
 *    communication), then sph_rates_finish turns the sums of the n_local
 *    particles into rates.  The partial sums are plain sums over pairs, so
 *    adding them in any order is correct (the order decides the rounding).
 *    Without ghosts shared by processes (one process, or newton_pair off
 *    with each local-ghost pair listed on both sides) the ghost sums are
 *    simply not used.
 *  - sph_rates_pass_half (below): one call, a half list for the local
 *    pairs (each once) in which each pair of a local and a ghost particle
 *    is listed in the local particle's row, and on the ghost's own process
 *    too: the rates of the n_local particles, the ghosts' terms dropped,
 *    no partial sums and no reverse communication.
 * Results do not depend on the number of threads (bitwise).
 */
typedef struct sph_particles {
    size_t n_local;
    size_t n_total;
    const double *x;      /* n_total * stride */
    const double *v;      /* n_total * stride */
    const double *rho;    /* n_total */
    const double *S;      /* n_total * ncomp */
    const double *mass;   /* n_total */
    const int *material;  /* n_total */
    size_t stride;        /* doubles from one particle's x (and v) to the
                               next's: 0 means dim; e.g. 3 for LAMMPS's
                               arrays in 2D */
    const double *damage; /* n_total: D of each particle when effect damage
                             is on (ghosts too), else ignored */
} sph_particles;

/* Neighbours of each local particle a (row a): indices[offsets[a] ..
 * offsets[a + 1]) or lists[a][0 .. counts[a]).  Rows in ascending order
 * without repeats are the fastest: the pair pass then gathers runs of
 * consecutive neighbours at once (each call tests the rows). */
typedef struct sph_neighbours {
    const size_t *offsets;
    const int *indices;
    const int *const *lists;
    const int *counts;
} sph_neighbours;

typedef struct sph_rates {
    double *dv_dt;   /* n_local * dim (gravity and damping included) */
    double *drho_dt; /* n_local */
    double *dS_dt;   /* n_local * ncomp */
    double *dx_dt;   /* n_local * dim, XSPH-corrected velocity, or NULL */
} sph_rates;

SPH_API sph_status sph_rates_evaluate(sph_sim *sim, const sph_particles *particles,
                                      const sph_neighbours *neighbours, sph_rates *rates);

/* Doubles per particle of the partial sums of sph_rates_pairs (depends on
 * the dimension and on kernel_correction and xsph being on). */
SPH_API size_t sph_rates_partial_size(const sph_sim *sim);
/* The pair pass over a half list: partial[n_total * sph_rates_partial_size]
 * is overwritten with the sums of every particle, local and ghost. */
SPH_API sph_status sph_rates_pairs(sph_sim *sim, const sph_particles *particles,
                                   const sph_neighbours *half_list, double *partial);
/* Rates of the n_local particles from their complete partial sums (ghost
 * contributions already added): the corrected velocity gradient, the
 * Jaumann stress rate, gravity, damping and the XSPH velocity. */
SPH_API sph_status sph_rates_finish(sph_sim *sim, const sph_particles *particles,
                                    const double *partial, sph_rates *rates);

/* The rates in two passes over the pairs, for integrators that need them
 * at different states (the leapfrog: density and stress rates at the half
 * step, accelerations at the whole step).  The continuity pass computes
 * drho/dt, dS/dt (velocity gradient, with the kernel-correction matrix when
 * that effect is on) and the XSPH velocity; the momentum pass dv/dt
 * (stress, artificial viscosity and stress, gravity, damping).  A pass
 * writes only its own rate arrays (the others may be NULL) and its partial
 * sums hold only what it computes: sph_rates_pass_size(sim, pass) doubles
 * per particle, which is what a reverse communication needs to send.  The
 * rates of the two passes at one state equal those of SPH_RATES_ALL
 * bitwise. */
typedef enum sph_rate_pass {
    SPH_RATES_CONTINUITY = 1,
    SPH_RATES_MOMENTUM = 2,
    SPH_RATES_ALL = 3
} sph_rate_pass;
SPH_API size_t sph_rates_pass_size(const sph_sim *sim, int pass);
SPH_API sph_status sph_rates_pass_pairs(sph_sim *sim, int pass, const sph_particles *particles,
                                        const sph_neighbours *half_list, double *partial);
SPH_API sph_status sph_rates_pass_finish(sph_sim *sim, int pass, const sph_particles *particles,
                                         const double *partial, sph_rates *rates);
/* One pass (or SPH_RATES_ALL) over a half list, finished: each pair of
 * local particles listed once (best in the row of the smaller index), each
 * pair of a local particle a and a ghost listed in a's row; a's rates get
 * the pair's terms, the ghost's are dropped (its own process lists the
 * pair too).  The rates equal those of sph_rates_pass_pairs +
 * sph_rates_pass_finish when the ghosts' sums reach their owners (to
 * round-off: the order of the sums differs). */
SPH_API sph_status sph_rates_pass_half(sph_sim *sim, int pass, const sph_particles *particles,
                                       const sph_neighbours *half_list, sph_rates *rates);

/* Improved Euler stages on external arrays of n particles (dim, ncomp
 * from sim).  Stage 1 (predict): saves y_n into `saved` (v, rho, S:
 * dim + 1 + ncomp doubles per particle) and sets y* = y_n + dt f(y_n).
 * Stage 2 (correct): y_{n+1} = (y_n + y*)/2 + dt/2 f(y*), with
 * x_{n+1} = x* + dt/2 (v* - v_n).  `integrate_motion[i]` is 0 for
 * particles whose velocity is prescribed: their velocity is left alone
 * while their position still advances by dt v and their density and stress
 * evolve (pass NULL to integrate all). */
SPH_API sph_status sph_improved_euler_predict(sph_sim *sim, size_t n, double dt, double *x,
                                              double *v, double *rho, double *S,
                                              const sph_rates *rates,
                                              const unsigned char *integrate_motion, double *saved);
SPH_API sph_status sph_improved_euler_correct(sph_sim *sim, size_t n, double dt, double *x,
                                              double *v, double *rho, double *S,
                                              const sph_rates *rates,
                                              const unsigned char *integrate_motion,
                                              const double *saved);

/* Rigid translation under an applied force (SPH_MOTION_FORCE), split for
 * distributed particles.  sph_rigid_force_sum() adds the contributions of
 * the members among n particles to `sums` (dim + 1 doubles, zeroed by the
 * caller: the total mass, then the sum of m dv/dt); add the sums of all
 * ranks together.  sph_rigid_force_apply() then gives every member the
 * common acceleration (applied + sum m dv/dt) / total mass, with `applied`
 * the external force on the whole body (dim entries).  `member` (n
 * entries, non-zero for members) may be NULL: all n are members. */
SPH_API sph_status sph_rigid_force_sum(sph_sim *sim, size_t n, const double *mass,
                                       const double *dv_dt, const unsigned char *member,
                                       double *sums);
SPH_API sph_status sph_rigid_force_apply(sph_sim *sim, size_t n, const double *applied,
                                         const double *sums, const unsigned char *member,
                                         double *dv_dt);

/* The same stages for a code that moves some particles itself (the LAMMPS
 * plugin: fix move), on its own position and velocity arrays, `stride`
 * doubles apart (>= dim; 3 for LAMMPS's x and v in 2D).  Particles with
 * integrate_motion[i] == 0 keep their x and v untouched; their density
 * and stress evolve.  The corrector also applies the watchdog
 * (sph_set_watchdog) to the integrated particles, `material` giving each
 * particle's material: on SPH_ERR_UNSTABLE or SPH_ERR_NONFINITE,
 * *particle is the first particle concerned (else -1). */
SPH_API sph_status sph_improved_euler_predict_strided(sph_sim *sim, size_t n, double dt, double *x,
                                                      double *v, size_t stride, double *rho,
                                                      double *S, const sph_rates *rates,
                                                      const unsigned char *integrate_motion,
                                                      double *saved);
SPH_API sph_status sph_improved_euler_correct_strided(sph_sim *sim, size_t n, double dt, double *x,
                                                      double *v, size_t stride, double *rho,
                                                      double *S, const sph_rates *rates,
                                                      const unsigned char *integrate_motion,
                                                      const int *material, const double *saved,
                                                      long *particle);

/* Deprecated aliases, kept for one release (0.3.x) and removed after it:
 * the Improved Euler stages were named after Heun's method before the
 * registry's name "improved_euler" was used throughout.  Each calls the
 * function named in its warning with the same arguments. */
SPH_API sph_status sph_heun_predict(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                    double *rho, double *S, const sph_rates *rates,
                                    const unsigned char *integrate_motion, double *saved)
    SPH_DEPRECATED("sph_improved_euler_predict");
SPH_API sph_status sph_heun_correct(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                    double *rho, double *S, const sph_rates *rates,
                                    const unsigned char *integrate_motion, const double *saved)
    SPH_DEPRECATED("sph_improved_euler_correct");
SPH_API sph_status sph_heun_predict_strided(sph_sim *sim, size_t n, double dt, double *x, double *v,
                                            size_t stride, double *rho, double *S,
                                            const sph_rates *rates,
                                            const unsigned char *integrate_motion, double *saved)
    SPH_DEPRECATED("sph_improved_euler_predict_strided");
SPH_API sph_status sph_heun_correct_strided(
    sph_sim *sim, size_t n, double dt, double *x, double *v, size_t stride, double *rho, double *S,
    const sph_rates *rates, const unsigned char *integrate_motion, const int *material,
    const double *saved, long *particle) SPH_DEPRECATED("sph_improved_euler_correct_strided");

/* The leapfrog (sph_set_integrator "leapfrog") in three stages on external
 * arrays, `stride` doubles apart (>= dim), for a code that owns its
 * particles (the LAMMPS plugin: fix sphsolid/leapfrog).  Per step:
 *   1. sph_leapfrog_begin_strided() with the rates at the start (a_n: dv/dt
 *      with the forces of the rigid bodies applied; drho/dt, dS/dt of the
 *      previous step's half step, or of the start on a first step): saves
 *      x_n, rho_n, S_n in `saved` (dim + 1 + ncomp doubles per particle,
 *      sph_integrator_info_get's saved_values), kicks the integrated
 *      velocities by dt/2 dv/dt, moves every position by dt/2 v and
 *      predicts rho and S at the half step;
 *   2. evaluate the density and stress rates there (the continuity pass,
 *      sph_rates_pass_pairs/pass_finish; keep them for the next step's
 *      stage 1), then
 *      sph_leapfrog_drift_strided(): x = x_n + dt v (or the XSPH velocity)
 *      for the integrated particles, x = x_n for the others (their mover
 *      moves them on), rho = rho_n + dt drho/dt, S = S_n + dt dS/dt, with
 *      the watchdog's density bounds;
 *   3. evaluate the acceleration at the new state (the momentum pass), then
 *      sph_leapfrog_end_strided():
 *      v += dt/2 dv/dt for the integrated particles, and the watchdog.
 * On SPH_ERR_NONFINITE or SPH_ERR_UNSTABLE *particle is the first particle
 * concerned (else -1). */
SPH_API sph_status sph_leapfrog_begin_strided(sph_sim *sim, size_t n, double dt, double *x,
                                              double *v, size_t stride, double *rho, double *S,
                                              const sph_rates *rates,
                                              const unsigned char *integrate_motion, double *saved);
SPH_API sph_status sph_leapfrog_drift_strided(sph_sim *sim, size_t n, double dt, double *x,
                                              const double *v, size_t stride, double *rho,
                                              double *S, const sph_rates *rates,
                                              const unsigned char *integrate_motion,
                                              const double *saved, const int *material,
                                              long *particle);
SPH_API sph_status sph_leapfrog_end_strided(sph_sim *sim, size_t n, double dt, double *v,
                                            size_t stride, const double *rho, const double *dv_dt,
                                            const unsigned char *integrate_motion,
                                            const int *material, long *particle);

/* Derived fields of external particles (n of them, material indices of
 * sim): pressure P (n), full Cauchy stress sigma = -P I + S (n * ncomp) and
 * von Mises stress (n).  Any output may be NULL. */
SPH_API sph_status sph_derived_fields(sph_sim *sim, size_t n, const double *rho, const double *S,
                                      const int *material, double *pressure, double *stress,
                                      double *von_mises);

/* Elastic energy of each of n external particles [J; J per metre of depth
 * in 2D]: m (u_vol(rho) + S:S / (4 mu rho)), the per-particle terms that
 * sph_energy() sums (`energy`: n doubles). */
SPH_API sph_status sph_energy_fields(sph_sim *sim, size_t n, const double *mass, const double *rho,
                                     const double *S, const int *material, double *energy);

/* The energy account (sph_set_energy_account) on a caller's particles, a
 * code that owns them (the LAMMPS plugin: pair_style sphsolid
 * energy_account yes, compute sphsolid/energy), from the terms the
 * handle's own account uses; the caller integrates and sums (over its
 * processes too):
 *  - sph_energy_power: the powers of one rate evaluation of the n_local
 *    particles [W; W/m in 2D].  power[0], the work rate of everything but
 *    the SPH forces among the particles: sum m (a - dv_sph) . v, with
 *    dv_sph the evaluation's SPH accelerations (sph_rates dv_dt, n_local
 *    * dim) and a the acceleration the integrator gives the particle:
 *    dv_dt (n_local * dim: a rigid body's common acceleration, gravity
 *    added, ...) where integrate_motion[a] is non-zero (NULL: all), 0
 *    where the caller prescribes the motion (it overrides the SPH force,
 *    doing -m dv_sph . v: constant speeds and rotations).  power[1], with
 *    effect artificial_viscosity on (else 0), the heat rate
 *    sum m_a m_b Pi_ab v_ab . grad_a W_ab over the pairs of the
 *    neighbours' rows (each pair listed once, ghosts included, positions
 *    as given); a pair with a ghost (index >= n_local) counts half if
 *    shared_ghost_pairs is non-zero (its other process lists it too).
 *    Uses particles->x, v, rho, mass, material and stride.  Integrated
 *    with the integrator's weights, the step's mean power times dt (the
 *    trapezoid of Improved Euler's two evaluations), these are the
 *    account's work and dissipated_viscosity.
 *  - sph_energy_sums: adds sum m v^2 / 2 to energy[0] and the elastic
 *    energy to energy[1] (damaged by damage[a] if damage is non-NULL, as
 *    sph_energy() reports it with effect damage on) of the n particles
 *    whose member[a] is non-zero (NULL: all); v `stride` doubles apart (0:
 *    dim).
 *  - sph_energy_released: adds to *released the elastic energy a stage
 *    took from n particles: sum m (u(rho, S_before, D_before) - u(rho, S,
 *    D)), u the damaged energy per mass; the damage stage (S unchanged:
 *    the account's dissipated_damage) or the drucker_prager return (D
 *    unchanged: dissipated_plastic).  damage_before and damage: both n
 *    values, or both NULL (undamaged). */
SPH_API sph_status sph_energy_power(sph_sim *sim, const sph_particles *particles,
                                    const sph_neighbours *neighbours, int shared_ghost_pairs,
                                    const double *dv_sph, const double *dv_dt,
                                    const unsigned char *integrate_motion, double *power);
SPH_API sph_status sph_energy_sums(sph_sim *sim, size_t n, const double *mass, const double *v,
                                   size_t stride, const double *rho, const double *S,
                                   const double *damage, const int *material,
                                   const unsigned char *member, double *energy);
SPH_API sph_status sph_energy_released(sph_sim *sim, size_t n, const double *mass,
                                       const int *material, const double *rho,
                                       const double *S_before, const double *damage_before,
                                       const double *S, const double *damage, double *released);

/* Effect damage on n external particles (a code that owns its particles:
 * the LAMMPS plugin), with the handle's seed, flaws parameter, materials
 * and smoothing length.  A particle's flaws are drawn from (seed, id[a],
 * flaw index): id is its global index, the one the handle's own particles
 * use (0, 1, ... in the order they were added), so a code that numbers
 * its particles from 1 passes number - 1 to get the same flaws, on any
 * number of processes.  mass[a] / rho0 is its volume at rest.
 *  - sph_damage_flaws: the number of flaws of each particle and its
 *    weakest activation strain (0 and inf where flawed[a] is 0, as the
 *    handle's prescribed bodies, or the material has no flaws; flawed may
 *    be NULL: all may be damaged);
 *  - sph_damage_grow: the damage stage after a step of dt: activation by
 *    each particle's largest principal strain at (rho, S), growth of
 *    damage[a] (D in [0, 1]); *changed is 1 if any D grew (rates
 *    evaluated before are stale then);
 *  - sph_damage_active: the flaws active at the current state (n doubles).
 * SPH_ERR_STATE while the effect is off. */
/* Effect drucker_prager on n external particles: the return of each
 * deviator S (n * ncomp, changed in place) onto the cone at its pressure
 * (rho) and damage (damage: n values, required while effect damage is on,
 * else ignored); member[a] = 0 skips particle a (prescribed bodies; NULL:
 * all).  *changed is 1 if a deviator was scaled. */
SPH_API sph_status sph_drucker_prager_return(sph_sim *sim, size_t n, const int *material,
                                             const double *rho, const double *damage,
                                             const unsigned char *member, double *S, int *changed);
SPH_API sph_status sph_damage_flaws(sph_sim *sim, size_t n, const uint64_t *id, const double *mass,
                                    const int *material, const unsigned char *flawed,
                                    int *flaw_count, double *flaw_strain);
SPH_API sph_status sph_damage_grow(sph_sim *sim, size_t n, double dt, const uint64_t *id,
                                   const double *mass, const int *material, const double *rho,
                                   const double *S, const int *flaw_count,
                                   const double *flaw_strain, double *damage, int *changed);
SPH_API sph_status sph_damage_active(sph_sim *sim, size_t n, const uint64_t *id, const double *mass,
                                     const int *material, const double *rho, const double *S,
                                     const int *flaw_count, const double *flaw_strain,
                                     double *active);

/* Effect damage: fragments of caller-owned particles, one round of a
 * labelling that a code spread over processes repeats until no process
 * reports a change.  Particles whose member[a] is non-zero (the handle's
 * free bodies) and whose particles->damage is below 1 are joined when
 * closer than the kernel support (the rule of SPH_FIELD_FRAGMENT), over the
 * neighbours of the n_local particles (CSR or lists, ghosts included, each
 * joined pair listed at least once).  label (n_total, in/out): each
 * joinable particle gets the least label of its region as far as this
 * call sees it, the others -1; *changed is 1 if a local label changed.
 * With labels starting at a global number (the LAMMPS plugin: the atom
 * ID) and the ghosts' labels brought up to date before each round, the
 * fixed point gives each fragment the least number of its particles.
 * Positions are used as given (ghosts already at their image). */
SPH_API sph_status sph_damage_fragment_labels(sph_sim *sim, const sph_particles *particles,
                                              const sph_neighbours *neighbours,
                                              const unsigned char *member, double *label,
                                              int *changed);

/* Probe interpolation split for distributed particles: add the
 * contributions of particles [0, n_local) to `sums`
 * (SPH_PROBE_VALUES(dim) + 1 doubles, zeroed by the caller; add the sums of
 * all ranks together), then turn the total into values with
 * sph_probe_finish().  Gives the same values as sph_probe_sample(). */
SPH_API sph_status sph_probe_accumulate(sph_sim *sim, const sph_particles *particles,
                                        const double *point, double *sums);
SPH_API sph_status sph_probe_finish(sph_sim *sim, const double *sums, double *values);

#ifdef __cplusplus
}
#endif

#endif /* SPHSOLID_H */
