// pnc card show / pnc card tables.
#include "commands.hpp"
#include "report.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/moduli.hpp"
#include "pnc/damage/reference.hpp"

#include <fmt/format.h>

#include <iostream>

namespace pnc::app {

namespace {
const char* kComp[6] = {"11", "22", "33", "23", "13", "12"};
}

int run_card_show(const CardShowArgs& a) {
  using namespace pnc::damage;
  const Card c = read_card(a.card);
  const Model m = c.params.model;
  const DerivedModuli d = derive_moduli(c.params);
  std::cerr << fmt::format("pnc card {}: NDM, model {} ({})\n", a.card, model_name(m),
                           m == Model::pnc ? "nanocomposite, 3 damage modes"
                                           : "pure polymer, isotropic reading");
  if (!c.software.empty())
    std::cerr << "  written by " << c.software << " on " << c.created << "\n";
  std::cerr << verdict_text(c.verdict) << constants_table(c);
  const double G = 1e9;
  std::cerr << "  derived moduli of C0 (GPa):\n";
  std::cerr << fmt::format("    by compliance inversion: E1 = {:.4g}, E2 = {:.4g}, E3 = {:.4g}\n",
                           d.E1 / G, d.E2 / G, d.E3 / G);
  std::cerr << fmt::format(
      "      nu12 = {:.4g}, nu13 = {:.4g}, nu23 = {:.4g} (nu21 = {:.4g}, nu31 = "
      "{:.4g}, nu32 = {:.4g})\n",
      d.nu12, d.nu13, d.nu23, d.nu21, d.nu31, d.nu32);
  std::cerr << fmt::format("      G23 = {:.4g}, G13 = {:.4g}, G12 = {:.4g}\n", d.G23 / G, d.G13 / G,
                           d.G12 / G);
  if (m == Model::pnc)
    std::cerr << fmt::format(
        "    E2 as printed (the source's determinant-ratio formula, labelled E2 in the "
        "published table; it equals E1 by inversion): {:.4g}\n",
        d.E2_as_printed / G);
  else
    std::cerr << fmt::format(
        "    isotropic formula (E from C22 -> C11, C12; docs/theory.md §1.5): {:.4g}\n",
        d.E_isotropic_formula / G);
  std::cerr << "  strength per case (first local maximum of the driven stress along the case "
               "path, strain <= "
            << a.max_strain << "):\n";
  nlohmann::json strengths = nlohmann::json::array();
  for (int id : model_cases(m)) {
    const CaseStrength s = case_strength(c.params, id, a.max_strain);
    if (s.peak)
      std::cerr << fmt::format("    case {} ({}): sigma{} max = {:.4g} MPa at strain {:.4g}\n", id,
                               deformation_case(id).name, kComp[s.component], *s.peak / 1e6,
                               s.strain_at_peak);
    else
      std::cerr << fmt::format("    case {} ({}): no peak (stress rises monotonically up to strain "
                               "{})\n",
                               id, deformation_case(id).name, s.max_strain_searched);
    strengths.push_back(
        {{"case", id},
         {"component", kComp[s.component]},
         {"peak_Pa", s.peak ? nlohmann::json(*s.peak) : nlohmann::json()},
         {"strain_at_peak", s.peak ? nlohmann::json(s.strain_at_peak) : nlohmann::json()},
         {"max_strain_searched", s.max_strain_searched}});
  }
  if (c.fit.present) {
    std::cerr << fmt::format("  fit: {} from {} ({}), {} iterations, {}\n", c.fit.termination,
                             c.fit.data_source, c.fit.data_hash, c.fit.iterations,
                             c.fit.stress_definition);
    std::cerr << fit_tables(c.fit, m);
  }
  if (a.json) {
    nlohmann::json j;
    j["command"] = "card show";
    j["card"] = a.card;
    j["model"] = model_name(m);
    j["verdict"] = verdict_json(c.verdict);
    j["constants"] = constants_json(c);
    j["moduli"] = {{"E1", d.E1},
                   {"E2", d.E2},
                   {"E3", d.E3},
                   {"nu12", d.nu12},
                   {"nu13", d.nu13},
                   {"nu23", d.nu23},
                   {"nu21", d.nu21},
                   {"nu31", d.nu31},
                   {"nu32", d.nu32},
                   {"G23", d.G23},
                   {"G13", d.G13},
                   {"G12", d.G12},
                   {"E2_as_printed", d.E2_as_printed},
                   {"E_isotropic_formula", d.E_isotropic_formula},
                   {"units", "Pa"},
                   {"note", "E1..E3 by compliance inversion; E2_as_printed is the source's "
                            "determinant-ratio formula for E2 as printed (equals E1); "
                            "E_isotropic_formula is the source's isotropic-polymer formula"}};
    j["strengths"] = strengths;
    if (c.fit.present) j["fit"] = fit_json(c.fit);
    std::cout << j.dump() << std::endl;
  }
  return 0;
}

int run_card_tables(const CardTablesArgs& a) {
  using namespace pnc::damage;
  check_output_file(a.out, "--out");
  const Model m = parse_model(a.model, "<command line>: --model");
  const Card c = card_from_parameters(
      dissertation_parameters(m),
      "Nair (2010) Tables 6.6-6.11 as read in docs/decisions.md D9 (not fitted here)");
  write_card(a.out, c, a.command_line);
  std::cerr << "pnc card tables: wrote the dissertation's " << model_name(m) << " constants to "
            << a.out << "\n"
            << constants_table(c);
  if (a.json) {
    nlohmann::json j;
    j["command"] = "card tables";
    j["card"] = a.out;
    j["model"] = model_name(m);
    j["constants"] = constants_json(c);
    std::cout << j.dump() << std::endl;
  }
  return 0;
}

} // namespace pnc::app
