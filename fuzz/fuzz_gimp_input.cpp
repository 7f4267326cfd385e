// Fuzz target: the JSON input of `pnc gimp run` (pnc::gimp::load_input_text), read into a 2-D
// and a 3-D solver (one of them refuses the dimension). Relative paths resolve against a
// scratch directory holding a valid pure-polymer card (pp_card.h5) and a particle CSV
// (particles.csv), so that the "damage_card" and "particles" routes are reached.
//
// Resource bound of the harness (not of pnc): inputs whose grid could hold more than
// kMaxParticles particles are skipped. Such inputs are valid and merely slow (the reader
// places every particle); they would turn the fuzzer's time limit into false reports.
#include "fuzz_util.hpp"

#include "pnc/damage/card.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/gimp_coupler/input.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace {

constexpr double kMaxParticles = 2e5;

// the scratch directory, removed at exit
struct ScratchDir {
  std::string path;
  ScratchDir();
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

ScratchDir::ScratchDir() {
  const char* t = std::getenv("TMPDIR");
  std::string dir = std::string(t && *t ? t : "/tmp") + "/pnc-fuzz-gimp-XXXXXX";
  if (!mkdtemp(dir.data())) std::abort();
  path = dir;
  using namespace pnc::damage;
  write_card(dir + "/pp_card.h5",
             card_from_parameters(dissertation_parameters(Model::pp), "fuzz seed"), "fuzz");
  std::ofstream(dir + "/particles.csv") << "x,y,z,volume,vx,vy,vz\n"
                                        << "1.5,1.5,1.5,0.1,0,0,0\n"
                                        << "2.5,1.5,1.5,0.1,1,0,0\n";
}

// false for inputs the harness does not run (see the resource bound above)
bool small_enough(const std::string& text) {
  const auto j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object() || !j.contains("grid") || !j["grid"].is_object()) return true;
  const auto& cells = j["grid"].value("cells", nlohmann::json());
  double n = 1;
  if (cells.is_array())
    for (const auto& c : cells)
      if (c.is_number()) n *= std::max(1.0, c.get<double>());
  double ppc = 2;
  if (j.contains("particles_per_cell") && j["particles_per_cell"].is_number())
    ppc = std::max(1.0, j["particles_per_cell"].get<double>());
  const double dim = cells.is_array() ? static_cast<double>(cells.size()) : 2.0;
  return n * std::pow(ppc, dim) <= kMaxParticles;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const ScratchDir scratch;
  const std::string& dir = scratch.path;
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (!small_enough(text)) return -1; // not added to the corpus
  pnc::fuzz::expect_clean([&] {
    pnc::gimp::Solver<2> s;
    (void)pnc::gimp::load_input_text<2>(text, "<fuzz>", dir, s);
  });
  pnc::fuzz::expect_clean([&] {
    pnc::gimp::Solver<3> s;
    (void)pnc::gimp::load_input_text<3>(text, "<fuzz>", dir, s);
  });
  return 0;
}
