// Equilibration stages of a user system and the measurement of the cases' start state
// (units real). Decisions D123 (reference state), D122 (force field re-issued per stage).
#include "equilibrate_detail.hpp"
#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/version.hpp"
#include "pnc/md/box.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/md/stage_stop.hpp"
#include "pnc/rve/equilibrate.hpp"
#include "pnc/rve/user_system.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>

namespace pnc::rve {

namespace fs = std::filesystem;

namespace {

constexpr const char* kTraceUnits = "chunk means: T (K), PE (kcal/mol), P total (atm), P virial "
                                    "(atm), density (g/cm^3), volume (A^3)";

std::string in_dir(const std::string& dir, const std::string& stage, const char* ext) {
  return (fs::path(dir) / (stage + ext)).string();
}
std::string stage_name(std::size_t i, const UserStage& s) {
  return fmt::format("stage_{}_{}", i + 1, s.kind);
}

/// Reads the state (data file or restart) and issues the force field: the same commands in
/// every stage and case (DeformSpec::force_field), decision D122.
void load(md::Lammps& l, const UserSystem& u, const std::string& file, bool restart) {
  l.cmd("units real");
  l.cmd("atom_style " + u.atom_style);
  if (restart) {
    l.cmd("read_restart " + md::lammps_path(file, "restart"));
  } else {
    // styles first, so that Coeffs sections of the data file can be read
    for (const auto& c : u.forcefield)
      for (const char* st :
           {"pair_style", "bond_style", "angle_style", "dihedral_style", "improper_style"})
        if (c.rfind(std::string(st) + " ", 0) == 0) l.cmd(c);
    l.cmd("read_data " + md::lammps_path(file, "data file"));
  }
  l.cmds(u.forcefield);
  l.cmd("reset_timestep 0");
  l.cmd("compute pnc_pv all pressure NULL virial");
  l.cmd("variable pnc_rho equal density");
  l.cmd("variable pnc_vol equal vol");
  l.cmd("thermo_style custom step temp pe press c_pnc_pv density vol");
}

using Rows = std::vector<std::array<double, 6>>;

void write_h5(const std::string& path, const std::string& stage, const std::string& criterion,
              const Rows& rows, const std::string& recipe_json) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    eqdetail::stamp_stage_file(f, stage, criterion, recipe_json);
    if (!rows.empty()) {
      h5::RowMatrix m(static_cast<Eigen::Index>(rows.size()), 6);
      for (std::size_t i = 0; i < rows.size(); ++i)
        for (int c = 0; c < 6; ++c)
          m(static_cast<Eigen::Index>(i), c) = rows[i][c];
      f.write_matrix("/trace", m);
      f.set_attr("/trace", "units", kTraceUnits);
    }
  }
  out.commit();
}

double mean_of(const Rows& r, int c, std::size_t from) {
  double s = 0;
  for (std::size_t i = from; i < r.size(); ++i)
    s += r[i][c];
  return s / static_cast<double>(r.size() - from);
}

