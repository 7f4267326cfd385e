// MD pipeline of `pnc characterize` (units real inside, Pa in cases.h5).
#include "pnc/rve/characterize.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/stop.hpp"
#include "pnc/damage/data.hpp"
#include "pnc/rve/clay.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace pnc::rve {

namespace fs = std::filesystem;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
} // namespace

void write_cases_h5(const std::string& path, const Recipe& r,
                    const std::vector<CaseResult>& cases) {
  damage::StressStrainData d;
  d.source = path;
  d.stress_definition =
      (r.stress == "virial" ? std::string("virial only, no kinetic term (eq. 6.23, Zhou 2003)")
                            : std::string("virial + kinetic term")) +
      (r.reference == "subtract"
           ? std::string("; relative to the zero-strain hold (sigma - sigma_0)")
           : std::string("; absolute, zero-strain row included")) +
      (r.moving_average > 1
           ? fmt::format("; {}-point moving average over strain steps", r.moving_average)
           : std::string("; no moving average")) +
      "; MD by pnc rve (LAMMPS), block-averaged standard errors";
  for (const auto& c : cases) {
    damage::CaseCurve cc;
    cc.id = c.case_id;
    Eigen::Matrix<double, Eigen::Dynamic, 6> s =
        r.stress == "virial" ? c.stress_virial : c.stress_total;
    Eigen::Matrix<double, Eigen::Dynamic, 6> se =
        r.stress == "virial" ? c.stress_virial_se : c.stress_total_se;
    cc.strain = c.strain;
    if (r.reference == "subtract") {
      const Eigen::Index n = s.rows() - 1;
      if (n < 1) fail(path, fmt::format("case_{}", c.case_id), "", "has no strain step");
      cc.strain = c.strain.bottomRows(n);
      const Eigen::RowVectorXd s0 = s.row(0), e0 = se.row(0);
      Eigen::Matrix<double, Eigen::Dynamic, 6> rs = s.bottomRows(n), re = se.bottomRows(n);
      for (Eigen::Index i = 0; i < n; ++i) {
        rs.row(i) -= s0;
        re.row(i) = (re.row(i).array().square() + e0.array().square()).sqrt().matrix();
      }
      s = rs;
      se = re;
    }
    if (r.moving_average > 1) {
      cc.stress = moving_average(s, r.moving_average);
      // s.e. of a window mean: sqrt(sum se^2) / n (independent step means)
      Eigen::Matrix<double, Eigen::Dynamic, 6> v = se.array().square().matrix();
      const auto mv = moving_average(v, r.moving_average);
      cc.stress_stderr.resize(se.rows(), 6);
      const Eigen::Index n = se.rows(), h = r.moving_average / 2;
      for (Eigen::Index i = 0; i < n; ++i) {
        const double w =
            static_cast<double>(std::min(n - 1, i + h) - std::max<Eigen::Index>(0, i - h) + 1);
        cc.stress_stderr.row(i) = (mv.row(i).array() / w).sqrt().matrix();
      }
    } else {
      cc.stress = s;
      cc.stress_stderr = se;
    }
    d.cases.push_back(cc);
  }
  std::sort(d.cases.begin(), d.cases.end(),
            [](const auto& a, const auto& b) { return a.id < b.id; });
  damage::write_stress_strain_h5(path, d);
}

