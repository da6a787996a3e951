/*
 * HDF5 output, read-back and checkpoints (layout: docs/hdf5_layout.md).
 * The file follows H5MD conventions where they fit: time series are groups
 * holding `step`, `time` and `value` datasets extended frame by frame.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "integrator.h"
#include "sim.h"

#ifdef SPHSOLID_HAVE_HDF5
#include <hdf5.h>

struct output_file {
    hid_t file;
    long snapshot_interval, probe_interval;
    long frames, probe_frames;
    long last_snapshot_step, last_probe_step;
    char path[1024];
};

/* ------------------------------------------------------------- helpers */

static void attr_double(hid_t obj, const char *name, const double *v, hsize_t n)
{
    hid_t space = H5Screate_simple(1, &n, NULL);
    hid_t a = H5Acreate2(obj, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_DOUBLE, v);
    H5Aclose(a);
    H5Sclose(space);
}

static void attr_long(hid_t obj, const char *name, long v)
{
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(obj, name, H5T_NATIVE_LONG, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_LONG, &v);
    H5Aclose(a);
    H5Sclose(space);
}

static void attr_string(hid_t obj, const char *name, const char *text)
{
    hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, strlen(text) + 1);
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, type, text);
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
}

static int read_attr_double(hid_t obj, const char *name, double *v)
{
    if (H5Aexists(obj, name) <= 0)
        return -1;
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    herr_t e = H5Aread(a, H5T_NATIVE_DOUBLE, v);
    H5Aclose(a);
    return e < 0 ? -1 : 0;
}

static int read_attr_long(hid_t obj, const char *name, long *v)
{
    if (H5Aexists(obj, name) <= 0)
        return -1;
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    herr_t e = H5Aread(a, H5T_NATIVE_LONG, v);
    H5Aclose(a);
    return e < 0 ? -1 : 0;
}

/* A fixed-length string attribute as attr_string writes it, into buf. */
static int read_attr_string(hid_t obj, const char *name, char *buf, size_t size)
{
    if (H5Aexists(obj, name) <= 0)
        return -1;
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    hid_t type = H5Aget_type(a);
    const size_t len = H5Tget_size(type);
    herr_t e = -1;
    if (H5Tget_class(type) == H5T_STRING && len < size) {
        hid_t mem = H5Tcopy(H5T_C_S1);
        H5Tset_size(mem, len);
        e = H5Aread(a, mem, buf);
        H5Tclose(mem);
        buf[len] = '\0';
    }
    H5Tclose(type);
    H5Aclose(a);
    return e < 0 ? -1 : 0;
}

static void write_dataset(hid_t loc, const char *name, hid_t type, int rank,
                          const hsize_t *dims, const void *data)
{
    hid_t space = H5Screate_simple(rank, dims, NULL);
    hid_t d = H5Dcreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
    H5Dclose(d);
    H5Sclose(space);
}

/* An H5MD time series: group with extendible step, time and value. */
static void series_create(hid_t loc, const char *name, int rank, const hsize_t *inner)
{
    hid_t g = H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    hsize_t dims[4] = {0}, maxd[4] = {H5S_UNLIMITED}, chunk[4] = {1};
    for (int i = 0; i < rank; ++i) {
        dims[i + 1] = maxd[i + 1] = chunk[i + 1] = inner[i];
    }
    const char *names[3] = {"step", "time", "value"};
    for (int k = 0; k < 3; ++k) {
        const int r = k < 2 ? 1 : rank + 1;
        hsize_t c1[4];
        memcpy(c1, chunk, sizeof c1);
        c1[0] = k < 2 ? 256 : 1;
        hid_t space = H5Screate_simple(r, dims, maxd);
        hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
        H5Pset_chunk(plist, r, c1);
        hid_t d = H5Dcreate2(g, names[k], k == 0 ? H5T_NATIVE_LONG : H5T_NATIVE_DOUBLE,
                             space, H5P_DEFAULT, plist, H5P_DEFAULT);
        H5Dclose(d);
        H5Pclose(plist);
        H5Sclose(space);
    }
    H5Gclose(g);
}

