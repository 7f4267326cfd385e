// pnc thermo ti | persistence | work: free energy of deformation by thermodynamic
// integration, persistence length by steered bending, free energy from the stress work
// (docs/theory.md section 4). Units: LAMMPS real (kcal/mol, A, fs, K) inside thermo/; moduli in Pa
// and EI also in N m^2 where named.
#include "checks.hpp"
#include "plot.hpp"
#include "registrars.hpp"
#include "report.hpp"
#include "run_control.hpp"
#include "thermo_report.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/run_log.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"
#include "pnc/rve/builder.hpp"
#include "pnc/rve/equilibrate.hpp"
#include "pnc/rve/recipe.hpp"
#include "pnc/thermo/persistence.hpp"
#include "pnc/thermo/ti.hpp"
#include "pnc/thermo/work.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace pnc::app {

namespace {

namespace fs = std::filesystem;

nlohmann::json jnum(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

/// Draws with plot_thermo.py; a failure is printed once and kept for the report.
std::vector<std::string> run_plot(const std::vector<std::string>& args, ThermoRun& run) {
  run.pngs = run_plot_script("plot_thermo.py", args, &run.plot_warning);
  if (!run.plot_warning.empty()) std::cerr << "pnc: warning: no plot: " << run.plot_warning << "\n";
  return run.pngs;
}

void print_progress(const std::string& what, int done, int total, double el, double eta) {
  std::cerr << fmt::format("  [{}/{}] {}  (elapsed {:.0f} s, ETA {:.0f} s)\n", done, total, what,
                           el, eta)
            << std::flush;
}

// ------------------------------------------------------------------------------- ti

struct TiArgs {
  thermo::TiSpec spec;
  std::string from, restart, out, vol = "0,0.00125,0.0025,0.00375,0.005",
                                  dev = "0,0.00125,0.0025,0.00375,0.005";
  bool demo = false, resume = false, json = false, no_plots = false;
};

std::vector<double> parse_list(const std::string& text, const char* field) {
  std::vector<double> v;
  if (text == "none" || text.empty()) return v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t pos = 0;
      v.push_back(std::stod(item, &pos));
      if (pos != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      fail("<command line>", field, item, "must be a comma-separated list of numbers (or none)");
    }
  }
  return v;
}

/// The equilibrated start state and the force-field commands.
std::pair<std::string, std::vector<std::string>> start_state(const TiArgs& a) {
  const int given = (a.from.empty() ? 0 : 1) + (a.restart.empty() ? 0 : 1) + (a.demo ? 1 : 0);
  if (given != 1)
    fail("<command line>", "--from/--restart/--demo", "",
         "give exactly one source of the equilibrated RVE");
  if (!a.restart.empty()) {
    if (!fs::is_regular_file(a.restart))
      fail(a.restart, "--restart", a.restart, "no such LAMMPS restart file");
    return {a.restart, rve::polymer_forcefield_commands({})};
  }
  if (!a.from.empty()) {
    const std::string rp = (fs::path(a.from) / "recipe.json").string();
    const std::string rs = (fs::path(a.from) / "equilibrate" / "final.restart").string();
    if (!fs::is_regular_file(rp))
      fail(a.from, "--from", a.from, "is not a `pnc characterize` output (no recipe.json)");
    if (!fs::is_regular_file(rs))
      fail(rs, "--from", a.from, "has no equilibrated state (equilibrate/final.restart)");
    const rve::Recipe r = rve::read_recipe(rp);
    if (r.model != "pp")
      fail(rp, "model", r.model,
           "thermo ti ramps a single-type LJ; the nanocomposite (model pnc) is not supported yet");
    if (r.system.enabled) // the built-in force field would be applied to the user's atoms
      fail(rp, "system", r.system.input_file,
           "thermo ti works on the built-in polymer force field; a run of your own system "
           "(recipe \"system\", docs/rve.md) is not supported yet");
    return {rs, rve::polymer_forcefield_commands(r.ff)};
  }
  // --demo: build and equilibrate the demo RVE (rve/ API) under <out>/rve
  const rve::Recipe r = rve::parse_recipe(rve::preset_json("demo"), "preset demo");
  const fs::path d = fs::path(a.out) / "rve";
  make_output_directory(d.string());
  const std::string data = (d / "rve.data").string();
  if (!(a.resume && fs::exists(data))) {
    std::cerr << fmt::format("pnc thermo ti [demo RVE] building {} chains x {} beads\n",
                             r.build.chains, r.build.beads_per_chain);
    const rve::System s = rve::build_polymer(r.build, r.ff);
    rve::write_data_file(data, s, "pnc thermo ti demo");
  }
  std::cerr << "pnc thermo ti [demo RVE] equilibrating (recipe demo)\n";
  const auto e = rve::equilibrate(data, r.ff, r.equilibrate, (d / "equilibrate").string(), a.resume,
                                  rve::expanded_json(r).dump(), false);
  std::cerr << fmt::format("  equilibrated: density {:.4f} g/cm3, P {:.0f} atm\n", e.density,
                           e.pressure_total);
  return {e.restart, rve::polymer_forcefield_commands(r.ff)};
}

nlohmann::json spec_json(const thermo::TiSpec& s) {
  return {{"rule", s.rule},
          {"points", s.points},
          {"vol", s.vol},
          {"dev", s.dev},
          {"eps0_kcal_mol", s.path.eps0},
          {"eps1_kcal_mol", s.path.eps1},
          {"sig0_A", s.path.sig0},
          {"sig1_A", s.path.sig1},
          {"cutoff_A", s.path.cutoff},
          {"timestep_fs", s.sampling.timestep_fs},
          {"equil_steps", s.sampling.equil_steps},
          {"prod_steps", s.sampling.prod_steps},
          {"sample_every", s.sampling.sample_every},
          {"blocks", s.sampling.blocks},
          {"temperature_K", s.sampling.temperature},
          {"damp_fs", s.damp_fs},
          {"seed", s.seed},
          {"fd_h", s.fd_h},
          {"dhdl_method", s.dhdl_method}};
}

int run_thermo_ti(TiArgs a) {
  a.spec.vol = parse_list(a.vol, "--vol");
  a.spec.dev = parse_list(a.dev, "--dev");
  a.spec.validate("<command line>");
  const RunDirLock lock(a.out, command_line()); // one process per run directory
  start_run_log(a.out, command_line());         // pnc.log: what this run printed
  const StopSignals signals;                    // SIGINT/SIGTERM: finished points are kept
  // one spec per output directory: --resume must not mix protocols
  const std::string sj = spec_json(a.spec).dump(2) + "\n";
  const std::string sp = (fs::path(a.out) / "ti_spec.json").string();
  if (fs::exists(sp)) {
    std::ifstream f(sp);
    std::stringstream ss;
    ss << f.rdbuf();
    if (ss.str() != sj)
      fail(sp, "--out", a.out,
           "holds a TI with other settings; use a new --out directory (or the same settings)");
    refuse_existing_run(a.out, a.resume, {"ti_spec.json"});
  }
  const auto [restart, ff] = start_state(a);
  write_text_atomically(sp, sj);
  const auto states = thermo::ti_states(a.spec);
  std::cerr << fmt::format("pnc thermo ti: {} state(s) x {} lambda point(s) ({} rule), {} + {} "
                           "steps of {} fs per point, dH/dl every {} steps; start state {}\n",
                           states.size(), a.spec.points, a.spec.rule, a.spec.sampling.equil_steps,
                           a.spec.sampling.prod_steps, a.spec.sampling.timestep_fs,
                           a.spec.sampling.sample_every, restart);
  const thermo::TiResult r =
      thermo::run_ti(a.spec, restart, ff, a.out, a.resume, sj, print_progress);

  // --- report
  std::cerr << "\n  state            dA = A(1) - A(0) (kcal/mol)     <dH/dl> at the nodes\n";
  double worst_fd = 0;
  for (const auto& st : r.states) {
    std::string nodes;
    for (const auto& p : st.ti.points) {
      nodes += fmt::format(" {:.3f}+-{:.3f}", p.dhdl.value, p.dhdl.se);
      if (p.checks.count("fd_dhdl_lammps"))
        worst_fd =
            std::max(worst_fd, std::fabs(p.checks.at("fd_dhdl_lammps") - p.checks.at("dhdl_pnc")) /
                                   std::max(1e-12, std::fabs(p.checks.at("dhdl_pnc"))));
    }
    std::cerr << fmt::format("  {:<14} {:>10.4f} +- {:.4f}          {}\n", st.state.id,
                             st.ti.dA.value, st.ti.dA.se, nodes);
  }
  std::cerr << fmt::format("  finite-difference check of dH/dl against LAMMPS's pair energy: "
                           "largest relative difference {:.2e}\n",
                           worst_fd);
  for (const auto& f : r.fits)
    if (std::isfinite(f.modulus))
      std::cerr << fmt::format(
          "  {} response (docs/theory.md §4.4, of A(1) - A(0)): {} = {:.3g} +- {:.2g} "
          "GPa (quadratic fit, V0 {:.0f} A^3)\n",
          f.kind, f.kind == "vol" ? "K" : "mu", f.modulus * 1e-9, f.modulus_se * 1e-9, f.v0);
  std::vector<std::string> pngs;
  ThermoRun rep{command_line(), a.out, r.h5, 0, !a.no_plots, {}, {}, {}};
  if (!a.no_plots) {
    std::ostringstream c1, c2;
    c1.precision(12);
    c2.precision(12);
    c1 << "state,lambda,dhdl,dhdl_se\n";
    c2 << "kind,strain,strain_measure,dA,dA_se\n";
    for (const auto& st : r.states) {
      for (const auto& p : st.ti.points)
        c1 << st.state.id << ',' << p.lambda << ',' << p.dhdl.value << ',' << p.dhdl.se << '\n';
      for (const char* k : {"vol", "dev"})
        if (st.state.kind == k || st.state.kind == "ref") {
          const bool in = st.state.kind == "ref"
                              ? !(std::string(k) == "vol" ? a.spec.vol : a.spec.dev).empty()
                              : true;
          if (!in) continue;
          const double m = std::string(k) == "vol" ? 3 * st.state.strain : st.state.strain;
          c2 << k << ',' << st.state.strain << ',' << m << ',' << st.ti.dA.value << ','
             << st.ti.dA.se << '\n';
        }
    }
    const fs::path pd = fs::path(a.out) / "plots";
    make_output_directory(pd.string());
    write_text_atomically((pd / "dhdl.csv").string(), c1.str());
    write_text_atomically((pd / "dA.csv").string(), c2.str());
    pngs = run_plot({"ti", (pd / "dhdl.csv").string(), (pd / "dA.csv").string(), pd.string()}, rep);
  }
  std::cerr << "  results: " << r.h5 << "\n";
  for (const auto& p : pngs)
    std::cerr << "  plot: " << p << "\n";
  rep.seconds = r.seconds;
  const std::string report = write_ti_report(rep, a.spec, r, worst_fd);
  std::cerr << "  report: " << report << "\n";
  std::cerr << fmt::format("  wall time {:.1f} s\n", r.seconds);
  if (a.json) std::cout << ti_json(rep, a.spec, r, report, worst_fd).dump() << std::endl;
  return 0;
}

// ---------------------------------------------------------------------- persistence

struct PersistenceArgs {
  thermo::PersistenceSpec spec;
  std::string out, rates = "0.01,0.025,0.05,0.075,0.1";
  bool resume = false, json = false, no_plots = false;
};

int run_thermo_persistence(PersistenceArgs a) {
  a.spec.rates = parse_list(a.rates, "--rates");
  a.spec.validate("<command line>");
  const RunDirLock lock(a.out, command_line()); // one process per run directory
  start_run_log(a.out, command_line());         // pnc.log: what this run printed
  const StopSignals signals;                    // SIGINT/SIGTERM: finished rates are kept
  std::cerr << fmt::format("pnc thermo persistence: {} chain of {} beads, supports {}, spring {} "
                           "kcal/mol/A^2, {} rates, pull {} A at {} fs steps, T {} K\n",
                           a.spec.chain, a.spec.beads, a.spec.supports, a.spec.spring_k,
                           a.spec.rates.size(), a.spec.pull_distance, a.spec.timestep_fs,
                           a.spec.temperature);
  const auto t0 = std::chrono::steady_clock::now();
  const thermo::PersistenceResult r =
      thermo::run_persistence(a.spec, a.out, a.resume, print_progress);
  ThermoRun rep{command_line(), a.out, r.h5, 0, !a.no_plots, {}, {}, {}};
  const double si = units::j_m_per_kcal_mol_A;
  std::cerr << fmt::format(
      "  L = {:.3f} A; EI(rate) = {:.4g} + {:.4g} rate (kcal/mol A, rate A/fs)\n", r.length,
      r.line.c[0], r.line.c[1]);
  std::cerr << fmt::format("  EI(0) = {:.4g} +- {:.2g} kcal/mol A (95 % CI), = {:.4g} +- {:.2g} N "
                           "m^2; xi_p = EI/kT = {:.2f} +- {:.2f} A at {} K\n",
                           r.ei0.value, r.ei0_ci95, r.ei0.value * si, r.ei0_ci95 * si, r.xi_p,
                           r.xi_p_ci95, a.spec.temperature);
  if (a.spec.chain == "harmonic")
    std::cerr << fmt::format("  by construction: EI = {:.4g} (discrete chain, this loading), "
                             "{:.4g} (continuum k_theta l0) kcal/mol A\n",
                             r.expected_ei, r.expected_ei_continuum);
  else
    std::cerr << "  dissertation (published values, docs/theory.md §4.5): EI(0) = 2.433e-29 N m^2, "
                 "xi_p = 58.74 A\n";
  std::vector<std::string> pngs;
  if (!a.no_plots) {
    std::ostringstream c;
    c.precision(12);
    c << "kind,rate,EI,EI_se,EI_end\n";
    for (const auto& rr : r.rates)
      c << "rate," << rr.rate << ',' << rr.ei.value << ',' << rr.ei.se << ',' << rr.ei_end << '\n';
    c << "fit,0," << r.line.c[0] << ',' << r.ei0_ci95 << ',' << r.line.c[1] << '\n';
    const std::string csv = (fs::path(a.out) / "EI_vs_rate.csv").string();
    write_text_atomically(csv, c.str());
    pngs = run_plot({"persistence", csv, a.out}, rep);
  }
  std::cerr << "  results: " << r.h5 << "\n";
  for (const auto& p : pngs)
    std::cerr << "  plot: " << p << "\n";
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string report = write_persistence_report(rep, a.spec, r);
  std::cerr << "  report: " << report << "\n";
  if (a.json) std::cout << persistence_json(rep, a.spec, r, report).dump() << std::endl;
  return 0;
}

// ----------------------------------------------------------------------------- work

struct WorkArgs {
  std::vector<std::string> from;
  std::string out;
  bool json = false;
};

nlohmann::json integral_json(const thermo::WorkIntegral& w, std::size_t k, double v0) {
  // SI keys (D238, D280): J/m^3 and J of the box; work.h5/work.csv keep kcal/mol beside J
  return {{"da_J_per_m3", jnum(w.value[k])},
          {"da_stderr_indep_J_per_m3", jnum(w.se_indep[k])},
          {"da_stderr_bound_J_per_m3", jnum(w.se_bound[k])},
          {"dA_J", jnum(w.value[k] * v0)},
          {"dA_stderr_indep_J", jnum(w.se_indep[k] * v0)},
          {"dA_stderr_bound_J", jnum(w.se_bound[k] * v0)}};
}

/// decision D143: |da| below twice its any-correlation error bound at the largest strain
bool is_noise(const thermo::WorkIntegral& w) {
  return w.has_se && !(std::fabs(w.value.back()) > 2 * w.se_bound.back());
}

int run_thermo_work(const WorkArgs& a) {
  if (a.from.empty() || a.from.size() > 2)
    fail("<command line>", "--from", fmt::format("{} given", a.from.size()),
         "give one run directory, or two at different temperatures");
  const RunDirLock lock(a.out, command_line()); // one process per output directory
  start_run_log(a.out, command_line());         // pnc.log: what this run printed
  const thermo::WorkRun r1 = thermo::read_work_run(a.from[0]);
  std::unique_ptr<thermo::WorkRun> r2;
  if (a.from.size() == 2) r2 = std::make_unique<thermo::WorkRun>(thermo::read_work_run(a.from[1]));
  const thermo::WorkResult r = thermo::stress_work(r1, r2.get());
  const std::string h5 = (fs::path(a.out) / "work.h5").string();
  const std::string csv = (fs::path(a.out) / "work.csv").string();
  thermo::write_work_h5(h5, r);
  thermo::write_work_csv(csv, r);
  std::cerr << fmt::format("pnc thermo work: {} run(s), T {} K, V0 {:.6g} m^3 ({:.0f} A^3)\n",
                           r.runs, r.temperature, r.volume, r.volume * 1e30);
  const double kc = r.volume * units::kcal_mol_per_joule;
  for (const auto& c : r.cases) {
    const std::size_t k = c.da.value.size() - 1;
    std::string line = fmt::format(
        "  case {}: at max strain {:.4g}: da = {:.4g} J/m^3 (+-{:.2g} indep, <= {:.2g} any "
        "correlation), dA = {:.4g} kcal/mol",
        c.id, c.strain.row(static_cast<Eigen::Index>(k)).cwiseAbs().maxCoeff(), c.da.value[k],
        c.da.se_indep[k], c.da.se_bound[k], c.da.value[k] * kc);
    if (r.runs == 2)
      line += fmt::format("; entropic {:.4g} +- {:.2g}, energetic {:.4g} +- {:.2g} J/m^3",
                          c.da_s.value[k], c.da_s.se_indep[k], c.da_u.value[k], c.da_u.se_indep[k]);
    if (is_noise(c.da)) line += "  [NOISE: |da| < 2 x its error bound]";
    if (r.runs == 2 && is_noise(c.da_s) && is_noise(c.da_u))
      line += "  [SPLIT NOISE: entropic and energetic parts < 2 x their error bounds]";
    if (c.softening) line += "  [SOFTENING: yield/damage, the integral is work, not free energy]";
    std::cerr << line << "\n";
  }
  for (const auto& n : r.notes)
    std::cerr << "  note: " << n << "\n";
  std::cerr << "  results: " << h5 << ", " << csv << "\n";
  // exit 4 (outputs written) when no case resolves what was asked: the total, or the split
  bool all_noise = true;
  for (const auto& c : r.cases)
    all_noise =
        all_noise && (is_noise(c.da) || (r.runs == 2 && is_noise(c.da_s) && is_noise(c.da_u)));
  if (all_noise)
    std::cerr << "  NO RESULT: every case is noise (exit code 4); longer or replicated runs are "
                 "needed\n";
  if (a.json) {
    nlohmann::json j;
    j["command"] = "thermo work";
    j["h5"] = h5;
    j["csv"] = csv;
    j["runs"] = r.runs;
    j["temperature_K"] = r.temperature;
    if (r.runs == 2) {
      j["temperature_1_K"] = r.t1;
      j["temperature_2_K"] = r.t2;
      j["volume_1_m3"] = r.volume1;
      j["volume_2_m3"] = r.volume2;
    }
    j["volume_m3"] = r.volume;
    j["notes"] = r.notes;
    nlohmann::json cs = nlohmann::json::array();
    for (const auto& c : r.cases) {
      const std::size_t k = c.da.value.size() - 1;
      nlohmann::json o;
      o["case"] = c.id;
      o["strain_max_1"] = c.strain.row(static_cast<Eigen::Index>(k)).cwiseAbs().maxCoeff();
      o["total"] = integral_json(c.da, k, r.volume);
      if (r.runs == 2) {
        o["entropic"] = integral_json(c.da_s, k, r.volume);
        o["energetic"] = integral_json(c.da_u, k, r.volume);
      }
      o["softening"] = c.softening;
      o["noise"] = is_noise(c.da);
      if (r.runs == 2) {
        o["entropic"]["noise"] = is_noise(c.da_s);
        o["energetic"]["noise"] = is_noise(c.da_u);
      }
      cs.push_back(o);
    }
    j["cases"] = cs;
    j["all_noise"] = all_noise;
    std::cout << j.dump() << std::endl;
  }
  return all_noise ? kExitNotUsable : 0;
}

} // namespace

