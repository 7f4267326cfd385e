// Set-up of the ESCM coupler (escm.hpp Coupler::setup; D70-D72): validation, LAMMPS, the
// volume cells and their zones, the INT particles removed and the IVC probes, the Gamma nodes,
// the LAMMPS groups, fixes and computes.
#include "coupler_impl.hpp"
#include "pnc/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pnc::gimp::escm {

namespace {

/// Zero-stress material of the IVC material points (D70): they carry position and (a tiny)
/// mass only; the stiffness of the IVC region is the atoms'.
class Probe final : public Material {
public:
  explicit Probe(double rho) : Material(rho) {}
  std::string type() const override { return "escm_probe"; }
  void update(const Mat3&, const Mat3&, const double*, double*, Mat3& sigma,
              double& W) const override {
    sigma.setZero();
    W = 0.0;
  }
  double wave_speed() const override { return 0.0; }
  double youngs_modulus() const override { return std::nan(""); }
  double poisson_ratio() const override { return std::nan(""); }
};

} // namespace

void bad_config(const std::string& field, const std::string& value, const std::string& rule) {
  // InputError, exit code 1: "escm::Config: field 'F': value 'V': RULE"
  pnc::fail("escm::Config", field, value, rule);
}

void Coupler::Impl::validate() {
  const auto& c = cfg;
  if (c.md_setup.empty())
    bad_config("md_setup", "[]", "LAMMPS commands creating the MD region are required");
  for (const auto& s : c.md_setup) {
    std::istringstream is(s);
    std::string w;
    is >> w;
    for (const char* forbidden : {"run", "minimize", "fix", "timestep", "clear", "quit", "shell",
                                  "include", "jump", "label", "next", "rerun", "write_restart"})
      if (w == forbidden)
        bad_config("md_setup", s,
                   "only commands that build the box, atoms and force field are allowed");
  }
  if (c.svc_rings < 1) bad_config("svc_rings", std::to_string(c.svc_rings), "must be >= 1");
  if (c.ivc_rings < 1) bad_config("ivc_rings", std::to_string(c.ivc_rings), "must be >= 1");
  if (c.substeps < 1) bad_config("substeps", std::to_string(c.substeps), "must be >= 1");
  if (!(c.dt > 0) || !std::isfinite(c.dt))
    bad_config("dt", std::to_string(c.dt), "must be > 0 (s)");
  if (!(c.interior_temperature >= 0) || !std::isfinite(c.interior_temperature))
    bad_config("interior_temperature", std::to_string(c.interior_temperature), "must be >= 0 (K)");
  if (!(c.ivc_damp_fs > 0) || !std::isfinite(c.ivc_damp_fs))
    bad_config("ivc_damp_fs", std::to_string(c.ivc_damp_fs), "must be > 0 (fs)");
  if (!std::isfinite(c.interior_damp_fs))
    bad_config("interior_damp_fs", std::to_string(c.interior_damp_fs), "must be finite");
  if (c.seed <= 0 || c.seed > 800000000)
    bad_config("seed", std::to_string(c.seed), "must be in [1, 8e8] (LAMMPS random seeds)");
  if (!(c.continuum_damping >= 0))
    bad_config("continuum_damping", std::to_string(c.continuum_damping), "must be >= 0 (1/s)");
  if (!(c.probe_mass_fraction > 0 && c.probe_mass_fraction <= 1))
    bad_config("probe_mass_fraction", std::to_string(c.probe_mass_fraction), "must be in (0, 1]");
  if (c.lammps_log.find_first_of(" \t\n'\"") != std::string::npos)
    bad_config("lammps_log", c.lammps_log, "must not contain blanks or quotes");
  dtau_fs = c.dt / c.substeps / units::s_per_fs;
  if (!(dtau_fs > 1e-6 && dtau_fs < 100))
    bad_config("dt", std::to_string(c.dt), "dt / substeps must be an MD step in (1e-6, 100) fs");
  const auto& g = solver.grid;
  for (std::size_t p = 0; p < solver.particles.size(); ++p)
    if (std::abs(solver.particles.l[p][0] - 0.5 * g.h) > 1e-9 * g.h ||
        std::abs(solver.particles.l[p][1] - 0.5 * g.h) > 1e-9 * g.h)
      bad_config("particles", std::to_string(p),
                 "ESCM needs one particle per cell, half-length h/2 (D70)");
}

