// Tests of ABI 1.1 of the material plugin (pnc_material.h "ABI 1.1", docs/plugin.md,
// decisions D210-D214), part 1: pnc_material_integrate2 with its tangent requests and
// energies, and the extensible point struct. Part 2 (properties, ABI compatibility):
// test_fe_material_props.cpp. Every reference value is computed here from the constants
// (docs/theory.md section 1), not from the plugin.
#include "v2_support.hpp"

#include <gtest/gtest.h>

namespace {

using namespace pnc_v2_test;

// ------------------------------------------------------------------ tangents
TEST(FeMaterialV2, ConsistentTangentMatchesFiniteDifferencesOfTheStress) {
  for (const Case& c : kCases) {
    const NdmParameters p = params(c.model, c.rotated);
    auto m = make(p);
    const std::vector<double> s0 = virgin(m.get());
    const Vec6 zero = Vec6::Zero();
    int damaging = 0;
    for (const Vec6& e : strains()) {
      const Out o = call(m.get(), s0.data(), zero, e, PNC_MATERIAL_TANGENT_CONSISTENT);
      ASSERT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
      damaging += damage_of(c.model, o.state1)[0] + damage_of(c.model, o.state1)[1] > 0;
      Mat6 fd;
      const double h = 1e-7;
      for (int j = 0; j < 6; ++j) {
        Vec6 ep = e, em = e;
        ep[j] += h;
        em[j] -= h;
        const Out a = call(m.get(), s0.data(), zero, ep, PNC_MATERIAL_TANGENT_NONE);
        const Out b = call(m.get(), s0.data(), zero, em, PNC_MATERIAL_TANGENT_NONE);
        fd.col(j) = (as_vec(a.stress) - as_vec(b.stress)) / (2 * h);
      }
      // Central differences: truncation O(h^2 |sigma'''|), round-off O(eps_mach |sigma| / h)
      // ~ 1e-16 * 1e8 Pa / 1e-7 = 0.1 Pa per unit strain against |K| ~ 1e9 Pa: a relative
      // 1e-6 bound is safe and catches any missing damage-growth term (>= 1e-3 relative).
      const Mat6 K = as_matrix(o.K);
      EXPECT_LT((K - fd).norm(), 1e-6 * K.norm()) << name_of(c) << " at " << e.transpose();
    }
    EXPECT_GE(damaging, 2) << name_of(c) << ": the strains must reach past the onset";
  }
}

TEST(FeMaterialV2, ElasticAndSecantRequestsAreC0AndTheSecantOfTheEndState) {
  for (const Case& c : kCases) {
    const NdmParameters p = params(c.model, c.rotated);
    auto m = make(p);
    const Mat6 C0 = global_stiffness(p, {0, 0, 0});
    // A history past the onset, then an unloading and a loading increment from it.
    const std::vector<double> v = virgin(m.get());
    const Vec6 zero = Vec6::Zero();
    const Vec6 e1 = strains()[2];
    const Out first = call(m.get(), v.data(), zero, e1, PNC_MATERIAL_TANGENT_NONE);
    ASSERT_EQ(first.status, PNC_MATERIAL_OK) << first.err;
    for (const double scale : {0.5, 1.1}) {
      const Vec6 de = (scale - 1.0) * e1, e = scale * e1;
      const Out el = call(m.get(), first.state1.data(), e1, de, PNC_MATERIAL_TANGENT_ELASTIC);
      const Out se = call(m.get(), first.state1.data(), e1, de, PNC_MATERIAL_TANGENT_SECANT);
      const Out co = call(m.get(), first.state1.data(), e1, de, PNC_MATERIAL_TANGENT_CONSISTENT);
      ASSERT_EQ(el.status, PNC_MATERIAL_OK) << el.err;
      ASSERT_EQ(se.status, PNC_MATERIAL_OK) << se.err;
      ASSERT_EQ(co.status, PNC_MATERIAL_OK) << co.err;
      // The rounding of T^T C T (two 6x6 products, entries ~1e9 Pa): 1e-13 relative.
      EXPECT_LT((as_matrix(el.K) - C0).norm(), 1e-13 * C0.norm()) << name_of(c);
      const Mat6 S = global_stiffness(p, damage_of(c.model, se.state1));
      EXPECT_LT((as_matrix(se.K) - S).norm(), 1e-13 * S.norm()) << name_of(c) << " " << scale;
      // A secant law: stress = S eps at the end strain, to the rounding of the products.
      EXPECT_LT((as_vec(se.stress) - S * e).norm(), 1e-13 * S.norm() * e.norm()) << name_of(c);
      // The request changes nothing else.
      EXPECT_EQ(se.stress, co.stress);
      EXPECT_EQ(se.state1, co.state1);
      EXPECT_EQ(el.stress, co.stress);
      // Unloading: no mode loads, the consistent tangent is the secant; reloading past the
      // history: it differs by the damage-growth term.
      const double gap = (as_matrix(co.K) - as_matrix(se.K)).norm() / S.norm();
      if (scale < 1)
        EXPECT_EQ(gap, 0.0) << name_of(c);
      else
        EXPECT_GT(gap, 1e-3) << name_of(c);
    }
  }
}

TEST(FeMaterialV2, V1AndV2GiveTheSameStressStateAndTangent) {
  for (const Case& c : kCases) {
    auto m = make(params(c.model, c.rotated));
    const std::vector<double> s0 = virgin(m.get());
    const Vec6 zero = Vec6::Zero();
    for (const Vec6& e : strains()) {
      const Out o = call(m.get(), s0.data(), zero, e, PNC_MATERIAL_TANGENT_CONSISTENT);
      std::array<double, 6> sig{}, s1{};
      std::array<double, 36> K{};
      char err[256];
      ASSERT_EQ(pnc_material_integrate(m.get(), s0.data(), s1.data(), zero.data(), e.data(),
                                       sig.data(), K.data(), err, sizeof err),
                PNC_MATERIAL_OK);
      // One kernel routine behind both entries (D210): the same floating-point sequence.
      EXPECT_EQ(o.stress, sig);
      EXPECT_EQ(o.K, K);
      EXPECT_EQ(o.state1, s1);
    }
  }
}

// ------------------------------------------------------------------ energies
// Is the strain tensor of an engineering-Voigt vector positive semidefinite?
bool psd(const Vec6& e) {
  Eigen::Matrix3d t;
  t << e[0], e[5] / 2, e[4] / 2, e[5] / 2, e[1], e[3] / 2, e[4] / 2, e[3] / 2, e[2];
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(t).eigenvalues().minCoeff() >= 0;
}

TEST(FeMaterialV2, EnergiesOfASecantLaw) {
  // Along loading-unloading-reloading paths of the six deformation cases (docs/theory.md 2.1)
  // and a general direction, step by step (docs/theory.md 1.6):
  //  stored = 1/2 sigma . eps                                      (a secant law)
  //  stored1 - stored0 + dissipated = 1/2 (e1 - e0) . S(D0) (e1 + e0)   (exact, D212)
  //  dissipated = 1/2 e1 . S(D0) e1 - stored1: the stored energy released at fixed strain
  //  dissipated = 0 where no damage grows (elastic and unloading increments).
  // Sign: dissipated = -1/2 sum_m dD_m el . dC1_m el with dD_m >= 0. Every damage constant of
  // the dissertation's cards is <= 0 and dC1_m couples normal strains only with each other
  // (shears on the diagonal), so el . dC1_m el <= 0 when the local normal strains share a
  // sign: for an aligned platelet on the case paths (one normal strain, or a pure shear),
  // and for any platelet under a positive semidefinite strain (el = R e R^T keeps it so).
  // Then dissipated >= 0; elsewhere the law does not promise it and only the identities
  // are checked.
  for (const Case& c : kCases) {
    const NdmParameters p = params(c.model, c.rotated);
    auto m = make(p);
    std::vector<Vec6> dirs;
    for (int i = 0; i < 6; ++i) {
      Vec6 d = Vec6::Zero();
      d[i] = i < 3 ? 0.25 : 0.5;
      dirs.push_back(d);
    }
    dirs.push_back(strains()[2]);
    double total_dissipated = 0;
    for (const Vec6& peak : dirs) {
      const bool nonnegative = !c.rotated || psd(peak);
      std::vector<double> s0 = virgin(m.get());
      Vec6 e0 = Vec6::Zero();
      double stored0 = 0;
      const double targets[3] = {1.0, 0.4, 1.2};
      const int steps[3] = {25, 10, 15};
      for (int seg = 0; seg < 3; ++seg) {
        const Vec6 de = (targets[seg] * peak - e0) / steps[seg];
        for (int s = 0; s < steps[seg]; ++s) {
          const Out o = call(m.get(), s0.data(), e0, de, PNC_MATERIAL_TANGENT_NONE);
          ASSERT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
          const Vec6 e1 = e0 + de;
          const Vec6 sig = as_vec(o.stress);
          const std::array<double, 3> D0 = damage_of(c.model, padded(s0));
          const std::array<double, 3> D1 = damage_of(c.model, o.state1);
          const Mat6 S0 = global_stiffness(p, D0);
          // J/m^3, for relative rounding (the stored energy turns negative where a damaged
          // shear stiffness does, e.g. C44 + A22 D2 < 0 past D2 = 0.56 for the pnc card)
          const double scale = std::abs(0.5 * e1.dot(S0 * e1)) + std::abs(o.stored) + 1.0;
          const std::string where = name_of(c) + " seg " + std::to_string(seg) + " step " +
                                    std::to_string(s) + " dir " + std::to_string(&peak - &dirs[0]);
          EXPECT_NEAR(o.stored, 0.5 * sig.dot(e1), 1e-14 * scale) << where;
          EXPECT_NEAR(o.stored - stored0 + o.dissipated, 0.5 * (e1 - e0).dot(S0 * (e1 + e0)),
                      1e-12 * scale)
              << where;
          EXPECT_NEAR(o.dissipated, 0.5 * e1.dot(S0 * e1) - o.stored, 1e-12 * scale) << where;
          if (D0 == D1) {
            EXPECT_EQ(o.dissipated, 0.0) << where;
          }
          if (seg == 1) {
            EXPECT_EQ(o.dissipated, 0.0) << "unloading dissipates nothing; " << where;
          }
          if (nonnegative) {
            EXPECT_GE(o.dissipated, 0.0) << where;
          }
          total_dissipated += o.dissipated;
          stored0 = o.stored;
          for (std::size_t i = 0; i < s0.size(); ++i)
            s0[i] = o.state1[i];
          e0 = e1;
        }
      }
    }
    EXPECT_GT(total_dissipated, 0.0) << name_of(c) << ": the paths must damage";
  }
}

// ------------------------------------------------------------------ the point struct
TEST(FeMaterialV2, AnOlderSmallerPointIsAcceptedAndOnlyItsBytesAreTouched) {
  auto m = make(params(Model::pnc, false));
  const std::vector<double> s0 = virgin(m.get());
  const Vec6 zero = Vec6::Zero(), e = strains()[1];
  std::array<double, 6> sig{}, s1{};
  std::array<double, 36> K{};
  pnc_material_point pt;
  pnc_material_point_init(&pt);
  pt.tangent_request = PNC_MATERIAL_TANGENT_CONSISTENT;
  pt.state0 = s0.data();
  pt.state1 = s1.data();
  pt.strain0 = zero.data();
  pt.dstrain = e.data();
  pt.stress = sig.data();
  pt.tangent = K.data();
  // A struct that ends after `tangent`: the library must not write the energies.
  pt.size = static_cast<uint32_t>(offsetof(pnc_material_point, stored_energy));
  pt.stored_energy = -7.0;
  pt.dissipated_energy = -8.0;
  ASSERT_EQ(pnc_material_integrate2(m.get(), &pt), PNC_MATERIAL_OK);
  EXPECT_EQ(pt.stored_energy, -7.0);
  EXPECT_EQ(pt.dissipated_energy, -8.0);
  const Out full = call(m.get(), s0.data(), zero, e, PNC_MATERIAL_TANGENT_CONSISTENT);
  EXPECT_EQ(sig, full.stress);
  EXPECT_EQ(K, full.K);
  // One that ends after stored_energy: that one is written, dissipated_energy is not.
  pt.size = static_cast<uint32_t>(offsetof(pnc_material_point, dissipated_energy));
  ASSERT_EQ(pnc_material_integrate2(m.get(), &pt), PNC_MATERIAL_OK);
  EXPECT_EQ(pt.stored_energy, full.stored);
  EXPECT_EQ(pt.dissipated_energy, -8.0);
  // Too small to hold the arrays: refused, nothing written.
  sig.fill(42.0);
  pt.size = static_cast<uint32_t>(offsetof(pnc_material_point, tangent));
  EXPECT_EQ(pnc_material_integrate2(m.get(), &pt), PNC_MATERIAL_BAD_ARGUMENT);
  EXPECT_EQ(sig[0], 42.0);
  // A bigger struct of this version (a host that pads it) is fine.
  std::vector<unsigned char> big(sizeof(pnc_material_point) + 64, 0);
  pt.size = static_cast<uint32_t>(big.size());
  std::memcpy(big.data(), &pt, sizeof pt);
  EXPECT_EQ(pnc_material_integrate2(m.get(), reinterpret_cast<pnc_material_point*>(big.data())),
            PNC_MATERIAL_OK);
}

TEST(FeMaterialV2, ANewerVersionAndBadArgumentsAreRefusedWithAMessage) {
  auto m = make(params(Model::pp, false));
  const std::vector<double> s0 = virgin(m.get());
  const Vec6 zero = Vec6::Zero(), e = strains()[0];
  std::array<double, 6> sig{}, s1{};
  std::array<double, 36> K{};
  char err[640];
  auto fresh = [&]() {
    pnc_material_point pt;
    pnc_material_point_init(&pt);
    pt.tangent_request = PNC_MATERIAL_TANGENT_SECANT;
    pt.state0 = s0.data();
    pt.state1 = s1.data();
    pt.strain0 = zero.data();
    pt.dstrain = e.data();
    pt.stress = sig.data();
    pt.tangent = K.data();
    pt.err = err;
    pt.err_len = sizeof err;
    err[0] = '\0';
    sig.fill(42.0);
    return pt;
  };
  auto expect = [&](pnc_material_point pt, int status, const std::vector<std::string>& words) {
    EXPECT_EQ(pnc_material_integrate2(m.get(), &pt), status) << err;
    for (const auto& w : words)
      EXPECT_NE(std::string(err).find(w), std::string::npos) << "'" << w << "' in: " << err;
    EXPECT_EQ(sig[0], 42.0) << "nothing but the message is written on failure";
  };
  pnc_material_point pt = fresh();
  pt.version = PNC_MATERIAL_POINT_VERSION + 1;
  pt.size = static_cast<uint32_t>(sizeof pt + 16); // a newer header's struct is bigger
  std::vector<unsigned char> newer(sizeof pt + 16, 0);
  std::memcpy(newer.data(), &pt, sizeof pt);
  EXPECT_EQ(pnc_material_integrate2(m.get(), reinterpret_cast<pnc_material_point*>(newer.data())),
            PNC_MATERIAL_BAD_ARGUMENT);
  EXPECT_NE(std::string(err).find("field 'point.version': value '" +
                                  std::to_string(PNC_MATERIAL_POINT_VERSION + 1) + "'"),
            std::string::npos)
      << err;
  EXPECT_NE(std::string(err).find("versions 1.." + std::to_string(PNC_MATERIAL_POINT_VERSION)),
            std::string::npos)
      << err;
  pt = fresh();
  pt.version = 0;
  expect(pt, PNC_MATERIAL_BAD_ARGUMENT, {"point.version", "'0'"});
  pt = fresh();
  pt.tangent_request = 7;
  expect(pt, PNC_MATERIAL_BAD_ARGUMENT, {"point.tangent_request", "'7'"});
  pt = fresh();
  pt.tangent = nullptr;
  expect(pt, PNC_MATERIAL_BAD_ARGUMENT, {"tangent", "NULL"});
  pt = fresh();
  pt.tangent = nullptr;
  pt.tangent_request = PNC_MATERIAL_TANGENT_NONE; // then NULL is fine
  EXPECT_EQ(pnc_material_integrate2(m.get(), &pt), PNC_MATERIAL_OK) << err;
  for (const double dt : {std::nan(""), -1.0, std::numeric_limits<double>::infinity()}) {
    pt = fresh();
    pt.dt = dt;
    expect(pt, PNC_MATERIAL_BAD_INPUT, {"point.dt", ">= 0"});
  }
  const Vec6 bad = (Vec6() << 0, std::nan(""), 0, 0, 0, 0).finished();
  pt = fresh();
  pt.dstrain = bad.data();
  expect(pt, PNC_MATERIAL_BAD_INPUT, {"point.dstrain[1]", "nan", "finite"});
  const std::array<double, 2> bad_state{1.0, std::numeric_limits<double>::infinity()};
  pt = fresh();
  pt.state0 = bad_state.data();
  expect(pt, PNC_MATERIAL_BAD_INPUT, {"point.state0[1]", "inf"});
  // A finite strain whose energy overflows: a non-finite output is never OK.
  const Vec6 huge = Vec6::Constant(1e160);
  pt = fresh();
  pt.dstrain = huge.data();
  expect(pt, PNC_MATERIAL_BAD_INPUT, {"result"});
  EXPECT_EQ(pnc_material_integrate2(nullptr, nullptr), PNC_MATERIAL_BAD_ARGUMENT);
  pt = fresh();
  EXPECT_EQ(pnc_material_integrate2(nullptr, &pt), PNC_MATERIAL_BAD_ARGUMENT);
  EXPECT_NE(std::string(err).find("field 'm'"), std::string::npos) << err;
}

} // namespace
