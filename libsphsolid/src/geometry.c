/* Geometry of laboratory specimens and their platens.
 *
 * The loading axis is y in every builder, as in the paper's scene: a
 * specimen stands on a plate below it and a piston presses on it from
 * above.  Every builder lays particles on a lattice and passes them to
 * sph_add_particles(), then records the body's lattice (extent and step per
 * axis) so that a platen can be laid against it with matching columns.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim.h"

static const char *label(const char *name) { return name ? name : ""; }

/* Records a lattice body's extent and per-axis lattice step. */
void body_set_lattice(sph_sim *sim, int id, const double lo[3], const double hi[3],
                      const double step[3])
{
    body *b = &sim->bodies[id];
    for (int i = 0; i < 3; ++i) {
        b->lo[i] = i < sim->dim ? lo[i] : 0.0;
        b->hi[i] = i < sim->dim ? hi[i] : 0.0;
        b->step[i] = i < sim->dim ? step[i] : 0.0;
    }
}

sph_status lattice_add(sph_sim *sim, const char *name, int material, const double lo[3],
                       const double hi[3], const long count[3], const double step[3],
                       double spacing, const char *what, int *id)
{
    const int dim = sim->dim;
    const size_t n = (size_t)count[0] * (size_t)count[1] * (size_t)count[2];
    double *pos = malloc(n * (size_t)dim * sizeof *pos), *vol = malloc(n * sizeof *vol);
    if (!pos || !vol) {
        free(pos);
        free(vol);
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %zu %s particles", n, what);
    }
    const double volume = step[0] * step[1] * (dim == 3 ? step[2] : 1.0);
    size_t k = 0;
    for (long iz = 0; iz < count[2]; ++iz)
        for (long iy = 0; iy < count[1]; ++iy)
            for (long ix = 0; ix < count[0]; ++ix, ++k) {
                pos[k * dim + 0] = lo[0] + (ix + 0.5) * step[0];
                pos[k * dim + 1] = lo[1] + (iy + 0.5) * step[1];
                if (dim == 3)
                    pos[k * dim + 2] = lo[2] + (iz + 0.5) * step[2];
                vol[k] = volume;
            }
    sph_status st = sph_add_particles(sim, name, material, n, pos, vol, spacing, id);
    free(pos);
    free(vol);
    if (st)
        return st;
    body_set_lattice(sim, *id, lo, hi, step);
    return SPH_OK;
}

void body_extent_from_particles(sph_sim *sim, int id)
{
    body *b = &sim->bodies[id];
    const int dim = sim->dim;
    for (int i = 0; i < 3; ++i) {
        b->lo[i] = i < dim ? INFINITY : 0.0;
        b->hi[i] = i < dim ? -INFINITY : 0.0;
        b->step[i] = i < dim ? b->spacing : 0.0;
    }
    for (size_t a = b->first; a < b->first + b->count; ++a)
        for (int i = 0; i < dim; ++i) {
            const double x = sim->x[a * dim + i];
            if (x < b->lo[i])
                b->lo[i] = x;
            if (x > b->hi[i])
                b->hi[i] = x;
        }
    for (int i = 0; i < dim; ++i) {
        b->lo[i] -= 0.5 * b->spacing;
        b->hi[i] += 0.5 * b->spacing;
    }
}

sph_status sph_body_extent(sph_sim *sim, int id, double lo[3], double hi[3], double step[3])
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (id < 0 || id >= sim->n_bodies)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body=%d: %d bodies are defined", id, sim->n_bodies);
    const body *b = &sim->bodies[id];
    for (int i = 0; i < 3; ++i) {
        if (lo)
            lo[i] = b->lo[i];
        if (hi)
            hi[i] = b->hi[i];
        if (step)
            step[i] = b->step[i];
    }
    return sph_ok(sim);
}

