// Tests of ABI 1.1 of the material plugin (pnc_material.h "ABI 1.1", docs/plugin.md,
// decisions D210-D214): pnc_material_integrate2 with its tangent requests and energies, the
// extensible point struct, the property and state-index queries, and a host compiled against
// the frozen ABI 1.0 header (tests/fe_material/abi_v1/) running against this library.
// Every reference value is computed here from the constants (docs/theory.md section 1), not
// from the plugin.
#include "pnc/fe_material/material.hpp"
#include "pnc/fe_material/pnc_material.h"

#include "pnc/damage/ndm.hpp"
#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include <dlfcn.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace {

using pnc::damage::Model;
using pnc::damage::NdmParameters;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// ------------------------------------------------------------------ independent references
Eigen::Matrix3d rotation_zx(double deg_z, double deg_x) {
  const double pi = std::acos(-1.0);
  const double a = deg_z * pi / 180, b = deg_x * pi / 180;
  Eigen::Matrix3d Rz, Rx;
  Rz << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  Rx << 1, 0, 0, 0, std::cos(b), -std::sin(b), 0, std::sin(b), std::cos(b);
  return Rz * Rx;
}

double k(const NdmParameters& p, const char* name) {
  return p[name];
}

// [C0] + [C1(D)] in the platelet frame, written from docs/theory.md (1.1)-(1.2): the normal
// block C_ij + damage terms, the shear diagonal; pp in its isotropic reading.
Mat6 local_stiffness(const NdmParameters& p, const std::array<double, 3>& D) {
  Mat6 C = Mat6::Zero();
  if (p.model == Model::pnc) {
    C(0, 0) = k(p, "C11") + 2 * k(p, "A1") * D[0];
    C(1, 1) = k(p, "C22") + 2 * k(p, "A5") * D[1];
    C(2, 2) = k(p, "C33") + 2 * k(p, "A9") * D[2];
    C(0, 1) = C(1, 0) = k(p, "C12") + k(p, "A10") * D[0] + k(p, "A11") * D[1];
    C(0, 2) = C(2, 0) = k(p, "C13") + k(p, "A13") * D[0] + k(p, "A15") * D[2];
    C(1, 2) = C(2, 1) = k(p, "C23") + k(p, "A17") * D[1] + k(p, "A18") * D[2];
    C(3, 3) = k(p, "C44") + k(p, "A22") * D[1];
    C(4, 4) = k(p, "C55") + k(p, "A26") * D[2];
    C(5, 5) = k(p, "C66") + k(p, "A24") * D[1];
  } else {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        C(i, j) = i == j ? k(p, "C11") + 2 * k(p, "B1") * D[0] : k(p, "C12") + k(p, "B2") * D[0];
      C(3 + i, 3 + i) = k(p, "C44") + k(p, "B4") * D[0];
    }
  }
  return C;
}

// Engineering-Voigt strain rotation e_local = T e_global, built column by column from
// R e R^T of each unit strain (tensor algebra, not the kernel's closed form).
Mat6 strain_rotation(const Eigen::Matrix3d& R) {
  Mat6 T;
  for (int J = 0; J < 6; ++J) {
    Vec6 u = Vec6::Zero();
    u[J] = 1.0;
    Eigen::Matrix3d e;
    e << u[0], u[5] / 2, u[4] / 2, u[5] / 2, u[1], u[3] / 2, u[4] / 2, u[3] / 2, u[2];
    const Eigen::Matrix3d el = R * e * R.transpose();
    T.col(J) << el(0, 0), el(1, 1), el(2, 2), 2 * el(1, 2), 2 * el(0, 2), 2 * el(0, 1);
  }
  return T;
}

Mat6 global_stiffness(const NdmParameters& p, const std::array<double, 3>& D) {
  const Mat6 T = strain_rotation(p.R);
  return T.transpose() * local_stiffness(p, D) * T;
}

double lambda_c() {
  return std::pow(26.0 / 7.0, 1.0 / 6.0);
}

NdmParameters params(Model m, bool rotated) {
  NdmParameters p = pnc::damage::dissertation_parameters(m);
  if (rotated) p.R = rotation_zx(30.0, 20.0);
  return p;
}

