// NDM kernel: see pnc/damage/ndm.hpp and docs/decisions.md (D1-D8).
#include "pnc/damage/ndm.hpp"

#include "ndm_internal.hpp"
#include "pnc/core/error.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <type_traits>

namespace pnc::damage {

using namespace detail; // the kernel pieces shared with the batched route (ndm_internal.hpp)

// ---------------------------------------------------------------- stiffness
namespace {
// the constants' indices (detail::PncIdx, detail::PpIdx) are in ndm_internal.hpp
} // namespace

namespace {
// The one place where the layout of [C0] + [C1(D)] is written (docs/theory.md §1.1,
// in the engineering form of decisions D1-D3); stiffness_c0/c1/c1_dD below are views of it. Without
// C0 (with_c0 false) and a unit D it gives d C1 / d D_m exactly (C1 is linear in D).
void assemble_stiffness(const NdmParameters& p, const std::array<double, 3>& D, Matrix6& C,
                        bool with_c0 = true) {
  const auto& k = p.k;
  auto c0 = [&k, with_c0](int i) { return with_c0 ? k[static_cast<std::size_t>(i)] : 0.0; };
  C.setZero();
  if (p.model == Model::pnc) {
    const double D1 = D[0], D2 = D[1], D3 = D[2];
    C(0, 0) = c0(iC11) + D1 * (2 * k[iA1]);
    C(1, 1) = c0(iC22) + D2 * (2 * k[iA5]);
    C(2, 2) = c0(iC33) + D3 * (2 * k[iA9]);
    C(0, 1) = C(1, 0) = c0(iC12) + (D1 * k[iA10] + D2 * k[iA11]);
    C(0, 2) = C(2, 0) = c0(iC13) + (D1 * k[iA13] + D3 * k[iA15]);
    C(1, 2) = C(2, 1) = c0(iC23) + (D2 * k[iA17] + D3 * k[iA18]);
    C(3, 3) = c0(iC44) + D2 * k[iA22];
    C(4, 4) = c0(iC55) + D3 * k[iA26];
    C(5, 5) = c0(iC66) + D2 * k[iA24];
  } else {
    const double d = D[0];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        C(i, j) = (i == j) ? c0(jC11) + d * (2 * k[jB1]) : c0(jC12) + d * k[jB2];
      C(3 + i, 3 + i) = c0(jC44) + d * k[jB4];
    }
  }
}

} // namespace

Matrix6 stiffness_c0(const NdmParameters& p) {
  Matrix6 C;
  assemble_stiffness(p, {0.0, 0.0, 0.0}, C);
  return C;
}

Matrix6 stiffness_c1(const NdmParameters& p, const std::array<double, 3>& D) {
  Matrix6 C;
  assemble_stiffness(p, D, C);
  return C - stiffness_c0(p);
}

Matrix6 stiffness_c1_dD(const NdmParameters& p, int mode) {
  std::array<double, 3> D{0.0, 0.0, 0.0};
  if (mode < 0 || mode > 2 || (p.model == Model::pp && mode > 0)) return Matrix6::Zero();
  D[static_cast<std::size_t>(mode)] = 1.0;
  Matrix6 C;
  assemble_stiffness(p, D, C, false); // C1 is linear in D: exact, no C0 added and subtracted
  return C;
}

// ---------------------------------------------------------------- damage function
// lambda_c, the damage function and the onset margin live in ndm_internal.hpp (shared with
// the batched route, ndm_batch.cpp, D261).
namespace detail {
const double kLambdaC = std::pow(26.0 / 7.0, 1.0 / 6.0);
// k = 1 / |2 lc^-13 - lc^-7|: makes D(lambda_c) = 0 exactly (decision D4).
const double kDamageScale = 1.0 / std::abs(2 * std::pow(kLambdaC, -13) - std::pow(kLambdaC, -7));
} // namespace detail

double critical_stretch() {
  return kLambdaC;
}

double damage_function(double x) {
  double D, dD;
  damage_and_slope(x, D, dD);
  return D;
}

double damage_function_derivative(double x) {
  double D, dD;
  damage_and_slope(x, D, dD);
  return dD;
}

