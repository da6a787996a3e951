/* Geometry of laboratory specimens and their platens.
 *
 * The loading axis is y in every builder, as in the paper's scene: a
 * specimen stands on a plate below it and a piston presses on it from
 * above.  Every builder lays particles on a lattice and passes them to
 * sph_add_particles(), then records the body's lattice (extent and step per
 * axis) so that a platen can be laid against it with matching columns.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "physics/kernel.h"
#include "core/sim.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

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
    {
        /* before building the lattice: would a run of this many fit? */
        char label_[SPH_NAME_SIZE + 40];
        snprintf(label_, sizeof label_, "%s '%s' (dx=%g m)", what, name ? name : "", spacing);
        sph_status st = memory_check(sim, (double)n, label_);
        if (st)
            return st;
    }
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
    if (2.0 * radius / dx > 1e12 || length / dx > 1e12)
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "cylinder '%s': diameter %g m and length %g m are %g and %g spacings "
                        "dx=%g m: too many",
                        label(name), 2.0 * radius, length, 2.0 * radius / dx, length / dx, dx);
    const long n_side = lround(2.0 * radius / dx), n_y = lround(length / dx);
    if (n_side < 1 || n_y < 1)
        return sph_fail(
            sim, SPH_ERR_ARGUMENT,
            "cylinder '%s': dx=%g m is more than twice the diameter %g m or the length %g m",
            label(name), dx, 2.0 * radius, length);
    const double s = 2.0 * radius / (double)n_side, sy = length / (double)n_y;
    {
        /* before building anything: would a run of about pi/4 n_side^2 n_y
         * particles (the circle's share of the square lattice) fit? */
        char what[SPH_NAME_SIZE + 40];
        snprintf(what, sizeof what, "cylinder '%s' (dx=%g m)", label(name), dx);
        const sph_status st =
            memory_check(sim, 0.25 * M_PI * (double)n_side * (double)n_side * (double)n_y, what);
        if (st)
            return st;
    }
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
    /* the face on the body's extent, moved towards the body by the inset */
    const double inset = sim->platen_inset * dy;
    if (side < 0) {
        hi[1] = b->lo[1] + inset;
        lo[1] = hi[1] - layers * dy;
    } else {
        lo[1] = b->hi[1] - inset;
        hi[1] = lo[1] + layers * dy;
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
    if (sim && !(isfinite(speed) && speed >= 0.0))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "piston '%s': speed=%g m/s must be finite and >= 0 (the piston moves "
                        "down, -y, at this speed; a body pulled upwards takes sph_set_motion)",
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

/* ------------------------------------------------------- end placement */

sph_status sph_set_platen_inset(sph_sim *sim, double inset)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (!(inset > -1.0 && inset < 0.5))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "platen inset=%g lattice steps: must be in (-1, 0.5) (0.5 would put a "
                        "platen row half a step from the body's, where sph_add_particles "
                        "refuses overlap)",
                        inset);
    sim->platen_inset = inset;
    return sph_ok(sim);
}

double sph_platen_inset(const sph_sim *sim) { return sim ? sim->platen_inset : 0.0; }

/* The static problem of sph_static_platen_inset on one lattice column
 * stack: rows y_r (specimen rows first), each row a full lattice layer.
 * Returns in *ratio the stiffness L_eff / L of the specimen rows between
 * a plate and a piston set in by `inset` steps (see the header). */
enum { STATIC_ROWS_PER_SUPPORT = 8, STATIC_EXTRA_ROWS = 16 };

/* d/dy_a of W summed over one lattice layer at height offset dy (the
 * layer's columns at the lattice steps across y), times the layer's
 * particle volume. */
static double layer_gradient(const sph_sim *sim, const double step[3], double dy)
{
    const int dim = sim->dim;
    const double h = sim->h, support = kernel_support(sim->kernel) * h;
    const double sigma = kernel_sigma(sim->kernel, dim) / pow(h, dim + 2);
    const double volume = step[0] * step[1] * (dim == 3 ? step[2] : 1.0);
    const long kx = (long)ceil(support / step[0]) + 1;
    const long kz = dim == 3 ? (long)ceil(support / step[2]) + 1 : 0;
    double sum = 0.0;
    if (fabs(dy) >= support) /* every column lies beyond the support */
        return sum;
    for (long iz = -kz; iz <= kz; ++iz)
        for (long ix = -kx; ix <= kx; ++ix) {
            const double x = ix * step[0], z = dim == 3 ? iz * step[2] : 0.0;
            const double r = sqrt(x * x + z * z + dy * dy);
            if (r >= support)
                continue;
            sum += volume * sigma * kernel_f(sim->kernel, dim, r / h) * dy;
        }
    return sum;
}

/* v minus its components along the `kept` orthonormal columns of q (rows
 * values each): Gram-Schmidt, twice for round-off. */
