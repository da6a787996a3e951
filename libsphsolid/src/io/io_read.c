/*
 * Reading HDF5 files: opening with the format version (outputs of every
 * earlier format, checkpoints of this one), comparing the file's scene
 * with the simulation, reading into scratch arrays and committing only
 * when all was read; frames of output files (see io_hdf5.c).
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

int io_read_attr_long(hid_t obj, const char *name, long *v)
{
    return read_attr(obj, name, H5T_NATIVE_LONG, v);
}

/* A string attribute into buf (truncated to size). */
int io_read_attr_string(hid_t obj, const char *name, char *buf, size_t size)
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
        io_close_id(mt);
        free(tmp);
    }
    io_close_id(ft);
    io_close_id(a);
    return err;
}

/* Up to `size` doubles of a small attribute; the count in *count. */
int io_read_attr_doubles(hid_t obj, const char *name, double *v, size_t size, size_t *count)
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
    io_close_id(sp);
    io_close_id(a);
    return err;
}

/* Opens a libsphsolid file of the given content into *file (-1 on
 * failure) and its format version into *version; fails naming the path and
 * what is wrong.  Outputs of every format up to SPH_FILE_FORMAT are read
 * (format 1: before the version was recorded, libsphsolid 0.1.0 and 0.2.0);
 * checkpoints only of this format. */
sph_status io_open_checked(sph_sim *sim, const char *path, const char *content, hid_t *file,
                           long *version_out)
{
    *file = -1;
    *version_out = 0;
    if (!path || !*path)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "file path is empty");
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) {
        io c = {0};
        io_fail_at(&c, "open", 0);
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
    if (io_read_attr_long(f, "sphsolid_format", &version)) {
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
    io_read_attr_string(f, "sphsolid_content", kind, sizeof kind);
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
        if (io_read_attr_string(par, "effects", text, sizeof text))
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
        io_close_id(all);
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
            if (g < 0 || io_read_attr_doubles(g, p.key, &value, 1, &count) || count != 1)
                st = sph_fail(sim, SPH_ERR_IO, "'%s': cannot read /parameters/effects/%s/%s", path,
                              e.name, p.key);
            else if (value != here[j])
                st = sph_fail(sim, SPH_ERR_ARGUMENT,
                              "'%s' does not match this simulation: effect %s has %s=%.17g in the "
                              "file, %s=%.17g here",
                              path, e.name, p.key, value, p.key, here[j]);
        }
        io_close_id(g);
    }
    if (!st && info.nlinks != known_on)
        st = sph_fail(sim, SPH_ERR_ARGUMENT,
                      "'%s' was written with an effect this library does not know (known: %s)",
                      path, sph_effect_names());
    io_close_id(all);
    return st;
}

/* Compares the file's /parameters with the simulation (with_effects: the
 * effects too, effects_match); fails naming the first difference
 * (SPH_ERR_ARGUMENT: another scene, SPH_ERR_IO: a record that cannot be
 * read). */
