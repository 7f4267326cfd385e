// Recipes of `pnc characterize`: strict JSON parsing with errors naming field, value, rule.
#include "pnc/rve/recipe.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

namespace pnc::rve {

namespace {

using json = nlohmann::json;

// Ranges of the integer keys: LAMMPS runs at most 2^31 - 1 steps in one `run`; the builder's
// limits are in BuildSpec::validate() (at most kMaxBeads beads in all).
constexpr std::int64_t kMaxSteps = 2000000000;
constexpr std::int64_t kMaxChains = 100000;
constexpr std::int64_t kMaxBeadsPerChain = 10000;

class Section {
public:
  Section(const json& j, std::string path, const std::string& source)
      : j_(j), path_(std::move(path)), source_(source) {
    if (!j_.is_object()) fail(source_, path_, show_json(j_), "must be a JSON object");
  }
  std::string field(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }
  template <class T> void get(const std::string& key, T& out) {
    static_assert(std::is_same_v<T, bool> || !std::is_integral_v<T>,
                  "integers are read with get_int and a range");
    seen_.insert(key);
    if (!j_.contains(key)) return;
    const json& v = j_.at(key);
    if constexpr (std::is_same_v<T, bool>) {
      if (!v.is_boolean()) fail(source_, field(key), show_json(v), "must be true or false");
      out = v.get<bool>();
    } else if constexpr (std::is_same_v<T, std::string>) {
      if (!v.is_string()) fail(source_, field(key), show_json(v), "must be a string");
      out = v.get<std::string>();
    } else {
      if (!v.is_number()) fail(source_, field(key), show_json(v), "must be a number");
      if (!std::isfinite(v.get<double>()))
        fail(source_, field(key), show_json(v), "must be a finite number");
      out = v.get<T>();
    }
  }
  /// An integer key in [lo, hi] (checked, never narrowed: pnc/core/params.hpp).
  template <class T>
  void get_int(const std::string& key, T& out, std::int64_t lo, std::int64_t hi) {
    seen_.insert(key);
    if (j_.contains(key)) out = get_integer_as<T>(j_.at(key), source_, field(key), lo, hi);
  }
  void get_cases(const std::string& key, std::vector<int>& out) {
    seen_.insert(key);
    if (!j_.contains(key)) return;
    const json& v = j_.at(key);
    if (!v.is_array() || v.empty())
      fail(source_, field(key), show_json(v), "must be a non-empty array of case ids 1..6");
    out.clear();
    for (const auto& e : v) {
      if (!e.is_number_integer() && !e.is_number_unsigned())
        fail(source_, field(key), show_json(e),
             "case ids are integers 1..6 (docs/theory.md section 2.1)");
      out.push_back(get_integer_as<int>(e, source_, field(key), 1, 6));
    }
  }
  Section sub(const std::string& key) {
    seen_.insert(key);
    static const json empty = json::object();
    return Section(j_.contains(key) ? j_.at(key) : empty, field(key), source_);
  }
  void check_unknown() const {
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!seen_.count(it.key())) {
        std::string allowed;
        for (const auto& k : seen_)
          allowed += (allowed.empty() ? "" : ", ") + k;
        fail(source_, field(it.key()), show_json(it.value()), "unknown key; allowed: " + allowed);
      }
  }

private:
  const json& j_;
  std::string path_;
  const std::string& source_;
  std::set<std::string> seen_;
};

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
  Section top(j, "", source);
  top.get("name", r.name);
  check_free_text(source, "name", r.name);
  top.get_int("seed", r.seed, 1, 1000000);
  top.get("model", r.model);
  if (r.model != "pp" && r.model != "pnc" && r.model != "kg" && r.model != "kg_platelet")
    fail(source, "model", r.model,
         "must be \"pp\" (pure polymer), \"pnc\" (with clay), \"kg\" (glassy bead-spring "
         "polymer) or \"kg_platelet\" (the glass with a platelet)");
  const bool kg = r.model == "kg" || r.model == "kg_platelet";
  if (j.contains("platelet")) { // decision D170: the glass with one platelet
    if (r.model != "kg_platelet")
      fail(source, "platelet", show_json(j.at("platelet")),
           "a platelet block needs \"model\": \"kg_platelet\"");
    r.platelet = parse_platelet(j.at("platelet"), source);
    top.sub("platelet");
  }
  const bool user = j.contains("system"); // your own system (user_system.hpp), decision D121
  if (user) {
    for (const char* k : {"build", "clay", "forcefield", "platelet"})
      if (j.contains(k))
        fail(source, k, show_json(j.at(k)),
             "a recipe with a \"system\" section (your own data file and force field) has no "
             "builder, clay or built-in force-field section");
    r.system = parse_user_system(
        j.at("system"), j.contains("equilibrate") ? &j.at("equilibrate") : nullptr, source);
    top.sub("system");
  }
  if (r.model == "pnc" && !j.contains("clay") && !user)
    fail(source, "model", r.model,
         "model \"pnc\" needs a \"clay\" block naming the platelet (cells_a or aspect_ratio, "
         "cells_b), e.g. {\"cells_a\": 7, \"cells_b\": 1}; see the preset paper_pnc");
  if (r.model != "pnc" && j.contains("clay"))
    fail(source, "clay", show_json(j.at("clay")), "a clay block needs \"model\": \"pnc\"");
  if (r.seed < 1 || r.seed > 1000000)
    fail(source, "seed", std::to_string(r.seed), "must be in 1..1000000");
  {
    Section s = top.sub("build");
    s.get_int("chains", r.build.chains, 1, kMaxChains);
    s.get_int("beads_per_chain", r.build.beads_per_chain, 4, kMaxBeadsPerChain);
    s.get("density", r.build.density);
    s.get("min_distance", r.build.min_distance);
    s.check_unknown();
  }
  {
    Section s = top.sub("clay");
    s.get_int("cells_a", r.clay.cells_a, 1, 200);
    s.get_int("cells_b", r.clay.cells_b, 1, 200);
    s.get("aspect_ratio", r.clay.aspect_ratio);
    s.get("min_distance", r.clay.min_distance);
    s.get("gap_x", r.clay.gap_x);
    s.check_unknown();
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
  if (kg) {
    Section s = top.sub("forcefield");
    s.get("sigma", r.kg.sigma);
    s.get("epsilon", r.kg.epsilon);
    s.get("bead_mass", r.kg.bead_mass);
    s.get("fene_K_reduced", r.kg.fene_K_reduced);
    s.get("fene_R0_sigma", r.kg.fene_R0_sigma);
    s.get("cutoff_sigma", r.kg.cutoff_sigma);
    s.get("bond_length_sigma", r.kg.bond_length_sigma);
    s.check_unknown();
    // keys of the polypropylene protocol that the glass protocol does not use (D137)
    if (j.contains("equilibrate") && j.at("equilibrate").is_object())
      for (const char* k :
           {"langevin_chunk_steps", "langevin_max_chunks", "steady_tolerance", "clay_steps"})
        if (j.at("equilibrate").contains(k))
          fail(source, std::string("equilibrate.") + k, show_json(j.at("equilibrate").at(k)),
               "not used by model kg (its protocol: pushoff, melt, quench, final; docs/rve.md)");
  } else {
    Section s = top.sub("forcefield");
    s.get("sigma", r.ff.sigma);
    s.get("epsilon", r.ff.epsilon);
    s.get("cutoff_sigma", r.ff.cutoff_sigma);
    s.check_unknown();
  }
  if (user) {
    top.sub("equilibrate"); // the user's stages, parsed by parse_user_system
  } else {
    auto& e = r.equilibrate;
    Section s = top.sub("equilibrate");
    s.get("timestep_fs", e.timestep_fs);
    s.get("temperature", e.temperature);
    s.get("damp_fs", e.damp_fs);
    s.get_int("pushoff_steps", e.pushoff_steps, 0, kMaxSteps);
    s.get_int("pushoff_max_rounds", e.pushoff_max_rounds, 1, 1000);
    s.get("pushoff_A_max", e.pushoff_A_max);
    s.get("pushoff_min_distance_sigma", e.pushoff_min_distance_sigma);
    s.get_int("hot_steps", e.hot_steps, 0, kMaxSteps);
    s.get("hot_temperature", e.hot_temperature);
    s.get_int("clay_steps", e.clay_steps, 0, kMaxSteps);
    s.get_int("cool_steps", e.cool_steps, 0, kMaxSteps);
    s.get_int("langevin_chunk_steps", e.langevin_chunk_steps, 0, kMaxSteps);
    s.get_int("langevin_max_chunks", e.langevin_max_chunks, 2, 10000);
    s.get("steady_tolerance", e.steady_tolerance);
    s.get("ensemble", e.ensemble);
    s.get("pressure_atm", e.pressure_atm);
    s.get("pdamp_fs", e.pdamp_fs);
    s.get_int("npt_steps", e.npt_steps, 0, kMaxSteps);
    s.get_int("final_steps", e.final_steps, 0, kMaxSteps);
    s.check_unknown();
  }
  {
    auto& d = r.deform;
    Section s = top.sub("deform");
    if (r.model == "pnc" || r.model == "kg_platelet") r.cases = {1, 2, 3, 4, 5, 6};
    s.get_cases("cases", r.cases);
    s.get("strain_max", d.strain_max);
    s.get("shear_strain_max", d.shear_strain_max); // decision D12m
    s.get_int("steps", d.steps, 1, 100000);
    s.get("timestep_fs", d.timestep_fs);
    s.get_int("hold_steps", d.hold_steps, 1, kMaxSteps);
    s.get_int("sample_every", d.sample_every, 1, 1000000);
    s.get_int("blocks", d.blocks, 2, 10000);
    s.get_int("reference_holds", d.reference_holds, 1, 1000);
    s.get("temperature", d.temperature);
    s.get("damp_fs", d.damp_fs);
    s.get("minimize", d.minimize);
    s.check_unknown();
  }
  {
    auto& pc = r.phase_check;
    Section s = top.sub("phase_check");
    s.get("enabled", pc.enabled);
    s.get_int("steps", pc.steps, 1000, kMaxSteps);
    s.get_int("sample_every", pc.sample_every, 1, 1000);
    s.get_int("blocks", pc.blocks, 4, 1000);
    s.get("shear_strain", pc.shear_strain);
    s.get("bulk_strain", pc.bulk_strain);
    s.get("cavitation_strain", pc.cavitation_strain);
    s.get_int("cavitation_steps", pc.cavitation_steps, 100, kMaxSteps);
    s.check_unknown();
    pc.validate(source);
  }
  {
    Section s = top.sub("analysis");
    s.get("stress", r.stress);
    s.get_int("moving_average", r.moving_average, 1, 1001);
    s.get("reference", r.reference);
    s.check_unknown();
    if (r.reference != "subtract" && r.reference != "none")
      fail(source, "analysis.reference", r.reference,
           "must be \"subtract\" (stress relative to the zero-strain hold) or \"none\"");
    if (r.stress != "virial" && r.stress != "total")
      fail(source, "analysis.stress", r.stress,
           "must be \"virial\" (no kinetic term, eq. 6.23) or \"total\" (with kinetic term)");
    if (r.moving_average < 1 || r.moving_average % 2 == 0)
      fail(source, "analysis.moving_average", std::to_string(r.moving_average),
           "must be an odd number >= 1 (1 = off)");
  }
  {
    Section s = top.sub("fit");
    s.get("fit_alpha", r.fit_alpha);
    s.get("hold_alpha", r.hold_alpha);
    s.get("alpha", r.fit_alpha_start);
    s.get("strain_max", r.fit_strain_max);
    s.get("stretch_max", r.fit_stretch_max); // decision D12m
    if (!(r.fit_stretch_max >= 0 && r.fit_stretch_max <= 10))
      fail(source, "fit.stretch_max", fmt::format("{}", r.fit_stretch_max),
           "must be in [0, 10] (lambda_max - 1; 0 = fit every row)");
    if (r.fit_stretch_max > 0 && r.fit_strain_max > 0)
      fail(source, "fit.stretch_max", fmt::format("{}", r.fit_stretch_max),
           "fit.strain_max and fit.stretch_max exclude each other (one fit range)");
    if (!(r.fit_strain_max >= 0 && r.fit_strain_max <= 10))
      fail(source, "fit.strain_max", fmt::format("{}", r.fit_strain_max),
           "must be in [0, 10] (a strain; 0 = fit every row)");
    s.check_unknown();
    if (r.fit_alpha && r.hold_alpha)
      fail(source, "fit.hold_alpha", "true", "fit.fit_alpha and fit.hold_alpha exclude each other");
    if (j.contains("fit") && j.at("fit").is_object() && j.at("fit").contains("alpha") &&
        !(r.fit_alpha_start >= 0.5 && r.fit_alpha_start <= 1.5))
      fail(source, "fit.alpha", fmt::format("{}", r.fit_alpha_start),
           "must be in [0.5, 1.5] (the bounds of the fitted alpha)");
  }
  {
    Section s = top.sub("run");
    s.get_int("jobs", r.jobs, 1, 64);
    s.get_int("replicas", r.replicas, 1, 64); // decision D130
    s.check_unknown();
    if (r.jobs < 1 || r.jobs > 64)
      fail(source, "run.jobs", std::to_string(r.jobs), "must be in 1..64");
  }
  top.sub("slurm"); // the Slurm executor's section (slurm.hpp), parsed there
  if (j.contains("slurm")) r.slurm = parse_slurm_spec(j.at("slurm"), source);
  top.check_unknown();
  if ((r.model == "pp" || r.model == "kg") &&
      std::none_of(r.cases.begin(), r.cases.end(), [](int c) { return c >= 1 && c <= 3; }))
    fail(source, "deform.cases", fmt::format("{}", fmt::join(r.cases, ",")),
         "the pure polymer (models pp and kg) needs at least one extension case (1-3); its "
         "isotropic law pools any of cases 1-6 (decision D12l)");
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
                       (r.build.density * avogadro_per_A3_cm3));
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

namespace {

// TOML -> JSON, so that one validator (parse_recipe) serves both formats. Dates and times
// have no meaning in a recipe and are rejected with the key that holds them.
json toml_to_json(const toml::value& v, const std::string& path, const std::string& source) {
  switch (v.type()) {
  case toml::value_t::boolean:
    return v.as_boolean();
  case toml::value_t::integer:
    return static_cast<std::int64_t>(v.as_integer());
  case toml::value_t::floating:
    return v.as_floating();
  case toml::value_t::string:
    return v.as_string().str;
  case toml::value_t::array: {
    json a = json::array();
    std::size_t i = 0;
    for (const auto& e : v.as_array())
      a.push_back(toml_to_json(e, fmt::format("{}[{}]", path, i++), source));
    return a;
  }
  case toml::value_t::table: {
    json o = json::object();
    for (const auto& [k, e] : v.as_table())
      o[k] = toml_to_json(e, path.empty() ? k : path + "." + k, source);
    return o;
  }
  default:
    fail(source, path, clip(toml::format(v)), "dates and times are not recipe values");
  }
}

// A TOML scalar or inline array. Floats in their shortest exact form (fmt), always with a
// decimal point or exponent so that they read back as floats.
std::string toml_scalar(const json& j) {
  if (j.is_number_float()) {
    std::string f = fmt::format("{}", j.get<double>());
    if (f.find_first_of(".eEn") == std::string::npos) f += ".0";
    return f;
  }
  if (j.is_array()) {
    std::string a = "[";
    for (std::size_t i = 0; i < j.size(); ++i)
      a += (i ? ", " : "") + toml_scalar(j[i]);
    return a + "]";
  }
  if (j.is_object() || j.is_null())
    throw std::logic_error("toml_scalar: objects and null are not TOML scalars");
  return j.dump(); // booleans, integers, strings: JSON's spelling is TOML's
}

void write_toml_table(const json& t, const std::string& name, std::string& out) {
  if (!name.empty()) out += "\n[" + name + "]\n";
  for (const auto& [k, v] : t.items())
    if (!v.is_object()) out += k + " = " + toml_scalar(v) + "\n";
  for (const auto& [k, v] : t.items())
    if (v.is_object()) write_toml_table(v, name.empty() ? k : name + "." + k, out);
}

// Offset of the first byte that is not valid UTF-8 (RFC 3629: no overlong forms, no
// surrogates, at most U+10FFFF), or npos. TOML files are UTF-8; toml11 3.7's own error path
// for invalid UTF-8 inside a literal string reads out of bounds (found by fuzz_recipe_toml),
// so the text is checked before toml11 sees it.
std::size_t invalid_utf8_at(const std::string& s) {
  const auto* b = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned c = b[i];
    std::size_t len = 0;
    unsigned lo = 0x80, hi = 0xbf; // allowed range of the second byte
    if (c < 0x80)
      len = 1;
    else if (c >= 0xc2 && c <= 0xdf)
      len = 2;
    else if (c == 0xe0)
      len = 3, lo = 0xa0;
    else if ((c >= 0xe1 && c <= 0xec) || c == 0xee || c == 0xef)
      len = 3;
    else if (c == 0xed)
      len = 3, hi = 0x9f;
    else if (c == 0xf0)
      len = 4, lo = 0x90;
    else if (c >= 0xf1 && c <= 0xf3)
      len = 4;
    else if (c == 0xf4)
      len = 4, hi = 0x8f;
    else
      return i;
    if (i + len > n) return i;
    for (std::size_t k = 1; k < len; ++k) {
      const unsigned d = b[i + k];
      if (k == 1 ? (d < lo || d > hi) : (d < 0x80 || d > 0xbf)) return i;
    }
    i += len;
  }
  return std::string::npos;
}

} // namespace

