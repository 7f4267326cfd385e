#pragma once
// pnc/gimp_coupler/materials.hpp: constitutive laws of the GIMP solver, one interface.
//
// Units: SI throughout. Stress and moduli in Pa, density in kg/m^3, energy density in J/m^3
// of reference volume, wave speed in m/s. Deformation gradients are 3x3; a plane-strain
// (2-D) solver passes F with F(2,2) = 1 and F(0,2) = F(1,2) = F(2,0) = F(2,1) = 0, and the
// law returns the full 3x3 Cauchy stress (sigma_33 is kept for output).
//
// Per-particle state lives in the solver's arrays (n_state() doubles per particle); a law
// reads the state at the start of the step (s0) and writes the new one (s1); the two never
// alias. update() is const and thread-safe.
//
// Laws (docs/gimp.md, docs/decisions.md D30-):
//  - LinearElastic: St Venant-Kirchhoff, S = lambda tr(E) I + 2 mu E, E = (C - I)/2,
//    sigma = J^-1 F S F^T. Objective; reduces to Hooke's law (E, nu) for small strain.
//  - HyperelasticPolymer: the compressible law of docs/theory.md §5.3 read as
//    W = c1 (I3 - 1)^2 + c2 (I1 I3^(-1/3) + 3 I2^2 I3^(-4/3) - 30) (decision D31); small-strain
//    bulk modulus K = 8 c1, shear modulus mu = 38 c2.
//  - DamageLaw: the NDM through the fe_material plugin: small strain eps = U - I from the
//    polar decomposition F = R U (engineering shear); the plugin's stress T is read as the
//    Biot stress (work conjugate of U): sigma = J^-1 R sym(T U) R^T (decision D32).
#include <Eigen/Dense>

#include <array>
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pnc::fe_material {
class Material;
}

