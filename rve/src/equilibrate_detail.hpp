#pragma once
// Helpers shared by the equilibration protocols (equilibrate.cpp: polymer and composite;
// equilibrate_glass.cpp: the bead-spring glass). Private to rve/src. Units real.
#include "pnc/md/lammps_path.hpp"
#include "pnc/rve/equilibrate.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/version.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/md/stage_stop.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace pnc::rve::eqdetail {

inline std::string p(const std::string& dir, const std::string& stage, const char* ext) {
  return (std::filesystem::path(dir) / (stage + ext)).string();
}

/// Means over chunks of a run: T (K), PE (kcal/mol), P total (atm), P virial (atm),
/// density (g/cm3), volume (A^3).
struct Trace {
  std::vector<std::array<double, 6>> rows;
  double mean(int c, std::size_t from = 0) const {
    double s = 0;
    for (std::size_t i = from; i < rows.size(); ++i)
      s += rows[i][c];
    return s / static_cast<double>(rows.size() - from);
  }
};

inline void define_measures(md::Lammps& l) {
  l.cmd("compute pnc_pv all pressure NULL virial");
  l.cmd("variable pnc_rho equal density");
  l.cmd("variable pnc_vol equal vol");
  l.cmd("variable pnc_pe equal pe");
  l.cmd("thermo_style custom step temp pe press c_pnc_pv density vol");
}

/// `whole_ramp`: thermostat ramps (Tstart -> Tstop) span all chunks (run ... start/stop),
/// not each chunk; assumes the timestep counter is 0 at the call. `temp`: the temperature
/// compute traced (thermo_temp = all atoms; a group's when part of the system is frozen).
inline void run_chunks(md::Lammps& l, long steps, int chunks, Trace& t, bool whole_ramp = false,
                       const std::string& temp = "thermo_temp") {
  if (steps <= 0) return;
  long chunk = std::max<long>(10, (steps / chunks) / 10 * 10);
  const int n = static_cast<int>((steps + chunk - 1) / chunk);
  l.cmd(fmt::format("thermo {}", chunk));
  l.cmd(fmt::format("fix pnc_avg all ave/time 10 {} {} c_{} c_thermo_pe c_thermo_press "
                    "c_pnc_pv v_pnc_rho v_pnc_vol",
                    chunk / 10, chunk, temp));
  for (int i = 0; i < n; ++i) {
    if (whole_ramp)
      l.cmd(fmt::format("run {} start 0 stop {}", chunk, chunk * n));
    else
      l.cmd(fmt::format("run {}", chunk));
    std::array<double, 6> r{};
    for (int c = 0; c < 6; ++c)
      r[c] = l.fix_value("pnc_avg", c);
    t.rows.push_back(r);
  }
  l.cmd("unfix pnc_avg");
}

inline void read_state(md::Lammps& l, const std::vector<std::string>& ffcmds,
                       const EquilibrateSpec& s, const std::string& restart) {
  l.cmd("units real");
  l.cmd("atom_style molecular");
  l.cmd("read_restart " + md::lammps_path(restart, "restart"));
  l.cmds(ffcmds);
  l.cmd("reset_timestep 0");
  l.cmd(fmt::format("timestep {:.10g}", s.timestep_fs));
  define_measures(l);
}

inline double min_pair_distance(md::Lammps& l, double cutoff, const std::string& group = "all") {
  // neighbour pairs within the pair cutoff (excluded 1-2/1-3/1-4 pairs are not listed)
  l.cmd("compute pnc_pl " + group + " pair/local dist");
  l.cmd("compute pnc_dmin all reduce min c_pnc_pl");
  l.cmd("run 0");
  const double d = l.compute_value("pnc_dmin");
  l.cmd("uncompute pnc_dmin");
  l.cmd("uncompute pnc_pl");
  return std::min(d, cutoff);
}

/// The attributes and datasets every equilibration-stage .h5 starts with (format, stage, pnc
/// version, creation time, end criterion, recipe).
inline void stamp_stage_file(h5::File& f, const std::string& stage, const std::string& criterion,
                             const std::string& recipe_json) {
  f.set_attr("/", "format", "pnc-rve-equilibration-stage");
  f.set_attr("/", "stage", stage);
  f.set_attr("/", "pnc_version", version_string());
  f.set_attr("/", "created_utc", utc_timestamp());
  f.write_string("/criterion", criterion);
  f.write_string("/recipe", recipe_json.empty() ? "{}" : recipe_json);
}

inline void write_stage(const std::string& path, const std::string& stage,
                        const std::string& criterion, const Trace& t,
                        const std::string& recipe_json) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    stamp_stage_file(f, stage, criterion, recipe_json);
    if (!t.rows.empty()) {
      h5::RowMatrix m(static_cast<Eigen::Index>(t.rows.size()), 6);
      for (std::size_t i = 0; i < t.rows.size(); ++i)
        for (int c = 0; c < 6; ++c)
          m(static_cast<Eigen::Index>(i), c) = t.rows[i][c];
      f.write_matrix("/trace", m);
      f.set_attr("/trace", "units",
                 "chunk means: T (K), PE (kcal/mol), P total (atm), P virial (atm), density "
                 "(g/cm^3), volume (A^3)");
    }
  }
  out.commit();
}