double damage_of_kappa(const NdmParameters& p, double kappa, double* slope) {
  double D, dD;
  mode_damage(kappa, p.alpha(), onset_margin(p.alpha()), D, dD);
  if (slope) *slope = dD / p.alpha();
  return D;
}

// ---------------------------------------------------------------- kinematics
namespace {
// Unit eigenvector of e for its (simple) largest eigenvalue lam: the longest cross product of
// two rows of e - lam I. Falls back to Eigen's solver when lam is (nearly) repeated
// (then the direction, and the tangent, is not unique anyway).
Eigen::Vector3d largest_eigenvector(const Eigen::Matrix3d& e, double lam) {
  Eigen::Matrix3d M = e;
  M.diagonal().array() -= lam;
  const Eigen::Vector3d r0 = M.row(0), r1 = M.row(1), r2 = M.row(2);
  const Eigen::Vector3d c01 = r0.cross(r1), c02 = r0.cross(r2), c12 = r1.cross(r2);
  const double n01 = c01.squaredNorm(), n02 = c02.squaredNorm(), n12 = c12.squaredNorm();
  const double scale = e.squaredNorm();
  const double best = std::max(n01, std::max(n02, n12));
  if (!(best > 1e-20 * scale * scale)) { // (nearly) repeated largest eigenvalue
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(e, Eigen::ComputeEigenvectors);
    return es.eigenvectors().col(2);
  }
  const Eigen::Vector3d& c = best == n01 ? c01 : (best == n02 ? c02 : c12);
  return c / std::sqrt(best);
}

} // namespace

namespace {
// Mode stretches of decisions D6/D7 without derivatives; stretch_row() adds the derivative of
// one mode on demand (integrate() needs it only for loading modes).
// The tensorial small strain e of an engineering-Voigt strain v.
inline Eigen::Matrix3d tensor(const Voigt& v) {
  Eigen::Matrix3d e;
  e << v[0], 0.5 * v[5], 0.5 * v[4], //
      0.5 * v[5], v[1], 0.5 * v[3],  //
      0.5 * v[4], 0.5 * v[3], v[2];
  return e;
}

struct Stretch {
  Voigt v;                 // the strain, platelet frame (engineering Voigt); tensor(v) = e
  double lambda_max = 1.0; // largest principal stretch of F(v) (if have_lambda_max), D6
  bool have_lambda_max = false;
  std::array<double, 3> lambda{1.0, 1.0, 1.0};
  std::array<double, 3> shear{0.0, 0.0, 0.0};      // t_k = sqrt(sum_{j != k} e_kj^2)
  std::array<double, 3> dshear{1.0, 1.0, 1.0};     // d lambda_k / d t_k = 1 + t_k / r_k
  std::array<bool, 3> clipped{true, false, false}; // lambda_k = lambda_max (the cap binds)
};

// Decision D6: a small strain is read as the upper-triangular (LAMMPS triclinic cell)
// deformation gradient with the same small strain, F = I + diag(e) + g12 e1(x)e2 +
// g13 e1(x)e3 + g23 e2(x)e3, exact for every deformation case of the RVE.
inline Eigen::Matrix3d deformation_gradient(const Voigt& v) {
  Eigen::Matrix3d F;
  F << 1.0 + v[0], v[5], v[4], //
      0.0, 1.0 + v[1], v[3],   //
      0.0, 0.0, 1.0 + v[2];
  return F;
}
inline Eigen::Matrix3d right_cauchy_green(const Voigt& v) {
  double c[6];
  cauchy_green(v, c); // (the batched route's expression, D402)
  Eigen::Matrix3d C;
  C << c[0], c[3], c[4], //
      c[3], c[1], c[5],  //
      c[4], c[5], c[2];
  return C;
}
// Largest principal stretch of F(v): sqrt of the largest eigenvalue of C = F^T F (closed form:
// the trigonometric solution of the characteristic cubic, its cosine by a Newton iteration
// (D409), one square root for a block-diagonal C; ndm_internal.hpp, D402).
inline double largest_stretch(const Voigt& v) {
  double c[6];
  cauchy_green(v, c);
  return std::sqrt(largest_eigenvalue(c));
}

// The general (not block-diagonal) pnc stretches of D7, the caps by Sylvester's criterion on
// lambda^2 I - C.
void general_stretch(Stretch& s) {
  const Eigen::Matrix3d e = tensor(s.v);
  double C[6];
  cauchy_green(s.v, C);
  auto need_lambda_max = [&s, &C]() {
    if (!s.have_lambda_max) {
      s.lambda_max = std::sqrt(largest_eigenvalue(C));
      s.have_lambda_max = true;
    }
    return s.lambda_max;
  };
#pragma GCC unroll 3
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    s.shear[k] = mode_shear(e(k, a), e(k, b));
    double uncapped;
    uncapped_stretch(e(k, k), s.shear[k], uncapped, s.dshear[k]);
    // The cap binds when the uncapped stretch exceeds lambda_max (ties at rounding level
    // either way give the same stretch); mu I - C positive definite, without lambda_max.
    s.clipped[k] = uncapped > 0.0 && exceeds_largest_eigenvalue(C, uncapped * uncapped);
    s.lambda[k] = s.clipped[k] ? need_lambda_max() : uncapped;
  }
}

