// Phase check stage (units real inside, SI in phase.h5): decisions D125-D129.
#include "pnc/rve/phase_check.hpp"

#include "pnc/md/box.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/stage_stop.hpp"
#include "pnc/rve/deform.hpp"
#include "pnc/rve/equilibrate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>

namespace pnc::rve {

namespace fs = std::filesystem;

void PhaseCheckSpec::validate(const std::string& source) const {
  if (steps < 1000 || steps > 2000000000)
    fail(source, "phase_check.steps", std::to_string(steps), "must be in 1000..2000000000");
  if (sample_every < 1 || sample_every > 1000)
    fail(source, "phase_check.sample_every", std::to_string(sample_every), "must be in 1..1000");
  if (blocks < 4 || blocks > 1000)
    fail(source, "phase_check.blocks", std::to_string(blocks), "must be in 4..1000");
  auto frac = [&](const char* f, double v, double hi) {
    if (!(v > 0 && v <= hi))
      fail(source, f, fmt::format("{}", v), fmt::format("must be in (0, {}]", hi));
  };
  frac("phase_check.shear_strain", shear_strain, 0.1);
  frac("phase_check.bulk_strain", bulk_strain, 0.1);
  frac("phase_check.cavitation_strain", cavitation_strain, 0.5);
  if (cavitation_steps < 100 || cavitation_steps > 2000000000)
    fail(source, "phase_check.cavitation_steps", std::to_string(cavitation_steps),
         "must be in 100..2000000000");
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string h5_path(const std::string& dir) {
  return (fs::path(dir) / "phase.h5").string();
}

void read_state(md::Lammps& l, const PhaseCheckInput& in) {
  l.cmd("clear");
  l.cmd("units real");
  l.cmd("atom_style " + in.atom_style);
  l.cmd("read_restart " + md::lammps_path(in.start_state, "restart"));
  l.cmds(in.force_field);
  l.cmd("reset_timestep 0");
  l.cmd(fmt::format("timestep {:.10g}", in.timestep_fs));
}

std::vector<double> part(const std::vector<double>& x, double from, double to) {
  const auto n = static_cast<double>(x.size());
  return {x.begin() + static_cast<long>(from * n), x.begin() + static_cast<long>(to * n)};
}

struct Hold {
  std::vector<double> pxy, p; // atm, total (with kinetic term)
  double void_first = kNaN, void_last = kNaN;
};

double voids(md::Lammps& l, double probe) {
  const md::LmpBox box = l.box();
  return void_fraction(l.gather("x", 3), box.lo.data(), box.hi.data(), probe, 1.0);
}

/// A deformation-case hold (NVE + Langevin zero yes + momentum) from the start state with
/// the box strained: kind 's' simple shear xy = gamma, 'v' isotropic volumetric strain.
Hold hold(md::Lammps& l, const PhaseCheckInput& in, char kind, double strain, long steps,
          std::uint64_t seed, bool with_voids) {
  read_state(l, in);
  const md::LmpBox box = l.box();
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  if (kind == 's') {
    l.cmd("change_box all triclinic");
    l.cmds(in.force_field); // a long-range solver is defined again on the triclinic box
    F(0, 1) = strain;       // simple shear 1-2: xy += gamma Ly
  } else {
    F *= std::cbrt(1.0 + strain); // isotropic volumetric strain
  }
  l.cmd(md::box_change(box, F, "<phase check>"));
  l.cmd("fix pnc_nve all nve");
  l.cmd(fmt::format("fix pnc_lan all langevin {0:.10g} {0:.10g} {1:.10g} {2} zero yes",
                    in.temperature, in.damp_fs, seed));
  l.cmd("fix pnc_mom all momentum 100 linear 1 1 1");
  l.cmd(fmt::format("fix pnc_hs all vector {} c_thermo_press[4] c_thermo_press",
                    in.hold_sample_every));
  l.cmd(fmt::format("thermo {}", std::max<long>(1, steps / 5)));
  Hold h;
  if (with_voids && in.probe_A > 0) {
    const long q = std::max<long>(in.hold_sample_every,
                                  steps / 4 / in.hold_sample_every * in.hold_sample_every);
    l.cmd(fmt::format("run {}", q));
    h.void_first = voids(l, in.probe_A);
    l.cmd(fmt::format("run {}", steps - q));
    h.void_last = voids(l, in.probe_A);
  } else {
    l.cmd(fmt::format("run {}", steps));
  }
  const long rows = steps / in.hold_sample_every + 1;
  for (long i = 1; i < rows; ++i) { // row 0: the state just after the remap
    h.pxy.push_back(l.fix_value("pnc_hs", static_cast<int>(i), 0));
    h.p.push_back(l.fix_value("pnc_hs", static_cast<int>(i), 1));
  }
  return h;
}

void autocorrelation_run(md::Lammps& l, const PhaseCheckSpec& s, const PhaseCheckInput& in,
                         PhaseCheckResult& r, AcfEstimate& acf) {
  read_state(l, in);
  r.volume_m3 = l.box().volume() * units::m3_per_angstrom3;
  // decision D125: re-thermalise at the deformation temperature, then NVE (no thermostat
  // perturbs the dynamics whose correlation is measured)
  l.cmd("fix pnc_nve all nve");
  l.cmd(fmt::format("fix pnc_lan all langevin {0:.10g} {0:.10g} {1:.10g} {2} zero yes",
                    in.temperature, in.damp_fs, in.seed));
  l.cmd(fmt::format("thermo {}", std::max<long>(100, in.hold_steps / 5)));
  l.cmd(fmt::format("run {}", std::max<long>(100, in.hold_steps / 5)));
  l.cmd("unfix pnc_lan");
  l.cmd("reset_timestep 0");
  l.cmd(fmt::format("fix pnc_acf all vector {} c_thermo_press[4] c_thermo_press[5] "
                    "c_thermo_press[6] c_thermo_temp",
                    s.sample_every));
  l.cmd(fmt::format("thermo {}", std::max<long>(1, s.steps / 10)));
  l.cmd(fmt::format("run {}", s.steps));
  const long rows = s.steps / s.sample_every + 1;
  std::vector<std::vector<double>> comp(3);
  std::vector<double> temp;
  for (long i = 0; i < rows; ++i) {
    for (int c = 0; c < 3; ++c)
      comp[c].push_back(l.fix_value("pnc_acf", static_cast<int>(i), c) * md::pa_per_atm);
    temp.push_back(l.fix_value("pnc_acf", static_cast<int>(i), 3));
  }
  auto mean = [](const std::vector<double>& x) {
    double m = 0;
    for (double v : x)
      m += v;
    return m / static_cast<double>(x.size());
  };
  r.temperature_K = mean(temp);
  r.nve_T_first_K = mean(part(temp, 0.0, 0.1));
  r.nve_T_last_K = mean(part(temp, 0.9, 1.0));
  r.dt_s = s.sample_every * in.timestep_fs * 1e-15;
  r.hold_time_s = static_cast<double>(in.hold_steps) * in.timestep_fs * 1e-15;
  const int max_lag = static_cast<int>(std::lround(r.hold_time_s / r.dt_s));
  acf = autocorrelation(comp, r.dt_s, max_lag, s.blocks);
  const double to_G = r.volume_m3 / (units::boltzmann * r.temperature_K); // Pa^2 -> Pa
  for (std::size_t k = 0; k < acf.value.size(); ++k) {
    r.acf_t_s.push_back(acf.lag[k]);
    r.acf_G_Pa.push_back(acf.value[k] * to_G);
    r.acf_G_se_Pa.push_back(acf.se[k] * to_G);
  }
  const std::size_t last = r.acf_G_Pa.size() - 1;
  auto lag = [&](double t) {
    return std::min(last, static_cast<std::size_t>(std::lround(t / r.dt_s)));
  };
  auto win = [&](std::size_t k0, std::size_t k1, double& m, double& se) {
    std::tie(m, se) = window_mean(acf, k0, k1);
    m *= to_G;
    se *= to_G;
  };
  r.G_t0_Pa = r.acf_G_Pa[0];
  r.G_t0_se_Pa = r.acf_G_se_Pa[0];
  r.G_at_plateau_time_Pa = r.acf_G_Pa[lag(kPlateauTime_s)];
  r.G_at_plateau_time_se_Pa = r.acf_G_se_Pa[lag(kPlateauTime_s)];
  win(lag(0.5 * kPlateauTime_s), lag(1.5 * kPlateauTime_s), r.G_plateau_Pa, r.G_plateau_se_Pa);
  win(lag(0.5 * r.hold_time_s), last, r.G_acf_late_Pa, r.G_acf_late_se_Pa);
  r.G_acf_hold_Pa = r.acf_G_Pa.back();
  r.G_acf_hold_se_Pa = r.acf_G_se_Pa.back();
  r.tau_int_s = acf.tau_int;
  r.block_s = acf.block_length;
  r.blocks_ok = acf.blocks_ok;
}

void density_drift(const PhaseCheckInput& in, PhaseCheckResult& r) {
  r.drift_kg_m3_s = r.drift_se_kg_m3_s = kNaN;
  if (in.equilibrate_dir.empty() || !(in.npt_chunk_fs > 0)) return;
  const std::string p = (fs::path(in.equilibrate_dir) / "final.h5").string();
  if (!fs::exists(p)) return;
  h5::File f(p, h5::File::Mode::read);
  if (!f.exists("/trace_npt")) return;
  const h5::RowMatrix m = f.read_matrix("/trace_npt");
  std::vector<double> t, y;
  for (Eigen::Index i = m.rows() / 2; i < m.rows(); ++i) {
    t.push_back((static_cast<double>(i) + 0.5) * in.npt_chunk_fs * 1e-15);
    y.push_back(m(i, 4) * 1000.0); // g/cm^3 -> kg/m^3
  }
  std::tie(r.drift_kg_m3_s, r.drift_se_kg_m3_s) = slope_se(t, y);
}

void put(h5::File& f, const std::string& name, double v, const char* units) {
  f.write_scalar(name, v);
  f.set_attr(name, "units", units);
}

void write_phase_h5(const std::string& path, const PhaseCheckSpec& s, const PhaseCheckInput& in,
                    const PhaseCheckResult& r) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    f.set_attr("/", "format", "pnc-rve-phase-check");
    f.write_string("/recipe", in.recipe_json.empty() ? "{}" : in.recipe_json);
    f.write_string("/phase", r.phase);
    f.write_scalar("/solid", r.solid ? 1.0 : 0.0);
    f.write_string("/summary", r.summary);
    put(f, "/temperature", r.temperature_K, "K");
    put(f, "/nve_temperature_first", r.nve_T_first_K, "K");
    put(f, "/nve_temperature_last", r.nve_T_last_K, "K");
    put(f, "/volume", r.volume_m3, "m^3");
    put(f, "/hold_time", r.hold_time_s, "s");
    put(f, "/acf/dt", r.dt_s, "s");
    f.write_vector("/acf/t", r.acf_t_s);
    f.set_attr("/acf/t", "units", "s");
    f.write_vector("/acf/G", r.acf_G_Pa);
    f.set_attr("/acf/G", "units", "Pa");
    f.set_attr("/acf/G", "definition",
               "V/(k_B T) <ds(0) ds(t)>, mean of the three off-diagonal components of the total "
               "stress (with kinetic term), NVE (decision D125)");
    f.write_vector("/acf/G_stderr", r.acf_G_se_Pa);
    f.set_attr("/acf/G_stderr", "units", "Pa");
    put(f, "/acf/tau_int", r.tau_int_s, "s");
    put(f, "/acf/block_length", r.block_s, "s");
    f.write_scalar("/acf/blocks", s.blocks);
    f.write_scalar("/acf/blocks_ok", r.blocks_ok ? 1.0 : 0.0);
    f.write_scalar("/holds_blocks_ok", r.holds_blocks_ok ? 1.0 : 0.0);
    const std::pair<const char*, double> vals[] = {
        {"/G_t0", r.G_t0_Pa},
        {"/G_t0_stderr", r.G_t0_se_Pa},
        {"/G_plateau", r.G_plateau_Pa},
        {"/G_plateau_stderr", r.G_plateau_se_Pa},
        {"/G_at_plateau_time", r.G_at_plateau_time_Pa},
        {"/G_at_plateau_time_stderr", r.G_at_plateau_time_se_Pa},
        {"/G_acf_late", r.G_acf_late_Pa},
        {"/G_acf_late_stderr", r.G_acf_late_se_Pa},
        {"/G_acf_hold", r.G_acf_hold_Pa},
        {"/G_acf_hold_stderr", r.G_acf_hold_se_Pa},
        {"/G_hold", r.G_hold_Pa},
        {"/G_hold_stderr", r.G_hold_se_Pa},
        {"/K", r.K_Pa},
        {"/K_stderr", r.K_se_Pa},
        {"/cavitation/P_first", r.cav_P_first_Pa},
        {"/cavitation/P_first_stderr", r.cav_P_first_se_Pa},
        {"/cavitation/P_last", r.cav_P_last_Pa},
        {"/cavitation/P_last_stderr", r.cav_P_last_se_Pa}};
    for (const auto& [n, v] : vals)
      put(f, n, v, "Pa");
    put(f, "/plateau_time", kPlateauTime_s, "s");
    put(f, "/shear_strain", s.shear_strain, "1");
    put(f, "/bulk_strain", s.bulk_strain, "1 (volumetric)");
    put(f, "/cavitation/strain", r.cav_strain, "1 (volumetric)");
    put(f, "/cavitation/void_first", r.cav_void_first, "1 (fraction)");
    put(f, "/cavitation/void_last", r.cav_void_last, "1 (fraction)");
    f.write_scalar("/cavitation/cavitates", r.cavitates ? 1.0 : 0.0);
    put(f, "/density_drift", r.drift_kg_m3_s, "kg/m^3/s");
    put(f, "/density_drift_stderr", r.drift_se_kg_m3_s, "kg/m^3/s");
  }
  out.commit();
}