/// The end of a pushoff stage (either force field): the restart `dir`/pushoff.restart and the
/// record `dir`/pushoff.h5 whose criterion says the smallest distance `d` (A) between `pairs`
/// ("non-excluded", "unbonded") against `target` (A), met or not, after `round` rounds.
template <class Spec>
void finish_pushoff(md::Lammps& l, const std::string& dir, const char* pairs, double d,
                    double target, const Spec& s, int round, const Trace& t,
                    const std::string& recipe_json) {
  const bool met = d >= target;
  l.cmd("write_restart " + md::lammps_path(p(dir, "pushoff", ".restart"), "--out"));
  write_stage(p(dir, "pushoff", ".h5"), "pushoff",
              fmt::format("min {} distance {:.3f} A {} {:.3f} A ({:.2f} sigma) after {} round(s) "
                          "of {} steps{}",
                          pairs, d, met ? ">=" : "<", target, s.pushoff_min_distance_sigma,
                          std::min(round, s.pushoff_max_rounds), s.pushoff_steps,
                          met ? "" : " -- NOT met; continuing with minimisation"),
              t, recipe_json);
}

/// How a pushoff stage pushes: the `fix adapt` target of the soft prefactor (e.g. "pair soft a
/// * *"), the command that fixes the prefactor at pushoff_A_max after the ramp, the group whose
/// pairs are measured, and what those pairs are called in the record ("non-excluded",
/// "unbonded").
struct PushoffPairs {
  std::string adapt;
  std::string coeff_at_max;
  std::string group;
  const char* name;
};

/// The rounds of a pushoff stage (either force field) and its end: round 1 ramps the soft
/// prefactor from 0 to s.pushoff_A_max over pushoff_steps, later rounds run at A_max, until no
/// pair of `pp.group` within 2^(1/6) sigma (A) is closer than pushoff_min_distance_sigma * sigma
/// or after pushoff_max_rounds rounds; then finish_pushoff writes the restart and the record.
template <class Spec>
void run_pushoff(md::Lammps& l, const Spec& s, double sigma, const PushoffPairs& pp,
                 const std::string& dir, const std::string& recipe_json) {
  Trace t;
  double d = 0;
  int round = 0;
  const double target = s.pushoff_min_distance_sigma * sigma;
  for (round = 1; round <= s.pushoff_max_rounds; ++round) {
    if (round == 1) {
      l.cmd(fmt::format("variable pnc_A equal ramp(0,{:.10g})", s.pushoff_A_max));
      l.cmd("fix pnc_adapt all adapt 1 " + pp.adapt + " v_pnc_A");
      run_chunks(l, s.pushoff_steps, 5, t, true); // ramp(0, A_max) over the whole round
      l.cmd("unfix pnc_adapt");
      l.cmd(pp.coeff_at_max);
    } else {
      run_chunks(l, s.pushoff_steps, 5, t);
    }
    d = min_pair_distance(l, std::pow(2.0, 1.0 / 6.0) * sigma, pp.group);
    if (d >= target) break;
  }
  finish_pushoff(l, dir, pp.name, d, target, s, round, t, recipe_json);
}

/// Stage "final" (equilibrate.hpp stage 6): from `from_restart`, NPT at spec.pressure_atm
/// (ensemble "npt"; with the clay on x2, x3 only), the box set to the mean volume of the second
/// half, NVT (Langevin) for final_steps, then the measurement written to `dir`/final.h5 and the
/// state to `dir`/final.restart. `cutoff` (A) bounds the reported smallest pair distance, `sig`
/// (A) is the void-fraction probe radius. Defined in equilibrate.cpp.
void final_stage(md::Lammps& l, const std::vector<std::string>& ffcmds, const EquilibrateSpec& s,
                 const std::string& dir, const std::string& from_restart, bool with_clay,
                 double cutoff, double sig, const std::string& recipe_json);

/// Runs one equilibration stage `name` in a supervised child (skipped when `resume` and its
/// results exist), then prints the end criterion the stage wrote to `<dir>/<name>.h5`.
/// Throws (throw_stage_failure: pnc::ToolError with LAMMPS's message) when the stage fails.
inline void run_equilibration_stage(const std::string& dir, const std::string& name,
                                    const md::StageBody& body, bool resume, int ranks) {
  namespace fs = std::filesystem;
  if (resume && fs::exists(p(dir, name, ".h5")) && fs::exists(p(dir, name, ".restart"))) {
    std::cerr << fmt::format("  equilibrate/{}: done (resumed)\n", name);
    return;
  }
  std::cerr << fmt::format("  equilibrate/{}: running (log {})\n", name, p(dir, name, ".log"))
            << std::flush;
  const md::StageOutcome o =
      md::run_stage({"equilibrate/" + name, p(dir, name, ".log"), {}, ranks}, md::stoppable(body));
  pnc::throw_if_stopped("stage equilibrate/" + name + " stopped; the finished stages are kept");
  if (!o.ok) md::throw_stage_failure(o, "stage equilibrate/" + name);
  const std::string crit =
      h5::File(p(dir, name, ".h5"), h5::File::Mode::read).read_string("/criterion");
  std::cerr << fmt::format("  equilibrate/{}: {} ({:.1f} s)\n", name, crit, o.seconds);
}

} // namespace pnc::rve::eqdetail