// Mode stretches of a strain v (platelet frame). The block-diagonal case, which is every point
// of a 2-D run, is inlined into integrate().
[[gnu::always_inline]] inline Stretch compute_stretch(Model m, const Voigt& v) {
  Stretch s;
  s.v = v;
  if (m == Model::pp) {
    s.lambda_max = largest_stretch(v);
    s.have_lambda_max = true;
    s.lambda[0] = s.lambda_max; // pp: the maximum principal stretch
    return s;
  }
  if (v[3] == 0.0 && v[4] == 0.0) {
    // Block-diagonal strain (every plane strain or plane stress point with x3 out of plane):
    // the closed form shared with the batched route (D351).
    double lam[3], un[2], grow[2], t;
    block_stretches(v[0], v[1], v[2], v[5], s.lambda_max, lam, un, grow, t);
    s.have_lambda_max = true;
    s.shear = {t, t, 0.0};
    for (int k = 0; k < 2; ++k) {
      s.dshear[k] = grow[k];
      s.clipped[k] = un[k] > s.lambda_max;
    }
    s.clipped[2] = false;
    s.lambda = {lam[0], lam[1], lam[2]};
    return s;
  }
  general_stretch(s);
  return s;
}

// d lambda_mode / d eps (engineering Voigt). N caches the principal direction of C for
// lambda_max.
Eigen::Matrix<double, 1, 6> stretch_row(const Stretch& s, int mode, Eigen::Vector3d& N,
                                        bool& have_N) {
  Eigen::Matrix<double, 1, 6> row = Eigen::Matrix<double, 1, 6>::Zero();
  if (s.clipped[mode]) {
    double r[6]; // D399: one expression for the kernel and the batched route
    if (capped_stretch_row(s.v, s.lambda_max, r)) {
      row << r[0], r[1], r[2], r[3], r[4], r[5];
      return row;
    }
    // lambda_max (nearly) repeated: Eigen's solver for the direction
    if (!have_N) { // clipped: lambda_max known
      N = largest_eigenvector(right_cauchy_green(s.v), s.lambda_max * s.lambda_max);
      have_N = true;
    }
    // d lambda / d v_I = (F N)_a N_b / lambda for the entry (a, b) of F that v_I sets
    const Eigen::Vector3d FN = deformation_gradient(s.v) * N;
    row << FN[0] * N[0], FN[1] * N[1], FN[2] * N[2], FN[1] * N[2], FN[0] * N[2], FN[0] * N[1];
    return row / s.lambda_max;
  }
  // Voigt index of the shear pair (k, j): (1,2)->3, (0,2)->4, (0,1)->5.
  static const int pair_index[3][3] = {{-1, 5, 4}, {5, -1, 3}, {4, 3, -1}};
  const int a = (mode + 1) % 3, b = (mode + 2) % 3;
  row[mode] = 1.0;
  if (s.shear[mode] > 0) { // d t / d gamma = e_ka / (2 t), e_ka = gamma / 2
    const int ia = pair_index[mode][a], ib = pair_index[mode][b];
    const double f = s.dshear[mode] * 0.5 / (2 * s.shear[mode]);
    row[ia] = f * s.v[ia];
    row[ib] = f * s.v[ib];
  }
  return row;
}
} // namespace

