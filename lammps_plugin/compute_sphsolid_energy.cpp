/*
 * compute_sphsolid_energy.cpp - the energy account of pair sphsolid (see
 * the header).
 */
#include "compute_sphsolid_energy.h"

#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "error.h"
#include "force.h"
#include "update.h"

using namespace LAMMPS_NS;

ComputeSPHSolidEnergy::ComputeSPHSolidEnergy(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), pair(nullptr)
{
  if (narg != 3)
    error->all(FLERR, "compute sphsolid/energy takes no arguments after the style name, got '{}'",
               arg[3]);
  if (igroup != 0)
    error->all(FLERR,
               "compute sphsolid/energy must use group all: the account's work and dissipated "
               "energies are those of all atoms");
  vector_flag = 1;
  size_vector = N_VALUES;
  extvector = 1;
  vector = new double[size_vector];
  for (int k = 0; k < size_vector; k++) vector[k] = 0.0;
}

ComputeSPHSolidEnergy::~ComputeSPHSolidEnergy()
{
  delete[] vector;
}

void ComputeSPHSolidEnergy::init()
{
  pair = dynamic_cast<PairSPHSolid *>(force->pair_match("sphsolid", 1));
  if (!pair) error->all(FLERR, "compute sphsolid/energy needs 'pair_style sphsolid'");
  if (!pair->energy_account_on())
    error->all(FLERR, "compute sphsolid/energy needs pair sphsolid's energy account: add "
                      "'energy_account yes' to the pair_style command");
}

/* ---------------------------------------------------------------------- */

void ComputeSPHSolidEnergy::compute_vector()
{
  invoked_vector = update->ntimestep;
  FixSPHSolidState *state = pair->state();
  if (!state) error->all(FLERR, "compute sphsolid/energy: pair sphsolid has no per-atom state yet");

  // this rank's energies and shares of the account, summed over the ranks
  double mine[IMBALANCE] = {0.0};
  pair->energy_sums(mine);    // kinetic, elastic
  mine[WORK] = state->account[FixSPHSolidState::WORK];
  mine[DISSIPATED_DAMAGE] = state->account[FixSPHSolidState::DISSIPATED_DAMAGE];
  mine[DISSIPATED_PLASTIC] = state->account[FixSPHSolidState::DISSIPATED_PLASTIC];
  mine[DISSIPATED_VISCOSITY] = state->account[FixSPHSolidState::DISSIPATED_VISCOSITY];
  MPI_Allreduce(mine, vector, IMBALANCE, MPI_DOUBLE, MPI_SUM, world);

  // before the account starts (no run yet) the energy now is its start
  const double held = vector[KINETIC] + vector[ELASTIC];
  const double start = state->account_started ? state->account_reference : held;
  vector[IMBALANCE] = held + vector[DISSIPATED_DAMAGE] + vector[DISSIPATED_PLASTIC] +
                      vector[DISSIPATED_VISCOSITY] - vector[WORK] - start;
}
