/*
 * fix_sphsolid_state.cpp - per-atom SPH state (see fix_sphsolid_state.h).
 */
#include "fix_sphsolid_state.h"

#include "sphsolid.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "sphsolid_error.h"
#include "memory.h"

#include <algorithm>
#include <cmath>
#include <string>

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

FixSPHSolidState::FixSPHSolidState(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), rho(nullptr), S(nullptr), saved(nullptr), carried_rho(nullptr),
    carried_S(nullptr), damage(nullptr), flaw_count(nullptr), flaw_strain(nullptr), nmax_arrays(0)
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
  restart_global = 1;    // the energy account's totals
  create_attribute = 1;
  reset_account();
  forward_motion = false;
  forward_stress = true;
  set_comm_sizes();

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
  memory->destroy(damage);
  memory->destroy(flaw_count);
  memory->destroy(flaw_strain);
}

/* the energy account starts again (pair_style given again) */
void FixSPHSolidState::reset_account()
{
  for (double &value : account) value = 0.0;
  account_reference = 0.0;
  account_started = false;
}

/* values per atom of a forward message (with positions and velocities) and
   of an exchange */
void FixSPHSolidState::set_comm_sizes()
{
  const int with_damage = damage ? 1 : 0;
  comm_forward = 3 + 3 + 1 + ncomp + with_damage;
  maxexchange = 2 * (1 + ncomp) + nsaved + 3 * with_damage;
}

void FixSPHSolidState::set_damage(bool on)
{
  if (on == damage_on()) return;
  if (!on) {
    memory->destroy(damage);
    memory->destroy(flaw_count);
    memory->destroy(flaw_strain);
    damage = flaw_strain = nullptr;
    flaw_count = nullptr;
  } else {
    const int n = std::max(nmax_arrays, 1);
    memory->create(damage, n, "sphsolid:damage");
    memory->create(flaw_count, n, "sphsolid:flaw_count");
    memory->create(flaw_strain, n, "sphsolid:flaw_strain");
    for (int i = 0; i < n; i++) {
      damage[i] = 0.0;
      flaw_count[i] = 0;
      flaw_strain[i] = INFINITY;
    }
  }
  set_comm_sizes();
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
  if (damage) {
    memory->grow(damage, nmax, "sphsolid:damage");
    memory->grow(flaw_count, nmax, "sphsolid:flaw_count");
    memory->grow(flaw_strain, nmax, "sphsolid:flaw_strain");
  }
  nmax_arrays = nmax;
}

void FixSPHSolidState::copy_arrays(int i, int j, int /*delflag*/)
{
  rho[j] = rho[i];
  for (int k = 0; k < ncomp; k++) S[j][k] = S[i][k];
  for (int k = 0; k < nsaved; k++) saved[j][k] = saved[i][k];
  carried_rho[j] = carried_rho[i];
  for (int k = 0; k < ncomp; k++) carried_S[j][k] = carried_S[i][k];
  if (damage) {
    damage[j] = damage[i];
    flaw_count[j] = flaw_count[i];
    flaw_strain[j] = flaw_strain[i];
  }
}

void FixSPHSolidState::set_arrays(int i)
{
  rho[i] = 0.0;
  for (int k = 0; k < ncomp; k++) S[i][k] = 0.0;
  for (int k = 0; k < nsaved; k++) saved[i][k] = 0.0;
  carried_rho[i] = NAN;
  for (int k = 0; k < ncomp; k++) carried_S[i][k] = NAN;
  if (damage) {
    damage[i] = 0.0;
    flaw_count[i] = 0;
    flaw_strain[i] = INFINITY;
  }
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
  if (damage) {
    buf[m++] = damage[i];
    buf[m++] = flaw_count[i];
    buf[m++] = flaw_strain[i];
  }
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
  if (damage) {
    damage[nlocal] = buf[m++];
    flaw_count[nlocal] = static_cast<int>(buf[m++]);
    flaw_strain[nlocal] = buf[m++];
  }
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
      if (damage) buf[m++] = damage[j];
    }
    return m;
  }
  for (int ii = 0; ii < n; ii++) {
    const int j = list[ii];
    buf[m++] = rho[j];
    if (forward_stress)
      for (int k = 0; k < ncomp; k++) buf[m++] = S[j][k];
    if (damage) buf[m++] = damage[j];
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
      if (damage) damage[i] = buf[m++];
    }
    return;
  }
  for (int i = first; i < first + n; i++) {
    rho[i] = buf[m++];
    if (forward_stress)
      for (int k = 0; k < ncomp; k++) S[i][k] = buf[m++];
    if (damage) damage[i] = buf[m++];
  }
}