static int extend_append(hid_t g, const char *name, hid_t type, const void *data)
{
    hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
    if (d < 0)
        return -1;
    hid_t space = H5Dget_space(d);
    hsize_t dims[4], start[4] = {0}, count[4];
    const int rank = H5Sget_simple_extent_dims(space, dims, NULL);
    H5Sclose(space);
    start[0] = dims[0];
    dims[0] += 1;
    int err = H5Dset_extent(d, dims) < 0;
    space = H5Dget_space(d);
    memcpy(count, dims, sizeof count);
    count[0] = 1;
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start, NULL, count, NULL);
    hid_t mem = H5Screate_simple(rank, count, NULL);
    err |= H5Dwrite(d, type, mem, space, H5P_DEFAULT, data) < 0;
    H5Sclose(mem);
    H5Sclose(space);
    H5Dclose(d);
    return err ? -1 : 0;
}

static int series_append(hid_t loc, const char *path, long step, double time,
                         const double *value)
{
    hid_t g = H5Gopen2(loc, path, H5P_DEFAULT);
    if (g < 0)
        return -1;
    int err = extend_append(g, "step", H5T_NATIVE_LONG, &step);
    err |= extend_append(g, "time", H5T_NATIVE_DOUBLE, &time);
    err |= extend_append(g, "value", H5T_NATIVE_DOUBLE, value);
    H5Gclose(g);
    return err;
}

/* -------------------------------------------------------------- output */

static sph_status write_snapshot(sph_sim *sim)
{
    struct output_file *o = sim->out;
    const size_t n = sim->n;
    const int dim = sim->dim, nc = sim->ncomp;
    double *buf = malloc(n * (size_t)nc * sizeof *buf);
    if (!buf)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate the snapshot buffer");
    hid_t all = H5Gopen2(o->file, "/particles/all", H5P_DEFAULT);
    int err = all < 0;
    err |= series_append(all, "position", sim->step, sim->t, sim->x);
    err |= series_append(all, "velocity", sim->step, sim->t, sim->v);
    err |= series_append(all, "density", sim->step, sim->t, sim->rho);
    err |= series_append(all, "deviatoric_stress", sim->step, sim->t, sim->S);
    sph_field_copy(sim, SPH_FIELD_PRESSURE, buf);
    err |= series_append(all, "pressure", sim->step, sim->t, buf);
    sph_field_copy(sim, SPH_FIELD_VON_MISES, buf);
    err |= series_append(all, "von_mises", sim->step, sim->t, buf);
    H5Gclose(all);
    free(buf);
    (void)dim;
    H5Fflush(o->file, H5F_SCOPE_GLOBAL);
    if (err)
        return sph_fail(sim, SPH_ERR_IO, "cannot write snapshot %ld to '%s'", o->frames, o->path);
    o->frames++;
    o->last_snapshot_step = sim->step;
    return sph_ok(sim);
}

static sph_status write_probes(sph_sim *sim)
{
    struct output_file *o = sim->out;
    if (sim->n_probes == 0)
        return SPH_OK;
    const int nv = SPH_PROBE_VALUES(sim->dim);
    double *values = malloc((size_t)sim->n_probes * nv * sizeof *values);
    if (!values)
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate probe values");
    for (int k = 0; k < sim->n_probes; ++k)
        probe_sample_point(sim, sim->probes[k].point, values + (size_t)k * nv);
    int err = series_append(o->file, "/observables/probes", sim->step, sim->t, values);
    free(values);
    if (err)
        return sph_fail(sim, SPH_ERR_IO, "cannot write probe samples to '%s'", o->path);
    o->probe_frames++;
    o->last_probe_step = sim->step;
    return SPH_OK;
}

sph_status output_write_due(sph_sim *sim)
{
    struct output_file *o = sim->out;
    sph_status st = SPH_OK;
    if (o->snapshot_interval > 0 && sim->step % o->snapshot_interval == 0 &&
        o->last_snapshot_step != sim->step)
        st = write_snapshot(sim);
    if (!st && o->probe_interval > 0 && sim->step % o->probe_interval == 0 &&
        o->last_probe_step != sim->step)
        st = write_probes(sim);
    return st;
}

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