void Coupler::Impl::setup() {
  validate();
  const auto cellmap = particle_cells();
  const auto atoms_of_cell = start_lammps();
  remove_interior(build_cells(cellmap, atoms_of_cell));
  solver.initialize();
  gamma_nodes();
  csum.assign(ivc_cells.size(), Eigen::Vector2d::Zero());
  fx.assign(ivc_cells.size(), 0.0);
  fy.assign(ivc_cells.size(), 0.0);
  md_groups_and_fixes();
  block_start = 0;
  cmd("run 0");
  pe0 = compute_scalar("escm_pe");
  acc = EnergyRow{};
  solver.update_energies();
  const double Lz_m = Lz_A * units::m_per_A;
  acc.initial = (solver.energy.kinetic + solver.energy.strain) * Lz_m +
                compute_scalar("escm_ke") * units::J_per_kcalmol;
  ready = true;
}

std::pair<int, int> Coupler::Impl::cell_of(const Eigen::Vector2d& x) const {
  const auto& g = solver.grid;
  return std::pair<int, int>{static_cast<int>(std::floor((x[0] - g.origin[0]) / g.h)),
                             static_cast<int>(std::floor((x[1] - g.origin[1]) / g.h))};
}

// Particle of each grid cell.
std::map<std::pair<int, int>, std::size_t> Coupler::Impl::particle_cells() const {
  const auto& P = solver.particles;
  std::map<std::pair<int, int>, std::size_t> cellmap;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const auto ij = cell_of(P.x[p]);
    if (!cellmap.emplace(ij, p).second)
      bad_config("particles", std::to_string(p), "two particles in one grid cell (D70)");
  }
  return cellmap;
}

// LAMMPS with md_setup, its checks, the initial atom positions; the atoms of each grid cell.
std::map<std::pair<int, int>, std::vector<int>> Coupler::Impl::start_lammps() {
  lmp = md::Lammps::open_in_process({"escm", "-screen", "none", "-log", cfg.lammps_log, "-nocite"},
                                    "starting the ESCM MD region");
  for (const auto& c : cfg.md_setup)
    cmd(c);
  // Checks of what md_setup built (before any command of ours that depends on it).
  if (lmp->extract_global_string("units") != "real")
    bad_config("md_setup", "units", "the MD region must use `units real`");
  if (lmp->extract_setting("dimension") != 3) bad_config("md_setup", "dimension", "must be 3");
  const md::LmpBox box = lmp->box();
  const auto per = lmp->periodic();
  if (per[0] || per[1] || !per[2])
    bad_config("md_setup", "boundary", "x and y must be non-periodic, z periodic (the slab)");
  if (box.xy != 0 || box.xz != 0 || box.yz != 0)
    bad_config("md_setup", "box", "must be orthogonal");
  Lz_A = box.hi[2] - box.lo[2];
  natoms = static_cast<int>(lmp->natoms());
  if (natoms <= 0) bad_config("md_setup", "atoms", "no atoms");
  const std::vector<md::AtomId> ids = lmp->gather_ids();
  const std::vector<double> xs = lmp->gather("x", 3);
  // gather_atoms orders by id: requires ids 1..natoms.
  for (int i = 0; i < natoms; ++i)
    if (ids[static_cast<std::size_t>(i)] != i + 1)
      bad_config("md_setup", "atom ids", "must be 1..n without gaps (reset_atom_ids)");
  x_init.resize(static_cast<std::size_t>(natoms));
  std::map<std::pair<int, int>, std::vector<int>> atoms_of_cell;
  for (int i = 0; i < natoms; ++i) {
    const Eigen::Vector3d xa(xs[3 * i], xs[3 * i + 1], xs[3 * i + 2]);
    x_init[static_cast<std::size_t>(i)] = xa;
    const Eigen::Vector2d xc = cfg.md_offset + units::m_per_A * xa.head<2>();
    atoms_of_cell[cell_of(xc)].push_back(i + 1);
  }
  return atoms_of_cell;
}

