// thermo/ with LAMMPS (each lambda point / pull in a supervised child): free-energy
// differences known exactly, TI against FEP, the finite-difference check of dH/dlambda on a
// polymer, and the bending analysis on a chain of known stiffness. Small systems, short runs.
#include "pnc/core/error.hpp"
#include "pnc/core/units.hpp"
#include "pnc/md/builder.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/thermo/persistence.hpp"
#include "pnc/thermo/ti.hpp"

#include <lammps/library.h>

#include "lj_fluid.hpp"
#include "tiny_polymer.hpp"

#include "common/temp_dir.hpp"

#include <fmt/format.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

using namespace pnc::thermo;
namespace fs = std::filesystem;
namespace md = pnc::md;

namespace {

fs::path tmpdir(const std::string& tag) {
  return pnc::test::fresh_dir("test_thermo_" + tag);
}

double fix_scalar(md::Lammps& l, const char* id) {
  auto* p = static_cast<double*>(
      lammps_extract_fix(l.handle(), id, LMP_STYLE_GLOBAL, LMP_TYPE_SCALAR, 0, 0));
  if (!p) throw std::runtime_error("no scalar");
  const double v = *p;
  lammps_free(p);
  return v;
}

/// N free atoms tethered to their sites by fix spring/self with k(l) = k0 + l (k1 - k0):
/// H(l) = sum k(l)/2 |r - r0|^2, dH/dl = (k1 - k0)/k(l) E_spring.
LambdaSystem einstein(int n, double k0, double k1, double T) {
  LambdaSystem sys;
  auto k = [=](double l) { return k0 + l * (k1 - k0); };
  sys.setup = [=](md::Lammps& l, double lambda, std::uint64_t seed) {
    l.cmd("units real");
    l.cmd("atom_style atomic");
    l.cmd("region pnc_b block 0 40 0 40 0 40");
    l.cmd("create_box 1 pnc_b");
    l.cmd(fmt::format("create_atoms 1 random {} 4711 NULL", n));
    l.cmd("mass 1 21.0");
    l.cmd("pair_style zero 3.0");
    l.cmd("pair_coeff * *");
    l.cmd(fmt::format("velocity all create {} {} dist gaussian", T, seed));
    l.cmd("fix pnc_nve all nve");
    l.cmd(fmt::format("fix pnc_lan all langevin {0} {0} 50.0 {1}", T, seed + 7));
    l.cmd(fmt::format("fix pnc_sp all spring/self {:.15g}", k(lambda)));
    l.cmd("thermo 100000");
  };
  sys.sample = [=](md::Lammps& l, double lambda, double lp, double ln) {
    const double e = fix_scalar(l, "pnc_sp");
    LambdaSample s;
    s.dhdl = (k1 - k0) / k(lambda) * e;
    s.u = e;
    s.du_prev = std::isfinite(lp) ? e * (k(lp) / k(lambda) - 1) : std::nan("");
    s.du_next = std::isfinite(ln) ? e * (k(ln) / k(lambda) - 1) : std::nan("");
    return s;
  };
  return sys;
}

std::vector<std::pair<PointJob, LambdaSystem>> with(const std::vector<PointJob>& jobs,
                                                    const LambdaSystem& s) {
  std::vector<std::pair<PointJob, LambdaSystem>> out;
  for (const auto& j : jobs)
    out.push_back({j, s});
  return out;
}

} // namespace