static void write_static(sph_sim *sim, hid_t file)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const hsize_t n = sim->n;
    hid_t h5md = H5Gcreate2(file, "h5md", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    {
        hsize_t two = 2;
        int version[2] = {1, 1};
        hid_t space = H5Screate_simple(1, &two, NULL);
        hid_t a = H5Acreate2(h5md, "version", H5T_NATIVE_INT, space, H5P_DEFAULT, H5P_DEFAULT);
        H5Awrite(a, H5T_NATIVE_INT, version);
        H5Aclose(a);
        H5Sclose(space);
        hid_t creator = H5Gcreate2(h5md, "creator", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        attr_string(creator, "name", "libsphsolid");
        attr_string(creator, "version", sph_version());
        H5Gclose(creator);
        hid_t author = H5Gcreate2(h5md, "author", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        attr_string(author, "name", "libsphsolid");
        H5Gclose(author);
    }
    H5Gclose(h5md);

    hid_t par = H5Gcreate2(file, "parameters", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    attr_long(par, "dimension", dim);
    attr_long(par, "stress_components", nc);
    attr_double(par, "smoothing_length", &sim->h, 1);
    attr_double(par, "spacing", &sim->dx_ref, 1);
    attr_double(par, "dt", &sim->dt, 1);
    attr_string(par, "kernel", sph_kernel_name((sph_kernel)sim->kernel));
    attr_string(par, "integrator", sim_integrator(sim)->name);
    {
        char fx[1024];
        effects_describe(&sim->fx, fx, sizeof fx);
        attr_string(par, "effects", fx);
    }
    attr_string(par, "stress_order", dim == 2 ? "xx yy zz xy" : "xx yy zz xy xz yz");
    {
        double *m = malloc((size_t)(sim->n_materials ? sim->n_materials : 1) * 3 * sizeof *m);
        for (int k = 0; k < sim->n_materials; ++k) {
            m[3 * k] = sim->materials[k].K;
            m[3 * k + 1] = sim->materials[k].mu;
            m[3 * k + 2] = sim->materials[k].rho0;
        }
        hsize_t d[2] = {(hsize_t)sim->n_materials, 3};
        write_dataset(par, "materials", H5T_NATIVE_DOUBLE, 2, d, m);
        free(m);
        attr_string(par, "materials_columns", "bulk_modulus shear_modulus rho0");
    }
    hid_t bodies = H5Gcreate2(par, "bodies", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    for (int k = 0; k < sim->n_bodies; ++k) {
        const body *b = &sim->bodies[k];
        hid_t g = H5Gcreate2(bodies, b->name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        attr_long(g, "index", k);
        attr_long(g, "first", (long)b->first);
        attr_long(g, "count", (long)b->count);
        attr_long(g, "material", b->material);
        attr_string(g, "motion", motion_name(b->motion));
        if (b->motion == SPH_MOTION_ROTATION) {
            attr_double(g, "angular_velocity", b->vector, 3);
            attr_double(g, "centre", b->centre, (hsize_t)dim);
        } else {
            attr_double(g, "vector", b->vector, (hsize_t)dim);
        }
        attr_double(g, "spacing", &b->spacing, 1);
        H5Gclose(g);
    }
    H5Gclose(bodies);
    H5Gclose(par);

    hid_t parts = H5Gcreate2(file, "particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    hid_t all = H5Gcreate2(parts, "all", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    hid_t box = H5Gcreate2(all, "box", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    attr_long(box, "dimension", dim);
    {
        const char *periodic = "periodic", *none = "none";
        hid_t type = H5Tcopy(H5T_C_S1);
        H5Tset_size(type, 9);
        char bnd[3][9] = {"none", "none", "none"};
        for (int i = 0; i < dim && i < 3; ++i)
            strcpy(bnd[i], sim->has_domain && sim->periodic[i] ? periodic : none);
        hsize_t d = (hsize_t)dim;
        hid_t space = H5Screate_simple(1, &d, NULL);
        hid_t a = H5Acreate2(box, "boundary", type, space, H5P_DEFAULT, H5P_DEFAULT);
        H5Awrite(a, type, bnd);
        H5Aclose(a);
        H5Sclose(space);
        H5Tclose(type);
        if (sim->has_domain) {
            double edges[3];
            for (int i = 0; i < dim; ++i)
                edges[i] = sim->hi[i] - sim->lo[i];
            hsize_t dd = (hsize_t)dim;
            write_dataset(box, "edges", H5T_NATIVE_DOUBLE, 1, &dd, edges);
            write_dataset(box, "offset", H5T_NATIVE_DOUBLE, 1, &dd, sim->lo);
        }
    }
    H5Gclose(box);
    write_dataset(all, "mass", H5T_NATIVE_DOUBLE, 1, &n, sim->mass);
    write_dataset(all, "body", H5T_NATIVE_INT, 1, &n, sim->body_of);
    write_dataset(all, "material", H5T_NATIVE_INT, 1, &n, sim->material_of);
    hsize_t vec[2] = {n, (hsize_t)dim}, ten[2] = {n, (hsize_t)nc};
    series_create(all, "position", 2, vec);
    series_create(all, "velocity", 2, vec);
    series_create(all, "density", 1, &n);
    series_create(all, "pressure", 1, &n);
    series_create(all, "deviatoric_stress", 2, ten);
    series_create(all, "von_mises", 1, &n);
    H5Gclose(all);
    H5Gclose(parts);

    hid_t obs = H5Gcreate2(file, "observables", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (sim->n_probes > 0) {
        const int nv = SPH_PROBE_VALUES(dim);
        hsize_t inner[2] = {(hsize_t)sim->n_probes, (hsize_t)nv};
        series_create(obs, "probes", 2, inner);
        hid_t pg = H5Gopen2(obs, "probes", H5P_DEFAULT);
        char names[4096] = "";
        double *points = malloc((size_t)sim->n_probes * dim * sizeof *points);
        for (int k = 0; k < sim->n_probes; ++k) {
            if (k)
                strncat(names, " ", sizeof names - strlen(names) - 1);
            strncat(names, sim->probes[k].name, sizeof names - strlen(names) - 1);
            for (int i = 0; i < dim; ++i)
                points[k * dim + i] = sim->probes[k].point[i];
        }
        attr_string(pg, "names", names);
        attr_string(pg, "columns", dim == 2 ? "von_mises pressure sigma_xx sigma_yy sigma_zz sigma_xy"
                                            : "von_mises pressure sigma_xx sigma_yy sigma_zz sigma_xy sigma_xz sigma_yz");
        hsize_t pd[2] = {(hsize_t)sim->n_probes, (hsize_t)dim};
        write_dataset(pg, "points", H5T_NATIVE_DOUBLE, 2, pd, points);
        free(points);
        H5Gclose(pg);
    }
    H5Gclose(obs);
}

sph_status sph_output_open(sph_sim *sim, const char *path, long snapshot_interval,
                           long probe_interval)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!path || !*path)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "output path is empty");
    if (snapshot_interval < 0 || probe_interval < 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "output intervals (snapshot %ld, probe %ld) must be >= 0",
                        snapshot_interval, probe_interval);
    if (sim->out)
        return sph_fail(sim, SPH_ERR_STATE, "an output file is already open ('%s')", sim->out->path);
    sph_status st = sim_prepare(sim);
    if (st)
        return st;
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    hid_t file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0)
        return sph_fail(sim, SPH_ERR_IO, "cannot create HDF5 file '%s'", path);
    struct output_file *o = calloc(1, sizeof *o);
    if (!o) {
        H5Fclose(file);
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate the output state");
    }
    o->file = file;
    o->snapshot_interval = snapshot_interval;
    o->probe_interval = probe_interval;
    o->last_snapshot_step = o->last_probe_step = -1;
    snprintf(o->path, sizeof o->path, "%s", path);
    sim->out = o;
    write_static(sim, file);
    if ((st = write_snapshot(sim)))
        return st;
    if (probe_interval > 0 && (st = write_probes(sim)))
        return st;
    return sph_ok(sim);
}

sph_status sph_output_snapshot(sph_sim *sim)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!sim->out)
        return sph_fail(sim, SPH_ERR_STATE, "no output file is open");
    if (sim->out->last_snapshot_step == sim->step)
        return sph_ok(sim);
    return write_snapshot(sim);
}

void output_free(sph_sim *sim)
{
    if (sim->out) {
        H5Fclose(sim->out->file);
        free(sim->out);
        sim->out = NULL;
    }
}

sph_status sph_output_close(sph_sim *sim)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!sim->out)
        return sph_fail(sim, SPH_ERR_STATE, "no output file is open");
    struct output_file *o = sim->out;
    /* the final state is always in the file, then the XDMF companion */
    sph_status st = o->last_snapshot_step != sim->step ? write_snapshot(sim) : SPH_OK;
    if (!st && o->probe_interval > 0 && o->last_probe_step != sim->step)
        st = write_probes(sim);
    char path[sizeof o->path];
    memcpy(path, o->path, sizeof path);
    herr_t e = H5Fclose(o->file);
    free(o);
    sim->out = NULL;
    if (st)
        return st;
    if (e < 0)
        return sph_fail(sim, SPH_ERR_IO, "closing the output file failed");
    return sph_write_xdmf(sim, path);
}

