#pragma once
// Shared helpers of the NDM kernel tests (test_ndm_stretch.cpp, test_ndm_kernel.cpp):
// references written independently of the kernel (D6 by Eigen's SVD, tensor/Voigt maps) and
// one integration from zero strain. Internal to the tests.
#include "pnc/damage/ndm.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace pnc_ndm_test {

using namespace pnc::damage;

// P: NdmParameters or PreparedNdm (the two integrate() overloads).
template <class P>
inline Voigt integrate_total(const P& p, const NdmState& s0, const Voigt& eps,
                             NdmState* s1_out = nullptr, Matrix6* K = nullptr) {
  NdmState s1;
  Voigt sigma;
  ErrorBuffer err;
  EXPECT_EQ(integrate(p, s0, s1, Voigt::Zero(), eps, sigma, K, err), Status::ok) << err.msg;
  if (s1_out) *s1_out = s1;
  return sigma;
}

inline Eigen::Matrix3d rotation(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

inline Eigen::Matrix3d to_tensor(const Voigt& v) {
  Eigen::Matrix3d e;
  e << v[0], v[5] / 2, v[4] / 2, v[5] / 2, v[1], v[3] / 2, v[4] / 2, v[3] / 2, v[2];
  return e;
}
// Decision D6 written out independently of the kernel: the upper-triangular (LAMMPS cell)
// deformation gradient of a small strain and its largest singular value by Eigen's SVD.
inline double reference_largest_stretch(const Voigt& v) {
  Eigen::Matrix3d F;
  F << 1 + v[0], v[5], v[4], 0, 1 + v[1], v[3], 0, 0, 1 + v[2];
  return Eigen::JacobiSVD<Eigen::Matrix3d>(F).singularValues()[0];
}
inline Voigt strain_to_voigt(const Eigen::Matrix3d& e) {
  Voigt v;
  v << e(0, 0), e(1, 1), e(2, 2), 2 * e(1, 2), 2 * e(0, 2), 2 * e(0, 1);
  return v;
}
inline Eigen::Matrix3d stress_tensor(const Voigt& s) {
  Eigen::Matrix3d t;
  t << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
  return t;
}

} // namespace pnc_ndm_test
