// What the fuzz target fuzz_material (fuzz/fuzz_material.cpp) found in pnc_material_integrate:
// finite strains or constants large enough to overflow the stress or the tangent came back
// as status OK with inf/NaN, and a non-finite state was integrated and passed on. Both are
// now PNC_MATERIAL_BAD_INPUT with a message and untouched outputs.
#include "pnc/fe_material/pnc_material.h"

#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace {

struct Mat {
  pnc_material* m = nullptr;
  explicit Mat(pnc::damage::Model model, const double* rotation9 = nullptr) {
    const auto p = pnc::damage::dissertation_parameters(model);
    const std::vector<double> k(p.k.begin(), p.k.begin() + static_cast<long>(p.size()));
    char err[512] = "";
    m = pnc_material_create_from_constants(pnc::damage::model_name(model), k.data(),
                                           static_cast<int>(k.size()), rotation9, err, sizeof err);
    EXPECT_NE(m, nullptr) << err;
  }
  ~Mat() { pnc_material_destroy(m); }
};

// Runs one increment from the virgin state with canary-filled outputs; returns the status and
// whether every output kept its canary.
int integrate_once(const Mat& mat, const double de[6], bool& untouched, std::string& err,
                   const double* state0 = nullptr) {
  double s0[6], s1[6], stress[6], tangent[36];
  pnc_material_init_state(mat.m, s0);
  if (state0)
    for (int i = 0; i < pnc_material_n_state(mat.m); ++i)
      s0[i] = state0[i];
  for (double* a : {s1, stress})
    for (int i = 0; i < 6; ++i)
      a[i] = -7;
  for (double& t : tangent)
    t = -7;
  const double e0[6] = {0, 0, 0, 0, 0, 0};
  char buf[512] = "";
  const int st = pnc_material_integrate(mat.m, s0, s1, e0, de, stress, tangent, buf, sizeof buf);
  untouched = true;
  for (int i = 0; i < 6; ++i)
    untouched = untouched && s1[i] == -7 && stress[i] == -7;
  for (double t : tangent)
    untouched = untouched && t == -7;
  err = buf;
  return st;
}

} // namespace

TEST(FeMaterialRobust, OverflowingStressIsBadInputNotInfinity) {
  for (auto model : {pnc::damage::Model::pp, pnc::damage::Model::pnc}) {
    Mat mat(model);
    ASSERT_NE(mat.m, nullptr);
    bool untouched = false;
    std::string err;
    // finite strains whose stress (C ~ 1e9 Pa) exceeds the largest double
    const double huge[6] = {1e300, -1e300, 0, 0, 0, 1e305};
    EXPECT_EQ(integrate_once(mat, huge, untouched, err), PNC_MATERIAL_BAD_INPUT);
    EXPECT_TRUE(untouched);
    EXPECT_NE(err.find("non-finite result"), std::string::npos) << err; // the shared check
    EXPECT_NE(err.find("strain0 + dstrain"), std::string::npos) << err;
    // an ordinary damaging increment still works
    const double fine[6] = {0, 0.05, 0, 0, 0, 0.02};
    EXPECT_EQ(integrate_once(mat, fine, untouched, err), PNC_MATERIAL_OK) << err;
    EXPECT_FALSE(untouched);
  }
}

TEST(FeMaterialRobust, NonFiniteStateIsBadInput) {
  Mat mat(pnc::damage::Model::pnc);
  ASSERT_NE(mat.m, nullptr);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double de[6] = {0.01, 0, 0, 0, 0, 0};
  for (const double bad : {nan, inf, -inf}) {
    for (int i = 0; i < 6; ++i) {
      double state[6] = {1, 1, 1, 0, 0, 0};
      state[i] = bad;
      bool untouched = false;
      std::string err;
      EXPECT_EQ(integrate_once(mat, de, untouched, err, state), PNC_MATERIAL_BAD_INPUT) << i;
      EXPECT_TRUE(untouched) << i;
      EXPECT_NE(err.find("state0[" + std::to_string(i) + "]"), std::string::npos) << err;
    }
  }
}