/* ------------------------------------------------------------ read back */

static hid_t open_readable(sph_sim *sim, const char *path)
{
    if (!path) {
        sph_fail(sim, SPH_ERR_ARGUMENT, "file path is NULL");
        return -1;
    }
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0)
        sph_fail(sim, SPH_ERR_IO, "cannot open '%s' as an HDF5 file", path);
    return f;
}

/* Read frame `frame` of series `name` (value must have `per` doubles per
 * particle and sim->n particles). */
static int read_series_frame(hid_t all, const char *name, long frame, size_t n,
                             int per, double *out, long *step, double *time)
{
    char p[128];
    snprintf(p, sizeof p, "%s/value", name);
    hid_t d = H5Dopen2(all, p, H5P_DEFAULT);
    if (d < 0)
        return -1;
    hid_t space = H5Dget_space(d);
    hsize_t dims[3] = {0, 0, 1};
    const int rank = H5Sget_simple_extent_dims(space, dims, NULL);
    if (dims[1] != n || (rank == 3 ? dims[2] : 1) != (hsize_t)per || frame < 0 || (hsize_t)frame >= dims[0]) {
        H5Sclose(space);
        H5Dclose(d);
        return -2;
    }
    hsize_t start[3] = {(hsize_t)frame, 0, 0}, count[3] = {1, dims[1], dims[2]};
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start, NULL, count, NULL);
    hid_t mem = H5Screate_simple(rank, count, NULL);
    herr_t e = H5Dread(d, H5T_NATIVE_DOUBLE, mem, space, H5P_DEFAULT, out);
    H5Sclose(mem);
    H5Sclose(space);
    H5Dclose(d);
    if (e < 0)
        return -1;
    if (step || time) {
        snprintf(p, sizeof p, "%s/step", name);
        hid_t ds = H5Dopen2(all, p, H5P_DEFAULT);
        snprintf(p, sizeof p, "%s/time", name);
        hid_t dt = H5Dopen2(all, p, H5P_DEFAULT);
        hsize_t s1 = (hsize_t)frame, c1 = 1;
        hid_t m1 = H5Screate_simple(1, &c1, NULL);
        hid_t sp = H5Dget_space(ds);
        H5Sselect_hyperslab(sp, H5S_SELECT_SET, &s1, NULL, &c1, NULL);
        H5Dread(ds, H5T_NATIVE_LONG, m1, sp, H5P_DEFAULT, step);
        H5Sclose(sp);
        sp = H5Dget_space(dt);
        H5Sselect_hyperslab(sp, H5S_SELECT_SET, &s1, NULL, &c1, NULL);
        H5Dread(dt, H5T_NATIVE_DOUBLE, m1, sp, H5P_DEFAULT, time);
        H5Sclose(sp);
        H5Sclose(m1);
        H5Dclose(ds);
        H5Dclose(dt);
    }
    return 0;
}

