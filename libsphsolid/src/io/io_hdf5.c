/*
 * HDF5 files (layout: docs/hdf5_layout.md): the helpers shared by output
 * (io_output.c), reading (io_read.c) and checkpoints (io_checkpoint.c):
 * error capture, writing attributes, datasets and series, the scene
 * records.
 *
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
 *   - nothing readers already trust is rewritten across a page boundary:
 *     a chunk that later appends rewrite in place (one holding several
 *     rows of a series) fits in one page and starts on a page boundary,
 *     as do the metadata blocks (IO_PAGE, file_access).  Linux copies a
 *     write into a file a page at a time and stops a killed process only
 *     between pages, so such a rewrite is left wholly old or wholly new,
 *     never a chunk whose checksum no longer matches rows written before;
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

#include "integrators/integrator.h"
#include "io/io_hdf5.h"

int sph_output_format_version(void) { return (int)SPH_FILE_FORMAT; }

#ifdef SPHSOLID_HAVE_HDF5
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

/* ----------------------------------------------------- error capture */

void io_quiet_begin(quiet *q)
{
    q->func = NULL;
    q->data = NULL;
    H5Eget_auto2(H5E_DEFAULT, &q->func, &q->data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

void io_quiet_end(const quiet *q)
{
    H5Eclear2(H5E_DEFAULT);
    H5Eset_auto2(H5E_DEFAULT, q->func, q->data);
}

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
 * `if (io_fail_at(c, ...)) ...`. */
int io_fail_at(io *c, const char *what, int use_errno)
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
int io_fail_memory(io *c, const char *what, size_t bytes)
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
int io_ok(io *c, long long result, const char *what)
{
    if (result < 0) {
        io_fail_at(c, what, 0);
        return 0;
    }
    return !c->failed;
}

void io_close_id(hid_t id)
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

int io_write_attr(io *c, hid_t obj, const char *name, hid_t type, hid_t space, const void *data)
{
    if (c->failed)
        return -1;
    hid_t a = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    if (!io_ok(c, a, name)) {
        io_close_id(a);
        return -1;
    }
    io_ok(c, H5Awrite(a, type, data), name);
    io_ok(c, H5Aclose(a), name);
    return c->failed ? -1 : 0;
}

int io_attr_double(io *c, hid_t obj, const char *name, const double *v, hsize_t n)
{
    hid_t space = H5Screate_simple(1, &n, NULL);
    if (!io_ok(c, space, name))
        return -1;
    io_write_attr(c, obj, name, H5T_NATIVE_DOUBLE, space, v);
    H5Sclose(space);
    return c->failed ? -1 : 0;
}

/* A scalar attribute of a native type (H5T_NATIVE_LONG, _DOUBLE). */
static int attr_scalar(io *c, hid_t obj, const char *name, hid_t type, const void *v)
{
    hid_t space = H5Screate(H5S_SCALAR);
    if (!io_ok(c, space, name))
        return -1;
    io_write_attr(c, obj, name, type, space, v);
    H5Sclose(space);
    return c->failed ? -1 : 0;
}

int io_attr_long(io *c, hid_t obj, const char *name, long v)
{
    return attr_scalar(c, obj, name, H5T_NATIVE_LONG, &v);
}

int io_attr_string(io *c, hid_t obj, const char *name, const char *text)
{
    hid_t type = H5Tcopy(H5T_C_S1);
    hid_t space = H5Screate(H5S_SCALAR);
    if (io_ok(c, type, name) && io_ok(c, space, name) &&
        io_ok(c, H5Tset_size(type, strlen(text) + 1), name))
        io_write_attr(c, obj, name, type, space, text);
    io_close_id(space);
    io_close_id(type);
    return c->failed ? -1 : 0;
}

/* Overwrites an existing scalar long attribute. */
int io_attr_long_update(io *c, hid_t obj, const char *name, long v)
{
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    if (io_ok(c, a, name))
        io_ok(c, H5Awrite(a, H5T_NATIVE_LONG, &v), name);
    if (a >= 0)
        io_ok(c, H5Aclose(a), name);
    return c->failed ? -1 : 0;
}

hid_t io_group_create(io *c, hid_t loc, const char *name)
{
    if (c->failed)
        return -1;
    hid_t g = H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    io_ok(c, g, name);
    return g;
}

int io_group_close(io *c, hid_t g, const char *name)
{
    if (g >= 0)
        io_ok(c, H5Gclose(g), name);
    return c->failed ? -1 : 0;
}

/* A fixed-size dataset, chunked (about 1 MiB per chunk) so that HDF5's
 * Fletcher32 filter checks every block of it on reading. */
int io_write_dataset(io *c, hid_t loc, const char *name, hid_t type, int rank, const hsize_t *dims,
                     const void *data)
{
    if (c->failed)
        return -1;
    hid_t space = H5Screate_simple(rank, dims, NULL);
    hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
    hid_t d = -1;
    if (io_ok(c, space, name) && io_ok(c, plist, name)) {
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
            io_ok(c, H5Pset_chunk(plist, rank, chunk), name);
            io_ok(c, H5Pset_fletcher32(plist), name);
        }
        if (!c->failed) {
            d = H5Dcreate2(loc, name, type, space, H5P_DEFAULT, plist, H5P_DEFAULT);
            if (io_ok(c, d, name) && total > 0)
                io_ok(c, H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), name);
            if (d >= 0)
                io_ok(c, H5Dclose(d), name);
        }
    }
    io_close_id(plist);
    io_close_id(space);
    return c->failed ? -1 : 0;
}

