/*
 * Checkpoints: built in memory, written to a fresh temporary file beside
 * the target, synced and renamed over it; read back only into the same
 * scene, with the effects and the integrator's carried rates (see
 * io_hdf5.c).
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
    io_quiet_begin(&q);
    /* The file is built in memory (HDF5's core driver, no disk access), its
     * image written to the temporary name with checked plain writes, synced
     * and renamed: a failing disk never reaches HDF5, which would otherwise
     * be left with a file it cannot close. */
    io c = {0};
    hid_t f = io_file_create(&c, tmp, 1);
    io_write_format(&c, f, "checkpoint");
    io_write_parameters(&c, sim, f);
    hid_t g = io_group_create(&c, f, "checkpoint");
    io_attr_long(&c, g, "dimension", sim->dim);
    io_attr_long(&c, g, "particles", (long)sim->n);
    io_attr_long(&c, g, "bodies", sim->n_bodies);
    io_attr_long(&c, g, "step", sim->step);
    io_attr_double(&c, g, "time", &sim->t, 1);
    io_attr_double(&c, g, "dt", &sim->dt, 1);
    io_attr_long(&c, g, "dt_set", sim->dt_set);
    io_attr_string(&c, g, "integrator", sim_integrator(sim)->name);
    {
        /* the clock again, checksummed (attributes of this format are not) */
        const double clock[4] = {(double)sim->step, sim->t, sim->dt, (double)sim->dt_set};
        const hsize_t four = 4;
        io_write_dataset(&c, g, "clock", H5T_NATIVE_DOUBLE, 1, &four, clock);
    }
    const hsize_t n = sim->n;
    hsize_t vec[2] = {n, (hsize_t)sim->dim}, ten[2] = {n, (hsize_t)sim->ncomp};
    io_write_dataset(&c, g, "position", H5T_NATIVE_DOUBLE, 2, vec, sim->x);
    io_write_dataset(&c, g, "velocity", H5T_NATIVE_DOUBLE, 2, vec, sim->v);
    io_write_dataset(&c, g, "density", H5T_NATIVE_DOUBLE, 1, &n, sim->rho);
    io_write_dataset(&c, g, "deviatoric_stress", H5T_NATIVE_DOUBLE, 2, ten, sim->S);
    io_write_dataset(&c, g, "mass", H5T_NATIVE_DOUBLE, 1, &n, sim->mass);
    if (sim->fx.damage && damage_prepare(sim) == SPH_OK)
        io_write_dataset(&c, g, "damage", H5T_NATIVE_DOUBLE, 1, &n, sim->damage);
    if (!c.failed) {
        double *vectors = calloc((size_t)sim->n_bodies * 3 + 1, sizeof *vectors);
        if (!vectors) {
            io_fail_memory(&c, "motion_vectors", 0);
        } else {
            for (int k = 0; k < sim->n_bodies; ++k)
                memcpy(vectors + 3 * k, sim->bodies[k].vector, 3 * sizeof(double));
            hsize_t d[2] = {(hsize_t)sim->n_bodies, 3};
            io_write_dataset(&c, g, "motion_vectors", H5T_NATIVE_DOUBLE, 2, d, vectors);
            for (int k = 0; k < sim->n_bodies; ++k)
                memcpy(vectors + 3 * k, sim->bodies[k].centre, 3 * sizeof(double));
            io_write_dataset(&c, g, "motion_centres", H5T_NATIVE_DOUBLE, 2, d, vectors);
            free(vectors);
        }
    }
    if (sim_integrator(sim)->carries_rates && carried_rates_valid(sim)) {
        /* the rates the next step starts from */
        io_write_dataset(&c, g, "rate_velocity", H5T_NATIVE_DOUBLE, 2, vec, sim->dv_dt);
        io_write_dataset(&c, g, "rate_density", H5T_NATIVE_DOUBLE, 1, &n, sim->drho_dt);
        io_write_dataset(&c, g, "rate_deviatoric_stress", H5T_NATIVE_DOUBLE, 2, ten, sim->dS_dt);
        if (sim->energy_account && sim->power_carry_valid) {
            /* their powers, which open the energy account's next step */
            const hsize_t two = 2;
            io_write_dataset(&c, g, "rate_powers", H5T_NATIVE_DOUBLE, 1, &two, sim->power_carry);
        }
    }
    io_group_close(&c, g, "checkpoint");
    void *image = NULL;
    ssize_t size = -1;
    if (!c.failed && io_ok(&c, H5Fflush(f, H5F_SCOPE_GLOBAL), "the in-memory image") &&
        io_ok(&c, size = H5Fget_file_image(f, NULL, 0), "the in-memory image")) {
        image = malloc((size_t)size);
        if (!image) {
            io_fail_memory(&c, "the in-memory image", (size_t)size);
        } else {
            io_ok(&c, H5Fget_file_image(f, image, (size_t)size), "the in-memory image");
        }
    }
    if (f >= 0 && H5Fclose(f) < 0)
        io_fail_at(&c, "the in-memory image (close)", 0);
    io_quiet_end(&q);
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
    reading r;
    sph_status st = io_read_open(sim, path, "checkpoint", "the checkpoint", &r);
    if (st)
        return st;
    state_copy s = {0};
    hid_t g = H5Gopen2(r.f, "checkpoint", H5P_DEFAULT);
    if (g < 0) {
        st = sph_fail(sim, SPH_ERR_IO, "'%s' has no /checkpoint group", path);
        goto done;
    }
    long dim = 0, n = 0, nb = 0, step = 0, dt_set = 0;
    double t = 0, dt = 0;
    size_t one = 0;
    if (io_read_attr_long(g, "dimension", &dim) || io_read_attr_long(g, "particles", &n) ||
        io_read_attr_long(g, "bodies", &nb) || io_read_attr_long(g, "step", &step) ||
        io_read_attr_long(g, "dt_set", &dt_set) || io_read_attr_doubles(g, "time", &t, 1, &one) ||
        io_read_attr_doubles(g, "dt", &dt, 1, &one)) {
        st = sph_fail(sim, SPH_ERR_IO, "checkpoint '%s' lacks its attributes", path);
        goto done;
    }
    char integ_name[64] = "";
    const integrator *in = NULL;
    if (io_read_attr_string(g, "integrator", integ_name, sizeof integ_name)) {
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
    if ((st = io_scene_matches(sim, r.f, path, 1, r.version)))
        goto done;
    {
        /* the checksummed copy of the clock decides */
        io cc = {0};
        double clock[4];
        if (io_read_doubles(&cc, g, "clock", -1, 4, clock)) {
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
    if (io_state_alloc(&s, sim)) {
        st = sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate scratch arrays to read '%s'", path);
        goto done;
    }
    io c = {0};
    const size_t nn = sim->n, d = (size_t)sim->dim;
    static const char *const values[4] = {"position", "velocity", "density", "deviatoric_stress"};
    io_state_read(&c, g, values, -1, sim, &s);
    if (!c.failed)
        io_read_doubles(&c, g, "mass", -1, nn, s.mass);
    if (!c.failed)
        io_read_doubles(&c, g, "motion_vectors", -1, (size_t)nb * 3, s.motion);
    if (!c.failed)
        io_read_doubles(&c, g, "motion_centres", -1, (size_t)nb * 3, s.motion + (size_t)nb * 3);
    if (c.failed) {
        st = sph_fail(sim, SPH_ERR_IO, "cannot read checkpoint '%s': %s (reading %s)", path,
                      c.cause, c.what);
        goto done;
    }
    if (!io_state_plausible(sim, &s, path, 1)) {
        st = SPH_ERR_IO;
        goto done;
    }
    if (io_first_nonfinite(s.motion, (size_t)nb * 6) >= 0) {
        st = sph_fail(sim, SPH_ERR_IO,
                      "checkpoint '%s' is damaged: a body's motion vector is not finite", path);
        goto done;
    }
    const int with_rates = in->carries_rates && H5Lexists(g, "rate_velocity", H5P_DEFAULT) > 0;
    double powers[2] = {0.0, 0.0}; /* of the rates, for the energy account, if written */
    int with_powers = 0;
    if (with_rates) {
        s.dv = malloc(nn * d * sizeof(double));
        s.drho = malloc(nn * sizeof(double));
        s.dS = malloc(nn * (size_t)sim->ncomp * sizeof(double));
        if (!s.dv || !s.drho || !s.dS) {
            st = sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate scratch arrays to read '%s'", path);
            goto done;
        }
        io_read_doubles(&c, g, "rate_velocity", -1, nn * d, s.dv);
        if (!c.failed)
            io_read_doubles(&c, g, "rate_density", -1, nn, s.drho);
        if (!c.failed)
            io_read_doubles(&c, g, "rate_deviatoric_stress", -1, nn * (size_t)sim->ncomp, s.dS);
        if (!c.failed && H5Lexists(g, "rate_powers", H5P_DEFAULT) > 0 &&
            !io_read_doubles(&c, g, "rate_powers", -1, 2, powers))
            with_powers = isfinite(powers[0]) && isfinite(powers[1]);
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
    double *damage = NULL; /* effect damage: D, if the checkpoint holds it */
    if (sim->fx.damage && H5Lexists(g, "damage", H5P_DEFAULT) > 0) {
        if (!(damage = malloc(nn * sizeof *damage)) || (st = damage_prepare(sim))) {
            free(damage);
            st = st ? st : sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate D to read '%s'", path);
            goto done;
        }
        if (io_read_doubles(&c, g, "damage", -1, nn, damage)) {
            free(damage);
            st = sph_fail(sim, SPH_ERR_IO, "cannot read checkpoint '%s': %s (reading %s)", path,
                          c.cause, c.what);
            goto done;
        }
    }
    /* commit: nothing above changed the simulation */
    io_state_commit(sim, &s, step, t);
    if (damage) {
        memcpy(sim->damage, damage, nn * sizeof *damage);
        free(damage);
    }
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
        if (with_powers) {
            sim->power_carry[0] = powers[0];
            sim->power_carry[1] = powers[1];
            sim->power_carry_valid = 1;
        }
    }
    st = sph_ok(sim);
done:
    io_read_release(&r.q, &s, g, r.f);
    return st;
}

#else /* no HDF5 */

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