void detail::stretch_values(Model m, const Voigt& v, std::array<double, 3>& lambda) {
  lambda = compute_stretch(m, v).lambda;
}

double detail::largest_principal_stretch(const Voigt& v) {
  return largest_stretch(v);
}

ModeStretch mode_stretches(Model m, const Voigt& v, bool with_derivative) {
  const Stretch s = compute_stretch(m, v);
  ModeStretch out;
  out.lambda = s.lambda;
  out.lambda_max = s.have_lambda_max ? s.lambda_max : largest_stretch(s.v);
  if (with_derivative) {
    Eigen::Vector3d N;
    bool have_N = false;
    for (int k = 0; k < (m == Model::pnc ? 3 : 1); ++k)
      out.dlambda.row(k) = stretch_row(s, k, N, have_N);
  }
  return out;
}

Matrix6 strain_rotation(const Eigen::Matrix3d& R) {
  // Closed form of el = R e R^T for each unit engineering strain J (pair (a, b) of J;
  // a = b for a normal strain): el(i, j) = (R(i,a) R(j,b) + R(i,b) R(j,a)) / 2, doubled on
  // the engineering shear rows. Bitwise equal to the triple product it replaces.
  static const int pa[6] = {0, 1, 2, 1, 0, 0}, pb[6] = {0, 1, 2, 2, 2, 1};
  Matrix6 T;
  for (int J = 0; J < 6; ++J) {
    const int a = pa[J], b = pb[J];
    for (int I = 0; I < 6; ++I) {
      const int i = pa[I], j = pb[I];
      const double v = 0.5 * (R(i, a) * R(j, b) + R(i, b) * R(j, a));
      T(I, J) = I < 3 ? v : 2 * v;
    }
  }
  return T;
}

void ErrorBuffer::set(const char* text) {
  std::strncpy(msg, text, sizeof msg - 1);
  msg[sizeof msg - 1] = '\0';
}

// ---------------------------------------------------------------- integration
namespace {

// dC1/dD_m * e, using the sparsity of dC1/dD_m.
Voigt c1_times(const NdmParameters& p, int m, const Voigt& e) {
  const auto& k = p.k;
  Voigt v;
  if (p.model == Model::pnc) {
    pnc_c1_times(k, m, e, v); // shared with the batched route (D399)
  } else {
    pp_c1_times(k, e, v); // shared with the batched route (D419)
  }
  return v;
}
} // namespace

namespace {

// T^T C T is symmetric; the rounding of the two products is not, so symmetrise: the
// row-major tangent route relies on C0g + sum D_m dC1g_m being exactly symmetric.
void rotate_symmetric(const Matrix6& T, Matrix6& C) {
  const Matrix6 G = T.transpose() * C * T;
  C = 0.5 * (G + G.transpose());
}

// prepare() without the damage pieces dC1g: T and C0g only.
PreparedNdm prepare_base(const NdmParameters& p) {
  PreparedNdm q;
  q.p = p;
  q.rotated = !p.R.isIdentity(0.0);
  q.C0g = stiffness_c0(p);
  if (q.rotated) { // otherwise the platelet frame is the global frame: no products
    q.T = strain_rotation(p.R);
    rotate_symmetric(q.T, q.C0g);
  }
  return q;
}

// The damage piece dC1g_m of prepared parameters, as prepare() forms it.
Matrix6 damage_piece(const PreparedNdm& q, int m) {
  Matrix6 M = stiffness_c1_dD(q.p, m);
  if (q.rotated) rotate_symmetric(q.T, M);
  return M;
}

} // namespace

Voigt local_strain(const PreparedNdm& q, const Voigt& eps) {
  return q.rotated ? times(q.T, eps) : eps; // D351: the one platelet-frame strain
}

PreparedNdm prepare(const NdmParameters& p) {
  PreparedNdm q = prepare_base(p);
  for (int m = 0; m < 3; ++m)
    q.dC1g[static_cast<std::size_t>(m)] = damage_piece(q, m);
  return q;
}

