// Equilibration protocol (docs/theory.md §3.3, D19), one child process per stage. Units real.
#include "pnc/rve/equilibrate.hpp"

#include "pnc/md/box.hpp"

#include "equilibrate_detail.hpp"

#include "pnc/md/lammps_path.hpp"
#include "pnc/md/stage_stop.hpp"
#include "pnc/rve/clay.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/core/version.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

namespace pnc::rve {

namespace fs = std::filesystem;

void EquilibrateSpec::validate(const std::string& source) const {
  auto pos = [&](const char* f, double v) {
    if (!(v > 0) || !std::isfinite(v)) fail(source, f, fmt::format("{}", v), "must be > 0");
  };
  auto nonneg = [&](const char* f, long v) {
    if (v < 0) fail(source, f, std::to_string(v), "must be >= 0");
  };
  pos("equilibrate.timestep_fs", timestep_fs);
  pos("equilibrate.temperature", temperature);
  pos("equilibrate.damp_fs", damp_fs);
  pos("equilibrate.hot_temperature", hot_temperature);
  pos("equilibrate.pushoff_A_max", pushoff_A_max);
  pos("equilibrate.steady_tolerance", steady_tolerance);
  pos("equilibrate.pdamp_fs", pdamp_fs);
  nonneg("equilibrate.hot_steps", hot_steps);
  nonneg("equilibrate.cool_steps", cool_steps);
  nonneg("equilibrate.clay_steps", clay_steps);
  nonneg("equilibrate.npt_steps", npt_steps);
  if (pushoff_steps < 100)
    fail(source, "equilibrate.pushoff_steps", std::to_string(pushoff_steps), "must be >= 100");
  if (langevin_chunk_steps < 100)
    fail(source, "equilibrate.langevin_chunk_steps", std::to_string(langevin_chunk_steps),
         "must be >= 100");
  if (final_steps < 100)
    fail(source, "equilibrate.final_steps", std::to_string(final_steps), "must be >= 100");
  if (langevin_max_chunks < 2)
    fail(source, "equilibrate.langevin_max_chunks", std::to_string(langevin_max_chunks),
         "must be >= 2 (the criterion compares two chunks)");
  if (pushoff_max_rounds < 1)
    fail(source, "equilibrate.pushoff_max_rounds", std::to_string(pushoff_max_rounds),
         "must be >= 1");
  if (!(pushoff_min_distance_sigma > 0 && pushoff_min_distance_sigma < 1.2))
    fail(source, "equilibrate.pushoff_min_distance_sigma",
         fmt::format("{}", pushoff_min_distance_sigma), "must be in (0, 1.2)");
  if (ensemble != "npt" && ensemble != "nvt")
    fail(source, "equilibrate.ensemble", ensemble,
         "must be \"npt\" (set pressure) or \"nvt\" (set density)");
  if (!std::isfinite(pressure_atm) || std::fabs(pressure_atm) > 1e5)
    fail(source, "equilibrate.pressure_atm", fmt::format("{}", pressure_atm),
         "must be finite, |p| <= 1e5 atm");
  if (seed < 1 || seed > 900000000)
    fail(source, "seed", std::to_string(seed), "must be in 1..900000000 (LAMMPS seeds)");
}

double void_fraction(const std::vector<double>& x, const double lo[3], const double hi[3],
                     double probe, double h) {
  int nc[3], ng[3];
  double L[3], w[3];
  for (int a = 0; a < 3; ++a) {
    L[a] = hi[a] - lo[a];
    nc[a] = std::max(1, static_cast<int>(std::floor(L[a] / probe)));
    w[a] = L[a] / nc[a];
    ng[a] = std::max(1, static_cast<int>(std::round(L[a] / h)));
  }
  auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
  std::vector<std::vector<std::size_t>> cells(static_cast<std::size_t>(nc[0]) * nc[1] * nc[2]);
  auto cidx = [&](int i, int j, int k) {
    return (static_cast<std::size_t>(wrap(i, nc[0])) * nc[1] + wrap(j, nc[1])) * nc[2] +
           wrap(k, nc[2]);
  };
  auto ccoord = [&](double p, int a) {
    double u = std::fmod(p - lo[a], L[a]);
    if (u < 0) u += L[a];
    return std::min(nc[a] - 1, static_cast<int>(u / w[a]));
  };
  const std::size_t n = x.size() / 3;
  for (std::size_t i = 0; i < n; ++i)
    cells[cidx(ccoord(x[3 * i], 0), ccoord(x[3 * i + 1], 1), ccoord(x[3 * i + 2], 2))].push_back(i);
  const double p2 = probe * probe;
  long empty = 0, total = 0;
  for (int gi = 0; gi < ng[0]; ++gi)
    for (int gj = 0; gj < ng[1]; ++gj)
      for (int gk = 0; gk < ng[2]; ++gk) {
        const double g[3] = {lo[0] + (gi + 0.5) * L[0] / ng[0], lo[1] + (gj + 0.5) * L[1] / ng[1],
                             lo[2] + (gk + 0.5) * L[2] / ng[2]};
        const int c[3] = {ccoord(g[0], 0), ccoord(g[1], 1), ccoord(g[2], 2)};
        bool covered = false;
        for (int dx = -1; dx <= 1 && !covered; ++dx)
          for (int dy = -1; dy <= 1 && !covered; ++dy)
            for (int dz = -1; dz <= 1 && !covered; ++dz)
              for (std::size_t j : cells[cidx(c[0] + dx, c[1] + dy, c[2] + dz)]) {
                double r2 = 0;
                for (int a = 0; a < 3; ++a) {
                  double d = x[3 * j + a] - g[a];
                  d -= L[a] * std::round(d / L[a]);
                  r2 += d * d;
                }
                if (r2 < p2) {
                  covered = true;
                  break;
                }
              }
        ++total;
        empty += covered ? 0 : 1;
      }
  return static_cast<double>(empty) / static_cast<double>(total);
}

using namespace eqdetail;

void eqdetail::final_stage(md::Lammps& l, const std::vector<std::string>& ffcmds,
                           const EquilibrateSpec& s, const std::string& dir,
                           const std::string& from_restart, bool with_clay, double cutoff,
                           double sig, const std::string& recipe_json) {
  const std::string mob = with_clay ? "pnc_poly" : "all";
  read_state(l, ffcmds, s, from_restart);
  Trace tn, tf;
  std::string how;
  if (s.ensemble == "npt") {
    if (with_clay) // x1 (along the platelet) held, x2 and x3 coupled
      l.cmd(fmt::format("fix pnc_npt all npt temp {0:.10g} {0:.10g} {1:.10g} y {2:.10g} "
                        "{2:.10g} {3:.10g} z {2:.10g} {2:.10g} {3:.10g} couple yz",
                        s.temperature, s.damp_fs, s.pressure_atm, s.pdamp_fs));
    else
      l.cmd(fmt::format("fix pnc_npt all npt temp {0:.10g} {0:.10g} {1:.10g} iso {2:.10g} "
                        "{2:.10g} {3:.10g}",
                        s.temperature, s.damp_fs, s.pressure_atm, s.pdamp_fs));
    run_chunks(l, s.npt_steps, 10, tn);
    l.cmd("unfix pnc_npt");
    const double vmean = tn.mean(5, tn.rows.size() / 2);
    const md::LmpBox box = l.box();
    const double ratio = vmean / box.volume();
    const double f = with_clay ? std::sqrt(ratio) : std::cbrt(ratio);
    Eigen::Matrix3d F = f * Eigen::Matrix3d::Identity();
    if (with_clay) F(0, 0) = 1.0; // x1 held
    const std::string cmd = md::box_change(box, F, "<equilibrate>");
    if (!cmd.empty()) l.cmd(cmd);
    how = fmt::format(
        "NPT at {:.1f} atm{} for {} steps (mean density of the second half {:.4f} "
        "g/cm3), box set to its mean volume {:.1f} A^3, then NVT (Langevin) for {} steps",
        s.pressure_atm, with_clay ? " on x2, x3 (coupled; x1 held)" : "", s.npt_steps,
        tn.mean(4, tn.rows.size() / 2), vmean, s.final_steps);
  } else {
    how = fmt::format("NVT at the build density, Langevin for {} steps", s.final_steps);
  }
  l.cmd("fix pnc_nve all nve");
  l.cmd(fmt::format("fix pnc_lan all langevin {0:.10g} {0:.10g} {1:.10g} {2}", s.temperature,
                    s.damp_fs, s.seed + 5));
  run_chunks(l, s.final_steps, 10, tf);
  l.cmd("unfix pnc_lan");
  l.cmd("unfix pnc_nve");
  const double dmin = min_pair_distance(l, cutoff, mob);
  const md::LmpBox box = l.box();
  const double vf = void_fraction(l.gather("x", 3), box.lo.data(), box.hi.data(), sig, 1.0);
  l.cmd("write_restart " + md::lammps_path(p(dir, "final", ".restart"), "--out"));
  // P over chunks: standard error from the chunk means
  double m = tf.mean(2), var = 0;
  for (const auto& r : tf.rows)
    var += (r[2] - m) * (r[2] - m);
  const double se = std::sqrt(var / static_cast<double>(tf.rows.size() - 1) /
                              static_cast<double>(tf.rows.size()));
  const std::string crit = fmt::format(
      "{}; density {:.4f} g/cm3, P {:.0f} +- {:.0f} atm (total), {:.0f} atm (virial only), "
      "T {:.1f} K, void fraction {:.4f}, min pair distance {:.3f} A",
      how, tf.mean(4), m, se, tf.mean(3), tf.mean(0), vf, dmin);
  AtomicOutput out(p(dir, "final", ".h5"));
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    stamp_stage_file(f, "final", crit, recipe_json);
    f.write_string("/ensemble", s.ensemble);
    f.write_scalar("/density", tf.mean(4));
    f.set_attr("/density", "units", "g/cm^3");
    f.write_scalar("/pressure_total", m);
    f.set_attr("/pressure_total", "units", "atm");
    f.write_scalar("/pressure_total_stderr", se);
    f.set_attr("/pressure_total_stderr", "units", "atm");
    f.write_scalar("/pressure_virial", tf.mean(3));
    f.set_attr("/pressure_virial", "units", "atm");
    f.write_scalar("/temperature", tf.mean(0));
    f.set_attr("/temperature", "units", "K");
    f.write_scalar("/void_fraction", vf);
    f.set_attr("/void_fraction", "definition",
               "fraction of the points of a 1 A grid farther than sigma from every bead centre");
    f.write_scalar("/min_distance", dmin);
    f.set_attr("/min_distance", "units", "A");
    auto put = [&](const char* name, const Trace& t) {
      if (t.rows.empty()) return;
      h5::RowMatrix mm(static_cast<Eigen::Index>(t.rows.size()), 6);
      for (std::size_t i = 0; i < t.rows.size(); ++i)
        for (int c = 0; c < 6; ++c)
          mm(static_cast<Eigen::Index>(i), c) = t.rows[i][c];
      f.write_matrix(name, mm);
      f.set_attr(name, "units",
                 "chunk means: T (K), PE (kcal/mol), P total (atm), P virial (atm), density "
                 "(g/cm^3), volume (A^3)");
    };
    put("/trace", tf);
    put("/trace_npt", tn);
  }
  out.commit();
}

