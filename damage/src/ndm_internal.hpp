#pragma once
// Pieces of the NDM kernel shared by its one integration routine (ndm.cpp, D210) and the
// batched route (ndm_batch.cpp, D261), so that both evaluate the same expressions, operation
// for operation: lambda_c, the damage function D(x) with its slope, the onset margin, the
// products with a strain (the platelet-frame strain, the stress), the uncapped mode stretch of
// D7, the mode shear and the block-diagonal stretches (D351). Internal to the damage library.
#include "pnc/damage/ndm.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pnc::damage::detail {

/// Indices of the pnc law's constants in NdmParameters::k (the order of constant_names()).
enum PncIdx {
  iC11,
  iC22,
  iC33,
  iC12,
  iC13,
  iC23,
  iC44,
  iC55,
  iC66,
  iA1,
  iA5,
  iA9,
  iA10,
  iA11,
  iA13,
  iA15,
  iA17,
  iA18,
  iA22,
  iA24,
  iA26,
  iAlphaPnc
};

/// Indices of the pp law's constants in NdmParameters::k (the order of constant_names()).
enum PpIdx { jC11, jC12, jC44, jB1, jB2, jB4, jAlphaPp };

/// v = dC1/dD e of the pp law (its one mode; engineering Voigt strain e), as every route forms
/// it (the single-point kernel's c1_times() and the batched damage-growth pass, D419).
template <class K, class E, class V> inline void pp_c1_times(const K& k, const E& e, V& v) {
  const double s = e[0] + e[1] + e[2];
  for (int i = 0; i < 3; ++i) {
    v[i] = 2 * k[jB1] * e[i] + k[jB2] * (s - e[i]);
    v[3 + i] = k[jB4] * e[3 + i];
  }
}

/// v = dC1/dD_m e of the pnc law (mode m = 0, 1, 2; platelet-frame engineering Voigt strain e),
/// by the sparsity of dC1/dD_m, as every route forms it (the single-point kernel's c1_times()
/// and the batched damage-growth pass, D399). k: NdmParameters::k.
template <class K, class E, class V> inline void pnc_c1_times(const K& k, int m, const E& e, V& v) {
  switch (m) {
  case 0:
    v[0] = 2 * k[iA1] * e[0] + k[iA10] * e[1] + k[iA13] * e[2];
    v[1] = k[iA10] * e[0];
    v[2] = k[iA13] * e[0];
    v[3] = 0.0;
    v[4] = 0.0;
    v[5] = 0.0;
    break;
  case 1:
    v[0] = k[iA11] * e[1];
    v[1] = k[iA11] * e[0] + 2 * k[iA5] * e[1] + k[iA17] * e[2];
    v[2] = k[iA17] * e[1];
    v[3] = k[iA22] * e[3];
    v[4] = 0.0;
    v[5] = k[iA24] * e[5];
    break;
  default:
    v[0] = k[iA15] * e[2];
    v[1] = k[iA18] * e[2];
    v[2] = k[iA15] * e[0] + k[iA18] * e[1] + 2 * k[iA9] * e[2];
    v[3] = 0.0;
    v[4] = k[iA26] * e[4];
    v[5] = 0.0;
    break;
  }
}

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

/// Row `a` (a[0..5]) of a matrix times a strain e (engineering Voigt) as every route of the
/// kernel forms the products with a strain (the rotation el = T eps, the stress C eps; D351):
/// the full row in column order, or for a plane strain (e33 = g23 = g13 = 0, every point of a
/// 2-D run) columns 1, 2 and 6 only. The batched route selects without a branch (times_row()),
/// the single-point route picks one per strain (times()).
template <class Row>
inline double row_full(const Row& a, double e0, double e1, double e2, double e3, double e4,
                       double e5) {
  return a[0] * e0 + a[1] * e1 + a[2] * e2 + a[3] * e3 + a[4] * e4 + a[5] * e5;
}
template <class Row> inline double row_plane(const Row& a, double e0, double e1, double e5) {
  return a[0] * e0 + a[1] * e1 + a[5] * e5;
}
inline bool is_plane(double e2, double e3, double e4) {
  return e2 == 0.0 && e3 == 0.0 && e4 == 0.0;
}
template <class Row>
inline double times_row(const Row& a, double e0, double e1, double e2, double e3, double e4,
                        double e5) {
  const double full = row_full(a, e0, e1, e2, e3, e4, e5);
  const double pl = row_plane(a, e0, e1, e5);
  return is_plane(e2, e3, e4) ? pl : full;
}
/// A e: the sums of row_full() / row_plane(), in the same column order, written column-wise so
/// that Eigen keeps the rows in vector registers; each entry is the same sequence of IEEE
/// products and sums as times_row() (the batched route's), so the two agree bit for bit
/// (FeMaterialBatch.* and FeMaterialV2.ModeStretchQueryAndIntegrationAgreeBitForBit check it).
inline Voigt times(const Matrix6& A, const Voigt& e) {
  if (is_plane(e[2], e[3], e[4])) return A.col(0) * e[0] + A.col(1) * e[1] + A.col(5) * e[5];
  return A.col(0) * e[0] + A.col(1) * e[1] + A.col(2) * e[2] + A.col(3) * e[3] + A.col(4) * e[4] +
         A.col(5) * e[5];
}