MdOutcome run_md(const Recipe& r, const std::string& dir, bool resume, int jobs, int ranks,
                 int equilibrate_ranks) {
  MdOutcome o;
  o.dir = dir;
  make_output_directory(dir);
  const std::string recipe_text = expanded_json(r).dump(2);
  o.recipe_path = (fs::path(dir) / "recipe.json").string();
  if (fs::exists(o.recipe_path)) {
    std::ifstream f(o.recipe_path);
    std::stringstream ss;
    ss << f.rdbuf();
    if (ss.str() != recipe_text + "\n") {
      if (resume)
        fail(o.recipe_path, "", "",
             "--resume with a recipe different from the one this directory was made with; "
             "use a new --out directory");
      if (!fs::is_empty(fs::path(dir)))
        fail(dir, "--out", dir,
             "holds a run of another recipe; use a new --out directory or delete it");
    } else {
      refuse_existing_run(dir, resume, {"cases", "cases.h5"});
    }
  }
  write_text_atomically(o.recipe_path, recipe_text + "\n");

  // --- build
  auto t0 = std::chrono::steady_clock::now();
  const fs::path bdir = fs::path(dir) / "build";
  make_output_directory(bdir.string());
  o.data_file = (bdir / "rve.data").string();
  o.build_record = (bdir / "build.h5").string();
  if (!(resume && fs::exists(o.data_file) && fs::exists(o.build_record))) {
    std::cerr << fmt::format("pnc characterize [build] {} chains x {} beads at {} g/cm3, seed {}\n",
                             r.build.chains, r.build.beads_per_chain, r.build.density, r.seed);
    CompositeInfo ci;
    const System s = r.model == "pnc"  ? build_composite(r.build, r.ff, r.clay, &ci)
                     : r.model == "kg" ? build_bead_spring(r.build, r.kg)
                                       : build_polymer(r.build, r.ff);
    write_data_file(o.data_file, s, "pnc characterize " + r.name);
    if (r.model == "kg")
      write_bead_spring_record(o.build_record, s, r.build, r.kg, recipe_text);
    else
      write_build_record(o.build_record, s, r.build, r.ff, recipe_text);
    if (r.model == "pnc") {
      const nlohmann::json cj = {
          {"cells_a", r.clay.cells_a},
          {"cells_b", r.clay.cells_b},
          {"clay_atoms", ci.clay_atoms},
          {"polymer_beads", ci.polymer_beads},
          {"clay_mass_g_mol", ci.clay_mass},
          {"polymer_mass_g_mol", ci.polymer_mass},
          {"platelet_length_A", ci.length},
          {"platelet_width_A", ci.width},
          {"platelet_thickness_A", ci.thickness},
          {"aspect_ratio_length_over_width", ci.aspect_ratio},
          {"clay_bounding_volume_A3", ci.clay_volume},
          {"box_volume_A3", ci.box_volume},
          {"volume_fraction", ci.volume_fraction},
          {"weight_fraction", ci.weight_fraction},
          {"min_polymer_clay_distance_A", min_polymer_clay_distance(s)},
          {"definitions", "volume fraction = platelet bounding volume (cells_a a x cells_b b x "
                          "atom-centre thickness) / box volume at the build; weight fraction = "
                          "W_clay / (W_clay + W_PP)"}};
      write_text_atomically((bdir / "clay.json").string(), cj.dump(2) + "\n");
      std::cerr << fmt::format("  clay: {} x {} cells, {} atoms, {:.2f} x {:.2f} x {:.2f} A "
                               "(aspect ratio {:.2f}), volume fraction {:.4f}, weight fraction "
                               "{:.4f}, min bead-clay distance {:.3f} A\n",
                               r.clay.cells_a, r.clay.cells_b, ci.clay_atoms, ci.length, ci.width,
                               ci.thickness, ci.aspect_ratio, ci.volume_fraction,
                               ci.weight_fraction, min_polymer_clay_distance(s));
    }
    std::cerr << fmt::format(
        "  built {} beads, box {:.3f} A, min non-bonded distance {:.3f} A\n", s.x.size(),
        s.length()[0], r.model == "kg" ? min_unbonded_distance(s) : min_nonbonded_distance(s));
  } else {
    std::cerr << "pnc characterize [build] done (resumed)\n";
  }
  o.seconds_build = seconds_since(t0);

  pnc::throw_if_stopped("after the build");
  // --- equilibrate
  t0 = std::chrono::steady_clock::now();
  const int eq_ranks = equilibrate_ranks > 0 ? equilibrate_ranks : ranks;
  std::cerr << fmt::format("pnc characterize [equilibrate] ensemble {}, {} MPI rank(s)\n",
                           r.equilibrate.ensemble, eq_ranks);
  const std::string eq_dir = (fs::path(dir) / "equilibrate").string();
  o.equilibrated = r.model == "kg" ? equilibrate_glass(o.data_file, r.kg, r.equilibrate, eq_dir,
                                                       resume, recipe_text, eq_ranks)
                                   : equilibrate(o.data_file, r.ff, r.equilibrate, eq_dir, resume,
                                                 recipe_text, r.model == "pnc", eq_ranks);
  o.seconds_equilibrate = seconds_since(t0);

  // --- cases
  t0 = std::chrono::steady_clock::now();
  std::vector<std::pair<StageSpec, StageBody>> stages;
  std::vector<int> run_ids;
  for (int id : r.cases) {
    DeformSpec d = r.deform;
    d.case_id = id;
    d.seed = static_cast<std::uint64_t>(r.seed) * 100 + static_cast<std::uint64_t>(id);
    d.start_state = o.equilibrated.restart;
    d.force_field = r.model == "pnc"  ? composite_forcefield_commands(r.ff)
                    : r.model == "kg" ? bead_spring_commands(r.kg)
                                      : polymer_forcefield_commands(r.ff);
    d.recipe_json = recipe_text;
    const std::string cdir = (fs::path(dir) / "cases" / fmt::format("case_{}", id)).string();
    if (resume && fs::exists(fs::path(cdir) / "checkpoint.h5")) {
      const CaseResult c = read_case(cdir);
      if (c.rows_done >= d.steps + 1) {
        std::cerr << fmt::format("pnc characterize [case {}] done (resumed)\n", id);
        continue;
      }
      std::cerr << fmt::format("pnc characterize [case {}] resuming after step {}/{}\n", id,
                               c.rows_done - 1, d.steps);
    }
    stages.push_back({case_stage(d, cdir, ranks), case_body(d, cdir, resume)});
    run_ids.push_back(id);
  }
  if (!stages.empty())
    std::cerr << fmt::format("pnc characterize [cases] {} case(s), {} at a time, {} MPI rank(s) "
                             "each; LAMMPS logs in {}/cases/case_<n>/lammps.log\n",
                             stages.size(), std::max(1, jobs), ranks, dir);
  const auto outcomes = run_stages(stages, jobs);
  pnc::throw_if_stopped("the running cases stopped; their checkpoints are kept");
  std::string first_error;
  for (std::size_t i = 0; i < outcomes.size(); ++i) {
    if (outcomes[i].ok) {
      std::cerr << fmt::format("pnc characterize [case {}] finished in {:.1f} s\n", run_ids[i],
                               outcomes[i].seconds);
    } else {
      std::cerr << fmt::format("pnc characterize [case {}] FAILED: {} (log {})\n", run_ids[i],
                               outcomes[i].error, outcomes[i].log_path);
      if (first_error.empty())
        first_error = fmt::format("case {}: {} (log {})", run_ids[i], outcomes[i].error,
                                  outcomes[i].log_path);
    }
  }
  if (!first_error.empty())
    fail(dir, "cases", "", first_error + "; finished steps are kept: rerun with --resume");
  for (int id : r.cases)
    o.cases.push_back(read_case((fs::path(dir) / "cases" / fmt::format("case_{}", id)).string()));
  o.seconds_cases = seconds_since(t0);
  o.cases_h5 = (fs::path(dir) / "cases.h5").string();
  write_cases_h5(o.cases_h5, r, o.cases);
  return o;
}

} // namespace pnc::rve