static void project_out(double *v, const double *q, int kept, int rows)
{
    for (int pass = 0; pass < 2; ++pass)
        for (int k = 0; k < kept; ++k) {
            const double *qk = q + (size_t)k * rows;
            /* four partial sums: the chain of additions, not the
             * products, bounds this loop */
            double part[4] = {0.0, 0.0, 0.0, 0.0};
            int r = 0;
            for (; r + 4 <= rows; r += 4)
                for (int l = 0; l < 4; ++l)
                    part[l] += qk[r + l] * v[r + l];
            for (; r < rows; ++r)
                part[0] += qk[r] * v[r];
            const double dot = (part[0] + part[1]) + (part[2] + part[3]);
            for (int r = 0; r < rows; ++r)
                v[r] -= dot * qk[r];
        }
}

static sph_status static_stiffness(sph_sim *sim, const double step[3], double inset, double *ratio)
{
    const double dy = step[1], support = kernel_support(sim->kernel) * sim->h;
    const int reach = (int)ceil(support / dy); /* rows within the support */
    const int p = reach + 1, n = STATIC_ROWS_PER_SUPPORT * reach + STATIC_EXTRA_ROWS;
    const int rows = n + 2 * p;
    const double length = n * dy;
    double *y = malloc((size_t)rows * sizeof *y);
    double *d = malloc((size_t)rows * (size_t)rows * sizeof *d); /* D(y_r - y_c) */
    double *q = malloc((size_t)rows * (size_t)n * sizeof *q);    /* orthonormal columns */
    double *g = malloc((size_t)rows * sizeof *g);
    if (!y || !d || !q || !g) {
        free(y);
        free(d);
        free(q);
        free(g);
        return sph_fail(sim, SPH_ERR_MEMORY, "static platen inset: out of memory");
    }
    /* specimen rows 0..n-1, plate rows n..n+p-1, piston rows n+p.. */
    for (int j = 0; j < n; ++j)
        y[j] = (j + 0.5) * dy;
    for (int k = 0; k < p; ++k) {
        y[n + k] = -(k + 0.5) * dy + inset * dy;
        y[n + p + k] = length + (k + 0.5) * dy - inset * dy;
    }
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < rows; ++c)
            d[(size_t)r * rows + c] = layer_gradient(sim, step, y[r] - y[c]);
    /* g_r = sum_c (u_c - u_r) D(y_r - y_c): the SPH strain of every row.
     * The force on a specimen row is minus the derivative of the strain
     * energy sum_r g_r^2 / 2 (constant modulus and volume), so the static
     * state minimises |g|^2 over the specimen displacements: g is the
     * residual of the least-squares problem G_s u_s = -G_p u_p, unique even
     * where G_s has null vectors (the lattice's odd-even mode). */
    int kept = 0;
    for (int a = 0; a < n; ++a) { /* column a of G_s: unit displacement of row a */
        double *col = q + (size_t)kept * rows;
        double diag = 0.0;
        for (int r = 0; r < rows; ++r) {
            col[r] = r == a ? 0.0 : d[(size_t)r * rows + a];
            diag -= r == a ? 0.0 : d[(size_t)a * rows + r];
        }
        col[a] = diag;
        double norm0 = 0.0;
        for (int r = 0; r < rows; ++r)
            norm0 += col[r] * col[r];
        project_out(col, q, kept, rows);
        double norm = 0.0;
        for (int r = 0; r < rows; ++r)
            norm += col[r] * col[r];
        if (norm <= 1e-20 * norm0)
            continue; /* dependent on the columns kept */
        norm = sqrt(norm);
        for (int r = 0; r < rows; ++r)
            col[r] /= norm;
        ++kept;
    }
    /* b = G_p u_p with the plate at rest and the piston displaced by -1 */
    for (int r = 0; r < rows; ++r) {
        const double ur = r >= n + p ? -1.0 : 0.0;
        double s = 0.0;
        for (int c = 0; c < rows; ++c) {
            const double uc = c >= n + p ? -1.0 : 0.0;
            s += (uc - ur) * d[(size_t)r * rows + c];
        }
        g[r] = s;
    }
    project_out(g, q, kept, rows);
    /* the lattice gradient moment: g of u = y in the bulk */
    double moment = 0.0;
    for (int c = 0; c < rows; ++c)
        moment += (y[c] - y[n / 2]) * d[(size_t)(n / 2) * rows + c];
    /* the strain in the middle (mean of two rows: the odd-even mode cancels) */
    const double strain = 0.5 * (g[n / 2 - 1] + g[n / 2]);
    free(y);
    free(d);
    free(q);
    free(g);
    if (!(strain < 0.0) || !isfinite(strain) || !(moment > 0.0))
        return sph_fail(sim, SPH_ERR_STATE,
                        "static platen inset: no compressive static state (strain %g, "
                        "lattice moment %g)",
                        strain, moment);
    /* L_eff: the length whose continuum strain -1/L_eff, seen through the
     * lattice moment, is the strain in the middle */
    *ratio = moment / -strain / length;
    return SPH_OK;
}

