// ESCM coupling (escm.hpp), validations (a) and (b) of docs/escm.md: the LJ-crystal tension
// test against the all-continuum model and the wave crossing the handshakes. Units: continuum
// SI, MD LAMMPS real.
#include "escm_specimen.hpp"
#include "pnc/gimp_coupler/escm.hpp"
#include "pnc/gimp_coupler/escm_lj.hpp"

#include "pnc/core/csv.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

using namespace pnc::gimp;
using namespace pnc::gimp::escm;
using namespace escm_test;

namespace {

/// Tension specimen: 20 x 14 cells, atom block 10 x 10 cells with two SVC rings (10.6 A, more
/// than the 8.5 A cutoff, so IVC atoms have a full neighbour shell: D72), one IVC ring, INT
/// 4 x 4 cells; 1200 atoms.
Spec tension_spec() {
  Spec sp;
  sp.ncx = 20;
  sp.ncy = 14;
  sp.bx0 = 5;
  sp.by0 = 2;
  sp.bnx = 10;
  sp.bny = 10;
  sp.svc_rings = 2;
  return sp;
}

struct TensionResult {
  double u_right = 0;                   // time-mean x displacement of the right column, m
  double reaction = 0;                  // time-mean reaction of the left edge, N per m
  std::vector<Eigen::Vector2d> u_cells; // time-mean displacement per block cell, m
  EnergyRow energy;
  double outside_share = 0;
};

/// Tension of the specimen by a traction on its right column, ramped over t_load after a
/// zero-load settling phase (coupled only), then held; left edge x-fixed, corner y-fixed, no
/// continuum damping. Returned displacements are time means over the hold window (two
/// periods of the fundamental mode), measured from the end of the settling phase, so that
/// they are the static response (D77). coupled = false: the all-continuum reference.
TensionResult tension(bool coupled, double strain, Mode mode) {
  const LjFcc lj = lj_fcc(kEps, kSig, kRc, kMass);
  const Spec sp = tension_spec();
  const double h = h_of(lj);
  Solver<2> s;
  build_continuum(s, sp, lj);
  NodeBC<2> left, corner, rbc;
  left.lo = Eigen::Vector2d(-0.1 * h, -10 * h);
  left.hi = Eigen::Vector2d(0.1 * h, 100 * h);
  left.mask = {true, false};
  corner.lo = Eigen::Vector2d(-0.1 * h, -0.1 * h);
  corner.hi = Eigen::Vector2d(0.1 * h, 0.1 * h);
  corner.mask = {false, true};
  // The right edge and the padding node column beyond it: a particle that moves right
  // touches that column with a vanishing weight; left free, its tiny nodal mass makes the
  // edge unstable (D77).
  rbc.lo = Eigen::Vector2d((sp.ncx - 0.1) * h, -10 * h);
  rbc.hi = Eigen::Vector2d((sp.ncx + 1.1) * h, 100 * h);
  rbc.mask = {true, false};
  s.bcs = {left, corner, rbc};
  const int N = 20;
  const double dtau = 4e-15, dt = N * dtau;
  const double t_settle = coupled ? 10e-12 : 0.0, t_load = 20e-12;
  // Mass-proportional damping of both models at 0.7 of critical for the fundamental mode of
  // the fixed-fixed strip (omega_1 = pi c_bar / L): continuum particle velocities and, in the
  // MD, Langevin drag with damp = 1 / c (the same m v / tau force law, D75). Every mode decays
  // at least at 0.7 omega_1 (3.9 ps); the hold lasts 30 ps and is averaged over its last 10 ps.
  const double L = sp.ncx * h;
  const double omega1 = M_PI * std::sqrt(lj.strip_modulus() / lj.density) / L;
  const double damping = 2 * 0.7 * omega1;
  const double t_hold = 30e-12, t_avg = 10e-12;
  const double u_target = strain * L;
  Config cfg = md_config(sp, lj);
  cfg.svc_rings = sp.svc_rings;
  cfg.substeps = N;
  cfg.dt = dt;
  cfg.interior_damp_fs = 1.0 / damping / units::s_per_fs;
  cfg.ivc_damp_fs = cfg.interior_damp_fs;
  cfg.continuum_damping = damping;
  cfg.mode = mode;
  std::unique_ptr<Coupler> cp;
  std::vector<std::size_t> right; // right-column particles (indices change in setup)
  if (coupled) {
    cp = std::make_unique<Coupler>(s, cfg);
    cp->setup();
  } else {
    s.initialize();
  }
  for (std::size_t p = 0; p < s.particles.size(); ++p)
    if (s.particles.x0[p][0] > (sp.ncx - 1) * h) right.push_back(p);
  auto cell_positions = [&](std::vector<Eigen::Vector2d>& out) {
    out.clear();
    if (!coupled) {
      for (int j = sp.by0; j < sp.by0 + sp.bny; ++j)
        for (int i = sp.bx0; i < sp.bx0 + sp.bnx; ++i)
          out.push_back(s.particles.x[static_cast<std::size_t>(j * sp.ncx + i)]);
      return;
    }
    std::vector<int> ids;
    std::vector<Eigen::Vector3d> x, v;
    cp->atoms(ids, x, v);
    const auto& x0 = cp->atoms_initial();
    std::map<std::pair<int, int>, std::pair<Eigen::Vector2d, int>> acc;
    for (int j = sp.by0; j < sp.by0 + sp.bny; ++j)
      for (int i = sp.bx0; i < sp.bx0 + sp.bnx; ++i)
        acc[{i, j}] = {Eigen::Vector2d::Zero(), 0};
    for (std::size_t k = 0; k < x.size(); ++k) {
      const Eigen::Vector2d xc = cp->to_continuum(x0[k]);
      auto& a =
          acc[{static_cast<int>(std::floor(xc[0] / h)), static_cast<int>(std::floor(xc[1] / h))}];
      a.first += cp->to_continuum(x[k]);
      a.second += 1;
    }
    for (int j = sp.by0; j < sp.by0 + sp.bny; ++j)
      for (int i = sp.bx0; i < sp.bx0 + sp.bnx; ++i) {
        const auto& a = acc[{i, j}];
        out.push_back(a.first / a.second);
      }
  };
  auto right_mean = [&] {
    double u = 0;
    for (auto p : right)
      u += s.particles.x[p][0] - s.particles.x0[p][0];
    return u / static_cast<double>(right.size());
  };
  auto one = [&] {
    const double tl = s.time + 0.5 * dt - t_settle;
    s.bcs[2].velocity[0] =
        (tl > 0 && tl < t_load) ? u_target / t_load * (1 - std::cos(2 * M_PI * tl / t_load)) : 0.0;
    if (coupled) {
      cp->step();
    } else {
      s.step(dt);
      const double f = std::exp(-damping * dt);
      for (auto& v : s.particles.v)
        v *= f;
    }
  };
  while (s.time < t_settle - 0.5 * dt)
    one();
  std::vector<Eigen::Vector2d> base, now, sum;
  cell_positions(base);
  const double u0 = right_mean();
  while (s.time < t_settle + t_load - 0.5 * dt)
    one();
  TensionResult r;
  int n = 0;
  sum.assign(base.size(), Eigen::Vector2d::Zero());
  while (s.time < t_settle + t_load + t_hold - 0.5 * dt) {
    one();
    if (s.steps % 5 || s.time < t_settle + t_load + t_hold - t_avg) continue;
    cell_positions(now);
    for (std::size_t k = 0; k < now.size(); ++k)
      sum[k] += now[k] - base[k];
    r.u_right += right_mean() - u0;
    r.reaction += s.bcs[0].reaction[0];
    ++n;
  }
  r.u_right /= n;
  r.reaction /= n;
  for (auto& v : sum)
    r.u_cells.push_back(v / n);
  if (coupled) {
    // Outputs: the energy CSV reads back with the strict core reader, one row per step.
    const std::string dir = ::testing::TempDir();
    cp->write_energy_csv(dir + "escm_energy.csv");
    cp->write_atoms_vtu(dir + "escm_atoms.vtu");
    const pnc::CsvTable tab = pnc::read_csv(dir + "escm_energy.csv");
    EXPECT_EQ(tab.rows.size(), static_cast<std::size_t>(s.steps));
    EXPECT_EQ(tab.header.size(), 13u);
    r.energy = cp->energy_log().back();
    r.outside_share = cp->timing().outside_share();
    const auto& e = r.energy;
    std::printf("energy [J]: cont KE %.3e SE %.3e | MD KE %.3e PE %.3e | W_bc %.3e W_c->md %.3e "
                "W_md->c %.3e | heat int %.3e ivc %.3e | balance %.3e\n",
                e.cont_kinetic, e.cont_strain, e.md_kinetic, e.md_potential, e.work_boundary,
                e.work_cont_on_md, e.work_md_on_cont, e.heat_removed_int, e.heat_removed_ivc,
                e.balance());
    const auto& t = cp->timing();
    std::printf("timing [s]: lammps %.3f callback %.3f continuum %.3f coupling %.3f\n", t.lammps,
                t.callback, t.continuum, t.coupling);
  }
  return r;
}

} // namespace

