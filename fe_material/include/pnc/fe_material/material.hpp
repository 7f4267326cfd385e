#pragma once
// pnc/fe_material/material.hpp: header-only C++ wrapper over the C ABI of the pnc material
// plugin (pnc_material.h, docs/plugin.md). Two ways in:
//
//   // 1. linked: target_link_libraries(app PRIVATE pnc::fe_material)
//   auto mat = pnc::fe_material::Material::from_card("fit.h5");
//
//   // 2. loaded at run time: target_link_libraries(app PRIVATE pnc::fe_material_headers)
//   pnc::fe_material::Plugin plugin("/path/to/libpnc_material.so");
//   auto mat = plugin.from_card("fit.h5");
//
//   std::vector<double> s0 = mat.initial_state(), s1(s0.size());
//   std::array<double, 6> eps0{}, deps{0.01, 0, 0, 0, 0, 0}, sig;
//   std::array<double, 36> K;                      // row-major d sigma / d eps, Pa
//   mat.integrate(s0, s1, eps0, deps, sig, &K);    // throws pnc::fe_material::Error
//
//   // ABI 1.1: tangent on request, energies, properties, state indices
//   auto e = mat.integrate2(s0.data(), s1.data(), eps0.data(), deps.data(), sig.data(),
//                           K.data(), PNC_MATERIAL_TANGENT_SECANT);    // e.stored, e.dissipated
//   double onset = mat.property("damage_onset_stretch");
//   int k2 = mat.state_index("kappa2");
//
//   // ABI 1.2: n points in one call, structure of arrays (component k of point i at k*ld + i)
//   pnc_material_point_soa b;
//   pnc_material_point_soa_init(&b);
//   b.ld = n; b.strain0 = e0.data(); b.dstrain = de.data(); b.state0 = b.state1 = st.data();
//   b.stress = sig.data();                          // 6*n, 6*n, n_state*n, 6*n doubles
//   mat.integrate_batch(n, b);                      // throws, naming the first failed point
//
// Units and Voigt order as in pnc_material.h: Pa, 11,22,33,23,13,12, engineering shear
// strain. A Material is move-only; integrate() is const and may be called from many threads
// on one Material. A Material made by a Plugin keeps the plugin loaded while it exists.
#include "pnc/fe_material/material_api.hpp" // Error, Api, detail::Library
#include "pnc/fe_material/pnc_material.h"

#include <dlfcn.h>

#include <array>
#include <cstddef>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pnc::fe_material {

using Voigt6 = std::array<double, 6>;     ///< 11,22,33,23,13,12; engineering shear strain
using Tangent36 = std::array<double, 36>; ///< row-major d sigma_i / d eps_j

class Plugin;

/// One material: model, constants and platelet rotation; immutable.
class Material {
public:
  /// Reads a material card with the linked library (needs pnc::fe_material at link time).
  /// A card whose verdict is "not usable" is refused (Error with its reasons) unless
  /// allow_not_usable is true (or PNC_ALLOW_NOT_USABLE_CARD=1 is set).
  static Material from_card(const std::string& card_path, bool allow_not_usable = false) {
    return create_card(linked(), card_path, allow_not_usable);
  }
  /// Builds a material from constants (order of constant_names(), SI) without touching any
  /// file; `rotation` is R row-major (x_local = R x_global), null for the identity. Linked
  /// library.
  static Material from_constants(const std::string& model, const std::vector<double>& constants,
                                 const std::array<double, 9>* rotation = nullptr) {
    return create_constants(linked(), model, constants, rotation);
  }

  Material(Material&& o) noexcept : lib_(std::move(o.lib_)), m_(std::exchange(o.m_, nullptr)) {}
  Material& operator=(Material&& o) noexcept {
    if (this != &o) {
      reset();
      lib_ = std::move(o.lib_);
      m_ = std::exchange(o.m_, nullptr);
    }
    return *this;
  }
  Material(const Material&) = delete;
  Material& operator=(const Material&) = delete;
  ~Material() { reset(); }