sph_status sph_add_prism(sph_sim *sim, const char *name, int material, const double base_centre[3],
                         double width, double depth, double height, double dx, int *body_id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (sim->dim != 3)
        return sph_fail(sim, SPH_ERR_STATE,
                        "prism '%s' is 3D; this simulation is %dD (use sph_add_block)", label(name),
                        sim->dim);
    if (!base_centre)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "prism '%s': base_centre is NULL", label(name));
    const double size[3] = {width, height, depth};
    const char *what[3] = {"width", "height", "depth"};
    for (int i = 0; i < 3; ++i) {
        if (!isfinite(base_centre[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "prism '%s': base_centre[%d]=%g is not finite",
                            label(name), i, base_centre[i]);
        if (!(size[i] > 0.0) || !isfinite(size[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT, "prism '%s': %s=%g m must be finite and > 0",
                            label(name), what[i], size[i]);
    }
    const double lo[3] = {base_centre[0] - 0.5 * width, base_centre[1],
                          base_centre[2] - 0.5 * depth};
    const double hi[3] = {base_centre[0] + 0.5 * width, base_centre[1] + height,
                          base_centre[2] + 0.5 * depth};
    return sph_add_block(sim, name, material, lo, hi, dx, body_id);
}

sph_status sph_add_cylinder(sph_sim *sim, const char *name, int material,
                            const double base_centre[3], double radius, double length, double dx,
                            int *body_id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (sim->dim != 3)
        return sph_fail(sim, SPH_ERR_STATE, "cylinder '%s' is 3D; this simulation is %dD",
                        label(name), sim->dim);
    if (!base_centre)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "cylinder '%s': base_centre is NULL", label(name));
    for (int i = 0; i < 3; ++i)
        if (!isfinite(base_centre[i]))
            return sph_fail(sim, SPH_ERR_ARGUMENT,
                            "cylinder '%s': base_centre[%d]=%g is not finite", label(name), i,
                            base_centre[i]);
    if (!(radius > 0.0) || !isfinite(radius))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "cylinder '%s': radius=%g m must be finite and > 0",
                        label(name), radius);
    if (!(length > 0.0) || !isfinite(length))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "cylinder '%s': length=%g m must be finite and > 0",
                        label(name), length);
    if (!(dx > 0.0) || !isfinite(dx))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "cylinder '%s': dx=%g must be finite and > 0",
                        label(name), dx);
    const long n_side = lround(2.0 * radius / dx), n_y = lround(length / dx);
    if (n_side < 1 || n_y < 1)
        return sph_fail(
            sim, SPH_ERR_ARGUMENT,
            "cylinder '%s': dx=%g m is more than twice the diameter %g m or the length %g m",
            label(name), dx, 2.0 * radius, length);
    const double s = 2.0 * radius / (double)n_side, sy = length / (double)n_y;
    /* one cross-section: the lattice points strictly inside the circle */
    double *ring = malloc((size_t)n_side * (size_t)n_side * 2 * sizeof *ring);
    if (!ring)
        return sph_fail(sim, SPH_ERR_MEMORY, "cylinder '%s': cannot allocate its cross-section",
                        label(name));
    size_t per_layer = 0;
    for (long k = 0; k < n_side; ++k)
        for (long i = 0; i < n_side; ++i) {
            const double px = -radius + (i + 0.5) * s, pz = -radius + (k + 0.5) * s;
            if (px * px + pz * pz < radius * radius) {
                ring[2 * per_layer] = px;
                ring[2 * per_layer + 1] = pz;
                ++per_layer;
            }
        }
    if (per_layer == 0) {
        free(ring);
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "cylinder '%s' holds no particle at dx=%g m (radius %g m)", label(name), dx,
                        radius);
    }
    const size_t n = per_layer * (size_t)n_y;
    if (n > (size_t)1 << 31) {
        free(ring);
        return sph_fail(sim, SPH_ERR_ARGUMENT, "cylinder '%s': %zu particles is too many",
                        label(name), n);
    }
    double *pos = malloc(n * 3 * sizeof *pos), *vol = malloc(n * sizeof *vol);
    if (!pos || !vol) {
        free(ring);
        free(pos);
        free(vol);
        return sph_fail(sim, SPH_ERR_MEMORY, "cannot allocate %zu cylinder particles", n);
    }
    const double volume = s * s * sy;
    size_t a = 0;
    for (long j = 0; j < n_y; ++j)
        for (size_t k = 0; k < per_layer; ++k, ++a) {
            pos[3 * a + 0] = base_centre[0] + ring[2 * k];
            pos[3 * a + 1] = base_centre[1] + (j + 0.5) * sy;
            pos[3 * a + 2] = base_centre[2] + ring[2 * k + 1];
            vol[a] = volume;
        }
    free(ring);
    int id;
    sph_status st = sph_add_particles(sim, name, material, n, pos, vol, dx, &id);
    free(pos);
    free(vol);
    if (st)
        return st;
    const double lo[3] = {base_centre[0] - radius, base_centre[1], base_centre[2] - radius};
    const double hi[3] = {base_centre[0] + radius, base_centre[1] + length,
                          base_centre[2] + radius};
    const double step[3] = {s, sy, s};
    body_set_lattice(sim, id, lo, hi, step);
    if (body_id)
        *body_id = id;
    return sph_ok(sim);
}