namespace pnc::gimp {

using Mat3 = Eigen::Matrix3d;

/// The law failed at point `index` of an update_many() call; what() is update()'s message.
class PointFailure : public std::runtime_error {
public:
  PointFailure(std::size_t index, const std::string& what)
      : std::runtime_error(what), index_(index) {}
  std::size_t index() const noexcept { return index_; }

private:
  std::size_t index_;
};

class Material {
public:
  virtual ~Material() = default;
  virtual std::string type() const = 0;
  /// Reference mass density, kg/m^3.
  double density() const { return rho0_; }
  virtual int n_state() const { return 0; }
  virtual std::vector<std::string> state_names() const { return {}; }
  virtual void init_state(double* /*s*/) const {}
  /// Cauchy stress sigma (Pa) at deformation gradient F1, given F0 at the start of the step
  /// and the state s0 there; writes the new state s1 and the stored-energy density W (J/m^3 of
  /// reference volume). Throws std::runtime_error if the law fails (e.g. det F <= 0).
  virtual void update(const Mat3& F0, const Mat3& F1, const double* s0, double* s1, Mat3& sigma,
                      double& W) const = 0;
  /// update() for n particles at once (decision D264): point i has F0[i], F1[i], its state at
  /// state + i * stride (n_state() doubles, read as s0 and overwritten with s1 in place) and
  /// writes sigma[i] (Pa) and W[i] (J/m^3). The same numbers as n update() calls. A point the
  /// law cannot take throws PointFailure with its index (the points before it are written,
  /// the rest unspecified); InputError passes through. The default is the loop over update().
  virtual void update_many(std::size_t n, const Mat3* F0, const Mat3* F1, double* state,
                           std::size_t stride, Mat3* sigma, double* W) const;
  /// Doubles per particle of a scratch that update_many_cached() keeps between steps to save
  /// work (decision D416). Not state: never in checkpoints or output, zero after the solver's
  /// initialize() (a resume included) and stale after the particles are reordered, so a law
  /// uses an entry only after checking that it belongs to the point's F0. 0 (default): none.
  virtual int n_scratch() const { return 0; }
  /// update_many() with that scratch: point i's n_scratch() doubles at
  /// scratch + i * scratch_stride (scratch_stride >= n_scratch()), which must hold zeros or
  /// what this law wrote there for some point. The same numbers as update_many(), bit for bit.
  /// The default calls update_many().
  virtual void update_many_cached(std::size_t n, const Mat3* F0, const Mat3* F1, double* state,
                                  std::size_t stride, double* /*scratch*/,
                                  std::size_t /*scratch_stride*/, Mat3* sigma, double* W) const {
    update_many(n, F0, F1, state, stride, sigma, W);
  }
  /// Small-strain dilatational wave speed sqrt(M / rho0), M the largest diagonal stiffness
  /// (m/s); the CFL time step uses it.
  virtual double wave_speed() const = 0;
  /// Small-strain Young's modulus and Poisson's ratio of an isotropic law (NaN otherwise).
  virtual double youngs_modulus() const = 0;
  virtual double poisson_ratio() const = 0;

protected:
  explicit Material(double rho0) : rho0_(rho0) {}
  double rho0_;
};

/// St Venant-Kirchhoff (objective linear elasticity in E = (C - I)/2).
class LinearElastic final : public Material {
public:
  LinearElastic(double rho0, double E, double nu);
  std::string type() const override { return "linear_elastic"; }
  void update(const Mat3& F0, const Mat3& F1, const double* s0, double* s1, Mat3& sigma,
              double& W) const override;
  double wave_speed() const override;
  double youngs_modulus() const override { return E_; }
  double poisson_ratio() const override { return nu_; }

private:
  double E_, nu_, lambda_, mu_;
};

/// Compressible hyperelastic polymer (docs/theory.md §5.3, decision D31):
/// W = c1 (I3 - 1)^2 + c2 (I1 / I3^(1/3) + 3 I2^2 / I3^(4/3) - 30), invariants of C = F^T F.
/// W = 0 and S = 0 at C = I; small-strain K = 8 c1, mu = 38 c2.
class HyperelasticPolymer final : public Material {
public:
  HyperelasticPolymer(double rho0, double c1, double c2);
  /// c1, c2 (Pa) giving small-strain Young's modulus E (Pa) and Poisson's ratio nu.
  static std::pair<double, double> calibrate(double E, double nu);
  std::string type() const override { return "hyperelastic_polymer"; }
  void update(const Mat3& F0, const Mat3& F1, const double* s0, double* s1, Mat3& sigma,
              double& W) const override;
  /// update() of each particle without the base class's state copies (no state).
  void update_many(std::size_t n, const Mat3* F0, const Mat3* F1, double* state, std::size_t stride,
                   Mat3* sigma, double* W) const override;
  double wave_speed() const override;
  double youngs_modulus() const override;
  double poisson_ratio() const override;
  double c1() const { return c1_; }
  double c2() const { return c2_; }
  /// Strain energy density W(C) (J/m^3) and second Piola-Kirchhoff stress S = 2 dW/dC (Pa).
  double energy(const Mat3& C) const;
  Mat3 pk2(const Mat3& C) const;

private:
  double c1_, c2_;
};

/// The NDM damage law through the fe_material plugin (decision D32). State per particle: the
/// plugin's state variables (names from the card's model, e.g. kappa1..D3). [C0], E1, nu12
/// and the stored energy W come from the plugin's ABI 1.1 queries and integrate2 (D214);
/// wave_speed() is sqrt(max(C11, C22, C33) / rho0) of the global-frame [C0].
class DamageLaw final : public Material {
public:
  DamageLaw(double rho0, std::shared_ptr<const pnc::fe_material::Material> law);
  std::string type() const override { return "damage_card"; }
  int n_state() const override { return n_state_; }
  std::vector<std::string> state_names() const override { return names_; }
  void init_state(double* s) const override;
  void update(const Mat3& F0, const Mat3& F1, const double* s0, double* s1, Mat3& sigma,
              double& W) const override;
  /// Through the plugin's batched entry (ABI 1.2, pnc_material_integrate_batch; D264) when the
  /// plugin has it, the per-particle loop otherwise. Stress and state equal update()'s bit for
  /// bit; W to the last bits (the batched energies, D261).
  void update_many(std::size_t n, const Mat3* F0, const Mat3* F1, double* state, std::size_t stride,
                   Mat3* sigma, double* W) const override;
  /// The scratch of a point (D416): its last F1 (9 doubles, column-major) and that F1's small
  /// strain U - I (6, Voigt, engineering shear). The next step's F0 is that F1 bit for bit, so
  /// its polar decomposition is not repeated; a point whose F0 differs computes it.
  int n_scratch() const override { return 15; }
  void update_many_cached(std::size_t n, const Mat3* F0, const Mat3* F1, double* state,
                          std::size_t stride, double* scratch, std::size_t scratch_stride,
                          Mat3* sigma, double* W) const override;
  double wave_speed() const override { return c_; }
  double youngs_modulus() const override;
  double poisson_ratio() const override;
  const pnc::fe_material::Material& law() const { return *law_; }

private:
  std::shared_ptr<const pnc::fe_material::Material> law_;
  int n_state_;
  std::vector<std::string> names_;
  double c_;
};

/// Right polar decomposition F = R U (R proper orthogonal, U symmetric positive definite).
void polar_decomposition(const Mat3& F, Mat3& R, Mat3& U);

/// Small-strain Voigt vector (11,22,33,23,13,12, engineering shear) of a symmetric tensor.
std::array<double, 6> to_voigt_strain(const Mat3& e);
Mat3 from_voigt_stress(const std::array<double, 6>& s);

} // namespace pnc::gimp
