// Lattice sums of an LJ FCC crystal (escm_lj.hpp).
#include "pnc/gimp_coupler/escm_lj.hpp"

#include "pnc/core/units.hpp"
#include "pnc/gimp_coupler/escm.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace pnc::gimp::escm {

double LjFcc::E() const {
  const double lam = C12, mu = 0.5 * (C11 - C12);
  return mu * (3.0 * lam + 2.0 * mu) / (lam + mu);
}

double LjFcc::nu() const {
  const double lam = C12, mu = 0.5 * (C11 - C12);
  return lam / (2.0 * (lam + mu));
}

namespace {

// FCC neighbour vectors in units of a, within rc / a.
std::vector<std::array<double, 3>> fcc_neighbours(double rc_over_a) {
  const int n = static_cast<int>(std::ceil(rc_over_a)) + 1;
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::vector<std::array<double, 3>> out;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k)
        for (const auto& b : basis) {
          const std::array<double, 3> r{i + b[0], j + b[1], k + b[2]};
          const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
          if (r2 > 1e-12 && r2 < rc_over_a * rc_over_a) out.push_back(r);
        }
  return out;
}

} // namespace

LjFcc lj_fcc(double eps, double sig, double rc, double mass) {
  if (!(eps > 0) || !(sig > 0) || !(rc > 0) || !(mass > 0))
    throw std::invalid_argument("lj_fcc: eps, sigma, rc and mass must be > 0");
  auto dphi = [&](double r) { // phi'(r)
    const double s6 = std::pow(sig / r, 6);
    return 4.0 * eps * (-12.0 * s6 * s6 + 6.0 * s6) / r;
  };
  auto d2phi = [&](double r) {
    const double s6 = std::pow(sig / r, 6);
    return 4.0 * eps * (156.0 * s6 * s6 - 42.0 * s6) / (r * r);
  };
  // Zero pressure: g(a) = sum phi'(r) r = 0. The neighbour set depends on a; bisection on a
  // around the nearest-neighbour-only solution, neighbour list rebuilt at each a.
  auto g = [&](double a) {
    double s = 0.0;
    for (const auto& n : fcc_neighbours(rc / a)) {
      const double r = a * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      s += dphi(r) * r;
    }
    return s;
  };
  double lo = std::sqrt(2.0) * sig * 0.95, hi = std::sqrt(2.0) * sig * 1.25;
  if (rc < lo / std::sqrt(2.0))
    throw std::invalid_argument("lj_fcc: rc below the neighbour distance");
  if (!(g(lo) < 0 && g(hi) > 0)) throw std::invalid_argument("lj_fcc: no zero-pressure lattice");
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) < 0 ? lo : hi) = mid;
  }
  LjFcc out;
  const double a = 0.5 * (lo + hi);
  out.a0_A = a;
  double c11 = 0, c12 = 0, c44 = 0;
  for (const auto& n : fcc_neighbours(rc / a)) {
    const double x = a * n[0], y = a * n[1], z = a * n[2];
    const double r = std::sqrt(x * x + y * y + z * z);
    const double k = (d2phi(r) - dphi(r) / r) / (r * r);
    c11 += k * x * x * x * x;
    c12 += k * x * x * y * y;
    c44 += k * y * y * z * z;
  }
  const double omega = a * a * a / 4.0;                                   // A^3
  const double conv = units::J_per_kcalmol / std::pow(units::m_per_A, 3); // kcal/mol/A^3 -> Pa
  out.C11 = c11 / (2.0 * omega) * conv;
  out.C12 = c12 / (2.0 * omega) * conv;
  out.C44 = c44 / (2.0 * omega) * conv;
  out.density = mass * units::kg_per_gmol / (omega * std::pow(units::m_per_A, 3));
  return out;
}

double lj_fcc_separation_work(const LjFcc& lj, double eps, double sig, double rc) {
  // A pair n (units of a0) with n_y = m a0/2 > 0 crosses the plane from m layers below it;
  // a (010) layer has 2 atoms per a0^2 (D83).
  const double a = lj.a0_A;
  double sum = 0.0; // kcal/mol per atom of a layer
  for (const auto& n : fcc_neighbours(rc / a)) {
    if (n[1] <= 0) continue;
    const double r = a * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double sr6 = std::pow(sig / r, 6);
    sum += 2.0 * n[1] * 4.0 * eps * (sr6 * sr6 - sr6);
  }
  const double per_area = -sum / (0.5 * a * a); // kcal/mol/A^2
  return per_area * pnc::units::j_m2_per_kcal_mol_A2;
}

std::vector<std::string> lj_fcc_block_commands(const LjFcc& lj, int nx, int ny, int nz,
                                               double mass_gmol, double eps_kcalmol, double sigma_A,
                                               double rc_A, int types) {
  std::vector<std::string> c = {"units real", "atom_style atomic", "boundary s s p"};
  std::ostringstream s;
  s.precision(12);
  auto flush = [&] {
    c.push_back(s.str());
    s.str("");
  };
  s << "lattice fcc " << lj.a0_A;
  flush();
  s << "region escm_box block -0.25 " << nx - 0.25 << " -0.25 " << ny - 0.25 << " 0 " << nz
    << " units lattice";
  flush();
  c.push_back("create_box " + std::to_string(types) + " escm_box");
  c.push_back("create_atoms 1 box");
  s << "mass * " << mass_gmol;
  flush();
  s << "pair_style lj/cut " << rc_A;
  flush();
  s << "pair_coeff * * " << eps_kcalmol << ' ' << sigma_A;
  flush();
  return c;
}

} // namespace pnc::gimp::escm
