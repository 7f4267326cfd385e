// Steered bending of a short chain: EI and persistence length (docs/theory.md §4.5, D66-D68; units
// real).
#include "pnc/thermo/persistence.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/md/stage_stop.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>

namespace pnc::thermo {

namespace fs = std::filesystem;

void PersistenceSpec::validate(const std::string& source) const {
  if (chain != "pp" && chain != "harmonic")
    fail(source, "chain", chain, "must be \"pp\" or \"harmonic\"");
  if (supports != "pinned" && supports != "roller")
    fail(source, "supports", supports, "must be \"pinned\" or \"roller\"");
  if (beads < 3 || beads > 200) fail(source, "beads", std::to_string(beads), "must be in 3..200");
  auto pos = [&](const char* f, double v) {
    if (!(v > 0) || !std::isfinite(v)) fail(source, f, fmt::format("{}", v), "must be > 0");
  };
  pos("angle_K", angle_K);
  pos("bond_K", bond_K);
  pos("l0", l0);
  pos("spring_k", spring_k);
  pos("pull_distance", pull_distance);
  pos("timestep_fs", timestep_fs);
  pos("temperature", temperature);
  pos("damp_fs", damp_fs);
  if (rates.size() < 2) fail(source, "rates", std::to_string(rates.size()), "need >= 2 rates");
  for (double r : rates)
    pos("rates", r);
  if (hold_steps < 0) fail(source, "hold_steps", std::to_string(hold_steps), "must be >= 0");
  if (sample_every < 1) fail(source, "sample_every", std::to_string(sample_every), "must be >= 1");
  if (blocks < 3) fail(source, "blocks", std::to_string(blocks), "must be >= 3");
  for (double r : rates) {
    const double steps = pull_distance / (r * timestep_fs) / sample_every;
    if (steps < 2.0 * blocks)
      fail(source, "rates", fmt::format("{}", r),
           fmt::format("the pull gives {:.0f} samples, fewer than 2 x blocks = {}; lower the "
                       "rate or the timestep, or raise pull_distance",
                       steps, 2 * blocks));
  }
  if (seed < 1 || seed > 800000000)
    fail(source, "seed", std::to_string(seed), "must be in 1..800000000 (LAMMPS seeds)");
  ff.validate(source);
}

double discrete_bending_stiffness(int beads, double b, double k_theta) {
  const int m = beads - 2; // interior beads = joints
  if (m < 1) fail("<bending>", "beads", std::to_string(beads), "must be >= 3");
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(m, m);
  for (int j = 0; j < m; ++j) {
    D(j, j) = -2;
    if (j > 0) D(j, j - 1) = 1;
    if (j + 1 < m) D(j, j + 1) = 1;
  }
  // E = sum_j k/2 phi_j^2, phi_j = (y_{j-1} - 2 y_j + y_{j+1}) / b (ends y = 0)
  const Eigen::MatrixXd K = k_theta / (b * b) * D.transpose() * D;
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(m);
  const double c = one.dot(K.ldlt().solve(one)); // 1^T K^-1 1
  return m * static_cast<double>(m) / c;         // F/d = m^2 / (1^T K^-1 1)
}

namespace {

struct Geometry {
  std::vector<std::array<double, 3>> x;
  double length = 0;
};

Geometry chain_geometry(const PersistenceSpec& s) {
  Geometry g;
  if (s.chain == "harmonic") {
    for (int i = 0; i < s.beads; ++i)
      g.x.push_back({i * s.l0, 0.0, 0.0});
  } else {
    // all-trans planar zigzag in the xz plane (bond l0, angle theta0), pulled along y
    const double h = 0.5 * s.ff.theta0_deg * std::acos(-1.0) / 180.0;
    for (int i = 0; i < s.beads; ++i)
      g.x.push_back({i * s.ff.l0 * std::sin(h), 0.0, (i % 2) * s.ff.l0 * std::cos(h)});
  }
  const auto& a = g.x.front();
  const auto& b = g.x.back();
  g.length = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                       (b[2] - a[2]) * (b[2] - a[2]));
  return g;
}

void setup_chain(md::Lammps& l, const PersistenceSpec& s, const Geometry& g) {
  const int n = s.beads;
  l.cmd("units real");
  l.cmd("atom_style molecular");
  l.cmd("boundary p p p");
  const double span = g.length + 60.0;
  l.cmd(fmt::format("region pnc_box block {0:.6g} {1:.6g} -30 30 -30 30", -30.0, span - 30.0));
  l.cmd("create_box 1 pnc_box bond/types 1 angle/types 1 dihedral/types 1 "
        "extra/bond/per/atom 2 extra/angle/per/atom 3 extra/dihedral/per/atom 4 "
        "extra/special/per/atom 10");
  const double mass = s.chain == "pp" ? s.ff.bead_mass : 21.0;
  l.cmd(fmt::format("mass 1 {:.10g}", mass));
  for (const auto& p : g.x)
    l.cmd(fmt::format("create_atoms 1 single {:.12g} {:.12g} {:.12g} units box", p[0], p[1], p[2]));
  if (s.chain == "pp") {
    l.cmds(md::polymer_forcefield_commands(s.ff));
  } else {
    l.cmd("pair_style zero 3.0");
    l.cmd("pair_coeff * *");
    l.cmd("bond_style harmonic");
    l.cmd(fmt::format("bond_coeff 1 {:.12g} {:.12g}", s.bond_K, s.l0));
    l.cmd("angle_style harmonic");
    l.cmd(fmt::format("angle_coeff 1 {:.12g} 180.0", s.angle_K));
    l.cmd("special_bonds lj 0.0 0.0 0.0");
  }
  for (int i = 1; i < n; ++i)
    l.cmd(fmt::format("create_bonds single/bond 1 {} {} special no", i, i + 1));
  for (int i = 1; i + 1 < n; ++i)
    l.cmd(fmt::format("create_bonds single/angle 1 {} {} {} special no", i, i + 1, i + 2));
  if (s.chain == "pp")
    for (int i = 1; i + 2 < n; ++i)
      l.cmd(fmt::format("create_bonds single/dihedral 1 {} {} {} {} special no", i, i + 1, i + 2,
                        i + 3));
  l.cmd("special_bonds lj 0.0 0.0 0.0"); // rebuilds the special lists from the topology
  l.cmd(fmt::format("group pnc_end1 id 1"));
  l.cmd(fmt::format("group pnc_end2 id {}", n));
  l.cmd(fmt::format("group pnc_mid id 2:{}", n - 1));
  if (s.supports == "roller")
    l.cmd("group pnc_move union pnc_mid pnc_end2");
  else
    l.cmd("group pnc_move union pnc_mid");
}

struct RateFiles {
  std::string h5, log;
};

RateFiles rate_files(const std::string& dir, std::size_t i) {
  return {(fs::path(dir) / fmt::format("rate_{}.h5", i)).string(),
          (fs::path(dir) / fmt::format("rate_{}.log", i)).string()};
}

void rate_child(md::Lammps& l, const PersistenceSpec& s, const Geometry& g, double rate,
                std::uint64_t seed, const std::string& out) {
  const auto t0 = std::chrono::steady_clock::now();
  setup_chain(l, s, g);
  const int nmid = s.beads - 2;
  l.cmd(
      fmt::format("velocity pnc_mid create {:.10g} {} dist gaussian mom no", s.temperature, seed));
  l.cmd("fix pnc_nve pnc_move nve");
  l.cmd(fmt::format("fix pnc_lan pnc_move langevin {0:.10g} {0:.10g} {1:.10g} {2}", s.temperature,
                    s.damp_fs, seed + 1));
  if (s.supports == "roller") {
    l.cmd("velocity pnc_end2 set NULL 0.0 0.0");
    l.cmd("fix pnc_roll pnc_end2 setforce NULL 0.0 0.0");
  }
  l.cmd(fmt::format("timestep {:.10g}", s.timestep_fs));
  l.cmd("thermo_style custom step temp pe ebond eangle edihed");
  l.cmd("thermo 1000");
  if (s.hold_steps > 0) l.cmd(fmt::format("run {}", s.hold_steps));
  const long steps = std::lround(s.pull_distance / (rate * s.timestep_fs));
  l.cmd("reset_timestep 0");
  l.cmd(fmt::format("variable pnc_a equal {:.15g}*step", rate * s.timestep_fs));
  l.cmd("variable pnc_d equal xcm(pnc_mid,y)");
  l.cmd(fmt::format("variable pnc_F equal {:.15g}*(v_pnc_a-v_pnc_d)", s.spring_k));
  l.cmd(fmt::format("variable pnc_f equal v_pnc_F/{}", nmid));
  l.cmd("fix pnc_pull pnc_mid addforce 0.0 v_pnc_f 0.0");
  l.cmd(fmt::format("fix pnc_rec all vector {} v_pnc_a v_pnc_d v_pnc_F", s.sample_every));
  l.cmd(fmt::format("thermo {}", std::max<long>(1, steps / 10)));
  l.cmd(fmt::format("run {}", steps));
  const long rows = steps / s.sample_every + 1;
  RateResult r;
  r.rate = rate;
  for (long i = 1; i < rows; ++i) { // row 0: the instant the pull starts
    r.anchor.push_back(l.fix_value("pnc_rec", static_cast<int>(i), 0));
    r.d.push_back(l.fix_value("pnc_rec", static_cast<int>(i), 1));
    r.F.push_back(l.fix_value("pnc_rec", static_cast<int>(i), 2));
  }
  const double L3 = g.length * g.length * g.length;
  // dF/dd as the ratio of the slopes against the (noise-free) anchor position: regressing F
  // on the thermally noisy d would bias the slope low (errors in variables; F = k (a - d)
  // carries the same noise with slope -k), D66
  r.slope = block_slope_ratio(r.anchor, r.F, r.d, s.blocks);
  r.ei = {r.slope.value * L3 / 48.0, r.slope.se * L3 / 48.0};
  const std::size_t tail = std::max<std::size_t>(1, r.d.size() / 10);
  double fm = 0, dm = 0;
  for (std::size_t i = r.d.size() - tail; i < r.d.size(); ++i) {
    fm += r.F[i];
    dm += r.d[i];
  }
  fm /= static_cast<double>(tail);
  dm /= static_cast<double>(tail);
  r.ei_end = fm * L3 / (48.0 * dm); // the printed end-of-pull ratio (docs/theory.md §4.5, D67)
  r.d_max = dm;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  AtomicOutput o(out);
  {
    h5::File f(o.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    f.set_attr("/", "format", "pnc-thermo-bending-rate");
    f.write_scalar("/rate", rate);
    f.set_attr("/rate", "units", "A/fs");
    f.write_vector("/samples/anchor", r.anchor);
    f.set_attr("/samples/anchor", "units", "A");
    f.write_vector("/samples/d", r.d);
    f.set_attr("/samples/d", "units", "A (y of the interior beads' centre of mass)");
    f.write_vector("/samples/F", r.F);
    f.set_attr("/samples/F", "units", "kcal/mol/A (spring force on that centre of mass)");
    f.write_scalar("/slope", r.slope.value);
    f.write_scalar("/slope_stderr", r.slope.se);
    f.set_attr("/slope", "units", "kcal/mol/A^2 (dF/dd)");
    f.write_scalar("/EI", r.ei.value);
    f.write_scalar("/EI_stderr", r.ei.se);
    f.set_attr("/EI", "units", "kcal/mol*A (L^3/48 dF/dd)");
    f.write_scalar("/EI_end_ratio", r.ei_end);
    f.set_attr("/EI_end_ratio", "units",
               "kcal/mol*A (F L^3/(48 d), last 10 % means, theory.md §4.5)");
    f.write_scalar("/d_end", r.d_max);
    f.write_scalar("/length", g.length);
    f.write_scalar("/seconds", r.seconds);
  }
  o.commit();
}

RateResult read_rate(const std::string& path) {
  h5::File f(path, h5::File::Mode::read);
  if (f.attr_string("/", "format").value_or("") != "pnc-thermo-bending-rate")
    fail(path, "format", f.attr_string("/", "format").value_or(""),
         "must be pnc-thermo-bending-rate");
  RateResult r;
  r.rate = f.read_scalar("/rate");
  r.anchor = f.read_vector("/samples/anchor");
  r.d = f.read_vector("/samples/d");
  r.F = f.read_vector("/samples/F");
  r.slope = {f.read_scalar("/slope"), f.read_scalar("/slope_stderr")};
  r.ei = {f.read_scalar("/EI"), f.read_scalar("/EI_stderr")};
  r.ei_end = f.read_scalar("/EI_end_ratio");
  r.d_max = f.read_scalar("/d_end");
  r.seconds = f.read_scalar("/seconds");
  return r;
}

} // namespace

PersistenceResult run_persistence(const PersistenceSpec& spec, const std::string& dir, bool resume,
                                  const RateProgress& progress) {
  spec.validate("<persistence>");
  make_output_directory(dir);
  refuse_existing_run(dir, resume, {"rate_0.h5", "persistence.h5"});
  const Geometry g = chain_geometry(spec);
  PersistenceResult res;
  res.spec = spec;
  res.length = g.length;
  pnc::ProgressOptions po; // reused rates are done but not in the rate (D345)
  po.enabled = static_cast<bool>(progress);
  po.sink = progress;
  pnc::Progress bar("pnc thermo persistence", static_cast<double>(spec.rates.size()),
                    "bending rates", po);
  for (std::size_t i = 0; i < spec.rates.size(); ++i) {
    const RateFiles rf = rate_files(dir, i);
    bool have = resume && fs::exists(rf.h5);
    if (have && std::fabs(read_rate(rf.h5).rate - spec.rates[i]) > 1e-15)
      fail(rf.h5, "/rate", fmt::format("{}", read_rate(rf.h5).rate),
           fmt::format("expected {} (another run's file; use a new --out)", spec.rates[i]));
    if (!have) {
      const double rate = spec.rates[i];
      const std::uint64_t seed = spec.seed * 100 + i * 2;
      const auto o = md::run_stage({fmt::format("bending rate {}", rate), rf.log, {}},
                                   md::stoppable([&spec, &g, rate, seed, &rf](md::Lammps& l) {
                                     rate_child(l, spec, g, rate, seed, rf.h5);
                                   }));
      pnc::throw_if_stopped(fmt::format("bending rate {} stopped; finished rates are kept", rate));
      if (!o.ok) md::throw_stage_failure(o, fmt::format("bending rate {} A/fs", rate));
    }
    res.rates.push_back(read_rate(rf.h5));
    const auto& r = res.rates.back();
    const std::string detail =
        fmt::format("rate {:.4g} A/fs: EI = {:.4g} +- {:.2g} kcal/mol*A (slope), {:.4g} "
                    "(end ratio), d_end {:.3f} A{}",
                    r.rate, r.ei.value, r.ei.se, r.ei_end, r.d_max, have ? " (resumed)" : "");
    if (have)
      bar.skip(1, detail);
    else
      bar.advance(1, detail);
  }
  std::vector<double> x, y, sy;
  for (const auto& r : res.rates) {
    x.push_back(r.rate);
    y.push_back(r.ei.value);
    sy.push_back(r.ei.se);
  }
  // weighted straight line; errors scaled by the scatter about it when dof > 0 (D66)
  res.line = polyfit(x, y, sy, 1, true);
  if (res.line.dof > 0 && res.line.chi2_reduced < 1) { // never claim more than the s.e. give
    res.line = polyfit(x, y, sy, 1, false);
  }
  res.ei0 = {res.line.c[0], res.line.se[0]};
  res.ei0_ci95 = res.line.dof > 0 ? t95(res.line.dof) * res.line.se[0] : std::nan("");
  const double kT = units::kB_kcal_mol_K * spec.temperature;
  res.xi_p = res.ei0.value / kT;
  res.xi_p_ci95 = res.ei0_ci95 / kT;
  if (spec.chain == "harmonic") {
    const double kth = 2 * spec.angle_K; // E = K (theta - pi)^2 = (k_theta/2) phi^2
    res.expected_ei = discrete_bending_stiffness(spec.beads, spec.l0, kth) * res.length *
                      res.length * res.length / 48.0;
    res.expected_ei_continuum = kth * spec.l0;
  } else {
    res.expected_ei = res.expected_ei_continuum = std::nan("");
  }
  res.h5 = (fs::path(dir) / "persistence.h5").string();
  AtomicOutput o(res.h5);
  {
    h5::File f(o.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    f.set_attr("/", "format", "pnc-thermo-persistence");
    f.set_attr("/", "units", "LAMMPS real inside (A, fs, kcal/mol, K); SI where named");
    f.write_string("/spec/chain", spec.chain);
    f.write_string("/spec/supports", spec.supports);
    f.write_scalar("/spec/beads", spec.beads);
    f.write_scalar("/spec/spring_k", spec.spring_k);
    f.set_attr("/spec/spring_k", "units", "kcal/mol/A^2");
    f.write_scalar("/spec/pull_distance", spec.pull_distance);
    f.write_scalar("/spec/timestep", spec.timestep_fs);
    f.write_scalar("/spec/hold_steps", spec.hold_steps);
    f.write_scalar("/spec/temperature", spec.temperature);
    f.write_scalar("/spec/damp", spec.damp_fs);
    f.write_string("/spec/seed", std::to_string(spec.seed));
    if (spec.chain == "harmonic") {
      f.write_scalar("/spec/angle_K", spec.angle_K);
      f.set_attr("/spec/angle_K", "units", "kcal/mol/rad^2 (LAMMPS angle harmonic K, theta0 180)");
      f.write_scalar("/spec/bond_K", spec.bond_K);
      f.write_scalar("/spec/l0", spec.l0);
    }
    f.write_scalar("/length", res.length);
    f.set_attr("/length", "units", "A (end-to-end distance as built)");
    std::vector<double> ei, eis, eie, sl, sls;
    for (const auto& r : res.rates) {
      ei.push_back(r.ei.value);
      eis.push_back(r.ei.se);
      eie.push_back(r.ei_end);
      sl.push_back(r.slope.value);
      sls.push_back(r.slope.se);
    }
    f.write_vector("/rates", x);
    f.set_attr("/rates", "units", "A/fs");
    f.write_vector("/EI", ei);
    f.write_vector("/EI_stderr", eis);
    f.write_vector("/EI_end_ratio", eie);
    f.set_attr("/EI", "units", "kcal/mol*A");
    f.write_vector("/slope", sl);
    f.write_vector("/slope_stderr", sls);
    for (std::size_t i = 0; i < res.rates.size(); ++i) {
      const std::string gname = fmt::format("/samples/rate_{}", i);
      f.write_vector(gname + "/anchor", res.rates[i].anchor);
      f.write_vector(gname + "/d", res.rates[i].d);
      f.write_vector(gname + "/F", res.rates[i].F);
    }
    f.write_vector("/fit/line", res.line.c);
    f.write_vector("/fit/line_stderr", res.line.se);
    f.set_attr("/fit/line", "definition", "EI = c0 + c1 rate (kcal/mol*A, rate in A/fs)");
    f.write_scalar("/EI0", res.ei0.value);
    f.write_scalar("/EI0_stderr", res.ei0.se);
    f.write_scalar("/EI0_ci95", res.ei0_ci95);
    f.set_attr("/EI0", "units", "kcal/mol*A");
    f.write_scalar("/EI0_SI", res.ei0.value * units::j_m_per_kcal_mol_A);
    f.write_scalar("/EI0_ci95_SI", res.ei0_ci95 * units::j_m_per_kcal_mol_A);
    f.set_attr("/EI0_SI", "units", "N m^2");
    f.write_scalar("/xi_p", res.xi_p);
    f.write_scalar("/xi_p_ci95", res.xi_p_ci95);
    f.set_attr("/xi_p", "units", "A (EI0 / kB T, theory.md §4.5)");
    if (spec.chain == "harmonic") {
      f.write_scalar("/expected/EI_discrete", res.expected_ei);
      f.write_scalar("/expected/EI_continuum", res.expected_ei_continuum);
      f.set_attr("/expected", "definition",
                 "EI_discrete = L^3/48 F/d of the discrete chain (small deflections); "
                 "EI_continuum = k_theta l0 = 2 K l0; kcal/mol*A");
    }
  }
  o.commit();
  return res;
}

} // namespace pnc::thermo
