/*
 * pair_sphsolid.cpp - pair style sphsolid (see pair_sphsolid.h).
 *
 * No equation of the model appears here: the rates come from the
 * library's pair pass over LAMMPS's half list and its finish; this file
 * only moves data between LAMMPS's arrays and the library's layout.  A
 * pair of owned atoms is computed once.  A pair of an owned and a ghost
 * atom is listed on both ranks (LAMMPS's half list built with newton off),
 * and the pair style honours the newton_pair setting for it, as LAMMPS's
 * pair styles do:
 *  - newton off: both ranks compute it, each adding only its own atom's
 *    terms (sph_rates_pass_half); one exchange per rate evaluation (the
 *    ghosts' state), nothing sent back;
 *  - newton on: one of the two ranks computes it, the one a hash of the
 *    two atom IDs picks (so that pairs across a subdomain boundary split
 *    evenly between its sides), and the ghosts' partial sums are sent
 *    back to their owners between the pair pass and the finish (LAMMPS's
 *    reverse communication, as the MACHDYN and SPH packages do for their
 *    pair sums); two exchanges per evaluation, each pair computed once.
 */
#include "pair_sphsolid.h"

#include "fix_sphsolid_state.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "sphsolid_error.h"
#include "fix.h"
#include "group.h"
#include "force.h"
#include "lattice.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <sstream>

using namespace LAMMPS_NS;

static const char STATE_FIX_ID[] = "SPHSOLID_STATE";

/* ---------------------------------------------------------------------- */

PairSPHSolid::PairSPHSolid(LAMMPS *lmp) :
    Pair(lmp), dim(0), spacing(0.0), h_over_dx(0.0), support(0.0), xsph(false), damage(false),
    drucker_prager(false), account(false), account_reset(false), power_sum(), power_evaluations(0),
    power_last(), power_last_valid(false), sim(nullptr), state_fix(nullptr), cached_build(-1),
    cached_nall(-1), nmax_scratch(0), nrates(-1), send_back(false), partial_size(0), pass_size(0),
    compute_pass(SPH_RATES_ALL), pairs_computed(0), ghost_pairs(0), part_seconds()
{
  single_enable = 0;
  restartinfo = 0;    // pair_style and pair_coeff are given again after read_restart
  one_coeff = 0;
  manybody_flag = 0;
  no_virial_fdotr_compute = 1;    // no pair virial: the stress lives in the SPH state
}

PairSPHSolid::~PairSPHSolid()
{
  if (copymode) return;
  if (sim) sph_destroy(sim);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
  // the per-atom SPH state belongs to this pair style
  if (modify && modify->get_fix_by_id(STATE_FIX_ID)) modify->delete_fix(STATE_FIX_ID);
}

/* ---------------------------------------------------------------------- */

void PairSPHSolid::allocate()
{
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n, n, "pair:cutsq");
  type_params.assign(n, SPHSolidMaterial());
  type_material.assign(n, -1);
}

/* ----------------------------------------------------------------------
   pair_style sphsolid dx [h_over_dx r] [kernel name] [energy_account yes|no]
                       [effect [key value]...]...
------------------------------------------------------------------------- */

void PairSPHSolid::settings(int narg, char **arg)
{
  if (narg < 1)
    error->all(FLERR, "pair_style sphsolid: missing the particle spacing dx, e.g. "
                      "'pair_style sphsolid 0.001 artificial_viscosity alpha 1.0'");
  if (domain->dimension != 2 && domain->dimension != 3)
    error->all(FLERR, "pair_style sphsolid: dimension {} is not 2 or 3", domain->dimension);
  dim = domain->dimension;

  spacing = utils::numeric(FLERR, arg[0], false, lmp);
  if (!(spacing > 0.0))
    error->all(FLERR, "pair_style sphsolid: particle spacing dx must be positive, got {}", arg[0]);

  std::set<std::string> effect_names;
  {
    std::istringstream words(sph_effect_names());
    std::string w;
    while (words >> w) effect_names.insert(w);
  }
  auto is_keyword = [&](const std::string &w) {
    return w == "h_over_dx" || w == "kernel" || w == "energy_account" || effect_names.count(w) > 0;
  };

  h_over_dx = 0.0;    // 0: the library's default
  kernel.clear();     // empty: the library's default
  effects.clear();
  xsph = false;
  damage = false;
  drucker_prager = false;
  account = false;
  // given again after a run: the energy account starts again at the next init
  account_reset = sim != nullptr;

  int iarg = 1;
  while (iarg < narg) {
    const std::string word = arg[iarg];
    if (word == "h_over_dx") {
      if (iarg + 1 >= narg) error->all(FLERR, "pair_style sphsolid: h_over_dx needs a value");
      h_over_dx = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(h_over_dx > 0.0))
        error->all(FLERR, "pair_style sphsolid: h_over_dx must be positive, got {}", arg[iarg + 1]);
      iarg += 2;
    } else if (word == "kernel") {
      if (iarg + 1 >= narg) error->all(FLERR, "pair_style sphsolid: kernel needs a name");
      kernel = arg[iarg + 1];    // the library judges the name
      iarg += 2;
    } else if (word == "energy_account") {
      if (iarg + 1 >= narg)
        error->all(FLERR, "pair_style sphsolid: energy_account needs yes or no");
      account = utils::logical(FLERR, arg[iarg + 1], false, lmp) != 0;
      iarg += 2;
    } else if (effect_names.count(word)) {
      if (word == "gravity")
        error->all(FLERR, "pair_style sphsolid: gravity is not a pair keyword; use LAMMPS's "
                          "'fix ID group gravity magnitude vector x y z'");
      std::string parameters;
      iarg++;
      while (iarg < narg && !is_keyword(arg[iarg])) {
        if (iarg + 1 >= narg || is_keyword(arg[iarg + 1]))
          error->all(FLERR, "pair_style sphsolid: {} parameter '{}' needs a value", word,
                     arg[iarg]);
        const double value = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
        parameters += fmt::format("{}{}={:.17g}", parameters.empty() ? "" : " ", arg[iarg], value);
        iarg += 2;
      }
      for (const auto &e : effects)
        if (e.first == word) error->all(FLERR, "pair_style sphsolid: effect {} given twice", word);
      effects.emplace_back(word, parameters);
      if (word == "xsph") xsph = true;
      if (word == "damage") damage = true;
      if (word == "drucker_prager") drucker_prager = true;
    } else {
      std::string known = "h_over_dx kernel energy_account";
      for (const auto &e : effect_names)
        if (e != "gravity") known += " " + e;
      error->all(FLERR, "pair_style sphsolid: unknown keyword '{}' (known: {})", word, known);
    }
  }

  // let the library validate the effects and parameters now, not at run time
  sph_sim *check = build_handle(true);
  support = sph_support_radius(check);
  sph_destroy(check);
}