namespace {

// The one integration routine of the kernel (decision D210): every integrate() overload and
// so every entry point (fit, plugin C ABI v1 and v2, UMAT, GIMP, deal.II) runs it. The
// global-frame stiffness is C0g + sum_m D_m dC1g_m (prepare()); the damage-growth term of the
// consistent tangent is rotated as two vectors, T^T a (g T).
//
// K may be a Map over a row-major array viewed column-major, i.e. K^T (KMatrix is then a
// Map): the symmetric part is copied as it is (Cg is exactly symmetric, prepare()) while the
// damage-growth outer product a g is added as g^T a^T.
// VIn / VOut are Voigt or Maps over the caller's arrays (the C ABI route copies nothing).
//
// have_pieces false: q came from prepare_base() (integrate(p, ...), one call per parameter
// set), and the damage pieces dC1g_m are formed here, by the function prepare() uses, only for
// the modes that are damaged: the same numbers without the cost of the undamaged ones.
template <class KMatrix, class VIn, class VOut>
Status integrate_impl(const PreparedNdm& q, bool have_pieces, const NdmState& s0, NdmState& s1,
                      const VIn& eps0, const VIn& deps, VOut& sigma, KMatrix* K, TangentKind kind,
                      NdmEnergy* energy, ErrorBuffer& err) {
  constexpr bool K_transposed = !std::is_same_v<KMatrix, Matrix6>;
  const NdmParameters& p = q.p;
  const Voigt eps = eps0 + deps;
  if (!eps.allFinite()) {
    err.set("ndm: strain is not finite");
    return Status::bad_input;
  }
  if (kind == TangentKind::none) K = nullptr;
  const bool rotated = q.rotated;
  // A plane strain in the global x1-x2 plane (e33 = g23 = g13 = 0, every point of a 2-D run)
  // needs only columns 1, 2 and 6 of T and of the stiffness (detail::times, D351).
  const Voigt el = local_strain(q, eps);
  // mode stretches (decisions D6/D7), derivatives only where the tangent needs them
  const bool pnc = p.model == Model::pnc;
  const int n = pnc ? 3 : 1;
  const Stretch st = compute_stretch(p.model, el);
  const auto& lambda = st.lambda;
  const double alpha =
      p.k[pnc ? static_cast<std::size_t>(iAlphaPnc) : static_cast<std::size_t>(jAlphaPp)];
  NdmState out = s0;
  std::array<double, 3> dD{0, 0, 0};
  std::array<bool, 3> loading{false, false, false};
  const double no_damage_below = onset_margin(alpha);
  bool below_onset = true; // every mode: D = dD = 0
  for (int m = 0; m < n; ++m) {
    loading[m] = lambda[m] > s0.kappa[m];
    out.kappa[m] = loading[m] ? lambda[m] : s0.kappa[m];
    below_onset = mode_damage(out.kappa[m], alpha, no_damage_below, out.D[m], dD[m]) && below_onset;
  }
  if (below_onset) {
    // Every mode below the damage onset (D = dD = 0, and so D0 = 0: kappa never decreases):
    // C0g is the stress matrix and every tangent, exactly what the general branch would form.
    sigma = times(q.C0g, eps);
    if (K) *K = q.C0g;
    if (energy) *energy = NdmEnergy{0.5 * sigma.dot(eps), 0.0};
    s1 = out;
    return Status::ok;
  }
  Matrix6 Cd; // C0g + sum D_m dC1g_m, formed only when some D_m > 0
  const Matrix6* Cg = &q.C0g;
  for (int m = 0; m < n; ++m) {
    if (out.D[m] == 0.0) continue;
    if (Cg != &Cd) Cd = q.C0g;
    Cg = &Cd;
    if (have_pieces)
      Cd.noalias() += out.D[m] * q.dC1g[static_cast<std::size_t>(m)];
    else
      Cd.noalias() += out.D[m] * damage_piece(q, m);
  }
  sigma = times(*Cg, eps);
  if (K) *K = kind == TangentKind::elastic ? q.C0g : *Cg;
  if (K && kind == TangentKind::consistent) {
    bool have_N = false;
    Eigen::Vector3d N = Eigen::Vector3d::Zero();
    for (int m = 0; m < n; ++m) {
      if (!loading[m] || dD[m] == 0.0) continue;
      const Eigen::Matrix<double, 1, 6> row = stretch_row(st, m, N, have_N);
      const double f = dD[m] / alpha;
      // T^T a and g T by detail::transpose_times, as the batched route forms them (D399)
      const Voigt a = rotated ? transpose_times(q.T, c1_times(p, m, el)) : c1_times(p, m, el);
      const Eigen::Matrix<double, 1, 6> g =
          rotated
              ? Eigen::Matrix<double, 1, 6>(f * transpose_times(q.T, row.transpose()).transpose())
              : Eigen::Matrix<double, 1, 6>(f * row);
      if constexpr (K_transposed)
        K->noalias() += g.transpose() * a.transpose();
      else
        K->noalias() += a * g;
    }
  }
  if (energy) {
    // psi(eps1, D0) - psi(eps1, D1) = -1/2 sum_m (D1_m - D0_m) el . dC1_m el (decision D212);
    // eps . dC1g_m eps = el . dC1_m el in the platelet frame.
    double released = 0.0;
    for (int m = 0; m < n; ++m) {
      double D0, dD0;
      mode_damage(s0.kappa[m], alpha, no_damage_below, D0, dD0);
      if (out.D[m] != D0) released -= 0.5 * (out.D[m] - D0) * el.dot(c1_times(p, m, el));
    }
    *energy = NdmEnergy{0.5 * sigma.dot(eps), released};
  }
  s1 = out;
  return Status::ok;
}

} // namespace