/// T^T v: entry r is column r of T times v in column order (row_full()), as both routes form
/// the damage-growth term of a rotated consistent tangent (the vector T^T a and the row g T,
/// which is T^T g^T); the same sequence of IEEE products and sums in both (D399).
inline Voigt transpose_times(const Matrix6& T, const Voigt& v) {
  Voigt o;
  for (int r = 0; r < 6; ++r)
    o[r] = row_full(T.col(r), v[0], v[1], v[2], v[3], v[4], v[5]);
  return o;
}

/// C = F^T F of D6's F(v) (engineering Voigt strain v[0..5], platelet frame; F upper
/// triangular, rows (1 + v0, v5, v4), (0, 1 + v1, v3), (0, 0, 1 + v2)) as c = {C00, C11, C22,
/// C01, C02, C12}: C_ij = sum_k F_ki F_kj over the k where neither factor is a structural zero
/// of F, left to right. One expression for the kernel and the batched route (the caps,
/// lambda_max and the capped stretch's derivative; D399, D402).
template <class V> inline void cauchy_green(const V& v, double (&c)[6]) {
  const double f00 = 1.0 + v[0], f11 = 1.0 + v[1], f22 = 1.0 + v[2];
  c[0] = f00 * f00;
  c[1] = v[5] * v[5] + f11 * f11;
  c[2] = v[4] * v[4] + v[3] * v[3] + f22 * f22;
  c[3] = f00 * v[5];
  c[4] = f00 * v[4];
  c[5] = v[5] * v[4] + f11 * v[3];
}

/// mu > the largest eigenvalue of the symmetric C (entries as cauchy_green()), without the
/// eigenvalue: mu I - C positive definite by Sylvester's criterion on its leading minors.
/// EarlyExit (the kernel): no further minor once one is not positive; false (a loop over
/// points, which then has no branch): all three formed. The same expressions either way.
template <bool EarlyExit = true>
inline bool exceeds_largest_eigenvalue(const double (&c)[6], double mu) {
  const double a = mu - c[0], b = mu - c[1], cc = mu - c[2];
  const double x = c[3], y = c[4], z = c[5];
  if constexpr (EarlyExit)
    if (!(a > 0.0)) return false;
  const double m2 = a * b - x * x;
  if constexpr (EarlyExit)
    if (!(m2 > 0.0)) return false;
  const double m3 = a * (b * cc - z * z) - cc * x * x - b * y * y - 2.0 * x * y * z;
  return (a > 0.0) & (m2 > 0.0) & (m3 > 0.0);
}