void dynamic_stage(md::Lammps& l, const UserStage& s, std::uint64_t seed,
                   const std::string& restart, const std::string& h5path, const std::string& name,
                   const std::string& rj) {
  l.cmd(fmt::format("timestep {:.10g}", s.timestep_fs));
  l.cmd("run 0");
  const double t0 = l.thermo("temp");
  const bool created = !(t0 > 1e-9);
  if (created) // a state without velocities (data file, minimised state)
    l.cmd(fmt::format("velocity all create {:.10g} {} dist gaussian mom yes", s.temperature, seed));
  if (s.kind == "langevin") {
    l.cmd("fix pnc_nve all nve");
    l.cmd(fmt::format("fix pnc_lan all langevin {:.10g} {:.10g} {:.10g} {} zero yes", s.temperature,
                      s.t_end(), s.damp_fs, seed + 1));
  } else {
    l.cmd(fmt::format("fix pnc_npt all npt temp {0:.10g} {1:.10g} {2:.10g} iso {3:.10g} {3:.10g} "
                      "{4:.10g}",
                      s.temperature, s.t_end(), s.damp_fs, s.pressure_atm, s.pdamp_fs));
  }
  // 10 chunks (a multiple of 10 steps each; steps >= 100), sampled every 10 steps: a pressure
  // compute every step would cost an MPI reduction per step
  const long chunk = s.steps / 100 * 10;
  l.cmd(fmt::format("thermo {}", chunk));
  l.cmd(fmt::format("fix pnc_avg all ave/time 10 {1} {0} c_thermo_temp c_thermo_pe c_thermo_press "
                    "c_pnc_pv v_pnc_rho v_pnc_vol",
                    chunk, chunk / 10));
  Rows rows;
  for (int i = 0; i < 10; ++i) {
    l.cmd(fmt::format("run {} start 0 stop {}", chunk, s.steps)); // one ramp over the stage
    std::array<double, 6> r{};
    for (int c = 0; c < 6; ++c)
      r[c] = l.fix_value("pnc_avg", c);
    rows.push_back(r);
  }
  l.cmd("unfix pnc_avg");
  if (s.steps > 10 * chunk)
    l.cmd(fmt::format("run {} start 0 stop {}", s.steps - 10 * chunk, s.steps));
  std::string how = fmt::format("{} steps of {} fs, T {:.1f} -> {:.1f} K", s.steps, s.timestep_fs,
                                s.temperature, s.t_end());
  if (s.kind == "npt") {
    l.cmd("unfix pnc_npt");
    // decision D123: the state handed on has the mean volume of the second half (iso scaling)
    const double vmean = mean_of(rows, 5, rows.size() / 2);
    const md::LmpBox box = l.box(); // D123: iso scaling, the tilts with the lengths
    const double f = std::cbrt(vmean / box.volume());
    const std::string cmd = md::box_change(box, f * Eigen::Matrix3d::Identity(), "<npt stage>");
    if (!cmd.empty()) l.cmd(cmd);
    how += fmt::format(", NPT (iso) at {:.1f} atm; mean density of the second half {:.4f} g/cm3, "
                       "box set to its mean volume {:.1f} A^3",
                       s.pressure_atm, mean_of(rows, 4, rows.size() / 2), vmean);
  } else {
    how += ", NVE + Langevin";
  }
  how += fmt::format("; second half: T {:.1f} K, P {:.0f} atm (total){}",
                     mean_of(rows, 0, rows.size() / 2), mean_of(rows, 2, rows.size() / 2),
                     created ? "; velocities created at the start" : "");
  l.cmd("write_restart " + md::lammps_path(restart, "--out"));
  write_h5(h5path, name, how, rows, rj);
}

void minimize_stage(md::Lammps& l, const UserStage& s, const std::string& restart,
                    const std::string& h5path, const std::string& name, const std::string& rj) {
  l.cmd("run 0");
  const double e0 = l.thermo("pe");
  l.cmd("min_style cg");
  l.cmd(fmt::format("minimize 0.0 {:.10g} {} {}", s.ftol, s.max_iterations, 10 * s.max_iterations));
  l.cmd("run 0");
  const double e1 = l.thermo("pe"), fn = l.thermo("fnorm");
  l.cmd("write_restart " + md::lammps_path(restart, "--out"));
  write_h5(h5path, name,
           fmt::format("energy minimisation at fixed box (cg, ftol {:g} kcal/mol/A): PE {:.6g} -> "
                       "{:.6g} kcal/mol, force norm {:.3g} kcal/mol/A{}",
                       s.ftol, e0, e1, fn, fn <= s.ftol ? "" : " -- ftol NOT reached"),
           {}, rj);
}

/// Smallest distance between two atoms (bonded pairs included; minimum image in an orthogonal
/// periodic box); NaN for a triclinic box or more than 20000 atoms (not measured).
double min_distance(md::Lammps& l) {
  const md::LmpBox box = l.box();
  const auto& lo = box.lo;
  const auto& hi = box.hi;
  const auto x = l.gather("x", 3);
  const std::size_t n = x.size() / 3;
  if (box.xy != 0 || box.xz != 0 || box.yz != 0 || n > 20000 || n < 2)
    return std::numeric_limits<double>::quiet_NaN();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      double r2 = 0;
      for (int a = 0; a < 3; ++a) {
        const double L = hi[a] - lo[a];
        double d = x[3 * i + a] - x[3 * j + a];
        d -= L * std::round(d / L);
        r2 += d * d;
      }
      best = std::min(best, r2);
    }
  return std::sqrt(best);
}

} // namespace

