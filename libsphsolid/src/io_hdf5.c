/*
 * HDF5 output, read-back and checkpoints (layout: docs/hdf5_layout.md).
 * The file follows H5MD conventions where they fit: time series are groups
 * holding `step`, `time` and `value` datasets extended frame by frame.
 *
 * Integrity (docs/reliability.md):
 *   - every HDF5 call that writes, flushes or closes is checked; the first
 *     failure is reported with the file, the object and the cause HDF5 or
 *     the operating system gave (e.g. "No space left on device");
 *   - files carry a format version (root attribute `sphsolid_format`), HDF5's
 *     Fletcher32 checksum on every dataset and checksummed metadata (the
 *     HDF5 1.8 file format), so a reader refuses corrupt or foreign files;
 *   - output frames count only once flushed: `complete_frames` is raised
 *     after the frame's data reached the file, so a full disk or a killed
 *     process leaves every earlier frame readable;
 *   - checkpoints are built in memory, written to a fresh temporary file,
 *     synced, closed and renamed over the target: a failure leaves the
 *     previous checkpoint in place;
 *   - readers compare the file's scene (dimension, materials, bodies' names,
 *     particle ranges, shapes, materials and motions) with the simulation,
 *     read into scratch arrays and only then change the simulation;
 *   - HDF5's automatic error printing is switched off only while the
 *     library's own calls run (saved and restored), never for the process.
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp, fsync, fchmod */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "integrator.h"
#include "sim.h"

/* The version of the layout this library writes.  Version 1 files (before
 * the version was recorded) have no `sphsolid_format` attribute. */
#define SPH_FILE_FORMAT 2L

int sph_output_format_version(void) { return (int)SPH_FILE_FORMAT; }

#ifdef SPHSOLID_HAVE_HDF5
#include <fcntl.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

/* Probe samples are kept in memory and appended to the file PROBE_BLOCK at
 * a time, and whenever the file is committed (output_commit), so a reader
 * sees the same samples as if each were appended when taken: it trusts
 * only the samples counted at the last commit. */
#define PROBE_BLOCK 256

struct output_file {
    hid_t file;
    long snapshot_interval, probe_interval;
    long frames, probe_frames; /* probe_frames counts the pending samples */
    long last_snapshot_step, last_probe_step;
    long pending;       /* probe samples not yet in the file */
    long *pending_step; /* PROBE_BLOCK each */
    double *pending_time, *pending_value;
    int failed; /* a write failed: the file takes no more */
    char error[SPH_ERRMSG_SIZE];
    char *path;
    dev_t dev; /* the open file's identity (fstat), to tell when the path */
    ino_t ino; /* no longer names it (removed or replaced during a run) */
};

/* ----------------------------------------------------- error capture */

/* HDF5's automatic error printing, saved while the library's calls run and
 * restored afterwards: the host's handler is never lost. */
typedef struct quiet {
    H5E_auto2_t func;
    void *data;
} quiet;

static void quiet_begin(quiet *q)
{
    q->func = NULL;
    q->data = NULL;
    H5Eget_auto2(H5E_DEFAULT, &q->func, &q->data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

static void quiet_end(const quiet *q)
{
    H5Eclear2(H5E_DEFAULT);
    H5Eset_auto2(H5E_DEFAULT, q->func, q->data);
}

/* One read or write of a file: the first failure is kept with the object
 * it concerned and its cause. */
typedef struct io {
    int failed;
    char what[160];
    char cause[256];
} io;

static herr_t innermost_error(unsigned n, const H5E_error2_t *e, void *data)
{
    char *out = data;
    if (n != 0 || !e)
        return 0;
    const char *desc = e->desc ? e->desc : "";
    const char *key = "error message = '";
    const char *p = strstr(desc, key);
    if (p) {
        p += strlen(key);
        snprintf(out, 256, "%.*s", (int)strcspn(p, "'"), p);
    } else if (*desc) {
        snprintf(out, 256, "%s", desc);
    } else {
        char minor[128] = "";
        H5Eget_msg(e->min_num, NULL, minor, sizeof minor);
        snprintf(out, 256, "%s", minor);
    }
    return 0;
}

/* Records a failure of `what` (the cause from HDF5's error stack, or from
 * errno when `use_errno`); returns -1 so callers can write
 * `if (fail_at(c, ...)) ...`. */
static int fail_at(io *c, const char *what, int use_errno)
{
    if (!c->failed) {
        c->failed = 1;
        snprintf(c->what, sizeof c->what, "%s", what);
        c->cause[0] = '\0';
        if (use_errno)
            snprintf(c->cause, sizeof c->cause, "%s", strerror(errno));
        else
            H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost_error, c->cause);
        if (!c->cause[0])
            snprintf(c->cause, sizeof c->cause, "HDF5 reported an error");
    }
    H5Eclear2(H5E_DEFAULT);
    return -1;
}

/* Records an allocation failure for `what` (`bytes` named when known). */
static int fail_memory(io *c, const char *what, size_t bytes)
{
    if (!c->failed) {
        c->failed = 1;
        snprintf(c->what, sizeof c->what, "%s", what);
        if (bytes)
            snprintf(c->cause, sizeof c->cause, "out of memory (%zu bytes)", bytes);
        else
            snprintf(c->cause, sizeof c->cause, "out of memory");
    }
    return -1;
}

/* Checks one HDF5 call's result (negative: failure). */
static int ok(io *c, long long result, const char *what)
{
    if (result < 0) {
        fail_at(c, what, 0);
        return 0;
    }
    return !c->failed;
}

static void close_id(hid_t id)
{
    if (id < 0)
        return;
    switch (H5Iget_type(id)) {
    case H5I_FILE: H5Fclose(id); break;
    case H5I_GROUP: H5Gclose(id); break;
    case H5I_DATASET: H5Dclose(id); break;
    case H5I_DATASPACE: H5Sclose(id); break;
    case H5I_DATATYPE: H5Tclose(id); break;
    case H5I_ATTR: H5Aclose(id); break;
    case H5I_GENPROP_LST: H5Pclose(id); break;
    default: break;
    }
}

/* ------------------------------------------------------------ writing */

static int write_attr(io *c, hid_t obj, const char *name, hid_t type, hid_t space, const void *data)
{
    if (c->failed)
        return -1;
    hid_t a = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    if (!ok(c, a, name)) {
        close_id(a);
        return -1;
    }
    ok(c, H5Awrite(a, type, data), name);
    ok(c, H5Aclose(a), name);
    return c->failed ? -1 : 0;
}

static int attr_double(io *c, hid_t obj, const char *name, const double *v, hsize_t n)
{
    hid_t space = H5Screate_simple(1, &n, NULL);
    if (!ok(c, space, name))
        return -1;
    write_attr(c, obj, name, H5T_NATIVE_DOUBLE, space, v);
    H5Sclose(space);
    return c->failed ? -1 : 0;
}

/* A scalar attribute of a native type (H5T_NATIVE_LONG, _DOUBLE). */
static int attr_scalar(io *c, hid_t obj, const char *name, hid_t type, const void *v)
{
    hid_t space = H5Screate(H5S_SCALAR);
    if (!ok(c, space, name))
        return -1;
    write_attr(c, obj, name, type, space, v);
    H5Sclose(space);
    return c->failed ? -1 : 0;
}

static int attr_long(io *c, hid_t obj, const char *name, long v)
{
    return attr_scalar(c, obj, name, H5T_NATIVE_LONG, &v);
}

static int attr_string(io *c, hid_t obj, const char *name, const char *text)
{
    hid_t type = H5Tcopy(H5T_C_S1);
    hid_t space = H5Screate(H5S_SCALAR);
    if (ok(c, type, name) && ok(c, space, name) && ok(c, H5Tset_size(type, strlen(text) + 1), name))
        write_attr(c, obj, name, type, space, text);
    close_id(space);
    close_id(type);
    return c->failed ? -1 : 0;
}

/* Overwrites an existing scalar long attribute. */
static int attr_long_update(io *c, hid_t obj, const char *name, long v)
{
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    if (ok(c, a, name))
        ok(c, H5Awrite(a, H5T_NATIVE_LONG, &v), name);
    if (a >= 0)
        ok(c, H5Aclose(a), name);
    return c->failed ? -1 : 0;
}

static hid_t group_create(io *c, hid_t loc, const char *name)
{
    if (c->failed)
        return -1;
    hid_t g = H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ok(c, g, name);
    return g;
}

static int group_close(io *c, hid_t g, const char *name)
{
    if (g >= 0)
        ok(c, H5Gclose(g), name);
    return c->failed ? -1 : 0;
}

/* A fixed-size dataset, chunked (about 1 MiB per chunk) so that HDF5's
 * Fletcher32 filter checks every block of it on reading. */
static int write_dataset(io *c, hid_t loc, const char *name, hid_t type, int rank,
                         const hsize_t *dims, const void *data)
{
    if (c->failed)
        return -1;
    hid_t space = H5Screate_simple(rank, dims, NULL);
    hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
    hid_t d = -1;
    if (ok(c, space, name) && ok(c, plist, name)) {
        hsize_t chunk[4], row = H5Tget_size(type), total = 1;
        for (int i = 0; i < rank; ++i)
            total *= dims[i];
        for (int i = 1; i < rank; ++i) {
            chunk[i] = dims[i];
            row *= dims[i];
        }
        chunk[0] = (hsize_t)1 << 20;
        chunk[0] = row ? chunk[0] / row : 1;
        if (chunk[0] < 1)
            chunk[0] = 1;
        if (chunk[0] > dims[0])
            chunk[0] = dims[0];
        if (total > 0) {
            ok(c, H5Pset_chunk(plist, rank, chunk), name);
            ok(c, H5Pset_fletcher32(plist), name);
        }
        if (!c->failed) {
            d = H5Dcreate2(loc, name, type, space, H5P_DEFAULT, plist, H5P_DEFAULT);
            if (ok(c, d, name) && total > 0)
                ok(c, H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), name);
            if (d >= 0)
                ok(c, H5Dclose(d), name);
        }
    }
    close_id(plist);
    close_id(space);
    return c->failed ? -1 : 0;
}

/* An H5MD time series: group with extendible step, time and value, each
 * chunked and checksummed (value in chunks of value_rows records). */
