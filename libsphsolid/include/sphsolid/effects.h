/*
 * sphsolid/effects.h - effects: switched on by name, with key=value parameters.
 * Part of the public API of libsphsolid: include <sphsolid.h>, which
 * includes every part in order (its conventions hold for all).
 */
#ifndef SPHSOLID_PUBLIC_EFFECTS_H
#define SPHSOLID_PUBLIC_EFFECTS_H

#include "sphsolid/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

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

#ifdef __cplusplus
}
#endif

#endif /* SPHSOLID_PUBLIC_EFFECTS_H */