std::unique_ptr<pnc_material, void (*)(pnc_material*)> make(const NdmParameters& p) {
  char err[512] = {0};
  double R[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      R[3 * r + c] = p.R(r, c);
  pnc_material* m = pnc_material_create_from_constants(
      pnc::damage::model_name(p.model), p.k.data(), static_cast<int>(p.size()), R, err, sizeof err);
  EXPECT_NE(m, nullptr) << err;
  return {m, &pnc_material_destroy};
}

// One integrate2 call; the point is returned for its energies.
struct Out {
  int status;
  std::array<double, 6> stress{}, state1{};
  std::array<double, 36> K{};
  double stored = 0, dissipated = 0;
  std::string err;
};
Out call(const pnc_material* m, const double* s0, const Vec6& e0, const Vec6& de, int request) {
  Out o;
  char err[640] = {0};
  pnc_material_point pt;
  pnc_material_point_init(&pt);
  pt.tangent_request = request;
  pt.state0 = s0;
  pt.state1 = o.state1.data();
  pt.strain0 = e0.data();
  pt.dstrain = de.data();
  pt.stress = o.stress.data();
  pt.tangent = request == PNC_MATERIAL_TANGENT_NONE ? nullptr : o.K.data();
  pt.err = err;
  pt.err_len = sizeof err;
  o.status = pnc_material_integrate2(m, &pt);
  o.stored = pt.stored_energy;
  o.dissipated = pt.dissipated_energy;
  o.err = err;
  return o;
}

Mat6 as_matrix(const std::array<double, 36>& K) {
  Mat6 M;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      M(i, j) = K[static_cast<std::size_t>(6 * i + j)];
  return M;
}
Vec6 as_vec(const std::array<double, 6>& v) {
  return Eigen::Map<const Vec6>(v.data());
}
std::array<double, 3> damage_of(Model m, const std::array<double, 6>& state) {
  if (m == Model::pnc) return {state[3], state[4], state[5]};
  return {state[1], 0.0, 0.0};
}

std::array<double, 6> padded(const std::vector<double>& s) {
  std::array<double, 6> out{};
  for (std::size_t i = 0; i < s.size() && i < 6; ++i)
    out[i] = s[i];
  return out;
}

std::vector<double> virgin(const pnc_material* m) {
  std::vector<double> s(static_cast<std::size_t>(pnc_material_n_state(m)));
  pnc_material_init_state(m, s.data());
  return s;
}

struct Case {
  Model model;
  bool rotated;
};
std::string name_of(const Case& c) {
  return std::string(pnc::damage::model_name(c.model)) + (c.rotated ? "_rotated" : "_aligned");
}
const Case kCases[] = {
    {Model::pnc, false}, {Model::pnc, true}, {Model::pp, false}, {Model::pp, true}};

// Strains: below onset, past onset in several directions (the pnc onset is a mode stretch of
// alpha lambda_c = 1.07, pp 1.17).
std::vector<Vec6> strains() {
  std::vector<Vec6> out;
  Vec6 e;
  e << 0.01, -0.005, 0.002, 0.004, -0.003, 0.006; // elastic
  out.push_back(e);
  e << 0.02, 0.13, -0.01, 0.015, 0.01, -0.02; // mode 2 / max stretch past onset
  out.push_back(e);
  e << 0.21, 0.03, 0.195, 0.04, -0.03, 0.05; // several modes loading
  out.push_back(e);
  e << 0.05, 0.3, -0.02, 0.02, 0.01, 0.04; // past the pp onset (max stretch 1.17) too
  out.push_back(e);
  return out;
}

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

// ------------------------------------------------------------------ properties
double prop(const pnc_material* m, const std::string& name) {
  int st = -1;
  const double v = pnc_material_property(m, name.c_str(), &st);
  EXPECT_EQ(st, PNC_MATERIAL_OK) << name;
  return v;
}

// Brute-force lower bound of the largest P-wave modulus: the largest eigenvalue of the
// acoustic tensor over a fine grid of directions.
double sampled_p_wave_max(const Mat6& C, int n) {
  static const int v[3][3] = {{0, 5, 4}, {5, 1, 3}, {4, 3, 2}};
  double best = 0;
  for (int a = 0; a <= n; ++a)
    for (int b = 0; b < 2 * n; ++b) {
      const double th = std::acos(-1.0) * a / n, ph = std::acos(-1.0) * b / n;
      const Eigen::Vector3d d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                              std::cos(th));
      Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
      for (int i = 0; i < 3; ++i)
        for (int kk = 0; kk < 3; ++kk)
          for (int j = 0; j < 3; ++j)
            for (int l = 0; l < 3; ++l)
              G(i, kk) += C(v[i][j], v[kk][l]) * d[j] * d[l];
      best = std::max(best, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(G).eigenvalues()[2]);
    }
  return best;
}

