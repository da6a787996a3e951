/*
 * XDMF companion of an HDF5 output file (docs/hdf5_layout.md), for ParaView
 * and VTK: `run.h5` -> `run.xmf` in the same folder.  One grid per frame in a
 * temporal collection, polyvertex cells, geometry from position, velocity as
 * a vector, density, pressure and von Mises stress as scalars, each
 * deviatoric stress component as a scalar (S_xx, ...) and the body index.
 * The XML only points into the HDF5 file (hyperslabs of the frame); no
 * particle data is copied.  Written to `<name>.xmf.tmp` and renamed, so a
 * failed write keeps the previous companion.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/io_hdf5.h"
#include "core/sim.h"

#ifdef SPHSOLID_HAVE_HDF5
#include <hdf5.h>

/* `path` with its suffix replaced by ".xmf" (malloc'ed), and the file name
 * of `path` without folders (points into path). */
static char *xdmf_name(const char *path, const char **base)
{
    const char *slash = strrchr(path, '/');
    *base = slash ? slash + 1 : path;
    const char *dot = strrchr(*base, '.');
    const size_t stem = dot && dot != *base ? (size_t)(dot - path) : strlen(path);
    char *out = malloc(stem + 5);
    if (out) {
        memcpy(out, path, stem);
        memcpy(out + stem, ".xmf", 5);
    }
    return out;
}

/* Dimensions of a dataset (rank returned, -1 if absent). */
static int dataset_dims(hid_t file, const char *name, hsize_t *dims)
{
    if (H5Lexists(file, name, H5P_DEFAULT) <= 0)
        return -1;
    hid_t d = H5Dopen2(file, name, H5P_DEFAULT);
    if (d < 0)
        return -1;
    hid_t space = H5Dget_space(d);
    int rank = H5Sget_simple_extent_ndims(space);
    if (rank > 0 && rank <= 3)
        H5Sget_simple_extent_dims(space, dims, NULL);
    else
        rank = -1;
    H5Sclose(space);
    H5Dclose(d);
    return rank;
}

/* The /parameters attribute stress_order ("xx yy zz xy ..."), or the
 * default order of the library. */
static void stress_order(hid_t file, int ncomp, char names[6][3])
{
    static const char *defaults[6] = {"xx", "yy", "zz", "xy", "xz", "yz"};
    for (int c = 0; c < 6; ++c)
        snprintf(names[c], 3, "%s", defaults[c]);
    if (H5Aexists_by_name(file, "/parameters", "stress_order", H5P_DEFAULT) <= 0)
        return;
    hid_t a = H5Aopen_by_name(file, "/parameters", "stress_order", H5P_DEFAULT, H5P_DEFAULT);
    hid_t type = H5Aget_type(a);
    char text[64] = {0};
    if (H5Tget_class(type) == H5T_STRING && !H5Tis_variable_str(type) &&
        H5Tget_size(type) < sizeof text) {
        hid_t mem = H5Tcopy(H5T_C_S1);
        H5Tset_size(mem, sizeof text);
        if (H5Aread(a, mem, text) >= 0) {
            char *save = NULL, *word = strtok_r(text, " ", &save);
            for (int c = 0; c < ncomp && word; ++c, word = strtok_r(NULL, " ", &save))
                snprintf(names[c], 3, "%s", word);
        }
        H5Tclose(mem);
    }
    H5Tclose(type);
    H5Aclose(a);
}

/* One frame's hyperslab of /particles/all/<name>/value: all of a frame
 * (width 0: scalar per particle; else `width` columns) or one column. */