static int series_create(io *c, hid_t loc, const char *name, int rank, const hsize_t *inner,
                         hsize_t value_rows)
{
    hid_t g = group_create(c, loc, name);
    hsize_t dims[4] = {0}, maxd[4] = {H5S_UNLIMITED}, chunk[4] = {1};
    for (int i = 0; i < rank; ++i)
        dims[i + 1] = maxd[i + 1] = chunk[i + 1] = inner[i];
    const char *names[3] = {"step", "time", "value"};
    for (int k = 0; k < 3 && !c->failed; ++k) {
        const int r = k < 2 ? 1 : rank + 1;
        hsize_t c1[4];
        memcpy(c1, chunk, sizeof c1);
        c1[0] = k < 2 ? 256 : value_rows;
        char what[160];
        snprintf(what, sizeof what, "%s/%s", name, names[k]);
        hid_t space = H5Screate_simple(r, dims, maxd);
        hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
        if (ok(c, space, what) && ok(c, plist, what) && ok(c, H5Pset_chunk(plist, r, c1), what) &&
            ok(c, H5Pset_fletcher32(plist), what)) {
            hid_t d = H5Dcreate2(g, names[k], k == 0 ? H5T_NATIVE_LONG : H5T_NATIVE_DOUBLE, space,
                                 H5P_DEFAULT, plist, H5P_DEFAULT);
            if (ok(c, d, what))
                ok(c, H5Dclose(d), what);
        }
        close_id(plist);
        close_id(space);
    }
    return group_close(c, g, name);
}

static int extend_append(io *c, hid_t g, const char *group, const char *name, hid_t type,
                         hsize_t rows, const void *data)
{
    char what[160];
    snprintf(what, sizeof what, "%s/%s", group, name);
    hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
    if (!ok(c, d, what))
        return -1;
    hid_t space = H5Dget_space(d), mem = -1;
    hsize_t dims[4] = {0}, start[4] = {0}, count[4];
    const int rank = space >= 0 ? H5Sget_simple_extent_dims(space, dims, NULL) : -1;
    close_id(space);
    space = -1;
    if (ok(c, rank, what)) {
        start[0] = dims[0];
        dims[0] += rows;
        memcpy(count, dims, sizeof count);
        count[0] = rows;
        if (ok(c, H5Dset_extent(d, dims), what) && ok(c, space = H5Dget_space(d), what) &&
            ok(c, H5Sselect_hyperslab(space, H5S_SELECT_SET, start, NULL, count, NULL), what) &&
            ok(c, mem = H5Screate_simple(rank, count, NULL), what))
            ok(c, H5Dwrite(d, type, mem, space, H5P_DEFAULT, data), what);
    }
    close_id(mem);
    close_id(space);
    ok(c, H5Dclose(d), what);
    return c->failed ? -1 : 0;
}

/* Appends `rows` records (steps, times, values one after another). */
static int series_append_rows(io *c, hid_t loc, const char *path, hsize_t rows, const long *step,
                              const double *time, const double *value)
{
    hid_t g = H5Gopen2(loc, path, H5P_DEFAULT);
    if (!ok(c, g, path)) {
        close_id(g);
        return -1;
    }
    extend_append(c, g, path, "step", H5T_NATIVE_LONG, rows, step);
    extend_append(c, g, path, "time", H5T_NATIVE_DOUBLE, rows, time);
    extend_append(c, g, path, "value", H5T_NATIVE_DOUBLE, rows, value);
    group_close(c, g, path);
    return c->failed ? -1 : 0;
}

static int series_append(io *c, hid_t loc, const char *path, long step, double time,
                         const double *value)
{
    return series_append_rows(c, loc, path, 1, &step, &time, value);
}

/* File access: output files in the HDF5 1.8 format (checksummed metadata;
 * readable by HDF5 1.8 and later and by h5py); checkpoints built in memory
 * (no disk access by HDF5: the image is written by write_image) in the
 * oldest format that holds them, whose in-memory image HDF5 1.10 hands out
 * intact.  Closing a file closes everything in it. */
static hid_t file_access(io *c, int in_memory)
{
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    if (ok(c, fapl, "file access properties") &&
        ok(c,
           H5Pset_libver_bounds(fapl, in_memory ? H5F_LIBVER_EARLIEST : H5F_LIBVER_V18,
                                H5F_LIBVER_V18),
           "file format") &&
        ok(c, H5Pset_fclose_degree(fapl, H5F_CLOSE_STRONG), "file access properties") &&
        (!in_memory || ok(c, H5Pset_fapl_core(fapl, (size_t)1 << 16, 0), "in-memory file")))
        return fapl;
    close_id(fapl);
    return -1;
}

/* Creates (or truncates) `path` with the access properties of file_access;
 * -1 with the cause in c on failure. */
static hid_t file_create(io *c, const char *path, int in_memory)
{
    hid_t fapl = file_access(c, in_memory);
    hid_t file = -1;
    if (!c->failed) {
        file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
        ok(c, file, "the file (create)");
    }
    close_id(fapl);
    return file;
}

/* ------------------------------------------------------ scene records */

static const char *motion_name(sph_motion m)
{
    switch (m) {
    case SPH_MOTION_FREE: return "free";
    case SPH_MOTION_FIXED: return "fixed";
    case SPH_MOTION_VELOCITY: return "velocity";
    case SPH_MOTION_FORCE: return "force";
    case SPH_MOTION_ROTATION: return "rotation";
    }
    return "unknown";
}

static int write_format(io *c, hid_t file, const char *content)
{
    attr_long(c, file, "sphsolid_format", SPH_FILE_FORMAT);
    attr_string(c, file, "sphsolid_content", content);
    return c->failed ? -1 : 0;
}

/* /parameters/effects: a group per effect that is on, named as in the
 * registry (effects.c), holding one float64 attribute per parameter. */
static int write_effects(io *c, sph_sim *sim, hid_t par)
{
    hid_t all = group_create(c, par, "effects");
    for (int k = 0; k < sph_effect_count() && !c->failed; ++k) {
        sph_effect_info e;
        double values[EFFECTS_MAX_PARAMETERS];
        if (sph_effect_info_get(k, &e) || !effects_values(&sim->fx, k, values))
            continue;
        hid_t g = group_create(c, all, e.name);
        for (int j = 0; j < e.parameter_count; ++j) {
            sph_effect_parameter p;
            if (!sph_effect_parameter_get(k, j, &p))
                attr_scalar(c, g, p.key, H5T_NATIVE_DOUBLE, &values[j]);
        }
        group_close(c, g, e.name);
    }
    group_close(c, all, "parameters/effects");
    return c->failed ? -1 : 0;
}

/* /parameters: the model and the scene's bodies; readers compare it with
 * the simulation they load into. */
static int write_parameters(io *c, sph_sim *sim, hid_t file)
{
    const int dim = sim->dim, nc = sim->ncomp;
    hid_t par = group_create(c, file, "parameters");
    attr_long(c, par, "dimension", dim);
    attr_long(c, par, "stress_components", nc);
    attr_double(c, par, "smoothing_length", &sim->h, 1);
    attr_double(c, par, "spacing", &sim->dx_ref, 1);
    attr_double(c, par, "dt", &sim->dt, 1);
    attr_string(c, par, "kernel", sph_kernel_name((sph_kernel)sim->kernel));
    attr_string(c, par, "integrator", sim_integrator(sim)->name);
    {
        char fx[1024];
        effects_describe(&sim->fx, fx, sizeof fx);
        attr_string(c, par, "effects", fx);
        write_effects(c, sim, par);
    }
    attr_string(c, par, "stress_order", dim == 2 ? "xx yy zz xy" : "xx yy zz xy xz yz");
    {
        double *m = malloc((size_t)(sim->n_materials ? sim->n_materials : 1) * 3 * sizeof *m);
        if (!m) {
            fail_memory(c, "materials", 0);
        } else {
            for (int k = 0; k < sim->n_materials; ++k) {
                m[3 * k] = sim->materials[k].K;
                m[3 * k + 1] = sim->materials[k].mu;
                m[3 * k + 2] = sim->materials[k].rho0;
            }
            hsize_t d[2] = {(hsize_t)sim->n_materials, 3};
            write_dataset(c, par, "materials", H5T_NATIVE_DOUBLE, 2, d, m);
            free(m);
        }
        attr_string(c, par, "materials_columns", "bulk_modulus shear_modulus rho0");
    }
    hid_t bodies = group_create(c, par, "bodies");
    for (int k = 0; k < sim->n_bodies && !c->failed; ++k) {
        const body *b = &sim->bodies[k];
        hid_t g = group_create(c, bodies, b->name);
        attr_long(c, g, "index", k);
        attr_long(c, g, "first", (long)b->first);
        attr_long(c, g, "count", (long)b->count);
        attr_long(c, g, "material", b->material);
        attr_string(c, g, "motion", motion_name(b->motion));
        if (b->motion == SPH_MOTION_ROTATION) {
            attr_double(c, g, "angular_velocity", b->vector, 3);
            attr_double(c, g, "centre", b->centre, (hsize_t)dim);
        } else {
            attr_double(c, g, "vector", b->vector, (hsize_t)dim);
        }
        attr_double(c, g, "spacing", &b->spacing, 1);
        attr_double(c, g, "extent_lo", b->extent_lo, (hsize_t)dim);
        attr_double(c, g, "extent_hi", b->extent_hi, (hsize_t)dim);
        group_close(c, g, b->name);
    }
    group_close(c, bodies, "bodies");
    group_close(c, par, "parameters");
    return c->failed ? -1 : 0;
}

/* ------------------------------------------------------------- output */

static sph_status output_failed(sph_sim *sim, const char *action, const io *c)
{
    struct output_file *o = sim->out;
    o->failed = 1;
    sph_fail(sim, SPH_ERR_IO,
             "%s '%s' failed: %s (writing %s); the file keeps the %ld frame%s written before",
             action, o->path, c->cause, c->what, o->frames, o->frames == 1 ? "" : "s");
    memcpy(o->error, sim->errmsg, sizeof o->error);
    return SPH_ERR_IO;
}

/* Makes the frames and samples written so far count: their data is flushed
 * first, then the counts readers trust, then flushed again. */
/* The file the run writes is still the one its path names: a file removed
 * or replaced (renamed over, deleted and created again) during a run would
 * take the frames that follow with it, and an XDMF written at the end would
 * describe the other file.  Fails, and the file takes no more, if not. */
