// The material laws of `pnc gimp run` (materials[].type): each law declares its keys and
// builds itself from a checked entry; material_kinds() lists them, one line per law. A new
// law is a class in materials.hpp, a declare and a make function here, and one row below.
// SI units (Pa, kg/m^3).
#include "input_declare.hpp"
#include "input_parts.hpp"

#include "pnc/fe_material/material.hpp"

#include <tuple>

namespace pnc::gimp::input_detail {

namespace fs = std::filesystem;
using declare::real;
using declare::string;

namespace {

// ---- linear_elastic: St Venant-Kirchhoff ----

void declare_linear_elastic(Parameters& p) {
  real(p, "E", nullptr, RealRange::above(0), "Pa", "Young's modulus").require();
  real(p, "nu", nullptr, RealRange::open(-1, 0.5), "1", "Poisson's ratio").require();
}

std::shared_ptr<const Material> make_linear_elastic(const Node& m, const std::string&, double rho) {
  return std::make_shared<LinearElastic>(rho, m.num("E"), m.num("nu"));
}

// ---- hyperelastic_polymer: docs/theory.md section 5.3, D31 ----

void declare_hyperelastic_polymer(Parameters& p) {
  real(p, "E", nullptr, RealRange::above(0), "Pa", "small-strain Young's modulus")
      .no_default("1.5e9 Pa unless c1, c2 are given")
      .remark("not with c1, c2");
  real(p, "nu", nullptr, RealRange::open(-1, 0.5), "1", "small-strain Poisson's ratio")
      .no_default("0.33 unless c1, c2 are given");
  real(p, "c1", nullptr, RealRange::above(0), "Pa", "volumetric constant (K = 8 c1)")
      .no_default("from E, nu")
      .remark("c1 and c2 together");
  real(p, "c2", nullptr, RealRange::above(0), "Pa", "shear constant (mu = 38 c2)")
      .no_default("from E, nu");
}

std::shared_ptr<const Material> make_hyperelastic_polymer(const Node& m, const std::string&,
                                                          double rho) {
  double c1, c2;
  if (m.has("c1") || m.has("c2")) {
    if (m.has("E") || m.has("nu"))
      m.bad("E", m.has("E") ? m.at("E") : m.at("nu"), "give either (c1, c2) or (E, nu)");
    if (!m.has("c1") || !m.has("c2"))
      fail(m.src, m.key(m.has("c1") ? "c2" : "c1"), "<missing>", "give c1 and c2 together");
    c1 = m.num("c1");
    c2 = m.num("c2");
  } else {
    const double E = m.num("E", 1.5e9), nu = m.num("nu", 0.33);
    std::tie(c1, c2) = HyperelasticPolymer::calibrate(E, nu);
  }
  return std::make_shared<HyperelasticPolymer>(rho, c1, c2);
}

// ---- damage_card: the NDM of a card through the fe_material plugin (D32) ----

void declare_damage_card(Parameters& p) {
  string(p, "card", nullptr, {}, "HDF5 material card (relative to the input file's folder)")
      .require();
}

std::shared_ptr<const Material> make_damage_card(const Node& m, const std::string& base_dir,
                                                 double rho) {
  const fs::path card = resolve(base_dir, m.str("card"));
  if (!fs::exists(card)) m.bad("card", m.at("card"), "file not found: " + card.string());
  try {
    auto law = std::make_shared<const pnc::fe_material::Material>(
        pnc::fe_material::Material::from_card(card.string()));
    return std::make_shared<DamageLaw>(rho, law);
  } catch (const pnc::fe_material::Error& e) {
    m.bad("card", m.at("card"), std::string("not a usable material card: ") + e.what());
  }
}

} // namespace

const std::vector<MaterialKind>& material_kinds() {
  static const std::vector<MaterialKind> kinds = {
      {"linear_elastic", "St Venant-Kirchhoff", declare_linear_elastic, make_linear_elastic},
      {"hyperelastic_polymer", "the polymer's hyperelastic law (theory.md section 5.3, D31)",
       declare_hyperelastic_polymer, make_hyperelastic_polymer},
      {"damage_card", "the NDM of a material card through the fe_material plugin (D32)",
       declare_damage_card, make_damage_card},
  };
  return kinds;
}

const MaterialKind* find_material_kind(const std::string& type) {
  for (const auto& k : material_kinds())
    if (k.type == type) return &k;
  return nullptr;
}

std::vector<Choice> material_type_choices() {
  std::vector<Choice> c;
  for (const auto& k : material_kinds())
    c.push_back({k.type, k.text});
  return c;
}

} // namespace pnc::gimp::input_detail
