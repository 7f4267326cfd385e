// bench/dealii_fracture/bench_plugin_call.cpp: the cost of one material-plugin call, alone (no
// assembly around it), for the speed report of the deal.II demo (docs/dealii_demo.md, Speed;
// bench/dealii_fracture/bench_newton.sh reads it).
//
//   bench_dealii_plugin_call CARD.h5 [PLUGIN.so]
//
// The plugin is loaded at run time as the demo loads it (dlopen; default: the one built
// here). Plane-strain strain increments of the size seen in the demo: below the damage onset
// (elastic point) and past it with a loading mode (damaging point, tangent with the
// damage-growth term); 2,000,000 calls each, stress + consistent tangent. The steady clock's
// own cost is printed too (the demo reads it once per 64 cells). Output: one JSON object,
// nanoseconds per call.
#include <pnc/fe_material/material.hpp>

#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <iostream>
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
