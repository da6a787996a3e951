/* Ready-made scenes: the paper's uniaxial piston test and gravity case. */
#include <math.h>

#include "core/sim.h"

sph_status sph_build_paper_scene(sph_sim *sim, double dx, double piston_speed, int gravity_only,
                                 sph_paper_scene *scene)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (sim->dim != 2)
        return sph_fail(sim, SPH_ERR_STATE,
                        "the paper scene is 2D (plane strain); this simulation is %dD", sim->dim);
    if (sim->n_bodies != 0)
        return sph_fail(sim, SPH_ERR_STATE,
                        "the paper scene needs an empty simulation (it has %d bodies)",
                        sim->n_bodies);
    if (!(dx > 0.0) || !isfinite(dx) || dx > 0.02)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "dx=%g m: must be in (0, 0.02] m", dx);
    if (!isfinite(piston_speed) || piston_speed < 0.0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "piston_speed=%g m/s: must be finite and >= 0",
                        piston_speed);

    const double width = 0.086, height = 0.140;
    sph_paper_scene s = {.specimen = -1,
                         .piston = -1,
                         .plate = -1,
                         .material = -1,
                         .probe_A = -1,
                         .probe_B = -1,
                         .probe_C = -1};
    sph_status st = sph_add_material_K_mu(sim, 12.2e9, 2.67e9, 2300.0, &s.material);
    if (st)
        return st;
    const double lo[3] = {-0.5 * width, 0.0, 0.0}, hi[3] = {0.5 * width, height, 0.0};
    if ((st = sph_add_block(sim, "specimen", s.material, lo, hi, dx, &s.specimen)))
        return st;
    /* Plate and piston: the specimen's lattice columns and row spacing, at
     * least one kernel support thick (sph_support_layers). */
    if ((st = sph_add_plate(sim, "plate", s.material, s.specimen, 0, &s.plate)))
        return st;
    if (!gravity_only) {
        if ((st =
                 sph_add_piston(sim, "piston", s.material, s.specimen, 0, piston_speed, &s.piston)))
            return st;
    } else {
        if ((st = sph_effect(sim, "gravity", "gy=-9.81")))
            return st;
    }
    const double A[2] = {0.0, 0.070}, B[2] = {0.0215, 0.1035}, C[2] = {0.0215, 0.070};
    if ((st = sph_add_probe(sim, "A", A, &s.probe_A)) ||
        (st = sph_add_probe(sim, "B", B, &s.probe_B)) ||
        (st = sph_add_probe(sim, "C", C, &s.probe_C)))
        return st;
    if (scene)
        *scene = s;
    return sph_ok(sim);
}
