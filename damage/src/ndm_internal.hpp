#pragma once
// Pieces of the NDM kernel shared by its one integration routine (ndm.cpp, D210) and the
// batched route (ndm_batch.cpp, D261), so that both evaluate the same expressions, operation
// for operation: lambda_c, the damage function D(x) with its slope, the onset margin and the
// uncapped mode stretch of D7. Internal to the damage library.
#include "pnc/damage/ndm.hpp"

#include <array>
#include <cmath>

namespace pnc::damage::detail {

/// lambda_c = (26/7)^(1/6) (eq. 5.79) and k = 1 / |2 lc^-13 - lc^-7| (D4); defined in ndm.cpp.
extern const double kLambdaC;
extern const double kDamageScale;

/// D(x) and dD/dx together (eq. 5.80, decision D4), one division. Branch-free (the formula
/// is evaluated and then selected) so that a loop over points vectorises; x <= lambda_c
/// (and NaN) give 0 and 0, as before.
inline void damage_and_slope(double x, double& D, double& dD) {
  const double xi = 1.0 / x;
  const double x2 = xi * xi, x6 = x2 * x2 * x2, x7 = x6 * xi, x8 = x6 * x2;
  const bool on = x > kLambdaC;
  D = on ? 1.0 + kDamageScale * (2 * x7 * x6 - x7) : 0.0;
  dD = on ? kDamageScale * (-26 * x8 * x6 + 7 * x8) : 0.0;
}

/// Damage of a mode at the largest stretch kappa, as integrate() forms it: below
/// `no_damage_below` (alpha lambda_c less a margin that covers the rounding of the division)
/// kappa / alpha <= lambda_c certainly, so D = dD/dx = 0 without dividing; above it,
/// D(kappa / alpha) as printed. Returns true when the mode is below the onset.
inline bool mode_damage(double kappa, double alpha, double no_damage_below, double& D, double& dD) {
  if (kappa < no_damage_below) {
    D = dD = 0.0;
    return true;
  }
  damage_and_slope(kappa / alpha, D, dD);
  return false;
}

/// The stretch below which a mode certainly has no damage: alpha lambda_c (1 - 1e-12).
inline double onset_margin(double alpha) {
  return alpha * kLambdaC * (1.0 - 1e-12);
}

/// The uncapped mode stretch of D7 with the finite shear term: lambda = e_kk + t +
/// sqrt(1 + t^2) (1 + e_kk in extension; t + sqrt(1 + t^2), the principal stretch of simple
/// shear by gamma = 2t, in shear), and d lambda / d t.
inline void uncapped_stretch(double ekk, double t, double& lambda, double& dlambda_dt) {
  const double r = std::sqrt(1.0 + t * t);
  lambda = ekk + t + r;
  dlambda_dt = 1.0 + t / r;
}

/// The mode stretches of D6/D7 of a platelet-frame strain v exactly as integrate() forms them
/// (compute_stretch() in ndm.cpp: for pnc the capped stretches, lambda_max by the closed-form
/// cubic where a cap binds; for pp the largest principal stretch), without derivatives.
void stretch_values(Model m, const Voigt& v, std::array<double, 3>& lambda);

/// lambda_max of D6 as integrate() forms it where a cap binds: the square root of the largest
/// eigenvalue of C = F^T F (closed-form cubic; one square root for block-diagonal C).
double largest_principal_stretch(const Voigt& v);

} // namespace pnc::damage::detail
