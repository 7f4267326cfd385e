// The registry of deformation cases (pnc/damage/cases.hpp, D316): each row is checked against
// the mechanics it claims, not against itself.
#include "pnc/core/error.hpp"
#include "pnc/damage/cases.hpp"
#include "pnc/damage/reference.hpp"

#include "fit_model.hpp" // damage/src: the start regression's labels

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

using namespace pnc::damage;

namespace {
/// Engineering Voigt form of a symmetric tensor (shear entries doubled).
Voigt engineering(const Eigen::Matrix3d& e) {
  Voigt v;
  v << e(0, 0), e(1, 1), e(2, 2), 2 * e(1, 2), 2 * e(0, 2), 2 * e(0, 1);
  return v;
}
/// The first id after the registered rows.
int unregistered_id() {
  return static_cast<int>(deformation_cases().size()) + 1;
}
/// A mixed case as one row (D360), test-only: equibiaxial extension in the 1-2 plane,
/// G = e_1 e_1 + e_2 e_2, x3 held. Not registered: no MD data or NDM damage mode exists for it.
DeformationCase equibiaxial() {
  Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
  g(0, 0) = g(1, 1) = 1.0;
  return {unregistered_id(), "equibiaxial extension x1-x2 (x3 held)", {0, 1}, {0, 1, 2}, 0, g};
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
  const int bad = unregistered_id();
  try {
    deformation_case(bad, "cases.csv");
    ADD_FAILURE() << "case " << bad << " accepted";
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("cases.csv"), std::string::npos) << m;
    EXPECT_NE(m.find(std::to_string(bad)), std::string::npos) << m;
    EXPECT_NE(m.find("simple shear 1-2"), std::string::npos) << m;
  }
}

// The small strain of F(t) is the linearised Green-Lagrange strain: dE/dt at t = 0 (central
// difference; E is quadratic in t, so the difference is exact up to round-off) must equal
// case_strain(c, 1), and its non-zero entries must be exactly the row's `driven` set, each
// the row's sense: +1, or -1 for the negative shears (D360, D424). The registered rows drive
// one component each; the test-only equibiaxial row two.
TEST(DeformationCases, StrainIsTheLinearisedGreenStrainOfTheGradient) {
  const double h = 1e-3;
  std::vector<DeformationCase> rows = deformation_cases();
  rows.push_back(equibiaxial());
  for (const auto& c : rows) {
    const Voigt lin =
        engineering(green(deformation_gradient(c, h)) - green(deformation_gradient(c, -h))) /
        (2 * h);
    const Voigt e = case_strain(c, 1.0);
    EXPECT_LT((lin - e).cwiseAbs().maxCoeff(), 1e-12) << "case " << c.id;
    // the sense from the gradient alone: the sign of its one non-zero entry per driven component
    const double sense = c.gradient.sum() > 0 ? 1.0 : -1.0;
    EXPECT_EQ(driven_sense(c), sense) << "case " << c.id;
    Voigt expect = Voigt::Zero();
    for (int v : c.driven)
      expect[v] = sense;
    EXPECT_EQ(e, expect) << "case " << c.id;
    EXPECT_TRUE(c.gradient.isUpperTriangular()) << "case " << c.id << ": LAMMPS box form";
    if (c.id < unregistered_id()) {
      EXPECT_EQ(case_strain(c.id, 0.37), case_strain(c, 0.37)) << "the id overload";
      ASSERT_EQ(c.driven.size(), 1u) << "case " << c.id;
      EXPECT_EQ(single_driven(c, "test"), c.driven[0]);
    }
  }
}

// Code that relates one stress to one strain (the NDM fit, strengths, reports) refuses a row
// that drives several components, naming the case, its components and who refused (D360).
TEST(DeformationCases, SingleDrivenRefusesAMixedCaseByName) {
  try {
    single_driven(equibiaxial(), "the NDM fit");
    ADD_FAILURE() << "an equibiaxial case passed as one driven component";
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    const std::string id = "case " + std::to_string(unregistered_id());
    for (const char* want : {id.c_str(), "equibiaxial", "e11, e22", "the NDM fit", "one driven"})
      EXPECT_NE(m.find(want), std::string::npos) << want << " not in: " << m;
  }
}

// A row whose driven components grow in opposite senses has no one sense to read "along" it:
// driven_sense refuses it, naming the case and each driven strain at load 1 (D424).
TEST(DeformationCases, DrivenSenseRefusesARowDrivenBothWaysNamingItsStrains) {
  DeformationCase c = equibiaxial();
  c.name = "extension x1, compression x2";
  c.gradient(1, 1) = -1.0;
  try {
    driven_sense(c);
    ADD_FAILURE() << "a row driven both ways was given one sense";
  } catch (const pnc::InputError& e) {
    const std::string m = e.what();
    for (const char* want : {"compression x2", "driven components", "+1 -1", "one sense"})
      EXPECT_NE(m.find(want), std::string::npos) << want << " not in: " << m;
  }
}