static sph_status output_still_named(sph_sim *sim)
{
    struct output_file *o = sim->out;
    if (o->failed)
        return sph_fail(sim, SPH_ERR_IO, "%s", o->error);
    struct stat now;
    if (stat(o->path, &now) != 0) {
        sph_fail(sim, SPH_ERR_IO,
                 "output file '%s' was removed during the run (%s): the %ld frame%s written "
                 "went with it; output stopped, no XDMF written",
                 o->path, strerror(errno), o->frames, o->frames == 1 ? "" : "s");
    } else if (now.st_dev != o->dev || now.st_ino != o->ino) {
        sph_fail(sim, SPH_ERR_IO,
                 "output file '%s' was replaced during the run: the path names another file "
                 "(device %llu, inode %llu; the run wrote device %llu, inode %llu) and the %ld "
                 "frame%s written are not in it; output stopped, no XDMF written",
                 o->path, (unsigned long long)now.st_dev, (unsigned long long)now.st_ino,
                 (unsigned long long)o->dev, (unsigned long long)o->ino, o->frames,
                 o->frames == 1 ? "" : "s");
    } else {
        return SPH_OK;
    }
    o->failed = 1;
    memcpy(o->error, sim->errmsg, sizeof o->error);
    return SPH_ERR_IO;
}

/* The identity of the file just created at o->path: fstat of HDF5's
 * descriptor (the sec2 driver), else stat of the path. */
static int output_identify(struct output_file *o)
{
    struct stat s;
    int *fd = NULL;
    if (H5Fget_vfd_handle(o->file, H5P_DEFAULT, (void **)&fd) >= 0 && fd && fstat(*fd, &s) == 0) {
        o->dev = s.st_dev;
        o->ino = s.st_ino;
        return 0;
    }
    if (stat(o->path, &s) != 0)
        return -1;
    o->dev = s.st_dev;
    o->ino = s.st_ino;
    return 0;
}

static int probes_append_pending(io *c, struct output_file *o)
{
    if (o->pending > 0 && series_append_rows(c, o->file, "/observables/probes", (hsize_t)o->pending,
                                             o->pending_step, o->pending_time, o->pending_value))
        return -1;
    o->pending = 0;
    return 0;
}

static int output_commit(io *c, struct output_file *o, long frames, long probe_frames)
{
    if (probes_append_pending(c, o) ||
        !ok(c, H5Fflush(o->file, H5F_SCOPE_GLOBAL), "the file (flush)"))
        return -1;
    hid_t all = H5Gopen2(o->file, "/particles/all", H5P_DEFAULT);
    if (ok(c, all, "/particles/all"))
        attr_long_update(c, all, "complete_frames", frames);
    group_close(c, all, "/particles/all");
    if (probe_frames >= 0) {
        hid_t pg = H5Gopen2(o->file, "/observables/probes", H5P_DEFAULT);
        if (ok(c, pg, "/observables/probes"))
            attr_long_update(c, pg, "complete_samples", probe_frames);
        group_close(c, pg, "/observables/probes");
    }
    ok(c, H5Fflush(o->file, H5F_SCOPE_GLOBAL), "the file (flush)");
    return c->failed ? -1 : 0;
}

static sph_status write_snapshot(sph_sim *sim)
{
    struct output_file *o = sim->out;
    if (o->failed)
        return sph_fail(sim, SPH_ERR_IO, "%s", o->error);
    const size_t n = sim->n;
    double *buf = malloc(n * (size_t)sim->ncomp * sizeof *buf);
    if (!buf)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate the snapshot buffer");
    io c = {0};
    hid_t all = H5Gopen2(o->file, "/particles/all", H5P_DEFAULT);
    if (ok(&c, all, "/particles/all")) {
        series_append(&c, all, "position", sim->step, sim->t, sim->x);
        series_append(&c, all, "velocity", sim->step, sim->t, sim->v);
        series_append(&c, all, "density", sim->step, sim->t, sim->rho);
        series_append(&c, all, "deviatoric_stress", sim->step, sim->t, sim->S);
        if (!c.failed && sph_field_copy(sim, SPH_FIELD_PRESSURE, buf) == SPH_OK)
            series_append(&c, all, "pressure", sim->step, sim->t, buf);
        if (!c.failed && sph_field_copy(sim, SPH_FIELD_VON_MISES, buf) == SPH_OK)
            series_append(&c, all, "von_mises", sim->step, sim->t, buf);
    }
    group_close(&c, all, "/particles/all");
    free(buf);
    char action[64];
    snprintf(action, sizeof action, "writing snapshot %ld to", o->frames);
    if (c.failed || output_commit(&c, o, o->frames + 1, sim->n_probes > 0 ? o->probe_frames : -1))
        return output_failed(sim, action, &c);
    o->frames++;
    o->last_snapshot_step = sim->step;
    return sph_ok(sim);
}

/* Samples the probes into the pending block (in_run: from the run driver,
 * see probe_sample_point); a full block goes to the file. */
static sph_status write_probes(sph_sim *sim, int in_run)
{
    struct output_file *o = sim->out;
    if (sim->n_probes == 0)
        return SPH_OK;
    if (o->failed)
        return sph_fail(sim, SPH_ERR_IO, "%s", o->error);
    const size_t nv = (size_t)SPH_PROBE_VALUES(sim->dim) * (size_t)sim->n_probes;
    if (!o->pending_step) {
        o->pending_step = malloc(PROBE_BLOCK * sizeof *o->pending_step);
        o->pending_time = malloc(PROBE_BLOCK * sizeof *o->pending_time);
        o->pending_value = malloc(PROBE_BLOCK * nv * sizeof *o->pending_value);
        if (!o->pending_step || !o->pending_time || !o->pending_value) {
            free(o->pending_step);
            free(o->pending_time);
            free(o->pending_value);
            o->pending_step = NULL;
            o->pending_time = NULL;
            o->pending_value = NULL;
            return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate probe values");
        }
    }
    double *values = o->pending_value + (size_t)o->pending * nv;
    for (int k = 0; k < sim->n_probes; ++k) {
        const sph_status st = probe_sample_point(
            sim, &sim->probes[k], values + (size_t)k * (nv / (size_t)sim->n_probes), in_run);
        if (st)
            return st;
    }
    o->pending_step[o->pending] = sim->step;
    o->pending_time[o->pending] = sim->t;
    o->pending++;
    o->probe_frames++;
    o->last_probe_step = sim->step;
    if (o->pending == PROBE_BLOCK) {
        io c = {0};
        if (probes_append_pending(&c, o))
            return output_failed(sim, "writing probe samples to", &c);
    }
    return SPH_OK;
}

sph_status output_write_due(sph_sim *sim)
{
    struct output_file *o = sim->out;
    const int snapshot = o->snapshot_interval > 0 && sim->step % o->snapshot_interval == 0 &&
                         o->last_snapshot_step != sim->step;
    const int probes = o->probe_interval > 0 && sim->step % o->probe_interval == 0 &&
                       o->last_probe_step != sim->step;
    if (!snapshot && !probes)
        return SPH_OK;
    sph_status st = output_still_named(sim);
    if (st)
        return st;
    quiet q;
    quiet_begin(&q);
    if (snapshot)
        st = write_snapshot(sim);
    if (!st && probes)
        st = write_probes(sim, 1);
    quiet_end(&q);
    return st;
}

static int write_static(io *c, sph_sim *sim, hid_t file)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const hsize_t n = sim->n;
    write_format(c, file, "output");
    hid_t h5md = group_create(c, file, "h5md");
    {
        hsize_t two = 2;
        int version[2] = {1, 1};
        hid_t space = H5Screate_simple(1, &two, NULL);
        if (ok(c, space, "h5md/version"))
            write_attr(c, h5md, "version", H5T_NATIVE_INT, space, version);
        close_id(space);
        hid_t creator = group_create(c, h5md, "creator");
        attr_string(c, creator, "name", "libsphsolid");
        attr_string(c, creator, "version", sph_version());
        group_close(c, creator, "h5md/creator");
        hid_t author = group_create(c, h5md, "author");
        attr_string(c, author, "name", "libsphsolid");
        group_close(c, author, "h5md/author");
    }
    group_close(c, h5md, "h5md");
    write_parameters(c, sim, file);

    hid_t parts = group_create(c, file, "particles");
    hid_t all = group_create(c, parts, "all");
    attr_long(c, all, "complete_frames", 0);
    hid_t box = group_create(c, all, "box");
    attr_long(c, box, "dimension", dim);
    if (!c->failed) {
        hid_t type = H5Tcopy(H5T_C_S1);
        char bnd[3][9] = {"none", "none", "none"};
        for (int i = 0; i < dim && i < 3; ++i)
            strcpy(bnd[i], sim->has_domain && sim->periodic[i] ? "periodic" : "none");
        hsize_t d = (hsize_t)dim;
        hid_t space = H5Screate_simple(1, &d, NULL);
        if (ok(c, type, "box/boundary") && ok(c, H5Tset_size(type, 9), "box/boundary") &&
            ok(c, space, "box/boundary"))
            write_attr(c, box, "boundary", type, space, bnd);
        close_id(space);
        close_id(type);
        if (sim->has_domain) {
            double edges[3];
            for (int i = 0; i < dim; ++i)
                edges[i] = sim->hi[i] - sim->lo[i];
            write_dataset(c, box, "edges", H5T_NATIVE_DOUBLE, 1, &d, edges);
            write_dataset(c, box, "offset", H5T_NATIVE_DOUBLE, 1, &d, sim->lo);
        }
    }
    group_close(c, box, "box");
    write_dataset(c, all, "mass", H5T_NATIVE_DOUBLE, 1, &n, sim->mass);
    write_dataset(c, all, "body", H5T_NATIVE_INT, 1, &n, sim->body_of);
    write_dataset(c, all, "material", H5T_NATIVE_INT, 1, &n, sim->material_of);
    hsize_t vec[2] = {n, (hsize_t)dim}, ten[2] = {n, (hsize_t)nc};
    series_create(c, all, "position", 2, vec, 1);
    series_create(c, all, "velocity", 2, vec, 1);
    series_create(c, all, "density", 1, &n, 1);
    series_create(c, all, "pressure", 1, &n, 1);
    series_create(c, all, "deviatoric_stress", 2, ten, 1);
    series_create(c, all, "von_mises", 1, &n, 1);
    group_close(c, all, "particles/all");
    group_close(c, parts, "particles");

    hid_t obs = group_create(c, file, "observables");
    if (sim->n_probes > 0 && !c->failed) {
        const int nv = SPH_PROBE_VALUES(dim);
        hsize_t inner[2] = {(hsize_t)sim->n_probes, (hsize_t)nv};
        series_create(c, obs, "probes", 2, inner, PROBE_BLOCK);
        hid_t pg = H5Gopen2(obs, "probes", H5P_DEFAULT);
        ok(c, pg, "observables/probes");
        attr_long(c, pg, "complete_samples", 0);
        size_t size = 1;
        for (int k = 0; k < sim->n_probes; ++k)
            size += strlen(sim->probes[k].name) + 1;
        char *names = calloc(size, 1);
        double *points = malloc((size_t)sim->n_probes * dim * sizeof *points);
        if (!names || !points) {
            fail_memory(c, "observables/probes", 0);
        } else {
            for (int k = 0; k < sim->n_probes; ++k) {
                if (k)
                    strcat(names, " ");
                strcat(names, sim->probes[k].name);
                for (int i = 0; i < dim; ++i)
                    points[k * dim + i] = sim->probes[k].point[i];
            }
            attr_string(c, pg, "names", names);
            attr_string(
                c, pg, "columns",
                dim == 2
                    ? "von_mises pressure sigma_xx sigma_yy sigma_zz sigma_xy"
                    : "von_mises pressure sigma_xx sigma_yy sigma_zz sigma_xy sigma_xz sigma_yz");
            hsize_t pd[2] = {(hsize_t)sim->n_probes, (hsize_t)dim};
            write_dataset(c, pg, "points", H5T_NATIVE_DOUBLE, 2, pd, points);
        }
        free(names);
        free(points);
        group_close(c, pg, "observables/probes");
    }
    group_close(c, obs, "observables");
    return c->failed ? -1 : 0;
}