/* ----------------------------------------------------------------------
   restart: rho, S, the leapfrog's carried rates (the stage-1 copy is only
   alive inside a step) and, with damage on, D, the flaw count and the
   weakest activation strain; files with rho and S only, or without the
   damage state, are read too.  A file with the damage state turns the
   arrays on (pair sphsolid turns them off again at init if its damage
   effect is off).
------------------------------------------------------------------------- */

int FixSPHSolidState::pack_restart(int i, double *buf)
{
  int m = 0;
  buf[m++] = size_restart(i);    // LAMMPS convention: first value = count including itself
  buf[m++] = rho[i];
  for (int k = 0; k < ncomp; k++) buf[m++] = S[i][k];
  buf[m++] = carried_rho[i];
  for (int k = 0; k < ncomp; k++) buf[m++] = carried_S[i][k];
  if (damage) {
    buf[m++] = damage[i];
    buf[m++] = flaw_count[i];
    buf[m++] = flaw_strain[i];
  }
  return m;
}

void FixSPHSolidState::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  const int count = static_cast<int>(extra[nlocal][m]);
  const int plain = 2 + ncomp, with_rates = 3 + 2 * ncomp, with_damage = with_rates + 3;
  if (count != plain && count != with_rates && count != with_damage)
    sphsolid_one(lmp, FLERR,
                 "SPH state in the restart file has {} values per atom, a {}D run needs {} (or {} "
                 "with the leapfrog's rates, {} with the damage state)",
                 count - 1, dim, plain - 1, with_rates - 1, with_damage - 1);
  m++;
  rho[nlocal] = extra[nlocal][m++];
  for (int k = 0; k < ncomp; k++) S[nlocal][k] = extra[nlocal][m++];
  for (int k = 0; k < nsaved; k++) saved[nlocal][k] = 0.0;
  carried_rho[nlocal] = count == plain ? NAN : extra[nlocal][m++];
  for (int k = 0; k < ncomp; k++) carried_S[nlocal][k] = count == plain ? NAN : extra[nlocal][m++];
  if (count == with_damage) {
    set_damage(true);
    damage[nlocal] = extra[nlocal][m++];
    flaw_count[nlocal] = static_cast<int>(extra[nlocal][m++]);
    flaw_strain[nlocal] = extra[nlocal][m++];
  } else if (damage) {
    damage[nlocal] = 0.0;
    flaw_count[nlocal] = 0;
    flaw_strain[nlocal] = INFINITY;
  }
}

int FixSPHSolidState::size_restart(int /*i*/)
{
  return 3 + 2 * ncomp + (damage ? 3 : 0);
}

int FixSPHSolidState::maxsize_restart()
{
  return 3 + 2 * ncomp + (damage ? 3 : 0);
}

/* ----------------------------------------------------------------------
   restart, global: the energy account's totals summed over the ranks, its
   starting energy and whether it started (a collective: every rank calls
   write_restart; rank 0 writes).  Read back on rank 0 only, so that the
   ranks' shares still add up to the totals.
------------------------------------------------------------------------- */

void FixSPHSolidState::write_restart(FILE *fp)
{
  double list[N_ACCOUNT + 2];
  MPI_Allreduce(account, list, N_ACCOUNT, MPI_DOUBLE, MPI_SUM, world);
  list[N_ACCOUNT] = account_reference;
  list[N_ACCOUNT + 1] = account_started ? 1.0 : 0.0;
  if (comm->me == 0) {
    const int size = (int) sizeof(list);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), N_ACCOUNT + 2, fp);
  }
}

void FixSPHSolidState::restart(char *buf)
{
  const auto *list = reinterpret_cast<const double *>(buf);
  for (int k = 0; k < N_ACCOUNT; k++) account[k] = comm->me == 0 ? list[k] : 0.0;
  account_reference = list[N_ACCOUNT];
  account_started = list[N_ACCOUNT + 1] != 0.0;
}

/* ---------------------------------------------------------------------- */

double FixSPHSolidState::memory_usage()
{
  return (double) nmax_arrays * (2 * (1 + ncomp) + nsaved) * sizeof(double) +
         (damage ? (double) nmax_arrays * (2 * sizeof(double) + sizeof(int)) : 0.0);
}