/* The keys of the library's material registry (sph_material_key_get), in
   its order: pair_coeff takes each by name, so a key the library learns
   needs no edit here. */
static std::vector<sph_material_key_info> material_keys()
{
  std::vector<sph_material_key_info> keys;
  for (int k = 0; k < sph_material_key_count(); k++) {
    sph_material_key_info info;
    if (sph_material_key_get(k, &info) == SPH_OK) keys.push_back(info);
  }
  return keys;
}

/* A user's word in a message: at most 40 characters, and its length. */
static std::string clip(const std::string &word)
{
  if (word.size() <= 40) return word;
  return fmt::format("{}... ({} characters)", word.substr(0, 40), word.size());
}

/* The library material for a pair_coeff: whichever pair of constants was
   given decides the library call; the registry keys given are set on it
   (the library checks each value against the key's range). */
static sph_status add_material(sph_sim *s, const SPHSolidMaterial &m, int *index)
{
  sph_status status;
  if (m.kind == "K_mu")
    status = sph_add_material_K_mu(s, m.first, m.second, m.rho0, index);
  else if (m.kind == "E_nu")
    status = sph_add_material_E_nu(s, m.first, m.second, m.rho0, index);
  else
    status = sph_add_material_K_nu(s, m.first, m.second, m.rho0, index);
  for (const auto &key : m.keys)
    if (status == SPH_OK) status = sph_material_set(s, *index, key.first.c_str(), key.second);
  return status;
}

/* ----------------------------------------------------------------------
   pair_coeff I J K v mu v rho0 v  |  E v nu v rho0 v  |  K v nu v rho0 v
              [key v]...   (any key of the library's material registry)
------------------------------------------------------------------------- */

void PairSPHSolid::coeff(int narg, char **arg)
{
  if (narg < 2)
    error->all(FLERR, "pair_coeff for sphsolid: expected 'pair_coeff I J K <Pa> mu <Pa> rho0 "
                      "<kg/m^3>' (or E and nu, or K and nu, instead of K and mu)");
  if (!allocated) allocate();

  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);

  const std::vector<sph_material_key_info> registry = material_keys();
  std::set<std::string> elastic = {"K", "mu", "E", "nu", "rho0"};
  std::map<std::string, double> given;
  SPHSolidMaterial m;
  for (int iarg = 2; iarg < narg; iarg += 2) {
    const std::string key = arg[iarg];
    bool known = elastic.count(key) > 0;
    for (const auto &info : registry) known = known || key == info.key;
    if (!known) {
      std::string names = "K, mu, E, nu, rho0";
      for (const auto &info : registry) names += std::string(", ") + info.key;
      error->all(FLERR, "pair_coeff for sphsolid: unknown keyword '{}' (expected {})", clip(key),
                 names);
    }
    if (iarg + 1 >= narg) error->all(FLERR, "pair_coeff for sphsolid: {} needs a value", key);
    if (given.count(key) || m.keys.count(key))
      error->all(FLERR, "pair_coeff for sphsolid: {} given twice", key);
    const double value = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    if (elastic.count(key))
      given[key] = value;
    else
      m.keys[key] = value;
  }
  if (!given.count("rho0"))
    error->all(FLERR, "pair_coeff for sphsolid: missing rho0 (reference density in kg/m^3)");

  m.rho0 = given["rho0"];
  const size_t nconst = given.size() - 1;
  if (nconst == 2 && given.count("K") && given.count("mu")) {
    m.kind = "K_mu", m.first = given["K"], m.second = given["mu"];
  } else if (nconst == 2 && given.count("E") && given.count("nu")) {
    m.kind = "E_nu", m.first = given["E"], m.second = given["nu"];
  } else if (nconst == 2 && given.count("K") && given.count("nu")) {
    m.kind = "K_nu", m.first = given["K"], m.second = given["nu"];
  } else {
    std::string got;
    for (const auto &g : given)
      if (g.first != "rho0") got += " " + g.first;
    error->all(FLERR,
               "pair_coeff for sphsolid: give exactly one pair of elastic constants "
               "(K and mu, E and nu, or K and nu), got:{}",
               got.empty() ? " none" : got);
  }

  // the library checks the values (K > 0, mu >= 0, -1 < nu < 0.5, rho0 > 0)
  sph_sim *check = nullptr;
  sph_create(dim ? dim : domain->dimension, &check);
  if (!check) error->all(FLERR, "pair_coeff for sphsolid: out of memory");
  int index = 0;
  sph_status status = SPH_OK;
  status = add_material(check, m, &index);
  if (status != SPH_OK) fail(check, status, fmt::format("pair_coeff {} {}", arg[0], arg[1]), true);
  sph_destroy(check);

  int count = 0;
  for (int i = ilo; i <= ihi; i++)
    for (int j = std::max(jlo, i); j <= jhi; j++)
      if (i == j) {
        type_params[i] = m;
        setflag[i][i] = 1;
        count++;
      }
  if (count == 0)
    error->all(FLERR,
               "pair_coeff {} {} for sphsolid: a material belongs to one atom type; use "
               "'pair_coeff I I ...' or 'pair_coeff * * ...' (mixed pairs follow from the "
               "materials of the two types)",
               arg[0], arg[1]);
}

/* ---------------------------------------------------------------------- */