Status integrate(const NdmParameters& p, const NdmState& s0, NdmState& s1, const Voigt& eps0,
                 const Voigt& deps, Voigt& sigma, Matrix6* K, ErrorBuffer& err) {
  return integrate_impl(prepare_base(p), false, s0, s1, eps0, deps, sigma, K,
                        TangentKind::consistent, nullptr, err);
}

Status integrate(const PreparedNdm& q, const NdmState& s0, NdmState& s1, const Voigt& eps0,
                 const Voigt& deps, Voigt& sigma, Matrix6* K, ErrorBuffer& err, TangentKind kind,
                 NdmEnergy* energy) {
  return integrate_impl(q, true, s0, s1, eps0, deps, sigma, K, kind, energy, err);
}

Status integrate_row_major(const PreparedNdm& q, const NdmState& s0, NdmState& s1,
                           const double* eps0, const double* deps, double* sigma,
                           double* K_row_major, ErrorBuffer& err, TangentKind kind,
                           NdmEnergy* energy) {
  const Eigen::Map<const Voigt> e0(eps0), de(deps);
  Eigen::Map<Voigt> sig(sigma);
  // A column-major view of the row-major array is K^T.
  Eigen::Map<Matrix6> Kt(K_row_major);
  return integrate_impl(q, true, s0, s1, e0, de, sig, K_row_major ? &Kt : nullptr, kind, energy,
                        err);
}

Eigen::Matrix<double, Eigen::Dynamic, 6>
stress_path(const NdmParameters& p, const Eigen::Matrix<double, Eigen::Dynamic, 6>& strain,
            std::vector<NdmState>* states) {
  Eigen::Matrix<double, Eigen::Dynamic, 6> out(strain.rows(), 6);
  const PreparedNdm q = prepare(p);
  NdmState s0, s1;
  Voigt prev = Voigt::Zero(), sig;
  ErrorBuffer err;
  if (states) states->resize(static_cast<std::size_t>(strain.rows()));
  for (Eigen::Index i = 0; i < strain.rows(); ++i) {
    const Voigt e = strain.row(i).transpose();
    if (integrate(q, s0, s1, prev, e - prev, sig, nullptr, err) != Status::ok)
      fail("<strain path>", "row " + std::to_string(i), "", err.msg);
    out.row(i) = sig.transpose();
    if (states) (*states)[static_cast<std::size_t>(i)] = s1;
    s0 = s1;
    prev = e;
  }
  return out;
}

} // namespace pnc::damage