/* Rows per chunk of a series whose rows take row_bytes each: at most
 * max_rows, and a chunk of more than one row (rewritten in place as rows
 * are appended) fits in one page with its 4-byte checksum. */
static hsize_t series_chunk_rows(hsize_t row_bytes, hsize_t max_rows)
{
    hsize_t rows = (IO_PAGE - 4) / row_bytes;
    if (rows > max_rows)
        rows = max_rows;
    return rows < 1 ? 1 : rows;
}

/* An H5MD time series: group with extendible step, time and value, each
 * chunked and checksummed (value in chunks of at most value_rows records;
 * see series_chunk_rows). */
int io_series_create(io *c, hid_t loc, const char *name, int rank, const hsize_t *inner,
                     hsize_t value_rows)
{
    hid_t g = io_group_create(c, loc, name);
    hsize_t dims[4] = {0}, maxd[4] = {H5S_UNLIMITED}, chunk[4] = {1}, value_bytes = 8;
    for (int i = 0; i < rank; ++i) {
        dims[i + 1] = maxd[i + 1] = chunk[i + 1] = inner[i];
        value_bytes *= inner[i];
    }
    const char *names[3] = {"step", "time", "value"};
    for (int k = 0; k < 3 && !c->failed; ++k) {
        const int r = k < 2 ? 1 : rank + 1;
        hsize_t c1[4];
        memcpy(c1, chunk, sizeof c1);
        c1[0] = k < 2 ? series_chunk_rows(8, 256) : series_chunk_rows(value_bytes, value_rows);
        char what[160];
        snprintf(what, sizeof what, "%s/%s", name, names[k]);
        hid_t space = H5Screate_simple(r, dims, maxd);
        hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
        if (io_ok(c, space, what) && io_ok(c, plist, what) &&
            io_ok(c, H5Pset_chunk(plist, r, c1), what) &&
            io_ok(c, H5Pset_fletcher32(plist), what)) {
            hid_t d = H5Dcreate2(g, names[k], k == 0 ? H5T_NATIVE_LONG : H5T_NATIVE_DOUBLE, space,
                                 H5P_DEFAULT, plist, H5P_DEFAULT);
            if (io_ok(c, d, what))
                io_ok(c, H5Dclose(d), what);
        }
        io_close_id(plist);
        io_close_id(space);
    }
    return io_group_close(c, g, name);
}

