/* -*- c++ -*-
 * sphsolid_args.h - argument parsing shared by the plugin's styles.
 */
#ifndef SPHSOLID_ARGS_H
#define SPHSOLID_ARGS_H

#include "error.h"
#include "lammps.h"
#include "utils.h"

namespace LAMMPS_NS {

/* A vector of the simulation's `dim` components given as the `count`
 * arguments `arg` (a probe point, an applied force): out[0..dim) from
 * utils::numeric (which refuses nan and out-of-range numbers, naming them),
 * zero past dim.  Any other count is an error:
 * "<style> needs <what> <dim> <unit>, e.g. '<example>[ 0.0]'<usage>; got N values",
 * the 2D example getting a third zero in 3D. */
inline void read_dim_vector(LAMMPS *lmp, int count, char **arg, int dim, const char *style,
                            const char *what, const char *unit, const char *example,
                            const char *usage, double out[3])
{
  if (count != dim)
    lmp->error->all(FLERR, "{} needs {} {} {}, e.g. '{}{}'{}; got {} values", style, what, dim,
                    unit, example, dim == 3 ? " 0.0" : "", usage, count);
  out[0] = out[1] = out[2] = 0.0;
  for (int d = 0; d < dim; d++) out[d] = utils::numeric(FLERR, arg[d], false, lmp);
}

}    // namespace LAMMPS_NS

#endif