// Cells of the block: zone by ring; every cell needs a particle and atoms. Returns the flags of
// the particles to remove (INT).
std::vector<char>
Coupler::Impl::build_cells(const std::map<std::pair<int, int>, std::size_t>& cellmap,
                           const std::map<std::pair<int, int>, std::vector<int>>& atoms_of_cell) {
  const auto& P = solver.particles;
  int imin = 1 << 30, imax = -(1 << 30), jmin = imin, jmax = imax;
  for (const auto& [ij, v] : atoms_of_cell) {
    imin = std::min(imin, ij.first);
    imax = std::max(imax, ij.first);
    jmin = std::min(jmin, ij.second);
    jmax = std::max(jmax, ij.second);
  }
  const int rings = cfg.svc_rings + cfg.ivc_rings;
  if (imax - imin + 1 < 2 * rings + 1 || jmax - jmin + 1 < 2 * rings + 1)
    bad_config("md_setup", "atom block", "narrower than 2 (svc_rings + ivc_rings) + 1 cells");
  cell_of_id.assign(static_cast<std::size_t>(natoms) + 1, -1);
  zone_of_id.assign(static_cast<std::size_t>(natoms) + 1, Zone::none);
  std::vector<char> remove(P.size(), 0);
  cells.clear();
  for (int j = jmin; j <= jmax; ++j)
    for (int i = imin; i <= imax; ++i) {
      const int ring = std::min({i - imin, imax - i, j - jmin, jmax - j});
      const Zone z = ring < cfg.svc_rings ? Zone::svc : ring < rings ? Zone::ivc : Zone::interior;
      const auto it = cellmap.find({i, j});
      if (it == cellmap.end())
        bad_config("particles", "cell (" + std::to_string(i) + ", " + std::to_string(j) + ")",
                   "the atom block needs a continuum particle in each of its cells (D70)");
      const auto at = atoms_of_cell.find({i, j});
      if (z != Zone::interior && (at == atoms_of_cell.end() || at->second.empty()))
        bad_config("md_setup", "cell (" + std::to_string(i) + ", " + std::to_string(j) + ")",
                   "every volume cell needs atoms");
      const std::vector<int> none;
      const auto& ats = at == atoms_of_cell.end() ? none : at->second;
      for (int id : ats)
        zone_of_id[static_cast<std::size_t>(id)] = z;
      counts[static_cast<int>(z)] += static_cast<int>(ats.size());
      if (z == Zone::interior) {
        remove[it->second] = 1;
        continue;
      }
      Cell c;
      c.zone = z;
      c.particle = it->second; // re-indexed below
      c.ij = {i, j};
      c.atoms = ats;
      Eigen::Vector2d s = Eigen::Vector2d::Zero();
      for (int id : ats)
        s += x_init[static_cast<std::size_t>(id - 1)].head<2>();
      c.c0_A = s / static_cast<double>(ats.size());
      c.mean_A = c.prev_mean_A = c.c0_A;
      c.force_N.setZero();
      c.atom_force.setZero();
      c.velocity_mps.setZero();
      cells.push_back(c);
    }
  return remove;
}

// Atoms outside the block's cells cannot exist (the block is their bounding box).
// Remove INT particles, re-index, turn IVC particles into probes.
void Coupler::Impl::remove_interior(const std::vector<char>& remove) {
  auto& P = solver.particles;
  std::vector<std::size_t> newidx(P.size(), static_cast<std::size_t>(-1));
  Particles<2> Q;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (remove[p]) continue;
    newidx[p] = Q.size();
    Q.add(P.x[p], P.l[p], P.m[p], P.V0[p], P.mat[p], P.v[p]);
    Q.x0.back() = P.x0[p];
    Q.F.back() = P.F[p];
  }
  for (auto& tr : solver.tractions) {
    std::vector<std::size_t> keep;
    for (auto p : tr.particles)
      if (!remove[p]) keep.push_back(newidx[p]);
    tr.particles = keep;
  }
  double rho_max = 0;
  for (const auto& m : solver.materials)
    rho_max = std::max(rho_max, m->density());
  const int probe = static_cast<int>(solver.materials.size());
  solver.materials.push_back(std::make_shared<Probe>(rho_max * cfg.probe_mass_fraction));
  for (std::size_t k = 0; k < cells.size(); ++k) {
    auto& c = cells[k];
    c.particle = newidx[c.particle];
    if (c.zone == Zone::ivc) {
      const int slot = static_cast<int>(ivc_cells.size());
      ivc_cells.push_back(static_cast<int>(k));
      Q.m[c.particle] *= cfg.probe_mass_fraction;
      Q.mat[c.particle] = probe;
      for (int id : c.atoms)
        cell_of_id[static_cast<std::size_t>(id)] = slot;
    }
  }
  P = std::move(Q);
}

