/*
 * Internal interface of the HDF5 files (layout: docs/hdf5_layout.md): the
 * shared helpers (io_hdf5.c), output (io_output.c), reading outputs and
 * comparing scenes (io_read.c) and checkpoints (io_checkpoint.c).
 */
#ifndef SPHSOLID_IO_HDF5_H
#define SPHSOLID_IO_HDF5_H

#include "core/sim.h"

/* The version of the layout this library writes.  Version 1 files (before
 * the version was recorded) have no `sphsolid_format` attribute. */
#define SPH_FILE_FORMAT 2L

/* The page a rewrite in place must not cross (see io_hdf5.c). */
#define IO_PAGE 4096u

#define NO_HDF5(sim) sph_fail(sim, SPH_ERR_UNSUPPORTED, "libsphsolid was built without HDF5")

#ifdef SPHSOLID_HAVE_HDF5
#include <hdf5.h>

/* HDF5's automatic error printing, saved while the library's calls run and
 * restored afterwards: the host's handler is never lost. */
typedef struct quiet {
    H5E_auto2_t func;
    void *data;
} quiet;

/* One read or write of a file: the first failure is kept with the object
 * it concerned and its cause. */
typedef struct io {
    int failed;
    char what[160];
    char cause[256];
} io;

/* Scratch copies of the state a read fills before anything is committed. */
typedef struct state_copy {
    double *x, *v, *rho, *S, *mass, *motion;
    double *dv, *drho, *dS; /* rates an integrator carries, if any */
} state_copy;

/* io_hdf5.c: error capture, writing, scene records */
void io_quiet_begin(quiet *q);
void io_quiet_end(const quiet *q);
int io_fail_at(io *c, const char *what, int use_errno);
int io_fail_memory(io *c, const char *what, size_t bytes);
int io_ok(io *c, long long result, const char *what);
void io_close_id(hid_t id);
int io_write_attr(io *c, hid_t obj, const char *name, hid_t type, hid_t space, const void *data);
int io_attr_double(io *c, hid_t obj, const char *name, const double *v, hsize_t n);
int io_attr_long(io *c, hid_t obj, const char *name, long v);
int io_attr_string(io *c, hid_t obj, const char *name, const char *text);
int io_attr_long_update(io *c, hid_t obj, const char *name, long v);
hid_t io_group_create(io *c, hid_t loc, const char *name);
int io_group_close(io *c, hid_t g, const char *name);
int io_write_dataset(io *c, hid_t loc, const char *name, hid_t type, int rank, const hsize_t *dims,
                     const void *data);
int io_series_create(io *c, hid_t loc, const char *name, int rank, const hsize_t *inner,
                     hsize_t value_rows);
int io_series_append_rows(io *c, hid_t loc, const char *path, hsize_t rows, const long *step,
                          const double *time, const double *value);
int io_series_append(io *c, hid_t loc, const char *path, long step, double time,
                     const double *value);
hid_t io_file_create(io *c, const char *path, int in_memory);
const char *io_motion_name(sph_motion m);
int io_write_format(io *c, hid_t file, const char *content);
int io_write_parameters(io *c, sph_sim *sim, hid_t file);

/* io_read.c: reading, scene comparison */
int io_read_attr_long(hid_t obj, const char *name, long *v);
int io_read_attr_string(hid_t obj, const char *name, char *buf, size_t size);
int io_read_attr_doubles(hid_t obj, const char *name, double *v, size_t size, size_t *count);
sph_status io_open_checked(sph_sim *sim, const char *path, const char *content, hid_t *file,
                           long *version_out);
/* A file being read into a simulation: HDF5's messages off (q), the file
 * and its format version. */
typedef struct reading {
    quiet q;
    hid_t f;
    long version;
} reading;
sph_status io_read_open(sph_sim *sim, const char *path, const char *content, const char *written,
                        reading *r);
sph_status io_scene_matches(sph_sim *sim, hid_t f, const char *path, int with_effects,
                            long version);
int io_read_doubles(io *c, hid_t loc, const char *name, long frame, size_t expect, double *out);
long io_first_nonfinite(const double *a, size_t n);
int io_state_alloc(state_copy *s, const sph_sim *sim);
int io_state_read(io *c, hid_t loc, const char *const names[4], long frame, const sph_sim *sim,
                  state_copy *s);
void io_read_release(const quiet *q, state_copy *s, hid_t group, hid_t file);
void io_state_commit(sph_sim *sim, const state_copy *s, long step, double time);
int io_state_plausible(sph_sim *sim, const state_copy *s, const char *path, int with_mass);

#endif
#endif