/* A platen of `layers` lattice layers below (side < 0) or above the body. */
static sph_status add_platen(sph_sim *sim, const char *name, int material, int against, int layers,
                             int side, const char *role, int *platen_id)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (against < 0 || against >= sim->n_bodies)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "%s '%s': body=%d, but %d bodies are defined", role,
                        label(name), against, sim->n_bodies);
    const body *b = &sim->bodies[against];
    if (material < 0)
        material = b->material;
    const double dy = b->step[1];
    /* the least layers that are 2h thick; an explicit count may also meet
     * 2h with the body's nominal spacing (dy differs from it only by the
     * rounding of the lattice to the body's extent) */
    const long least = sph_support_layers(sim, dy);
    const long least_nominal = sph_support_layers(sim, b->spacing);
    if (layers == 0)
        layers = (int)least;
    if (layers < least && layers < least_nominal)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "%s '%s': layers=%d of %g m give %g m, thinner than the kernel support %g "
                        "m (at least %ld layers)",
                        role, label(name), layers, dy, layers * dy, sph_support_radius(sim),
                        least < least_nominal ? least : least_nominal);
    double lo[3], hi[3];
    for (int i = 0; i < 3; ++i) {
        lo[i] = b->lo[i];
        hi[i] = b->hi[i];
    }
    if (side < 0) {
        hi[1] = b->lo[1];
        lo[1] = b->lo[1] - layers * dy;
    } else {
        lo[1] = b->hi[1];
        hi[1] = b->hi[1] + layers * dy;
    }
    /* across y: the body's columns (its step); along y: `layers` of dy */
    const int dim = sim->dim;
    long count[3] = {1, 1, 1};
    double step[3] = {0.0, dy, 0.0};
    for (int i = 0; i < dim; ++i) {
        if (i == 1)
            count[i] = layers;
        else {
            count[i] = lround((hi[i] - lo[i]) / b->step[i]);
            if (count[i] < 1)
                count[i] = 1;
            step[i] = (hi[i] - lo[i]) / (double)count[i];
        }
    }
    int id;
    sph_status st = lattice_add(sim, name, material, lo, hi, count, step, b->spacing, role, &id);
    if (st)
        return st;
    if (platen_id)
        *platen_id = id;
    return sph_ok(sim);
}

sph_status sph_add_plate(sph_sim *sim, const char *name, int material, int body, int layers,
                         int *plate)
{
    int id = -1;
    sph_status st = add_platen(sim, name, material, body, layers, -1, "plate", &id);
    if (st)
        return st;
    if ((st = sph_set_motion(sim, id, SPH_MOTION_FIXED, NULL)))
        return st;
    if (plate)
        *plate = id;
    return SPH_OK;
}

sph_status sph_add_piston(sph_sim *sim, const char *name, int material, int body, int layers,
                          double speed, int *piston)
{
    if (sim && !isfinite(speed))
        return sph_fail(sim, SPH_ERR_ARGUMENT, "piston '%s': speed=%g m/s is not finite",
                        label(name), speed);
    int id = -1;
    sph_status st = add_platen(sim, name, material, body, layers, +1, "piston", &id);
    if (st)
        return st;
    const double v[3] = {0.0, -speed, 0.0};
    if ((st = sph_set_motion(sim, id, SPH_MOTION_VELOCITY, v)))
        return st;
    if (piston)
        *piston = id;
    return SPH_OK;
}
