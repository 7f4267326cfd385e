// The keys of a `pnc thermo persistence --input` file, each declared once
// (pnc/core/parameters.hpp, D321): name, type, default (the values of PersistenceSpec), range,
// unit and one line of text; the command-line options take their checks and help from here
// (app/cli_parameters.hpp, D320). The rules between keys are PersistenceSpec::validate's.
// Units: LAMMPS real (kcal/mol, A, fs, K); rates in A/fs.
#include "pnc/thermo/persistence_parameters.hpp"

#include "input_file.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/params.hpp"

#include <memory>

namespace pnc::thermo {

namespace {

// LAMMPS runs at most 2^31 - 1 steps in one `run` command.
constexpr std::int64_t kMaxSteps = 2000000000;
// A rate list holds at most this many rates (one LAMMPS run each).
constexpr std::size_t kMaxRates = 1000;
// Spring and bond constants above this are not a chain pnc can integrate at fs steps.
constexpr double kMaxStiffness = 1e6;

void declare_persistence(Parameters& p, PersistenceSpec& s) {
  p.string("chain", s.chain,
           {{"pp", "the coarse-grained polypropylene, docs/theory.md section 3.1"},
            {"harmonic", "a straight chain bent against an angle-harmonic term: EI known, D68"}},
           "the chain that is bent");
  p.integer("beads", s.beads, 3, 200, "", "beads of the chain (the dissertation: 4)");
  p.real("angle_k", s.angle_K, RealRange::open_closed(0, kMaxStiffness), "kcal/mol/rad^2",
         "harmonic chain: the LAMMPS angle K (k_theta = 2 K)");
  p.real("bond_k", s.bond_K, RealRange::open_closed(0, kMaxStiffness), "kcal/mol/A^2",
         "harmonic chain: the LAMMPS bond K (stiff, D68)");
  p.string("supports", s.supports,
           {{"pinned", "both end beads fixed"},
            {"roller", "the last bead free along the chain: a simply supported beam, D67"}},
           "how the end beads are held");
  p.real("spring_k", s.spring_k, RealRange::open_closed(0, kMaxStiffness), "kcal/mol/A^2",
         "constant of the pulling spring");
  p.reals("rates", s.rates, RealRange::above(0), 2, kMaxRates, "A/fs",
          "anchor speeds, one pull each; EI(rate) is extrapolated to rate 0 (D66)")
      .remark("each pull at least 2 x blocks samples");
  p.real("pull_distance", s.pull_distance, RealRange::open_closed(0, 1000), "A",
         "anchor travel per pull (D66)");
  p.real("timestep", s.timestep_fs, RealRange::open_closed(0, 10), "fs", "MD time step");
  p.integer("hold_steps", s.hold_steps, 0, kMaxSteps, "", "steps at zero force before each pull");
  p.integer("sample_every", s.sample_every, 1, 1000000, "", "steps between samples of F and d");
  p.integer("blocks", s.blocks, 3, 10000, "", "blocks of the standard errors");
  p.real("temperature", s.temperature, RealRange::open_closed(0, 1e4), "K",
         "temperature of the Langevin thermostat and of kT in xi_p = EI/kT");
  p.integer("seed", s.seed, 1, 800000000, "", "thermostat seed (LAMMPS seeds)");
}

} // namespace

Parameters persistence_input_parameters(PersistenceSpec& s) {
  Parameters p("pnc thermo persistence input");
  declare_persistence(p, s);
  return p;
}

Parameters persistence_input_parameters() {
  auto s = std::make_shared<PersistenceSpec>();
  Parameters p = persistence_input_parameters(*s);
  p.hold(s);
  return p;
}

PersistenceSpec parse_persistence_input(const nlohmann::json& j, const std::string& source) {
  PersistenceSpec s;
  if (!j.is_object()) fail(source, "", show_json(j), "must be a JSON object (a TOML table)");
  persistence_input_parameters(s).read(j, source);
  s.validate(source); // the rules between keys
  return s;
}

PersistenceSpec read_persistence_input(const std::string& path) {
  return parse_persistence_input(detail::read_input_json(path, "the persistence input file"), path);
}

void override_persistence_input(PersistenceSpec& in, const PersistenceSpec& given,
                                const std::vector<std::string>& keys) {
  detail::override_keys(in, given, keys,
                        [](PersistenceSpec& s) { return persistence_input_parameters(s); });
}

} // namespace pnc::thermo
