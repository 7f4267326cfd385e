// bench/dealii_fracture/bench_plugin_call.cpp: the cost of one material-plugin call, alone (no
// assembly around it), for the speed report of the deal.II demo (docs/dealii_demo.md, Speed;
// bench/dealii_fracture/bench_newton.sh reads it).
//
//   bench_dealii_plugin_call CARD.h5 [PLUGIN.so]
//
// The plugin is loaded at run time as the demo loads it (dlopen; default: the one built
// here). Plane-strain strain increments of the size seen in the demo: below the damage onset
// (elastic point) and past it with a loading mode (damaging point, tangent with the
// damage-growth term); 2,000,000 calls each, stress + consistent tangent, then the same
// points through the batched entry in batches of 256 (D311). The steady clock's
// own cost is printed too (the demo reads it once per 64 cells). Output: one JSON object,
// nanoseconds per call.
#include <pnc/fe_material/material.hpp>

#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <iostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#ifndef PNC_MATERIAL_PLUGIN_PATH
#define PNC_MATERIAL_PLUGIN_PATH "libpnc_material.so.1"
#endif

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::cerr << "usage: bench_dealii_plugin_call CARD.h5 [PLUGIN.so]\n";
    return 1;
  }
  using Clock = std::chrono::steady_clock;
  auto seconds_since = [](Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  };
  try {
    const pnc::fe_material::Plugin plugin(argc == 3 ? argv[2] : PNC_MATERIAL_PLUGIN_PATH);
    const auto mat = plugin.from_card(argv[1]);
    const int n = 2000000;
    std::vector<double> s0 = mat.initial_state(), s1(s0.size());
    std::array<double, 6> e0{}, sg{};
    std::array<double, 36> K{};
    nlohmann::json j;
    using Voigt6 = std::array<double, 6>; // 11 22 33 23 13 12, engineering shear
    const std::array<std::pair<const char*, Voigt6>, 2> cases{
        {{"elastic_point", Voigt6{0.01, 0.02, 0, 0, 0, 0.005}},
         {"damaging_point", Voigt6{0.01, 0.12, 0, 0, 0, 0.02}}}};
    double sink = 0;
    for (const auto& [name, de] : cases) {
      const auto t0 = Clock::now();
      for (int i = 0; i < n; ++i) {
        mat.try_integrate(s0.data(), s1.data(), e0.data(), de.data(), sg.data(), K.data(), nullptr,
                          0);
        sink += sg[1];
      }
      j[name]["ns_per_call_with_tangent"] = 1e9 * seconds_since(t0) / n;
      // The same points through the batched entry (ABI 1.2), in batches of 256: the 64 cells
      // x 4 points of one chunk of the demo's 2-D assembly (D311).
      const std::size_t nb = 256, ns = s0.size();
      std::vector<double> be0(6 * nb, 0.0), bde(6 * nb), bs0(ns * nb), bs1(ns * nb), bsg(6 * nb),
          bK(36 * nb);
      for (std::size_t p = 0; p < nb; ++p) {
        for (std::size_t k = 0; k < 6; ++k)
          bde[k * nb + p] = de[k];
        for (std::size_t k = 0; k < ns; ++k)
          bs0[k * nb + p] = s0[k];
      }
      pnc_material_point_soa b;
      pnc_material_point_soa_init(&b);
      b.tangent_request = PNC_MATERIAL_TANGENT_CONSISTENT;
      b.ld = nb;
      b.strain0 = be0.data();
      b.dstrain = bde.data();
      b.state0 = bs0.data();
      b.state1 = bs1.data();
      b.stress = bsg.data();
      b.tangent = bK.data();
      const std::size_t batches = static_cast<std::size_t>(n) / nb;
      const auto t1 = Clock::now();
      for (std::size_t i = 0; i < batches; ++i) {
        if (mat.try_integrate_batch(nb, &b) != PNC_MATERIAL_OK)
          throw std::runtime_error("the batched entry refused a batch");
        sink += bsg[nb];
      }
      j[name]["ns_per_point_batched_256_with_tangent"] = 1e9 * seconds_since(t1) / (batches * nb);
    }
    const auto t0 = Clock::now();
    for (int i = 0; i < n; ++i)
      sink += static_cast<double>(Clock::now().time_since_epoch().count() & 1);
    j["steady_clock_now_ns"] = 1e9 * seconds_since(t0) / n;
    j["calls"] = n;
    j["checksum"] = sink;
    std::cout << j.dump(2) << std::endl;
  } catch (const std::exception& e) {
    std::cerr << "bench_dealii_plugin_call: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