static void slab(FILE *f, const char *href, const char *name, long frame, long frames, hsize_t n,
                 int width, int column, int ncomp)
{
    if (width == 0 && column < 0) {
        fprintf(f,
                "<DataItem ItemType=\"HyperSlab\" Dimensions=\"%llu\" Type=\"HyperSlab\">\n"
                "  <DataItem Dimensions=\"3 2\" Format=\"XML\">%ld 0 1 1 1 %llu</DataItem>\n"
                "  <DataItem Dimensions=\"%ld %llu\" NumberType=\"Float\" Precision=\"8\" "
                "Format=\"HDF\">%s:/particles/all/%s/value</DataItem>\n</DataItem>\n",
                (unsigned long long)n, frame, (unsigned long long)n, frames, (unsigned long long)n,
                href, name);
    } else if (column < 0) {
        fprintf(f,
                "<DataItem ItemType=\"HyperSlab\" Dimensions=\"%llu %d\" Type=\"HyperSlab\">\n"
                "  <DataItem Dimensions=\"3 3\" Format=\"XML\">%ld 0 0 1 1 1 1 %llu %d</DataItem>\n"
                "  <DataItem Dimensions=\"%ld %llu %d\" NumberType=\"Float\" Precision=\"8\" "
                "Format=\"HDF\">%s:/particles/all/%s/value</DataItem>\n</DataItem>\n",
                (unsigned long long)n, width, frame, (unsigned long long)n, width, frames,
                (unsigned long long)n, width, href, name);
    } else {
        fprintf(f,
                "<DataItem ItemType=\"HyperSlab\" Dimensions=\"%llu\" Type=\"HyperSlab\">\n"
                "  <DataItem Dimensions=\"3 3\" Format=\"XML\">%ld 0 %d 1 1 1 1 %llu 1</DataItem>\n"
                "  <DataItem Dimensions=\"%ld %llu %d\" NumberType=\"Float\" Precision=\"8\" "
                "Format=\"HDF\">%s:/particles/all/%s/value</DataItem>\n</DataItem>\n",
                (unsigned long long)n, frame, column, (unsigned long long)n, frames,
                (unsigned long long)n, ncomp, href, name);
    }
}

static void write_xml(FILE *f, const char *href, const double *times, long frames, hsize_t n,
                      int dim, int ncomp, char order[6][3], int n_scalars)
{
    fputs("<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
          "<Xdmf Version=\"2.0\">\n<Domain>\n"
          "<Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
          f);
    /* the last two only in files of runs with effect damage (n_scalars 5) */
    static const char *scalars[5] = {"density", "pressure", "von_mises", "damage", "fragment"};
    for (long i = 0; i < frames; ++i) {
        fprintf(f, "<Grid Name=\"frame %ld\" GridType=\"Uniform\">\n<Time Value=\"%.17g\"/>\n", i,
                times[i]);
        fprintf(f,
                "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%llu\" "
                "NodesPerElement=\"1\"/>\n<Geometry GeometryType=\"%s\">\n",
                (unsigned long long)n, dim == 2 ? "XY" : "XYZ");
        slab(f, href, "position", i, frames, n, dim, -1, ncomp);
        fputs("</Geometry>\n<Attribute Name=\"velocity\" AttributeType=\"Vector\" "
              "Center=\"Node\">\n",
              f);
        slab(f, href, "velocity", i, frames, n, dim, -1, ncomp);
        fputs("</Attribute>\n", f);
        for (int k = 0; k < n_scalars; ++k) {
            fprintf(f, "<Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Node\">\n",
                    scalars[k]);
            slab(f, href, scalars[k], i, frames, n, 0, -1, ncomp);
            fputs("</Attribute>\n", f);
        }
        for (int c = 0; c < ncomp; ++c) {
            fprintf(f, "<Attribute Name=\"S_%s\" AttributeType=\"Scalar\" Center=\"Node\">\n",
                    order[c]);
            slab(f, href, "deviatoric_stress", i, frames, n, 0, c, ncomp);
            fputs("</Attribute>\n", f);
        }
        fprintf(f,
                "<Attribute Name=\"body\" AttributeType=\"Scalar\" Center=\"Node\">\n"
                "<DataItem Dimensions=\"%llu\" NumberType=\"Int\" Precision=\"4\" "
                "Format=\"HDF\">%s:/particles/all/body</DataItem>\n</Attribute>\n</Grid>\n",
                (unsigned long long)n, href);
    }
    fputs("</Grid>\n</Domain>\n</Xdmf>\n", f);
}