static int extend_append(io *c, hid_t g, const char *group, const char *name, hid_t type,
                         hsize_t rows, const void *data)
{
    char what[160];
    snprintf(what, sizeof what, "%s/%s", group, name);
    hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
    if (!io_ok(c, d, what))
        return -1;
    hid_t space = H5Dget_space(d), mem = -1;
    hsize_t dims[4] = {0}, start[4] = {0}, count[4];
    const int rank = space >= 0 ? H5Sget_simple_extent_dims(space, dims, NULL) : -1;
    io_close_id(space);
    space = -1;
    if (io_ok(c, rank, what)) {
        start[0] = dims[0];
        dims[0] += rows;
        memcpy(count, dims, sizeof count);
        count[0] = rows;
        if (io_ok(c, H5Dset_extent(d, dims), what) && io_ok(c, space = H5Dget_space(d), what) &&
            io_ok(c, H5Sselect_hyperslab(space, H5S_SELECT_SET, start, NULL, count, NULL), what) &&
            io_ok(c, mem = H5Screate_simple(rank, count, NULL), what))
            io_ok(c, H5Dwrite(d, type, mem, space, H5P_DEFAULT, data), what);
    }
    io_close_id(mem);
    io_close_id(space);
    io_ok(c, H5Dclose(d), what);
    return c->failed ? -1 : 0;
}

/* Appends `rows` records (steps, times, values one after another). */
int io_series_append_rows(io *c, hid_t loc, const char *path, hsize_t rows, const long *step,
                          const double *time, const double *value)
{
    hid_t g = H5Gopen2(loc, path, H5P_DEFAULT);
    if (!io_ok(c, g, path)) {
        io_close_id(g);
        return -1;
    }
    extend_append(c, g, path, "step", H5T_NATIVE_LONG, rows, step);
    extend_append(c, g, path, "time", H5T_NATIVE_DOUBLE, rows, time);
    extend_append(c, g, path, "value", H5T_NATIVE_DOUBLE, rows, value);
    io_group_close(c, g, path);
    return c->failed ? -1 : 0;
}

int io_series_append(io *c, hid_t loc, const char *path, long step, double time,
                     const double *value)
{
    return io_series_append_rows(c, loc, path, 1, &step, &time, value);
}

/* File access: output files in the HDF5 1.8 format (checksummed metadata;
 * readable by HDF5 1.8 and later and by h5py), every block of half a page
 * or more (multi-row chunks, metadata blocks) aligned on a page boundary;
 * checkpoints built in memory
 * (no disk access by HDF5: the image is written by write_image) in the
 * oldest format that holds them, whose in-memory image HDF5 1.10 hands out
 * intact.  Closing a file closes everything in it. */
static hid_t file_access(io *c, int in_memory)
{
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    if (io_ok(c, fapl, "file access properties") &&
        io_ok(c,
              H5Pset_libver_bounds(fapl, in_memory ? H5F_LIBVER_EARLIEST : H5F_LIBVER_V18,
                                   H5F_LIBVER_V18),
              "file format") &&
        io_ok(c, H5Pset_fclose_degree(fapl, H5F_CLOSE_STRONG), "file access properties") &&
        (in_memory || io_ok(c, H5Pset_alignment(fapl, IO_PAGE / 2, IO_PAGE), "file alignment")) &&
        (!in_memory || io_ok(c, H5Pset_fapl_core(fapl, (size_t)1 << 16, 0), "in-memory file")))
        return fapl;
    io_close_id(fapl);
    return -1;
}

/* Creates (or truncates) `path` with the access properties of file_access;
 * -1 with the cause in c on failure. */
hid_t io_file_create(io *c, const char *path, int in_memory)
{
    hid_t fapl = file_access(c, in_memory);
    hid_t file = -1;
    if (!c->failed) {
        file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
        io_ok(c, file, "the file (create)");
    }
    io_close_id(fapl);
    return file;
}

/* ------------------------------------------------------ scene records */

const char *io_motion_name(sph_motion m)
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

int io_write_format(io *c, hid_t file, const char *content)
{
    io_attr_long(c, file, "sphsolid_format", SPH_FILE_FORMAT);
    io_attr_string(c, file, "sphsolid_content", content);
    return c->failed ? -1 : 0;
}

/* /parameters/effects: a group per effect that is on, named as in the
 * registry (effects.c), holding one float64 attribute per parameter. */