sph_sim *PairSPHSolid::build_handle(bool with_effects)
{
  sph_sim *s = nullptr;
  sph_status status = sph_create(dim, &s);
  if (!s) error->all(FLERR, "pair sphsolid: out of memory creating a library handle");
  if (status != SPH_OK) fail(s, status, "creating the library handle", true);

  if (!kernel.empty()) {
    status = sph_set_kernel_by_name(s, kernel.c_str());
    if (status != SPH_OK) fail(s, status, "kernel", true);
  }
  if (h_over_dx > 0.0) {
    status = sph_set_smoothing_ratio(s, h_over_dx);
    if (status != SPH_OK) fail(s, status, "h_over_dx", true);
  }
  status = sph_set_threads(s, comm->nthreads);
  if (status != SPH_OK) fail(s, status, "threads", true);

  if (with_effects)
    for (const auto &e : effects) {
      status = sph_effect(s, e.first.c_str(), e.second.c_str());
      if (status != SPH_OK) fail(s, status, "pair_style effect " + e.first, true);
    }

  // one library material per distinct pair_coeff, in type order
  std::vector<SPHSolidMaterial> distinct;
  for (size_t t = 1; t < type_params.size(); t++) {
    type_material[t] = -1;
    const SPHSolidMaterial &m = type_params[t];
    if (m.kind.empty()) continue;
    int index = -1;
    for (size_t k = 0; k < distinct.size(); k++)
      if (distinct[k] == m) index = (int) k;
    if (index < 0) {
      status = add_material(s, m, &index);
      if (status != SPH_OK) fail(s, status, fmt::format("material of atom type {}", t), true);
      distinct.push_back(m);
    }
    type_material[t] = index;
  }

  // h = h_over_dx * dx, and the artificial stress's W(dx), from the
  // pair_style spacing: this handle never holds particles of its own
  status = sph_set_spacing(s, spacing);
  if (status != SPH_OK) fail(s, status, "particle spacing dx", true);
  return s;
}

/* ---------------------------------------------------------------------- */

/* The library judges values this rank holds, and a value may differ
 * between ranks (a variable of the rank): error->one prints the message
 * from the rank that refused it before the job stops.  error->all on one
 * rank alone would print nothing (only rank 0 prints) and leave the other
 * ranks in a collective until mpirun kills the job. */
void PairSPHSolid::fail(sph_sim *s, sph_status status, const std::string &what, bool destroy)
{
  const std::string message = fmt::format("{} ({})", sph_errmsg(s), sph_status_name(status));
  if (destroy) sph_destroy(s);
  sphsolid_one(lmp, FLERR, "pair sphsolid: {}: {}", what, message);
}

/* ---------------------------------------------------------------------- */

double PairSPHSolid::handle_timestep(const char *integrator, double (*step_of)(const sph_sim *))
{
  if (!allocated) return 0.0;
  for (int t = 1; t <= atom->ntypes; t++)
    if (!setflag[t][t]) return 0.0;
  // a handle without bodies takes its steps from its materials
  sph_sim *s = build_handle(false);
  const double dt = sph_set_integrator(s, integrator) == SPH_OK ? step_of(s) : 0.0;
  sph_destroy(s);
  return dt;
}

double PairSPHSolid::default_timestep(const char *integrator)
{
  return handle_timestep(integrator, sph_default_dt);
}

/* ---------------------------------------------------------------------- */

void PairSPHSolid::init_style()
{
  if (strcmp(update->unit_style, "si") != 0)
    error->all(FLERR,
               "pair sphsolid requires 'units si' (libsphsolid works in SI units), got "
               "'units {}'",
               update->unit_style);
  if (domain->dimension != dim)
    error->all(FLERR, "pair sphsolid: dimension changed to {} after pair_style (was {})",
               domain->dimension, dim);
  if (!comm->ghost_velocity)
    error->all(FLERR,
               "pair sphsolid needs the velocities of ghost atoms: add 'comm_modify vel yes'");
  if (!atom->tag_enable) error->all(FLERR, "pair sphsolid needs atom IDs (atom_modify id yes)");
  check_ranks_agree();

  // a half list in which a pair with a ghost is listed on both ranks
  // (newton off): with newton_pair off each rank adds its own atom's
  // terms and nothing is sent back; with it on, convert_list() keeps the
  // pair on one of the ranks and the ghosts' sums are sent back
  neighbor->add_request(this, NeighConst::REQ_NEWTON_OFF);
  send_back = force->newton_pair != 0;
  cached_build = -1;               // materials of the types may have changed
  compute_pass = SPH_RATES_ALL;    // until an integrator fix asks for less (its init follows)
  reset_seconds();

  if (sim) sph_destroy(sim);
  sim = nullptr;
  sim = build_handle(true);
  support = sph_support_radius(sim);
  partial_size = (int) sph_rates_pass_size(sim, SPH_RATES_ALL);
  comm_reverse = partial_size;    // the largest pass; each sends only its own sums
  comm_reverse_off = partial_size;

  state_fix = dynamic_cast<FixSPHSolidState *>(modify->get_fix_by_id(STATE_FIX_ID));
  if (!state_fix) {
    state_fix = dynamic_cast<FixSPHSolidState *>(
        modify->add_fix(fmt::format("{} all SPHSOLID/STATE", STATE_FIX_ID)));
    if (!state_fix) error->all(FLERR, "pair sphsolid: could not create its per-atom state fix");
  }
  if (state_fix->dimension() != dim)
    error->all(FLERR, "pair sphsolid: the stored per-atom state is {}D, the run is {}D",
               state_fix->dimension(), dim);
  // the damage state lives with the atoms while the effect is on; D read
  // from a restart file is kept, the flaws are drawn again at the
  // integrator's init (draw_flaws)
  state_fix->set_damage(damage);
  if (account_reset) state_fix->reset_account();
  account_reset = false;
  power_sum[0] = power_sum[1] = 0.0;
  power_evaluations = 0;

  check_deck();

  // every atom needs a positive mass
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    if (!(mass_of(i) > 0.0))
      sphsolid_one(lmp, FLERR,
                   "pair sphsolid: atom {} has mass {}; SPH particles need a positive mass",
                   atom->tag[i], mass_of(i));

  initialise_state();
}

/* ----------------------------------------------------------------------
   every rank read the same settings: a rank-dependent variable in the deck
   would give each rank another model (other message sizes, other sums)
------------------------------------------------------------------------- */

static unsigned long long text_hash(const std::string &text)
{
  unsigned long long h = 14695981039346656037ULL;    // FNV-1a
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ULL;
  return h;
}