/// The largest eigenvalue of the symmetric C (entries as cauchy_green()) in two halves around
/// its one cosine, so that a loop over points runs both halves vectorised and the cosine point
/// by point (D402). eigen_start(): when C is block-diagonal (C02 = C12 = 0, C01 = C12 = 0 or
/// C01 = C02 = 0, tested in that order) the eigenvalue itself in `value` (one square root) and
/// trig = false; else trig = true and the trigonometric solution's shift q, scale pp and
/// r = det(B) / 2 clamped to [-1, 1], B = (C - q I) / pp (EarlyExit, the kernel: only what
/// the case needs; false, a loop over points: both, with no branch). The eigenvalue is then
/// eigen_end(value, q, pp, eigen_cos(r), trig).
template <bool EarlyExit = true>
inline void eigen_start(const double (&c)[6], double& value, double& q, double& pp, double& r,
                        bool& trig) {
  const double e00 = c[0], e11 = c[1], e22 = c[2], e01 = c[3], e02 = c[4], e12 = c[5];
  // the block (i; a, b) with the entry e(a, b): max(e(i, i), m + sqrt(d^2 + e(a, b)^2))
  const bool k2 = (e02 == 0.0) & (e12 == 0.0), k1 = (e01 == 0.0) & (e12 == 0.0),
             k0 = (e01 == 0.0) & (e02 == 0.0);
  trig = !(k2 | k1 | k0);
  if (!EarlyExit || !trig) {
    const double ii = k2 ? e22 : (k1 ? e11 : e00), aa = k2 ? e00 : (k1 ? e00 : e11),
                 bb = k2 ? e11 : e22, ab = k2 ? e01 : (k1 ? e02 : e12);
    const double m = 0.5 * (aa + bb), d = 0.5 * (aa - bb);
    value = std::max(ii, m + std::sqrt(d * d + ab * ab));
    if (EarlyExit) return;
  }
  const double p1 = e01 * e01 + e02 * e02 + e12 * e12;
  q = (e00 + e11 + e22) / 3.0;
  const double a = e00 - q, b = e11 - q, cc = e22 - q;
  const double p2 = a * a + b * b + cc * cc + 2.0 * p1;
  pp = std::sqrt(p2 / 6.0);
  const double ip = 1.0 / pp;
  const double b00 = a * ip, b11 = b * ip, b22 = cc * ip;
  const double b01 = e01 * ip, b02 = e02 * ip, b12 = e12 * ip;
  const double det =
      b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
  r = std::min(1.0, std::max(-1.0, 0.5 * det));
}
/// cos(acos(r) / 3) for r in [-1, 1] without a library call, so that a loop over points
/// vectorises it with the single point's bits (D409). It is the largest root c of
/// 4c^3 - 3c = r, written c = 1/2 + w u with w = sqrt(1 + r): u in [0.353, 0.409] is the root
/// of 6u^2 + 4w u^3 = 1, whose derivative stays above 4 on the whole range (the form has no
/// square-root singularity at r = -1, where the two largest eigenvalues meet). Start: a
/// degree-4 fit of u(w) on [0, sqrt 2] (within 5.3e-6); two Newton steps take that below 1e-19
/// before rounding. Branch-free; |c - cos(acos(r) / 3)| <= 8 u_r for every r (u_r = 2^-53).
[[gnu::always_inline]] inline double eigen_cos(double r) {
  const double w = std::sqrt(1.0 + r);
  double u = (((9.601709833911914e-4 * w - 5.566805085785019e-3) * w + 1.776054887244956e-2) * w -
              5.536869155452663e-2) *
                 w +
             0.4082430825472669;
#pragma GCC unroll 2
  for (int k = 0; k < 2; ++k) {
    const double wu = w * u;
    const double h = u * u * (6.0 + 4.0 * wu) - 1.0;
    u = u - h / (12.0 * u * (1.0 + wu));
  }
  return 0.5 + w * u;
}
inline double eigen_end(double value, double q, double pp, double cos_third, bool trig) {
  return trig ? q + 2.0 * pp * cos_third : value;
}
/// The largest eigenvalue of C in one call (the kernel's use).
inline double largest_eigenvalue(const double (&c)[6]) {
  double value = 0.0, q = 0.0, pp = 0.0, r = 0.0;
  bool trig;
  eigen_start(c, value, q, pp, r, trig);
  return trig ? eigen_end(value, q, pp, eigen_cos(r), true) : value;
}

