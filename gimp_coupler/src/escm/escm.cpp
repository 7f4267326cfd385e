// The coupled step of the ESCM coupling of the 2-D GIMP solver to an in-process LAMMPS
// instance (escm.hpp, docs/escm.md, decisions D70-D79), and the Coupler's accessors. Set-up:
// escm_setup.cpp; checkpoint and restore: escm_state.cpp; CSV and VTU: escm_output.cpp.
#include "coupler_impl.hpp"
#include "pnc/core/error.hpp"

#include <cmath>
#include <stdexcept>

namespace pnc::gimp::escm {

void Coupler::Impl::callback(md::Step step, int nlocal, const md::AtomId* ids, double** x,
                             double** fext) {
  const auto t0 = Clock::now();
  const bool count = step > block_start;
  for (int i = 0; i < nlocal; ++i) {
    const int k = cell_of_id[static_cast<std::size_t>(ids[i])];
    if (k < 0) {
      fext[i][0] = fext[i][1] = fext[i][2] = 0.0;
      continue;
    }
    fext[i][0] = fx[static_cast<std::size_t>(k)];
    fext[i][1] = fy[static_cast<std::size_t>(k)];
    fext[i][2] = 0.0;
    if (count) {
      auto& s = csum[static_cast<std::size_t>(k)];
      s[0] += x[i][0];
      s[1] += x[i][1];
    }
  }
  if (count) ++nsub;
  timing.callback += seconds(t0, Clock::now());
}

// Centroids of the IVC cells now (A), from the local arrays.
std::vector<Eigen::Vector2d> Coupler::Impl::centroids() const {
  const md::LocalAtoms a = lmp->local_atoms();
  const int nlocal = a.n;
  const auto* id = a.id;
  auto** x = a.x;
  std::vector<Eigen::Vector2d> c(ivc_cells.size(), Eigen::Vector2d::Zero());
  for (int i = 0; i < nlocal; ++i) {
    const int k = cell_of_id[static_cast<std::size_t>(id[i])];
    if (k >= 0) c[static_cast<std::size_t>(k)] += Eigen::Vector2d(x[i][0], x[i][1]);
  }
  for (std::size_t k = 0; k < c.size(); ++k)
    c[k] /= static_cast<double>(cells[static_cast<std::size_t>(ivc_cells[k])].atoms.size());
  return c;
}

// Both exist from set-up on (md_groups_and_fixes, langevin_fixes); md/ throws naming the
// compute or fix otherwise.
double Coupler::Impl::compute_scalar(const char* id) const {
  return lmp->compute_value(id);
}

double Coupler::Impl::fix_scalar(const char* id) const {
  return lmp->fix_scalar(id);
}

void Coupler::Impl::step() {
  if (!ready) throw std::runtime_error("escm: step() before setup()");
  const auto t0 = Clock::now();
  auto& g = solver.grid;
  auto& P = solver.particles;
  const double dt = cfg.dt;
  const double Lz_m = Lz_A * units::m_per_A;
  // 1. Gamma nodes (fixed, D71) get the velocity of the IVC cells touching them.
  std::vector<Eigen::Vector2d> vg(gamma.size(), Eigen::Vector2d::Zero());
  for (std::size_t i = 0; i < gamma.size(); ++i) {
    for (const auto& [k, w] : gamma_cells[i])
      vg[i] +=
          w * cells[static_cast<std::size_t>(ivc_cells[static_cast<std::size_t>(k)])].velocity_mps;
  }
  solver.prescribed_nodes = gamma;
  solver.prescribed_velocity = vg;
  const double w_before = solver.prescribed_work;
  const auto t1 = Clock::now();
  solver.step(dt);
  const auto t2 = Clock::now();
  const double w_md_on_cont = (solver.prescribed_work - w_before) * Lz_m;
  // IVC material points: positions from the MD averages (D73), velocity of the cell.
  for (int k : ivc_cells) {
    const auto& c = cells[static_cast<std::size_t>(k)];
    P.x[c.particle] = P.x0[c.particle] + units::m_per_A * (c.mean_A - c.c0_A);
    P.v[c.particle] = c.velocity_mps;
  }
  if (cfg.continuum_damping > 0) { // D75
    const double f = std::exp(-cfg.continuum_damping * dt);
    double ke = 0.0;
    for (std::size_t p = 0; p < P.size(); ++p) {
      ke += 0.5 * P.m[p] * P.v[p].squaredNorm();
      P.v[p] *= f;
    }
    acc.heat_removed_cont += (1.0 - f * f) * ke * Lz_m;
    solver.update_energies();
  }
  // Forces on the IVC cells (D71).
  for (int k : ivc_cells)
    cells[static_cast<std::size_t>(k)].force_N.setZero();
  if (cfg.mode == Mode::neumann)
    for (std::size_t i = 0; i < gamma.size(); ++i)
      for (const auto& [k, w] : gamma_cells[i])
        cells[static_cast<std::size_t>(ivc_cells[static_cast<std::size_t>(k)])].force_N -=
            w * solver.prescribed_reaction[i];
  for (std::size_t k = 0; k < ivc_cells.size(); ++k) {
    auto& c = cells[static_cast<std::size_t>(ivc_cells[k])];
    c.atom_force = c.force_N * Lz_m / units::N_per_kcalmolA / static_cast<double>(c.atoms.size());
    fx[k] = c.atom_force[0];
    fy[k] = c.atom_force[1];
    csum[k].setZero();
  }
  // SVC atoms: velocity v* of the grid at the atom (D72), z velocity 0.
  const auto& vs = solver.grid_velocity_star();
  {
    const md::LocalAtoms la = lmp->local_atoms();
    const int nlocal = la.n;
    const auto* id = la.id;
    auto** x = la.x;
    auto** v = la.v;
    for (int i = 0; i < nlocal; ++i) {
      if (zone_of_id[static_cast<std::size_t>(id[i])] != Zone::svc) continue;
      const Eigen::Vector2d xc = cfg.md_offset + units::m_per_A * Eigen::Vector2d(x[i][0], x[i][1]);
      const double sx = (xc[0] - g.origin[0]) / g.h, sy = (xc[1] - g.origin[1]) / g.h;
      const int i0 = static_cast<int>(std::floor(sx)), j0 = static_cast<int>(std::floor(sy));
      if (i0 < 0 || j0 < 0 || i0 + 1 >= g.n[0] || j0 + 1 >= g.n[1])
        pnc::fail_simulation("escm: SVC atom " + std::to_string(id[i]), -1,
                             std::numeric_limits<double>::quiet_NaN(), "",
                             "it left the continuum grid (enlarge the grid or the MD region's "
                             "margin)");
      const double fxi = sx - i0, fyj = sy - j0;
      Eigen::Vector2d vel = Eigen::Vector2d::Zero();
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          const double w = (a ? fxi : 1 - fxi) * (b ? fyj : 1 - fyj);
          vel += w * vs[static_cast<std::size_t>(g.index({i0 + a, j0 + b}))];
        }
      v[i][0] = vel[0] / units::mps_per_Afs;
      v[i][1] = vel[1] / units::mps_per_Afs;
      v[i][2] = 0.0;
    }
  }
  const std::vector<Eigen::Vector2d> cstart = centroids();
  // 2. MD block.
  nsub = 0;
  block_start = static_cast<long>(lmp->thermo("step"));
  const auto t3 = Clock::now();
  const double cb0 = timing.callback;
  cmd("run " + std::to_string(cfg.substeps) + " pre no post no");
  const auto t4 = Clock::now();
  if (nsub != cfg.substeps)
    throw std::runtime_error("escm: fix external callback ran " + std::to_string(nsub) +
                             " times in a block of " + std::to_string(cfg.substeps));
  const std::vector<Eigen::Vector2d> cend = centroids();
  // 3. IVC averages (D73) and the work of the IVC forces.
  double w_cont_on_md = 0.0;
  for (std::size_t k = 0; k < ivc_cells.size(); ++k) {
    auto& c = cells[static_cast<std::size_t>(ivc_cells[k])];
    const double na = static_cast<double>(c.atoms.size());
    w_cont_on_md += na * c.atom_force.dot(cend[k] - cstart[k]);
    c.prev_mean_A = c.mean_A;
    c.mean_A = csum[k] / (na * cfg.substeps);
    c.velocity_mps = units::m_per_A * (c.mean_A - c.prev_mean_A) / dt;
  }
  // Energies.
  EnergyRow r = acc;
  r.step = solver.steps;
  r.time_s = solver.time;
  r.cont_kinetic = solver.energy.kinetic * Lz_m;
  r.cont_strain = solver.energy.strain * Lz_m;
  r.md_kinetic = compute_scalar("escm_ke") * units::J_per_kcalmol;
  r.md_potential = (compute_scalar("escm_pe") - pe0) * units::J_per_kcalmol;
  r.work_boundary = (solver.energy.boundary_work + solver.energy.external_work) * Lz_m;
  r.work_cont_on_md = acc.work_cont_on_md + w_cont_on_md * units::J_per_kcalmol;
  r.work_md_on_cont = acc.work_md_on_cont + w_md_on_cont;
  r.heat_removed_int = counts[0] > 0 && cfg.interior_damp_fs > 0
                           ? heat_off_int + fix_scalar("escm_lint") * units::J_per_kcalmol
                           : 0.0;
  r.heat_removed_ivc = heat_off_ivc + fix_scalar("escm_livc") * units::J_per_kcalmol;
  acc = r;
  log.push_back(r);
  const auto t5 = Clock::now();
  const double cb = timing.callback - cb0;
  timing.continuum += seconds(t1, t2);
  timing.lammps += seconds(t3, t4) - cb;
  timing.coupling += seconds(t0, t1) + seconds(t2, t3) + seconds(t4, t5);
}

