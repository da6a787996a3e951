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

/* One include for users.  The API is split by job into the parts below,
   each including the ones before it. */
#include "sphsolid/core.h"
#include "sphsolid/scene.h"
#include "sphsolid/effects.h"
#include "sphsolid/integrators.h"
#include "sphsolid/fields.h"
#include "sphsolid/io.h"
#include "sphsolid/scenes.h"
#include "sphsolid/rates.h"

#endif /* SPHSOLID_H */
