/* -*- c++ -*-
 * sphsolid_error.h - errors raised on one MPI rank that reach the user.
 */
#ifndef SPHSOLID_ERROR_H
#define SPHSOLID_ERROR_H

#include "error.h"
#include "lammps.h"

#include <cstdio>
#include <mpi.h>
#include <string>

namespace LAMMPS_NS {

/* error->one with the message printed by the rank that raised it.  LAMMPS
 * prints error->one's message only to the rank's screen and log file, and
 * MPI_Abort follows at once: with `-screen none` (the tests' decks,
 * open_lammps) a rank other than 0 has neither, and a screen's buffered
 * line is often lost in the abort, so an error on rank 1 alone (a value
 * of a variable of the rank, a particle only it holds) stopped the job
 * with no message.  In a run of several ranks the rank writes "ERROR on
 * proc N: <message>" to stderr (unbuffered) first; then error->one stops
 * the job (MPI_Abort), or raises the Python exception of the lammps
 * module.  A serial run reports through error->one alone. */
template <typename... Args>
[[noreturn]] void sphsolid_one(LAMMPS *lmp, const std::string &file, int line,
                               const std::string &format, Args &&...args)
{
  const std::string message = fmt::vformat(format, fmt::make_format_args(args...));
  int me = 0, ranks = 1;
  MPI_Comm_rank(lmp->world, &me);
  MPI_Comm_size(lmp->world, &ranks);
  if (ranks > 1) {
    fprintf(stderr, "ERROR on proc %d: %s\n", me, message.c_str());
    fflush(stderr);
  }
  lmp->error->one(file, line, "{}", message);
}

}    // namespace LAMMPS_NS

#endif