static int write_effects(io *c, sph_sim *sim, hid_t par)
{
    hid_t all = io_group_create(c, par, "effects");
    for (int k = 0; k < sph_effect_count() && !c->failed; ++k) {
        sph_effect_info e;
        double values[EFFECTS_MAX_PARAMETERS];
        if (sph_effect_info_get(k, &e) || !effects_values(&sim->fx, k, values))
            continue;
        hid_t g = io_group_create(c, all, e.name);
        for (int j = 0; j < e.parameter_count; ++j) {
            sph_effect_parameter p;
            if (!sph_effect_parameter_get(k, j, &p))
                attr_scalar(c, g, p.key, H5T_NATIVE_DOUBLE, &values[j]);
        }
        io_group_close(c, g, e.name);
    }
    io_group_close(c, all, "parameters/effects");
    return c->failed ? -1 : 0;
}

/* /parameters: the model and the scene's bodies; readers compare it with
 * the simulation they load into. */
int io_write_parameters(io *c, sph_sim *sim, hid_t file)
{
    const int dim = sim->dim, nc = sim->ncomp;
    hid_t par = io_group_create(c, file, "parameters");
    io_attr_long(c, par, "dimension", dim);
    io_attr_long(c, par, "stress_components", nc);
    io_attr_double(c, par, "smoothing_length", &sim->h, 1);
    io_attr_double(c, par, "spacing", &sim->dx_ref, 1);
    io_attr_double(c, par, "dt", &sim->dt, 1);
    io_attr_string(c, par, "kernel", sph_kernel_name((sph_kernel)sim->kernel));
    io_attr_string(c, par, "integrator", sim_integrator(sim)->name);
    {
        char fx[1024];
        effects_describe(&sim->fx, fx, sizeof fx);
        io_attr_string(c, par, "effects", fx);
        write_effects(c, sim, par);
    }
    io_attr_string(c, par, "stress_order", dim == 2 ? "xx yy zz xy" : "xx yy zz xy xz yz");
    {
        double *m = malloc((size_t)(sim->n_materials ? sim->n_materials : 1) * 3 * sizeof *m);
        if (!m) {
            io_fail_memory(c, "materials", 0);
        } else {
            for (int k = 0; k < sim->n_materials; ++k) {
                m[3 * k] = sim->materials[k].K;
                m[3 * k + 1] = sim->materials[k].mu;
                m[3 * k + 2] = sim->materials[k].rho0;
            }
            hsize_t d[2] = {(hsize_t)sim->n_materials, 3};
            io_write_dataset(c, par, "materials", H5T_NATIVE_DOUBLE, 2, d, m);
            free(m);
        }
        io_attr_string(c, par, "materials_columns", "bulk_modulus shear_modulus rho0");
    }
    hid_t bodies = io_group_create(c, par, "bodies");
    for (int k = 0; k < sim->n_bodies && !c->failed; ++k) {
        const body *b = &sim->bodies[k];
        hid_t g = io_group_create(c, bodies, b->name);
        io_attr_long(c, g, "index", k);
        io_attr_long(c, g, "first", (long)b->first);
        io_attr_long(c, g, "count", (long)b->count);
        io_attr_long(c, g, "material", b->material);
        io_attr_string(c, g, "motion", io_motion_name(b->motion));
        if (b->motion == SPH_MOTION_ROTATION) {
            io_attr_double(c, g, "angular_velocity", b->vector, 3);
            io_attr_double(c, g, "centre", b->centre, (hsize_t)dim);
        } else {
            io_attr_double(c, g, "vector", b->vector, (hsize_t)dim);
        }
        io_attr_double(c, g, "spacing", &b->spacing, 1);
        io_attr_double(c, g, "extent_lo", b->extent_lo, (hsize_t)dim);
        io_attr_double(c, g, "extent_hi", b->extent_hi, (hsize_t)dim);
        io_group_close(c, g, b->name);
    }
    io_group_close(c, bodies, "bodies");
    io_group_close(c, par, "parameters");
    return c->failed ? -1 : 0;
}

#endif
