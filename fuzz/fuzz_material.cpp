// Fuzz target: the plugin's C ABI (pnc_material_create_from_constants, then a short strain path
// through pnc_material_integrate). The bytes choose the model, perturb the dissertation's
// constants (or replace them with raw doubles), the rotation, the start state and the strain
// increments. Checked on every call, beyond "no crash, no sanitizer report":
//  - creation either succeeds or returns NULL with a message;
//  - integrate with status OK gives finite stress, tangent and state;
//  - integrate with any other status leaves state1, stress and tangent untouched and writes a
//    message;
//  - pnc_material_integrate2 (ABI 1.1) on the same input, with the tangent request cycling
//    through none/elastic/secant/consistent, gives the same status, and when OK the same
//    stress and state bit for bit (the consistent tangent too: one kernel routine, D210) and
//    finite energies; when not OK it writes nothing but its message.
#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/pnc_material.h"

#include "fuzzed_double.hpp"

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

using pnc::fuzz::all_finite;
using pnc::fuzz::fuzzed;
constexpr double kCanary = -12345.678;
void fill_canary(double* v, int n) {
  pnc::fuzz::fill_canary(v, n, kCanary);
}
bool is_canary(const double* v, int n) {
  return pnc::fuzz::is_canary(v, 0, n, kCanary);
}

[[noreturn]] void bug(const char* what, const char* err) {
  std::fprintf(stderr, "pnc fuzz_material: %s (err: '%s')\n", what, err ? err : "");
  std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const bool pnc = in.ConsumeBool();
  const auto model = pnc ? pnc::damage::Model::pnc : pnc::damage::Model::pp;
  const pnc::damage::NdmParameters ref = pnc::damage::dissertation_parameters(model);
  std::vector<double> k(ref.k.begin(), ref.k.begin() + static_cast<long>(ref.size()));
  const int n_perturbed = in.ConsumeIntegralInRange<int>(0, 3);
  for (int i = 0; i < n_perturbed; ++i) {
    const std::size_t j = in.ConsumeIntegralInRange<std::size_t>(0, k.size() - 1);
    k[j] = fuzzed(in, k[j]);
  }
  double rot[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double* rotation = nullptr;
  if (in.ConsumeBool()) {
    // a proper rotation from three angles, sometimes spoilt
    const double a = in.ConsumeFloatingPointInRange<double>(-4, 4);
    const double b = in.ConsumeFloatingPointInRange<double>(-4, 4);
    const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b);
    const double r[9] = {ca * cb, -sa, ca * sb, sa * cb, ca, sa * sb, -sb, 0, cb};
    std::memcpy(rot, r, sizeof rot);
    if (in.ConsumeBool()) {
      const int j = in.ConsumeIntegralInRange<int>(0, 8);
      rot[j] = fuzzed(in, rot[j]);
    }
    rotation = rot;
  }
  char err[512] = "";
  pnc_material* m = pnc_material_create_from_constants(
      pnc ? "pnc" : "pp", k.data(), static_cast<int>(k.size()), rotation, err, sizeof err);
  if (!m) {
    if (err[0] == '\0') bug("create_from_constants returned NULL without a message", err);
    return 0;
  }
  const int ns = pnc_material_n_state(m);
  double state[8], state1[8];
  pnc_material_init_state(m, state);
  if (in.ConsumeBool()) {
    const int j = in.ConsumeIntegralInRange<int>(0, ns - 1);
    state[j] = fuzzed(in, state[j] + 0.1);
  }
  double strain[6] = {0, 0, 0, 0, 0, 0};
  const bool with_tangent = in.ConsumeBool();
  const double scale = std::ldexp(1.0, in.ConsumeIntegralInRange<int>(-30, 4));
  const int steps = in.ConsumeIntegralInRange<int>(1, 8);
  for (int step = 0; step < steps && in.remaining_bytes() > 0; ++step) {
    double d[6];
    for (double& x : d)
      x = fuzzed(in, scale);
    double stress[6], tangent[36];
    fill_canary(stress, 6);
    fill_canary(tangent, 36);
    fill_canary(state1, ns);
    err[0] = '\0';
    const int st = pnc_material_integrate(m, state, state1, strain, d, stress,
                                          with_tangent ? tangent : nullptr, err, sizeof err);
    // The same increment through the v2 point interface.
    double stress2[6], tangent2[36], state2[8];
    char err2[512] = "";
    fill_canary(stress2, 6);
    fill_canary(tangent2, 36);
    fill_canary(state2, ns);
    pnc_material_point pt;
    pnc_material_point_init(&pt);
    pt.tangent_request = step % 4; // NONE, ELASTIC, SECANT, CONSISTENT
    pt.state0 = state;
    pt.state1 = state2;
    pt.strain0 = strain;
    pt.dstrain = d;
    pt.stress = stress2;
    pt.tangent = tangent2;
    pt.err = err2;
    pt.err_len = sizeof err2;
    const int st2 = pnc_material_integrate2(m, &pt);
    // integrate (v1) with a tangent computes the consistent one; integrate2 asked for less
    // (none, elastic, secant) may succeed where that tangent overflows: only a v2 call that asks
    // at least what v1 asked must agree with v1 on success
    const bool asks_as_much =
        !with_tangent || pt.tangent_request == PNC_MATERIAL_TANGENT_CONSISTENT;
    if (st2 == PNC_MATERIAL_OK) {
      if (st != PNC_MATERIAL_OK) {
        if (asks_as_much) bug("integrate2 OK where integrate failed", err);
      } else if (std::memcmp(stress, stress2, sizeof stress) != 0 ||
                 std::memcmp(state1, state2, sizeof(double) * static_cast<std::size_t>(ns)) != 0) {
        bug("integrate2 and integrate differ", err2);
      } else if (with_tangent && pt.tangent_request == PNC_MATERIAL_TANGENT_CONSISTENT &&
                 std::memcmp(tangent, tangent2, sizeof tangent) != 0) {
        bug("the consistent tangents of integrate2 and integrate differ", err2);
      }
      if (pt.tangent_request != PNC_MATERIAL_TANGENT_NONE && !all_finite(tangent2, 36))
        bug("integrate2 OK with a non-finite tangent", err2);
      if (!std::isfinite(pt.stored_energy) || !std::isfinite(pt.dissipated_energy))
        bug("integrate2 OK with a non-finite energy", err2);
    } else {
      if (!is_canary(stress2, 6) || !is_canary(tangent2, 36) || !is_canary(state2, ns))
        bug("a failed integrate2 wrote its outputs", err2);
      if (err2[0] == '\0') bug("a failed integrate2 gave no message", err2);
    }
    if (st == PNC_MATERIAL_OK) {
      if (!all_finite(stress, 6)) bug("status OK with a non-finite stress", err);
      if (with_tangent && !all_finite(tangent, 36)) bug("status OK with a non-finite tangent", err);
      if (!all_finite(state1, ns)) bug("status OK with a non-finite state", err);
      std::memcpy(state, state1, sizeof(double) * static_cast<std::size_t>(ns));
      for (int i = 0; i < 6; ++i)
        strain[i] += d[i];
    } else {
      if (!is_canary(stress, 6) || !is_canary(tangent, 36) || !is_canary(state1, ns))
        bug("a failed integrate wrote its outputs", err);
      if (err[0] == '\0') bug("a failed integrate gave no message", err);
      break;
    }
  }
  pnc_material_destroy(m);
  return 0;
}