Coupler::Coupler(Solver<2>& solver, Config cfg)
    : d_(std::make_unique<Impl>(solver, std::move(cfg))) {}
Coupler::~Coupler() {
  d_->lmp.reset(); // closes LAMMPS before the state its callback uses
}
void Coupler::setup() {
  d_->setup();
}
void Coupler::step() {
  d_->step();
}
CouplerState Coupler::checkpoint() {
  return d_->checkpoint();
}
void Coupler::restore(const CouplerState& st) {
  d_->restore(st);
}
const std::vector<Cell>& Coupler::cells() const {
  return d_->cells;
}
const Config& Coupler::config() const {
  return d_->cfg;
}
double Coupler::slab_thickness_A() const {
  return d_->Lz_A;
}
double Coupler::md_timestep_fs() const {
  return d_->dtau_fs;
}
const std::vector<EnergyRow>& Coupler::energy_log() const {
  return d_->log;
}
const Timing& Coupler::timing() const {
  return d_->timing;
}
std::array<int, 3> Coupler::zone_counts() const {
  return d_->counts;
}
Zone Coupler::zone_of(int id) const {
  if (id < 1 || id > d_->natoms) return Zone::none;
  return d_->zone_of_id[static_cast<std::size_t>(id)];
}
void* Coupler::lammps() const {
  return d_->lmp ? d_->lmp->handle() : nullptr;
}
const std::vector<Eigen::Vector3d>& Coupler::atoms_initial() const {
  return d_->x_init;
}
Eigen::Vector2d Coupler::to_continuum(const Eigen::Vector3d& xA) const {
  return d_->cfg.md_offset + units::m_per_A * xA.head<2>();
}

void Coupler::atoms(std::vector<int>& ids, std::vector<Eigen::Vector3d>& x,
                    std::vector<Eigen::Vector3d>& v) const {
  const int n = d_->natoms;
  const std::vector<double> xs = d_->lmp->gather("x", 3), vs = d_->lmp->gather("v", 3);
  ids.resize(static_cast<std::size_t>(n));
  x.resize(ids.size());
  v.resize(ids.size());
  for (int i = 0; i < n; ++i) {
    ids[static_cast<std::size_t>(i)] = i + 1;
    x[static_cast<std::size_t>(i)] = Eigen::Vector3d(xs[3 * i], xs[3 * i + 1], xs[3 * i + 2]);
    v[static_cast<std::size_t>(i)] = Eigen::Vector3d(vs[3 * i], vs[3 * i + 1], vs[3 * i + 2]);
  }
}

} // namespace pnc::gimp::escm