void PairSPHSolid::check_ranks_agree()
{
  // one (keyword, value) per setting, the same list on every rank: the
  // effects of the registry, every atom type
  std::vector<std::pair<std::string, std::string>> settings;
  auto number = [](double v) {
    return fmt::format("{}", v);
  };    // shortest exact
  settings.emplace_back("dx", number(spacing));
  settings.emplace_back("h_over_dx", number(h_over_dx));
  settings.emplace_back("kernel", kernel);
  settings.emplace_back("energy_account", account ? "yes" : "no");
  {
    std::istringstream words(sph_effect_names());
    std::string name;
    while (words >> name) {
      std::string value = "off";
      for (const auto &e : effects)
        if (e.first == name) value = "on " + e.second;
      settings.emplace_back(name, value);
    }
  }
  for (int t = 1; t <= atom->ntypes; t++) {
    const SPHSolidMaterial &m = type_params[t];
    std::string text =
        fmt::format("{} {} {} {}", m.kind, number(m.first), number(m.second), number(m.rho0));
    for (const auto &key : m.keys) text += fmt::format(" {} {}", key.first, number(key.second));
    settings.emplace_back(fmt::format("pair_coeff {} {}", t, t), text);
  }
  settings.emplace_back("timestep", number(update->dt));

  const int count = (int) settings.size();
  int counts[2] = {-count, count}, extreme[2];
  MPI_Allreduce(counts, extreme, 2, MPI_INT, MPI_MAX, world);
  if (-extreme[0] != extreme[1])
    error->all(FLERR,
               "pair sphsolid: the number of settings differs between MPI ranks ({} to {}: "
               "atom types or the effect registry differ)",
               -extreme[0], extreme[1]);
  std::vector<unsigned long long> mine(count), low(count), high(count);
  for (int k = 0; k < count; k++) mine[k] = text_hash(settings[k].second);
  MPI_Allreduce(mine.data(), low.data(), count, MPI_UNSIGNED_LONG_LONG, MPI_MIN, world);
  MPI_Allreduce(mine.data(), high.data(), count, MPI_UNSIGNED_LONG_LONG, MPI_MAX, world);
  for (int k = 0; k < count; k++)
    if (low[k] != high[k])
      error->all(FLERR,
                 "pair sphsolid: {} differs between MPI ranks ('{}' on rank {}, another value on "
                 "some other rank): every rank must read the same pair_style, pair_coeff and "
                 "timestep values (is a variable of the deck rank-dependent?)",
                 settings[k].first, settings[k].second, comm->me);
}

/* ----------------------------------------------------------------------
   deck checks at each run's init: an integrator for the SPH state, no
   other integrator on its atoms, masses and lattice that agree with dx,
   a timestep within the stable step
------------------------------------------------------------------------- */

void PairSPHSolid::check_deck()
{
  // integrators of the SPH state: fixes of style sphsolid/... that
  // integrate (sphsolid/improved_euler, sphsolid/leapfrog, ...)
  std::vector<Fix *> sph_integrators, others;
  for (int k = 0; k < modify->nfix; k++) {
    Fix *f = modify->fix[k];
    if (!f->time_integrate) continue;
    if (utils::strmatch(f->style, "^sphsolid/"))
      sph_integrators.push_back(f);
    else
      others.push_back(f);
  }
  if (update->whichflag == 1 && update->nsteps > 0 && sph_integrators.empty())
    error->all(FLERR, "pair sphsolid: no sphsolid integrator fix (e.g. 'fix 1 all "
                      "sphsolid/improved_euler'): without one "
                      "the density and stress never evolve and the run has no elastic forces");
  // another integrator (fix nve, fix move, ...) on the same atoms would
  // move them twice and leave the SPH state behind
  for (Fix *mine : sph_integrators)
    for (Fix *other : others) {
      bigint local = 0, both = 0;
      for (int i = 0; i < atom->nlocal; i++)
        if ((atom->mask[i] & mine->groupbit) && (atom->mask[i] & other->groupbit)) local++;
      MPI_Allreduce(&local, &both, 1, MPI_LMP_BIGINT, MPI_SUM, world);
      if (both > 0)
        error->all(
            FLERR,
            "pair sphsolid: fix {} ({}) integrates {} atoms that fix {} ({}) also integrates "
            "(group {}): each atom needs exactly one integrator; leave prescribed or "
            "separately integrated atoms out of group {}",
            other->id, other->style, both, mine->id, mine->style, group->names[other->igroup],
            group->names[mine->igroup]);
    }

  // masses: m = rho0 dx^d for particles on the pair's lattice
  const double cell = std::pow(spacing, dim);
  if (!atom->rmass && comm->me == 0)
    for (int t = 1; t <= atom->ntypes; t++) {
      if (!setflag[t][t] || !atom->mass_setflag[t]) continue;
      const double expected = type_params[t].rho0 * cell;
      if (std::fabs(atom->mass[t] - expected) > 1e-6 * expected)
        error->warning(FLERR,
                       "pair sphsolid: atom type {} has mass {:.6g} kg, but rho0 dx^{} = {:.6g} kg "
                       "(rho0 {:.6g} kg/m^3, dx {:.6g} m): its particles' volume m/rho0 is {:.4g} "
                       "dx^{}; check the mass command or the pair_style spacing",
                       t, atom->mass[t], dim, expected, type_params[t].rho0, spacing,
                       atom->mass[t] / expected, dim);
    }
  // the lattice, when one is defined, should have the pair's spacing
  if (domain->lattice && domain->lattice->style != Lattice::NONE && comm->me == 0 &&
      std::fabs(domain->lattice->xlattice - spacing) > 1e-6 * spacing)
    error->warning(FLERR,
                   "pair sphsolid: pair_style spacing dx = {:.6g} m, but the lattice spacing is "
                   "{:.6g} m: h = h_over_dx * dx and the masses assume dx",
                   spacing, domain->lattice->xlattice);
  // a step far above the stable one blows up within a few steps
  if (update->whichflag == 1 && update->nsteps > 0 && !update->dt_default) {
    const double stable = stable_timestep(integrator_name());
    if (stable > 0.0 && update->dt > stable && comm->me == 0)
      error->warning(FLERR,
                     "pair sphsolid: timestep {:.6g} s is {:.3g} times the stable step {:.6g} s "
                     "(CFL limit of the stiffest material): the run will go unstable",
                     update->dt, update->dt / stable, stable);
  }
}

