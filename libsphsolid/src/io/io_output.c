/*
 * HDF5 output: snapshots and probe samples appended frame by frame, each
 * frame committed only once flushed, the file checked to be still the one
 * its path names, the XDMF companion at close (see io_hdf5.c).
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp, fsync, fchmod */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/integrator.h"
#include "io/io_hdf5.h"

#ifdef SPHSOLID_HAVE_HDF5
#include <fcntl.h>
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
    if (o->pending > 0 &&
        io_series_append_rows(c, o->file, "/observables/probes", (hsize_t)o->pending,
                              o->pending_step, o->pending_time, o->pending_value))
        return -1;
    o->pending = 0;
    return 0;
}

static int output_commit(io *c, struct output_file *o, long frames, long probe_frames)
{
    if (probes_append_pending(c, o) ||
        !io_ok(c, H5Fflush(o->file, H5F_SCOPE_GLOBAL), "the file (flush)"))
        return -1;
    hid_t all = H5Gopen2(o->file, "/particles/all", H5P_DEFAULT);
    if (io_ok(c, all, "/particles/all"))
        io_attr_long_update(c, all, "complete_frames", frames);
    io_group_close(c, all, "/particles/all");
    if (probe_frames >= 0) {
        hid_t pg = H5Gopen2(o->file, "/observables/probes", H5P_DEFAULT);
        if (io_ok(c, pg, "/observables/probes"))
            io_attr_long_update(c, pg, "complete_samples", probe_frames);
        io_group_close(c, pg, "/observables/probes");
    }
    io_ok(c, H5Fflush(o->file, H5F_SCOPE_GLOBAL), "the file (flush)");
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
    if (io_ok(&c, all, "/particles/all")) {
        io_series_append(&c, all, "position", sim->step, sim->t, sim->x);
        io_series_append(&c, all, "velocity", sim->step, sim->t, sim->v);
        io_series_append(&c, all, "density", sim->step, sim->t, sim->rho);
        io_series_append(&c, all, "deviatoric_stress", sim->step, sim->t, sim->S);
        if (!c.failed && sph_field_copy(sim, SPH_FIELD_PRESSURE, buf) == SPH_OK)
            io_series_append(&c, all, "pressure", sim->step, sim->t, buf);
        if (!c.failed && sph_field_copy(sim, SPH_FIELD_VON_MISES, buf) == SPH_OK)
            io_series_append(&c, all, "von_mises", sim->step, sim->t, buf);
        /* effect damage: D and the fragments, if the file was opened with it */
        if (!c.failed && sim->fx.damage && H5Lexists(all, "damage", H5P_DEFAULT) > 0) {
            if (sph_field_copy(sim, SPH_FIELD_DAMAGE, buf) == SPH_OK)
                io_series_append(&c, all, "damage", sim->step, sim->t, buf);
            if (!c.failed && sph_field_copy(sim, SPH_FIELD_FRAGMENT, buf) == SPH_OK)
                io_series_append(&c, all, "fragment", sim->step, sim->t, buf);
        }
    }
    io_group_close(&c, all, "/particles/all");
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
    io_quiet_begin(&q);
    if (snapshot)
        st = write_snapshot(sim);
    if (!st && probes)
        st = write_probes(sim, 1);
    io_quiet_end(&q);
    return st;
}