sph_status io_scene_matches(sph_sim *sim, hid_t f, const char *path, int with_effects, long version)
{
    hid_t par = H5Gopen2(f, "parameters", H5P_DEFAULT);
    if (par < 0)
        return sph_fail(sim, SPH_ERR_IO, "'%s' has no /parameters group", path);
    sph_status st = SPH_OK;
    long dim = 0, nb = 0;
    H5G_info_t info;
    hid_t bodies = -1, mat = -1;
    double *materials = NULL;
    if (io_read_attr_long(par, "dimension", &dim)) {
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
    io_close_id(msp);
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
        io_fail_at(&c, "materials", 0);
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
        const int bad = g < 0 || io_read_attr_long(g, "index", &index) ||
                        io_read_attr_long(g, "first", &first) ||
                        io_read_attr_long(g, "count", &count) ||
                        io_read_attr_long(g, "material", &material) ||
                        io_read_attr_string(g, "motion", motion, sizeof motion) ||
                        io_read_attr_doubles(g, "spacing", &spacing, 1, &ns) ||
                        (version > 1 && (io_read_attr_doubles(g, "extent_lo", lo, 3, &nlo) ||
                                         io_read_attr_doubles(g, "extent_hi", hi, 3, &nhi)));
        if (!bad && version == 1 && /* format 1 files record extents from 0.2.0 on */
            (io_read_attr_doubles(g, "extent_lo", lo, 3, &nlo) ||
             io_read_attr_doubles(g, "extent_hi", hi, 3, &nhi)))
            nlo = nhi = 0;
        io_close_id(g);
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
        if (strcmp(motion, io_motion_name(b->motion)) != 0)
            DIFFERS("motion '%s'", motion, io_motion_name(b->motion));
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
    io_close_id(mat);
    io_close_id(bodies);
    H5Gclose(par);
    return st;
}

/* Reads `expect` doubles of dataset `name` (or one frame of a series when
 * frame >= 0); -1 with the cause in c on failure. */
int io_read_doubles(io *c, hid_t loc, const char *name, long frame, size_t expect, double *out)
{
    hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
    if (!io_ok(c, d, name))
        return -1;
    hid_t space = H5Dget_space(d), mem = -1;
    hsize_t dims[4] = {0}, start[4] = {0}, count[4] = {0};
    const int rank = space >= 0 ? H5Sget_simple_extent_dims(space, dims, NULL) : -1;
    if (io_ok(c, rank, name)) {
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
            if (io_ok(c, H5Sselect_hyperslab(space, H5S_SELECT_SET, start, NULL, count, NULL),
                      name) &&
                io_ok(c, mem = H5Screate_simple(rank, count, NULL), name))
                io_ok(c, H5Dread(d, H5T_NATIVE_DOUBLE, mem, space, H5P_DEFAULT, out), name);
        } else if (expect > 0) {
            io_ok(c, H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out), name);
        }
    }
    io_close_id(mem);
    io_close_id(space);
    H5Dclose(d);
    return c->failed ? -1 : 0;
}

static int read_long_at(io *c, hid_t loc, const char *name, long frame, long *out)
{
    hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
    if (!io_ok(c, d, name))
        return -1;
    hid_t space = H5Dget_space(d), mem = -1;
    hsize_t s = (hsize_t)frame, one = 1;
    if (io_ok(c, space, name) &&
        io_ok(c, H5Sselect_hyperslab(space, H5S_SELECT_SET, &s, NULL, &one, NULL), name) &&
        io_ok(c, mem = H5Screate_simple(1, &one, NULL), name))
        io_ok(c, H5Dread(d, H5T_NATIVE_LONG, mem, space, H5P_DEFAULT, out), name);
    io_close_id(mem);
    io_close_id(space);
    H5Dclose(d);
    return c->failed ? -1 : 0;
}

/* The first non-finite value of an array, for the message; -1 if none. */
long io_first_nonfinite(const double *a, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(a[i]))
            return (long)i;
    return -1;
}

int io_state_alloc(state_copy *s, const sph_sim *sim)
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
int io_state_read(io *c, hid_t loc, const char *const names[4], long frame, const sph_sim *sim,
                  state_copy *s)
{
    const size_t n = sim->n, dim = (size_t)sim->dim;
    double *const to[4] = {s->x, s->v, s->rho, s->S};
    const size_t count[4] = {n * dim, n * dim, n, n * (size_t)sim->ncomp};
    for (int k = 0; k < 4 && !c->failed; ++k)
        io_read_doubles(c, loc, names[k], frame, count[k], to[k]);
    return c->failed ? -1 : 0;
}

/* Opens `path`, a file of `content` ("checkpoint", "output"), to read it
 * into the simulation, which must hold the particles of the scene it was
 * written from (`written`: what the error message calls the file); HDF5's
 * messages are off from here (r->q) until io_read_release.  On failure
 * nothing is held. */
sph_status io_read_open(sph_sim *sim, const char *path, const char *content, const char *written,
                        reading *r)
{
    r->f = -1;
    r->version = 0;
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (sim->n == 0)
        return sph_fail(
            sim, SPH_ERR_STATE,
            "the simulation has no particles: build the scene %s was written from first", written);
    io_quiet_begin(&r->q);
    const sph_status st = io_open_checked(sim, path, content, &r->f, &r->version);
    if (st)
        io_quiet_end(&r->q);
    return st;
}

