/* Builds against the installed header and library and runs ten steps of
 * the paper scene; exits non-zero on any library error. */
#include <stdio.h>

#include <sphsolid.h>

int main(void)
{
    sph_sim *sim = NULL;
    sph_paper_scene scene;
    if (sph_create(2, &sim) || sph_build_paper_scene(sim, 4e-3, 1.5e-3, 0, &scene) ||
        sph_run(sim, 10)) {
        fprintf(stderr, "consumer: %s\n", sph_errmsg(sim));
        sph_destroy(sim);
        return 1;
    }
    printf("consumer: libsphsolid %s, %zu particles, t = %g s\n", sph_version(),
           sph_particle_count(sim), sph_time(sim));
    sph_destroy(sim);
    return 0;
}
