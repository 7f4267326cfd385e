#pragma once
// pnc/damage/ndm.hpp: the nano-scale damage model (NDM) of Nair (2010) (docs/theory.md
// §1), as one pure integration function in the spirit of the MGIS behaviour
// interface. Every caller (the Ceres fit, the fe_material plugin, the GIMP solver, the
// deal.II demo, the UMAT shim) goes through integrate(); there are no globals and no
// "current point" members.
//
// Units: the kernel is unit-agnostic. Stresses come out in the units of the stiffness
// constants (the material card stores Pa; the fit works in MPa). Strains are dimensionless.
//
// Conventions (docs/decisions.md, entries D1-D8):
//  * Voigt order 1..6 = 11, 22, 33, 23, 13, 12; strain with ENGINEERING shear
//    (gamma_23 = 2 eps_23 ...), stress plain. {sigma} = ([C0] + [C1(D)]) {eps}  (docs/theory.md
//    §1.1).
//  * C0 holds the physical orthotropic stiffnesses C0_ij in that engineering form
//    (C0_44 = mu_23 ...). The source's c1..c9 constants convert as in decision D1.
//  * C1 (docs/theory.md §1.1) in engineering form: normal block as printed, shear diagonal
//    C1_44 = A22 D2, C1_55 = A26 D3, C1_66 = A24 D2 (the printed 2 A D acts on the
//    tensorial shear strain, see D2). The pure polymer uses the isotropic reading (D3).
//  * Damage D(lambda) = 1 + k (2 x^-13 - x^-7) for x = lambda/alpha > lambda_c, else 0, with
//    k = 1/|2 lc^-13 - lc^-7| = 10.0142 (printed 10.015) so that D(lambda_c) = 0 (D4, D5).
//  * Mode stretches in the platelet frame (D7) from the deformation gradient that the small
//    strain describes as an upper-triangular (LAMMPS triclinic cell) deformation,
//    F = I + diag(e) + g12 e1(x)e2 + g13 e1(x)e3 + g23 e2(x)e3 (D6): exact for extension and
//    for finite simple shear (principal stretch gamma/2 + sqrt(1 + gamma^2/4)).
//  * Damage is irreversible: kappa_k = max over history of lambda_k (D8).
#include <Eigen/Dense>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace pnc::damage {

using Voigt = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// Which law: the nanocomposite (three damage modes, A constants) or the pure polymer
/// (one damage variable, B constants).
enum class Model { pnc, pp };
const char* model_name(Model m);
/// Parses "pnc" or "pp"; throws pnc::InputError otherwise.
Model parse_model(const std::string& name, const std::string& source = "<model>");

/// Named constants of each model, in the order used by NdmParameters::k.
/// pnc: C11 C22 C33 C12 C13 C23 C44 C55 C66  A1 A5 A9 A10 A11 A13 A15 A17 A18 A22 A24 A26 alpha
/// pp : C11 C12 C44  B1 B2 B4 alpha   (isotropic reading: C22=C33=C11, C13=C23=C12,
///                                     C55=C66=C44; see decisions.md D3)
/// Stiffness-like constants are in stress units; alpha is dimensionless.
const std::vector<std::string>& constant_names(Model m);
/// Index of a constant by name, or -1.
int constant_index(Model m, const std::string& name);
/// SI unit of a constant in cards and files: "1" for alpha, "Pa" for every other one.
std::string constant_unit(const std::string& name);

constexpr int kMaxConstants = 22;

struct NdmParameters {
  Model model = Model::pnc;
  std::array<double, kMaxConstants> k{}; ///< constants in the order of constant_names()
  /// Rotation from the global (loading) frame to the platelet frame: x_local = R x_global
  /// (docs/theory.md §1.1 and §1.3, D7). Identity when the platelet lies along the global x1.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();

  double& operator[](const std::string& name);
  double operator[](const std::string& name) const;
  std::size_t size() const { return constant_names(model).size(); }
  double alpha() const { return k[size() - 1]; }
};

/// The undamaged stiffness [C0] (engineering Voigt) in the platelet frame.
Matrix6 stiffness_c0(const NdmParameters& p);
/// The damage part [C1(D)] in the platelet frame; D = {D1, D2, D3} (pp: D[0] only).
Matrix6 stiffness_c1(const NdmParameters& p, const std::array<double, 3>& D);
/// d[C1]/dD_k (constant matrices since C1 is linear in D).
Matrix6 stiffness_c1_dD(const NdmParameters& p, int k);

