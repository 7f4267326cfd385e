// Fuzz target: the plugin's Abaqus-style entry point umat_ (pnc/fe_material/umat.h). The bytes
// choose NTENS/NDI/NSHR, NSTATV, NPROPS and PROPS (the model code, the dissertation's constants
// perturbed or replaced by raw doubles, an optional rotation), STATEV, STRAN and DSTRAN, and a
// short sequence of increments. Checked on every call, beyond "no crash, no sanitizer report":
//  - an accepted call (PNEWDT left at 1) writes a finite STRESS(1..NTENS), STATEV(1..NSTATV)
//    and DDSDDE(NTENS x NTENS), and touches nothing past them;
//  - a refused call lowers PNEWDT to 0.5 and leaves STRESS, STATEV and DDSDDE untouched.
// umat_ reports each refusal on stderr (one line); that is its documented behaviour.
// Configuration errors (NTENS, NPROPS, PROPS, NSTATV) stop the process by default, as Abaqus's
// XIT would (docs/decisions.md D165); the fuzzer runs umat_ in the documented non-exiting mode
// PNC_UMAT_ON_CONFIG_ERROR=cutback, in which every refusal lowers PNEWDT to 0.5.
#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/umat.h"

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
using pnc::fuzz::fill_canary;
using pnc::fuzz::fuzzed;
using pnc::fuzz::is_canary;

[[noreturn]] void bug(const char* what) {
  std::fprintf(stderr, "pnc fuzz_umat: %s\n", what);
  std::abort();
}