TEST(FeMaterialV2, PropertiesAgreeWithTheConstants) {
  for (const Case& c : kCases) {
    const NdmParameters p = params(c.model, c.rotated);
    auto m = make(p);
    const Mat6 C0 = global_stiffness(p, {0, 0, 0});
    const int modes = c.model == Model::pnc ? 3 : 1;
    const double tol = 1e-13 * C0.norm(); // rounding of T^T C T
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const std::string ij = std::to_string(i + 1) + std::to_string(j + 1);
        EXPECT_NEAR(prop(m.get(), "elastic_stiffness_" + ij), C0(i, j), tol) << ij;
        for (int mode = 0; mode < modes; ++mode) {
          std::array<double, 3> unit{0, 0, 0};
          unit[static_cast<std::size_t>(mode)] = 1.0;
          const Mat6 M = global_stiffness(p, unit) - C0;
          EXPECT_NEAR(prop(m.get(), "damage_stiffness_" + std::to_string(mode + 1) + "_" + ij),
                      M(i, j), tol)
              << mode << " " << ij;
        }
      }
    double C36[36], M36[36];
    ASSERT_EQ(pnc_material_elastic_stiffness(m.get(), C36), PNC_MATERIAL_OK);
    EXPECT_EQ(C36[1], prop(m.get(), "elastic_stiffness_12"));
    ASSERT_EQ(pnc_material_damage_stiffness(m.get(), modes - 1, M36), PNC_MATERIAL_OK);
    EXPECT_EQ(M36[7], prop(m.get(), "damage_stiffness_" + std::to_string(modes) + "_22"));
    EXPECT_EQ(pnc_material_damage_stiffness(m.get(), modes, M36), PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(pnc_material_damage_stiffness(m.get(), -1, M36), PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(prop(m.get(), "n_damage_modes"), modes);
    EXPECT_NEAR(prop(m.get(), "critical_stretch"), lambda_c(), 1e-15);
    EXPECT_NEAR(prop(m.get(), "damage_onset_stretch"), p.alpha() * lambda_c(), 1e-15);
    // Moduli by compliance inversion of C0 (docs/theory.md 1.5).
    const Mat6 S = C0.inverse();
    const double E = 1e-12 * C0.norm();
    EXPECT_NEAR(prop(m.get(), "youngs_modulus_1"), 1 / S(0, 0), E);
    EXPECT_NEAR(prop(m.get(), "youngs_modulus_3"), 1 / S(2, 2), E);
    EXPECT_NEAR(prop(m.get(), "shear_modulus_12"), 1 / S(5, 5), E);
    EXPECT_NEAR(prop(m.get(), "poisson_ratio_12"), -S(0, 1) / S(0, 0), 1e-12);
    EXPECT_NEAR(prop(m.get(), "poisson_ratio_31"), -S(2, 0) / S(2, 2), 1e-12);
    // The largest P-wave modulus: at least every sampled direction's, and within the
    // sampling error (1-degree grid: relative 1e-3 of the curvature) above the best of them;
    // independent of the platelet rotation.
    const double M = prop(m.get(), "p_wave_modulus_max");
    const double sampled = sampled_p_wave_max(C0, 180);
    EXPECT_GE(M, sampled * (1 - 1e-14)) << name_of(c);
    EXPECT_LE(M, sampled * (1 + 1e-3)) << name_of(c);
    auto aligned = make(params(c.model, false));
    EXPECT_NEAR(M, prop(aligned.get(), "p_wave_modulus_max"), 1e-12 * M) << name_of(c);
    if (c.model == Model::pp) {
      // Cubic symmetry (the pp reading: C22 = C33 = C11, C55 = C66 = C44) with anisotropy
      // 2 C44 / (C11 - C12) > 1: the fastest longitudinal wave runs along <111>,
      // M = (C11 + 2 C12 + 4 C44) / 3, faster than along an axis (C11).
      const double c11 = p["C11"], c12 = p["C12"], c44 = p["C44"];
      ASSERT_GT(2 * c44 / (c11 - c12), 1.0);
      EXPECT_NEAR(M, (c11 + 2 * c12 + 4 * c44) / 3, 1e-12 * M);
      EXPECT_GT(M, c11 * 1.1);
    } else {
      // The nanocomposite card: the axis x1 (C11) is the fastest direction.
      EXPECT_NEAR(M, p["C11"], 1e-12 * M);
    }
  }
  // An isotropic material (C44 = (C11 - C12) / 2): M = C11 in every direction.
  NdmParameters iso = params(Model::pp, false);
  iso["C44"] = 0.5 * (iso["C11"] - iso["C12"]);
  auto mi = make(iso);
  EXPECT_NEAR(prop(mi.get(), "p_wave_modulus_max"), iso["C11"], 1e-12 * iso["C11"]);
}

TEST(FeMaterialV2, PropertyEnumerationUnknownNamesAndStateIndices) {
  auto m = make(params(Model::pnc, true));
  const int n = pnc_material_n_properties(m.get());
  EXPECT_EQ(n, 36 + 3 * 36 + 4 + 3 + 3 + 6);
  for (int i = 0; i < n; ++i) {
    const char* name = pnc_material_property_name(m.get(), i);
    const char* units = pnc_material_property_units(m.get(), i);
    ASSERT_NE(name, nullptr) << i;
    ASSERT_NE(units, nullptr) << i;
    EXPECT_TRUE(std::string(units) == "Pa" || std::string(units) == "1") << name;
    int st = -1;
    EXPECT_TRUE(std::isfinite(pnc_material_property(m.get(), name, &st))) << name;
    EXPECT_EQ(st, PNC_MATERIAL_OK);
  }
  EXPECT_EQ(pnc_material_property_name(m.get(), n), nullptr);
  EXPECT_EQ(pnc_material_property_name(m.get(), -1), nullptr);
  int st = 0;
  EXPECT_TRUE(std::isnan(pnc_material_property(m.get(), "wave_speed", &st)));
  EXPECT_EQ(st, PNC_MATERIAL_UNKNOWN_NAME);
  EXPECT_TRUE(std::isnan(pnc_material_property(m.get(), nullptr, &st)));
  EXPECT_EQ(st, PNC_MATERIAL_UNKNOWN_NAME);
  EXPECT_TRUE(std::isnan(pnc_material_property(nullptr, "n_damage_modes", &st)));
  EXPECT_EQ(st, PNC_MATERIAL_BAD_ARGUMENT);
  EXPECT_TRUE(std::isnan(pnc_material_property(m.get(), "damage_stiffness_4_11", nullptr)));

  EXPECT_EQ(pnc_material_state_index(m.get(), "kappa1"), 0);
  EXPECT_EQ(pnc_material_state_index(m.get(), "kappa3"), 2);
  EXPECT_EQ(pnc_material_state_index(m.get(), "D2"), 4);
  EXPECT_EQ(pnc_material_state_index(m.get(), "kappa"), -1);
  EXPECT_EQ(pnc_material_state_index(m.get(), nullptr), -1);
  auto pp = make(params(Model::pp, false));
  EXPECT_EQ(pnc_material_state_index(pp.get(), "kappa"), 0);
  EXPECT_EQ(pnc_material_state_index(pp.get(), "D"), 1);
  EXPECT_EQ(pnc_material_state_index(pp.get(), "kappa1"), 0); // one loop over modes for both
  EXPECT_EQ(pnc_material_state_index(pp.get(), "D1"), 1);
  EXPECT_EQ(pnc_material_state_index(pp.get(), "kappa2"), -1);
  EXPECT_EQ(pnc_material_n_properties(pp.get()), 36 + 36 + 4 + 3 + 3 + 6);

  for (Model md : {Model::pnc, Model::pp}) {
    const auto& names = pnc::damage::constant_names(md);
    const char* mn = pnc::damage::model_name(md);
    ASSERT_EQ(pnc_material_model_n_constants(mn), static_cast<int>(names.size()));
    for (std::size_t i = 0; i < names.size(); ++i)
      EXPECT_EQ(pnc_material_model_constant_name(mn, static_cast<int>(i)), names[i]);
    EXPECT_EQ(pnc_material_model_constant_name(mn, static_cast<int>(names.size())), nullptr);
  }
  EXPECT_EQ(pnc_material_model_n_constants("steel"), 0);
  EXPECT_EQ(pnc_material_model_n_constants(nullptr), 0);
  EXPECT_EQ(pnc_material_model_constant_name("steel", 0), nullptr);
}

TEST(FeMaterialV2, PropertiesAreComputedOnceWhenThreadsAskAtTheSameTime) {
  // The properties are computed at the first query (std::call_once): 8 threads asking a fresh
  // material at once must all see the values one thread sees later.
  auto m = make(params(Model::pnc, true));
  std::vector<double> got(8, 0.0);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i)
    threads.emplace_back(
        [&, i] { got[i] = pnc_material_property(m.get(), "p_wave_modulus_max", nullptr); });
  for (auto& t : threads)
    t.join();
  const double ref = pnc_material_property(m.get(), "p_wave_modulus_max", nullptr);
  EXPECT_TRUE(std::isfinite(ref));
  for (const double v : got)
    EXPECT_EQ(v, ref);
}

