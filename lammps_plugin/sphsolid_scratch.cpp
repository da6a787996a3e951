/*
 * sphsolid_scratch.cpp - a throw-away library handle (see the header).
 */
#include "sphsolid_scratch.h"

#include "pair_sphsolid.h"

#include <algorithm>
#include <string>

using namespace LAMMPS_NS;

SPHSolidScratch::SPHSolidScratch(PairSPHSolid *pair) :
    sim(nullptr), dim(pair->dimension()), ncomp(pair->stress_components()),
    spacing(pair->particle_spacing())
{
  sim = pair->build_handle(false, false);
}

SPHSolidScratch::~SPHSolidScratch()
{
  if (sim) sph_destroy(sim);
}

void SPHSolidScratch::add(int m, const double *xi, double mi, double rhoi, const double *Si)
{
  material.push_back(m);
  x.insert(x.end(), xi, xi + dim);
  mass.push_back(mi);
  rho.push_back(rhoi);
  S.insert(S.end(), Si, Si + ncomp);
}

sph_status SPHSolidScratch::build()
{
  const size_t n = material.size();
  handle_index.assign(n, 0);
  std::vector<int> materials(material);
  std::sort(materials.begin(), materials.end());
  materials.erase(std::unique(materials.begin(), materials.end()), materials.end());

  size_t first = 0;
  std::vector<double> positions;
  for (int m : materials) {
    positions.clear();
    size_t count = 0;
    for (size_t k = 0; k < n; k++)
      if (material[k] == m) {
        positions.insert(positions.end(), x.begin() + k * dim, x.begin() + (k + 1) * dim);
        handle_index[k] = first + count++;
      }
    int body = 0;
    const std::string name = "lammps_material_" + std::to_string(m);
    const sph_status status =
        sph_add_particles(sim, name.c_str(), m, count, positions.data(), nullptr, spacing, &body);
    if (status != SPH_OK) {
      error_message = sph_errmsg(sim);
      return status;
    }
    first += count;
  }
  if (n == 0) return SPH_OK;

  double *field_mass, *field_rho, *field_S;
  size_t rows, cols;
  sph_status status = sph_field(sim, SPH_FIELD_MASS, &field_mass, &rows, &cols);
  if (status == SPH_OK) status = sph_field(sim, SPH_FIELD_DENSITY, &field_rho, &rows, &cols);
  if (status == SPH_OK)
    status = sph_field(sim, SPH_FIELD_DEVIATORIC_STRESS, &field_S, &rows, &cols);
  if (status != SPH_OK) {
    error_message = sph_errmsg(sim);
    return status;
  }
  for (size_t k = 0; k < n; k++) {
    const size_t j = handle_index[k];
    field_mass[j] = mass[k];
    field_rho[j] = rho[k];
    for (int c = 0; c < ncomp; c++) field_S[j * ncomp + c] = S[k * ncomp + c];
  }
  return SPH_OK;
}
