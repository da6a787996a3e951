/*
 * sphsolid/core.h - the handle, its status codes and its messages.
 * Part of the public API of libsphsolid: include <sphsolid.h>, which
 * includes every part in order (its conventions hold for all).
 */
#ifndef SPHSOLID_PUBLIC_CORE_H
#define SPHSOLID_PUBLIC_CORE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(SPHSOLID_BUILDING) && defined(__GNUC__)
#define SPH_API __attribute__((visibility("default")))
#else
#define SPH_API
#endif
/* Marks a deprecated alias: compilers warn where it is used. */
#if defined(__GNUC__) || defined(__clang__)
#define SPH_DEPRECATED(replacement) __attribute__((deprecated("use " replacement)))
#else
#define SPH_DEPRECATED(replacement)
#endif

/* SPHSOLID_VERSION_MAJOR/_MINOR/_PATCH and SPHSOLID_VERSION_STRING, as
 * sph_version() reports them. */
#include "sphsolid_version.h"

/* Number of stored deviatoric stress components per particle. */
#define SPH_STRESS_COMPONENTS(dim) ((dim) == 2 ? 4 : 6)

typedef enum sph_status {
    SPH_OK = 0,
    SPH_ERR_ARGUMENT = 1,    /* a bad value was passed; the message names it */
    SPH_ERR_MEMORY = 2,      /* allocation failed */
    SPH_ERR_STATE = 3,       /* call not valid in the current state */
    SPH_ERR_IO = 4,          /* file could not be read or written */
    SPH_ERR_NONFINITE = 5,   /* the run produced a non-finite value */
    SPH_ERR_UNSUPPORTED = 6, /* feature not compiled in (e.g. HDF5) */
    SPH_ERR_STOPPED = 7,     /* a progress callback asked the run to stop */
    SPH_ERR_DOMAIN = 8,      /* a particle left the domain */
    SPH_ERR_UNSTABLE = 9     /* the watchdog saw a runaway speed or density */
} sph_status;

typedef struct sph_sim sph_sim;

/* ---------------------------------------------------------------- handle */

/* Create a simulation in `dimension` (2 or 3) dimensions.  On a bad
 * dimension *sim still receives a handle that carries the message (like
 * sqlite3_open); destroy it with sph_destroy().  *sim is NULL only when
 * memory ran out. */
SPH_API sph_status sph_create(int dimension, sph_sim **sim);
SPH_API void sph_destroy(sph_sim *sim);

/* Message for the last failed call on this handle ("" after success). */
SPH_API const char *sph_errmsg(const sph_sim *sim);
/* Static name of a status code. */
SPH_API const char *sph_status_name(sph_status status);
/* The version and the compiled-in options, e.g. "0.2.0 openmp hdf5". */
SPH_API const char *sph_version(void);

SPH_API int sph_dimension(const sph_sim *sim);

/* Number of OpenMP threads used by this handle (0 = OpenMP default).
 * Results do not depend on it.  More than SPH_THREADS_PER_CORE per core
 * the process may use (omp_get_num_procs) are refused. */
#define SPH_THREADS_PER_CORE 8
SPH_API sph_status sph_set_threads(sph_sim *sim, int threads);

#ifdef __cplusplus
}
#endif

#endif /* SPHSOLID_PUBLIC_CORE_H */