  /// "pnc" or "pp".
  std::string model() const { return detail::str(api().model(m_)); }
  /// Where the library came from: "<linked>" or the plugin path.
  const std::string& library() const { return lib_->path; }

  int n_constants() const { return api().n_constants(m_); }
  std::vector<std::string> constant_names() const {
    std::vector<std::string> out;
    for (int i = 0; i < n_constants(); ++i)
      out.push_back(detail::str(api().constant_name(m_, i)));
    return out;
  }
  std::vector<double> constants() const {
    std::vector<double> out;
    for (int i = 0; i < n_constants(); ++i)
      out.push_back(api().constant(m_, i));
    return out;
  }
  /// A constant by name (SI); throws Error for a name the model does not have.
  double constant(const std::string& name) const {
    for (int i = 0; i < n_constants(); ++i)
      if (detail::str(api().constant_name(m_, i)) == name) return api().constant(m_, i);
    throw Error("pnc::fe_material::Material: field '" + name + "': not a constant of model " +
                model());
  }
  /// Platelet rotation R, row-major, x_local = R x_global.
  std::array<double, 9> rotation() const {
    std::array<double, 9> R{};
    api().rotation(m_, R.data());
    return R;
  }

  int n_state() const { return api().n_state(m_); }
  /// kappa1 kappa2 kappa3 D1 D2 D3 (pnc) or kappa D (pp).
  std::vector<std::string> state_names() const {
    std::vector<std::string> out;
    for (int i = 0; i < n_state(); ++i)
      out.push_back(detail::str(api().state_name(m_, i)));
    return out;
  }
  /// The virgin state.
  std::vector<double> initial_state() const {
    std::vector<double> s(static_cast<std::size_t>(n_state()));
    api().init_state(m_, s.data());
    return s;
  }
  void init_state(double* state) const { api().init_state(m_, state); }

  /// One increment, no exceptions: returns PNC_MATERIAL_OK or a status with the message in
  /// err. Arrays as in pnc_material_integrate(); tangent may be null.
  int try_integrate(const double* state0, double* state1, const double* eps0, const double* deps,
                    double* stress, double* tangent, char* err, std::size_t errlen) const noexcept {
    return api().integrate(m_, state0, state1, eps0, deps, stress, tangent, err, errlen);
  }
  /// One increment; throws Error (naming the argument, the value and the rule) on failure.
  void integrate(const double* state0, double* state1, const double* eps0, const double* deps,
                 double* stress, double* tangent = nullptr) const {
    char err[512] = {0};
    const int st = try_integrate(state0, state1, eps0, deps, stress, tangent, err, sizeof err);
    if (st != PNC_MATERIAL_OK) throw Error(err, st);
  }
  /// One increment with containers; state1 is resized to n_state().
  void integrate(const std::vector<double>& state0, std::vector<double>& state1, const Voigt6& eps0,
                 const Voigt6& deps, Voigt6& stress, Tangent36* tangent = nullptr) const {
    const auto ns = static_cast<std::size_t>(n_state());
    if (state0.size() != ns)
      throw Error("pnc::fe_material::Material::integrate: argument 'state0': value '" +
                  std::to_string(state0.size()) + " entries': model " + model() + " has " +
                  std::to_string(ns) + " state variables");
    state1.resize(ns);
    integrate(state0.data(), state1.data(), eps0.data(), deps.data(), stress.data(),
              tangent ? tangent->data() : nullptr);
  }

  /// The UMAT PROPS of this material (umat.h, docs/plugin.md): model code, constants (SI)
  /// and, when it is not the identity or with_rotation is true, the platelet rotation R.
  /// Throws Error when the library predates this metadata.
  std::vector<double> umat_props(bool with_rotation = false) const {
    require_props_metadata();
    const unsigned flags = with_rotation ? PNC_MATERIAL_PROPS_WITH_ROTATION : 0u;
    std::vector<double> props(static_cast<std::size_t>(api().umat_nprops(m_, flags)));
    if (api().umat_props(m_, flags, props.data(), static_cast<int>(props.size())) !=
        static_cast<int>(props.size()))
      throw Error("pnc::fe_material::Material::umat_props: the library refused to write PROPS");
    return props;
  }
  /// Names ("model_code", "C11", ..., "R33") and units ("Pa", "1") of the first n PROPS.
  std::vector<std::string> umat_prop_names(std::size_t n) const {
    require_props_metadata();
    std::vector<std::string> out;
    for (std::size_t i = 0; i < n; ++i)
      out.push_back(detail::str(api().umat_prop_name(m_, static_cast<int>(i))));
    return out;
  }
  std::vector<std::string> umat_prop_units(std::size_t n) const {
    require_props_metadata();
    std::vector<std::string> out;
    for (std::size_t i = 0; i < n; ++i)
      out.push_back(detail::str(api().umat_prop_units(m_, static_cast<int>(i))));
    return out;
  }

