#pragma once
// x^(-1/3) as the hyperelastic law computes it (hyperelastic.cpp, D405): a first guess from the
// bits of x and four division-free Newton steps, within 5 u (u = 2^-53) on [2^-1000, 2^1000];
// 1 / std::cbrt(x) outside that range (and for NaN, inf, subnormals). Private to pnc::gimp and
// its tests. Dimensionless.

namespace pnc::gimp::detail {

double inverse_cbrt(double x);

} // namespace pnc::gimp::detail
