/* Error reporting: every failing call leaves a message on its handle. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "core/sim.h"

sph_status sph_fail(sph_sim *sim, sph_status status, const char *fmt, ...)
{
    if (sim) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(sim->errmsg, sizeof sim->errmsg, fmt, ap);
        va_end(ap);
    }
    return status;
}

const char *sph_clip(char *out, const char *text)
{
    size_t k = 0;
    for (; text[k] && k < SPH_CLIP; ++k)
        out[k] = (unsigned char)text[k] < 32 || text[k] == 127 ? '?' : text[k];
    out[k] = '\0';
    if (text[k])
        snprintf(out + k, 40, "... (%zu characters)", k + strlen(text + k));
    return out;
}

sph_status sph_need(sph_sim *sim, const void *p, const char *fn, const char *name)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    return p ? SPH_OK : sph_fail(sim, SPH_ERR_ARGUMENT, "%s: %s is NULL", fn, name);
}

sph_status sph_ok(sph_sim *sim)
{
    if (sim)
        sim->errmsg[0] = '\0';
    return SPH_OK;
}

const char *sph_errmsg(const sph_sim *sim)
{
    return sim ? sim->errmsg : "no simulation handle (NULL)";
}

const char *sph_status_name(sph_status status)
{
    switch (status) {
    case SPH_OK: return "ok";
    case SPH_ERR_ARGUMENT: return "bad argument";
    case SPH_ERR_MEMORY: return "out of memory";
    case SPH_ERR_STATE: return "invalid state";
    case SPH_ERR_IO: return "input/output error";
    case SPH_ERR_NONFINITE: return "non-finite value";
    case SPH_ERR_UNSUPPORTED: return "not supported in this build";
    case SPH_ERR_STOPPED: return "stopped by callback";
    case SPH_ERR_DOMAIN: return "particle left the domain";
    case SPH_ERR_UNSTABLE: return "run went unstable";
    }
    return "unknown status";
}

const char *sph_version(void)
{
    return SPHSOLID_VERSION_STRING
#ifdef _OPENMP
        " openmp"
#endif
#ifdef SPHSOLID_HAVE_HDF5
        " hdf5"
#endif
        ;
}