double PairSPHSolid::stable_timestep(const char *integrator)
{
  return handle_timestep(integrator, sph_stable_dt);
}

const char *PairSPHSolid::integrator_name()
{
  // fix sphsolid/<name> integrates with the library's <name>; sphsolid/heun
  // is the deprecated name of sphsolid/improved_euler
  for (int k = 0; k < modify->nfix; k++) {
    Fix *f = modify->fix[k];
    if (!f->time_integrate || !utils::strmatch(f->style, "^sphsolid/")) continue;
    const char *name = f->style + strlen("sphsolid/");
    return strcmp(name, "heun") == 0 ? "improved_euler" : name;
  }
  return "improved_euler";
}

std::string PairSPHSolid::step_advice(const char *integrator)
{
  const char *name = integrator ? integrator : integrator_name();
  return fmt::format("timestep {:.6g} s, stable step {:.6g} s of {}", update->dt,
                     stable_timestep(name), name);
}

/* ----------------------------------------------------------------------
   atoms that have never carried SPH state (density 0, the value of a new
   atom) start at rest in their material's reference state: rho = rho0,
   S = 0.  Atoms whose state came from a restart file keep it.
------------------------------------------------------------------------- */

void PairSPHSolid::initialise_state()
{
  const int nlocal = atom->nlocal;
  const int ncomp = stress_components();
  const int *type = atom->type;
  bigint count = 0;
  for (int i = 0; i < nlocal; i++) {
    if (state_fix->rho[i] != 0.0) continue;
    state_fix->rho[i] = type_params[type[i]].rho0;
    for (int k = 0; k < ncomp; k++) state_fix->S[i][k] = 0.0;
    count++;
  }
  bigint total = 0;
  MPI_Allreduce(&count, &total, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (total > 0 && comm->me == 0)
    utils::logmesg(lmp,
                   "pair sphsolid: {} atoms without SPH state start at their material's "
                   "reference density rho0 with zero deviatoric stress\n",
                   total);
}

/* ---------------------------------------------------------------------- */

double PairSPHSolid::init_one(int i, int j)
{
  if (!setflag[i][i] || !setflag[j][j])
    error->all(FLERR, "pair sphsolid: atom type {} has no material (pair_coeff {} {} ...)",
               setflag[i][i] ? j : i, setflag[i][i] ? j : i, setflag[i][i] ? j : i);
  return support;
}

/* ---------------------------------------------------------------------- */

/* ---------------------------------------------------------------------- */

void PairSPHSolid::grow_scratch()
{
  if (atom->nmax <= nmax_scratch) return;
  nmax_scratch = atom->nmax;
  const size_t n = nmax_scratch;
  const int ncomp = stress_components();
  massbuf.resize(n);
  materialbuf.resize(n);
  rate_dv.resize(n * dim);
  rate_drho.resize(n);
  rate_dS.resize(n * ncomp);
  if (xsph) rate_dx.resize(n * dim);
  if (send_back) partial.resize(n * partial_size);
}

/* ----------------------------------------------------------------------
   With newton_pair on, which of the two ranks that list a pair of owned
   atom i and ghost j computes it: the one owning the atom of the smaller
   ID, or of the larger, by one bit of a hash of the two IDs.  Both ranks
   decide alike, so each pair is computed once, and the pairs across a
   subdomain boundary split about evenly between its two sides whatever the
   lattice (a rule by coordinates, as LAMMPS's own newton on list, gives
   them all to one side).  An atom near its own periodic image (equal IDs)
   computes the pair with the image above it (z, then y, then x), as
   LAMMPS does.
------------------------------------------------------------------------- */

static inline uint64_t mix_ids(uint64_t a, uint64_t b)
{
  uint64_t h = a * 0x9E3779B97F4A7C15ULL + b;    // splitmix64's finaliser
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ULL;
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBULL;
  return h ^ (h >> 31);
}

bool PairSPHSolid::computes_pair_with_ghost(int i, int j) const
{
  if (!send_back) return true;
  const tagint ti = atom->tag[i], tj = atom->tag[j];
  if (ti != tj) {
    const bool smaller_computes = mix_ids(std::min(ti, tj), std::max(ti, tj)) & 1;
    return (ti < tj) == smaller_computes;
  }
  const double *xi = atom->x[i], *xj = atom->x[j];
  if (xj[2] != xi[2]) return xj[2] > xi[2];
  if (xj[1] != xi[1]) return xj[1] > xi[1];
  return xj[0] > xi[0];
}

/* ----------------------------------------------------------------------
   LAMMPS's half list as CSR rows sorted by index, as the library's own
   list is: a pair of owned atoms goes to the row of the smaller index, a
   pair with a ghost stays in the owned atom's row (with newton_pair off
   the ghost's own rank lists it too, for its atom; with it on, only the
   rank that computes it: computes_pair_with_ghost).  Neighbour data are then read in memory
   order and most pair terms land in nearby rows.  Special-bond bits in the
   top of the indices are stripped.  Only on a new list.
------------------------------------------------------------------------- */

void PairSPHSolid::convert_list()
{
  const int nlocal = atom->nlocal;
  const int inum = list->inum;
  const int *ilist = list->ilist;
  neighbour_counts.assign(nlocal, 0);
  bigint ghosts = 0;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (j < nlocal) {
        neighbour_counts[std::min(i, j)]++;
      } else if (computes_pair_with_ghost(i, j)) {
        neighbour_counts[i]++;
        ghosts++;
      }
    }
  }
  neighbour_offsets.resize((size_t) nlocal + 1);
  neighbour_offsets[0] = 0;
  for (int i = 0; i < nlocal; i++)
    neighbour_offsets[i + 1] = neighbour_offsets[i] + neighbour_counts[i];
  pairs_computed = neighbour_offsets[nlocal];
  ghost_pairs = ghosts;
  neighbour_indices.resize(std::max<size_t>(neighbour_offsets[nlocal], 1));
  std::vector<size_t> fill(neighbour_offsets.begin(), neighbour_offsets.end() - 1);
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (j < nlocal)
        neighbour_indices[fill[std::min(i, j)]++] = std::max(i, j);
      else if (computes_pair_with_ghost(i, j))
        neighbour_indices[fill[i]++] = j;
    }
  }
  for (int i = 0; i < nlocal; i++)
    std::sort(neighbour_indices.data() + neighbour_offsets[i],
              neighbour_indices.data() + neighbour_offsets[i + 1]);
}