/* Closes the output file whatever happened; returns -1 (cause in c) when
 * the final flush or close failed. */
static int output_release(io *c, sph_sim *sim)
{
    struct output_file *o = sim->out;
    int err = 0;
    if (o->file >= 0 && H5Fclose(o->file) < 0) {
        fail_at(c, "the file (close)", 0);
        err = -1;
    }
    free(o->pending_step);
    free(o->pending_time);
    free(o->pending_value);
    free(o->path);
    free(o);
    sim->out = NULL;
    return err;
}

sph_status sph_output_open(sph_sim *sim, const char *path, long snapshot_interval,
                           long probe_interval)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!path || !*path)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "output path is empty");
    if (snapshot_interval < 0 || probe_interval < 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "output intervals (snapshot %ld, probe %ld) must be >= 0",
                        snapshot_interval, probe_interval);
    if (sim->out)
        return sph_fail(sim, SPH_ERR_STATE, "an output file is already open ('%s')",
                        sim->out->path);
    sph_status st = sim_prepare(sim);
    if (st)
        return st;
    struct output_file *o = calloc(1, sizeof *o);
    char *copy = malloc(strlen(path) + 1);
    if (!o || !copy) {
        free(o);
        free(copy);
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate the output state");
    }
    strcpy(copy, path);
    quiet q;
    quiet_begin(&q);
    io c = {0};
    hid_t file = file_create(&c, path, 0);
    if (c.failed) {
        quiet_end(&q);
        free(o);
        free(copy);
        return sph_fail(sim, SPH_ERR_IO, "cannot create HDF5 file '%s': %s", path, c.cause);
    }
    o->file = file;
    o->snapshot_interval = snapshot_interval;
    o->probe_interval = probe_interval;
    o->last_snapshot_step = o->last_probe_step = -1;
    o->path = copy;
    sim->out = o;
    if (output_identify(o)) {
        st = sph_fail(sim, SPH_ERR_IO, "cannot stat the output file '%s' just created: %s", path,
                      strerror(errno));
        io ignored = {0};
        output_release(&ignored, sim);
    } else if (write_static(&c, sim, file)) {
        st = sph_fail(sim, SPH_ERR_IO, "cannot write the header of '%s': %s (writing %s)", path,
                      c.cause, c.what);
        io ignored = {0};
        output_release(&ignored, sim);
    } else if (!(st = write_snapshot(sim)) && probe_interval > 0 && !(st = write_probes(sim, 0))) {
        io cc = {0};
        if (output_commit(&cc, o, o->frames, o->probe_frames))
            st = output_failed(sim, "writing probe samples to", &cc);
    }
    quiet_end(&q);
    return st ? st : sph_ok(sim);
}

sph_status sph_output_snapshot(sph_sim *sim)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!sim->out)
        return sph_fail(sim, SPH_ERR_STATE, "no output file is open");
    if (sim->out->last_snapshot_step == sim->step && !sim->out->failed)
        return sph_ok(sim);
    sph_status st = output_still_named(sim);
    if (st)
        return st;
    quiet q;
    quiet_begin(&q);
    st = write_snapshot(sim);
    quiet_end(&q);
    return st;
}

void output_free(sph_sim *sim)
{
    if (sim->out) {
        quiet q;
        quiet_begin(&q);
        io c = {0};
        if (!sim->out->failed)
            output_commit(&c, sim->out, sim->out->frames,
                          sim->n_probes > 0 ? sim->out->probe_frames : -1);
        output_release(&c, sim);
        quiet_end(&q);
    }
}

sph_status sph_output_close(sph_sim *sim)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!sim->out)
        return sph_fail(sim, SPH_ERR_STATE, "no output file is open");
    struct output_file *o = sim->out;
    quiet q;
    quiet_begin(&q);
    io c = {0};
    char *path = malloc(strlen(o->path) + 1);
    if (path)
        strcpy(path, o->path);
    if (!o->failed)
        output_still_named(sim);
    const int failed = o->failed;
    char earlier[SPH_ERRMSG_SIZE];
    memcpy(earlier, o->error, sizeof earlier);
    /* the final state is always in the file, then the XDMF companion */
    sph_status st = SPH_OK;
    if (!failed && o->last_snapshot_step != sim->step)
        st = write_snapshot(sim);
    if (!st && !failed && o->probe_interval > 0 && o->last_probe_step != sim->step)
        st = write_probes(sim, 0);
    const long frames = o->frames;
    if (!failed && !o->failed)
        output_commit(&c, o, o->frames, sim->n_probes > 0 ? o->probe_frames : -1);
    output_release(&c, sim);
    quiet_end(&q);
    if (st) {
        /* already reported */
    } else if (failed) {
        st = sph_fail(sim, SPH_ERR_IO, "closed after an earlier failure: %s", earlier);
    } else if (c.failed) {
        st = sph_fail(sim, SPH_ERR_IO,
                      "closing '%s' failed: %s (writing %s); frames after %ld may be lost",
                      path ? path : "?", c.cause, c.what, frames);
    } else if (path) {
        st = sph_write_xdmf(sim, path);
    }
    free(path);
    return st ? st : sph_ok(sim);
}

/* ----------------------------------------------------------- reading */

static int read_attr(hid_t obj, const char *name, hid_t type, void *v)
{
    if (H5Aexists(obj, name) <= 0)
        return -1;
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    if (a < 0)
        return -1;
    herr_t e = H5Aread(a, type, v);
    H5Aclose(a);
    return e < 0 ? -1 : 0;
}

static int read_attr_long(hid_t obj, const char *name, long *v)
{
    return read_attr(obj, name, H5T_NATIVE_LONG, v);
}

/* A string attribute into buf (truncated to size). */
static int read_attr_string(hid_t obj, const char *name, char *buf, size_t size)
{
    if (H5Aexists(obj, name) <= 0)
        return -1;
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    hid_t ft = a >= 0 ? H5Aget_type(a) : -1;
    int err = -1;
    if (ft >= 0 && H5Tget_class(ft) == H5T_STRING && !H5Tis_variable_str(ft)) {
        const size_t len = H5Tget_size(ft);
        char *tmp = calloc(len + 1, 1);
        hid_t mt = H5Tcopy(H5T_C_S1);
        if (tmp && mt >= 0 && H5Tset_size(mt, len) >= 0 && H5Aread(a, mt, tmp) >= 0) {
            snprintf(buf, size, "%s", tmp);
            err = 0;
        }
        close_id(mt);
        free(tmp);
    }
    close_id(ft);
    close_id(a);
    return err;
}

/* Up to `size` doubles of a small attribute; the count in *count. */
static int read_attr_doubles(hid_t obj, const char *name, double *v, size_t size, size_t *count)
{
    if (H5Aexists(obj, name) <= 0)
        return -1;
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    hid_t sp = a >= 0 ? H5Aget_space(a) : -1;
    const hssize_t np = sp >= 0 ? H5Sget_simple_extent_npoints(sp) : -1;
    int err = -1;
    if (np >= 0 && (size_t)np <= size && H5Aread(a, H5T_NATIVE_DOUBLE, v) >= 0) {
        *count = (size_t)np;
        err = 0;
    }
    close_id(sp);
    close_id(a);
    return err;
}

/* Opens a libsphsolid file of the given content into *file (-1 on
 * failure) and its format version into *version; fails naming the path and
 * what is wrong.  Outputs of every format up to SPH_FILE_FORMAT are read
 * (format 1: before the version was recorded, libsphsolid 0.1.0 and 0.2.0);
 * checkpoints only of this format. */