// Validation (a): LJ FCC crystal MD region (1200 atoms), continuum calibrated to its C11, C12
// (D76); neumann mode (the dissertation's algorithm). Quasi-static tension to 0.2 % strain.
// Checks:
//  - the all-continuum reference against the analytic strip, F = (C11 - C12^2/C11) eps H:
//    5 % (the finite strain of the SVK law, ~0.3 %, and the residual of the damped
//    oscillation in the averaging window, measured ~1-3 %);
//  - overall stiffness (left-edge reaction) of the coupled model against the reference: 6 %
//    (measured 4.5 %, softer: the LJ crystal's anharmonicity, C111 ~ -10 C11, gives ~2 % in
//    the MD region at 0.2 % strain; the rest is the compliance of the handshake itself, the
//    free MD surface at the IVC and the lagged IVC averages, plus the reference's own 1 %);
//  - displacement continuity: the cell-mean displacement of every cell of the atom block (SVC,
//    IVC, INT atoms) against the reference continuum's particle in the same cell, max error
//    < 15 % of strain x block width (the MD free surface and lattice-scale relaxation at the
//    IVC, and the lag of 1.5 continuum steps of the IVC averages; measured 11 %).
TEST(Escm, LjCrystalTensionMatchesContinuum) {
  const double strain = 2e-3;
  const TensionResult ref = tension(false, strain, Mode::neumann);
  const TensionResult cpl = tension(true, strain, Mode::neumann);
  const LjFcc lj = lj_fcc(kEps, kSig, kRc, kMass);
  const Spec sp = tension_spec();
  const double h = h_of(lj);
  const double F_analytic = -lj.strip_modulus() * strain * sp.ncy * h;
  std::printf("left reaction [N/m]: analytic %.5e reference %.5e coupled %.5e\n", F_analytic,
              ref.reaction, cpl.reaction);
  double emax = 0;
  for (std::size_t k = 0; k < ref.u_cells.size(); ++k)
    emax = std::max(emax, (cpl.u_cells[k] - ref.u_cells[k]).norm());
  const double scale = strain * sp.bnx * h;
  std::printf("max |u_coupled - u_ref| over block cells: %.3e m = %.3f of strain * block width\n",
              emax, emax / scale);
  EXPECT_NEAR(ref.reaction / F_analytic, 1.0, 0.05);
  EXPECT_NEAR(cpl.reaction / ref.reaction, 1.0, 0.06);
  EXPECT_LT(emax / scale, 0.15);
  // Energy log: the thermostats removed heat and the log is complete.
  EXPECT_GT(cpl.energy.heat_removed_ivc, 0.0);
  const auto& e = cpl.energy;
  std::printf("handshake energy created %.4e J, balance %.4e J, heat cont %.4e J\n",
              e.work_cont_on_md + e.work_md_on_cont, e.balance(), e.heat_removed_cont);
  // The log closes: energy now - at start - work in + heat out (balance) equals the energy the
  // handshake created (the two handshake works) up to the time-integration errors of both
  // solvers and the half MD step by which the IVC force of a block outlasts it in the work
  // tally; 15 % of the created energy (measured 9 %).
  const double created = e.work_cont_on_md + e.work_md_on_cont;
  EXPECT_NEAR(e.balance() / created, 1.0, 0.15);
}

