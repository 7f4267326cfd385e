// pnc synth: synthetic stress-strain curves from the NDM (dissertation constants or a card).
#include "commands.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <iostream>

namespace pnc::app {

int run_synth(const SynthArgs& a) {
  using namespace pnc::damage;
  check_output_file(a.out, "--out");
  NdmParameters p;
  std::string from;
  if (!a.card.empty()) {
    p = read_card(a.card).params;
    from = a.card;
  } else {
    p = dissertation_parameters(parse_model(a.model, "<command line>: --model"));
    from = "dissertation tables 6.6-6.11";
  }
  SynthOptions o;
  o.cases = a.cases;
  o.points = a.points;
  o.max_extension = a.max_extension;
  o.max_shear = a.max_shear;
  o.noise_sd = a.noise_mpa * 1e6;
  o.seed = a.seed;
  StressStrainData d = synthesize(p, o);
  d.stress_definition += ", constants from " + from;
  const auto ends = [&](const char* s) {
    const std::string e(s);
    return a.out.size() >= e.size() && a.out.compare(a.out.size() - e.size(), e.size(), e) == 0;
  };
  if (ends(".csv"))
    write_stress_strain_csv(a.out, d);
  else if (ends(".h5") || ends(".hdf5"))
    write_stress_strain_h5(a.out, d);
  else
    fail("<command line>", "--out", a.out, "must end in .csv or .h5");
  std::cerr << fmt::format(
      "pnc synth: {} cases x {} points, model {}, noise sd {} MPa, seed {} -> {}\n", d.cases.size(),
      a.points, model_name(p.model), a.noise_mpa, a.seed, a.out);
  if (a.json) {
    nlohmann::json j;
    j["command"] = "synth";
    j["out"] = a.out;
    j["model"] = model_name(p.model);
    j["points"] = d.points();
    std::vector<int> ids;
    for (const auto& c : d.cases)
      ids.push_back(c.id);
    j["cases"] = ids;
    j["noise_sd_Pa"] = o.noise_sd;
    j["seed"] = a.seed;
    std::cout << j.dump() << std::endl;
  }
  return 0;
}

} // namespace pnc::app
