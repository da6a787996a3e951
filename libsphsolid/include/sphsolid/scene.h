/*
 * sphsolid/scene.h - materials, bodies, the domain and the kernel.
 * Part of the public API of libsphsolid: include <sphsolid.h>, which
 * includes every part in order (its conventions hold for all).
 */
#ifndef SPHSOLID_PUBLIC_SCENE_H
#define SPHSOLID_PUBLIC_SCENE_H

#include "sphsolid/core.h"

#ifdef __cplusplus
extern "C" {
#endif

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

/* The registry of the keys sph_material_set takes, for front ends that
 * read material keys from their users (scene files): key k in
 * [0, sph_material_key_count()) has a name, its SI unit ("" when it is a
 * pure number), a description, the value a material has until it is set,
 * and the closed range [min, max] it must lie in (HUGE_VAL: unbounded).
 * sph_material_key_get returns SPH_ERR_ARGUMENT for a k out of range or a
 * NULL info. */
typedef struct sph_material_key_info {
    const char *key;
    const char *unit;
    const char *description;
    double default_value;
    double min, max;
} sph_material_key_info;

SPH_API int sph_material_key_count(void);
SPH_API sph_status sph_material_key_get(int key, sph_material_key_info *info);

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

#ifdef __cplusplus
}
#endif

#endif /* SPHSOLID_PUBLIC_SCENE_H */
