#include "pnc/damage/moduli.hpp"

#include "pnc/damage/reference.hpp"

namespace pnc::damage {

DerivedModuli derive_moduli(const NdmParameters& p) {
  const Matrix6 C = stiffness_c0(p);
  const Eigen::Matrix3d Cn = C.topLeftCorner<3, 3>();
  const Eigen::Matrix3d S = Cn.inverse();
  DerivedModuli d{};
  d.E1 = 1 / S(0, 0);
  d.E2 = 1 / S(1, 1);
  d.E3 = 1 / S(2, 2);
  d.nu12 = -S(1, 0) / S(0, 0);
  d.nu13 = -S(2, 0) / S(0, 0);
  d.nu23 = -S(2, 1) / S(1, 1);
  d.nu21 = -S(0, 1) / S(1, 1);
  d.nu31 = -S(0, 2) / S(2, 2);
  d.nu32 = -S(1, 2) / S(2, 2);
  d.G23 = C(3, 3);
  d.G13 = C(4, 4);
  d.G12 = C(5, 5);
  d.E2_as_printed = Cn.determinant() / (Cn(1, 1) * Cn(2, 2) - Cn(1, 2) * Cn(1, 2));
  const double c22 = Cn(0, 0), c12 = Cn(0, 1);
  d.E_isotropic_formula = (c22 * c22 + c12 * c22 - 2 * c12 * c12) / (c22 + c12);
  return d;
}

CaseStrength case_strength(const NdmParameters& p, int case_id, double max_strain, int points) {
  const DeformationCase& dc = deformation_case(case_id);
  const int driven = single_driven(dc, "the case strength"); // D360
  const double sense = driven_sense(dc); // a negative shear peaks at its most negative (D424)
  CaseStrength out{case_id, driven, std::nullopt, 0.0, max_strain};
  Eigen::Matrix<double, Eigen::Dynamic, 6> path(points + 1, 6);
  for (int i = 0; i <= points; ++i)
    path.row(i) = case_strain(case_id, max_strain * i / points).transpose();
  const auto s = stress_path(p, path);
  // The strength is the FIRST local maximum of the driven stress along the path (the load
  // a strain-controlled test passes through before the stress drops; a later rise, e.g.
  // once damage saturates and C0 + C1(1) > 0, is not a strength). Decision D5.
  Eigen::Index imax = 0;
  for (Eigen::Index i = 1; i < points; ++i) {
    if (sense * s(i, driven) > sense * s(i - 1, driven) &&
        sense * s(i, driven) >= sense * s(i + 1, driven)) {
      imax = i;
      break;
    }
  }
  if (imax == 0) return out; // monotonic over the range: no peak
  // Refine on the bracket [i-1, i+1] by golden-section search on the monotonic path
  // (irreversibility does not matter: the path is monotonic, so the stress at a strain is a
  // function of that strain alone).
  auto f = [&](double t) {
    Eigen::Matrix<double, 1, 6> row = case_strain(case_id, t).transpose();
    return sense * stress_path(p, row)(0, driven);
  };
  const double im = static_cast<double>(imax);
  double a = max_strain * (im - 1) / points, b = max_strain * (im + 1) / points;
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  for (int it = 0; it < 80; ++it) {
    if (f(x1) > f(x2))
      b = x2;
    else
      a = x1;
    x1 = b - g * (b - a);
    x2 = a + g * (b - a);
  }
  out.strain_at_peak = 0.5 * (a + b);
  out.peak = sense * f(out.strain_at_peak);
  return out;
}

} // namespace pnc::damage