// Einstein crystal: Delta A = (3N/2) kT ln(k1/k0) exactly (classical harmonic tethers).
// The quadrature's own error is known too: it is what the rule gives for the exact
// integrand f(l) = (3N/2) kT (k1-k0)/k(l). Tolerances: 4 standard errors (block averages).
TEST(ThermoTi, EinsteinCrystalThroughTheTiMachinery) {
  const auto d = tmpdir("einstein");
  const int n = 30;
  const double k0 = 1.0, k1 = 4.0, T = 300, kT = pnc::units::kB_kcal_mol_K * T; // kcal/mol/A^2, K
  const LambdaSystem sys = einstein(n, k0, k1, T);
  SamplingSpec s;
  s.timestep_fs = 2.0;
  s.equil_steps = 1000;
  s.prod_steps = 20000;
  s.sample_every = 10;
  s.blocks = 10;
  s.temperature = T;
  const double exact = 1.5 * n * kT * std::log(k1 / k0);
  auto f = [&](double l) { return 1.5 * n * kT * (k1 - k0) / (k0 + l * (k1 - k0)); };
  for (const auto& [rule, pts] : {std::pair<std::string, int>{"gauss", 3}, {"trapezoid", 5}}) {
    const Quadrature q = make_rule(rule, pts, "test");
    const auto jobs = node_jobs(q, (d / rule).string(), "einstein " + rule, 100);
    run_points(s, with(jobs, sys), false, 2, nullptr);
    const LambdaIntegral li = collect(q, jobs, kT, s.blocks);
    double quad = 0;
    for (std::size_t i = 0; i < q.nodes.size(); ++i) {
      quad += q.weights[i] * f(q.nodes[i]);
      const auto& p = li.points[i];
      EXPECT_NEAR(p.dhdl.value, f(p.lambda), 4 * p.dhdl.se) << rule << " lambda " << p.lambda;
      EXPECT_GT(p.dhdl.se, 0);
    }
    std::cerr << fmt::format("  Einstein {} {}: TI {:.4f} +- {:.4f}, rule on exact integrand "
                             "{:.4f}, exact {:.4f} kcal/mol\n",
                             rule, pts, li.dA.value, li.dA.se, quad, exact);
    EXPECT_NEAR(li.dA.value, quad, 4 * li.dA.se) << rule;
    // the statistical error is small enough for the test to mean something: < 2 % of dA
    EXPECT_LT(li.dA.se, 0.02 * exact);
    if (rule == "gauss") {
      EXPECT_NEAR(li.dA.value, exact, 4 * li.dA.se + std::fabs(quad - exact));
    }
    // adjacent-node FEP forward (from the softer tether, whose configurations cover the
    // stiffer one's) agrees with the exact 3N/2 kT ln(k_b/k_a). The backward direction
    // (stiff -> soft) is the known poorly-overlapping one and is biased at these spacings;
    // it is not asserted here (TiAgreesWithFep... tests both directions where they overlap).
    for (std::size_t i = 0; i + 1 < li.points.size(); ++i) {
      const double la = li.points[i].lambda, lb = li.points[i + 1].lambda;
      const double ex = 1.5 * n * kT * std::log((k0 + lb * (k1 - k0)) / (k0 + la * (k1 - k0)));
      EXPECT_NEAR(li.fep_forward[i].value, ex, 4 * li.fep_forward[i].se) << rule << i;
    }
  }
  // resume: nothing is rerun (the files are not rewritten)
  const Quadrature q = gauss_legendre(3);
  const auto jobs = node_jobs(q, (d / "gauss").string(), "einstein gauss", 100);
  const auto t0 = fs::last_write_time(jobs[0].h5);
  int calls = 0;
  run_points(s, with(jobs, sys), true, 1, [&](const pnc::ProgressState& p) {
    ++calls;
    EXPECT_EQ(p.done, p.total);
  });
  EXPECT_EQ(fs::last_write_time(jobs[0].h5), t0);
  EXPECT_EQ(calls, 1);
}