EquilibratedState equilibrate_user(const UserSystem& u, const std::string& input,
                                   const std::string& dir, bool resume,
                                   const std::string& recipe_json, std::uint64_t seed, int ranks) {
  md::lammps_path(input, u.is_restart ? "restart" : "data file");
  md::lammps_path(in_dir(dir, "final", ".restart"), "--out");
  make_output_directory(dir);
  std::vector<std::string> names;
  auto stage = [&](const std::string& name, const md::StageBody& body) {
    if (resume && fs::exists(in_dir(dir, name, ".h5")) &&
        fs::exists(in_dir(dir, name, ".restart"))) {
      std::cerr << fmt::format("  equilibrate/{}: done (resumed)\n", name);
      return;
    }
    std::cerr << fmt::format("  equilibrate/{}: running (log {})\n", name,
                             in_dir(dir, name, ".log"))
              << std::flush;
    const md::StageOutcome o = md::run_stage(
        {"equilibrate/" + name, in_dir(dir, name, ".log"), {}, ranks}, md::stoppable(body));
    pnc::throw_if_stopped("stage equilibrate/" + name + " stopped; the finished stages are kept");
    if (!o.ok) md::throw_stage_failure(o, "stage equilibrate/" + name);
    std::cerr << fmt::format(
        "  equilibrate/{}: {} ({:.1f} s)\n", name,
        h5::File(in_dir(dir, name, ".h5"), h5::File::Mode::read).read_string("/criterion"),
        o.seconds);
  };
  std::string from = input;
  bool from_restart = u.is_restart;
  for (std::size_t i = 0; i < u.stages.size(); ++i) {
    const UserStage s = u.stages[i];
    const std::string name = stage_name(i, s);
    const std::string rs = in_dir(dir, name, ".restart"), hp = in_dir(dir, name, ".h5");
    const std::uint64_t sd = seed * 1000 + 10 * (i + 1);
    stage(name, [&, s, name, rs, hp, sd, from, from_restart](md::Lammps& l) {
      load(l, u, from, from_restart);
      if (s.kind == "minimize")
        minimize_stage(l, s, rs, hp, name, recipe_json);
      else
        dynamic_stage(l, s, sd, rs, hp, name, recipe_json);
    });
    names.push_back(name);
    from = rs;
    from_restart = true;
  }
  // the last dynamic stage's second half gives the finite-temperature means (decision D123)
  std::string last_dyn;
  for (std::size_t i = 0; i < u.stages.size(); ++i)
    if (u.stages[i].kind != "minimize") last_dyn = in_dir(dir, names[i], ".h5");
  if (!last_dyn.empty() && u.stages.back().kind == "minimize") last_dyn.clear();
  stage("final", [&](md::Lammps& l) {
    load(l, u, from, from_restart);
    l.cmd("run 0");
    double pt = l.thermo("press"), pv = l.compute_value("pnc_pv"), T = l.thermo("temp"), se = 0;
    const double rho = l.thermo("density");
    std::string how = "instantaneous values of the start state (run 0, no dynamics)";
    if (!last_dyn.empty()) {
      const auto m = h5::File(last_dyn, h5::File::Mode::read).read_matrix("/trace");
      const Eigen::Index n = m.rows(), h = n / 2, k = n - h;
      pt = m.col(2).tail(k).mean();
      pv = m.col(3).tail(k).mean();
      T = m.col(0).tail(k).mean();
      const double var =
          (m.col(2).tail(k).array() - pt).square().sum() / static_cast<double>(k - 1);
      se = std::sqrt(var / static_cast<double>(k));
      how = fmt::format("P and T: means of the second half ({} chunks) of {}, s.e. from the chunk "
                        "means; density of the start state",
                        k, fs::path(last_dyn).stem().string());
    }
    const double dmin = min_distance(l);
    l.cmd("write_restart " + md::lammps_path(in_dir(dir, "final", ".restart"), "--out"));
    const std::string crit = fmt::format(
        "{}; density {:.4f} g/cm3, P {:.1f} +- {:.1f} atm (total), {:.1f} atm (virial only), T "
        "{:.1f} K, smallest atom distance {:.3f} A",
        how, rho, pt, se, pv, T, dmin);
    AtomicOutput out(in_dir(dir, "final", ".h5"));
    {
      h5::File f(out.temp_path(), h5::File::Mode::truncate);
      h5::write_provenance(f);
      eqdetail::stamp_stage_file(f, "final", crit, recipe_json);
      f.write_string("/ensemble", "user stages");
      const std::pair<const char*, std::pair<double, const char*>> vals[] = {
          {"/density", {rho, "g/cm^3"}},
          {"/pressure_total", {pt, "atm"}},
          {"/pressure_total_stderr", {se, "atm"}},
          {"/pressure_virial", {pv, "atm"}},
          {"/temperature", {T, "K"}},
          {"/void_fraction", {std::numeric_limits<double>::quiet_NaN(), "1 (not measured)"}},
          {"/min_distance", {dmin, "A"}}};
      for (const auto& [name, v] : vals) {
        f.write_scalar(name, v.first);
        f.set_attr(name, "units", v.second);
      }
    }
    out.commit();
  });
  EquilibratedState e = read_equilibrated(dir);
  std::vector<std::string> crit;
  for (const auto& n : names)
    crit.push_back(n + ": " +
                   h5::File(in_dir(dir, n, ".h5"), h5::File::Mode::read).read_string("/criterion"));
  crit.insert(crit.end(), e.criteria.begin(), e.criteria.end());
  e.criteria = crit;
  return e;
}

} // namespace pnc::rve