TEST(FeMaterialV2, TheCxxWrapperThroughThePluginReachesAbi11) {
  const pnc::fe_material::Plugin plugin(PNC_MATERIAL_PLUGIN_PATH);
  EXPECT_EQ(plugin.abi_version_minor(), PNC_MATERIAL_ABI_VERSION_MINOR);
  EXPECT_EQ(plugin.model_constant_names("pp"),
            (std::vector<std::string>{"C11", "C12", "C44", "B1", "B2", "B4", "alpha"}));
  EXPECT_THROW(plugin.model_constant_names("steel"), pnc::fe_material::Error);
  const NdmParameters p = params(Model::pnc, true);
  const auto mat = plugin.from_constants("pnc", std::vector<double>(p.k.begin(), p.k.begin() + 22));
  EXPECT_EQ(mat.n_damage_modes(), 3);
  EXPECT_EQ(mat.state_index("D3"), 5);
  EXPECT_THROW((void)mat.state_index("D4"), pnc::fe_material::Error);
  EXPECT_THROW((void)mat.property("nope"), pnc::fe_material::Error);
  EXPECT_EQ(mat.property_names().size(), mat.property_units().size());
  const auto C = mat.elastic_stiffness();
  EXPECT_EQ(C[0], mat.property("elastic_stiffness_11"));
  EXPECT_THROW((void)mat.damage_stiffness(3), pnc::fe_material::Error);
  std::vector<double> s0 = mat.initial_state(), s1(6);
  const std::array<double, 6> z{}, e{0.01, 0.2, 0, 0, 0, 0};
  std::array<double, 6> sig{};
  std::array<double, 36> K{};
  const auto en = mat.integrate2(s0.data(), s1.data(), z.data(), e.data(), sig.data(), K.data(),
                                 PNC_MATERIAL_TANGENT_SECANT, 1e-3);
  double work = 0;
  for (int i = 0; i < 6; ++i)
    work += 0.5 * sig[static_cast<std::size_t>(i)] * e[static_cast<std::size_t>(i)];
  EXPECT_NEAR(en.stored, work, 1e-14 * std::abs(work));
  EXPECT_GT(en.dissipated, 0.0);
  try {
    mat.integrate2(s0.data(), s1.data(), z.data(), e.data(), sig.data(), nullptr,
                   PNC_MATERIAL_TANGENT_CONSISTENT);
    ADD_FAILURE() << "no exception";
  } catch (const pnc::fe_material::Error& err) {
    EXPECT_EQ(err.status(), PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_NE(std::string(err.what()).find("tangent"), std::string::npos) << err.what();
  }
}

// ------------------------------------------------------------------ ABI compatibility
TEST(FeMaterialAbi, NewSymbolsCarryTheMinorVersionAndV1SymbolsKeepTheirs) {
  void* h = dlopen(PNC_MATERIAL_PLUGIN_PATH, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(h, nullptr) << dlerror();
  const std::string v1 = "PNC_MATERIAL_" + std::to_string(PNC_MATERIAL_ABI_VERSION);
  const std::string v11 = v1 + ".1";
  for (const char* s : {"pnc_material_integrate", "pnc_material_create", "pnc_material_umat_props",
                        "umat_", "pnc_umat_"})
    EXPECT_NE(dlvsym(h, s, v1.c_str()), nullptr) << s << "@" << v1;
  for (const char* s :
       {"pnc_material_integrate2", "pnc_material_property", "pnc_material_state_index",
        "pnc_material_abi_version_minor", "pnc_material_model_constant_name"}) {
    EXPECT_NE(dlvsym(h, s, v11.c_str()), nullptr) << s << "@" << v11;
    EXPECT_EQ(dlvsym(h, s, v1.c_str()), nullptr) << s << " must not be in " << v1;
  }
  dlclose(h);
}

// Runs the C program built against the frozen ABI 1.0 header (abi_v1/pnc_material_v1.h) and
// linked to this library; it prints the stress and state after a loading-unloading-reloading
// path. The same path through integrate2 must give the same numbers: one kernel routine
// behind both entries (D210), so the floating-point sequence is the same and they are equal.
TEST(FeMaterialAbi, AHostBuiltAgainstTheV1HeaderRunsWithTheSameResults) {
  char out_path[] = "/tmp/pnc_abi_v1_XXXXXX";
  const int fd = mkstemp(out_path); // created exclusively
  ASSERT_GE(fd, 0);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, fd, STDOUT_FILENO);
  const std::string exe = PNC_ABI_V1_HOST;
  for (const char* model : {"pnc", "pp"}) {
    const Model md = std::string(model) == "pnc" ? Model::pnc : Model::pp;
    const NdmParameters p = params(md, false);
    std::vector<std::string> args{exe, model};
    for (std::size_t i = 0; i < p.size(); ++i) {
      char b[40];
      std::snprintf(b, sizeof b, "%.17g", p.k[i]); // round-trips exactly
      args.emplace_back(b);
    }
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    ASSERT_EQ(ftruncate(fd, 0), 0);
    ASSERT_EQ(lseek(fd, 0, SEEK_SET), 0);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ), 0) << exe;
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << exe << " " << model;
    std::ifstream in(out_path);
    std::string word;
    int abi = 0, n = 0;
    in >> word >> abi >> word >> n;
    ASSERT_EQ(abi, PNC_MATERIAL_ABI_VERSION);
    std::vector<double> stress(6), state(static_cast<std::size_t>(n));
    in >> word;
    for (auto& v : stress)
      in >> v;
    in >> word;
    for (auto& v : state)
      in >> v;
    ASSERT_TRUE(in) << "unreadable output of " << exe;
    // The same path, through integrate2.
    auto m = make(p);
    std::vector<double> s0 = virgin(m.get());
    Vec6 e0 = Vec6::Zero();
    const double targets[3] = {0.25, 0.1, 0.25};
    const int steps[3] = {15, 10, 10};
    Out o;
    for (int seg = 0; seg < 3; ++seg) {
      const double step = (targets[seg] - e0[1]) / steps[seg];
      for (int s = 0; s < steps[seg]; ++s) {
        Vec6 de = Vec6::Zero();
        de[1] = step;
        o = call(m.get(), s0.data(), e0, de, PNC_MATERIAL_TANGENT_CONSISTENT);
        ASSERT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
        e0[1] += step;
        for (std::size_t i = 0; i < s0.size(); ++i)
          s0[i] = o.state1[i];
      }
    }
    EXPECT_GT(s0[static_cast<std::size_t>(pnc_material_state_index(m.get(), "D2"))], 0.0)
        << model << ": the path must damage (mode 2 / the maximum stretch)";
    for (int i = 0; i < 6; ++i)
      EXPECT_EQ(stress[static_cast<std::size_t>(i)], o.stress[static_cast<std::size_t>(i)])
          << model << " stress " << i;
    for (int i = 0; i < n; ++i)
      EXPECT_EQ(state[static_cast<std::size_t>(i)], s0[static_cast<std::size_t>(i)])
          << model << " state " << i;
  }
  posix_spawn_file_actions_destroy(&fa);
  close(fd);
  std::remove(out_path);
}

} // namespace