// TI with Simpson's rule over a short lambda window against FEP between the adjacent nodes,
// on a 108-atom LJ fluid along the dissertation's path (two independent estimators of the
// same A(b) - A(a)). Tolerance 4 combined standard errors (Simpson's error ~h^5 f'''' is
// negligible at h = 0.02).
TEST(ThermoTi, TiAgreesWithFepBetweenAdjacentLambdas) {
  const auto d = tmpdir("fep");
  const LjPath p;
  const double T = 300;
  const LambdaSystem sys = pnc::test::lj_fluid(p, T);
  SamplingSpec s;
  s.timestep_fs = 2.0;
  s.equil_steps = 2000;
  s.prod_steps = 20000;
  s.sample_every = 10;
  s.blocks = 10;
  s.temperature = T;
  const double a = 0.86, b = 0.90, h = b - a;
  Quadrature simpson{"simpson", {a, 0.5 * (a + b), b}, {h / 6, 4 * h / 6, h / 6}};
  const auto jobs = node_jobs(simpson, d.string(), "lj", 500);
  run_points(s, with(jobs, sys), false, 2, nullptr);
  const double kT = pnc::units::kB_kcal_mol_K * T;
  const LambdaIntegral li = collect(simpson, jobs, kT, s.blocks);
  const Estimate fw{li.fep_forward[0].value + li.fep_forward[1].value,
                    std::hypot(li.fep_forward[0].se, li.fep_forward[1].se)};
  const Estimate bw{li.fep_backward[0].value + li.fep_backward[1].value,
                    std::hypot(li.fep_backward[0].se, li.fep_backward[1].se)};
  std::cerr << fmt::format("  LJ fluid A({}) - A({}): TI (Simpson) {:.4f} +- {:.4f}, FEP forward "
                           "{:.4f} +- {:.4f}, backward {:.4f} +- {:.4f} kcal/mol\n",
                           b, a, li.dA.value, li.dA.se, fw.value, fw.se, bw.value, bw.se);
  EXPECT_GT(std::fabs(li.dA.value), 10 * li.dA.se) << "the difference must be resolved";
  EXPECT_NEAR(li.dA.value, fw.value, 4 * std::hypot(li.dA.se, fw.se));
  EXPECT_NEAR(li.dA.value, bw.value, 4 * std::hypot(li.dA.se, bw.se));
  // the finite-difference check of every point: pnc's pair sum against LAMMPS's energies
  for (const auto& pt : li.points) {
    const auto& c = pt.checks;
    EXPECT_NEAR(c.at("u_pnc"), c.at("u_lammps"), 1e-9 * std::fabs(c.at("u_lammps")));
    // Richardson-extrapolated central difference; its error is below the estimated error
    // of the plain central difference |D_h - D_2h|/3 (+ round-off), both from LAMMPS
    EXPECT_NEAR(c.at("dhdl_pnc"), c.at("fd_dhdl_lammps"), c.at("fd_error_estimate"));
    EXPECT_LT(c.at("fd_error_estimate"), 1e-3 * std::fabs(c.at("dhdl_pnc")));
    // the energy/virial identity the default sampler uses (D64) equals the pair sum
    EXPECT_NEAR(c.at("dhdl_virial_identity"), c.at("dhdl_pnc"), 1e-8 * std::fabs(c.at("u_pnc")));
    EXPECT_NEAR(c.at("du_probe_virial_identity"), c.at("du_probe_pnc"),
                1e-8 * std::fabs(c.at("u_pnc")));
  }
}

using pnc::test::tiny_polymer_restart;

// Polymer: dH/dlambda from pair distances = central difference of LAMMPS's pair energy
// (through pair_coeff at lambda -+ h) for the undeformed, dilated and sheared box; the
// deformed volumes are det F V0 (F of docs/theory.md §4.2).
TEST(ThermoTi, PolymerDhdlMatchesLammpsFiniteDifferenceAndStatesHaveDetFVolume) {
  const auto d = tmpdir("polymer");
  const std::string rs = tiny_polymer_restart(d);
  TiSpec spec;
  spec.dhdl_method = "pairs"; // the chunked pair-distance sampler (the LJ test uses "virial")
  spec.sampling.equil_steps = 100;
  spec.sampling.prod_steps = 100;
  spec.sampling.sample_every = 10;
  spec.sampling.blocks = 5;
  const double s = 0.005;
  std::vector<std::pair<PointJob, LambdaSystem>> point_jobs;
  const std::vector<DeformState> states = {{"ref", 0, "ref"}, {"vol", s, "vol"}, {"dev", s, "dev"}};
  for (const auto& st : states) {
    PointJob j;
    j.lambda = 0.5;
    j.lambda_prev = 0.3;
    j.lambda_next = 0.7;
    j.h5 = (d / (st.id + ".h5")).string();
    j.label = st.id;
    j.seed = 9;
    point_jobs.push_back({j, polymer_system(spec, st, rs, md::polymer_forcefield_commands({}))});
  }
  run_points(spec.sampling, point_jobs, false, 2, nullptr);
  std::map<std::string, PointResult> r;
  for (const auto& st : states)
    r[st.id] = read_point((d / (st.id + ".h5")).string());
  for (const auto& [id, pt] : r) {
    const auto& c = pt.checks;
    EXPECT_GT(c.at("pairs"), 100) << id;
    EXPECT_NEAR(c.at("u_pnc"), c.at("u_lammps"), 1e-9 * std::fabs(c.at("u_lammps"))) << id;
    EXPECT_NEAR(c.at("dhdl_pnc"), c.at("fd_dhdl_lammps"), c.at("fd_error_estimate")) << id;
    EXPECT_LT(c.at("fd_error_estimate"), 1e-3 * std::fabs(c.at("dhdl_pnc"))) << id;
    EXPECT_NEAR(c.at("dhdl_virial_identity"), c.at("dhdl_pnc"), 1e-8 * std::fabs(c.at("u_pnc")))
        << id;
    EXPECT_EQ(pt.dhdl_s.size(), 10u);
  }
  const double v0 = r["ref"].checks.at("volume");
  EXPECT_NEAR(r["vol"].checks.at("volume") / v0, std::pow(1 + s, 3), 1e-9);
  EXPECT_NEAR(r["dev"].checks.at("volume") / v0, 1 - 3 * s * s + 2 * s * s * s, 1e-9);
}