/* Releases what a read holds (scratch, group, file, error handler). */
void io_read_release(const quiet *q, state_copy *s, hid_t group, hid_t file)
{
    state_free(s);
    io_close_id(group);
    io_close_id(file);
    io_quiet_end(q);
}

/* Copies the state read into the simulation at (step, time); neighbour
 * list and rates are rebuilt from it. */
void io_state_commit(sph_sim *sim, const state_copy *s, long step, double time)
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
    sim->power_carry_valid = 0; /* the account's powers were of the state replaced */
}

/* Refuses values no run can produce (checksums catch damaged blocks; this
 * catches files edited or written by a broken program). */
int io_state_plausible(sph_sim *sim, const state_copy *s, const char *path, int with_mass)
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
        const long i = io_first_nonfinite(arrays[k].a, n * arrays[k].per);
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
            io_close_id(space);
            io_close_id(d);
            if (rank < 1) {
                complete = -1;
                break;
            }
            if (complete < 0 || (long)dims[0] < complete)
                complete = (long)dims[0];
        }
        io_close_id(all);
        if (complete < 0)
            return sph_fail(sim, SPH_ERR_IO,
                            "'%s' (file format 1) lacks a series of /particles/all (position, "
                            "velocity, density, deviatoric_stress)",
                            path);
        *frames = complete;
        return SPH_OK;
    }
    const int bad = all < 0 || io_read_attr_long(all, "complete_frames", &complete) || complete < 0;
    io_close_id(all);
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
    io_quiet_begin(&q);
    hid_t f = -1;
    long version = 0;
    st = io_open_checked(sim, path, "output", &f, &version);
    if (!st)
        st = frame_count(sim, f, path, version, frames);
    io_close_id(f);
    io_quiet_end(&q);
    return st ? st : sph_ok(sim);
}

sph_status sph_read_frame(sph_sim *sim, const char *path, long frame)
{
    reading r;
    sph_status st = io_read_open(sim, path, "output", "the file", &r);
    if (st)
        return st;
    long frames = 0, step = 0;
    double time = 0.0;
    state_copy s = {0};
    hid_t all = -1;
    if ((st = frame_count(sim, r.f, path, r.version, &frames)))
        goto done;
    const long asked = frame;
    if (frame < 0)
        frame += frames;
    if (frame < 0 || frame >= frames) {
        st = sph_fail(sim, SPH_ERR_ARGUMENT, "frame=%ld: '%s' has %ld complete frames", asked, path,
                      frames);
        goto done;
    }
    if ((st = io_scene_matches(sim, r.f, path, 0, r.version)))
        goto done;
    if (io_state_alloc(&s, sim)) {
        st = sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate scratch arrays to read '%s'", path);
        goto done;
    }
    all = H5Gopen2(r.f, "/particles/all", H5P_DEFAULT);
    io c = {0};
    if (io_ok(&c, all, "/particles/all")) {
        static const char *const values[4] = {"position/value", "velocity/value", "density/value",
                                              "deviatoric_stress/value"};
        io_state_read(&c, all, values, frame, sim, &s);
        if (!c.failed)
            read_long_at(&c, all, "position/step", frame, &step);
        if (!c.failed) {
            hid_t d = H5Dopen2(all, "position/time", H5P_DEFAULT);
            if (io_ok(&c, d, "position/time")) {
                hid_t space = H5Dget_space(d), mem = -1;
                hsize_t s0 = (hsize_t)frame, one = 1;
                if (io_ok(&c, space, "position/time") &&
                    io_ok(&c, H5Sselect_hyperslab(space, H5S_SELECT_SET, &s0, NULL, &one, NULL),
                          "position/time") &&
                    io_ok(&c, mem = H5Screate_simple(1, &one, NULL), "position/time"))
                    io_ok(&c, H5Dread(d, H5T_NATIVE_DOUBLE, mem, space, H5P_DEFAULT, &time),
                          "position/time");
                io_close_id(mem);
                io_close_id(space);
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
    if (!io_state_plausible(sim, &s, path, 0)) {
        st = SPH_ERR_IO;
        goto done;
    }
    io_state_commit(sim, &s, step, time);
    st = sph_ok(sim);
done:
    io_read_release(&r.q, &s, all, r.f);
    return st;
}

#else /* no HDF5 */

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

#endif