  /// The card's verdict: "usable", "usable with warnings" or "not usable".
  std::string verdict() const { return detail::str(api().verdict(m_)); }

  // ---- ABI 1.1 (pnc_material_integrate2 and the queries; docs/plugin.md "ABI 1.1"). Every
  // method below throws Error when the library predates it.

  /// Energy densities of one increment (J/m^3), as in pnc_material_point.
  struct Energies {
    double stored = 0.0;     ///< 1/2 stress . strain at the end of the increment
    double dissipated = 0.0; ///< dissipated in the increment (psi(eps1, D0) - psi(eps1, D1))
  };
  /// One increment through pnc_material_integrate2, no exceptions: fills a point (size,
  /// version, the arrays, tangent_request = PNC_MATERIAL_TANGENT_*, dt in s) and returns the
  /// status; the message goes to err, the energies to *energies (may be null).
  int try_integrate2(const double* state0, double* state1, const double* eps0, const double* deps,
                     double* stress, double* tangent, int tangent_request, Energies* energies,
                     char* err, std::size_t errlen, double dt = 0.0) const noexcept {
    if (!api().integrate2) {
      detail_copy(err, errlen, "pnc_material_integrate2 is missing: the plugin predates ABI 1.1");
      return PNC_MATERIAL_INTERNAL;
    }
    pnc_material_point pt;
    pnc_material_point_init(&pt);
    pt.dt = dt;
    pt.tangent_request = tangent_request;
    pt.state0 = state0;
    pt.state1 = state1;
    pt.strain0 = eps0;
    pt.dstrain = deps;
    pt.stress = stress;
    pt.tangent = tangent;
    pt.err = err;
    pt.err_len = errlen;
    const int st = api().integrate2(m_, &pt);
    if (st == PNC_MATERIAL_OK && energies) *energies = {pt.stored_energy, pt.dissipated_energy};
    return st;
  }
  /// The same; throws Error (naming the field, the value and the rule) on failure.
  Energies integrate2(const double* state0, double* state1, const double* eps0, const double* deps,
                      double* stress, double* tangent = nullptr,
                      int tangent_request = PNC_MATERIAL_TANGENT_NONE, double dt = 0.0) const {
    detail::require_v2(*lib_, "pnc_material_integrate2");
    char err[640] = {0};
    Energies e;
    const int st = try_integrate2(state0, state1, eps0, deps, stress, tangent, tangent_request, &e,
                                  err, sizeof err, dt);
    if (st != PNC_MATERIAL_OK) throw Error(err, st);
    return e;
  }
  /// A property by name (pnc_material_property; units from property_units()); throws Error
  /// for a name the material does not have.
  double property(const std::string& name) const {
    detail::require_v2(*lib_, "pnc_material_property");
    int st = PNC_MATERIAL_OK;
    const double v = api().property(m_, name.c_str(), &st);
    if (st != PNC_MATERIAL_OK)
      throw Error("pnc::fe_material::Material::property: field '" + name +
                      "': not a property of this material (property_names() lists them)",
                  st);
    return v;
  }
  /// Every property name, and the units of each ("Pa", "1"), in the library's order.
  std::vector<std::string> property_names() const {
    detail::require_v2(*lib_, "pnc_material_property_name");
    std::vector<std::string> out;
    for (int i = 0; i < api().n_properties(m_); ++i)
      out.push_back(detail::str(api().property_name(m_, i)));
    return out;
  }
  std::vector<std::string> property_units() const {
    detail::require_v2(*lib_, "pnc_material_property_units");
    std::vector<std::string> out;
    for (int i = 0; i < api().n_properties(m_); ++i)
      out.push_back(detail::str(api().property_units(m_, i)));
    return out;
  }
  /// [C0] in the global frame, row-major, Pa.
  Tangent36 elastic_stiffness() const {
    detail::require_v2(*lib_, "pnc_material_elastic_stiffness");
    Tangent36 C{};
    api().elastic_stiffness(m_, C.data());
    return C;
  }
  /// d[C]/dD of damage mode `mode` (0-based, < n_damage_modes()), global frame, Pa.
  Tangent36 damage_stiffness(int mode) const {
    detail::require_v2(*lib_, "pnc_material_damage_stiffness");
    Tangent36 C{};
    if (api().damage_stiffness(m_, mode, C.data()) != PNC_MATERIAL_OK)
      throw Error("pnc::fe_material::Material::damage_stiffness: argument 'mode': value '" +
                  std::to_string(mode) + "': must be 0.." + std::to_string(n_damage_modes() - 1));
    return C;
  }
  /// Number of damage modes (3 for pnc, 1 for pp).
  int n_damage_modes() const { return static_cast<int>(property("n_damage_modes")); }
  /// Index of a state variable by name ("kappaK", "DK" for every mode K); throws Error if
  /// the material has no such variable.
  int state_index(const std::string& name) const {
    detail::require_v2(*lib_, "pnc_material_state_index");
    const int i = api().state_index(m_, name.c_str());
    if (i < 0)
      throw Error("pnc::fe_material::Material::state_index: field '" + name +
                  "': not a state variable of model " + model());
    return i;
  }
  // ---- ABI 1.2: the batched entry (pnc_material_point_soa; docs/plugin.md "ABI 1.2").