// Which rows are extensions is read from the gradient, not from ids: an extension is a
// gradient with only diagonal entries (a uniaxial one has one), a shear has an off-diagonal one.
TEST(DeformationCases, ExtensionPredicatesFollowTheGradient) {
  for (const DeformationCase& dc : deformation_cases()) {
    const Eigen::Matrix3d g = dc.gradient;
    const bool diagonal = g.isDiagonal(0.0);
    const int nonzero_diagonal = static_cast<int>((g.diagonal().array() != 0.0).count());
    EXPECT_EQ(is_extension(dc), diagonal) << "case " << dc.id;
    EXPECT_EQ(is_uniaxial_extension(dc), diagonal && nonzero_diagonal == 1) << "case " << dc.id;
  }
  EXPECT_TRUE(is_extension(equibiaxial()));
  EXPECT_FALSE(is_uniaxial_extension(equibiaxial()));
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

TEST(DeformationCases, RegressionLabelsFollowTheGradientOfEachRow) {
  // The stiffness entry a case's stress component informs, worked out from the row's gradient
  // alone (D362): an extension along a (G = e_a e_a) gives C_ab in component b; a simple shear
  // (G with one off-diagonal entry (i, j)) gives its own Voigt diagonal entry C_vv. The pp
  // model's isotropic reading names C11 (b = a), C12 (b != a) and C44.
  static const char* const voigt_of_pair[3][3] = {
      {"", "66", "55"}, {"66", "", "44"}, {"55", "44", ""}};
  for (const DeformationCase& c : deformation_cases()) {
    int a = -1, i = -1, j = -1; // the extension axis, or the shear entry (i, j)
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q)
        if (c.gradient(r, q) != 0 && r == q)
          a = r;
        else if (c.gradient(r, q) != 0)
          i = r, j = q;
    for (int comp : c.active) {
      std::string pnc_label, pp_label;
      if (a >= 0) {
        const int lo = std::min(a, comp) + 1, hi = std::max(a, comp) + 1;
        pnc_label = "C" + std::to_string(lo) + std::to_string(hi);
        pp_label = comp == a ? "C11" : "C12";
      } else {
        pnc_label = std::string("C") + voigt_of_pair[i][j];
        pp_label = "C44";
      }
      EXPECT_EQ(std::string(fitmodel::regression_labels(Model::pnc, c.id, comp).lin), pnc_label)
          << c.name << " component " << comp;
      EXPECT_EQ(std::string(fitmodel::regression_labels(Model::pp, c.id, comp).lin), pp_label)
          << c.name << " component " << comp;
    }
  }
}

// Rows 7-9 are rows 4-6 sheared the other way (D424): the opposite gradient, the same driven and
// active components and damage mode, a name saying so. Along each, the law is odd in the load
// (docs/theory.md section 2.1): the published pnc law (damaging past its onset) gives at every
// load the negated stress of the positive row and the same damage, integrated along the path.
TEST(DeformationCases, NegativeShearsAreThePositiveOnesReversed) {
  const NdmParameters p = dissertation_parameters(Model::pnc);
  for (int id = 7; id <= 9; ++id) {
    const DeformationCase& n = deformation_case(id);
    const DeformationCase& q = deformation_case(id - 3);
    EXPECT_EQ(n.gradient, -q.gradient) << n.name;
    EXPECT_EQ(n.driven, q.driven) << n.name;
    EXPECT_EQ(n.active, q.active) << n.name;
    EXPECT_EQ(n.damage_mode, q.damage_mode) << n.name;
    EXPECT_EQ(std::string(n.name), std::string("negative ") + q.name);
    const int points = 60;
    // past the onset: the principal stretch of a 0.3 shear exceeds alpha lambda_c
    ASSERT_GT(0.15 + std::sqrt(1 + 0.15 * 0.15), p.alpha() * critical_stretch());
    Eigen::Matrix<double, Eigen::Dynamic, 6> pn(points + 1, 6), pq(points + 1, 6);
    for (int i = 0; i <= points; ++i) { // to a shear of 0.3, past the onset (alpha lambda_c - 1)
      pn.row(i) = case_strain(n, 0.3 * i / points).transpose();
      pq.row(i) = case_strain(q, 0.3 * i / points).transpose();
    }
    const auto sn = stress_path(p, pn), sq = stress_path(p, pq);
    // FtF sees gamma^2 only; what may differ is the round-off of the stretch's eigen-solve
    const double scale = sq.cwiseAbs().maxCoeff();
    for (int i = 0; i <= points; ++i)
      for (int c = 0; c < 6; ++c)
        EXPECT_NEAR(sn(i, c), -sq(i, c), 1e-12 * scale)
            << n.name << " point " << i << " component " << c;
  }
}
