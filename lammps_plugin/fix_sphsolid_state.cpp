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
#include <cmath>
#include <string>

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

FixSPHSolidState::FixSPHSolidState(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), rho(nullptr), S(nullptr), saved(nullptr), carried_rho(nullptr),
    carried_S(nullptr), nmax_arrays(0)
{
  if (narg != 3)
    error->all(FLERR, "fix SPHSOLID/STATE is created by pair sphsolid and takes no arguments");
  dim = domain->dimension;
  ncomp = SPH_STRESS_COMPONENTS(dim);
  // the largest stage buffer of the library's integrators (Improved
  // Euler's with XSPH: v, rho, S and the transport velocity)
  nsaved = 0;
  sph_sim *probe = nullptr;
  if (sph_create(dim, &probe) == SPH_OK && sph_effect(probe, "xsph", "") == SPH_OK) {
    std::string names = sph_integrator_names();
    for (size_t start = 0; start < names.size();) {
      size_t end = names.find(' ', start);
      if (end == std::string::npos) end = names.size();
      sph_integrator_info info;
      if (sph_integrator_info_get(probe, names.substr(start, end - start).c_str(), &info) == SPH_OK)
        nsaved = std::max(nsaved, (int) info.saved_values);
      start = end + 1;
    }
  }
  sph_destroy(probe);
  if (nsaved == 0)
    error->all(FLERR, "fix SPHSOLID/STATE: cannot ask libsphsolid for its integrators' stage size");

  restart_peratom = 1;
  create_attribute = 1;
  comm_forward = 3 + 3 + 1 + ncomp;    // with positions and velocities
  forward_motion = false;
  forward_stress = true;
  maxexchange = 2 * (1 + ncomp) + nsaved;

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
  memory->destroy(carried_rho);
  memory->destroy(carried_S);
}

/* ---------------------------------------------------------------------- */

void FixSPHSolidState::grow_arrays(int nmax)
{
  nmax = std::max(nmax, 1);    // keep the arrays addressable for the library
  if (nmax <= nmax_arrays) return;
  memory->grow(rho, nmax, "sphsolid:rho");
  memory->grow(S, nmax, ncomp, "sphsolid:S");
  memory->grow(saved, nmax, nsaved, "sphsolid:saved");
  memory->grow(carried_rho, nmax, "sphsolid:carried_rho");
  memory->grow(carried_S, nmax, ncomp, "sphsolid:carried_S");
  nmax_arrays = nmax;
}

void FixSPHSolidState::copy_arrays(int i, int j, int /*delflag*/)
{
  rho[j] = rho[i];
  for (int k = 0; k < ncomp; k++) S[j][k] = S[i][k];
  for (int k = 0; k < nsaved; k++) saved[j][k] = saved[i][k];
  carried_rho[j] = carried_rho[i];
  for (int k = 0; k < ncomp; k++) carried_S[j][k] = carried_S[i][k];
}

void FixSPHSolidState::set_arrays(int i)
{
  rho[i] = 0.0;
  for (int k = 0; k < ncomp; k++) S[i][k] = 0.0;
  for (int k = 0; k < nsaved; k++) saved[i][k] = 0.0;
  carried_rho[i] = NAN;
  for (int k = 0; k < ncomp; k++) carried_S[i][k] = NAN;
}

/* ---------------------------------------------------------------------- */

int FixSPHSolidState::pack_exchange(int i, double *buf)
{
  int m = 0;
  buf[m++] = rho[i];
  for (int k = 0; k < ncomp; k++) buf[m++] = S[i][k];
  for (int k = 0; k < nsaved; k++) buf[m++] = saved[i][k];
  buf[m++] = carried_rho[i];
  for (int k = 0; k < ncomp; k++) buf[m++] = carried_S[i][k];
  return m;
}

int FixSPHSolidState::unpack_exchange(int nlocal, double *buf)
{
  int m = 0;
  rho[nlocal] = buf[m++];
  for (int k = 0; k < ncomp; k++) S[nlocal][k] = buf[m++];
  for (int k = 0; k < nsaved; k++) saved[nlocal][k] = buf[m++];
  carried_rho[nlocal] = buf[m++];
  for (int k = 0; k < ncomp; k++) carried_S[nlocal][k] = buf[m++];
  return m;
}

/* ---------------------------------------------------------------------- */