  /// Whether the plugin has the batched entry (ABI 1.2 or newer).
  bool has_batch() const noexcept { return api().integrate_batch != nullptr; }

  /// n points in one call, no exceptions: the caller fills *batch (pnc_material_point_soa_init,
  /// ld, the blocks, tangent_request) and gets the status, per-point status and message there.
  int try_integrate_batch(std::size_t n, pnc_material_point_soa* batch) const noexcept {
    if (!api().integrate_batch) {
      if (batch && batch->size >= sizeof(pnc_material_point_soa))
        detail_copy(batch->err, batch->err_len,
                    "pnc_material_integrate_batch is missing: the plugin predates ABI 1.2");
      return PNC_MATERIAL_INTERNAL;
    }
    return api().integrate_batch(m_, n, batch);
  }
  /// The same; throws Error (naming the first failed point, the field, the value and the rule)
  /// when any point fails. The points that did not fail are computed and written all the same.
  void integrate_batch(std::size_t n, pnc_material_point_soa& batch) const {
    if (!lib_->api.integrate_batch)
      throw Error("pnc::fe_material: '" + lib_->path +
                  "': symbol 'pnc_material_integrate_batch' is missing: the plugin predates ABI " +
                  std::to_string(PNC_MATERIAL_ABI_VERSION) + ".2; use a newer libpnc_material");
    char err[768] = {0};
    char* const user_err = batch.err;
    const std::size_t user_len = batch.err_len;
    if (!user_err) {
      batch.err = err;
      batch.err_len = sizeof err;
    }
    const int st = api().integrate_batch(m_, n, &batch);
    const std::string msg = batch.err ? batch.err : "";
    batch.err = user_err;
    batch.err_len = user_len;
    if (st != PNC_MATERIAL_OK) throw Error(msg, st);
  }

  // ---- ABI 1.3: the damage evolution law (docs/plugin.md "ABI 1.3").