namespace {

struct WaveRun {
  std::vector<Eigen::Vector2d> v_left; // velocities of the particles left of the block, m/s
  std::vector<double> m_left;          // their masses, kg
  double incident = 0;                 // energy put in by the pulse (reference only), J/m
};

/// A longitudinal pulse sent from the left edge of a long strip (50 x 14 cells, atom block
/// 10 x 10 cells at cell 30): left-edge velocity v0 sin^2(pi t / T) for t < T, then held.
/// The coupled model first settles for t_settle with damping (the MD surface relaxes), then
/// runs undamped. pulse = false: the same run without the pulse (its field is subtracted).
WaveRun wave(bool coupled, bool pulse) {
  const LjFcc lj = lj_fcc(kEps, kSig, kRc, kMass);
  Spec sp;
  sp.ncx = 50;
  sp.ncy = 14;
  sp.bx0 = 30;
  sp.by0 = 2;
  sp.bnx = 10;
  sp.bny = 10;
  sp.svc_rings = 2;
  const double h = h_of(lj);
  Solver<2> s;
  build_continuum(s, sp, lj);
  NodeBC<2> left;
  left.lo = Eigen::Vector2d(-2.1 * h, -10 * h);
  left.hi = Eigen::Vector2d(0.1 * h, 100 * h);
  left.mask = {true, false};
  s.bcs = {left};
  const int N = 20;
  const double dt = N * 4e-15;
  const double c = std::sqrt(lj.strip_modulus() / lj.density);
  const double T = 3e-12, v0 = 2e-3 * c; // peak strain 2e-3
  const double t_settle = coupled ? 8e-12 : 0.0, t_end = t_settle + 24e-12;
  const double damping = 2 * 0.7 * M_PI * c / (sp.ncx * h);
  Config cfg = md_config(sp, lj);
  cfg.svc_rings = sp.svc_rings;
  cfg.substeps = N;
  cfg.dt = dt;
  cfg.interior_damp_fs = 0; // INT: plain NVE, it must not absorb the wave
  cfg.ivc_damp_fs = 1.0 / damping / units::s_per_fs;
  std::unique_ptr<Coupler> cp;
  if (coupled) {
    cp = std::make_unique<Coupler>(s, cfg);
    cp->setup();
  } else {
    s.initialize();
  }
  WaveRun r;
  while (s.time < t_end - 0.5 * dt) {
    const double tl = s.time + 0.5 * dt - t_settle;
    s.bcs[0].velocity[0] =
        (pulse && tl > 0 && tl < T) ? v0 * std::pow(std::sin(M_PI * tl / T), 2) : 0.0;
    if (coupled) {
      cp->step();
    } else {
      s.step(dt);
    }
    if (s.time < t_settle) {
      const double f = std::exp(-damping * dt);
      for (auto& v : s.particles.v)
        v *= f;
    }
    if (!coupled && r.incident == 0 && tl > T + 1e-12)
      r.incident = s.energy.kinetic + s.energy.strain;
  }
  for (std::size_t p = 0; p < s.particles.size(); ++p)
    if (s.particles.x0[p][0] < (sp.bx0 - 4) * h) {
      r.v_left.push_back(s.particles.v[p]);
      r.m_left.push_back(s.particles.m[p]);
    }
  return r;
}

} // namespace

