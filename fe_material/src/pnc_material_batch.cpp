// ABI 1.2 of the pnc material plugin (pnc/fe_material/pnc_material.h): the batched entry
// pnc_material_integrate_batch. All physics is pnc::damage::integrate_batch() (the kernel's
// batched route, D261); this file checks the batch struct, passes the caller's blocks through
// without copies and reports the first failed point at the C boundary (D260).
#include "pnc/fe_material/pnc_material.h"

#include "abi_util.hpp"
#include "material_impl.hpp"

#include "pnc/damage/ndm.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

namespace {

using pnc::fe_material::detail::copy_message;

constexpr const char* kFn = "pnc_material_integrate_batch";

// End offset of a field of pnc_material_point_soa: the struct must be at least this big for
// the library to read or write the field.
#define PNC_SOA_END(field)                                                                         \
  (offsetof(pnc_material_point_soa, field) +                                                       \
   sizeof(static_cast<pnc_material_point_soa*>(nullptr)->field))

constexpr std::size_t kMinSoaSize = PNC_SOA_END(tangent);

bool has(const pnc_material_point_soa* b, std::size_t end) {
  return b->size >= end;
}

void report(pnc_material_point_soa* b, const char* text) {
  if (has(b, PNC_SOA_END(err_len))) copy_message(b->err, b->err_len, text);
}

int refuse(pnc_material_point_soa* b, int status, const std::string& field,
           const std::string& value, const char* rule) {
  char line[768];
  std::snprintf(line, sizeof line, "%s: field '%s': value '%s': %s", kFn, field.c_str(),
                value.c_str(), rule);
  report(b, line);
  return status;
}

std::string num(double x) {
  char s[32];
  std::snprintf(s, sizeof s, "%.17g", x);
  return s;
}

// "name[component k, point i]"
std::string where(const char* name, std::size_t k, std::size_t i) {
  return std::string(name) + "[component " + std::to_string(k) + ", point " + std::to_string(i) +
         "]";
}

// The message of a failed point i, checked in the order of pnc_material_integrate2: the
// strains, the state, the total strain, else the result.
int report_point(pnc_material_point_soa* b, std::size_t i, std::size_t n, int ns) {
  const std::string of = " (point " + std::to_string(i) + " of " + std::to_string(n) +
                         " is the first that failed; its outputs are not written)";
  for (const auto& [arr, name] : {std::pair<const double*, const char*>{b->strain0, "strain0"},
                                  std::pair<const double*, const char*>{b->dstrain, "dstrain"}})
    for (std::size_t k = 0; k < 6; ++k) {
      const double x = arr[k * b->ld + i];
      if (!std::isfinite(x))
        return refuse(b, PNC_MATERIAL_BAD_INPUT, where(name, k, i), num(x),
                      ("strains must be finite" + of).c_str());
    }
  for (std::size_t k = 0; k < static_cast<std::size_t>(ns); ++k) {
    const double x = b->state0[k * b->ld + i];
    if (!std::isfinite(x))
      return refuse(b, PNC_MATERIAL_BAD_INPUT, where("state0", k, i), num(x),
                    (std::string(pnc::fe_material::detail::kStateRule) + of).c_str());
  }
  for (std::size_t k = 0; k < 6; ++k) {
    const double x = b->strain0[k * b->ld + i] + b->dstrain[k * b->ld + i];
    if (!std::isfinite(x))
      return refuse(b, PNC_MATERIAL_BAD_INPUT, where("strain0 + dstrain", k, i), num(x),
                    ("the total strain must be finite" + of).c_str());
  }
  return refuse(b, PNC_MATERIAL_BAD_INPUT, "result of point " + std::to_string(i), "non-finite",
                (std::string(pnc::fe_material::detail::kResultRule) + of).c_str());
}

int integrate_batch(const pnc_material* m, std::size_t n, pnc_material_point_soa* b) {
  using pnc::damage::TangentKind;
  if (b->size < kMinSoaSize) return PNC_MATERIAL_BAD_ARGUMENT; // no error buffer to write
  if (b->version == 0 || b->version > PNC_MATERIAL_POINT_SOA_VERSION) {
    const std::string rule =
        "this library (ABI " + std::to_string(PNC_MATERIAL_ABI_VERSION) + "." +
        std::to_string(PNC_MATERIAL_ABI_VERSION_MINOR) +
        ") knows pnc_material_point_soa versions 1.." +
        std::to_string(PNC_MATERIAL_POINT_SOA_VERSION) +
        "; use a libpnc_material at least as new as the header the host was built with";
    return refuse(b, PNC_MATERIAL_BAD_ARGUMENT, "batch.version", std::to_string(b->version),
                  rule.c_str());
  }
  if (!m) return refuse(b, PNC_MATERIAL_BAD_ARGUMENT, "m", "NULL", "a material is required");
  const int req = b->tangent_request;
  if (req < PNC_MATERIAL_TANGENT_NONE || req > PNC_MATERIAL_TANGENT_CONSISTENT)
    return refuse(b, PNC_MATERIAL_BAD_ARGUMENT, "batch.tangent_request", std::to_string(req),
                  "must be PNC_MATERIAL_TANGENT_NONE (0), _ELASTIC (1), _SECANT (2) or "
                  "_CONSISTENT (3)");
  if (b->ld < n)
    return refuse(b, PNC_MATERIAL_BAD_ARGUMENT, "batch.ld", std::to_string(b->ld),
                  ("the leading dimension must be at least n = " + std::to_string(n)).c_str());
  if (b->ld > SIZE_MAX / sizeof(double) / PNC_MATERIAL_TANGENT_SIZE)
    return refuse(b, PNC_MATERIAL_BAD_ARGUMENT, "batch.ld", std::to_string(b->ld),
                  "36 x ld doubles must be addressable");
  if (n > 0 && (!b->strain0 || !b->dstrain || !b->state0 || !b->state1 || !b->stress ||
                (req != PNC_MATERIAL_TANGENT_NONE && !b->tangent)))
    return refuse(b, PNC_MATERIAL_BAD_ARGUMENT,
                  "batch.strain0/dstrain/state0/state1/stress/tangent", "NULL",
                  "these arrays are required when n > 0 (tangent unless tangent_request is "
                  "PNC_MATERIAL_TANGENT_NONE)");
  if (!std::isfinite(b->dt) || b->dt < 0)
    return refuse(b, PNC_MATERIAL_BAD_INPUT, "batch.dt", num(b->dt),
                  "the time increment must be finite and >= 0 (s)");

  pnc::damage::NdmBatch v;
  v.n = n;
  v.ld = b->ld;
  v.eps0 = b->strain0;
  v.deps = b->dstrain;
  v.state0 = b->state0;
  v.state1 = b->state1;
  v.sigma = b->stress;
  v.K = req == PNC_MATERIAL_TANGENT_NONE ? nullptr : b->tangent;
  v.kind = static_cast<TangentKind>(req);
  if (has(b, PNC_SOA_END(status))) v.status = b->status;
  if (has(b, PNC_SOA_END(stored_energy))) v.stored = b->stored_energy;
  if (has(b, PNC_SOA_END(dissipated_energy))) v.dissipated = b->dissipated_energy;
  const pnc::damage::NdmBatchStats st = pnc::damage::integrate_batch(m->kernel, v);
  if (has(b, PNC_SOA_END(n_failed))) b->n_failed = st.failed;
  if (has(b, PNC_SOA_END(first_failed))) b->first_failed = st.first_failed;
  if (st.failed == 0) return PNC_MATERIAL_OK;
  const int ns = static_cast<int>(pnc::damage::state_size(m->kernel.p.model));
  return report_point(b, st.first_failed, n, ns);
}

} // namespace

extern "C" {

PNC_MATERIAL_API int pnc_material_integrate_batch(const pnc_material* m, size_t n,
                                                  pnc_material_point_soa* batch) {
  if (!batch) return PNC_MATERIAL_BAD_ARGUMENT;
  try {
    return integrate_batch(m, n, batch);
  } catch (const std::exception& e) {
    report(batch, e.what());
  } catch (...) {
    report(batch, "pnc_material_integrate_batch: unknown internal error");
  }
  return PNC_MATERIAL_INTERNAL;
}

} // extern "C"