static sph_status open_checked(sph_sim *sim, const char *path, const char *content, hid_t *file,
                               long *version_out)
{
    *file = -1;
    *version_out = 0;
    if (!path || !*path)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "file path is empty");
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) {
        io c = {0};
        fail_at(&c, "open", 0);
        FILE *probe = fopen(path, "rb");
        if (!probe)
            sph_fail(sim, SPH_ERR_IO, "cannot open '%s': %s", path, strerror(errno));
        else {
            fclose(probe);
            sph_fail(sim, SPH_ERR_IO, "cannot open '%s' as an HDF5 file: %s", path, c.cause);
        }
        return SPH_ERR_IO;
    }
    long version = 0;
    char kind[32] = "";
    if (read_attr_long(f, "sphsolid_format", &version)) {
        /* format 1 wrote no version: an output has the H5MD group and the
         * position series, a checkpoint its /checkpoint group */
        const int checkpoint = H5Lexists(f, "checkpoint", H5P_DEFAULT) > 0;
        const int output = H5Lexists(f, "h5md", H5P_DEFAULT) > 0 &&
                           H5Lexists(f, "particles", H5P_DEFAULT) > 0 &&
                           H5Lexists(f, "/particles/all", H5P_DEFAULT) > 0 &&
                           H5Lexists(f, "/particles/all/position", H5P_DEFAULT) > 0;
        if (!checkpoint && output && strcmp(content, "output") == 0) {
            *file = f;
            *version_out = 1;
            return SPH_OK;
        }
        if (checkpoint && strcmp(content, "checkpoint") == 0)
            sph_fail(sim, SPH_ERR_IO,
                     "'%s' is a checkpoint in libsphsolid file format 1 (written before the "
                     "format was versioned); checkpoints are read only in the format of the "
                     "library that wrote them (format %ld): continue that run with the "
                     "version that wrote it, or start from a frame of its output file "
                     "(sph_read_frame reads every earlier output format)",
                     path, SPH_FILE_FORMAT);
        else if (checkpoint || output)
            sph_fail(sim, SPH_ERR_IO, "'%s' is a libsphsolid %s file (format 1), not %s %s file",
                     path, checkpoint ? "checkpoint" : "output", content[0] == 'o' ? "an" : "a",
                     content);
        else
            sph_fail(sim, SPH_ERR_IO,
                     "'%s' is not a libsphsolid file (no sphsolid_format attribute)", path);
        H5Fclose(f);
        return SPH_ERR_IO;
    }
    if (version < 1 || version > SPH_FILE_FORMAT ||
        (version != SPH_FILE_FORMAT && strcmp(content, "checkpoint") == 0)) {
        sph_fail(sim, SPH_ERR_IO,
                 "'%s' has libsphsolid file format %ld; this library writes format %ld and "
                 "reads outputs of formats 1 to %ld, checkpoints of format %ld only",
                 path, version, SPH_FILE_FORMAT, SPH_FILE_FORMAT, SPH_FILE_FORMAT);
        H5Fclose(f);
        return SPH_ERR_IO;
    }
    read_attr_string(f, "sphsolid_content", kind, sizeof kind);
    if (strcmp(kind, content) != 0) {
        sph_fail(sim, SPH_ERR_IO, "'%s' is a libsphsolid %s file, not %s %s file", path,
                 kind[0] ? kind : "(unknown)", content[0] == 'o' ? "an" : "a", content);
        H5Fclose(f);
        return SPH_ERR_IO;
    }
    *file = f;
    *version_out = version;
    return SPH_OK;
}

/* Compares the effects a file was written with (/parameters/effects,
 * or for files written before that group the /parameters `effects` text)
 * with the simulation's: a run continues bit for bit only with the same
 * effects.  Fails naming the first difference. */
static sph_status effects_match(sph_sim *sim, hid_t par, const char *path)
{
    sph_status st = SPH_OK;
    if (H5Lexists(par, "effects", H5P_DEFAULT) <= 0) {
        char text[1024] = "", here[1024];
        effects_describe(&sim->fx, here, sizeof here);
        if (read_attr_string(par, "effects", text, sizeof text))
            st = sph_fail(sim, SPH_ERR_IO, "'%s': /parameters records no effects", path);
        else if (strcmp(text, here) != 0)
            st = sph_fail(sim, SPH_ERR_ARGUMENT,
                          "'%s' does not match this simulation: effects '%s' in the file, '%s' "
                          "here",
                          path, text, here);
        return st;
    }
    hid_t all = H5Gopen2(par, "effects", H5P_DEFAULT);
    H5G_info_t info;
    if (all < 0 || H5Gget_info(all, &info) < 0) {
        close_id(all);
        return sph_fail(sim, SPH_ERR_IO, "'%s': cannot read /parameters/effects", path);
    }
    hsize_t known_on = 0;
    for (int k = 0; k < sph_effect_count() && !st; ++k) {
        sph_effect_info e;
        double here[EFFECTS_MAX_PARAMETERS];
        sph_effect_info_get(k, &e);
        const int on_here = effects_values(&sim->fx, k, here);
        const int on_file = H5Lexists(all, e.name, H5P_DEFAULT) > 0;
        known_on += (hsize_t)on_file;
        if (on_file != on_here) {
            st = sph_fail(sim, SPH_ERR_ARGUMENT,
                          "'%s' does not match this simulation: effect %s is %s in the file, %s "
                          "here",
                          path, e.name, on_file ? "on" : "off", on_here ? "on" : "off");
            break;
        }
        hid_t g = on_file ? H5Gopen2(all, e.name, H5P_DEFAULT) : -1;
        for (int j = 0; on_file && j < e.parameter_count && !st; ++j) {
            sph_effect_parameter p;
            sph_effect_parameter_get(k, j, &p);
            double value = 0.0;
            size_t count = 0;
            if (g < 0 || read_attr_doubles(g, p.key, &value, 1, &count) || count != 1)
                st = sph_fail(sim, SPH_ERR_IO, "'%s': cannot read /parameters/effects/%s/%s", path,
                              e.name, p.key);
            else if (value != here[j])
                st = sph_fail(sim, SPH_ERR_ARGUMENT,
                              "'%s' does not match this simulation: effect %s has %s=%.17g in the "
                              "file, %s=%.17g here",
                              path, e.name, p.key, value, p.key, here[j]);
        }
        close_id(g);
    }
    if (!st && info.nlinks != known_on)
        st = sph_fail(sim, SPH_ERR_ARGUMENT,
                      "'%s' was written with an effect this library does not know (known: %s)",
                      path, sph_effect_names());
    close_id(all);
    return st;
}

/* Compares the file's /parameters with the simulation (with_effects: the
 * effects too, effects_match); fails naming the first difference
 * (SPH_ERR_ARGUMENT: another scene, SPH_ERR_IO: a record that cannot be
 * read). */
static sph_status scene_matches(sph_sim *sim, hid_t f, const char *path, int with_effects,
                                long version)
{
    hid_t par = H5Gopen2(f, "parameters", H5P_DEFAULT);
    if (par < 0)
        return sph_fail(sim, SPH_ERR_IO, "'%s' has no /parameters group", path);
    sph_status st = SPH_OK;
    long dim = 0, nb = 0;
    H5G_info_t info;
    hid_t bodies = -1, mat = -1;
    double *materials = NULL;
    if (read_attr_long(par, "dimension", &dim)) {
        st = sph_fail(sim, SPH_ERR_IO, "'%s': /parameters lacks its dimension", path);
        goto done;
    }
    if (dim != sim->dim) {
        st = sph_fail(sim, SPH_ERR_ARGUMENT,
                      "'%s' does not match this simulation: the file is %ldD, the simulation %dD",
                      path, dim, sim->dim);
        goto done;
    }
    mat = H5Dopen2(par, "materials", H5P_DEFAULT);
    hid_t msp = mat >= 0 ? H5Dget_space(mat) : -1;
    const hssize_t mcount = msp >= 0 ? H5Sget_simple_extent_npoints(msp) : -1;
    close_id(msp);
    if (mcount < 0 || mcount % 3) {
        st = sph_fail(sim, SPH_ERR_IO, "'%s': cannot read /parameters/materials", path);
        goto done;
    }
    if (mcount / 3 != sim->n_materials) {
        st = sph_fail(
            sim, SPH_ERR_ARGUMENT,
            "'%s' does not match this simulation: the file has %ld materials, the simulation %d",
            path, (long)(mcount / 3), sim->n_materials);
        goto done;
    }
    materials = malloc((size_t)mcount * sizeof *materials + 1);
    if (!materials ||
        (mcount && H5Dread(mat, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, materials) < 0)) {
        io c = {0};
        fail_at(&c, "materials", 0);
        st =
            sph_fail(sim, SPH_ERR_IO, "'%s': cannot read /parameters/materials: %s", path, c.cause);
        goto done;
    }
    for (int k = 0; k < sim->n_materials; ++k) {
        const double here[3] = {sim->materials[k].K, sim->materials[k].mu, sim->materials[k].rho0};
        const char *names[3] = {"bulk modulus K", "shear modulus mu", "reference density rho0"};
        for (int j = 0; j < 3; ++j)
            if (materials[3 * k + j] != here[j]) {
                st = sph_fail(
                    sim, SPH_ERR_ARGUMENT,
                    "'%s' does not match this simulation: material %d has %s = %.17g in the "
                    "file, %.17g here",
                    path, k, names[j], materials[3 * k + j], here[j]);
                goto done;
            }
    }
    bodies = H5Gopen2(par, "bodies", H5P_DEFAULT);
    if (bodies < 0 || H5Gget_info(bodies, &info) < 0) {
        st = sph_fail(sim, SPH_ERR_IO, "'%s': cannot read /parameters/bodies", path);
        goto done;
    }
    nb = (long)info.nlinks;
    if (nb != sim->n_bodies) {
        st = sph_fail(
            sim, SPH_ERR_ARGUMENT,
            "'%s' does not match this simulation: the file has %ld bodies, the simulation %d", path,
            nb, sim->n_bodies);
        goto done;
    }
    for (int k = 0; k < sim->n_bodies; ++k) {
        const body *b = &sim->bodies[k];
        if (H5Lexists(bodies, b->name, H5P_DEFAULT) <= 0) {
            st = sph_fail(sim, SPH_ERR_ARGUMENT,
                          "'%s' does not match this simulation: the file has no body '%s'", path,
                          b->name);
            goto done;
        }
        hid_t g = H5Gopen2(bodies, b->name, H5P_DEFAULT);
        long index = -1, first = -1, count = -1, material = -1;
        char motion[32] = "";
        double lo[3] = {0}, hi[3] = {0}, spacing = 0;
        size_t nlo = 0, nhi = 0, ns = 0;
        const int bad = g < 0 || read_attr_long(g, "index", &index) ||
                        read_attr_long(g, "first", &first) || read_attr_long(g, "count", &count) ||
                        read_attr_long(g, "material", &material) ||
                        read_attr_string(g, "motion", motion, sizeof motion) ||
                        read_attr_doubles(g, "spacing", &spacing, 1, &ns) ||
                        (version > 1 && (read_attr_doubles(g, "extent_lo", lo, 3, &nlo) ||
                                         read_attr_doubles(g, "extent_hi", hi, 3, &nhi)));
        if (!bad && version == 1 && /* format 1 files record extents from 0.2.0 on */
            (read_attr_doubles(g, "extent_lo", lo, 3, &nlo) ||
             read_attr_doubles(g, "extent_hi", hi, 3, &nhi)))
            nlo = nhi = 0;
        close_id(g);
        if (bad) {
            st = sph_fail(sim, SPH_ERR_IO, "'%s': cannot read the record of body '%s'", path,
                          b->name);
            goto done;
        }
#define DIFFERS(fmt, file_value, here_value)                                    \
    do {                                                                        \
        st = sph_fail(sim, SPH_ERR_ARGUMENT,                                    \
                      "'%s' does not match this simulation: body '%s' has " fmt \
                      " in the file, " fmt " here",                             \
                      path, b->name, file_value, here_value);                   \
        goto done;                                                              \
    } while (0)
        if (index != k)
            DIFFERS("index %ld", index, (long)k);
        if (first != (long)b->first || count != (long)b->count) {
            st = sph_fail(
                sim, SPH_ERR_ARGUMENT,
                "'%s' does not match this simulation: body '%s' holds particles [%ld, %ld) in "
                "the file, [%zu, %zu) here",
                path, b->name, first, first + count, b->first, b->first + b->count);
            goto done;
        }
        if (material != b->material)
            DIFFERS("material %ld", material, (long)b->material);
        if (strcmp(motion, motion_name(b->motion)) != 0)
            DIFFERS("motion '%s'", motion, motion_name(b->motion));
        if (spacing != b->spacing)
            DIFFERS("spacing %.17g m", spacing, b->spacing);
        for (int i = 0; i < sim->dim; ++i) {
            if ((long)nlo != dim || (long)nhi != dim)
                break;
            if (lo[i] != b->extent_lo[i] || hi[i] != b->extent_hi[i]) {
                st = sph_fail(
                    sim, SPH_ERR_ARGUMENT,
                    "'%s' does not match this simulation: body '%s' spans %c in [%.9g, %.9g] "
                    "m in the file, [%.9g, %.9g] m here (another shape)",
                    path, b->name, "xyz"[i], lo[i], hi[i], b->extent_lo[i], b->extent_hi[i]);
                goto done;
            }
        }
#undef DIFFERS
    }
    if (with_effects)
        st = effects_match(sim, par, path);
done:
    free(materials);
    close_id(mat);
    close_id(bodies);
    H5Gclose(par);
    return st;
}