/* ---------------------------------------------------------------------- */

void PairSPHSolid::evaluate_rates(bool with_motion, int pass, double *drho_into, double *dS_into)
{
  // density and deviatoric stress of the ghosts, and with_motion their
  // positions and velocities too, in one exchange (the stress only for a
  // pass that reads it: the momentum pass)
  double start = cpu_seconds();
  state_fix->forward_motion = with_motion;
  state_fix->forward_stress = (pass & SPH_RATES_MOMENTUM) != 0;
  comm->forward_comm(state_fix);
  state_fix->forward_motion = false;
  state_fix->forward_stress = true;
  double now = cpu_seconds();
  part_seconds[PART_EXCHANGE] += now - start;
  start = now;

  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  if (xsph && rate_dx.size() < (size_t) nmax_scratch * dim) nmax_scratch = 0;
  if (send_back && partial.size() < (size_t) nmax_scratch * partial_size) nmax_scratch = 0;
  grow_scratch();
  nrates = nlocal;
  if (nall == 0) return;

  // positions and velocities: LAMMPS's arrays, 3 doubles per atom
  const double *xp = atom->x[0], *vp = atom->v[0];

  // masses, materials and the neighbour pointers change only with a new
  // neighbour list (LAMMPS moves and sorts atoms only when it re-neighbours)
  const double *rmass = atom->rmass;
  const int *type = atom->type;
  if (neighbor->ncalls != cached_build || nall != cached_nall) {
    if (!rmass)
      for (int i = 0; i < nall; i++) massbuf[i] = atom->mass[type[i]];
    for (int i = 0; i < nall; i++) materialbuf[i] = type_material[type[i]];
    convert_list();
    cached_build = neighbor->ncalls;
    cached_nall = nall;
  }
  now = cpu_seconds();
  part_seconds[PART_REFRESH] += now - start;
  start = now;
  const double *mp = rmass ? rmass : massbuf.data();

  sph_particles particles{};    // fields not set below stay zero
  particles.n_local = nlocal;
  particles.n_total = nall;
  particles.x = xp;
  particles.v = vp;
  particles.rho = state_fix->rho;
  particles.S = state_fix->S_data();
  particles.mass = mp;
  particles.material = materialbuf.data();
  particles.stride = 3;
  particles.damage = damage ? state_fix->damage : nullptr;    // ghosts' D came with their state

  sph_neighbours neighbours{};
  neighbours.offsets = neighbour_offsets.data();
  neighbours.indices = neighbour_indices.data();
  neighbours.lists = nullptr;
  neighbours.counts = nullptr;

  sph_rates rates;
  rates.dv_dt = rate_dv.data();
  rates.drho_dt = drho_into ? drho_into : rate_drho.data();
  rates.dS_dt = dS_into ? dS_into : rate_dS.data();
  rates.dx_dt = xsph ? rate_dx.data() : nullptr;

  // the pass over the pairs and its finish: the rates of the owned atoms.
  // newton off: the terms of a pair with a ghost go to the owned atom only.
  // newton on: pair sums on owned and ghost atoms, the ghosts' sums sent
  // back to their owners (a pass computes, and sends back, only its own
  // sums: pass_size doubles per atom), then the finish.
  sph_status status;
  if (send_back) {
    pass_size = (int) sph_rates_pass_size(sim, pass);
    status = sph_rates_pass_pairs(sim, pass, &particles, &neighbours, partial.data());
    if (status == SPH_OK) {
      now = cpu_seconds();
      part_seconds[PART_RATES] += now - start;
      comm->reverse_comm(this, pass_size);
      start = cpu_seconds();
      part_seconds[PART_EXCHANGE] += start - now;
      status = sph_rates_pass_finish(sim, pass, &particles, partial.data(), &rates);
    }
  } else {
    status = sph_rates_pass_half(sim, pass, &particles, &neighbours, &rates);
  }
  part_seconds[PART_RATES] += cpu_seconds() - start;
  if (status != SPH_OK) {
    // name the atom by its ID (the library sees local indices)
    const double *rho = particles.rho;
    for (int i = 0; i < (int) particles.n_total; i++)
      if (!(rho[i] > 0.0) || !std::isfinite(rho[i]))
        sphsolid_one(
            lmp, FLERR,
            "pair sphsolid at step {}: atom {} has density {:.6g} kg/m^3 (must be > 0): the "
            "run went unstable ({})",
            update->ntimestep, atom->tag[i], rho[i], step_advice());
    sphsolid_one(lmp, FLERR, "pair sphsolid: rate evaluation at step {}: {} ({}; {})",
                 update->ntimestep, sph_errmsg(sim), sph_status_name(status), step_advice());
  }
}

/* ---------------------------------------------------------------------- */

int PairSPHSolid::pack_reverse_comm(int n, int first, double *buf)
{
  const size_t width = pass_size;
  const double *src = partial.data() + (size_t) first * width;
  std::copy(src, src + (size_t) n * width, buf);
  return n * pass_size;
}

void PairSPHSolid::unpack_reverse_comm(int n, int *list, double *buf)
{
  const size_t width = pass_size;
  for (int k = 0; k < n; k++) {
    double *dst = partial.data() + (size_t) list[k] * width;
    for (size_t c = 0; c < width; c++) dst[c] += buf[(size_t) k * width + c];
  }
}

/* ----------------------------------------------------------------------
   effect damage on the owned atoms: the library's calls with each atom's
   ID as its global index
------------------------------------------------------------------------- */

void PairSPHSolid::damage_inputs()
{
  const int nlocal = atom->nlocal;
  const size_t n = std::max(nlocal, 1);
  idbuf.resize(n);
  localmass.resize(n);
  localmaterial.resize(n);
  const tagint *tag = atom->tag;
  const int *type = atom->type;
  for (int i = 0; i < nlocal; i++) {
    idbuf[i] = (uint64_t) (tag[i] - 1);    // the library numbers its particles from 0
    localmass[i] = mass_of(i);
    localmaterial[i] = type_material[type[i]];
  }
}

