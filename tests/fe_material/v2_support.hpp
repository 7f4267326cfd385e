#pragma once
// Shared helpers of the ABI 1.1 tests (test_fe_material_v2.cpp, test_fe_material_props.cpp):
// references written from docs/theory.md section 1 (not from the plugin), material factory,
// one integrate2 call. Internal to the tests.
#include "pnc/damage/ndm.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/material.hpp"
#include "pnc/fe_material/pnc_material.h"
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <gtest/gtest.h>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace pnc_v2_test {

using pnc::damage::Model;
using pnc::damage::NdmParameters;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// ------------------------------------------------------------------ independent references
inline Eigen::Matrix3d rotation_zx(double deg_z, double deg_x) {
  const double pi = std::acos(-1.0);
  const double a = deg_z * pi / 180, b = deg_x * pi / 180;
  Eigen::Matrix3d Rz, Rx;
  Rz << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  Rx << 1, 0, 0, 0, std::cos(b), -std::sin(b), 0, std::sin(b), std::cos(b);
  return Rz * Rx;
}

inline double k(const NdmParameters& p, const char* name) {
  return p[name];
}

// [C0] + [C1(D)] in the platelet frame, written from docs/theory.md (1.1)-(1.2): the normal
// block C_ij + damage terms, the shear diagonal; pp in its isotropic reading.
inline Mat6 local_stiffness(const NdmParameters& p, const std::array<double, 3>& D) {
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
inline Mat6 strain_rotation(const Eigen::Matrix3d& R) {
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

inline Mat6 global_stiffness(const NdmParameters& p, const std::array<double, 3>& D) {
  const Mat6 T = strain_rotation(p.R);
  return T.transpose() * local_stiffness(p, D) * T;
}

inline double lambda_c() {
  return std::pow(26.0 / 7.0, 1.0 / 6.0);
}

inline NdmParameters params(Model m, bool rotated) {
  NdmParameters p = pnc::damage::dissertation_parameters(m);
  if (rotated) p.R = rotation_zx(30.0, 20.0);
  return p;
}

inline std::unique_ptr<pnc_material, void (*)(pnc_material*)> make(const NdmParameters& p) {
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
inline Out call(const pnc_material* m, const double* s0, const Vec6& e0, const Vec6& de,
                int request) {
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

inline Mat6 as_matrix(const std::array<double, 36>& K) {
  Mat6 M;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      M(i, j) = K[static_cast<std::size_t>(6 * i + j)];
  return M;
}
inline Vec6 as_vec(const std::array<double, 6>& v) {
  return Eigen::Map<const Vec6>(v.data());
}
inline std::array<double, 3> damage_of(Model m, const std::array<double, 6>& state) {
  if (m == Model::pnc) return {state[3], state[4], state[5]};
  return {state[1], 0.0, 0.0};
}

inline std::array<double, 6> padded(const std::vector<double>& s) {
  std::array<double, 6> out{};
  for (std::size_t i = 0; i < s.size() && i < 6; ++i)
    out[i] = s[i];
  return out;
}

inline std::vector<double> virgin(const pnc_material* m) {
  std::vector<double> s(static_cast<std::size_t>(pnc_material_n_state(m)));
  pnc_material_init_state(m, s.data());
  return s;
}

struct Case {
  Model model;
  bool rotated;
};
inline std::string name_of(const Case& c) {
  return std::string(pnc::damage::model_name(c.model)) + (c.rotated ? "_rotated" : "_aligned");
}
inline constexpr Case kCases[] = {
    {Model::pnc, false}, {Model::pnc, true}, {Model::pp, false}, {Model::pp, true}};

// Strains: below onset, past onset in several directions (the pnc onset is a mode stretch of
// alpha lambda_c = 1.07, pp 1.17).
inline std::vector<Vec6> strains() {
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

} // namespace pnc_v2_test