EquilibratedState read_equilibrated(const std::string& dir) {
  const std::string path = p(dir, "final", ".h5");
  h5::File f(path, h5::File::Mode::read);
  EquilibratedState e;
  e.restart = p(dir, "final", ".restart");
  e.density = f.read_scalar("/density");
  e.pressure_virial = f.read_scalar("/pressure_virial");
  e.pressure_total = f.read_scalar("/pressure_total");
  e.pressure_total_se = f.read_scalar("/pressure_total_stderr");
  e.temperature = f.read_scalar("/temperature");
  e.void_fraction = f.read_scalar("/void_fraction");
  e.min_distance = f.read_scalar("/min_distance");
  for (const char* st : {"pushoff", "hot", "clay", "cool", "langevin", "melt", "quench", "final"}) {
    const std::string sp = p(dir, st, ".h5");
    if (fs::exists(sp))
      e.criteria.push_back(std::string(st) + ": " +
                           h5::File(sp, h5::File::Mode::read).read_string("/criterion"));
  }
  return e;
}

namespace {
// What the stages of one equilibration read (units real; sig: the polymer's LJ sigma, A; mob:
// the group that moves while the clay is frozen).
struct Protocol {
  const std::string& data_file;
  const EquilibrateSpec& s;
  const std::string& dir;
  const std::vector<std::string>& ffcmds;
  const std::string& mob;
  const std::string& recipe_json;
  double sig;
  bool with_clay;
};

// Stage "pushoff": a soft potential ramped up until no non-excluded pair is closer than
// pushoff_min_distance_sigma (or pushoff_max_rounds rounds), under Langevin with limited moves.
void pushoff_stage(md::Lammps& l, const Protocol& pr) {
  const std::string& data_file = pr.data_file;
  const EquilibrateSpec& s = pr.s;
  const std::string& dir = pr.dir;
  const std::vector<std::string>& ffcmds = pr.ffcmds;
  const std::string& mob = pr.mob;
  const std::string& recipe_json = pr.recipe_json;
  const double sig = pr.sig;
  l.cmd("units real");
  l.cmd("atom_style molecular");
  l.cmd("read_data " + md::lammps_path(data_file, "data file"));
  l.cmds(ffcmds);
  l.cmd(fmt::format("pair_style soft {:.10g}", std::pow(2.0, 1.0 / 6.0) * sig));
  l.cmd("pair_coeff * * 0.0");
  l.cmd(fmt::format("timestep {:.10g}", s.timestep_fs));
  define_measures(l);
  l.cmd(fmt::format("velocity {} create {:.10g} {} dist gaussian mom yes", mob, s.temperature,
                    s.seed));
  l.cmd("fix pnc_lim " + mob + " nve/limit 0.1");
  l.cmd(fmt::format("fix pnc_lan {} langevin {:.10g} {:.10g} {:.10g} {}", mob, s.temperature,
                    s.temperature, s.damp_fs, s.seed + 1));
  run_pushoff(l, s, sig,
              {"pair soft a * *", fmt::format("pair_coeff * * {:.10g}", s.pushoff_A_max), mob,
               "non-excluded"},
              dir, recipe_json);
}

// Stage "hot": minimised (clay frozen), then hot_steps at hot_temperature by velocity rescaling
// (the first 1000 steps with limited displacement).
void hot_stage(md::Lammps& l, const Protocol& pr) {
  const EquilibrateSpec& s = pr.s;
  const std::string& dir = pr.dir;
  const std::vector<std::string>& ffcmds = pr.ffcmds;
  const std::string& mob = pr.mob;
  const std::string& recipe_json = pr.recipe_json;
  const bool with_clay = pr.with_clay;
  read_state(l, ffcmds, s, p(dir, "pushoff", ".restart"));
  if (with_clay) l.cmd("fix pnc_frz pnc_clay setforce 0.0 0.0 0.0");
  l.cmd("minimize 1.0e-4 1.0e-6 1000 10000");
  if (with_clay) l.cmd("unfix pnc_frz");
  l.cmd("reset_timestep 0");
  l.cmd(fmt::format("velocity {} create {:.10g} {} dist gaussian mom yes", mob, s.hot_temperature,
                    s.seed + 2));
  l.cmd("fix pnc_lim " + mob + " nve/limit 0.1");
  l.cmd(fmt::format("fix pnc_rs {} temp/rescale 10 {:.10g} {:.10g} 10.0 1.0", mob,
                    s.hot_temperature, s.hot_temperature));
  // with the clay frozen the traced temperature is the polymer's (all atoms would dilute it
  // by the clay's zero velocities)
  const std::string temp = with_clay ? "pnc_tmob" : "thermo_temp";
  if (with_clay) l.cmd("compute pnc_tmob " + mob + " temp");
  Trace t;
  run_chunks(l, std::min<long>(1000, s.hot_steps), 1, t, false, temp); // limited displacement
  l.cmd("unfix pnc_lim");
  l.cmd("fix pnc_nve " + mob + " nve");
  run_chunks(l, s.hot_steps - std::min<long>(1000, s.hot_steps), 10, t, false, temp);
  l.cmd("write_restart " + md::lammps_path(p(dir, "hot", ".restart"), "--out"));
  write_stage(p(dir, "hot", ".h5"), "hot",
              fmt::format("{} steps at {:.0f} K by velocity rescaling; mean T{} of the second "
                          "half {:.1f} K",
                          s.hot_steps, s.hot_temperature, with_clay ? " (polymer)" : "",
                          t.mean(0, t.rows.size() / 2)),
              t, recipe_json);
}

// Stage "clay" (composite only): the clay relaxes with the polymer held fixed.
void clay_stage(md::Lammps& l, const Protocol& pr) {
  const EquilibrateSpec& s = pr.s;
  const std::string& dir = pr.dir;
  const std::vector<std::string>& ffcmds = pr.ffcmds;
  const std::string& recipe_json = pr.recipe_json;
  read_state(l, ffcmds, s, p(dir, "hot", ".restart"));
  // the source's clay relaxation (docs/theory.md §3.3, D25): the polymer is held fixed, the
  // clay relaxes in its field
  l.cmd("velocity pnc_poly set 0.0 0.0 0.0");
  l.cmd("fix pnc_frz pnc_poly setforce 0.0 0.0 0.0");
  l.cmd("run 0");
  const double e0 = l.thermo("pe");
  l.cmd("minimize 1.0e-6 1.0e-8 2000 20000");
  l.cmd("run 0");
  const double e1 = l.thermo("pe");
  l.cmd("unfix pnc_frz");
  l.cmd("reset_timestep 0");
  l.cmd(fmt::format("velocity pnc_clay create {:.10g} {} dist gaussian mom yes", s.temperature,
                    s.seed + 6));
  l.cmd("fix pnc_nve pnc_clay nve/limit 0.05");
  l.cmd(fmt::format("fix pnc_lan pnc_clay langevin {0:.10g} {0:.10g} {1:.10g} {2}", s.temperature,
                    s.damp_fs, s.seed + 7));
  Trace t;
  run_chunks(l, s.clay_steps, 5, t);
  l.cmd("write_restart " + md::lammps_path(p(dir, "clay", ".restart"), "--out"));
  write_stage(p(dir, "clay", ".h5"), "clay",
              fmt::format("polymer fixed; clay minimised (PE {:.1f} -> {:.1f} kcal/mol), then "
                          "{} steps NVE (limit 0.05 A/step) + Langevin {:.0f} K on the clay",
                          e0, e1, s.clay_steps, s.temperature),
              t, recipe_json);
}

// Stage "cool": one Langevin ramp from hot_temperature to temperature.
void cool_stage(md::Lammps& l, const Protocol& pr) {
  const EquilibrateSpec& s = pr.s;
  const std::string& dir = pr.dir;
  const std::vector<std::string>& ffcmds = pr.ffcmds;
  const std::string& recipe_json = pr.recipe_json;
  const bool with_clay = pr.with_clay;
  read_state(l, ffcmds, s, p(dir, with_clay ? "clay" : "hot", ".restart"));
  l.cmd("fix pnc_nve all nve");
  l.cmd(fmt::format("fix pnc_lan all langevin {:.10g} {:.10g} {:.10g} {}", s.hot_temperature,
                    s.temperature, s.damp_fs, s.seed + 3));
  Trace t;
  run_chunks(l, s.cool_steps, 10, t, true); // one ramp over the whole stage
  l.cmd("write_restart " + md::lammps_path(p(dir, "cool", ".restart"), "--out"));
  write_stage(p(dir, "cool", ".h5"), "cool",
              fmt::format("Langevin ramp {:.0f} -> {:.0f} K over {} steps; final chunk T {:.1f} K",
                          s.hot_temperature, s.temperature, s.cool_steps,
                          t.rows.empty() ? 0.0 : t.rows.back()[0]),
              t, recipe_json);
}

// Stage "langevin": Langevin chunks at temperature until the mean PE is steady.
void langevin_stage(md::Lammps& l, const Protocol& pr) {
  const EquilibrateSpec& s = pr.s;
  const std::string& dir = pr.dir;
  const std::vector<std::string>& ffcmds = pr.ffcmds;
  const std::string& recipe_json = pr.recipe_json;
  read_state(l, ffcmds, s, p(dir, "cool", ".restart"));
  l.cmd("fix pnc_nve all nve");
  l.cmd(fmt::format("fix pnc_lan all langevin {0:.10g} {0:.10g} {1:.10g} {2}", s.temperature,
                    s.damp_fs, s.seed + 4));
  Trace t;
  double rel = 1;
  int k = 0;
  for (k = 1; k <= s.langevin_max_chunks; ++k) {
    run_chunks(l, s.langevin_chunk_steps, 1, t);
    if (k >= 2) {
      const double a = t.rows[t.rows.size() - 2][1], b = t.rows.back()[1];
      rel = std::fabs(b - a) / std::max(1e-12, std::fabs(b));
      if (rel < s.steady_tolerance) break;
    }
  }
  l.cmd("write_restart " + md::lammps_path(p(dir, "langevin", ".restart"), "--out"));
  write_stage(
      p(dir, "langevin", ".h5"), "langevin",
      fmt::format("{} chunk(s) of {} steps at {:.0f} K; relative change of mean PE "
                  "between the last two chunks {:.4f} {} {}{}",
                  std::min(k, s.langevin_max_chunks), s.langevin_chunk_steps, s.temperature, rel,
                  rel < s.steady_tolerance ? "<" : ">=", s.steady_tolerance,
                  rel < s.steady_tolerance ? " (steady)" : " -- NOT steady at the chunk limit"),
      t, recipe_json);
}
} // namespace