  /// Damage of mode `mode` (0-based) at the largest mode stretch `kappa` (dimensionless), as
  /// integrate2() computes it; `slope`, if not null, receives dD/dkappa. Throws Error for a
  /// plugin older than ABI 1.3 or a refused argument (mode, kappa), naming it.
  double damage_of_stretch(int mode, double kappa, double* slope = nullptr) const {
    if (!lib_->api.damage_of_stretch)
      throw Error("pnc::fe_material: '" + lib_->path +
                  "': symbol 'pnc_material_damage_of_stretch' is missing: the plugin predates "
                  "ABI " +
                  std::to_string(PNC_MATERIAL_ABI_VERSION) + ".3; use a newer libpnc_material");
    double D = 0;
    const int st = api().damage_of_stretch(m_, mode, kappa, &D, slope);
    if (st != PNC_MATERIAL_OK)
      throw Error("pnc::fe_material::Material::damage_of_stretch: mode " + std::to_string(mode) +
                      ", kappa " + std::to_string(kappa) + ": mode must be 0.." +
                      std::to_string(n_damage_modes() - 1) + " and kappa finite and >= 0",
                  st);
    return D;
  }

  /// The mode stretches of a strain (6, engineering Voigt, global frame): lambda[k] for
  /// k < n_damage_modes() (dimensionless), and, if `dlambda` is not null, d lambda_k / d
  /// strain_j at (*dlambda)[6 k + j]. Throws Error for a plugin older than ABI 1.3 or a strain
  /// that is not finite.
  std::vector<double> mode_stretch(const double* strain,
                                   std::vector<double>* dlambda = nullptr) const {
    if (!lib_->api.mode_stretch)
      throw Error("pnc::fe_material: '" + lib_->path +
                  "': symbol 'pnc_material_mode_stretch' is missing: the plugin predates ABI " +
                  std::to_string(PNC_MATERIAL_ABI_VERSION) + ".3; use a newer libpnc_material");
    const auto n = static_cast<std::size_t>(n_damage_modes());
    std::vector<double> lambda(n);
    if (dlambda) dlambda->assign(6 * n, 0.0);
    if (api().mode_stretch(m_, strain, lambda.data(), dlambda ? dlambda->data() : nullptr) !=
        PNC_MATERIAL_OK)
      throw Error("pnc::fe_material::Material::mode_stretch: argument 'strain': must be 6 "
                  "finite values");
    return lambda;
  }

  /// The constant names of a model, in the order from_constants() takes (linked library).
  static std::vector<std::string> model_constant_names(const std::string& model) {
    return detail::model_constant_names(*linked(), model);
  }

  /// The C handle, for code that calls the C ABI directly.
  const pnc_material* get() const noexcept { return m_; }

private:
  friend class Plugin;
  Material(std::shared_ptr<const detail::Library> lib, pnc_material* m)
      : lib_(std::move(lib)), m_(m) {}
  const Api& api() const { return lib_->api; }
  void require_props_metadata() const {
    const Api& a = api();
    if (!a.umat_nprops || !a.umat_props || !a.umat_prop_name || !a.umat_prop_units)
      throw Error("pnc::fe_material::Material: '" + lib_->path +
                  "': symbol 'pnc_material_umat_props' is missing: the plugin predates the "
                  "PROPS metadata; use a newer libpnc_material");
  }
  void reset() noexcept {
    if (m_) lib_->api.destroy(m_);
    m_ = nullptr;
  }
  static void detail_copy(char* dst, std::size_t n, const char* text) noexcept {
    if (!dst || n == 0) return;
    std::size_t k = 0;
    for (; text[k] && k + 1 < n; ++k)
      dst[k] = text[k];
    dst[k] = '\0';
  }