// Bending analysis on a chain whose stiffness is set by construction: 4 beads, straight,
// angle harmonic K (theta - 180)^2, i.e. k_theta = 2K; one end pinned, the other on a roller
// (no axial constraint). Expected EI = L^3/48 * F/d of the discrete chain (2 k_theta / b^2
// for 4 beads) = 1.125 k_theta l0; the continuum value k_theta l0 is its long-chain limit.
// Tolerance: 3 x the standard error of the zero-rate intercept plus the geometric
// non-linearity of the largest deflection, (d_max / l0)^2 (the small-angle error of the
// bending energy's curvature).
TEST(ThermoPersistence, StiffHarmonicChainGivesItsConstructedBendingStiffness) {
  const auto d = tmpdir("bending");
  PersistenceSpec s;
  s.chain = "harmonic";
  s.beads = 4;
  s.angle_K = 500;
  s.bond_K = 300;
  s.supports = "roller";
  s.spring_k = 100;
  s.pull_distance = 3.0;
  s.rates = {0.0005, 0.001, 0.0015, 0.002};
  s.timestep_fs = 1.0;
  s.hold_steps = 1000;
  s.sample_every = 2;
  s.blocks = 10;
  const PersistenceResult r = run_persistence(s, d.string(), false, nullptr);
  double dmax = 0;
  for (const auto& rr : r.rates) {
    dmax = std::max(dmax, rr.d_max);
    std::cerr << fmt::format("  rate {} A/fs: EI {:.1f} +- {:.1f} (slope), {:.1f} (end ratio), "
                             "d_end {:.3f} A\n",
                             rr.rate, rr.ei.value, rr.ei.se, rr.ei_end, rr.d_max);
  }
  const double kth = 2 * s.angle_K;
  EXPECT_NEAR(r.expected_ei, 1.125 * kth * s.l0, 1e-9 * r.expected_ei);
  EXPECT_NEAR(r.length, 3 * s.l0, 1e-12);
  const double tol = 3 * r.ei0.se + std::pow(dmax / s.l0, 2) * r.expected_ei;
  std::cerr << fmt::format(
      "  EI(0) = {:.1f} +- {:.1f} (95 % CI +- {:.1f}) kcal/mol*A, expected "
      "{:.1f} (discrete), {:.1f} (continuum); tolerance {:.1f}; xi_p {:.0f} A\n",
      r.ei0.value, r.ei0.se, r.ei0_ci95, r.expected_ei, r.expected_ei_continuum, tol, r.xi_p);
  EXPECT_NEAR(r.ei0.value, r.expected_ei, tol);
  EXPECT_LT(tol, 0.15 * r.expected_ei) << "the test must be able to tell 1.125 from 1";
  EXPECT_NEAR(r.xi_p, r.ei0.value / (pnc::units::kB_kcal_mol_K * s.temperature), 1e-9 * r.xi_p);
}

// A LAMMPS error inside a lambda point is reported with LAMMPS's own message.
TEST(ThermoTi, LammpsErrorIsReportedWithItsMessage) {
  const auto d = tmpdir("error");
  const std::string bogus = (d / "not_a_restart").string();
  { std::ofstream(bogus) << "garbage\n"; }
  TiSpec spec;
  spec.sampling.equil_steps = 10;
  spec.sampling.prod_steps = 30;
  spec.sampling.sample_every = 10;
  spec.sampling.blocks = 3;
  PointJob j;
  j.lambda = 0.5;
  j.lambda_prev = j.lambda_next = std::nan("");
  j.h5 = (d / "p.h5").string();
  j.label = "bad";
  try {
    run_points(
        spec.sampling,
        {{j, polymer_system(spec, {"ref", 0, "ref"}, bogus, md::polymer_forcefield_commands({}))}},
        false, 1, nullptr);
    FAIL() << "no error";
  } catch (const pnc::ToolError& e) {
    const std::string m = e.what();
    EXPECT_EQ(e.context().tool, "LAMMPS");
    EXPECT_EQ(e.context().log_path, (d / "p.log").string());
    EXPECT_NE(m.find("ERROR"), std::string::npos) << m;
    EXPECT_NE(m.find("read_restart"), std::string::npos) << m;
  }
  EXPECT_FALSE(fs::exists(j.h5));
}
