// The registry of deformation cases (pnc/damage/cases.hpp, docs/theory.md section 2.1, D316).
#include "pnc/damage/cases.hpp"

#include "pnc/core/error.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace pnc::damage {

namespace {
/// e_a e_b: the gradient of an extension along a (a == b) or of a simple shear a-b (a < b).
Eigen::Matrix3d unit(int a, int b) {
  Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
  g(a, b) = 1.0;
  return g;
}
} // namespace

const std::vector<DeformationCase>& deformation_cases() {
  // one row per case: id, name, driven Voigt components (D360), active stresses, damage mode, dF/dt
  static const std::vector<DeformationCase> cases = {
      {1, "extension x1 (x2, x3 held)", {0}, {0, 1, 2}, 0, unit(0, 0)},
      {2, "extension x2 (x1, x3 held)", {1}, {0, 1, 2}, 1, unit(1, 1)},
      {3, "extension x3 (x1, x2 held)", {2}, {0, 1, 2}, 2, unit(2, 2)},
      {4, "simple shear 2-3", {3}, {3}, 1, unit(1, 2)},
      {5, "simple shear 1-3", {4}, {4}, 2, unit(0, 2)},
      {6, "simple shear 1-2", {5}, {5}, 1, unit(0, 1)},
      // the same shears in the negative sense (gamma = -t): one run can hold both senses of a
      // shear, whose softening differs between the two on one replica (D424)
      {7, "negative simple shear 2-3", {3}, {3}, 1, -unit(1, 2)},
      {8, "negative simple shear 1-3", {4}, {4}, 2, -unit(0, 2)},
      {9, "negative simple shear 1-2", {5}, {5}, 1, -unit(0, 1)},
  };
  return cases;
}

bool is_deformation_case(int id) {
  for (const auto& c : deformation_cases())
    if (c.id == id) return true;
  return false;
}

std::string deformation_case_rule() {
  std::string list;
  for (const auto& c : deformation_cases())
    list += fmt::format("{}{} {}", list.empty() ? "" : ", ", c.id, c.name);
  const auto& all = deformation_cases();
  return fmt::format("deformation case must be an integer {}..{} ({})", all.front().id,
                     all.back().id, list);
}

const DeformationCase& deformation_case(int id, const std::string& source) {
  for (const auto& c : deformation_cases())
    if (c.id == id) return c;
  fail(source, "case", std::to_string(id), deformation_case_rule());
}

Eigen::Matrix3d deformation_gradient(const DeformationCase& c, double t) {
  return Eigen::Matrix3d::Identity() + t * c.gradient;
}

Voigt case_strain(const DeformationCase& c, double amount) {
  const Eigen::Matrix3d g = amount * c.gradient; // F - I
  static constexpr int row[6] = {0, 1, 2, 1, 0, 0}, col[6] = {0, 1, 2, 2, 2, 1};
  Voigt e;
  for (int v = 0; v < 6; ++v) // engineering shear: gamma_ab = (F - I)_ab + (F - I)_ba
    e[v] = v < 3 ? g(row[v], col[v]) : g(row[v], col[v]) + g(col[v], row[v]);
  return e;
}

Voigt case_strain(int id, double amount) {
  return case_strain(deformation_case(id), amount);
}

double driven_sense(const DeformationCase& c) {
  const Voigt e = case_strain(c, 1.0);
  const double sense = e[c.driven.front()] > 0 ? 1.0 : -1.0;
  for (int v : c.driven)
    if (e[v] * sense <= 0) {
      std::string signs; // the strain of each driven component at load 1, e.g. "+1 -1"
      for (int w : c.driven)
        signs += fmt::format("{}{:+g}", signs.empty() ? "" : " ", e[w]);
      fail("<case " + std::to_string(c.id) + " " + c.name + ">", "driven components", signs,
           "a case drives all its components in one sense (D424)");
    }
  return sense;
}

bool is_extension(const DeformationCase& c) {
  return std::all_of(c.driven.begin(), c.driven.end(), [](int v) { return v < 3; });
}

bool is_uniaxial_extension(const DeformationCase& c) {
  return c.driven.size() == 1 && c.driven[0] < 3;
}

int single_driven(const DeformationCase& c, const std::string& user) {
  if (c.driven.size() == 1) return c.driven.front();
  // named as the strain columns of the data CSV (docs/formats.md)
  static constexpr const char* kStrain[6] = {"e11", "e22", "e33", "g23", "g13", "g12"};
  std::string comps;
  for (int v : c.driven)
    comps += fmt::format("{}{}", comps.empty() ? "" : ", ", kStrain[v]);
  fail("<case " + std::to_string(c.id) + " " + c.name + ">", "driven components", comps,
       user +
           " knows only cases with one driven component (uniaxial extension or simple "
           "shear); this case drives " +
           std::to_string(c.driven.size()) + " (D360)");
}

std::vector<int> model_cases(Model m) {
  return m == Model::pnc ? std::vector<int>{1, 2, 3, 4, 5, 6} : std::vector<int>{2, 6};
}

} // namespace pnc::damage