/// Orthotropic [C0] from the source's c1..c9 constants (decision D1: C11 = 2c1, C12 = c4,
/// C44 = c7 in engineering form).
Matrix6 c0_from_c_constants(const std::array<double, 9>& c);
/// Orthotropic [C0] from engineering constants (the orthotropic compliance inverse, D1b). Poisson
/// ratios nu_ij are "strain in j per strain in i" with nu_ji = nu_ij E_j / E_i.
Matrix6 c0_from_engineering(double E1, double E2, double E3, double nu12, double nu13, double nu23,
                            double mu12, double mu13, double mu23);

/// Damage function D(x) of docs/theory.md §1.2 for a (scaled) stretch x; D = 0 for x <= lambda_c.
double damage_function(double x);
/// dD/dx.
double damage_function_derivative(double x);
/// lambda_c = (26/7)^(1/6) = 1.24446 (docs/theory.md §1.2).
double critical_stretch();

/// The internal state: kappa_k = largest mode stretch reached so far (1 = virgin), and the
/// damage variables derived from it (stored for output). pp uses index 0 only.
struct NdmState {
  std::array<double, 3> kappa{1.0, 1.0, 1.0};
  std::array<double, 3> D{0.0, 0.0, 0.0};
};
/// Names of the state variables, in the flat order kappa1..3, D1..3 (pp: kappa, D).
const std::vector<std::string>& state_names(Model m);
std::size_t state_size(Model m);
/// Flat layout kappa1..n, D1..n (n = 3 for pnc, 1 for pp). Inline and with fixed sizes per
/// model: the plugin converts at every call.
inline void state_to_array(Model m, const NdmState& s, double* out) {
  if (m == Model::pnc) {
    for (std::size_t i = 0; i < 3; ++i) {
      out[i] = s.kappa[i];
      out[3 + i] = s.D[i];
    }
  } else {
    out[0] = s.kappa[0];
    out[1] = s.D[0];
  }
}
inline NdmState state_from_array(Model m, const double* in) {
  NdmState s;
  if (m == Model::pnc) {
    for (std::size_t i = 0; i < 3; ++i) {
      s.kappa[i] = in[i];
      s.D[i] = in[3 + i];
    }
  } else {
    s.kappa[0] = in[0];
    s.D[0] = in[1];
  }
  return s;
}

/// Mode stretches lambda_k of a small strain (engineering Voigt, platelet frame) and their
/// derivatives d lambda_k / d eps (rows), following decisions D6/D7, with e the tensorial
/// strain and t_k = sqrt(sum_{j != k} e_kj^2) the shear on the plane normal to x_k:
///   pnc: lambda_k = min( lambda_max, e_kk + t_k + sqrt(1 + t_k^2) ), n_k = e_k
///   pp : lambda_1 = lambda_max
/// lambda_max = largest principal stretch of F = I + diag(e) + g12 e1(x)e2 + g13 e1(x)e3 +
/// g23 e2(x)e3 (square root of the largest eigenvalue of F^T F). Both are exact for
/// laterally constrained extension (1 + e) and for simple shear (gamma/2 + sqrt(1 +
/// gamma^2/4)); dimensionless.
struct ModeStretch {
  std::array<double, 3> lambda{1.0, 1.0, 1.0};
  Eigen::Matrix<double, 3, 6> dlambda = Eigen::Matrix<double, 3, 6>::Zero();
  double lambda_max = 1.0; ///< largest principal stretch of F (see above)
};
ModeStretch mode_stretches(Model m, const Voigt& eps_local, bool with_derivative);

/// Voigt transformation of engineering strain from the global to the platelet frame:
/// eps_local = T(R) eps_global. Stress transforms as sigma_global = T^T sigma_local.
Matrix6 strain_rotation(const Eigen::Matrix3d& R);

enum class Status { ok = 0, bad_input = 1 };

/// A fixed error buffer (no allocation on the hot path), as in MGIS. Only the first byte is
/// cleared on construction (the kernel runs once per integration point).
struct ErrorBuffer {
  char msg[256];
  ErrorBuffer() { msg[0] = '\0'; }
  void set(const char* text);
};

/// Which tangent an integration returns (the plugin's tangent_request, decision D211).
///  none       : no tangent (K is not written even when given)
///  elastic    : the undamaged stiffness C0 in the global frame, T^T C0 T
///  secant     : the secant stiffness of the end state, T^T (C0 + C1(D1)) T, so that
///               sigma = K eps exactly (no damage-growth term)
///  consistent : d sigma / d eps of the increment: the secant plus the damage-growth term of
///               every loading mode (in general not symmetric)
enum class TangentKind { none = 0, elastic = 1, secant = 2, consistent = 3 };