  static std::shared_ptr<const detail::Library> linked() {
    auto lib = std::make_shared<detail::Library>();
    lib->path = "<linked>";
    Api& a = lib->api;
    a.abi_version = &pnc_material_abi_version;
    a.create = &pnc_material_create;
    a.create_ex = &pnc_material_create_ex;
    a.verdict = &pnc_material_verdict;
    a.create_from_constants = &pnc_material_create_from_constants;
    a.destroy = &pnc_material_destroy;
    a.model = &pnc_material_model;
    a.n_constants = &pnc_material_n_constants;
    a.constant_name = &pnc_material_constant_name;
    a.constant = &pnc_material_constant;
    a.rotation = &pnc_material_rotation;
    a.n_state = &pnc_material_n_state;
    a.state_name = &pnc_material_state_name;
    a.init_state = &pnc_material_init_state;
    a.integrate = &pnc_material_integrate;
    a.umat_nprops = &pnc_material_umat_nprops;
    a.umat_props = &pnc_material_umat_props;
    a.umat_prop_name = &pnc_material_umat_prop_name;
    a.umat_prop_units = &pnc_material_umat_prop_units;
    a.abi_version_minor = &pnc_material_abi_version_minor;
    a.integrate2 = &pnc_material_integrate2;
    a.property = &pnc_material_property;
    a.n_properties = &pnc_material_n_properties;
    a.property_name = &pnc_material_property_name;
    a.property_units = &pnc_material_property_units;
    a.elastic_stiffness = &pnc_material_elastic_stiffness;
    a.damage_stiffness = &pnc_material_damage_stiffness;
    a.state_index = &pnc_material_state_index;
    a.model_n_constants = &pnc_material_model_n_constants;
    a.model_constant_name = &pnc_material_model_constant_name;
    a.integrate_batch = &pnc_material_integrate_batch;
    a.damage_of_stretch = &pnc_material_damage_of_stretch;
    a.mode_stretch = &pnc_material_mode_stretch;
    return lib;
  }
  static Material create_card(std::shared_ptr<const detail::Library> lib,
                              const std::string& card_path, bool allow_not_usable) {
    char err[1024] = {0};
    pnc_material* m =
        allow_not_usable
            ? lib->api.create_ex(card_path.c_str(), PNC_MATERIAL_ALLOW_NOT_USABLE, err, sizeof err)
            : lib->api.create(card_path.c_str(), err, sizeof err);
    if (!m) throw Error(err);
    return Material(std::move(lib), m);
  }
  static Material create_constants(std::shared_ptr<const detail::Library> lib,
                                   const std::string& model, const std::vector<double>& constants,
                                   const std::array<double, 9>* rotation) {
    char err[1024] = {0};
    if (constants.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw Error("pnc::fe_material::Material::from_constants: too many constants");
    pnc_material* m = lib->api.create_from_constants(
        model.c_str(), constants.data(), static_cast<int>(constants.size()),
        rotation ? rotation->data() : nullptr, err, sizeof err);
    if (!m) throw Error(err);
    return Material(std::move(lib), m);
  }

  std::shared_ptr<const detail::Library> lib_;
  pnc_material* m_ = nullptr;
};

/// A pnc material plugin loaded at run time with dlopen(): resolves the C ABI with dlsym()
/// and checks its ABI version. Cheap to copy (shares the handle); the library stays loaded
/// while a Plugin or a Material made from it exists.
class Plugin {
public:
  explicit Plugin(const std::string& path, int dlopen_flags = RTLD_NOW | RTLD_LOCAL) {
    auto lib = std::make_shared<detail::Library>();
    lib->path = path;
    dlerror();
    lib->handle = dlopen(path.c_str(), dlopen_flags);
    if (!lib->handle)
      throw Error("pnc::fe_material::Plugin: '" + path +
                  "': cannot load the plugin: " + detail::str(dlerror()));
    Api& a = lib->api;
    resolve(*lib, "pnc_material_abi_version", a.abi_version);
    const int version = a.abi_version();
    if (version != PNC_MATERIAL_ABI_VERSION)
      throw Error("pnc::fe_material::Plugin: '" + path + "': field 'pnc_material_abi_version()'" +
                  ": value '" + std::to_string(version) + "': this program was built for ABI " +
                  std::to_string(PNC_MATERIAL_ABI_VERSION) +
                  " (pnc_material.h); use a matching plugin");
    resolve(*lib, "pnc_material_create", a.create);
    resolve(*lib, "pnc_material_create_ex", a.create_ex);
    resolve(*lib, "pnc_material_verdict", a.verdict);
    resolve(*lib, "pnc_material_create_from_constants", a.create_from_constants);
    resolve(*lib, "pnc_material_destroy", a.destroy);
    resolve(*lib, "pnc_material_model", a.model);
    resolve(*lib, "pnc_material_n_constants", a.n_constants);
    resolve(*lib, "pnc_material_constant_name", a.constant_name);
    resolve(*lib, "pnc_material_constant", a.constant);
    resolve(*lib, "pnc_material_rotation", a.rotation);
    resolve(*lib, "pnc_material_n_state", a.n_state);
    resolve(*lib, "pnc_material_state_name", a.state_name);
    resolve(*lib, "pnc_material_init_state", a.init_state);
    resolve(*lib, "pnc_material_integrate", a.integrate);
    resolve_optional(*lib, "pnc_material_umat_nprops", a.umat_nprops);
    resolve_optional(*lib, "pnc_material_umat_props", a.umat_props);
    resolve_optional(*lib, "pnc_material_umat_prop_name", a.umat_prop_name);
    resolve_optional(*lib, "pnc_material_umat_prop_units", a.umat_prop_units);
    resolve_optional(*lib, "pnc_material_abi_version_minor", a.abi_version_minor);
    resolve_optional(*lib, "pnc_material_integrate2", a.integrate2);
    resolve_optional(*lib, "pnc_material_property", a.property);
    resolve_optional(*lib, "pnc_material_n_properties", a.n_properties);
    resolve_optional(*lib, "pnc_material_property_name", a.property_name);
    resolve_optional(*lib, "pnc_material_property_units", a.property_units);
    resolve_optional(*lib, "pnc_material_elastic_stiffness", a.elastic_stiffness);
    resolve_optional(*lib, "pnc_material_damage_stiffness", a.damage_stiffness);
    resolve_optional(*lib, "pnc_material_state_index", a.state_index);
    resolve_optional(*lib, "pnc_material_model_n_constants", a.model_n_constants);
    resolve_optional(*lib, "pnc_material_model_constant_name", a.model_constant_name);
    resolve_optional(*lib, "pnc_material_integrate_batch", a.integrate_batch);
    resolve_optional(*lib, "pnc_material_damage_of_stretch", a.damage_of_stretch);
    resolve_optional(*lib, "pnc_material_mode_stretch", a.mode_stretch);
    lib_ = std::move(lib);
  }