sph_status sph_read_frame_count(sph_sim *sim, const char *path, long *frames)
{
    if (!sim || !frames)
        return SPH_ERR_ARGUMENT;
    hid_t f = open_readable(sim, path);
    if (f < 0)
        return SPH_ERR_IO;
    hid_t d = H5Dopen2(f, "/particles/all/position/value", H5P_DEFAULT);
    if (d < 0) {
        H5Fclose(f);
        return sph_fail(sim, SPH_ERR_IO, "'%s' has no /particles/all/position/value: not a libsphsolid output file", path);
    }
    hid_t space = H5Dget_space(d);
    hsize_t dims[3];
    H5Sget_simple_extent_dims(space, dims, NULL);
    *frames = (long)dims[0];
    H5Sclose(space);
    H5Dclose(d);
    H5Fclose(f);
    return sph_ok(sim);
}

sph_status sph_read_frame(sph_sim *sim, const char *path, long frame)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    long frames;
    sph_status st = sph_read_frame_count(sim, path, &frames);
    if (st)
        return st;
    if (frame < 0)
        frame += frames;
    if (frame < 0 || frame >= frames)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "frame=%ld: '%s' has %ld frames", frame, path, frames);
    hid_t f = open_readable(sim, path);
    if (f < 0)
        return SPH_ERR_IO;
    hid_t all = H5Gopen2(f, "/particles/all", H5P_DEFAULT);
    long step = 0;
    double time = 0.0;
    const size_t n = sim->n;
    int e = read_series_frame(all, "position", frame, n, sim->dim, sim->x, &step, &time);
    if (!e) e = read_series_frame(all, "velocity", frame, n, sim->dim, sim->v, NULL, NULL);
    if (!e) e = read_series_frame(all, "density", frame, n, 1, sim->rho, NULL, NULL);
    if (!e) e = read_series_frame(all, "deviatoric_stress", frame, n, sim->ncomp, sim->S, NULL, NULL);
    H5Gclose(all);
    H5Fclose(f);
    if (e == -2)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "'%s' does not match this simulation (%zu particles in %d dimensions)",
                        path, n, sim->dim);
    if (e)
        return sph_fail(sim, SPH_ERR_IO, "cannot read frame %ld of '%s'", frame, path);
    sim->step = step;
    sim->t = time;
    sim->nl.valid = 0;
    sim->rates_valid = 0;
    return sph_ok(sim);
}

