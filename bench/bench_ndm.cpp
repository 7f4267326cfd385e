// bench_ndm: throughput of the NDM kernel pnc::damage::integrate() (see bench/README.md).
//
// Every benchmark iteration sweeps a pre-generated batch of kBatch varied strain increments
// (so branch prediction and caches see realistic, non-repeating inputs) and reports
// items_per_second = kernel evaluations per second on one core.
//
//   BM_ndm<model, scenario, tangent>  model    : pnc (three modes) or pp (one mode)
//                                     scenario : elastic (small strain, no damage),
//                                                loading (past damage onset, damage growing),
//                                                rotated (loading with a non-identity R)
//                                     tangent  : stress + consistent tangent, or stress only
//   BM_reference<tangent>             sigma = C eps with a fixed 6x6 C over the same arrays
//                                     (the simplest possible "law"; K = C when asked), the
//                                     yardstick for the kernel's cost ratio.
#include "pnc/damage/ndm.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/pnc_material.h"

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace {

using pnc::damage::ErrorBuffer;
using pnc::damage::Matrix6;
using pnc::damage::Model;
using pnc::damage::NdmParameters;
using pnc::damage::NdmState;
using pnc::damage::Status;
using pnc::damage::Voigt;

constexpr std::size_t kBatch = 4096;

enum class Scenario { elastic, loading, rotated, rotated_elastic, plane_elastic };

/// One batch of kernel inputs: start states, start strains and increments.
struct Batch {
  NdmParameters p;
  std::vector<NdmState> s0;
  std::vector<Voigt> eps0, deps;
  double damaged_fraction = 0; ///< share of points with some D > 0 at the end of the step
  double loading_fraction = 0; ///< share of points where some damaged mode grows (kappa up)
};

/// Platelet rotation used by the `rotated` scenario: 30 deg about x3, then 20 deg about x1.
Eigen::Matrix3d platelet_rotation() {
  const double deg = 3.14159265358979323846 / 180.0;
  return (Eigen::AngleAxisd(20 * deg, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(30 * deg, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

/// Builds the batch for one model and scenario (fixed seed: every run sees the same inputs).
///  elastic : total strain with |normal| <= 0.005 and |shear| <= 0.005, virgin state; the
///            increment is the last 10 % of it. No mode reaches damage onset.
///  loading : extension along x2 of 0.12 +- 0.01 (pnc) or 0.20 +- 0.01 (pp: its onset is at
///            alpha lambda_c - 1 = 0.171), lateral normals +-0.01, shears +-0.02. The start
///            state is the kernel's state at 98 % of that strain, the increment the last 2 %:
///            a monotonic loading step with damage growing.
///  rotated : as loading, with the platelet rotated by platelet_rotation().
Batch make_batch(Model model, Scenario scenario) {
  Batch b;
  b.p = pnc::damage::dissertation_parameters(model);
  const bool elastic = scenario == Scenario::elastic || scenario == Scenario::rotated_elastic ||
                       scenario == Scenario::plane_elastic;
  if (scenario == Scenario::rotated || scenario == Scenario::rotated_elastic)
    b.p.R = platelet_rotation();
  if (scenario == Scenario::plane_elastic) // 2-D plane strain, platelet 0.5 deg about x3
    b.p.R = Eigen::AngleAxisd(0.5 * 3.14159265358979323846 / 180.0, Eigen::Vector3d::UnitZ())
                .toRotationMatrix();
  std::mt19937_64 rng(20240601u + static_cast<unsigned>(model) * 7u +
                      static_cast<unsigned>(scenario));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double stretch = model == Model::pnc ? 0.12 : 0.20;
  b.s0.resize(kBatch);
  b.eps0.resize(kBatch);
  b.deps.resize(kBatch);
  ErrorBuffer err;
  std::size_t damaged = 0, loading = 0;
  for (std::size_t i = 0; i < kBatch; ++i) {
    Voigt eps;
    double fraction;
    if (elastic) {
      for (int j = 0; j < 6; ++j)
        eps[j] = 0.005 * u(rng);
      if (scenario == Scenario::plane_elastic) eps[2] = eps[3] = eps[4] = 0.0;
      fraction = 0.9;
    } else {
      eps << 0.01 * u(rng), stretch + 0.01 * u(rng), 0.01 * u(rng), 0.02 * u(rng), 0.02 * u(rng),
          0.02 * u(rng);
      fraction = 0.98;
    }
    b.eps0[i] = fraction * eps;
    b.deps[i] = eps - b.eps0[i];
    NdmState virgin, s1;
    Voigt sigma;
    if (!elastic) {
      // start state = the kernel's own state after loading to eps0 from a virgin state
      pnc::damage::integrate(b.p, virgin, b.s0[i], Voigt::Zero(), b.eps0[i], sigma, nullptr, err);
    }
    pnc::damage::integrate(b.p, b.s0[i], s1, b.eps0[i], b.deps[i], sigma, nullptr, err);
    bool any_damage = false, any_loading = false;
    for (int m = 0; m < 3; ++m) {
      if (s1.D[m] != 0.0) any_damage = true;
      if (s1.D[m] != 0.0 && s1.kappa[m] > b.s0[i].kappa[m]) any_loading = true;
    }
    damaged += any_damage ? 1 : 0;
    loading += any_loading ? 1 : 0;
  }
  b.damaged_fraction = static_cast<double>(damaged) / kBatch;
  b.loading_fraction = static_cast<double>(loading) / kBatch;
  return b;
}

const char* scenario_name(Scenario s) {
  switch (s) {
  case Scenario::elastic:
    return "elastic";
  case Scenario::loading:
    return "loading";
  case Scenario::rotated:
    return "rotated";
  case Scenario::rotated_elastic:
    return "rotated_elastic";
  case Scenario::plane_elastic:
    return "plane_elastic";
  }
  return "?";
}

/// Prepared: through integrate(prepare(p), ...), as the material plugin calls it (the
/// rotation and the rotated stiffness pieces built once), instead of integrate(p, ...).
template <Model M, Scenario S, bool Tangent, bool Prepared = false>
void BM_ndm(benchmark::State& state) {
  const Batch b = make_batch(M, S);
  const pnc::damage::PreparedNdm q = pnc::damage::prepare(b.p);
  const bool elastic =
      S == Scenario::elastic || S == Scenario::rotated_elastic || S == Scenario::plane_elastic;
  if (!elastic && b.loading_fraction < 1.0) {
    state.SkipWithError("batch is not entirely past damage onset with damage growing");
    return;
  }
  std::vector<NdmState> s1(kBatch);
  std::vector<Voigt> sigma(kBatch);
  Matrix6 K;
  ErrorBuffer err;
  int bad = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      const Status st = Prepared ? pnc::damage::integrate(q, b.s0[i], s1[i], b.eps0[i], b.deps[i],
                                                          sigma[i], Tangent ? &K : nullptr, err)
                                 : pnc::damage::integrate(b.p, b.s0[i], s1[i], b.eps0[i], b.deps[i],
                                                          sigma[i], Tangent ? &K : nullptr, err);
      bad += st != Status::ok;
      if (Tangent) benchmark::DoNotOptimize(K.data());
    }
    benchmark::DoNotOptimize(sigma.data());
    benchmark::DoNotOptimize(s1.data());
    benchmark::ClobberMemory();
  }
  if (bad != 0) state.SkipWithError(err.msg);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(kBatch));
  state.counters["damaged"] = b.damaged_fraction;
  state.counters["time_per_eval"] = benchmark::Counter(
      static_cast<double>(kBatch),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(std::string(pnc::damage::model_name(M)) + " " + scenario_name(S) +
                 (Tangent ? " stress+tangent" : " stress") + (Prepared ? " prepared" : ""));
}

/// The same batch through the material plugin's C entry point, pnc_material_integrate()
/// (state, strain, stress and row-major tangent as the host's arrays), on a material made
/// from the batch's constants and rotation: the cost a finite-element host pays per point.
template <Scenario S> void BM_plugin(benchmark::State& state) {
  const Batch b = make_batch(Model::pnc, S);
  char err[256] = {0};
  double R[9];
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{R} = b.p.R;
  const std::size_t nk = b.p.size();
  pnc_material* m = pnc_material_create_from_constants("pnc", b.p.k.data(), static_cast<int>(nk), R,
                                                       err, sizeof err);
  if (!m) {
    state.SkipWithError(err);
    return;
  }
  const int ns = pnc_material_n_state(m);
  std::vector<double> s0(kBatch * static_cast<std::size_t>(ns)), s1(s0.size());
  for (std::size_t i = 0; i < kBatch; ++i)
    pnc::damage::state_to_array(Model::pnc, b.s0[i], &s0[i * static_cast<std::size_t>(ns)]);
  std::vector<Voigt> sigma(kBatch);
  std::vector<double> K(36);
  int bad = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      const std::size_t o = i * static_cast<std::size_t>(ns);
      bad += pnc_material_integrate(m, &s0[o], &s1[o], b.eps0[i].data(), b.deps[i].data(),
                                    sigma[i].data(), K.data(), err, sizeof err) != 0;
      benchmark::DoNotOptimize(K.data());
    }
    benchmark::DoNotOptimize(sigma.data());
    benchmark::DoNotOptimize(s1.data());
    benchmark::ClobberMemory();
  }
  pnc_material_destroy(m);
  if (bad != 0) state.SkipWithError(err);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(kBatch));
  state.counters["time_per_eval"] = benchmark::Counter(
      static_cast<double>(kBatch),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(std::string("pnc ") + scenario_name(S) + " stress+tangent, plugin C ABI");
}

/// The yardstick: sigma = C eps (C = the pnc model's undamaged stiffness, fixed) over the
/// same strain arrays, writing sigma (and K = C when Tangent) exactly where the kernel does.
template <bool Tangent> void BM_reference(benchmark::State& state) {
  const Batch b = make_batch(Model::pnc, Scenario::loading);
  const Matrix6 C = pnc::damage::stiffness_c0(b.p);
  std::vector<Voigt> sigma(kBatch);
  Matrix6 K;
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      const Voigt eps = b.eps0[i] + b.deps[i];
      sigma[i].noalias() = C * eps;
      if (Tangent) {
        K = C;
        benchmark::DoNotOptimize(K.data());
        benchmark::ClobberMemory();
      }
    }
    benchmark::DoNotOptimize(sigma.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(kBatch));
  state.counters["time_per_eval"] = benchmark::Counter(
      static_cast<double>(kBatch),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(Tangent ? "sigma = C eps, K = C" : "sigma = C eps");
}

constexpr Model pnc_ = Model::pnc;
constexpr Model pp_ = Model::pp;
constexpr Scenario elastic_ = Scenario::elastic;
constexpr Scenario loading_ = Scenario::loading;
constexpr Scenario rotated_ = Scenario::rotated;
constexpr Scenario rotated_elastic_ = Scenario::rotated_elastic;
constexpr Scenario plane_elastic_ = Scenario::plane_elastic;

} // namespace