/// Energy densities of an increment, in the units of the constants times strain^2 (J/m^3 for
/// a card in Pa); decision D212. The NDM is a secant law, sigma = S(D) eps with
/// S(D) = T^T (C0 + C1(D)) T, so
///  stored     = psi(eps1, D1) = 1/2 eps1 . S(D1) eps1 = 1/2 sigma1 . eps1 (a state value at
///               the end of the increment, not an increment);
///  dissipated = psi(eps1, D0) - psi(eps1, D1) = -1/2 sum_m (D1_m - D0_m) eps1 . dS/dD_m eps1,
///               the energy released by this increment's damage growth at the end strain
///               (D0 = D(kappa0) as the kernel computes it from the start state). Then
///               stored1 - stored0 + dissipated = 1/2 (eps1 - eps0) . S(D0) (eps1 + eps0)
///               exactly: the work of the frozen-damage stress over the increment.
struct NdmEnergy {
  double stored = 0.0;
  double dissipated = 0.0;
};

/// Integrate the NDM over one strain increment (MGIS-style).
///  p     : parameters (constants and platelet rotation)
///  s0    : state at the start of the increment (read only)
///  s1    : state at the end (written)
///  eps0  : total strain at the start, deps its increment (global frame, engineering Voigt)
///  sigma : Cauchy stress at the end (global frame, Voigt, units of the constants)
///  K     : if not null, the consistent tangent d sigma / d eps at the end (global frame);
///          includes the damage-growth term when a mode is loading.
/// Returns Status::ok, or Status::bad_input (non-finite strain or parameter) with a message
/// in err; s1 and sigma are then untouched.
/// The one routine of the prepared overload below (D210), prepared for this call only (damage
/// pieces of damaged modes alone): the same numbers as integrate(prepare(p), ...).
Status integrate(const NdmParameters& p, const NdmState& s0, NdmState& s1, const Voigt& eps0,
                 const Voigt& deps, Voigt& sigma, Matrix6* K, ErrorBuffer& err);

/// Parameters with what integrate() would otherwise recompute at every call done once: the
/// strain rotation T(R) (identity for an aligned platelet) and the global-frame stiffness
/// pieces C0g = T^T C0 T and dC1g_m = T^T (d C1 / d D_m) T (C1 is linear in D; both stored
/// exactly symmetric, as they are mathematically; without rotation they are C0 and dC1/dD_m
/// as assembled, with no product). Build it with prepare() when the parameters are fixed for
/// many calls (the material plugin does). It is the only integration route: the
/// NdmParameters overload prepares and calls it (decision D210).
/// A plain value: copy it, share it read-only between threads; rebuild it if p changes.
struct PreparedNdm {
  NdmParameters p;
  bool rotated = false; ///< R is not the identity
  Matrix6 T = Matrix6::Identity();
  Matrix6 C0g = Matrix6::Zero();
  std::array<Matrix6, 3> dC1g{};
};
PreparedNdm prepare(const NdmParameters& p);
/// The platelet-frame strain el = T(R) eps of a global-frame strain eps (both engineering
/// Voigt, dimensionless), as every route forms it (integrate(), integrate_batch() and the
/// plugin's mode-stretch query, so that they agree bit for bit; decision D351): eps itself for
/// an aligned platelet; for a plane strain (e33 = g23 = g13 = 0) columns 1, 2 and 6 of T only,
/// else the full product, each row summed in column order.
Voigt local_strain(const PreparedNdm& q, const Voigt& eps);
/// integrate() with prepared parameters (same contract as above); `kind` chooses the tangent
/// written into K (ignored when K is null) and `energy`, when not null, receives the energy
/// densities of the increment.
Status integrate(const PreparedNdm& q, const NdmState& s0, NdmState& s1, const Voigt& eps0,
                 const Voigt& deps, Voigt& sigma, Matrix6* K, ErrorBuffer& err,
                 TangentKind kind = TangentKind::consistent, NdmEnergy* energy = nullptr);
/// The same over plain arrays, the layout of the C plugin ABI, without intermediate copies:
/// eps0[6], deps[6] and sigma[6] in Voigt order, the tangent written row-major into
/// K_row_major[0..35] (not computed when null). Equal to the Matrix6 overload entry by entry.
Status integrate_row_major(const PreparedNdm& q, const NdmState& s0, NdmState& s1,
                           const double* eps0, const double* deps, double* sigma,
                           double* K_row_major, ErrorBuffer& err,
                           TangentKind kind = TangentKind::consistent, NdmEnergy* energy = nullptr);