static int write_static(io *c, sph_sim *sim, hid_t file)
{
    const int dim = sim->dim, nc = sim->ncomp;
    const hsize_t n = sim->n;
    io_write_format(c, file, "output");
    hid_t h5md = io_group_create(c, file, "h5md");
    {
        hsize_t two = 2;
        int version[2] = {1, 1};
        hid_t space = H5Screate_simple(1, &two, NULL);
        if (io_ok(c, space, "h5md/version"))
            io_write_attr(c, h5md, "version", H5T_NATIVE_INT, space, version);
        io_close_id(space);
        hid_t creator = io_group_create(c, h5md, "creator");
        io_attr_string(c, creator, "name", "libsphsolid");
        io_attr_string(c, creator, "version", sph_version());
        io_group_close(c, creator, "h5md/creator");
        hid_t author = io_group_create(c, h5md, "author");
        io_attr_string(c, author, "name", "libsphsolid");
        io_group_close(c, author, "h5md/author");
    }
    io_group_close(c, h5md, "h5md");
    io_write_parameters(c, sim, file);

    hid_t parts = io_group_create(c, file, "particles");
    hid_t all = io_group_create(c, parts, "all");
    io_attr_long(c, all, "complete_frames", 0);
    hid_t box = io_group_create(c, all, "box");
    io_attr_long(c, box, "dimension", dim);
    if (!c->failed) {
        hid_t type = H5Tcopy(H5T_C_S1);
        char bnd[3][9] = {"none", "none", "none"};
        for (int i = 0; i < dim && i < 3; ++i)
            strcpy(bnd[i], sim->has_domain && sim->periodic[i] ? "periodic" : "none");
        hsize_t d = (hsize_t)dim;
        hid_t space = H5Screate_simple(1, &d, NULL);
        if (io_ok(c, type, "box/boundary") && io_ok(c, H5Tset_size(type, 9), "box/boundary") &&
            io_ok(c, space, "box/boundary"))
            io_write_attr(c, box, "boundary", type, space, bnd);
        io_close_id(space);
        io_close_id(type);
        if (sim->has_domain) {
            double edges[3];
            for (int i = 0; i < dim; ++i)
                edges[i] = sim->hi[i] - sim->lo[i];
            io_write_dataset(c, box, "edges", H5T_NATIVE_DOUBLE, 1, &d, edges);
            io_write_dataset(c, box, "offset", H5T_NATIVE_DOUBLE, 1, &d, sim->lo);
        }
    }
    io_group_close(c, box, "box");
    io_write_dataset(c, all, "mass", H5T_NATIVE_DOUBLE, 1, &n, sim->mass);
    io_write_dataset(c, all, "body", H5T_NATIVE_INT, 1, &n, sim->body_of);
    io_write_dataset(c, all, "material", H5T_NATIVE_INT, 1, &n, sim->material_of);
    hsize_t vec[2] = {n, (hsize_t)dim}, ten[2] = {n, (hsize_t)nc};
    io_series_create(c, all, "position", 2, vec, 1);
    io_series_create(c, all, "velocity", 2, vec, 1);
    io_series_create(c, all, "density", 1, &n, 1);
    io_series_create(c, all, "pressure", 1, &n, 1);
    io_series_create(c, all, "deviatoric_stress", 2, ten, 1);
    io_series_create(c, all, "von_mises", 1, &n, 1);
    if (sim->fx.damage) {
        io_series_create(c, all, "damage", 1, &n, 1);
        io_series_create(c, all, "fragment", 1, &n, 1);
    }
    io_group_close(c, all, "particles/all");
    io_group_close(c, parts, "particles");

    hid_t obs = io_group_create(c, file, "observables");
    if (sim->n_probes > 0 && !c->failed) {
        const int nv = SPH_PROBE_VALUES(dim);
        hsize_t inner[2] = {(hsize_t)sim->n_probes, (hsize_t)nv};
        io_series_create(c, obs, "probes", 2, inner, PROBE_BLOCK);
        hid_t pg = H5Gopen2(obs, "probes", H5P_DEFAULT);
        io_ok(c, pg, "observables/probes");
        io_attr_long(c, pg, "complete_samples", 0);
        size_t size = 1;
        for (int k = 0; k < sim->n_probes; ++k)
            size += strlen(sim->probes[k].name) + 1;
        char *names = calloc(size, 1);
        double *points = malloc((size_t)sim->n_probes * dim * sizeof *points);
        if (!names || !points) {
            io_fail_memory(c, "observables/probes", 0);
        } else {
            for (int k = 0; k < sim->n_probes; ++k) {
                if (k)
                    strcat(names, " ");
                strcat(names, sim->probes[k].name);
                for (int i = 0; i < dim; ++i)
                    points[k * dim + i] = sim->probes[k].point[i];
            }
            io_attr_string(c, pg, "names", names);
            io_attr_string(
                c, pg, "columns",
                dim == 2
                    ? "von_mises pressure sigma_xx sigma_yy sigma_zz sigma_xy"
                    : "von_mises pressure sigma_xx sigma_yy sigma_zz sigma_xy sigma_xz sigma_yz");
            hsize_t pd[2] = {(hsize_t)sim->n_probes, (hsize_t)dim};
            io_write_dataset(c, pg, "points", H5T_NATIVE_DOUBLE, 2, pd, points);
        }
        free(names);
        free(points);
        io_group_close(c, pg, "observables/probes");
    }
    io_group_close(c, obs, "observables");
    return c->failed ? -1 : 0;
}

/* Closes the output file whatever happened; returns -1 (cause in c) when
 * the final flush or close failed. */
static int output_release(io *c, sph_sim *sim)
{
    struct output_file *o = sim->out;
    int err = 0;
    if (o->file >= 0 && H5Fclose(o->file) < 0) {
        io_fail_at(c, "the file (close)", 0);
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
    if (probe_interval > 0 && sim->n_probes == 0)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "probe interval %ld, but there are no probes to sample (add them "
                        "with sph_add_probe first, or pass a probe interval of 0)",
                        probe_interval);
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
    io_quiet_begin(&q);
    io c = {0};
    hid_t file = io_file_create(&c, path, 0);
    if (c.failed) {
        io_quiet_end(&q);
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
    io_quiet_end(&q);
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
    io_quiet_begin(&q);
    st = write_snapshot(sim);
    io_quiet_end(&q);
    return st;
}

void output_free(sph_sim *sim)
{
    if (sim->out) {
        quiet q;
        io_quiet_begin(&q);
        io c = {0};
        if (!sim->out->failed)
            output_commit(&c, sim->out, sim->out->frames,
                          sim->n_probes > 0 ? sim->out->probe_frames : -1);
        output_release(&c, sim);
        io_quiet_end(&q);
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
    io_quiet_begin(&q);
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
    io_quiet_end(&q);
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

#else /* no HDF5 */

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

#endif
