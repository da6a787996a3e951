/*
 * sphsolid/scenes.h - the paper's scene, built in one call.
 * Part of the public API of libsphsolid: include <sphsolid.h>, which
 * includes every part in order (its conventions hold for all).
 */
#ifndef SPHSOLID_PUBLIC_SCENES_H
#define SPHSOLID_PUBLIC_SCENES_H

#include "sphsolid/io.h"

#ifdef __cplusplus
extern "C" {
#endif

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

#ifdef __cplusplus
}
#endif

#endif /* SPHSOLID_PUBLIC_SCENES_H */
