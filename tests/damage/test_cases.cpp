// The registry of deformation cases (pnc/damage/cases.hpp, D316): each row is checked against
// the mechanics it claims, not against itself.
#include "pnc/core/error.hpp"
#include "pnc/damage/cases.hpp"
#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

using namespace pnc::damage;

namespace {
/// Engineering Voigt form of a symmetric tensor (shear entries doubled).
Voigt engineering(const Eigen::Matrix3d& e) {
  Voigt v;
  v << e(0, 0), e(1, 1), e(2, 2), 2 * e(1, 2), 2 * e(0, 2), 2 * e(0, 1);
  return v;
}
/// Green-Lagrange strain E = (F^T F - I) / 2.
Eigen::Matrix3d green(const Eigen::Matrix3d& F) {
  return 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
}
} // namespace

// ids 1..n without gaps, unique names, and the rule readers print names every id and name.
TEST(DeformationCases, IdsAreContiguousAndTheRuleNamesEveryCase) {
  const auto& all = deformation_cases();
  ASSERT_FALSE(all.empty());
  std::set<std::string> names;
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(all[i].id, static_cast<int>(i) + 1);
    EXPECT_TRUE(names.insert(all[i].name).second) << all[i].name;
    EXPECT_TRUE(is_deformation_case(all[i].id));
    EXPECT_NE(deformation_case_rule().find(all[i].name), std::string::npos);
  }
  EXPECT_FALSE(is_deformation_case(0));
  EXPECT_FALSE(is_deformation_case(static_cast<int>(all.size()) + 1));
  try {
    deformation_case(7, "cases.csv");
    ADD_FAILURE() << "case 7 accepted";
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("cases.csv"), std::string::npos) << m;
    EXPECT_NE(m.find("7"), std::string::npos) << m;
    EXPECT_NE(m.find("simple shear 1-2"), std::string::npos) << m;
  }
}

// The small strain of F(t) is the linearised Green-Lagrange strain: dE/dt at t = 0 (central
// difference; E is quadratic in t, so the difference is exact up to round-off) must equal
// case_strain(id, 1), and that must be the unit vector of the row's `driven` component.
TEST(DeformationCases, StrainIsTheLinearisedGreenStrainOfTheGradient) {
  const double h = 1e-3;
  for (const auto& c : deformation_cases()) {
    const Voigt lin =
        engineering(green(deformation_gradient(c, h)) - green(deformation_gradient(c, -h))) /
        (2 * h);
    const Voigt e = case_strain(c.id, 1.0);
    EXPECT_LT((lin - e).cwiseAbs().maxCoeff(), 1e-12) << "case " << c.id;
    EXPECT_EQ(e, Voigt::Unit(c.driven)) << "case " << c.id;
    EXPECT_TRUE(c.gradient.isUpperTriangular()) << "case " << c.id << ": LAMMPS box form";
  }
}

// `active` lists the stresses an orthotropic law makes non-zero under the case's strain: with
// the published pnc constants (orthotropic, all C_ij of the normal block non-zero), sigma =
// C0 eps is non-zero exactly there.
TEST(DeformationCases, ActiveComponentsAreTheNonZeroStressesOfAnOrthotropicLaw) {
  const Matrix6 C0 = stiffness_c0(dissertation_parameters(Model::pnc));
  for (const auto& c : deformation_cases()) {
    const Voigt s = C0 * case_strain(c.id, 0.01);
    const std::set<int> active(c.active.begin(), c.active.end());
    for (int v = 0; v < 6; ++v)
      EXPECT_EQ(s[v] != 0.0, active.count(v) == 1) << "case " << c.id << " component " << v;
  }
}
