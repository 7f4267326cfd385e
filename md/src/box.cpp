// Deforming a LAMMPS box by F (pnc/md/box.hpp; D316, D63).
#include "pnc/md/box.hpp"

#include "pnc/core/error.hpp"

#include <fmt/format.h>

#include <cmath>

namespace pnc::md {

LmpBox LmpBox::from_vector(const std::vector<double>& v, const std::string& source) {
  if (v.size() != 9)
    fail(source, "reference box", std::to_string(v.size()) + " values",
         "must hold xlo ylo zlo xhi yhi zhi xy xz yz");
  LmpBox b;
  b.lo = {v[0], v[1], v[2]};
  b.hi = {v[3], v[4], v[5]};
  b.xy = v[6], b.xz = v[7], b.yz = v[8];
  return b;
}

Eigen::Matrix3d LmpBox::edges() const {
  Eigen::Matrix3d h;
  h << hi[0] - lo[0], xy, xz, 0, hi[1] - lo[1], yz, 0, 0, hi[2] - lo[2];
  return h;
}

namespace {
std::string length_args(const LmpBox& ref, int a, double length) {
  const double centre = 0.5 * (ref.lo[a] + ref.hi[a]), half = 0.5 * length;
  return fmt::format(" {} final {:.15g} {:.15g}", "xyz"[a], centre - half, centre + half);
}

// F upper triangular: the new edges F a, F b, F c are already in the box form.
std::string upper_args(const LmpBox& ref, const Eigen::Matrix3d& F, const std::string& source) {
  std::string args;
  for (int a = 0; a < 3; ++a) {
    if (!(F(a, a) > 0))
      fail(source, fmt::format("F({},{})", a + 1, a + 1), fmt::format("{}", F(a, a)),
           "the stretches of a deformation gradient of the box must be > 0");
    const double L = ref.hi[a] - ref.lo[a];
    if (F(a, a) != 1.0) args += length_args(ref, a, L * F(a, a));
  }
  const double Ly = ref.hi[1] - ref.lo[1], Lz = ref.hi[2] - ref.lo[2];
  const double tilt[3] = {F(0, 0) * ref.xy + F(0, 1) * Ly,                    // xy of F b
                          F(0, 0) * ref.xz + F(0, 1) * ref.yz + F(0, 2) * Lz, // xz of F c
                          F(1, 1) * ref.yz + F(1, 2) * Lz};                   // yz of F c
  const double before[3] = {ref.xy, ref.xz, ref.yz};
  static const char* const names[3] = {"xy", "xz", "yz"};
  for (int k = 2; k >= 0; --k) // yz, xz, xy
    if (tilt[k] != before[k]) args += fmt::format(" {} final {:.15g}", names[k], tilt[k]);
  return args;
}

// Any other F: F H = Q R, R upper triangular with positive diagonal; the box R is F H rotated
// by Q^T, and the remap (fractional coordinates kept) maps x -> Q^T F x (D63).
std::string rotated_args(const LmpBox& ref, const Eigen::Matrix3d& F) {
  Eigen::HouseholderQR<Eigen::Matrix3d> qr(F * ref.edges());
  Eigen::Matrix3d R = qr.matrixQR().triangularView<Eigen::Upper>();
  for (int i = 0; i < 3; ++i)
    if (R(i, i) < 0) R.row(i) *= -1;
  std::string args;
  for (int a = 0; a < 3; ++a)
    args += length_args(ref, a, R(a, a));
  return args + fmt::format(" xy final {:.15g} xz final {:.15g} yz final {:.15g}", R(0, 1), R(0, 2),
                            R(1, 2));
}
} // namespace

std::string box_change(const LmpBox& ref, const Eigen::Matrix3d& F, const std::string& source) {
  if (!F.allFinite() || !(F.determinant() > 0))
    fail(source, "F", fmt::format("det {}", F.determinant()),
         "a deformation gradient must be finite with det F > 0");
  const std::string args =
      F.isUpperTriangular(0.0) ? upper_args(ref, F, source) : rotated_args(ref, F);
  return args.empty() ? "" : "change_box all" + args + " remap units box";
}

} // namespace pnc::md