BENCHMARK_TEMPLATE(BM_reference, true)->Name("reference/C_eps/stress+tangent");
BENCHMARK_TEMPLATE(BM_reference, false)->Name("reference/C_eps/stress");

BENCHMARK_TEMPLATE(BM_ndm, pnc_, elastic_, true)->Name("ndm/pnc/elastic/stress+tangent");
BENCHMARK_TEMPLATE(BM_ndm, pnc_, elastic_, false)->Name("ndm/pnc/elastic/stress");
BENCHMARK_TEMPLATE(BM_ndm, pnc_, loading_, true)->Name("ndm/pnc/loading/stress+tangent");
BENCHMARK_TEMPLATE(BM_ndm, pnc_, loading_, false)->Name("ndm/pnc/loading/stress");
BENCHMARK_TEMPLATE(BM_ndm, pnc_, rotated_, true)->Name("ndm/pnc/rotated/stress+tangent");
BENCHMARK_TEMPLATE(BM_ndm, pnc_, rotated_, false)->Name("ndm/pnc/rotated/stress");
BENCHMARK_TEMPLATE(BM_ndm, pnc_, rotated_elastic_, true)
    ->Name("ndm/pnc/rotated_elastic/stress+tangent");
// As the material plugin calls the kernel (integrate(prepare(p), ...)).
BENCHMARK_TEMPLATE(BM_ndm, pnc_, rotated_, true, true)
    ->Name("ndm/pnc/rotated/stress+tangent/prepared");