constexpr int kArray = 48; // every array is this long; entries past the used ones are canaries

} // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  setenv("PNC_UMAT_ON_CONFIG_ERROR", "cutback", 1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const bool pnc = in.ConsumeBool();
  const auto model = pnc ? pnc::damage::Model::pnc : pnc::damage::Model::pp;
  const pnc::damage::NdmParameters ref = pnc::damage::dissertation_parameters(model);
  const int nk = static_cast<int>(ref.size());
  const int ns_model = pnc ? 6 : 2;

  // layout: mostly valid, sometimes anything
  int ntens = in.ConsumeBool() ? 6 : 4;
  if (in.ConsumeIntegralInRange<int>(0, 15) == 0) ntens = in.ConsumeIntegralInRange<int>(-2, 12);
  int ndi = 3, nshr = ntens == 6 ? 3 : 1;
  if (in.ConsumeIntegralInRange<int>(0, 15) == 0) ndi = in.ConsumeIntegralInRange<int>(-1, 6);
  if (in.ConsumeIntegralInRange<int>(0, 15) == 0) nshr = in.ConsumeIntegralInRange<int>(-1, 6);
  int nstatv = ns_model;
  if (in.ConsumeIntegralInRange<int>(0, 15) == 0) nstatv = in.ConsumeIntegralInRange<int>(-1, 8);
  const bool rotated = in.ConsumeBool();
  int nprops = 1 + nk + (rotated ? 9 : 0);
  if (in.ConsumeIntegralInRange<int>(0, 15) == 0) nprops = in.ConsumeIntegralInRange<int>(-1, 40);

  std::vector<double> props(kArray, 0.0);
  props[0] = pnc ? 1.0 : 2.0;
  if (in.ConsumeIntegralInRange<int>(0, 15) == 0) props[0] = fuzzed(in, props[0]);
  for (int i = 0; i < nk; ++i)
    props[static_cast<std::size_t>(1 + i)] = ref.k[static_cast<std::size_t>(i)];
  const int n_perturbed = in.ConsumeIntegralInRange<int>(0, 3);
  for (int i = 0; i < n_perturbed; ++i) {
    const auto j = in.ConsumeIntegralInRange<std::size_t>(1, static_cast<std::size_t>(nk));
    props[j] = fuzzed(in, props[j]);
  }
  if (rotated) {
    const double a = in.ConsumeFloatingPointInRange<double>(-4, 4);
    const double b = in.ConsumeFloatingPointInRange<double>(-4, 4);
    const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b);
    const double r[9] = {ca * cb, -sa, ca * sb, sa * cb, ca, sa * sb, -sb, 0, cb};
    for (int i = 0; i < 9; ++i)
      props[static_cast<std::size_t>(1 + nk + i)] = r[i];
    if (in.ConsumeBool()) {
      const auto j = in.ConsumeIntegralInRange<std::size_t>(static_cast<std::size_t>(1 + nk),
                                                            static_cast<std::size_t>(nk + 9));
      props[j] = fuzzed(in, props[j]);
    }
  }

  double statev[kArray], stress[kArray], ddsdde[kArray * kArray];
  double stran[kArray] = {}, dstran[kArray] = {};
  std::vector<double> state(kArray, 0.0); // Abaqus starts STATEV at zero
  if (in.ConsumeBool()) {
    const int j = in.ConsumeIntegralInRange<int>(0, ns_model - 1);
    state[static_cast<std::size_t>(j)] = fuzzed(in, 1.1);
  }
  const double scale = std::ldexp(1.0, in.ConsumeIntegralInRange<int>(-30, 4));
  const int steps = in.ConsumeIntegralInRange<int>(1, 6);
  const char cmname[80] = "PNC-FUZZ";
  const int noel = 1, npt = 1, zero = 0;
  // `unused` stands for DDSDDT, DRPLDE, DRPLDT, PREDEF, DPRED, COORDS, DROT, DFGRD0/1: umat_
  // reads none of them
  double sse = 0, spd = 0, scd = 0, rpl = 0, unused[36] = {}, time[2] = {0, 0}, dtime = 1, temp = 0,
         dtemp = 0;
  for (int step = 0; step < steps && in.remaining_bytes() > 0; ++step) {
    for (int a = 0; a < 6; ++a)
      dstran[a] = fuzzed(in, scale);
    fill_canary(stress, kArray, -1111.5);
    fill_canary(ddsdde, kArray * kArray, -2222.5);
    fill_canary(statev, kArray, -3333.5);
    for (int i = 0; i < ns_model && i < kArray; ++i)
      statev[i] = state[static_cast<std::size_t>(i)];
    double before[kArray];
    std::memcpy(before, statev, sizeof before);
    double pnewdt = 1.0;
    umat_(stress, statev, ddsdde, &sse, &spd, &scd, &rpl, unused, unused, unused, stran, dstran,
          time, &dtime, &temp, &dtemp, unused, unused, cmname, &ndi, &nshr, &ntens, &nstatv,
          props.data(), &nprops, unused, unused, &pnewdt, &dtime, unused, unused, &noel, &npt,
          &zero, &zero, &zero, &zero, sizeof cmname);
    if (pnewdt == 1.0) {
      // accepted: only valid layouts can get here
      if (ntens != 6 && ntens != 4) bug("accepted an invalid NTENS");
      if (nstatv != ns_model) bug("accepted a wrong NSTATV");
      if (is_canary(stress, 0, ntens, -1111.5)) bug("accepted without writing STRESS");
      if (!all_finite(stress, ntens)) bug("accepted with a non-finite STRESS");
      if (!all_finite(statev, nstatv)) bug("accepted with a non-finite STATEV");
      if (!all_finite(ddsdde, ntens * ntens)) bug("accepted with a non-finite DDSDDE");
      if (!is_canary(stress, ntens, kArray, -1111.5)) bug("wrote past STRESS(NTENS)");
      if (!is_canary(ddsdde, ntens * ntens, kArray * kArray, -2222.5))
        bug("wrote past DDSDDE(NTENS, NTENS)");
      if (!is_canary(statev, nstatv, kArray, -3333.5)) bug("wrote past STATEV(NSTATV)");
      for (int i = 0; i < ns_model; ++i)
        state[static_cast<std::size_t>(i)] = statev[i];
      for (int a = 0; a < 6; ++a)
        stran[a] += dstran[a];
    } else {
      if (pnewdt != 0.5) bug("a refusal did not set PNEWDT to 0.5");
      if (!is_canary(stress, 0, kArray, -1111.5)) bug("a refused call wrote STRESS");
      if (!is_canary(ddsdde, 0, kArray * kArray, -2222.5)) bug("a refused call wrote DDSDDE");
      if (std::memcmp(before, statev, sizeof before) != 0) bug("a refused call wrote STATEV");
      break;
    }
  }
  return 0;
}
