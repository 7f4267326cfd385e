// pnc card export: the card as the input blocks of a host (Abaqus, CalculiX), as JSON or as the
// bare PROPS. The PROPS come from the plugin's own metadata (pnc_material_umat_*), the layout
// umat_ reads, so there is no second list of it here (docs/decisions.md D163).
#include "commands.hpp"
#include "material_plugin.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <iostream>

namespace pnc::app {

namespace {

constexpr std::size_t kPerLine = 8; // Abaqus/CalculiX data lines: at most 8 numbers each

std::string num(double v) {
  std::string s = fmt::format("{}", v); // shortest form that reads back exactly
  if (s.find_first_of(".eEn") == std::string::npos) s += "."; // a real in Fortran input
  return s;
}

// State variables, for *DEPVAR: name and meaning (docs/plugin.md "State variables").
std::string state_meaning(const std::string& name) {
  if (name.rfind("kappa", 0) == 0)
    return "largest stretch of damage mode " + (name.size() > 5 ? name.substr(5) : "") +
           " so far (1 = virgin)";
  return "damage variable " + name + " (0 = undamaged)";
}

void check_name(const std::string& name, std::size_t max) {
  if (name.empty() || name.size() > max)
    fail("<command line>", "--name", name,
         fmt::format("a material name has 1 to {} characters", max));
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'))
      fail("<command line>", "--name", name,
           "a material name has letters, digits, '_' and '-' only (no blanks or commas)");
}

std::string props_block(const std::vector<double>& props) {
  std::string s;
  for (std::size_t i = 0; i < props.size(); ++i)
    s += num(props[i]) + (i + 1 == props.size() ? "\n" : (i + 1) % kPerLine == 0 ? ",\n" : ", ");
  return s;
}

} // namespace

int run_card_export(const CardExportArgs& a) {
  if (!a.out.empty()) check_output_file(a.out, "--out");
  const pnc::fe_material::Plugin plugin = load_material_plugin(a.plugin);
  const pnc::fe_material::Material mat = load_card(plugin, a.card, a.allow_not_usable);
  const std::vector<double> props = mat.umat_props(a.with_rotation);
  const auto names = mat.umat_prop_names(props.size());
  const auto units = mat.umat_prop_units(props.size());
  const auto states = mat.state_names();
  const std::string header =
      fmt::format("pnc card export: {} (model {}, verdict {})", a.card, mat.model(), mat.verdict());
  const std::string layout =
      "PROPS layout of docs/plugin.md, read from the plugin " + plugin.path();
  const std::string si = "SI units: Pa; model code, alpha and R dimensionless";
  std::string text;
  if (a.format == "abaqus" || a.format == "calculix") {
    const bool ccx = a.format == "calculix";
    // CalculiX calls an Abaqus-style umat for materials named ABAQUS<name> (it strips the
    // prefix before the call); the name has at most 80 characters in both codes.
    const std::string name = a.name.empty() ? "PNC" : a.name;
    check_name(name, ccx ? 74 : 80);
    const std::string full = ccx ? "ABAQUS" + name : name;
    text += "** " + header + "\n** " + layout + "\n** " + si + "\n";
    text += "** PROPS: ";
    for (std::size_t i = 0; i < names.size(); ++i)
      text += (i ? " " : "") + names[i];
    text += "\n";
    if (ccx) {
      text += "** CalculiX: the ABAQUS prefix selects the Abaqus-style umat (a ccx rebuilt with "
              "libpnc_material, docs/hosts.md)\n";
      text += fmt::format("*MATERIAL, NAME={}\n*USER MATERIAL, CONSTANTS={}\n", full, props.size());
    } else {
      text += "** The consistent tangent is not symmetric: UNSYMM\n";
      text += fmt::format("*MATERIAL, NAME={}\n*USER MATERIAL, CONSTANTS={}, UNSYMM\n", full,
                          props.size());
    }
    text += props_block(props);
    text += fmt::format("*DEPVAR\n{}\n", states.size());
    if (!ccx)
      for (std::size_t i = 0; i < states.size(); ++i)
        text += fmt::format("{}, {}, {}\n", i + 1, states[i], state_meaning(states[i]));
    else
      for (std::size_t i = 0; i < states.size(); ++i)
        text += fmt::format("** SDV{} = {}: {}\n", i + 1, states[i], state_meaning(states[i]));
  } else if (a.format == "props") {
    for (std::size_t i = 0; i < props.size(); ++i)
      text += num(props[i]) + "\n";
  } else if (a.format == "json") {
    nlohmann::json j;
    j["command"] = "card export";
    j["card"] = a.card;
    j["model"] = mat.model();
    j["verdict"] = mat.verdict();
    j["plugin"] = plugin.path();
    j["nprops"] = props.size();
    j["props"] = nlohmann::json::array();
    for (std::size_t i = 0; i < props.size(); ++i)
      j["props"].push_back(
          {{"index", i + 1}, {"name", names[i]}, {"value", props[i]}, {"units", units[i]}});
    j["nstatv"] = states.size();
    j["statev"] = nlohmann::json::array();
    for (std::size_t i = 0; i < states.size(); ++i)
      j["statev"].push_back(
          {{"index", i + 1}, {"name", states[i]}, {"meaning", state_meaning(states[i])}});
    j["units"] = "SI: Pa for C*, A*, B*; 1 for model_code, alpha, R";
    j["note"] = header + "; " + layout;
    text = j.dump(2) + "\n";
  } else {
    fail("<command line>", "--format", a.format, "must be abaqus, calculix, json or props");
  }
  if (a.out.empty())
    std::cout << text << std::flush;
  else
    write_text_atomically(a.out, text);
  std::cerr << fmt::format("pnc card export: {} -> {} ({} PROPS, {} state variables){}\n", a.card,
                           a.format, props.size(), states.size(),
                           a.out.empty() ? "" : ", wrote " + a.out);
  return 0;
}

} // namespace pnc::app