/* ---------------------------------------------------------- checkpoints */

sph_status sph_checkpoint_write(sph_sim *sim, const char *path)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!path || !*path)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "checkpoint path is empty");
    if (sim->n == 0)
        return sph_fail(sim, SPH_ERR_STATE, "nothing to checkpoint: the simulation has no particles");
    if (!sim->dt_set && sim->dt <= 0.0)
        sim->dt = sph_default_dt(sim);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    /* Write to a temporary name and rename, so a crash mid-write leaves the
     * previous checkpoint intact. */
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    hid_t f = H5Fcreate(tmp, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (f < 0)
        return sph_fail(sim, SPH_ERR_IO, "cannot create checkpoint '%s'", tmp);
    hid_t g = H5Gcreate2(f, "checkpoint", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    attr_long(g, "dimension", sim->dim);
    attr_long(g, "particles", (long)sim->n);
    attr_long(g, "bodies", sim->n_bodies);
    attr_long(g, "step", sim->step);
    attr_double(g, "time", &sim->t, 1);
    attr_double(g, "dt", &sim->dt, 1);
    attr_long(g, "dt_set", sim->dt_set);
    attr_string(g, "integrator", sim_integrator(sim)->name);
    const hsize_t n = sim->n;
    hsize_t vec[2] = {n, (hsize_t)sim->dim}, ten[2] = {n, (hsize_t)sim->ncomp};
    write_dataset(g, "position", H5T_NATIVE_DOUBLE, 2, vec, sim->x);
    write_dataset(g, "velocity", H5T_NATIVE_DOUBLE, 2, vec, sim->v);
    write_dataset(g, "density", H5T_NATIVE_DOUBLE, 1, &n, sim->rho);
    write_dataset(g, "deviatoric_stress", H5T_NATIVE_DOUBLE, 2, ten, sim->S);
    write_dataset(g, "mass", H5T_NATIVE_DOUBLE, 1, &n, sim->mass);
    {
        double *vectors = calloc((size_t)sim->n_bodies * 3 + 1, sizeof *vectors);
        for (int k = 0; k < sim->n_bodies; ++k)
            memcpy(vectors + 3 * k, sim->bodies[k].vector, 3 * sizeof(double));
        hsize_t d[2] = {(hsize_t)sim->n_bodies, 3};
        write_dataset(g, "motion_vectors", H5T_NATIVE_DOUBLE, 2, d, vectors);
        for (int k = 0; k < sim->n_bodies; ++k)
            memcpy(vectors + 3 * k, sim->bodies[k].centre, 3 * sizeof(double));
        write_dataset(g, "motion_centres", H5T_NATIVE_DOUBLE, 2, d, vectors);
        free(vectors);
    }
    if (sim_integrator(sim)->carries_rates && carried_rates_valid(sim)) {
        /* the rates the next step starts from */
        write_dataset(g, "rate_velocity", H5T_NATIVE_DOUBLE, 2, vec, sim->dv_dt);
        write_dataset(g, "rate_density", H5T_NATIVE_DOUBLE, 1, &n, sim->drho_dt);
        write_dataset(g, "rate_deviatoric_stress", H5T_NATIVE_DOUBLE, 2, ten, sim->dS_dt);
    }
    H5Gclose(g);
    const herr_t e = H5Fclose(f);
    if (e < 0 || rename(tmp, path) != 0)
        return sph_fail(sim, SPH_ERR_IO, "cannot write checkpoint '%s'", path);
    return sph_ok(sim);
}

static int read_array(hid_t g, const char *name, size_t expect, double *out)
{
    hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
    if (d < 0)
        return -1;
    hid_t space = H5Dget_space(d);
    const hssize_t count = H5Sget_simple_extent_npoints(space);
    H5Sclose(space);
    if (count != (hssize_t)expect) {
        H5Dclose(d);
        return -2;
    }
    herr_t e = H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out);
    H5Dclose(d);
    return e < 0 ? -1 : 0;
}

