// Recipes of `pnc characterize`: read through the declared keys (recipe_parameters.cpp), then
// the rules between keys; errors name the file, the field, the value and the rule.
#include "pnc/rve/recipe.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/params.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>

namespace pnc::rve {

namespace {

using json = nlohmann::json;

// The recipe's model before it is read: an invalid one reads as "pp", whose declaration of
// "model" then refuses it.
std::string model_of(const json& j) {
  if (j.contains("model") && j.at("model").is_string()) {
    const auto& m = j.at("model").get_ref<const std::string&>();
    if (m == "pnc" || m == "kg" || m == "kg_platelet") return m;
  }
  return "pp";
}

// Which sections a recipe may have depends on its model and on "system": refused before the
// declared reads, with the reason (the declarations of the variant would call them unknown).
void check_sections(const json& j, const std::string& variant, const std::string& source) {
  if (variant == "system") {
    for (const char* k : {"build", "clay", "forcefield", "platelet"})
      if (j.contains(k))
        fail(source, k, show_json(j.at(k)),
             "a recipe with a \"system\" section (your own data file and force field) has no "
             "builder, clay or built-in force-field section");
    return;
  }
  if (j.contains("platelet") && variant != "kg_platelet") // decision D170
    fail(source, "platelet", show_json(j.at("platelet")),
         "a platelet block needs \"model\": \"kg_platelet\"");
  if (j.contains("clay") && variant != "pnc")
    fail(source, "clay", show_json(j.at("clay")), "a clay block needs \"model\": \"pnc\"");
  if (variant == "pnc" && !j.contains("clay"))
    fail(source, "model", "pnc",
         "model \"pnc\" needs a \"clay\" block naming the platelet (cells_a or aspect_ratio, "
         "cells_b), e.g. {\"cells_a\": 7, \"cells_b\": 1}; see the preset paper_pnc");
  // keys of the polypropylene protocol that the glass protocol does not use (D137)
  if ((variant == "kg" || variant == "kg_platelet") && j.contains("equilibrate") &&
      j.at("equilibrate").is_object())
    for (const char* k :
         {"langevin_chunk_steps", "langevin_max_chunks", "steady_tolerance", "clay_steps"})
      if (j.at("equilibrate").contains(k))
        fail(source, std::string("equilibrate.") + k, show_json(j.at("equilibrate").at(k)),
             "not used by model kg (its protocol: pushoff, melt, quench, final; docs/rve.md)");
}

} // namespace

void check_free_text(const std::string& source, const std::string& field, const std::string& value,
                     std::size_t max_chars) {
  if (value.empty()) fail(source, field, value, "must not be empty");
  if (value.size() > max_chars)
    fail(source, field, value.substr(0, max_chars) + "...",
         fmt::format("must be at most {} characters (it has {})", max_chars, value.size()));
  for (const char c : value) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u > 0x7e) {
      std::string shown;
      for (const char d : value) {
        const auto v = static_cast<unsigned char>(d);
        shown += v < 0x20 || v > 0x7e ? fmt::format("\\x{:02x}", v) : std::string(1, d);
      }
      fail(source, field, shown,
           fmt::format("must be printable ASCII characters only (found byte 0x{:02x}; no newline, "
                       "tab or other control character)",
                       u));
    }
  }
}

