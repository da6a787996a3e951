/* The registry of the material keys that sph_material_set takes: their
 * names, units, descriptions, defaults and ranges, for front ends that
 * read keys from their users (scene files, decks) and must know them all.
 * A key sph_material_set learns is added here too:
 * tests/c/test_bad_input.c checks that the two agree (each key here is
 * taken at its default and at its bounds and refused beyond them, and the
 * setter's list of known keys is this one). */
#include <math.h>

#include "core/sim.h"

static const sph_material_key_info keys[] = {
    {"weibull_k", "m^-3",
     "flaws per volume of the Weibull law n(eps) = k V eps^m of the effect damage (2D: per "
     "metre of depth); 0: no flaws",
     0.0, 0.0, HUGE_VAL},
    {"weibull_m", "", "exponent m of the Weibull flaw law of the effect damage; 0: no flaws", 0.0,
     0.0, HUGE_VAL},
};

int sph_material_key_count(void) { return (int)(sizeof keys / sizeof keys[0]); }

sph_status sph_material_key_get(int key, sph_material_key_info *info)
{
    if (key < 0 || key >= sph_material_key_count() || !info)
        return SPH_ERR_ARGUMENT;
    *info = keys[key];
    return SPH_OK;
}