/* Reads `expect` doubles of dataset `name` (or one frame of a series when
 * frame >= 0); -1 with the cause in c on failure. */
static int read_doubles(io *c, hid_t loc, const char *name, long frame, size_t expect, double *out)
{
    hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
    if (!ok(c, d, name))
        return -1;
    hid_t space = H5Dget_space(d), mem = -1;
    hsize_t dims[4] = {0}, start[4] = {0}, count[4] = {0};
    const int rank = space >= 0 ? H5Sget_simple_extent_dims(space, dims, NULL) : -1;
    if (ok(c, rank, name)) {
        hsize_t total = 1;
        for (int i = frame >= 0 ? 1 : 0; i < rank; ++i)
            total *= dims[i];
        if (total != expect || (frame >= 0 && (hsize_t)frame >= dims[0])) {
            c->failed = 1;
            snprintf(c->what, sizeof c->what, "%s", name);
            snprintf(c->cause, sizeof c->cause, "it holds %llu values per %s, %zu expected",
                     (unsigned long long)total, frame >= 0 ? "frame" : "file", expect);
        } else if (frame >= 0) {
            memcpy(count, dims, sizeof count);
            start[0] = (hsize_t)frame;
            count[0] = 1;
            if (ok(c, H5Sselect_hyperslab(space, H5S_SELECT_SET, start, NULL, count, NULL), name) &&
                ok(c, mem = H5Screate_simple(rank, count, NULL), name))
                ok(c, H5Dread(d, H5T_NATIVE_DOUBLE, mem, space, H5P_DEFAULT, out), name);
        } else if (expect > 0) {
            ok(c, H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out), name);
        }
    }
    close_id(mem);
    close_id(space);
    H5Dclose(d);
    return c->failed ? -1 : 0;
}

static int read_long_at(io *c, hid_t loc, const char *name, long frame, long *out)
{
    hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
    if (!ok(c, d, name))
        return -1;
    hid_t space = H5Dget_space(d), mem = -1;
    hsize_t s = (hsize_t)frame, one = 1;
    if (ok(c, space, name) &&
        ok(c, H5Sselect_hyperslab(space, H5S_SELECT_SET, &s, NULL, &one, NULL), name) &&
        ok(c, mem = H5Screate_simple(1, &one, NULL), name))
        ok(c, H5Dread(d, H5T_NATIVE_LONG, mem, space, H5P_DEFAULT, out), name);
    close_id(mem);
    close_id(space);
    H5Dclose(d);
    return c->failed ? -1 : 0;
}

/* The first non-finite value of an array, for the message; -1 if none. */
static long first_nonfinite(const double *a, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(a[i]))
            return (long)i;
    return -1;
}

/* Scratch copies of the state a read fills before anything is committed. */
typedef struct state_copy {
    double *x, *v, *rho, *S, *mass, *motion;
    double *dv, *drho, *dS; /* rates an integrator carries, if any */
} state_copy;

static int state_alloc(state_copy *s, const sph_sim *sim)
{
    const size_t n = sim->n, dim = (size_t)sim->dim, nc = (size_t)sim->ncomp;
    s->x = malloc(n * dim * sizeof(double));
    s->v = malloc(n * dim * sizeof(double));
    s->rho = malloc(n * sizeof(double));
    s->S = malloc(n * nc * sizeof(double));
    s->mass = malloc(n * sizeof(double));
    s->motion = malloc(((size_t)sim->n_bodies * 6 + 1) * sizeof(double));
    return s->x && s->v && s->rho && s->S && s->mass && s->motion ? 0 : -1;
}

static void state_free(state_copy *s)
{
    free(s->x);
    free(s->v);
    free(s->rho);
    free(s->S);
    free(s->mass);
    free(s->motion);
    free(s->dv);
    free(s->drho);
    free(s->dS);
}

/* Reads positions, velocities, density and deviatoric stress from the
 * datasets `names` (in that order; frame `frame` of a series, or -1). */
static int state_read(io *c, hid_t loc, const char *const names[4], long frame, const sph_sim *sim,
                      state_copy *s)
{
    const size_t n = sim->n, dim = (size_t)sim->dim;
    double *const to[4] = {s->x, s->v, s->rho, s->S};
    const size_t count[4] = {n * dim, n * dim, n, n * (size_t)sim->ncomp};
    for (int k = 0; k < 4 && !c->failed; ++k)
        read_doubles(c, loc, names[k], frame, count[k], to[k]);
    return c->failed ? -1 : 0;
}

/* Releases what a read holds (scratch, group, file, error handler). */
static void read_release(const quiet *q, state_copy *s, hid_t group, hid_t file)
{
    state_free(s);
    close_id(group);
    close_id(file);
    quiet_end(q);
}

/* Copies the state read into the simulation at (step, time); neighbour
 * list and rates are rebuilt from it. */
static void state_commit(sph_sim *sim, const state_copy *s, long step, double time)
{
    const size_t n = sim->n, dim = (size_t)sim->dim;
    memcpy(sim->x, s->x, n * dim * sizeof(double));
    memcpy(sim->v, s->v, n * dim * sizeof(double));
    memcpy(sim->rho, s->rho, n * sizeof(double));
    memcpy(sim->S, s->S, n * (size_t)sim->ncomp * sizeof(double));
    sim->step = step;
    sim->t = time;
    sim->nl.valid = 0;
    sim->rates_valid = 0;
}

/* Refuses values no run can produce (checksums catch damaged blocks; this
 * catches files edited or written by a broken program). */
static int state_plausible(sph_sim *sim, const state_copy *s, const char *path, int with_mass)
{
    const size_t n = sim->n, dim = (size_t)sim->dim, nc = (size_t)sim->ncomp;
    struct {
        const char *name;
        const double *a;
        size_t per;
    } arrays[] = {{"position", s->x, dim},
                  {"velocity", s->v, dim},
                  {"density", s->rho, 1},
                  {"deviatoric_stress", s->S, nc},
                  {"mass", s->mass, 1}};
    for (int k = 0; k < (with_mass ? 5 : 4); ++k) {
        const long i = first_nonfinite(arrays[k].a, n * arrays[k].per);
        if (i >= 0) {
            sph_fail(sim, SPH_ERR_IO, "'%s' is damaged: %s of particle %ld is %g", path,
                     arrays[k].name, i / (long)arrays[k].per, arrays[k].a[i]);
            return 0;
        }
    }
    for (size_t a = 0; a < n; ++a) {
        if (!(s->rho[a] > 0.0)) {
            sph_fail(sim, SPH_ERR_IO, "'%s' is damaged: density of particle %zu is %g", path, a,
                     s->rho[a]);
            return 0;
        }
        if (with_mass && !(s->mass[a] > 0.0)) {
            sph_fail(sim, SPH_ERR_IO, "'%s' is damaged: mass of particle %zu is %g", path, a,
                     s->mass[a]);
            return 0;
        }
    }
    return 1;
}

/* Frames of an output file that count: complete_frames (format 2), or in
 * format 1, which appended each series by itself, the frames every series
 * read back holds. */
static sph_status frame_count(sph_sim *sim, hid_t f, const char *path, long version, long *frames)
{
    hid_t all = H5Gopen2(f, "/particles/all", H5P_DEFAULT);
    long complete = -1;
    if (version == 1 && all >= 0) {
        static const char *const series[6] = {"position/value", "position/step",
                                              "position/time",  "velocity/value",
                                              "density/value",  "deviatoric_stress/value"};
        for (int k = 0; k < 6; ++k) {
            hid_t d = H5Dopen2(all, series[k], H5P_DEFAULT);
            hid_t space = d >= 0 ? H5Dget_space(d) : -1;
            hsize_t dims[4] = {0};
            const int rank = space >= 0 ? H5Sget_simple_extent_dims(space, dims, NULL) : -1;
            close_id(space);
            close_id(d);
            if (rank < 1) {
                complete = -1;
                break;
            }
            if (complete < 0 || (long)dims[0] < complete)
                complete = (long)dims[0];
        }
        close_id(all);
        if (complete < 0)
            return sph_fail(sim, SPH_ERR_IO,
                            "'%s' (file format 1) lacks a series of /particles/all (position, "
                            "velocity, density, deviatoric_stress)",
                            path);
        *frames = complete;
        return SPH_OK;
    }
    const int bad = all < 0 || read_attr_long(all, "complete_frames", &complete) || complete < 0;
    close_id(all);
    if (bad)
        return sph_fail(sim, SPH_ERR_IO, "'%s' has no complete_frames count on /particles/all",
                        path);
    *frames = complete;
    return SPH_OK;
}