int FixSPHSolidState::pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  int m = 0;
  if (forward_motion) {
    // what comm->forward_comm() sends of x and v (periodic image shift,
    // fix deform's velocity remap), so that one message carries it all
    double **x = atom->x, **v = atom->v;
    const int *mask = atom->mask;
    double dx = 0.0, dy = 0.0, dz = 0.0, dvx = 0.0, dvy = 0.0, dvz = 0.0;
    if (pbc_flag) {
      if (domain->triclinic == 0) {
        dx = pbc[0] * domain->xprd;
        dy = pbc[1] * domain->yprd;
        dz = pbc[2] * domain->zprd;
      } else {
        dx = pbc[0] * domain->xprd + pbc[5] * domain->xy + pbc[4] * domain->xz;
        dy = pbc[1] * domain->yprd + pbc[3] * domain->yz;
        dz = pbc[2] * domain->zprd;
      }
      if (domain->deform_vremap) {
        const double *h_rate = domain->h_rate;
        dvx = pbc[0] * h_rate[0] + pbc[5] * h_rate[5] + pbc[4] * h_rate[4];
        dvy = pbc[1] * h_rate[1] + pbc[3] * h_rate[3];
        dvz = pbc[2] * h_rate[2];
      }
    }
    for (int ii = 0; ii < n; ii++) {
      const int j = list[ii];
      const bool remap = dvx != 0.0 || dvy != 0.0 || dvz != 0.0;
      const bool vshift = remap && (mask[j] & domain->deform_groupbit);
      buf[m++] = x[j][0] + dx;
      buf[m++] = x[j][1] + dy;
      buf[m++] = x[j][2] + dz;
      buf[m++] = v[j][0] + (vshift ? dvx : 0.0);
      buf[m++] = v[j][1] + (vshift ? dvy : 0.0);
      buf[m++] = v[j][2] + (vshift ? dvz : 0.0);
      buf[m++] = rho[j];
      if (forward_stress)
        for (int k = 0; k < ncomp; k++) buf[m++] = S[j][k];
    }
    return m;
  }
  for (int ii = 0; ii < n; ii++) {
    const int j = list[ii];
    buf[m++] = rho[j];
    if (forward_stress)
      for (int k = 0; k < ncomp; k++) buf[m++] = S[j][k];
  }
  return m;
}

void FixSPHSolidState::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  if (forward_motion) {
    double **x = atom->x, **v = atom->v;
    for (int i = first; i < first + n; i++) {
      for (int d = 0; d < 3; d++) x[i][d] = buf[m++];
      for (int d = 0; d < 3; d++) v[i][d] = buf[m++];
      rho[i] = buf[m++];
      if (forward_stress)
        for (int k = 0; k < ncomp; k++) S[i][k] = buf[m++];
    }
    return;
  }
  for (int i = first; i < first + n; i++) {
    rho[i] = buf[m++];
    if (forward_stress)
      for (int k = 0; k < ncomp; k++) S[i][k] = buf[m++];
  }
}

/* ----------------------------------------------------------------------
   restart: rho, S and the leapfrog's carried rates (the stage-1 copy is
   only alive inside a step); files with rho and S only are read too
------------------------------------------------------------------------- */

int FixSPHSolidState::pack_restart(int i, double *buf)
{
  int m = 0;
  buf[m++] = 3 + 2 * ncomp;    // LAMMPS convention: first value = count including itself
  buf[m++] = rho[i];
  for (int k = 0; k < ncomp; k++) buf[m++] = S[i][k];
  buf[m++] = carried_rho[i];
  for (int k = 0; k < ncomp; k++) buf[m++] = carried_S[i][k];
  return m;
}

void FixSPHSolidState::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  const int count = static_cast<int>(extra[nlocal][m]);
  if (count != 2 + ncomp && count != 3 + 2 * ncomp)
    error->one(FLERR,
               "SPH state in the restart file has {} values per atom, a {}D run needs {} (or {} "
               "with the leapfrog's rates)",
               count - 1, dim, ncomp + 1, 2 * (ncomp + 1));
  m++;
  rho[nlocal] = extra[nlocal][m++];
  for (int k = 0; k < ncomp; k++) S[nlocal][k] = extra[nlocal][m++];
  for (int k = 0; k < nsaved; k++) saved[nlocal][k] = 0.0;
  carried_rho[nlocal] = count == 2 + ncomp ? NAN : extra[nlocal][m++];
  for (int k = 0; k < ncomp; k++)
    carried_S[nlocal][k] = count == 2 + ncomp ? NAN : extra[nlocal][m++];
}

int FixSPHSolidState::size_restart(int /*i*/)
{
  return 3 + 2 * ncomp;
}

int FixSPHSolidState::maxsize_restart()
{
  return 3 + 2 * ncomp;
}

/* ---------------------------------------------------------------------- */

double FixSPHSolidState::memory_usage()
{
  return (double) nmax_arrays * (2 * (1 + ncomp) + nsaved) * sizeof(double);
}
