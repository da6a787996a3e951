/* Effects: the public calls (the registry and parameters are in effects.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "physics/kernel.h"
#include "core/sim.h"

/* --------------------------------------------------------------- effects */

sph_status sph_effect(sph_sim *sim, const char *name, const char *parameters)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    sph_status st = effects_set(sim, name, parameters);
    if (st)
        return st;
    damage_redraw(sim); /* no-op unless damage is on and drawn */
    sim->rates_valid = 0;
    sim->power_carry_valid = 0;
    return sph_ok(sim);
}

sph_status sph_effect_off(sph_sim *sim, const char *name)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    sph_status st = effects_off(sim, name);
    if (st)
        return st;
    if (!sim->fx.damage)
        damage_free(sim);
    sim->rates_valid = 0;
    sim->power_carry_valid = 0;
    return sph_ok(sim);
}

int sph_effect_is_on(const sph_sim *sim, const char *name)
{
    return sim ? effects_is_on(&sim->fx, name) : -1;
}