sph_status sph_read_frame_count(sph_sim *sim, const char *path, long *frames)
{
    sph_status st = sph_need(sim, frames, "sph_read_frame_count", "frames");
    if (st)
        return st;
    quiet q;
    quiet_begin(&q);
    hid_t f = -1;
    long version = 0;
    st = open_checked(sim, path, "output", &f, &version);
    if (!st)
        st = frame_count(sim, f, path, version, frames);
    close_id(f);
    quiet_end(&q);
    return st ? st : sph_ok(sim);
}

sph_status sph_read_frame(sph_sim *sim, const char *path, long frame)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (sim->n == 0)
        return sph_fail(
            sim, SPH_ERR_STATE,
            "the simulation has no particles: build the scene the file was written from first");
    quiet q;
    quiet_begin(&q);
    sph_status st = SPH_OK;
    long frames = 0, step = 0;
    double time = 0.0;
    state_copy s = {0};
    hid_t all = -1;
    hid_t f = -1;
    long version = 0;
    if ((st = open_checked(sim, path, "output", &f, &version)))
        goto done;
    if ((st = frame_count(sim, f, path, version, &frames)))
        goto done;
    const long asked = frame;
    if (frame < 0)
        frame += frames;
    if (frame < 0 || frame >= frames) {
        st = sph_fail(sim, SPH_ERR_ARGUMENT, "frame=%ld: '%s' has %ld complete frames", asked, path,
                      frames);
        goto done;
    }
    if ((st = scene_matches(sim, f, path, 0, version)))
        goto done;
    if (state_alloc(&s, sim)) {
        st = sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate scratch arrays to read '%s'", path);
        goto done;
    }
    all = H5Gopen2(f, "/particles/all", H5P_DEFAULT);
    io c = {0};
    if (ok(&c, all, "/particles/all")) {
        static const char *const values[4] = {"position/value", "velocity/value", "density/value",
                                              "deviatoric_stress/value"};
        state_read(&c, all, values, frame, sim, &s);
        if (!c.failed)
            read_long_at(&c, all, "position/step", frame, &step);
        if (!c.failed) {
            hid_t d = H5Dopen2(all, "position/time", H5P_DEFAULT);
            if (ok(&c, d, "position/time")) {
                hid_t space = H5Dget_space(d), mem = -1;
                hsize_t s0 = (hsize_t)frame, one = 1;
                if (ok(&c, space, "position/time") &&
                    ok(&c, H5Sselect_hyperslab(space, H5S_SELECT_SET, &s0, NULL, &one, NULL),
                       "position/time") &&
                    ok(&c, mem = H5Screate_simple(1, &one, NULL), "position/time"))
                    ok(&c, H5Dread(d, H5T_NATIVE_DOUBLE, mem, space, H5P_DEFAULT, &time),
                       "position/time");
                close_id(mem);
                close_id(space);
                H5Dclose(d);
            }
        }
    }
    if (c.failed) {
        st = sph_fail(sim, SPH_ERR_IO, "cannot read frame %ld of '%s': %s (reading %s)", frame,
                      path, c.cause, c.what);
        goto done;
    }
    if (!isfinite(time)) {
        st = sph_fail(sim, SPH_ERR_IO, "'%s' is damaged: the time of frame %ld is %g", path, frame,
                      time);
        goto done;
    }
    if (!state_plausible(sim, &s, path, 0)) {
        st = SPH_ERR_IO;
        goto done;
    }
    state_commit(sim, &s, step, time);
    st = sph_ok(sim);
done:
    read_release(&q, &s, all, f);
    return st;
}

/* ------------------------------------------------------- checkpoints */

/* A new, unique temporary name beside `path` (any length), created empty;
 * NULL with errno set on failure. */
static char *temporary_beside(const char *path)
{
    const size_t len = strlen(path);
    char *tmp = malloc(len + 16);
    if (!tmp) {
        errno = ENOMEM;
        return NULL;
    }
    memcpy(tmp, path, len);
    memcpy(tmp + len, ".tmp-XXXXXX", 12);
    const int fd = mkstemp(tmp);
    if (fd < 0) {
        free(tmp);
        return NULL;
    }
    close(fd);
    return tmp;
}

/* Writes the whole image to the (empty) temporary file; -1 with errno. */
static int write_image(const char *tmp, const void *data, size_t size)
{
    const int fd = open(tmp, O_WRONLY | O_TRUNC);
    if (fd < 0)
        return -1;
    const char *p = data;
    while (size > 0) {
        const ssize_t w = write(fd, p, size);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            const int saved = w < 0 ? errno : EIO;
            close(fd);
            errno = saved;
            return -1;
        }
        p += w;
        size -= (size_t)w;
    }
    return close(fd);
}

/* Syncs the finished temporary file and renames it over `path`, then syncs
 * the directory (best effort) so the rename survives a power cut. */
static int sync_and_rename(const char *tmp, const char *path, const char **step)
{
    *step = "open";
    const int fd = open(tmp, O_RDONLY);
    if (fd < 0)
        return -1;
    *step = "sync";
    int err = fsync(fd) != 0 || fchmod(fd, 0644) != 0;
    const int saved = errno;
    if (close(fd) != 0 && !err) {
        *step = "close";
        return -1;
    }
    errno = saved;
    if (err)
        return -1;
    *step = "rename";
    if (rename(tmp, path) != 0)
        return -1;
    const size_t len = strlen(path);
    char *dir = malloc(len + 2);
    if (dir) {
        const char *slash = strrchr(path, '/');
        if (slash) {
            memcpy(dir, path, (size_t)(slash - path) + 1);
            dir[slash - path + 1] = '\0';
        } else {
            strcpy(dir, ".");
        }
        const int dfd = open(dir, O_RDONLY);
        if (dfd >= 0) {
            fsync(dfd);
            close(dfd);
        }
        free(dir);
    }
    return 0;
}

sph_status sph_checkpoint_write(sph_sim *sim, const char *path)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!path || !*path)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "checkpoint path is empty");
    if (sim->n == 0)
        return sph_fail(sim, SPH_ERR_STATE,
                        "nothing to checkpoint: the simulation has no particles");
    if (!sim->dt_set && sim->dt <= 0.0)
        sim->dt = sph_default_dt(sim);
    char *tmp = temporary_beside(path);
    if (!tmp)
        return sph_fail(sim, SPH_ERR_IO,
                        "cannot write checkpoint '%s': %s (creating a temporary file beside it); "
                        "the previous file is unchanged",
                        path, strerror(errno));
    quiet q;
    quiet_begin(&q);
    /* The file is built in memory (HDF5's core driver, no disk access), its
     * image written to the temporary name with checked plain writes, synced
     * and renamed: a failing disk never reaches HDF5, which would otherwise
     * be left with a file it cannot close. */
    io c = {0};
    hid_t f = file_create(&c, tmp, 1);
    write_format(&c, f, "checkpoint");
    write_parameters(&c, sim, f);
    hid_t g = group_create(&c, f, "checkpoint");
    attr_long(&c, g, "dimension", sim->dim);
    attr_long(&c, g, "particles", (long)sim->n);
    attr_long(&c, g, "bodies", sim->n_bodies);
    attr_long(&c, g, "step", sim->step);
    attr_double(&c, g, "time", &sim->t, 1);
    attr_double(&c, g, "dt", &sim->dt, 1);
    attr_long(&c, g, "dt_set", sim->dt_set);
    attr_string(&c, g, "integrator", sim_integrator(sim)->name);
    {
        /* the clock again, checksummed (attributes of this format are not) */
        const double clock[4] = {(double)sim->step, sim->t, sim->dt, (double)sim->dt_set};
        const hsize_t four = 4;
        write_dataset(&c, g, "clock", H5T_NATIVE_DOUBLE, 1, &four, clock);
    }
    const hsize_t n = sim->n;
    hsize_t vec[2] = {n, (hsize_t)sim->dim}, ten[2] = {n, (hsize_t)sim->ncomp};
    write_dataset(&c, g, "position", H5T_NATIVE_DOUBLE, 2, vec, sim->x);
    write_dataset(&c, g, "velocity", H5T_NATIVE_DOUBLE, 2, vec, sim->v);
    write_dataset(&c, g, "density", H5T_NATIVE_DOUBLE, 1, &n, sim->rho);
    write_dataset(&c, g, "deviatoric_stress", H5T_NATIVE_DOUBLE, 2, ten, sim->S);
    write_dataset(&c, g, "mass", H5T_NATIVE_DOUBLE, 1, &n, sim->mass);
    if (!c.failed) {
        double *vectors = calloc((size_t)sim->n_bodies * 3 + 1, sizeof *vectors);
        if (!vectors) {
            fail_memory(&c, "motion_vectors", 0);
        } else {
            for (int k = 0; k < sim->n_bodies; ++k)
                memcpy(vectors + 3 * k, sim->bodies[k].vector, 3 * sizeof(double));
            hsize_t d[2] = {(hsize_t)sim->n_bodies, 3};
            write_dataset(&c, g, "motion_vectors", H5T_NATIVE_DOUBLE, 2, d, vectors);
            for (int k = 0; k < sim->n_bodies; ++k)
                memcpy(vectors + 3 * k, sim->bodies[k].centre, 3 * sizeof(double));
            write_dataset(&c, g, "motion_centres", H5T_NATIVE_DOUBLE, 2, d, vectors);
            free(vectors);
        }
    }
    if (sim_integrator(sim)->carries_rates && carried_rates_valid(sim)) {
        /* the rates the next step starts from */
        write_dataset(&c, g, "rate_velocity", H5T_NATIVE_DOUBLE, 2, vec, sim->dv_dt);
        write_dataset(&c, g, "rate_density", H5T_NATIVE_DOUBLE, 1, &n, sim->drho_dt);
        write_dataset(&c, g, "rate_deviatoric_stress", H5T_NATIVE_DOUBLE, 2, ten, sim->dS_dt);
    }
    group_close(&c, g, "checkpoint");
    void *image = NULL;
    ssize_t size = -1;
    if (!c.failed && ok(&c, H5Fflush(f, H5F_SCOPE_GLOBAL), "the in-memory image") &&
        ok(&c, size = H5Fget_file_image(f, NULL, 0), "the in-memory image")) {
        image = malloc((size_t)size);
        if (!image) {
            fail_memory(&c, "the in-memory image", (size_t)size);
        } else {
            ok(&c, H5Fget_file_image(f, image, (size_t)size), "the in-memory image");
        }
    }
    if (f >= 0 && H5Fclose(f) < 0)
        fail_at(&c, "the in-memory image (close)", 0);
    quiet_end(&q);
    const char *step = "write";
    sph_status st = SPH_OK;
    if (c.failed)
        st = sph_fail(
            sim, SPH_ERR_IO,
            "cannot write checkpoint '%s': %s (building %s); the previous file is unchanged", path,
            c.cause, c.what);
    else if (write_image(tmp, image, (size_t)size) || sync_and_rename(tmp, path, &step))
        st = sph_fail(sim, SPH_ERR_IO,
                      "cannot write checkpoint '%s': %s (%s '%s'); the previous file is unchanged",
                      path, strerror(errno), step, tmp);
    if (st)
        unlink(tmp);
    free(image);
    free(tmp);
    return st ? st : sph_ok(sim);
}