std::string recipe_toml(const nlohmann::json& recipe) {
  std::string out;
  write_toml_table(recipe, "", out);
  return out;
}

Recipe read_recipe(const std::string& path) {
  const auto ext = std::filesystem::path(path).extension().string();
  if (ext != ".json" && ext != ".toml") fail(path, "", ext, "a recipe file ends in .json or .toml");
  const std::string text = read_text_file(path, "the recipe");
  json j;
  if (ext == ".toml") {
    if (const auto at = invalid_utf8_at(text); at != std::string::npos)
      fail(path, "",
           fmt::format("byte 0x{:02x} at offset {}", static_cast<unsigned char>(text[at]), at),
           "not valid TOML: a TOML file must be UTF-8");
    check_nesting(text, path, Syntax::toml); // toml11 parses nested values recursively
    toml::value t;
    try {
      std::istringstream in(text);
      t = toml::parse(in, path);
    } catch (const std::exception& e) {
      fail(path, "", "", "not valid TOML: " + clip(e.what(), 400));
    }
    j = toml_to_json(t, "", path);
  } else {
    j = parse_json(text, path);
  }
  return parse_recipe(j, path);
}

nlohmann::json expanded_json(const Recipe& r) {
  const auto& e = r.equilibrate;
  const auto& d = r.deform;
  json out{
      {"name", r.name},
      {"seed", r.seed},
      {"model", r.model},
      {"build",
       {{"chains", r.build.chains},
        {"beads_per_chain", r.build.beads_per_chain},
        {"density", r.build.density},
        {"min_distance", r.build.min_distance}}},
      {"forcefield",
       {{"sigma", r.ff.sigma}, {"epsilon", r.ff.epsilon}, {"cutoff_sigma", r.ff.cutoff_sigma}}},
      {"equilibrate",
       {{"timestep_fs", e.timestep_fs},
        {"temperature", e.temperature},
        {"damp_fs", e.damp_fs},
        {"pushoff_steps", e.pushoff_steps},
        {"pushoff_max_rounds", e.pushoff_max_rounds},
        {"pushoff_A_max", e.pushoff_A_max},
        {"pushoff_min_distance_sigma", e.pushoff_min_distance_sigma},
        {"hot_steps", e.hot_steps},
        {"hot_temperature", e.hot_temperature},
        {"clay_steps", e.clay_steps},
        {"cool_steps", e.cool_steps},
        {"langevin_chunk_steps", e.langevin_chunk_steps},
        {"langevin_max_chunks", e.langevin_max_chunks},
        {"steady_tolerance", e.steady_tolerance},
        {"ensemble", e.ensemble},
        {"pressure_atm", e.pressure_atm},
        {"pdamp_fs", e.pdamp_fs},
        {"npt_steps", e.npt_steps},
        {"final_steps", e.final_steps}}},
      {"deform",
       {{"cases", r.cases},
        {"strain_max", d.strain_max},
        {"steps", d.steps},
        {"timestep_fs", d.timestep_fs},
        {"hold_steps", d.hold_steps},
        {"sample_every", d.sample_every},
        {"blocks", d.blocks},
        {"reference_holds", d.reference_holds},
        {"temperature", d.temperature},
        {"damp_fs", d.damp_fs},
        {"minimize", d.minimize}}},
      {"analysis",
       {{"stress", r.stress}, {"moving_average", r.moving_average}, {"reference", r.reference}}},
      {"phase_check",
       {{"enabled", r.phase_check.enabled},
        {"steps", r.phase_check.steps},
        {"sample_every", r.phase_check.sample_every},
        {"blocks", r.phase_check.blocks},
        {"shear_strain", r.phase_check.shear_strain},
        {"bulk_strain", r.phase_check.bulk_strain},
        {"cavitation_strain", r.phase_check.cavitation_strain},
        {"cavitation_steps", r.phase_check.cavitation_steps}}},
      {"fit", {{"fit_alpha", r.fit_alpha}}},
      {"run", {{"jobs", r.jobs}, {"replicas", r.replicas}}}};
  if (r.fit_alpha_start > 0) out["fit"]["alpha"] = r.fit_alpha_start;
  if (r.hold_alpha) out["fit"]["hold_alpha"] = true;
  if (r.fit_strain_max > 0) out["fit"]["strain_max"] = r.fit_strain_max;
  if (r.fit_stretch_max > 0) out["fit"]["stretch_max"] = r.fit_stretch_max;
  if (r.deform.shear_strain_max != 0) out["deform"]["shear_strain_max"] = r.deform.shear_strain_max;
  if (r.slurm.given) out["slurm"] = slurm_spec_json(r.slurm);
  if (r.system.enabled) {
    const json u = user_system_json(r.system);
    out.erase("build");
    out.erase("forcefield");
    out["system"] = u.at("system");
    out["equilibrate"] = u.at("equilibrate");
    return out;
  }
  if (r.model == "kg_platelet") out["platelet"] = platelet_json(r.platelet);
  if (r.model == "kg" || r.model == "kg_platelet") {
    out["forcefield"] = {{"sigma", r.kg.sigma},
                         {"epsilon", r.kg.epsilon},
                         {"bead_mass", r.kg.bead_mass},
                         {"fene_K_reduced", r.kg.fene_K_reduced},
                         {"fene_R0_sigma", r.kg.fene_R0_sigma},
                         {"cutoff_sigma", r.kg.cutoff_sigma},
                         {"bond_length_sigma", r.kg.bond_length_sigma}};
    for (const char* k :
         {"langevin_chunk_steps", "langevin_max_chunks", "steady_tolerance", "clay_steps"})
      out["equilibrate"].erase(k);
  }
  if (r.model == "pnc")
    out["clay"] = {{"cells_a", r.clay.cells_a},
                   {"cells_b", r.clay.cells_b},
                   {"min_distance", r.clay.min_distance},
                   {"gap_x", r.clay.gap_x}};
  return out;
}

} // namespace pnc::rve