/* End offset (L_eff - L) / 2 in lattice steps at inset s. */
static sph_status end_offset(sph_sim *sim, const double step[3], double s, double rows, double *e)
{
    double ratio;
    sph_status st = static_stiffness(sim, step, s, &ratio);
    if (!st)
        *e = 0.5 * (ratio - 1.0) * rows;
    return st;
}

static sph_status offset_setup(sph_sim *sim, int body_id, double step[3], double *rows)
{
    if (!sim)
        return SPH_ERR_ARGUMENT;
    if (body_id < 0 || body_id >= sim->n_bodies)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "body=%d: %d bodies are defined", body_id,
                        sim->n_bodies);
    if (!(sim->h > 0.0))
        return sph_fail(sim, SPH_ERR_STATE, "static platen inset: the smoothing length is not set");
    const body *b = &sim->bodies[body_id];
    for (int i = 0; i < 3; ++i)
        step[i] = i < sim->dim && b->step[i] > 0.0 ? b->step[i] : b->spacing;
    *rows = (double)(STATIC_ROWS_PER_SUPPORT *
                         (int)ceil(kernel_support(sim->kernel) * sim->h / step[1]) +
                     STATIC_EXTRA_ROWS);
    return SPH_OK;
}

sph_status sph_platen_end_offset(sph_sim *sim, int body_id, double inset, double *offset)
{
    double step[3] = {0, 0, 0}, rows = 0.0, e = 0.0;
    sph_status st = offset_setup(sim, body_id, step, &rows);
    if (st)
        return st;
    if (!(inset > -1.0 && inset < 0.5))
        return sph_fail(sim, SPH_ERR_ARGUMENT,
                        "platen inset=%g lattice steps: must be in (-1, 0.5)", inset);
    if ((st = end_offset(sim, step, inset, rows, &e)))
        return st;
    if (offset)
        *offset = e;
    return sph_ok(sim);
}

sph_status sph_static_platen_inset(sph_sim *sim, int body_id, double *inset, double *offset)
{
    double step[3] = {0, 0, 0}, rows = 0.0;
    sph_status st = offset_setup(sim, body_id, step, &rows);
    if (st)
        return st;
    /* e(s) falls steeply from a gap (s < 0) to s = 0 and, for some kernels,
     * has a minimum before s = 0.5 (the cubic spline at h/dy 1.2 touches
     * zero there; at 1.5 it stays near one step): scan, take the first
     * zero above 0 (else below), else the least |e| */
    enum { SCAN = 199 };
    const double first = -0.5, spacing = 0.005; /* to 0.49 */
    double e[SCAN];
    for (int i = 0; i < SCAN; ++i)
        if ((st = end_offset(sim, step, first + i * spacing, rows, &e[i])))
            return st;
    const int zero = 100; /* first + zero * spacing = 0 */
    int at = -1;
    for (int i = zero; i + 1 < SCAN && at < 0; ++i)
        if (e[i] > 0.0 && e[i + 1] <= 0.0)
            at = i;
    for (int i = zero - 1; i >= 0 && at < 0; --i)
        if (e[i] > 0.0 && e[i + 1] <= 0.0)
            at = i;
    double lo, hi, best_s, best_e;
    if (at >= 0) { /* bisect the sign change */
        lo = first + at * spacing;
        hi = lo + spacing;
        for (int it = 0; it < 50 && hi - lo > 1e-12; ++it) {
            const double mid = 0.5 * (lo + hi);
            double em;
            if ((st = end_offset(sim, step, mid, rows, &em)))
                return st;
            if (em > 0.0)
                lo = mid;
            else
                hi = mid;
        }
        best_s = 0.5 * (lo + hi);
    } else { /* the least |e|: golden section around the best grid point */
        int k = 0;
        for (int i = 1; i < SCAN; ++i)
            if (fabs(e[i]) < fabs(e[k]))
                k = i;
        lo = first + (k > 0 ? k - 1 : 0) * spacing;
        hi = first + (k + 1 < SCAN ? k + 1 : k) * spacing;
        const double g = 0.5 * (sqrt(5.0) - 1.0);
        for (int it = 0; it < 60 && hi - lo > 1e-10; ++it) {
            const double a = hi - g * (hi - lo), c = lo + g * (hi - lo);
            double ea, ec;
            if ((st = end_offset(sim, step, a, rows, &ea)) ||
                (st = end_offset(sim, step, c, rows, &ec)))
                return st;
            if (fabs(ea) < fabs(ec))
                hi = c;
            else
                lo = a;
        }
        best_s = 0.5 * (lo + hi);
    }
    if ((st = end_offset(sim, step, best_s, rows, &best_e)))
        return st;
    if (inset)
        *inset = best_s;
    if (offset)
        *offset = best_e;
    return sph_ok(sim);
}