static sph_status write_xdmf(sph_sim *sim, const char *h5_path)
{
    hid_t file = H5Fopen(h5_path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0)
        return sph_fail(sim, SPH_ERR_IO, "sph_write_xdmf: cannot open HDF5 file '%s'", h5_path);
    hsize_t pos[3] = {0}, dev[3] = {0}, tdims[3] = {0};
    const int ok = dataset_dims(file, "/particles/all/position/value", pos) == 3 &&
                   dataset_dims(file, "/particles/all/deviatoric_stress/value", dev) == 3 &&
                   dataset_dims(file, "/particles/all/position/time", tdims) == 1 &&
                   tdims[0] == pos[0] && dev[0] == pos[0] && dev[1] == pos[1] &&
                   (pos[2] == 2 || pos[2] == 3) && dev[2] >= 1 && dev[2] <= 6;
    if (!ok) {
        H5Fclose(file);
        return sph_fail(sim, SPH_ERR_IO,
                        "sph_write_xdmf: '%s' is not a libsphsolid output file (no "
                        "/particles/all/position and deviatoric_stress series of matching shape)",
                        h5_path);
    }
    const long frames = (long)pos[0];
    const int dim = (int)pos[2], ncomp = (int)dev[2];
    double *times = malloc((frames > 0 ? (size_t)frames : 1) * sizeof *times);
    if (!times) {
        H5Fclose(file);
        return sph_fail(sim, SPH_ERR_MEMORY, "sph_write_xdmf: cannot allocate %ld times", frames);
    }
    io c = {0}; /* the cause, e.g. a time chunk whose checksum fails */
    if (frames > 0) {
        const char *what = "/particles/all/position/time";
        hid_t d = H5Dopen2(file, what, H5P_DEFAULT);
        if (io_ok(&c, d, what))
            io_ok(&c, H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, times), what);
        if (d >= 0)
            H5Dclose(d);
    }
    char order[6][3];
    stress_order(file, ncomp, order);
    hsize_t damage_dims[3] = {0};
    const int n_scalars =
        dataset_dims(file, "/particles/all/damage/value", damage_dims) == 2 &&
                damage_dims[0] == pos[0] &&
                dataset_dims(file, "/particles/all/fragment/value", damage_dims) == 2 &&
                damage_dims[0] == pos[0]
            ? 5
            : 3;
    H5Fclose(file);
    if (c.failed) {
        free(times);
        return sph_fail(sim, SPH_ERR_IO, "sph_write_xdmf: cannot read the frame times of '%s': %s",
                        h5_path, c.cause);
    }

    const char *href;
    char *xmf = xdmf_name(h5_path, &href);
    char *tmp = xmf ? malloc(strlen(xmf) + 5) : NULL;
    if (!tmp) {
        free(xmf);
        free(times);
        return sph_fail(sim, SPH_ERR_MEMORY, "sph_write_xdmf: out of memory");
    }
    sprintf(tmp, "%s.tmp", xmf);
    FILE *f = fopen(tmp, "w");
    sph_status st = SPH_OK;
    if (!f) {
        st = sph_fail(sim, SPH_ERR_IO, "sph_write_xdmf: cannot create '%s'", tmp);
    } else {
        write_xml(f, href, times, frames, pos[1], dim, ncomp, order, n_scalars);
        const int bad = ferror(f) != 0;
        if (fclose(f) != 0 || bad || rename(tmp, xmf) != 0) {
            remove(tmp);
            st = sph_fail(sim, SPH_ERR_IO, "sph_write_xdmf: cannot write '%s'", xmf);
        }
    }
    free(tmp);
    free(xmf);
    free(times);
    return st ? st : sph_ok(sim);
}

sph_status sph_write_xdmf(sph_sim *sim, const char *h5_path)
{
    if (!h5_path || !*h5_path)
        return sph_fail(sim, SPH_ERR_ARGUMENT, "sph_write_xdmf: the HDF5 path is empty");
    /* HDF5's error printing off for these calls only: the host's handler
     * is restored */
    H5E_auto2_t func = NULL;
    void *data = NULL;
    H5Eget_auto2(H5E_DEFAULT, &func, &data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    const sph_status st = write_xdmf(sim, h5_path);
    H5Eclear2(H5E_DEFAULT);
    H5Eset_auto2(H5E_DEFAULT, func, data);
    return st;
}

#else /* no HDF5 */

sph_status sph_write_xdmf(sph_sim *sim, const char *h5_path)
{
    (void)h5_path;
    return sph_fail(sim, SPH_ERR_UNSUPPORTED, "libsphsolid was built without HDF5");
}

#endif