void PairSPHSolid::draw_flaws(const unsigned char *flawed)
{
  if (!damage) return;
  damage_inputs();
  FixSPHSolidState *st = state_fix;
  const sph_status status =
      sph_damage_flaws(sim, atom->nlocal, idbuf.data(), localmass.data(), localmaterial.data(),
                       flawed, st->flaw_count, st->flaw_strain);
  if (status != SPH_OK)
    sphsolid_one(lmp, FLERR, "pair sphsolid: drawing the flaws of the damage effect: {} ({})",
                 sph_errmsg(sim), sph_status_name(status));
  // the library refuses a run without any atom that can be damaged
  int mine = 0, any = 0;
  for (int i = 0; i < atom->nlocal && !mine; i++) mine = st->flaw_count[i] > 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, world);
  if (!any)
    error->all(FLERR,
               "pair sphsolid: effect damage is on but no atom the integrator moves has a "
               "material with flaws: give its pair_coeff weibull_k [m^-3] and weibull_m > 0");
}

bool PairSPHSolid::grow_damage(double dt, bool any_rank, const unsigned char *free_atoms)
{
  if (!damage && !drucker_prager) return false;
  FixSPHSolidState *st = state_fix;
  int changed = 0, any = 0;
  const int nlocal = atom->nlocal;
  // energy account: the elastic energy each stage releases (the state
  // before it kept for the library's sph_energy_released)
  auto account_released = [&](const double *S_before, const double *D_before, int slot,
                              const char *stage) {
    const sph_status status = sph_energy_released(
        sim, nlocal, localmass.data(), localmaterial.data(), st->rho, S_before, D_before,
        st->S_data(), damage ? st->damage : nullptr, &st->account[slot]);
    if (status != SPH_OK)
      sphsolid_one(lmp, FLERR, "pair sphsolid: energy account of the {} at step {}: {} ({})", stage,
                   update->ntimestep, sph_errmsg(sim), sph_status_name(status));
  };
  if (damage) {
    damage_inputs();
    if (account) damage_before.assign(st->damage, st->damage + nlocal);
    const sph_status status = sph_damage_grow(
        sim, nlocal, dt, idbuf.data(), localmass.data(), localmaterial.data(), st->rho,
        st->S_data(), st->flaw_count, st->flaw_strain, st->damage, &changed);
    if (status != SPH_OK)
      sphsolid_one(lmp, FLERR, "pair sphsolid: damage stage at step {}: {} ({})", update->ntimestep,
                   sph_errmsg(sim), sph_status_name(status));
    if (account && changed)
      account_released(st->S_data(), damage_before.data(), FixSPHSolidState::DISSIPATED_DAMAGE,
                       "damage stage");
  }
  if (drucker_prager) {
    if (account) {
      damage_inputs();    // the masses too
      const double *S = st->S_data();
      stress_before.assign(S, S + (size_t) nlocal * stress_components());
    } else {
      localmaterial.resize((size_t) std::max(nlocal, 1));
      for (int i = 0; i < nlocal; i++) localmaterial[i] = type_material[atom->type[i]];
    }
    int returned = 0;
    const sph_status status = sph_drucker_prager_return(sim, nlocal, localmaterial.data(), st->rho,
                                                        damage ? st->damage : nullptr, free_atoms,
                                                        st->S_data(), &returned);
    if (status != SPH_OK)
      sphsolid_one(lmp, FLERR, "pair sphsolid: drucker_prager return at step {}: {} ({})",
                   update->ntimestep, sph_errmsg(sim), sph_status_name(status));
    if (account && returned)
      account_released(stress_before.data(), damage ? st->damage : nullptr,
                       FixSPHSolidState::DISSIPATED_PLASTIC, "drucker_prager return");
    changed |= returned;
  }
  if (!any_rank) return changed != 0;
  MPI_Allreduce(&changed, &any, 1, MPI_INT, MPI_MAX, world);
  return any != 0;
}

void PairSPHSolid::active_flaws(double *out)
{
  if (!damage) error->all(FLERR, "pair sphsolid: active flaws need the damage effect");
  damage_inputs();
  FixSPHSolidState *st = state_fix;
  const sph_status status =
      sph_damage_active(sim, atom->nlocal, idbuf.data(), localmass.data(), localmaterial.data(),
                        st->rho, st->S_data(), st->flaw_count, st->flaw_strain, out);
  if (status != SPH_OK)
    sphsolid_one(lmp, FLERR, "pair sphsolid: active flaws: {} ({})", sph_errmsg(sim),
                 sph_status_name(status));
}

/* ----------------------------------------------------------------------
   the energy account (energy_account yes): the library's terms on the
   owned atoms, the rank's shares kept in the state fix
------------------------------------------------------------------------- */

void PairSPHSolid::energy_sums(double out[2])
{
  damage_inputs();
  const sph_status status =
      sph_energy_sums(sim, atom->nlocal, localmass.data(), atom->v ? atom->v[0] : nullptr, 3,
                      state_fix->rho, state_fix->S_data(), damage ? state_fix->damage : nullptr,
                      localmaterial.data(), nullptr, out);
  if (status != SPH_OK)
    sphsolid_one(lmp, FLERR, "pair sphsolid: energy of the atoms at step {}: {} ({})",
                 update->ntimestep, sph_errmsg(sim), sph_status_name(status));
}

void PairSPHSolid::account_start()
{
  power_sum[0] = power_sum[1] = 0.0;
  power_evaluations = 0;
  power_last_valid = false;
  if (!account || state_fix->account_started) return;
  double mine[2] = {0.0, 0.0}, all[2];
  energy_sums(mine);
  MPI_Allreduce(mine, all, 2, MPI_DOUBLE, MPI_SUM, world);
  state_fix->account_reference = all[0] + all[1];
  state_fix->account_started = true;
}

