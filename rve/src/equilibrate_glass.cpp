// Equilibration of the glassy bead-spring polymer (model "kg"), one child process per stage.
// Units real. Decision D137.
#include "pnc/md/stage_stop.hpp"
#include "pnc/rve/bead_spring.hpp"
#include "pnc/rve/platelet.hpp"

#include "equilibrate_detail.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/stop.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <iostream>

namespace pnc::rve {

namespace fs = std::filesystem;
using namespace eqdetail;

void check_glass_protocol(const EquilibrateSpec& s, const std::string& source) {
  s.validate(source);
  if (s.ensemble != "npt")
    fail(source, "equilibrate.ensemble", s.ensemble,
         "model kg quenches and holds the glass at a set pressure: must be \"npt\"");
  if (!(s.hot_temperature > s.temperature))
    fail(source, "equilibrate.hot_temperature", fmt::format("{}", s.hot_temperature),
         fmt::format("the melt temperature must exceed the glass temperature {} K (model kg "
                     "quenches from hot_temperature to temperature)",
                     s.temperature));
  if (s.hot_steps < 1000)
    fail(source, "equilibrate.hot_steps", std::to_string(s.hot_steps),
         "model kg: the melt needs >= 1000 steps (the first 1000 run with a displacement limit)");
  if (s.cool_steps < 100)
    fail(source, "equilibrate.cool_steps", std::to_string(s.cool_steps),
         "model kg: the quench needs >= 100 steps");
  if (s.npt_steps < 100)
    fail(source, "equilibrate.npt_steps", std::to_string(s.npt_steps),
         "model kg: the glass hold at set pressure needs >= 100 steps");
}

EquilibratedState equilibrate_glass(const std::string& data_file, const BeadSpringForceField& ff,
                                    const EquilibrateSpec& s, const std::string& dir, bool resume,
                                    const std::string& recipe_json, int ranks,
                                    const PlateletSpec* platelet) {
  check_glass_protocol(s, "<equilibrate>");
  ff.validate("<equilibrate>");
  md::lammps_path(data_file, "data file");
  md::lammps_path(p(dir, "final", ".restart"), "--out");
  make_output_directory(dir);
  const double sig = ff.sigma;
  const std::vector<std::string> ffcmds =
      platelet ? kg_platelet_commands(ff, *platelet) : bead_spring_commands(ff);
  // the push-off's pair commands at soft prefactor A (decision D174 with the platelet)
  auto soft_pairs = [&](double A) {
    return platelet ? kg_platelet_pushoff_pair(ff, *platelet, A)
                    : std::vector<std::string>{
                          fmt::format("pair_style soft {:.10g}", std::pow(2.0, 1.0 / 6.0) * sig),
                          fmt::format("pair_coeff * * {:.10g}", A)};
  };
  const std::string adapt_pair = platelet ? "pair soft a 1 1" : "pair soft a * *";
  const double tu = ff.temperature_unit(), tau = ff.tau_fs();
  auto stage = [&](const std::string& name, const md::StageBody& body) {
    run_equilibration_stage(dir, name, body, resume, ranks);
  };

  // 1. soft push-off at the melt temperature: the built walk has overlapping beads of
  // different chains; FENE bonds (built at 0.97 sigma < R0) hold the chains together
  stage("pushoff", [&](md::Lammps& l) {
    l.cmd("units real");
    l.cmd("atom_style molecular");
    l.cmd("read_data " + md::lammps_path(data_file, "data file"));
    l.cmds(ffcmds);
    l.cmds(soft_pairs(0.0));
    l.cmd(fmt::format("timestep {:.10g}", s.timestep_fs));
    define_measures(l);
    l.cmd(fmt::format("velocity all create {:.10g} {} dist gaussian mom yes", s.hot_temperature,
                      s.seed));
    l.cmd(fmt::format("fix pnc_lim all nve/limit {:.10g}", 0.02 * sig));
    l.cmd(fmt::format("fix pnc_lan all langevin {0:.10g} {0:.10g} {1:.10g} {2}", s.hot_temperature,
                      s.damp_fs, s.seed + 1));
    // the soft pair's coefficient at A_max is the second command of soft_pairs
    run_pushoff(l, s, sig, {adapt_pair, soft_pairs(s.pushoff_A_max)[1], "all", "unbonded"}, dir,
                recipe_json);
  });

  // 2. melt: LJ on, minimisation, then Langevin at hot_temperature at the build density
  stage("melt", [&](md::Lammps& l) {
    read_state(l, ffcmds, s, p(dir, "pushoff", ".restart"));
    l.cmd("minimize 1.0e-4 1.0e-6 1000 10000");
    l.cmd("reset_timestep 0");
    l.cmd(fmt::format("velocity all create {:.10g} {} dist gaussian mom yes", s.hot_temperature,
                      s.seed + 2));
    l.cmd(fmt::format("fix pnc_lim all nve/limit {:.10g}", 0.02 * sig));
    l.cmd(fmt::format("fix pnc_lan all langevin {0:.10g} {0:.10g} {1:.10g} {2}", s.hot_temperature,
                      s.damp_fs, s.seed + 3));
    Trace t;
    run_chunks(l, 1000, 1, t);
    l.cmd("unfix pnc_lim");
    l.cmd("fix pnc_nve all nve");
    run_chunks(l, s.hot_steps - 1000, 10, t);
    l.cmd("write_restart " + md::lammps_path(p(dir, "melt", ".restart"), "--out"));
    write_stage(p(dir, "melt", ".h5"), "melt",
                fmt::format("{} steps ({:.0f} tau) Langevin at {:.0f} K (T* = {:.2f}) at the "
                            "build density; mean T of the second half {:.1f} K, P {:.0f} atm",
                            s.hot_steps, static_cast<double>(s.hot_steps) * s.timestep_fs / tau,
                            s.hot_temperature, s.hot_temperature / tu, t.mean(0, t.rows.size() / 2),
                            t.mean(2, t.rows.size() / 2)),
                t, recipe_json);
  });

  // 3. quench: Nose-Hoover NPT at pressure_atm, T ramped hot_temperature -> temperature
  stage("quench", [&](md::Lammps& l) {
    read_state(l, ffcmds, s, p(dir, "melt", ".restart"));
    l.cmd(fmt::format("fix pnc_npt all npt temp {0:.10g} {1:.10g} {2:.10g} iso {3:.10g} {3:.10g} "
                      "{4:.10g}",
                      s.hot_temperature, s.temperature, s.damp_fs, s.pressure_atm, s.pdamp_fs));
    Trace t;
    run_chunks(l, s.cool_steps, 10, t, true); // one ramp over the whole stage
    const double time_tau = static_cast<double>(s.cool_steps) * s.timestep_fs / tau;
    l.cmd("write_restart " + md::lammps_path(p(dir, "quench", ".restart"), "--out"));
    write_stage(
        p(dir, "quench", ".h5"), "quench",
        fmt::format("NPT at {:.1f} atm, T ramped {:.0f} -> {:.0f} K (T* {:.2f} -> {:.2f}) over {} "
                    "steps ({:.0f} tau; rate {:.2e} eps/k_B per tau, {:.3g} K/ps); last chunk "
                    "T {:.1f} K, density {:.4f} g/cm3",
                    s.pressure_atm, s.hot_temperature, s.temperature, s.hot_temperature / tu,
                    s.temperature / tu, s.cool_steps, time_tau,
                    (s.hot_temperature - s.temperature) / tu / time_tau,
                    (s.hot_temperature - s.temperature) /
                        (static_cast<double>(s.cool_steps) * s.timestep_fs * 1e-3),
                    t.rows.back()[0], t.rows.back()[4]),
        t, recipe_json);
  });

  // 4. glass hold at (temperature, pressure_atm), box at the mean volume, NVT, measurement
  stage("final", [&](md::Lammps& l) {
    final_stage(l, ffcmds, s, dir, p(dir, "quench", ".restart"), false, ff.cutoff(), sig,
                recipe_json);
  });
  return read_equilibrated(dir);
}

} // namespace pnc::rve