/// A batch of points in structure-of-arrays layout, the view behind the plugin's
/// pnc_material_integrate_batch (decisions D260, D261). Every array is a block of components,
/// component k of point i at [k * ld + i] (ld >= n): eps0, deps and sigma 6 x ld (Voigt order,
/// engineering shear strain; stress in the units of the constants), state0 and state1
/// state_size(model) x ld in the flat order of state_to_array(), K 36 x ld with entry (r, c) of
/// the row-major tangent d sigma_r / d eps_c at [(6 r + c) ld + i]. stored, dissipated
/// (energy densities, NdmEnergy) and status hold n entries. Optional outputs are null.
/// state1 may be state0 (the same block); no other arrays may overlap.
struct NdmBatch {
  std::size_t n = 0;
  std::size_t ld = 0;
  const double* eps0 = nullptr;
  const double* deps = nullptr;
  const double* state0 = nullptr;
  double* state1 = nullptr;
  double* sigma = nullptr;
  double* K = nullptr; ///< required unless kind is none
  double* stored = nullptr;
  double* dissipated = nullptr;
  int* status = nullptr; ///< per point: Status::ok (0) or Status::bad_input (1)
  TangentKind kind = TangentKind::none;
};

/// What one integrate_batch() call did: points per path (D261) and the first failure.
struct NdmBatchStats {
  std::size_t elastic = 0;   ///< every mode below the damage onset: sigma = C0g eps
  std::size_t unloading = 0; ///< damaged, no damage growth: sigma = (C0g + sum D dC1g) eps
  /// damage growth of a pnc point: the kernel's expressions in loops over the points (D399,
  /// D403)
  std::size_t growth = 0;
  /// through integrate_row_major(): pp's damage growth, and a pnc point whose capped mode grows
  /// at a repeated lambda_max when the consistent tangent is asked for
  std::size_t kernel = 0;
  std::size_t failed = 0;       ///< non-finite input or result: nothing of the point written
  std::size_t first_failed = 0; ///< index of the first failed point (n when none failed)
};

/// Integrates every point of b with prepared parameters: for each point the same numbers, bit
/// for bit, as integrate_row_major() with the same kind (energies: see D261), and the same
/// points fail (a non-finite strain, state or result). A failed point gets status bad_input
/// and nothing else written; the others are computed. No allocation; the points are taken in
/// chunks, grouped by path: elastic, unloading and (pnc) damage-growth points in loops over the
/// chunk that the compiler vectorises, the rest (pp's damage growth, a capped mode growing at a
/// repeated lambda_max) one by one through the kernel's routine.
NdmBatchStats integrate_batch(const PreparedNdm& q, const NdmBatch& b);

/// The instruction set of integrate_batch()'s loops over points (decisions D386, D413). The batch
/// is compiled three times from one source: for the project's baseline (SSE2) and, on x86-64 with
/// GCC or Clang, for AVX2 (4 doubles a vector) and AVX-512 (8 doubles a vector), never with
/// FMA; `automatic` takes the widest the CPU has. All give the same numbers bit for bit; forcing
/// one is for tests and benchmarks (and for a CPU whose clock drops on 512-bit vectors; the
/// environment variable PNC_SIMD caps the choice for a whole process, D415).
enum class BatchIsa { automatic, baseline, avx2, avx512 };
/// Whether integrate_batch(q, b, isa) can run `isa` on this CPU and build, under PNC_SIMD.
bool batch_isa_available(BatchIsa isa);
/// integrate_batch() on a chosen instruction set; throws std::invalid_argument (naming the
/// instruction set) when !batch_isa_available(isa) (the CPU or build lacks it, or PNC_SIMD caps
/// it).
NdmBatchStats integrate_batch(const PreparedNdm& q, const NdmBatch& b, BatchIsa isa);

/// Damage of one mode at the largest stretch kappa, as integrate() computes it: 0 up to the
/// onset kappa = alpha lambda_c, D(kappa / alpha) beyond; `slope` (if not null) receives
/// dD/dkappa (1/stretch). Dimensionless.
double damage_of_kappa(const NdmParameters& p, double kappa, double* slope = nullptr);

/// Drive the kernel along a strain path from a virgin state; returns stresses (rows) and,
/// if states is not null, the state after each point. Used by the fit, the synthetic data
/// generator and the tests: one code path for all.
Eigen::Matrix<double, Eigen::Dynamic, 6>
stress_path(const NdmParameters& p, const Eigen::Matrix<double, Eigen::Dynamic, 6>& strain,
            std::vector<NdmState>* states = nullptr);

/// Checks the parameters a user supplied: finite values, alpha > 0, C0 symmetric positive
/// definite, R orthogonal. Throws pnc::InputError naming `source` and the constant.
void validate(const NdmParameters& p, const std::string& source);

} // namespace pnc::damage