void PairSPHSolid::account_evaluation(const double *dv_dt, const unsigned char *integrate_motion)
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  if (nrates != nlocal || cached_nall != nall || neighbor->ncalls != cached_build)
    sphsolid_one(lmp, FLERR,
                 "pair sphsolid: energy account at step {}: the last rate evaluation is not of "
                 "the current atoms",
                 update->ntimestep);
  sph_particles particles{};
  particles.n_local = nlocal;
  particles.n_total = nall;
  particles.x = atom->x ? atom->x[0] : nullptr;
  particles.v = atom->v ? atom->v[0] : nullptr;
  particles.rho = state_fix->rho;
  particles.S = state_fix->S_data();
  particles.mass = atom->rmass ? atom->rmass : massbuf.data();
  particles.material = materialbuf.data();
  particles.stride = 3;
  sph_neighbours neighbours{};
  neighbours.offsets = neighbour_offsets.data();
  neighbours.indices = neighbour_indices.data();
  // newton off: a pair with a ghost is computed on both of its ranks
  double power[2];
  const double start = cpu_seconds();
  const sph_status status = sph_energy_power(sim, &particles, &neighbours, send_back ? 0 : 1,
                                             rate_dv.data(), dv_dt, integrate_motion, power);
  part_seconds[PART_RATES] += cpu_seconds() - start;
  if (status != SPH_OK)
    sphsolid_one(lmp, FLERR, "pair sphsolid: energy account at step {}: {} ({})", update->ntimestep,
                 sph_errmsg(sim), sph_status_name(status));
  power_sum[0] += power[0];
  power_sum[1] += power[1];
  power_evaluations++;
  power_last[0] = power[0];
  power_last[1] = power[1];
  power_last_valid = true;
}

bool PairSPHSolid::account_carry()
{
  if (power_evaluations > 0) return true;    // evaluated since the last step closed
  if (!power_last_valid) return false;
  power_sum[0] += power_last[0];
  power_sum[1] += power_last[1];
  power_evaluations++;
  return true;
}

void PairSPHSolid::account_step(double dt)
{
  if (power_evaluations == 0) return;
  // the mean power of the step's evaluations (Improved Euler: the
  // trapezoid of its two), as the library integrates its own account
  state_fix->account[FixSPHSolidState::WORK] += dt * power_sum[0] / power_evaluations;
  state_fix->account[FixSPHSolidState::DISSIPATED_VISCOSITY] +=
      dt * power_sum[1] / power_evaluations;
  power_sum[0] = power_sum[1] = 0.0;
  power_evaluations = 0;
}

/* ---------------------------------------------------------------------- */

void PairSPHSolid::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  evaluate_rates(false, compute_pass);

  // f[0] + 3 i is f[i]; the pointers read once (the stores could alias them)
  const double start = cpu_seconds();
  const int nlocal = atom->nlocal;
  double *f = nlocal > 0 ? atom->f[0] : nullptr;
  const double *dv = rate_dv.data();
  const AtomMasses mass = atom_masses();
  for (int i = 0; i < nlocal; i++) {
    const double m = mass[i];
    for (int d = 0; d < dim; d++) f[3 * i + d] += m * dv[(size_t) i * dim + d];
  }
  part_seconds[PART_COPIES] += cpu_seconds() - start;
}

/* ----------------------------------------------------------------------
   end of a run: the pairs each rank computes (the work balance of the
   subdomains; LAMMPS's "Neighs" counts the pairs with ghosts on both ranks)
------------------------------------------------------------------------- */

void PairSPHSolid::finish()
{
  const bigint mine[2] = {pairs_computed, ghost_pairs};
  bigint total[2] = {0, 0}, largest = 0, least = 0;
  MPI_Allreduce(mine, total, 2, MPI_LMP_BIGINT, MPI_SUM, world);
  MPI_Allreduce(&pairs_computed, &largest, 1, MPI_LMP_BIGINT, MPI_MAX, world);
  MPI_Allreduce(&pairs_computed, &least, 1, MPI_LMP_BIGINT, MPI_MIN, world);
  if (comm->me == 0) {
    const double average = (double) total[0] / comm->nprocs;
    utils::logmesg(lmp,
                   "pair sphsolid: {} pairs computed, per rank {:.6g} ave {} max {} min "
                   "(largest / average {:.4f}); {} of them with a ghost atom ({})\n",
                   total[0], average, largest, least, average > 0.0 ? largest / average : 1.0,
                   total[1],
                   send_back ? "newton on: each such pair computed on one of its ranks, the "
                               "ghosts' sums sent back"
                             : "newton off: each such pair computed on both of its ranks");
  }
  double seconds[N_PARTS];
  MPI_Allreduce(part_seconds, seconds, N_PARTS, MPI_DOUBLE, MPI_SUM, world);
  if (comm->me == 0)
    utils::logmesg(
        lmp,
        "pair sphsolid: CPU seconds per rank (average): library rate calls {:.6g}, library "
        "integrator stages {:.6g}, ghost exchanges {:.6g}, refresh after "
        "re-neighbouring {:.6g}, the plugin's copies {:.6g}\n",
        seconds[PART_RATES] / comm->nprocs, seconds[PART_STAGES] / comm->nprocs,
        seconds[PART_EXCHANGE] / comm->nprocs, seconds[PART_REFRESH] / comm->nprocs,
        seconds[PART_COPIES] / comm->nprocs);
}

/* ---------------------------------------------------------------------- */

void *PairSPHSolid::extract(const char *name, int &dimension)
{
  if (!allocated || !name) return nullptr;
  const std::string key = name;
  double fallback = 0.0;
  bool known = key == "rho0";
  for (const auto &info : material_keys())
    if (key == info.key) known = true, fallback = info.default_value;
  if (!known) return nullptr;
  std::vector<double> &values = extracted[key];
  values.assign(type_params.size(), 0.0);
  for (size_t t = 1; t < type_params.size(); t++) {
    const SPHSolidMaterial &m = type_params[t];
    const auto given = m.keys.find(key);
    values[t] = key == "rho0" ? m.rho0 : given != m.keys.end() ? given->second : fallback;
  }
  dimension = 1;
  return values.data();
}

/* ---------------------------------------------------------------------- */

double PairSPHSolid::memory_usage()
{
  double bytes = Pair::memory_usage();
  bytes += sizeof(double) * (massbuf.capacity() + rate_dv.capacity() + rate_drho.capacity() +
                             rate_dS.capacity() + rate_dx.capacity() + partial.capacity());
  bytes += sizeof(int) *
           (materialbuf.capacity() + neighbour_counts.capacity() + neighbour_indices.capacity());
  bytes += sizeof(size_t) * neighbour_offsets.capacity();
  bytes += sizeof(uint64_t) * idbuf.capacity() + sizeof(double) * localmass.capacity() +
           sizeof(int) * localmaterial.capacity();
  bytes += sizeof(double) * (damage_before.capacity() + stress_before.capacity());
  return bytes;
}