/// d lambda_max / d v (engineering Voigt strain v[0..5], platelet frame) where a mode's cap
/// binds (D6/D7): (F N)_a N_b / lambda_max for the entry (a, b) of F that v_I sets, N the unit
/// principal direction of C = F^T F for its largest eigenvalue lambda_max^2, taken as the
/// longest cross product of two rows of C - lambda_max^2 I. Every product and sum is written
/// out in one order (left to right), so the single-point kernel and the batched route get the
/// same bits (D399). Returns false when that eigenvalue is (nearly) repeated (longest cross
/// product^2 <= 1e-20 |C|^4): the direction is not unique, row holds no meaning, and the caller
/// takes Eigen's solver. Branch-free, so that a loop over points vectorises.
template <class V>
[[gnu::always_inline]] inline bool capped_stretch_row(const V& v, double lambda_max,
                                                      double (&row)[6]) {
  // F = I + diag(e) + g12 e1(x)e2 + g13 e1(x)e3 + g23 e2(x)e3 (D6), rows f[a][b]
  const double f[3][3] = {
      {1.0 + v[0], v[5], v[4]}, {0.0, 1.0 + v[1], v[3]}, {0.0, 0.0, 1.0 + v[2]}};
  double c6[6];
  cauchy_green(v, c6);
  const double C[3][3] = {{c6[0], c6[3], c6[4]}, {c6[3], c6[1], c6[5]}, {c6[4], c6[5], c6[2]}};
  const double lam = lambda_max * lambda_max;
  double M[3][3];
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i)
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j)
      M[i][j] = i == j ? C[i][j] - lam : C[i][j];
  auto cross = [](const double(&a)[3], const double(&b)[3], double(&o)[3]) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
  };
  double c01[3], c02[3], c12[3];
  cross(M[0], M[1], c01);
  cross(M[0], M[2], c02);
  cross(M[1], M[2], c12);
  auto sq = [](const double(&a)[3]) { return a[0] * a[0] + a[1] * a[1] + a[2] * a[2]; };
  const double n01 = sq(c01), n02 = sq(c02), n12 = sq(c12);
  double scale = 0.0;
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i)
    scale = scale + sq(C[i]);
  const double best = std::max(n01, std::max(n02, n12));
  const bool ok = best > 1e-20 * scale * scale;
  const double root = std::sqrt(best);
  double N[3];
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k)
    N[k] = (best == n01 ? c01[k] : (best == n02 ? c02[k] : c12[k])) / root;
  double FN[3];
#pragma GCC unroll 3
  for (int a = 0; a < 3; ++a)
    FN[a] = f[a][0] * N[0] + f[a][1] * N[1] + f[a][2] * N[2];
  const double r[6] = {FN[0] * N[0], FN[1] * N[1], FN[2] * N[2],
                       FN[1] * N[2], FN[0] * N[2], FN[0] * N[1]};
#pragma GCC unroll 6
  for (int k = 0; k < 6; ++k)
    row[k] = r[k] / lambda_max;
  return ok;
}

/// t_k = sqrt(e_ka^2 + e_kb^2), the shear on the plane normal to x_k (D7), without the square
/// root when one of the two shears is 0 (plane strain, plane stress); the root is formed and
/// then not selected, so that a loop over points vectorises.
inline double mode_shear(double ea, double eb) {
  const double root = std::sqrt(ea * ea + eb * eb);
  const double sh_b = ea == 0.0 ? std::abs(eb) : root;
  return eb == 0.0 ? std::abs(ea) : sh_b;
}

/// The pnc mode stretches of D6/D7 of a block-diagonal platelet-frame strain (g23 = g13 = 0;
/// every plane strain or plane stress point with x3 out of plane) in closed form: lambda_max
/// is the larger of 1 + e33 and the largest singular value of the 2x2 block [[1 + e11, g12],
/// [0, 1 + e22]] of F; modes 1 and 2 are min(uncapped, lambda_max) (no branch on the cap), mode
/// 3 is 1 + e33 (a principal stretch of F, never above lambda_max). un[k] and grow[k]: the
/// uncapped stretch of mode k and its d lambda / d t; t = |g12| / 2, the shear of modes 1, 2.
inline void block_stretches(double v0, double v1, double v2, double v5, double& lmax,
                            double (&lam)[3], double (&un)[2], double (&grow)[2], double& t) {
  const double p = 1.0 + v0, q = v5, r = 1.0 + v1;
  const double smax =
      0.5 * (std::sqrt((p + r) * (p + r) + q * q) + std::sqrt((p - r) * (p - r) + q * q));
  lmax = std::max(1.0 + v2, smax);
  t = 0.5 * std::abs(q);
  uncapped_stretch(v0, t, un[0], grow[0]);
  uncapped_stretch(v1, t, un[1], grow[1]);
  lam[0] = std::min(un[0], lmax);
  lam[1] = std::min(un[1], lmax);
  lam[2] = 1.0 + v2;
}

/// The mode stretches of D6/D7 of a platelet-frame strain v exactly as integrate() forms them
/// (compute_stretch() in ndm.cpp: for pnc the capped stretches, lambda_max by the closed-form
/// cubic where a cap binds; for pp the largest principal stretch), without derivatives.
void stretch_values(Model m, const Voigt& v, std::array<double, 3>& lambda);

/// lambda_max of D6 as integrate() forms it where a cap binds: the square root of the largest
/// eigenvalue of C = F^T F (closed-form cubic; one square root for block-diagonal C).
double largest_principal_stretch(const Voigt& v);

} // namespace pnc::damage::detail
