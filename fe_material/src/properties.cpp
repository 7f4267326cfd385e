// Derived properties of a material (material_impl.hpp): the global-frame stiffness pieces of
// the prepared law, the damage onset, moduli by compliance inversion and the largest P-wave
// modulus (decision D211).
#include "material_impl.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace pnc::fe_material::detail {

namespace {

using pnc::damage::Matrix6;

// Voigt index of the tensor pair (i, j): 11 22 33 23 13 12.
int voigt(int i, int j) {
  static const int v[3][3] = {{0, 5, 4}, {5, 1, 3}, {4, 3, 2}};
  return v[i][j];
}

// Acoustic tensor Gamma_ik = C_ijkl n_j n_l; with engineering Voigt C_ijkl = C(v(i,j), v(k,l)).
Eigen::Matrix3d acoustic(const Matrix6& C, const Eigen::Vector3d& n) {
  Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int l = 0; l < 3; ++l)
          G(i, k) += C(voigt(i, j), voigt(k, l)) * n[j] * n[l];
  return 0.5 * (G + G.transpose());
}

// Largest eigenvalue of Gamma(n) (and its eigenvector in v).
double top(const Matrix6& C, const Eigen::Vector3d& n, Eigen::Vector3d& v) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(acoustic(C, n));
  v = es.eigenvectors().col(2);
  return es.eigenvalues()[2];
}

} // namespace

double max_p_wave_modulus(const Matrix6& C) {
  // g(n) = largest eigenvalue of Gamma(n) on the unit sphere (an even function of n): the
  // largest value over the axes, the face and body diagonals and 600 Fibonacci directions of
  // the half sphere, then a pattern search (compass steps along two tangent directions and
  // their diagonals, halved when none improves, down to 1e-10 rad) from the 12 best. The
  // maximum of a smooth g is found to O(step^2), far below rounding.
  std::vector<Eigen::Vector3d> starts;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = 0; c <= 1; ++c)
        if (c > 0 || b > 0 || (b == 0 && a > 0))
          starts.push_back(Eigen::Vector3d(a, b, c).normalized());
  const int nf = 600;
  const double golden = std::acos(-1.0) * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < nf; ++i) {
    const double z = (i + 0.5) / nf, r = std::sqrt(1.0 - z * z), phi = golden * i;
    starts.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  Eigen::Vector3d v;
  auto g = [&C, &v](const Eigen::Vector3d& n) { return top(C, n, v); };
  std::vector<std::pair<double, std::size_t>> value;
  for (std::size_t i = 0; i < starts.size(); ++i)
    value.emplace_back(g(starts[i]), i);
  std::sort(value.begin(), value.end(), [](const auto& x, const auto& y) { return x > y; });
  double best = value.front().first;
  for (std::size_t s = 0; s < std::min<std::size_t>(12, value.size()); ++s) {
    Eigen::Vector3d n = starts[value[s].second];
    double gn = value[s].first;
    for (double step = 0.05; step > 1e-10;) {
      // a tangent basis at n
      const Eigen::Vector3d t1 =
          (std::abs(n[0]) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY())
              .cross(n)
              .normalized();
      const Eigen::Vector3d t2 = n.cross(t1);
      bool moved = false;
      for (const auto& [a, b] : {std::pair<double, double>{1, 0},
                                 {-1, 0},
                                 {0, 1},
                                 {0, -1},
                                 {1, 1},
                                 {1, -1},
                                 {-1, 1},
                                 {-1, -1}}) {
        const Eigen::Vector3d trial = (n + step * (a * t1 + b * t2)).normalized();
        const double gt = g(trial);
        if (gt > gn) {
          n = trial;
          gn = gt;
          moved = true;
          break;
        }
      }
      if (!moved) step *= 0.5;
    }
    best = std::max(best, gn);
  }
  return best;
}

std::vector<Property> make_properties(const pnc::damage::PreparedNdm& q) {
  std::vector<Property> out;
  auto add = [&out](std::string name, const char* units, double value) {
    out.push_back({std::move(name), units, value});
  };
  const char* digits = "123456";
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      add(std::string("elastic_stiffness_") + digits[i] + digits[j], "Pa", q.C0g(i, j));
  const int modes = q.p.model == pnc::damage::Model::pnc ? 3 : 1;
  for (int m = 0; m < modes; ++m)
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        add(std::string("damage_stiffness_") + digits[m] + "_" + digits[i] + digits[j], "Pa",
            q.dC1g[static_cast<std::size_t>(m)](i, j));
  add("n_damage_modes", "1", modes);
  add("critical_stretch", "1", pnc::damage::critical_stretch());
  add("damage_onset_stretch", "1", q.p.alpha() * pnc::damage::critical_stretch());
  add("p_wave_modulus_max", "Pa", max_p_wave_modulus(q.C0g));
  const Matrix6 S = q.C0g.inverse();
  for (int i = 0; i < 3; ++i)
    add(std::string("youngs_modulus_") + digits[i], "Pa", 1.0 / S(i, i));
  add("shear_modulus_23", "Pa", 1.0 / S(3, 3));
  add("shear_modulus_13", "Pa", 1.0 / S(4, 4));
  add("shear_modulus_12", "Pa", 1.0 / S(5, 5));
  const int pairs[6][2] = {{0, 1}, {0, 2}, {1, 2}, {1, 0}, {2, 0}, {2, 1}};
  for (const auto& pr : pairs)
    add(std::string("poisson_ratio_") + digits[pr[0]] + digits[pr[1]], "1",
        -S(pr[0], pr[1]) / S(pr[0], pr[0]));
  return out;
}

} // namespace pnc::fe_material::detail