// LAMMPS runs at most 2^31 - 1 steps in one `run` command.
constexpr long kMaxRunSteps = 2000000000L;

void register_thermo(CLI::App& app, Action& action) {
  auto* th = app.add_subcommand(
      "thermo", "Free energy of deformation (TI) and persistence length (LAMMPS, units real)");
  th->require_subcommand(1);

  auto ta = std::make_shared<TiArgs>();
  auto* ti = th->add_subcommand(
      "ti", "Thermodynamic integration of the LJ coupling over deformation states -> ti.h5");
  ti->add_option("--from", ta->from, "`pnc characterize` output directory (pure polymer)");
  ti->add_option("--restart", ta->restart, "Equilibrated LAMMPS restart (default PP force field)");
  ti->add_flag("--demo", ta->demo, "Build and equilibrate the demo RVE (600 beads) under OUT/rve");
  ti->add_option("--out", ta->out, "Output directory")->required();
  ti->add_option("--rule", ta->spec.rule, "Quadrature: gauss (default) or trapezoid")
      ->check(CLI::IsMember({"gauss", "trapezoid"}));
  ti->add_option("--points", ta->spec.points, "Quadrature points (default 3, Table 6.1)")
      ->check(CLI::Range(1, 64));
  ti->add_option("--vol", ta->vol, "alpha values of F = (1+alpha) I, comma-separated, or none");
  ti->add_option("--dev", ta->dev, "beta values of F = I + beta(1-delta_ij), or none");
  ti->add_option("--eps0", ta->spec.path.eps0, "epsilon at lambda = 0 (kcal/mol, (0, 100])")
      ->check(FinitePositive(100));
  ti->add_option("--eps1", ta->spec.path.eps1, "epsilon at lambda = 1 (kcal/mol, (0, 100])")
      ->check(FinitePositive(100));
  ti->add_option("--sig0", ta->spec.path.sig0, "sigma at lambda = 0 (A, (0, 10])")
      ->check(FinitePositive(10));
  ti->add_option("--sig1", ta->spec.path.sig1, "sigma at lambda = 1 (A, (0, 10])")
      ->check(FinitePositive(10));
  ti->add_option("--cutoff", ta->spec.path.cutoff, "LJ cut-off at every lambda (A, (0, 30])")
      ->check(FinitePositive(30));
  ti->add_option("--dhdl", ta->spec.dhdl_method,
                 "dH/dlambda sampler: virial (one run, energy + pair virial identity; default) "
                 "or pairs (pair-distance sums after every sample interval)")
      ->check(CLI::IsMember({"virial", "pairs"}));
  ti->add_option("--timestep", ta->spec.sampling.timestep_fs, "fs (default 0.5, (0, 10])")
      ->check(FinitePositive(10));
  ti->add_option("--equil-steps", ta->spec.sampling.equil_steps,
                 "Steps discarded per lambda point (default 60000 = 30 ps)")
      ->check(CLI::Range(0L, kMaxRunSteps));
  ti->add_option("--prod-steps", ta->spec.sampling.prod_steps,
                 "Steps averaged per lambda point (default 20000 = 10 ps)")
      ->check(CLI::Range(1L, kMaxRunSteps));
  ti->add_option("--sample-every", ta->spec.sampling.sample_every,
                 "Steps between dH/dlambda samples (default 100, D64)")
      ->check(CLI::Range(1, 1000000));
  ti->add_option("--blocks", ta->spec.sampling.blocks, "Blocks of the standard errors (10)")
      ->check(CLI::Range(3, 10000));
  ti->add_option("--temperature", ta->spec.sampling.temperature, "K (default 300, (0, 1e4])")
      ->check(FinitePositive(1e4));
  ti->add_option("--seed", ta->spec.seed, "Thermostat seed (1 to 800000000)")
      ->check(CLI::Range(1, 800000000));
  ti->add_option("--jobs", ta->spec.jobs, "Lambda points run at the same time")
      ->check(CLI::Range(1, 64));
  ti->add_flag("--resume", ta->resume, "Continue: finished (state, lambda) points are reused");
  ti->add_flag("--no-plots", ta->no_plots, "Do not draw plots");
  ti->add_flag("--json", ta->json, "Print one JSON object with the key numbers on stdout");
  ti->callback([ta, &action] { action = [ta] { return run_thermo_ti(*ta); }; });

  auto pa = std::make_shared<PersistenceArgs>();
  auto* pe = th->add_subcommand(
      "persistence", "Bending stiffness EI and persistence length by steered bending of a chain");
  pe->add_option(
        "--chain", pa->spec.chain,
        "pp (CG polypropylene, docs/theory.md §3.1) or harmonic (straight, angle harmonic)")
      ->check(CLI::IsMember({"pp", "harmonic"}));
  pe->add_option("--beads", pa->spec.beads, "Beads (default 4, 3 to 200)")
      ->check(CLI::Range(3, 200));
  pe->add_option("--angle-k", pa->spec.angle_K,
                 "harmonic chain: LAMMPS angle K (kcal/mol/rad^2), k_theta = 2K")
      ->check(FinitePositive(1e6));
  pe->add_option("--bond-k", pa->spec.bond_K, "harmonic chain: LAMMPS bond K (kcal/mol/A^2)")
      ->check(FinitePositive(1e6));
  pe->add_option("--supports", pa->spec.supports, "pinned (both ends fixed) or roller")
      ->check(CLI::IsMember({"pinned", "roller"}));
  pe->add_option("--spring-k", pa->spec.spring_k, "Pulling spring (kcal/mol/A^2, default 10)")
      ->check(FinitePositive(1e6));
  pe->add_option("--rates", pa->rates, "Anchor speeds, A/fs, comma-separated");
  pe->add_option("--pull-distance", pa->spec.pull_distance, "Anchor travel per pull (A, (0, 1000])")
      ->check(FinitePositive(1000));
  pe->add_option("--timestep", pa->spec.timestep_fs, "fs, (0, 10]")->check(FinitePositive(10));
  pe->add_option("--hold-steps", pa->spec.hold_steps, "Steps at zero force before each pull")
      ->check(CLI::Range(0L, kMaxRunSteps));
  pe->add_option("--sample-every", pa->spec.sample_every, "Steps between samples of F and d")
      ->check(CLI::Range(1, 1000000));
  pe->add_option("--blocks", pa->spec.blocks, "Blocks of the standard errors")
      ->check(CLI::Range(3, 10000));
  pe->add_option("--temperature", pa->spec.temperature, "K, (0, 1e4]")->check(FinitePositive(1e4));
  pe->add_option("--seed", pa->spec.seed, "Seed (1 to 800000000)")->check(CLI::Range(1, 800000000));
  pe->add_option("--out", pa->out, "Output directory")->required();
  pe->add_flag("--resume", pa->resume, "Reuse finished rates");
  pe->add_flag("--no-plots", pa->no_plots, "Do not draw plots");
  pe->add_flag("--json", pa->json, "Print one JSON object with the key numbers on stdout");
  pe->callback([pa, &action] { action = [pa] { return run_thermo_persistence(*pa); }; });
  auto wa = std::make_shared<WorkArgs>();
  auto* wk = th->add_subcommand(
      "work", "Free energy of deformation from the stress work of `pnc characterize` cases "
              "(post-processing; two runs at T1 != T2 add the energetic/entropic split)");
  wk->add_option("--from", wa->from,
                 "`pnc characterize` output directory; give it twice (second at another "
                 "temperature) for the split")
      ->required()
      ->take_all();
  wk->add_option("--out", wa->out, "Output directory (work.h5, work.csv)")->required();
  wk->add_flag("--json", wa->json, "Print one JSON object with the key numbers on stdout");
  wk->callback([wa, &action] { action = [wa] { return run_thermo_work(*wa); }; });
}

} // namespace pnc::app