  const std::string& path() const { return lib_->path; }
  int abi_version() const { return lib_->api.abi_version(); }
  /// The library's minor ABI version (0 when it predates the query, i.e. ABI 1.0).
  int abi_version_minor() const {
    return lib_->api.abi_version_minor ? lib_->api.abi_version_minor() : 0;
  }
  /// The constant names of a model, in the order from_constants() takes (ABI 1.1).
  std::vector<std::string> model_constant_names(const std::string& model) const {
    return detail::model_constant_names(*lib_, model);
  }
  const Api& api() const { return lib_->api; }

  /// Reads a material card through the plugin (a "not usable" card as in Material::from_card).
  Material from_card(const std::string& card_path, bool allow_not_usable = false) const {
    return Material::create_card(lib_, card_path, allow_not_usable);
  }
  /// Builds a material from constants through the plugin (no file access).
  Material from_constants(const std::string& model, const std::vector<double>& constants,
                          const std::array<double, 9>* rotation = nullptr) const {
    return Material::create_constants(lib_, model, constants, rotation);
  }

private:
  template <class Fn> static void resolve(detail::Library& lib, const char* name, Fn& fn) {
    dlerror();
    void* sym = dlsym(lib.handle, name);
    if (!sym)
      throw Error("pnc::fe_material::Plugin: '" + lib.path + "': symbol '" + name +
                  "' is missing: not a pnc material plugin of ABI " +
                  std::to_string(PNC_MATERIAL_ABI_VERSION) + " (" + detail::str(dlerror()) + ")");
    fn = reinterpret_cast<Fn>(sym);
  }
  /// A symbol added within the ABI version: left null when the plugin is older.
  template <class Fn> static void resolve_optional(detail::Library& lib, const char* name, Fn& fn) {
    dlerror();
    fn = reinterpret_cast<Fn>(dlsym(lib.handle, name));
  }

  std::shared_ptr<const detail::Library> lib_;
};

} // namespace pnc::fe_material