EquilibratedState equilibrate(const std::string& data_file, const md::PolymerForceField& ff,
                              const EquilibrateSpec& s, const std::string& dir, bool resume,
                              const std::string& recipe_json, bool with_clay, int ranks) {
  s.validate("<equilibrate>");
  // paths that reach LAMMPS commands: refused here, in the parent, if they cannot be quoted
  md::lammps_path(data_file, "data file");
  md::lammps_path(p(dir, "final", ".restart"), "--out");
  make_output_directory(dir);
  const double sig = ff.sigma;
  const std::vector<std::string> ffcmds =
      with_clay ? composite_forcefield_commands(ff) : md::polymer_forcefield_commands(ff);
  // the atoms that move while the clay is frozen, and the pairs the push-off criterion checks
  const std::string mob = with_clay ? "pnc_poly" : "all";
  const Protocol pr{data_file, s, dir, ffcmds, mob, recipe_json, sig, with_clay};
  auto stage = [&](const std::string& name, const md::StageBody& body) {
    run_equilibration_stage(dir, name, body, resume, ranks);
  };

  stage("pushoff", [&](md::Lammps& l) { pushoff_stage(l, pr); });
  stage("hot", [&](md::Lammps& l) { hot_stage(l, pr); });
  if (with_clay) stage("clay", [&](md::Lammps& l) { clay_stage(l, pr); });
  stage("cool", [&](md::Lammps& l) { cool_stage(l, pr); });
  stage("langevin", [&](md::Lammps& l) { langevin_stage(l, pr); });
  stage("final", [&](md::Lammps& l) {
    final_stage(l, ffcmds, s, dir, p(dir, "langevin", ".restart"), with_clay, ff.cutoff(), sig,
                recipe_json);
  });
  EquilibratedState e = read_equilibrated(dir);
  return e;
}

} // namespace pnc::rve