// Validation (b): a pulse (length ~37 A, 7 cells; peak strain 2e-3) runs from the continuum
// into the LJ crystal region and back out of it. 24 ps after it was sent, the pulse has
// crossed the block (its front reaches it at ~13 ps) and whatever the two handshakes
// reflected is in the left region (cells 0-25), not yet back at the left edge (~26 ps).
// Reflected energy = 2 x kinetic energy (a travelling wave carries equal kinetic and strain
// energy) of the scattered velocity field in that region: the coupled pulse response (pulse
// run minus the run without pulse, removing the MD surface relaxation) minus the
// all-continuum response; over the incident energy. Stated bound: 2 % (measured 0.5 %)
// reflected (the dissertation gives no number).
TEST(Escm, WaveCrossesHandshakeWithSmallReflection) {
  const WaveRun ref = wave(false, true);
  const WaveRun cp1 = wave(true, true);
  const WaveRun cp0 = wave(true, false);
  ASSERT_GT(ref.incident, 0);
  // Scattered field = coupled pulse response minus the all-continuum response (the system is
  // linear at this amplitude): what the handshake reflects, without the grid's own dispersive
  // tail, which the plain energy in the region also holds (printed for comparison).
  double ke_ref = 0, ke_cpl = 0, ke_scat = 0;
  for (std::size_t k = 0; k < ref.v_left.size(); ++k) {
    const Eigen::Vector2d resp = cp1.v_left[k] - cp0.v_left[k];
    ke_ref += 0.5 * ref.m_left[k] * ref.v_left[k].squaredNorm();
    ke_cpl += 0.5 * ref.m_left[k] * resp.squaredNorm();
    ke_scat += 0.5 * ref.m_left[k] * (resp - ref.v_left[k]).squaredNorm();
  }
  const double R_cpl = 2 * ke_scat / ref.incident;
  std::printf("energy left of the block / incident: all-continuum %.4f coupled %.4f; "
              "scattered by the handshake %.4f\n",
              2 * ke_ref / ref.incident, 2 * ke_cpl / ref.incident, R_cpl);
  EXPECT_LT(R_cpl, 0.02);
}
