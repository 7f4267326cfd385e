// ABI 1.1 of the pnc material plugin (pnc/fe_material/pnc_material.h): the v2 point
// interface (pnc_material_integrate2) and the property, stiffness and state-index queries.
// All physics is pnc::damage::integrate_row_major() (the kernel's one routine, D210); this
// file checks the point struct, converts arrays and reports errors at the C boundary.
#include "pnc/fe_material/pnc_material.h"

#include "abi_util.hpp"
#include "material_impl.hpp"

#include "pnc/damage/ndm.hpp"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <string>

namespace {

using pnc::fe_material::detail::copy_message;

constexpr const char* kFn = "pnc_material_integrate2";

// End offset of a field of pnc_material_point: the struct must be at least this big for the
// library to read or write the field.
#define PNC_POINT_END(field)                                                                       \
  (offsetof(pnc_material_point, field) + sizeof(static_cast<pnc_material_point*>(nullptr)->field))

constexpr std::size_t kMinPointSize = PNC_POINT_END(tangent);

// Writes the message when the caller's struct has the error buffer.
void report(pnc_material_point* pt, const char* text) {
  if (pt->size >= PNC_POINT_END(err_len)) copy_message(pt->err, pt->err_len, text);
}

int refuse(pnc_material_point* pt, int status, const char* field, const std::string& value,
           const char* rule) {
  char line[640];
  std::snprintf(line, sizeof line, "%s: field '%s': value '%s': %s", kFn, field, value.c_str(),
                rule);
  report(pt, line);
  return status;
}

std::string num(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// The index of the first non-finite of n entries, or -1.
int first_bad(const double* x, int n) {
  return pnc::fe_material::detail::first_non_finite(x, n);
}

int integrate2(const pnc_material* m, pnc_material_point* pt) {
  using pnc::damage::TangentKind;
  if (pt->size < kMinPointSize) return PNC_MATERIAL_BAD_ARGUMENT; // no error buffer to write
  if (pt->version == 0 || pt->version > PNC_MATERIAL_POINT_VERSION) {
    const std::string rule =
        "this library (ABI " + std::to_string(PNC_MATERIAL_ABI_VERSION) + "." +
        std::to_string(PNC_MATERIAL_ABI_VERSION_MINOR) + ") knows pnc_material_point versions 1.." +
        std::to_string(PNC_MATERIAL_POINT_VERSION) +
        "; use a libpnc_material at least as new as the header the host was built with";
    return refuse(pt, PNC_MATERIAL_BAD_ARGUMENT, "point.version", std::to_string(pt->version),
                  rule.c_str());
  }
  if (!m) return refuse(pt, PNC_MATERIAL_BAD_ARGUMENT, "m", "NULL", "a material is required");
  const int req = pt->tangent_request;
  if (req < PNC_MATERIAL_TANGENT_NONE || req > PNC_MATERIAL_TANGENT_CONSISTENT)
    return refuse(pt, PNC_MATERIAL_BAD_ARGUMENT, "point.tangent_request", std::to_string(req),
                  "must be PNC_MATERIAL_TANGENT_NONE (0), _ELASTIC (1), _SECANT (2) or "
                  "_CONSISTENT (3)");
  if (!pt->state0 || !pt->state1 || !pt->strain0 || !pt->dstrain || !pt->stress ||
      (req != PNC_MATERIAL_TANGENT_NONE && !pt->tangent))
    return refuse(pt, PNC_MATERIAL_BAD_ARGUMENT,
                  "point.state0/state1/strain0/dstrain/stress/tangent", "NULL",
                  "these arrays are required (tangent unless tangent_request is "
                  "PNC_MATERIAL_TANGENT_NONE)");
  if (!std::isfinite(pt->dt) || pt->dt < 0)
    return refuse(pt, PNC_MATERIAL_BAD_INPUT, "point.dt", num(pt->dt),
                  "the time increment must be finite and >= 0 (s)");
  for (const auto& [arr, name] :
       {std::pair<const double*, const char*>{pt->strain0, "point.strain0"},
        std::pair<const double*, const char*>{pt->dstrain, "point.dstrain"}}) {
    const int i = first_bad(arr, 6);
    if (i >= 0)
      return refuse(pt, PNC_MATERIAL_BAD_INPUT,
                    (std::string(name) + "[" + std::to_string(i) + "]").c_str(), num(arr[i]),
                    "strains must be finite");
  }
  const pnc::damage::Model model = m->kernel.p.model;
  const int ns = static_cast<int>(pnc::damage::state_size(model));
  if (const auto bad = pnc::fe_material::detail::check_state(pt->state0, ns))
    return refuse(pt, PNC_MATERIAL_BAD_INPUT,
                  ("point.state0[" + std::to_string(bad.index) + "]").c_str(), num(bad.value),
                  bad.rule);

  const pnc::damage::NdmState s0 = pnc::damage::state_from_array(model, pt->state0);
  pnc::damage::NdmState s1;
  pnc::damage::ErrorBuffer ebuf;
  pnc::damage::NdmEnergy energy;
  // Everything goes to local arrays first and reaches the caller only when it is finite.
  double sig[6], K[36], st1[6];
  const bool want_K = req != PNC_MATERIAL_TANGENT_NONE;
  const pnc::damage::Status st = pnc::damage::integrate_row_major(
      m->kernel, s0, s1, pt->strain0, pt->dstrain, sig, want_K ? K : nullptr, ebuf,
      static_cast<TangentKind>(req), &energy);
  if (st != pnc::damage::Status::ok)
    return refuse(pt, PNC_MATERIAL_BAD_INPUT, "point.strain0 + point.dstrain", "", ebuf.msg);
  pnc::damage::state_to_array(model, s1, st1);
  if (const auto bad = pnc::fe_material::detail::check_result(sig, st1, ns, want_K ? K : nullptr))
    return refuse(
        pt, PNC_MATERIAL_BAD_INPUT,
        (std::string("result ") + bad.what + "[" + std::to_string(bad.index) + "]").c_str(),
        num(bad.value), bad.rule);
  if (!std::isfinite(energy.stored) || !std::isfinite(energy.dissipated))
    return refuse(pt, PNC_MATERIAL_BAD_INPUT, "result stored_energy/dissipated_energy",
                  num(energy.stored) + " / " + num(energy.dissipated),
                  pnc::fe_material::detail::kResultRule);
  std::memcpy(pt->stress, sig, sizeof sig);
  if (want_K) std::memcpy(pt->tangent, K, sizeof K);
  std::memcpy(pt->state1, st1, static_cast<std::size_t>(ns) * sizeof(double));
  if (pt->size >= PNC_POINT_END(stored_energy)) pt->stored_energy = energy.stored;
  if (pt->size >= PNC_POINT_END(dissipated_energy)) pt->dissipated_energy = energy.dissipated;
  return PNC_MATERIAL_OK;
}

// The properties of m, or null when they cannot be computed (out of memory).
const std::vector<pnc::fe_material::detail::Property>* properties_of(const pnc_material* m) {
  if (!m) return nullptr;
  try {
    return &m->properties();
  } catch (...) {
    return nullptr;
  }
}

const pnc::fe_material::detail::Property* find_property(const pnc_material* m, const char* name) {
  const auto* props = properties_of(m);
  if (!props || !name) return nullptr;
  for (const auto& p : *props)
    if (p.name == name) return &p;
  return nullptr;
}

int n_modes(const pnc_material* m) {
  return m->kernel.p.model == pnc::damage::Model::pnc ? 3 : 1;
}

// "pnc" or "pp" without exceptions; false for anything else.
bool model_of(const char* model, pnc::damage::Model& out) {
  if (!model) return false;
  if (std::strcmp(model, "pnc") == 0) {
    out = pnc::damage::Model::pnc;
    return true;
  }
  if (std::strcmp(model, "pp") == 0) {
    out = pnc::damage::Model::pp;
    return true;
  }
  return false;
}

} // namespace

extern "C" {

PNC_MATERIAL_API int pnc_material_abi_version_minor(void) {
  return PNC_MATERIAL_ABI_VERSION_MINOR;
}

PNC_MATERIAL_API int pnc_material_integrate2(const pnc_material* m, pnc_material_point* point) {
  if (!point) return PNC_MATERIAL_BAD_ARGUMENT;
  try {
    return integrate2(m, point);
  } catch (const std::exception& e) {
    report(point, e.what());
  } catch (...) {
    report(point, "pnc_material_integrate2: unknown internal error");
  }
  return PNC_MATERIAL_INTERNAL;
}

PNC_MATERIAL_API double pnc_material_property(const pnc_material* m, const char* name,
                                              int* status) {
  const auto* p = find_property(m, name);
  if (status)
    *status = p                   ? PNC_MATERIAL_OK
              : !m                ? PNC_MATERIAL_BAD_ARGUMENT
              : !properties_of(m) ? PNC_MATERIAL_INTERNAL
                                  : PNC_MATERIAL_UNKNOWN_NAME;
  return p ? p->value : std::numeric_limits<double>::quiet_NaN();
}

PNC_MATERIAL_API int pnc_material_n_properties(const pnc_material* m) {
  const auto* props = properties_of(m);
  return props ? static_cast<int>(props->size()) : 0;
}

PNC_MATERIAL_API const char* pnc_material_property_name(const pnc_material* m, int i) {
  if (!m || i < 0 || i >= pnc_material_n_properties(m)) return nullptr;
  return (*properties_of(m))[static_cast<std::size_t>(i)].name.c_str();
}

PNC_MATERIAL_API const char* pnc_material_property_units(const pnc_material* m, int i) {
  if (!m || i < 0 || i >= pnc_material_n_properties(m)) return nullptr;
  return (*properties_of(m))[static_cast<std::size_t>(i)].units;
}

PNC_MATERIAL_API int pnc_material_elastic_stiffness(const pnc_material* m, double* C36) {
  if (!m || !C36) return PNC_MATERIAL_BAD_ARGUMENT;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      C36[6 * i + j] = m->kernel.C0g(i, j);
  return PNC_MATERIAL_OK;
}

PNC_MATERIAL_API int pnc_material_damage_stiffness(const pnc_material* m, int mode, double* C36) {
  if (!m || !C36 || mode < 0 || mode >= n_modes(m)) return PNC_MATERIAL_BAD_ARGUMENT;
  const auto& M = m->kernel.dC1g[static_cast<std::size_t>(mode)];
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      C36[6 * i + j] = M(i, j);
  return PNC_MATERIAL_OK;
}

PNC_MATERIAL_API int pnc_material_state_index(const pnc_material* m, const char* name) {
  if (!m || !name) return -1;
  const auto& names = pnc::damage::state_names(m->kernel.p.model);
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  // "kappaK" / "DK" for every mode K = 1..n: for a one-mode law, kappa1 and D1.
  if (n_modes(m) == 1) {
    if (std::strcmp(name, "kappa1") == 0) return 0;
    if (std::strcmp(name, "D1") == 0) return 1;
  }
  return -1;
}

PNC_MATERIAL_API int pnc_material_model_n_constants(const char* model) {
  pnc::damage::Model md;
  return model_of(model, md) ? static_cast<int>(pnc::damage::constant_names(md).size()) : 0;
}

PNC_MATERIAL_API const char* pnc_material_model_constant_name(const char* model, int i) {
  pnc::damage::Model md;
  if (!model_of(model, md) || i < 0 || i >= pnc_material_model_n_constants(model)) return nullptr;
  return pnc::damage::constant_names(md)[static_cast<std::size_t>(i)].c_str();
}

PNC_MATERIAL_API int pnc_material_damage_of_stretch(const pnc_material* m, int mode, double kappa,
                                                    double* D, double* dD_dkappa) {
  if (!m || !D || mode < 0 || mode >= n_modes(m) || !std::isfinite(kappa) || kappa < 0)
    return PNC_MATERIAL_BAD_ARGUMENT;
  // every mode follows the one damage function of the law (its alpha): the routine the
  // kernel's integration uses, so the query and integrate2 agree bit for bit
  double slope = 0.0;
  *D = pnc::damage::damage_of_kappa(m->kernel.p, kappa, &slope);
  if (dD_dkappa) *dD_dkappa = slope;
  return PNC_MATERIAL_OK;
}

PNC_MATERIAL_API int pnc_material_mode_stretch(const pnc_material* m, const double* strain,
                                               double* lambda, double* dlambda) {
  if (!m || !strain || !lambda) return PNC_MATERIAL_BAD_ARGUMENT;
  pnc::damage::Voigt eps;
  for (int i = 0; i < 6; ++i)
    eps[i] = strain[i];
  if (!eps.allFinite()) return PNC_MATERIAL_BAD_ARGUMENT;
  // the platelet-frame strain and the kernel's stretch routine, as the integration (D340)
  const auto& q = m->kernel;
  const pnc::damage::Voigt el = pnc::damage::local_strain(q, eps); // D351
  const pnc::damage::ModeStretch s = pnc::damage::mode_stretches(q.p.model, el, dlambda != nullptr);
  const int n = n_modes(m);
  for (int k = 0; k < n; ++k)
    lambda[k] = s.lambda[static_cast<std::size_t>(k)];
  if (dlambda) {
    const Eigen::Matrix<double, 3, 6> g =
        q.rotated ? Eigen::Matrix<double, 3, 6>(s.dlambda * q.T) : s.dlambda;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < 6; ++j)
        dlambda[6 * k + j] = g(k, j);
  }
  return PNC_MATERIAL_OK;
}

} // extern "C"