Recipe parse_recipe(const nlohmann::json& j, const std::string& source) {
  Recipe r;
  r.source_json = j;
  if (!j.is_object()) fail(source, "", show_json(j), "must be a JSON object");
  // the declarations to read with (recipe_parameters.cpp): your own system's (user_system.hpp,
  // decision D121) or the model's
  const std::string model = model_of(j);
  const std::string variant = j.contains("system") ? "system" : model;
  const bool user = variant == "system";
  check_sections(j, variant, source);
  if (model == "pnc" || model == "kg_platelet") r.cases = {1, 2, 3, 4, 5, 6};
  {
    Parameters p("pnc characterize recipe");
    declare_recipe(p, r, variant); // every key: type, range, default (recipe_parameters.cpp)
    p.read(j, source);
  }
  // rules between keys and sections, after the declared reads (decision D231)
  const bool kg = r.model == "kg" || r.model == "kg_platelet";
  if (user) finish_user_system(r.system, source); // one file, resolved and hashed
  if (r.model == "kg_platelet" && !user) r.platelet.validate(source);
  if (r.model == "pnc" && !user) {
    r.clay.validate(source);
    if (r.clay.aspect_ratio > 0) {
      if (j.at("clay").contains("cells_a"))
        fail(source, "clay.aspect_ratio", fmt::format("{}", r.clay.aspect_ratio),
             "give either clay.cells_a or clay.aspect_ratio, not both");
      const ClayLattice lat;
      r.clay.cells_a = std::max(
          1, static_cast<int>(std::lround(r.clay.aspect_ratio * r.clay.cells_b * lat.b / lat.a)));
      r.clay.aspect_ratio = 0; // expanded into cells_a
      r.clay.validate(source);
    }
  }
  r.phase_check.validate(source);
  if (r.fit_alpha && r.hold_alpha)
    fail(source, "fit.hold_alpha", "true", "fit.fit_alpha and fit.hold_alpha exclude each other");
  if (r.fit_stretch_max > 0 && r.fit_strain_max > 0) // decision D12m
    fail(source, "fit.stretch_max", fmt::format("{}", r.fit_stretch_max),
         "fit.strain_max and fit.stretch_max exclude each other (one fit range)");
  if (r.fit_isotropic && r.model != "pp" && r.model != "kg") // decision D396
    fail(source, "fit.isotropic", "true",
         "the isotropy ties (C44 = (C11 - C12)/2, B4 = B1 - B2/2) are of the pure-polymer law: "
         "models pp and kg, not " +
             r.model);
  if ((r.model == "pp" || r.model == "kg") &&
      std::none_of(r.cases.begin(), r.cases.end(), [](int c) { return c >= 1 && c <= 3; }))
    fail(source, "deform.cases", fmt::format("{}", fmt::join(r.cases, ",")),
         "the pure polymer (models pp and kg) needs at least one extension case (1-3); its "
         "isotropic law pools any of cases 1-9 (decision D12l)");
  r.equilibrate.seed = r.seed;
  r.build.seed = r.seed;
  r.build.validate(source);
  r.ff.validate(source);
  r.equilibrate.validate(source);
  if (r.phase_check.enabled && r.phase_check.steps < 2 * r.deform.hold_steps)
    fail(source, "phase_check.steps", std::to_string(r.phase_check.steps),
         fmt::format("must be >= 2 x deform.hold_steps = {} (G(t) is measured up to the hold "
                     "time from at least as many time origins)",
                     2 * r.deform.hold_steps));
  if (kg) {
    r.kg.validate(source);
    check_glass_protocol(r.equilibrate, source);
    if (!(r.build.min_distance < r.kg.bond_length()))
      fail(source, "build.min_distance", fmt::format("{}", r.build.min_distance),
           fmt::format("model kg: must be below the bond length {:.3f} A", r.kg.bond_length()));
  }
  DeformSpec probe = r.deform;
  probe.start_state = "<equilibrated state>";
  probe.seed = r.seed;
  probe.validate(source);
  // the cutoff must fit the smallest box: 2 r_c < L at the build density
  const double bead_mass = kg ? r.kg.bead_mass : r.ff.bead_mass;
  const double cutoff = kg ? r.kg.cutoff() : r.ff.cutoff();
  double L = std::cbrt(r.build.chains * r.build.beads_per_chain * bead_mass /
                       (r.build.density * md::avogadro_per_A3_cm3));
  if (user) return r; // LAMMPS checks the user's box against the cutoffs
  if (r.model == "kg_platelet") {
    check_platelet_recipe(r, source); // platelet.hpp: box, cutoffs, timesteps (D172, D173)
    return r;
  }
  if (r.model == "pnc") {
    const auto box = composite_box(r.build, r.ff, r.clay, source);
    L = std::min({box[0], box[1], box[2]});
  }
  if (2 * cutoff >= L)
    fail(source, "build.chains", std::to_string(r.build.chains),
         fmt::format("the box ({:.2f} A at the build density) must exceed twice the LJ cutoff "
                     "({:.2f} A): use more chains",
                     L, 2 * cutoff));
  return r;
}

std::string recipe_toml(const nlohmann::json& recipe) {
  return to_toml(recipe);
}

Recipe read_recipe(const std::string& path) {
  const auto ext = std::filesystem::path(path).extension().string();
  if (ext != ".json" && ext != ".toml") fail(path, "", ext, "a recipe file ends in .json or .toml");
  const std::string text = read_text_file(path, "the recipe");
  return parse_recipe(ext == ".toml" ? parse_toml(text, path) : parse_json(text, path), path);
}

} // namespace pnc::rve