BENCHMARK_TEMPLATE(BM_ndm, pnc_, rotated_elastic_, true, true)
    ->Name("ndm/pnc/rotated_elastic/stress+tangent/prepared");
// The typical point of a 2-D fracture run (the deal.II demo): plane strain, elastic, the
// platelet misaligned by 0.5 deg about x3 (D58).
BENCHMARK_TEMPLATE(BM_ndm, pnc_, plane_elastic_, true)
    ->Name("ndm/pnc/plane_elastic/stress+tangent");
BENCHMARK_TEMPLATE(BM_ndm, pnc_, plane_elastic_, true, true)
    ->Name("ndm/pnc/plane_elastic/stress+tangent/prepared");
// The same two batches through the plugin's pnc_material_integrate().
BENCHMARK_TEMPLATE(BM_plugin, plane_elastic_)->Name("ndm/pnc/plane_elastic/stress+tangent/plugin");
BENCHMARK_TEMPLATE(BM_plugin, rotated_)->Name("ndm/pnc/rotated/stress+tangent/plugin");

BENCHMARK_TEMPLATE(BM_ndm, pp_, elastic_, true)->Name("ndm/pp/elastic/stress+tangent");
BENCHMARK_TEMPLATE(BM_ndm, pp_, elastic_, false)->Name("ndm/pp/elastic/stress");
BENCHMARK_TEMPLATE(BM_ndm, pp_, loading_, true)->Name("ndm/pp/loading/stress+tangent");
BENCHMARK_TEMPLATE(BM_ndm, pp_, loading_, false)->Name("ndm/pp/loading/stress");
BENCHMARK_TEMPLATE(BM_ndm, pp_, rotated_, true)->Name("ndm/pp/rotated/stress+tangent");
BENCHMARK_TEMPLATE(BM_ndm, pp_, rotated_, false)->Name("ndm/pp/rotated/stress");