sph_status sph_checkpoint_read(sph_sim *sim, const char *path)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    hid_t f = open_readable(sim, path);
    if (f < 0)
        return SPH_ERR_IO;
    hid_t g = H5Gopen2(f, "checkpoint", H5P_DEFAULT);
    if (g < 0) {
        H5Fclose(f);
        return sph_fail(sim, SPH_ERR_IO, "'%s' has no /checkpoint group: not a libsphsolid checkpoint", path);
    }
    long dim = 0, n = 0, nb = 0, step = 0, dt_set = 0;
    double t = 0, dt = 0;
    int e = read_attr_long(g, "dimension", &dim) | read_attr_long(g, "particles", &n) |
            read_attr_long(g, "bodies", &nb) | read_attr_long(g, "step", &step) |
            read_attr_long(g, "dt_set", &dt_set) | read_attr_double(g, "time", &t) |
            read_attr_double(g, "dt", &dt);
    char name[64] = "improved_euler";   /* checkpoints before integrators had names */
    const integrator *in = NULL;
    if (!e && H5Aexists(g, "integrator") > 0 && read_attr_string(g, "integrator", name, sizeof name))
        e = 1;
    sph_status st = SPH_OK;
    if (!e && !(in = integrator_find(name))) {
        st = sph_fail(sim, SPH_ERR_IO, "checkpoint '%s' was written by integrator '%s', unknown here (known: %s)",
                      path, name, sph_integrator_names());
    } else if (e) {
        st = sph_fail(sim, SPH_ERR_IO, "checkpoint '%s' lacks its attributes", path);
    } else if (dim != sim->dim || (size_t)n != sim->n || nb != sim->n_bodies) {
        st = sph_fail(sim, SPH_ERR_ARGUMENT,
                      "checkpoint '%s' holds %ld particles in %ld bodies in %ldD; this simulation has %zu in %d bodies in %dD",
                      path, n, nb, dim, sim->n, sim->n_bodies, sim->dim);
    } else {
        double *vectors = malloc((size_t)nb * 6 * sizeof *vectors + 1);
        e = read_array(g, "position", sim->n * sim->dim, sim->x);
        e = e ? e : read_array(g, "velocity", sim->n * sim->dim, sim->v);
        e = e ? e : read_array(g, "density", sim->n, sim->rho);
        e = e ? e : read_array(g, "deviatoric_stress", sim->n * sim->ncomp, sim->S);
        e = e ? e : read_array(g, "mass", sim->n, sim->mass);
        e = e ? e : read_array(g, "motion_vectors", (size_t)nb * 3, vectors);
        e = e ? e : read_array(g, "motion_centres", (size_t)nb * 3, vectors + (size_t)nb * 3);
        if (e) {
            st = sph_fail(sim, SPH_ERR_IO, "cannot read the state arrays of checkpoint '%s'", path);
        } else {
            for (int k = 0; k < sim->n_bodies; ++k) {
                memcpy(sim->bodies[k].vector, vectors + 3 * k, 3 * sizeof(double));
                memcpy(sim->bodies[k].centre, vectors + 3 * (nb + k), 3 * sizeof(double));
            }
            sim->step = step;
            sim->t = t;
            sim->dt = dt;
            sim->dt_set = (int)dt_set;
            sim->nl.valid = 0;
            sim->rates_valid = 0;
            sim->integ = in;
            sim->carry_valid = 0;
            if (in->carries_rates && H5Lexists(g, "rate_velocity", H5P_DEFAULT) > 0) {
                double *dv = realloc(sim->dv_dt, sim->n * sim->dim * sizeof(double));
                double *dr = realloc(sim->drho_dt, sim->n * sizeof(double));
                double *dS = realloc(sim->dS_dt, sim->n * sim->ncomp * sizeof(double));
                if (dv) sim->dv_dt = dv;
                if (dr) sim->drho_dt = dr;
                if (dS) sim->dS_dt = dS;
                e = !dv || !dr || !dS;
                e = e ? e : read_array(g, "rate_velocity", sim->n * sim->dim, sim->dv_dt);
                e = e ? e : read_array(g, "rate_density", sim->n, sim->drho_dt);
                e = e ? e : read_array(g, "rate_deviatoric_stress", sim->n * sim->ncomp, sim->dS_dt);
                if (e)
                    st = sph_fail(sim, SPH_ERR_IO, "cannot read the integrator's rates of checkpoint '%s'", path);
                else
                    carried_rates_set(sim);
            }
        }
        free(vectors);
    }
    H5Gclose(g);
    H5Fclose(f);
    return st ? st : sph_ok(sim);
}

#else /* no HDF5 */

#define NO_HDF5(sim) sph_fail(sim, SPH_ERR_UNSUPPORTED, "libsphsolid was built without HDF5")

sph_status output_write_due(sph_sim *sim) { (void)sim; return SPH_OK; }
void output_free(sph_sim *sim) { (void)sim; }
sph_status sph_output_open(sph_sim *sim, const char *p, long a, long b)
{ (void)p; (void)a; (void)b; return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT; }
sph_status sph_output_snapshot(sph_sim *sim) { return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT; }
sph_status sph_output_close(sph_sim *sim) { return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT; }
sph_status sph_read_frame_count(sph_sim *sim, const char *p, long *f)
{ (void)p; (void)f; return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT; }
sph_status sph_read_frame(sph_sim *sim, const char *p, long f)
{ (void)p; (void)f; return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT; }
sph_status sph_checkpoint_write(sph_sim *sim, const char *p)
{ (void)p; return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT; }
sph_status sph_checkpoint_read(sph_sim *sim, const char *p)
{ (void)p; return sim ? NO_HDF5(sim) : SPH_ERR_ARGUMENT; }

#endif