sph_status sph_checkpoint_read(sph_sim *sim, const char *path)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (sim->n == 0)
        return sph_fail(sim, SPH_ERR_STATE,
                        "the simulation has no particles: build the scene the checkpoint was "
                        "written from first");
    quiet q;
    quiet_begin(&q);
    sph_status st = SPH_OK;
    state_copy s = {0};
    hid_t g = -1;
    hid_t f = -1;
    long version = 0;
    if ((st = open_checked(sim, path, "checkpoint", &f, &version)))
        goto done;
    g = H5Gopen2(f, "checkpoint", H5P_DEFAULT);
    if (g < 0) {
        st = sph_fail(sim, SPH_ERR_IO, "'%s' has no /checkpoint group", path);
        goto done;
    }
    long dim = 0, n = 0, nb = 0, step = 0, dt_set = 0;
    double t = 0, dt = 0;
    size_t one = 0;
    if (read_attr_long(g, "dimension", &dim) || read_attr_long(g, "particles", &n) ||
        read_attr_long(g, "bodies", &nb) || read_attr_long(g, "step", &step) ||
        read_attr_long(g, "dt_set", &dt_set) || read_attr_doubles(g, "time", &t, 1, &one) ||
        read_attr_doubles(g, "dt", &dt, 1, &one)) {
        st = sph_fail(sim, SPH_ERR_IO, "checkpoint '%s' lacks its attributes", path);
        goto done;
    }
    char integ_name[64] = "";
    const integrator *in = NULL;
    if (read_attr_string(g, "integrator", integ_name, sizeof integ_name)) {
        st = sph_fail(sim, SPH_ERR_IO, "checkpoint '%s' does not name its integrator", path);
        goto done;
    }
    if (!(in = integrator_find(integ_name))) {
        st = sph_fail(sim, SPH_ERR_IO,
                      "checkpoint '%s' was written by integrator '%s', unknown here (known: %s)",
                      path, integ_name, sph_integrator_names());
        goto done;
    }
    if (dim != sim->dim || n < 0 || (size_t)n != sim->n || nb != sim->n_bodies) {
        st = sph_fail(sim, SPH_ERR_ARGUMENT,
                      "checkpoint '%s' holds %ld particles in %ld bodies in %ldD; this simulation "
                      "has %zu in %d bodies in %dD",
                      path, n, nb, dim, sim->n, sim->n_bodies, sim->dim);
        goto done;
    }
    if ((st = scene_matches(sim, f, path, 1, version)))
        goto done;
    {
        /* the checksummed copy of the clock decides */
        io cc = {0};
        double clock[4];
        if (read_doubles(&cc, g, "clock", -1, 4, clock)) {
            st = sph_fail(sim, SPH_ERR_IO, "cannot read checkpoint '%s': %s (reading %s)", path,
                          cc.cause, cc.what);
            goto done;
        }
        if (clock[0] != (double)step || clock[1] != t || clock[2] != dt ||
            clock[3] != (double)dt_set) {
            st = sph_fail(sim, SPH_ERR_IO,
                          "checkpoint '%s' is damaged: its clock attributes (step %ld, t %g s, dt "
                          "%g s) differ from the checksummed clock (step %.0f, t %g s, dt %g s)",
                          path, step, t, dt, clock[0], clock[1], clock[2]);
            goto done;
        }
    }
    if (!isfinite(t) || !(dt > 0.0) || !isfinite(dt) || step < 0) {
        st = sph_fail(sim, SPH_ERR_IO, "checkpoint '%s' is damaged: time %g, dt %g, step %ld", path,
                      t, dt, step);
        goto done;
    }
    if (state_alloc(&s, sim)) {
        st = sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate scratch arrays to read '%s'", path);
        goto done;
    }
    io c = {0};
    const size_t nn = sim->n, d = (size_t)sim->dim;
    static const char *const values[4] = {"position", "velocity", "density", "deviatoric_stress"};
    state_read(&c, g, values, -1, sim, &s);
    if (!c.failed)
        read_doubles(&c, g, "mass", -1, nn, s.mass);
    if (!c.failed)
        read_doubles(&c, g, "motion_vectors", -1, (size_t)nb * 3, s.motion);
    if (!c.failed)
        read_doubles(&c, g, "motion_centres", -1, (size_t)nb * 3, s.motion + (size_t)nb * 3);
    if (c.failed) {
        st = sph_fail(sim, SPH_ERR_IO, "cannot read checkpoint '%s': %s (reading %s)", path,
                      c.cause, c.what);
        goto done;
    }
    if (!state_plausible(sim, &s, path, 1)) {
        st = SPH_ERR_IO;
        goto done;
    }
    if (first_nonfinite(s.motion, (size_t)nb * 6) >= 0) {
        st = sph_fail(sim, SPH_ERR_IO,
                      "checkpoint '%s' is damaged: a body's motion vector is not finite", path);
        goto done;
    }
    const int with_rates = in->carries_rates && H5Lexists(g, "rate_velocity", H5P_DEFAULT) > 0;
    if (with_rates) {
        s.dv = malloc(nn * d * sizeof(double));
        s.drho = malloc(nn * sizeof(double));
        s.dS = malloc(nn * (size_t)sim->ncomp * sizeof(double));
        if (!s.dv || !s.drho || !s.dS) {
            st = sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate scratch arrays to read '%s'", path);
            goto done;
        }
        read_doubles(&c, g, "rate_velocity", -1, nn * d, s.dv);
        if (!c.failed)
            read_doubles(&c, g, "rate_density", -1, nn, s.drho);
        if (!c.failed)
            read_doubles(&c, g, "rate_deviatoric_stress", -1, nn * (size_t)sim->ncomp, s.dS);
        if (c.failed) {
            st = sph_fail(sim, SPH_ERR_IO,
                          "cannot read the integrator's rates of checkpoint '%s': %s (reading %s)",
                          path, c.cause, c.what);
            goto done;
        }
        /* the simulation's own rate arrays, grown before anything changes */
        double *dv = realloc(sim->dv_dt, nn * d * sizeof(double));
        if (dv)
            sim->dv_dt = dv;
        double *dr = realloc(sim->drho_dt, nn * sizeof(double));
        if (dr)
            sim->drho_dt = dr;
        double *dS = realloc(sim->dS_dt, nn * (size_t)sim->ncomp * sizeof(double));
        if (dS)
            sim->dS_dt = dS;
        if (!dv || !dr || !dS) {
            st = sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate the rates to read '%s'", path);
            goto done;
        }
    }
    /* commit: nothing above changed the simulation */
    state_commit(sim, &s, step, t);
    memcpy(sim->mass, s.mass, nn * sizeof(double));
    for (int k = 0; k < sim->n_bodies; ++k) {
        memcpy(sim->bodies[k].vector, s.motion + 3 * k, 3 * sizeof(double));
        memcpy(sim->bodies[k].centre, s.motion + 3 * (nb + k), 3 * sizeof(double));
    }
    sim->dt = dt;
    sim->dt_set = (int)dt_set;
    sim->integ = in;
    sim->carry_valid = 0;
    if (with_rates) {
        memcpy(sim->dv_dt, s.dv, nn * d * sizeof(double));
        memcpy(sim->drho_dt, s.drho, nn * sizeof(double));
        memcpy(sim->dS_dt, s.dS, nn * (size_t)sim->ncomp * sizeof(double));
        carried_rates_set(sim);
    }
    st = sph_ok(sim);
done:
    read_release(&q, &s, g, f);
    return st;
}

#else /* no HDF5 */

#define NO_HDF5(sim) sph_fail(sim, SPH_ERR_UNSUPPORTED, "libsphsolid was built without HDF5")

sph_status output_write_due(sph_sim *sim)
{
    (void)sim;
    return SPH_OK;
}
void output_free(sph_sim *sim) { (void)sim; }
sph_status sph_output_open(sph_sim *sim, const char *p, long a, long b)
{
    (void)p;
    (void)a;
    (void)b;
    return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT;
}
sph_status sph_output_snapshot(sph_sim *sim) { return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT; }
sph_status sph_output_close(sph_sim *sim) { return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT; }
sph_status sph_read_frame_count(sph_sim *sim, const char *p, long *f)
{
    (void)p;
    (void)f;
    return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT;
}
sph_status sph_read_frame(sph_sim *sim, const char *p, long f)
{
    (void)p;
    (void)f;
    return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT;
}
sph_status sph_checkpoint_write(sph_sim *sim, const char *p)
{
    (void)p;
    return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT;
}
sph_status sph_checkpoint_read(sph_sim *sim, const char *p)
{
    (void)p;
    return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT;
}

#endif