void phase_child(md::Lammps& l, const PhaseCheckSpec& s, const PhaseCheckInput& in,
                 const std::string& dir) {
  PhaseCheckResult r;
  AcfEstimate acf;
  autocorrelation_run(l, s, in, r, acf);
  // decision D126: shear step pair, second half of each hold
  const Hold sp = hold(l, in, 's', s.shear_strain, in.hold_steps, in.seed + 1, false);
  const Hold sm = hold(l, in, 's', -s.shear_strain, in.hold_steps, in.seed + 2, false);
  const MeanSe a = hold_mean_se(part(sp.pxy, 0.5, 1.0)), b = hold_mean_se(part(sm.pxy, 0.5, 1.0));
  // sigma = -P: G = (sigma(+) - sigma(-)) / (2 gamma)
  r.G_hold_Pa = -(a.mean - b.mean) * md::pa_per_atm / (2 * s.shear_strain);
  r.G_hold_se_Pa = std::hypot(a.se, b.se) * md::pa_per_atm / (2 * s.shear_strain);
  // decision D127: volume pair, K = -dP/dlnV
  const Hold vp = hold(l, in, 'v', s.bulk_strain, in.hold_steps, in.seed + 3, false);
  const Hold vm = hold(l, in, 'v', -s.bulk_strain, in.hold_steps, in.seed + 4, false);
  const MeanSe c = hold_mean_se(part(vp.p, 0.5, 1.0)), d = hold_mean_se(part(vm.p, 0.5, 1.0));
  const double dlnv = std::log((1 + s.bulk_strain) / (1 - s.bulk_strain));
  r.K_Pa = -(c.mean - d.mean) * md::pa_per_atm / dlnv;
  r.K_se_Pa = std::hypot(c.se, d.se) * md::pa_per_atm / dlnv;
  // decision D129: cavitation hold
  const Hold cv = hold(l, in, 'v', s.cavitation_strain, s.cavitation_steps, in.seed + 5, true);
  const MeanSe p1 = hold_mean_se(part(cv.p, 0.25, 0.5)), p2 = hold_mean_se(part(cv.p, 0.75, 1.0));
  r.cav_strain = s.cavitation_strain;
  r.cav_P_first_Pa = p1.mean * md::pa_per_atm;
  r.cav_P_first_se_Pa = p1.se * md::pa_per_atm;
  r.cav_P_last_Pa = p2.mean * md::pa_per_atm;
  r.cav_P_last_se_Pa = p2.se * md::pa_per_atm;
  r.cav_void_first = cv.void_first;
  r.cav_void_last = cv.void_last;
  const bool void_grows = cv.void_last - cv.void_first > kCavitationVoidGrowth;
  const double rise = r.cav_P_last_Pa - r.cav_P_first_Pa;
  // decision D129: tension relaxing toward zero (an overshoot past zero is not relaxation)
  const bool p_relaxes =
      r.cav_P_first_Pa < 0 && rise > 0 &&
      std::fabs(r.cav_P_last_Pa) <
          std::fabs(r.cav_P_first_Pa) -
              kResolvedSigmas * std::hypot(r.cav_P_first_se_Pa, r.cav_P_last_se_Pa) &&
      std::fabs(r.cav_P_last_Pa) < 0.5 * std::fabs(r.cav_P_first_Pa);
  r.cavitates = void_grows || p_relaxes;
  r.holds_blocks_ok = a.ok && b.ok && c.ok && d.ok && p1.ok && p2.ok;
  density_drift(in, r);
  classify(r);
  write_phase_h5(h5_path(dir), s, in, r);
}

} // namespace

