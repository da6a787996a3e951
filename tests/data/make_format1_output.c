/*
 * Writes tests/data/format1_output.h5: an output file of libsphsolid 0.1.0
 * (file format 1, before the format was versioned), for the reader's test
 * of old files (tests/c/test_faults.c builds the same scene with the
 * current API).  Built against the library of 0.1.0 (the parent of the
 * commit "Version 0.2.0 ..."), not by this tree's build:
 *   git archive <commit> | tar -x -C /tmp/v010 && cd /tmp/v010 &&
 *   cmake -S . -B b -DSPHSOLID_TESTS=OFF -DSPHSOLID_EXAMPLES=OFF -DSPHSOLID_BENCH=OFF \
 *         -DSPHSOLID_LAMMPS_PLUGIN=OFF -DSPHSOLID_OPENMP=OFF && cmake --build b &&
 *   cc make_format1_output.c -Ilibsphsolid/include -Ib/libsphsolid b/libsphsolid/libsphsolid.a \
 *      -L/usr/lib/x86_64-linux-gnu/hdf5/serial -lhdf5 -lm -o gen && ./gen format1_output.h5
 * A free 2D block of 6 x 4 particles (1 mm, K 12.2 GPa, mu 2.67 GPa,
 * rho0 2300 kg/m^3) pushed down at 1 m/s, one probe at its centre, dt
 * 1e-7 s, a snapshot and a probe sample every step for 3 steps.
 */
#include <stdio.h>

#include "sphsolid.h"

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "format1_output.h5";
    sph_sim *sim = NULL;
    int mat, body;
    const double lo[3] = {0, 0, 0}, hi[3] = {6e-3, 4e-3, 0}, v[3] = {0, -1.0, 0};
    const double point[3] = {3e-3, 2e-3, 0};
    if (sph_create(2, &sim) || sph_add_material_K_mu(sim, 12.2e9, 2.67e9, 2300.0, &mat) ||
        sph_add_block(sim, "block", mat, lo, hi, 1e-3, &body) ||
        sph_set_body_velocity(sim, body, v) || sph_add_probe(sim, "centre", point, NULL) ||
        sph_set_dt(sim, 1e-7, 0) || sph_output_open(sim, path, 1, 1) || sph_run(sim, 3) ||
        sph_output_close(sim)) {
        fprintf(stderr, "%s\n", sim ? sph_errmsg(sim) : "no handle");
        return 1;
    }
    printf("%s written by libsphsolid %s\n", path, sph_version());
    sph_destroy(sim);
    return 0;
}
