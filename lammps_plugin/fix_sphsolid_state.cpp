/*
 * fix_sphsolid_state.cpp - per-atom SPH state (see fix_sphsolid_state.h).
 */
#include "fix_sphsolid_state.h"

#include "sphsolid.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "memory.h"

#include <algorithm>

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

FixSPHSolidState::FixSPHSolidState(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), rho(nullptr), S(nullptr), saved(nullptr), nmax_arrays(0)
{
  if (narg != 3)
    error->all(FLERR, "fix SPHSOLID/STATE is created by pair sphsolid and takes no arguments");
  dim = domain->dimension;
  ncomp = SPH_STRESS_COMPONENTS(dim);
  nsaved = dim + 1 + ncomp + dim;    // v, rho, S and, with XSPH, the transport velocity

  restart_peratom = 1;
  create_attribute = 1;
  comm_forward = 1 + ncomp;
  maxexchange = 1 + ncomp + nsaved;

  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);

  // atoms that exist already have no SPH state yet: density 0 marks that
  for (int i = 0; i < atom->nlocal; i++) set_arrays(i);
}

FixSPHSolidState::~FixSPHSolidState()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(rho);
  memory->destroy(S);
  memory->destroy(saved);
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidState::grow_arrays(int nmax)
{
  nmax = std::max(nmax, 1);    // keep the arrays addressable for the library
  if (nmax <= nmax_arrays) return;
  memory->grow(rho, nmax, "sphsolid:rho");
  memory->grow(S, nmax, ncomp, "sphsolid:S");
  memory->grow(saved, nmax, nsaved, "sphsolid:saved");
  nmax_arrays = nmax;
}

void FixSPHSolidState::copy_arrays(int i, int j, int /*delflag*/)
{
  rho[j] = rho[i];
  for (int k = 0; k < ncomp; k++) S[j][k] = S[i][k];
  for (int k = 0; k < nsaved; k++) saved[j][k] = saved[i][k];
}

void FixSPHSolidState::set_arrays(int i)
{
  rho[i] = 0.0;
  for (int k = 0; k < ncomp; k++) S[i][k] = 0.0;
  for (int k = 0; k < nsaved; k++) saved[i][k] = 0.0;
}

/* ---------------------------------------------------------------------- */

int FixSPHSolidState::pack_exchange(int i, double *buf)
{
  int m = 0;
  buf[m++] = rho[i];
  for (int k = 0; k < ncomp; k++) buf[m++] = S[i][k];
  for (int k = 0; k < nsaved; k++) buf[m++] = saved[i][k];
  return m;
}

int FixSPHSolidState::unpack_exchange(int nlocal, double *buf)
{
  int m = 0;
  rho[nlocal] = buf[m++];
  for (int k = 0; k < ncomp; k++) S[nlocal][k] = buf[m++];
  for (int k = 0; k < nsaved; k++) saved[nlocal][k] = buf[m++];
  return m;
}

/* ---------------------------------------------------------------------- */

int FixSPHSolidState::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/,
                                        int * /*pbc*/)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const int j = list[ii];
    buf[m++] = rho[j];
    for (int k = 0; k < ncomp; k++) buf[m++] = S[j][k];
  }
  return m;
}

void FixSPHSolidState::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    rho[i] = buf[m++];
    for (int k = 0; k < ncomp; k++) S[i][k] = buf[m++];
  }
}

/* ----------------------------------------------------------------------
   restart: rho and S (the stage-1 copy is only alive inside a step)
------------------------------------------------------------------------- */

int FixSPHSolidState::pack_restart(int i, double *buf)
{
  int m = 0;
  buf[m++] = 2 + ncomp;    // LAMMPS convention: first value = count including itself
  buf[m++] = rho[i];
  for (int k = 0; k < ncomp; k++) buf[m++] = S[i][k];
  return m;
}

void FixSPHSolidState::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  if (static_cast<int>(extra[nlocal][m]) != 2 + ncomp)
    error->one(FLERR, "SPH state in the restart file has {} values per atom, a {}D run needs {}",
               static_cast<int>(extra[nlocal][m]) - 1, dim, ncomp + 1);
  m++;
  rho[nlocal] = extra[nlocal][m++];
  for (int k = 0; k < ncomp; k++) S[nlocal][k] = extra[nlocal][m++];
  for (int k = 0; k < nsaved; k++) saved[nlocal][k] = 0.0;
}

int FixSPHSolidState::size_restart(int /*i*/)
{
  return 2 + ncomp;
}

int FixSPHSolidState::maxsize_restart()
{
  return 2 + ncomp;
}

/* ---------------------------------------------------------------------- */

double FixSPHSolidState::memory_usage()
{
  return (double) nmax_arrays * (1 + ncomp + nsaved) * sizeof(double);
}
