// pnc rve ...: the RVE builder and deformation driver (issue #3). Units inside rve/: LAMMPS
// real; stresses handed to the fit in Pa.
#include "registrars.hpp"

#include "pnc/core/error.hpp"
#include "pnc/rve/builder.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <memory>

namespace pnc::app {

namespace {

struct BuildArgs {
  rve::BuildSpec spec;
  std::string out;
  bool json = false;
};

int run_rve_build(const BuildArgs& a) {
  const rve::PolymerForceField ff;
  a.spec.validate("<command line>");
  std::filesystem::create_directories(a.out);
  const rve::System s = rve::build_polymer(a.spec, ff);
  const std::string data = (std::filesystem::path(a.out) / "rve.data").string();
  const std::string rec = (std::filesystem::path(a.out) / "build.h5").string();
  rve::write_data_file(data, s, "coarse-grained polypropylene RVE");
  write_build_record(rec, s, a.spec, ff, "{}");
  const double dmin = rve::min_nonbonded_distance(s);
  std::cerr << fmt::format("pnc rve build: {} chains x {} beads = {} beads, box {:.3f} A, "
                           "density {:.4f} g/cm3, min non-bonded distance {:.3f} A\n",
                           a.spec.chains, a.spec.beads_per_chain, s.x.size(), s.length()[0],
                           s.density(), dmin);
  std::cerr << "  data: " << data << "\n  record: " << rec << "\n";
  if (a.json) {
    nlohmann::json j;
    j["command"] = "rve build";
    j["data"] = data;
    j["record"] = rec;
    j["atoms"] = s.x.size();
    j["density_g_cm3"] = s.density();
    j["box_A"] = s.length()[0];
    j["min_nonbonded_distance_A"] = dmin;
    std::cout << j.dump() << std::endl;
  }
  return 0;
}

} // namespace

void register_rve(CLI::App& app, Action& action) {
  auto* rve = app.add_subcommand("rve", "Coarse-grained PP (+ clay) RVE: build, run cases");
  rve->require_subcommand(1);
  auto ba = std::make_shared<BuildArgs>();
  auto* build = rve->add_subcommand("build", "Build a polymer RVE: LAMMPS data file + HDF5 record");
  build->add_option("--chains", ba->spec.chains, "Number of chains");
  build->add_option("--beads", ba->spec.beads_per_chain, "Beads per chain");
  build->add_option("--density", ba->spec.density, "Target density (g/cm3)");
  build->add_option("--seed", ba->spec.seed, "Random seed");
  build->add_option("--min-distance", ba->spec.min_distance, "Minimum non-bonded distance (A)");
  build->add_option("--out", ba->out, "Output directory")->required();
  build->add_flag("--json", ba->json, "Print one JSON object on stdout");
  build->callback([ba, &action] { action = [ba] { return run_rve_build(*ba); }; });
}

} // namespace pnc::app
