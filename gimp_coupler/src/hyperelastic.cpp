// The hyperelastic polymer law's stress update (materials.hpp, HyperelasticPolymer; D405): one
// body written for a scalar and for four particles at once (GCC/Clang vector extension), the
// four-particle loop compiled for the baseline, AVX2 and AVX-512 (run-time choice as D377, D414).
// Same operations in the same order for both types and no FMA contraction (-ffp-contract=off,
// CMakeLists.txt): update_many() equals update() bit for bit. SI units: F dimensionless,
// sigma and W in Pa (J/m^3).
#include "pnc/core/cpu.hpp"
#include "pnc/gimp_coupler/materials.hpp"

#include "inverse_cbrt.hpp"
#include "material_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>

namespace pnc::gimp {

namespace {

// The vector helpers are always inlined: the warning about the ABI of passing 32-byte vectors
// between functions compiled with and without AVX does not apply.
#pragma GCC diagnostic ignored "-Wpsabi" // GCC and Clang

typedef double v4 __attribute__((vector_size(32)));

constexpr double kCbrtLo = 0x1p-1000, kCbrtHi = 0x1p1000;

/// The first guess of x^(-1/3) from the bits of x, 0x1p-1000 <= x <= 0x1p1000: the exponent and
/// mantissa bits divided by -3 around those of 1.0, shifted by a constant that balances the
/// guess's relative error over a period of the mantissa (|error| < 3.5 %).
[[gnu::always_inline]] inline double inverse_cbrt_guess(double x) {
  std::uint64_t i;
  std::memcpy(&i, &x, sizeof i);
  i = 0x553ef0ff289dd796ULL - i / 3;
  double y;
  std::memcpy(&y, &i, sizeof y);
  return y;
}

/// Four Newton steps y <- y (4 - x y^3) / 3 for f(y) = y^-3 - x: the relative error e goes to
/// about 2 e^2 per step (0.035 -> 2.4e-3 -> 1.2e-5 -> 3e-10 -> 2e-19), so the last step leaves
/// only its own rounding (at most 5 u to first order; GimpMaterials.InverseCubeRoot...).
template <class T> [[gnu::always_inline]] inline T newton_inverse_cbrt(T x, T y) {
  for (int k = 0; k < 4; ++k)
    y = y * (4.0 - x * (y * y * y)) * (1.0 / 3.0);
  return y;
}

template <class T> [[gnu::always_inline]] inline T det3(const T (&F)[3][3]) {
  return F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
         F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
         F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
}

/// sigma (Voigt order 11 22 33 23 13 12) and W of F with J = det F and y = J^(-1/3):
/// sigma = J^-1 F S F^T written with b = F F^T (F C^-1 F^T = I, F C F^T = b^2), over the six
/// components of the symmetric tensors.
template <class T>
[[gnu::always_inline]] inline void hyperelastic_body(double c1, double c2, const T (&F)[3][3], T J,
                                                     T y, T (&sig)[6], T& W) {
  constexpr int I[6] = {0, 1, 2, 1, 0, 0}, K[6] = {0, 1, 2, 2, 2, 1};
  T b[3][3], b2[6];
  for (int v = 0; v < 6; ++v) {
    const int i = I[v], k = K[v];
    b[i][k] = b[k][i] = F[i][0] * F[k][0] + F[i][1] * F[k][1] + F[i][2] * F[k][2];
  }
  for (int v = 0; v < 6; ++v) {
    const int i = I[v], k = K[v];
    b2[v] = b[i][0] * b[0][k] + b[i][1] * b[1][k] + b[i][2] * b[2][k];
  }
  const T I1 = b[0][0] + b[1][1] + b[2][2];
  const T I2 = 0.5 * (I1 * I1 - (b2[0] + b2[1] + b2[2]));
  const T I3 = J * J;
  const T r1 = y * y; // I3^(-1/3) = J^(-2/3)
  const T I2b = I2 * r1 * r1;
  const T a0 = 2 * c1 * (I3 - 1) * I3, a1 = c2 * r1, a2 = 6 * c2 * I2b * r1 * r1;
  const T diag = a0 - a1 * (I1 / 3.0) - a2 * (2.0 / 3.0 * I2), s = 2.0 / J;
  for (int v = 0; v < 6; ++v) {
    const int i = I[v], k = K[v];
    const T t = a1 * b[i][k] + a2 * (I1 * b[i][k] - b2[v]);
    sig[v] = s * (v < 3 ? diag + t : t);
  }
  W = c1 * (I3 - 1) * (I3 - 1) + c2 * (I1 * r1 + 3 * I2b * I2b - 30.0);
}

[[gnu::always_inline]] inline void store_voigt(const double (&s)[6], Mat3& sigma) {
  sigma(0, 0) = s[0];
  sigma(1, 1) = s[1];
  sigma(2, 2) = s[2];
  sigma(1, 2) = sigma(2, 1) = s[3];
  sigma(0, 2) = sigma(2, 0) = s[4];
  sigma(0, 1) = sigma(1, 0) = s[5];
}

/// The particles [0, n - n % 4) four at a time; returns how many were done (a group with a
/// det F outside (0, inf) or a J^(-1/3) needing the libm fallback stops the loop there, and
/// update_many() goes on point by point).
[[gnu::always_inline]] inline std::size_t update_fours(double c1, double c2, std::size_t n,
                                                       const Mat3* F1, Mat3* sigma, double* W) {
  std::size_t p = 0;
  for (; p + 4 <= n; p += 4) {
    // every entry is set below; {} for GCC 12's -Wmaybe-uninitialized in the AVX-512 copy
    v4 F[3][3]{};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        F[i][k] = v4{F1[p](i, k), F1[p + 1](i, k), F1[p + 2](i, k), F1[p + 3](i, k)};
    const v4 J = det3(F);
    double y0[4];
    for (int q = 0; q < 4; ++q) {
      if (!(J[q] >= kCbrtLo && J[q] <= kCbrtHi)) return p; // also det F <= 0, NaN, inf
      y0[q] = inverse_cbrt_guess(J[q]);
    }
    const v4 y = newton_inverse_cbrt(J, v4{y0[0], y0[1], y0[2], y0[3]});
    v4 sig[6], w;
    hyperelastic_body(c1, c2, F, J, y, sig, w);
    for (int q = 0; q < 4; ++q) {
      const double s[6] = {sig[0][q], sig[1][q], sig[2][q], sig[3][q], sig[4][q], sig[5][q]};
      store_voigt(s, sigma[p + q]);
      W[p + q] = w[q];
    }
  }
  return p;
}

std::size_t update_fours_baseline(double c1, double c2, std::size_t n, const Mat3* F1, Mat3* sigma,
                                  double* W) {
  return update_fours(c1, c2, n, F1, sigma, W);
}

PNC_TARGET_AVX2 std::size_t update_fours_avx2(double c1, double c2, std::size_t n, const Mat3* F1,
                                              Mat3* sigma, double* W) {
  return update_fours(c1, c2, n, F1, sigma, W);
}

PNC_TARGET_AVX512 std::size_t update_fours_avx512(double c1, double c2, std::size_t n,
                                                  const Mat3* F1, Mat3* sigma, double* W) {
  return update_fours(c1, c2, n, F1, sigma, W);
}

} // namespace

/// x^(-1/3) for x > 0 without a division or libm (inverse_cbrt.hpp).
double detail::inverse_cbrt(double x) {
  if (!(x >= kCbrtLo && x <= kCbrtHi)) return 1.0 / std::cbrt(x);
  return newton_inverse_cbrt(x, inverse_cbrt_guess(x));
}

void HyperelasticPolymer::update(const Mat3& /*F0*/, const Mat3& F1, const double* /*s0*/,
                                 double* /*s1*/, Mat3& sigma, double& W) const {
  double F[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      F[i][k] = F1(i, k);
  const double J = det3(F);
  detail::check_jacobian(J, "hyperelastic_polymer");
  double s[6];
  hyperelastic_body(c1_, c2_, F, J, detail::inverse_cbrt(J), s, W);
  store_voigt(s, sigma);
}

void HyperelasticPolymer::update_many(std::size_t n, const Mat3* F0, const Mat3* F1,
                                      double* /*state*/, std::size_t /*stride*/, Mat3* sigma,
                                      double* W) const {
  std::size_t p = 0;
  while (p < n) {
    p += pnc::cpu_has_avx512() ? update_fours_avx512(c1_, c2_, n - p, F1 + p, sigma + p, W + p)
         : pnc::cpu_has_avx2() ? update_fours_avx2(c1_, c2_, n - p, F1 + p, sigma + p, W + p)
                               : update_fours_baseline(c1_, c2_, n - p, F1 + p, sigma + p, W + p);
    const std::size_t end = std::min(n, p + 4); // the remainder, or the group the loop left
    for (; p < end; ++p) {
      try {
        update(F0[p], F1[p], nullptr, nullptr, sigma[p], W[p]);
      } catch (const std::exception& ex) {
        throw PointFailure(p, ex.what());
      }
    }
  }
}

} // namespace pnc::gimp