// Gamma (D71): the corner nodes of the IVC cells, fixed at setup; weight of cell p at node
// i = 1 / (number of IVC cells sharing i) (the reference weights S_ip = 1/4 of a particle
// at its cell centre, normalised over the IVC cells: a partition of unity).
void Coupler::Impl::gamma_nodes() {
  const auto& g = solver.grid;
  std::map<std::int64_t, std::size_t> gidx;
  gamma.clear();
  gamma_cells.clear();
  for (std::size_t k = 0; k < ivc_cells.size(); ++k) {
    const auto& c = cells[static_cast<std::size_t>(ivc_cells[k])];
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        const std::int64_t node = g.index({c.ij[0] + a, c.ij[1] + b});
        auto [it, fresh] = gidx.emplace(node, gamma.size());
        if (fresh) {
          gamma.push_back(node);
          gamma_cells.emplace_back();
        }
        gamma_cells[it->second].emplace_back(static_cast<int>(k), 1.0);
      }
  }
  for (auto& gc : gamma_cells)
    for (auto& kw : gc)
      kw.second = 1.0 / static_cast<double>(gc.size());
}

// Groups, fixes, computes.
void Coupler::Impl::md_groups_and_fixes() {
  auto group = [&](const std::string& name, Zone z) {
    std::ostringstream s;
    int n = 0;
    for (int id = 1; id <= natoms; ++id) {
      if (zone_of_id[static_cast<std::size_t>(id)] != z) continue;
      if (n % 400 == 0) {
        if (n) cmd(s.str());
        s.str("");
        s << "group " << name << " id";
      }
      s << ' ' << id;
      ++n;
    }
    if (n)
      cmd(s.str());
    else
      cmd("group " + name + " empty");
  };
  group("escm_svc", Zone::svc);
  group("escm_ivc", Zone::ivc);
  group("escm_int", Zone::interior);
  cmd("group escm_free union escm_ivc escm_int");
  if (cfg.mode == Mode::neumann) // D71
    cmd("neigh_modify exclude group escm_svc escm_svc");
  if (cfg.mode == Mode::neumann) cmd("neigh_modify exclude group escm_svc escm_free");
  std::ostringstream s;
  s.precision(17);
  s << "timestep " << dtau_fs;
  cmd(s.str());
  cmd("compute escm_ke escm_free ke");
  cmd("compute escm_pea escm_free pe/atom");
  cmd("compute escm_pe escm_free reduce sum c_escm_pea");
  cmd("fix escm_nve escm_free nve");
  // Checkpoints need a fixed local atom order (a spatial sort at a restart's set-up would
  // order the atoms differently from the run that wrote it).
  cmd("atom_modify sort 0 0.0");
  segment = 0;
  heat_off_int = heat_off_ivc = 0.0;
  langevin_fixes();
  cmd("fix escm_ext all external pf/callback 1 1");
  lmp->set_external_force("escm_ext",
                          [this](md::Step step, int n, const md::AtomId* ids, double** x,
                                 double** f) { callback(step, n, ids, x, f); });
  cmd("fix escm_svcnve escm_svc nve");
  cmd("fix escm_svcsf escm_svc setforce 0.0 0.0 0.0");
  cmd("thermo_style custom step c_escm_ke c_escm_pe");
  cmd("thermo_modify norm no");
  cmd("thermo " + std::to_string(cfg.substeps));
}

// The Langevin fixes of INT and IVC; re-created at each checkpoint (same IDs, same place in
// the fix list) with the seeds of the segment, so that a resumed run draws the same numbers.
void Coupler::Impl::langevin_fixes() {
  auto seed = [&](int offset) {
    const long long k = static_cast<long long>(cfg.seed) - 1 + offset + 7919LL * 2 * segment;
    return 1 + k % 899999999LL; // RanMars: 0 < seed <= 9e8
  };
  std::ostringstream s;
  s.precision(17);
  if (cfg.interior_damp_fs > 0 && counts[0] > 0) {
    s << "fix escm_lint escm_int langevin " << cfg.interior_temperature << ' '
      << cfg.interior_temperature << ' ' << cfg.interior_damp_fs << ' ' << seed(0) << " tally yes";
    cmd(s.str());
  }
  s.str("");
  s << "fix escm_livc escm_ivc langevin 0.0 0.0 " << cfg.ivc_damp_fs << ' ' << seed(1)
    << " tally yes";
  cmd(s.str());
}

} // namespace pnc::gimp::escm