PhaseCheckResult read_phase_check(const std::string& dir) {
  h5::File f(h5_path(dir), h5::File::Mode::read);
  PhaseCheckResult r;
  r.done = true;
  r.phase = f.read_string("/phase");
  r.solid = f.read_scalar("/solid") != 0.0;
  r.summary = f.read_string("/summary");
  r.temperature_K = f.read_scalar("/temperature");
  r.nve_T_first_K = f.read_scalar("/nve_temperature_first");
  r.nve_T_last_K = f.read_scalar("/nve_temperature_last");
  r.volume_m3 = f.read_scalar("/volume");
  r.hold_time_s = f.read_scalar("/hold_time");
  r.dt_s = f.read_scalar("/acf/dt");
  r.acf_t_s = f.read_vector("/acf/t");
  r.acf_G_Pa = f.read_vector("/acf/G");
  r.acf_G_se_Pa = f.read_vector("/acf/G_stderr");
  r.tau_int_s = f.read_scalar("/acf/tau_int");
  r.block_s = f.read_scalar("/acf/block_length");
  r.blocks_ok = f.read_scalar("/acf/blocks_ok") != 0.0;
  r.holds_blocks_ok = f.read_scalar("/holds_blocks_ok") != 0.0;
  const std::pair<const char*, double*> vals[] = {
      {"/G_t0", &r.G_t0_Pa},
      {"/G_t0_stderr", &r.G_t0_se_Pa},
      {"/G_plateau", &r.G_plateau_Pa},
      {"/G_plateau_stderr", &r.G_plateau_se_Pa},
      {"/G_at_plateau_time", &r.G_at_plateau_time_Pa},
      {"/G_at_plateau_time_stderr", &r.G_at_plateau_time_se_Pa},
      {"/G_acf_late", &r.G_acf_late_Pa},
      {"/G_acf_late_stderr", &r.G_acf_late_se_Pa},
      {"/G_acf_hold", &r.G_acf_hold_Pa},
      {"/G_acf_hold_stderr", &r.G_acf_hold_se_Pa},
      {"/G_hold", &r.G_hold_Pa},
      {"/G_hold_stderr", &r.G_hold_se_Pa},
      {"/K", &r.K_Pa},
      {"/K_stderr", &r.K_se_Pa},
      {"/cavitation/P_first", &r.cav_P_first_Pa},
      {"/cavitation/P_first_stderr", &r.cav_P_first_se_Pa},
      {"/cavitation/P_last", &r.cav_P_last_Pa},
      {"/cavitation/P_last_stderr", &r.cav_P_last_se_Pa},
      {"/cavitation/strain", &r.cav_strain},
      {"/cavitation/void_first", &r.cav_void_first},
      {"/cavitation/void_last", &r.cav_void_last},
      {"/density_drift", &r.drift_kg_m3_s},
      {"/density_drift_stderr", &r.drift_se_kg_m3_s}};
  for (const auto& [n, p] : vals)
    *p = f.read_scalar(n);
  r.cavitates = f.read_scalar("/cavitation/cavitates") != 0.0;
  return r;
}

PhaseCheckResult run_phase_check(const PhaseCheckSpec& spec, const PhaseCheckInput& in,
                                 const std::string& dir, bool resume, int ranks) {
  spec.validate("<phase_check>");
  md::lammps_path(in.start_state, "restart");
  make_output_directory(dir);
  if (resume && fs::exists(h5_path(dir))) {
    std::cerr << "  phase check: done (resumed)\n";
    return read_phase_check(dir);
  }
  const std::string log = (fs::path(dir) / "phase.log").string();
  std::cerr << fmt::format("  phase check: running (log {})\n", log) << std::flush;
  const md::StageOutcome o = md::run_stage(
      {"phase check", log, {}, ranks},
      md::stoppable([spec, in, dir](md::Lammps& l) { phase_child(l, spec, in, dir); }));
  pnc::throw_if_stopped("the phase check stopped; rerun with --resume to repeat it");
  if (!o.ok) md::throw_stage_failure(o, "stage phase check");
  PhaseCheckResult r = read_phase_check(dir);
  std::cerr << fmt::format("  phase check: {} ({:.1f} s)\n  {}\n", r.phase, o.seconds, r.summary);
  return r;
}

} // namespace pnc::rve
