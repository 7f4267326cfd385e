// bench_fit: wall time of the joint Ceres fit pnc::damage::fit_ndm() (see bench/README.md).
//
// The data are synthesised once, outside the timed loop, from the dissertation's constants
// (pnc::damage::dissertation_parameters) with Gaussian noise of sd 2 MPa, seed 1:
//   pnc : cases 1..6, 333 points each (1,998 points)
//   pp  : cases 2 and 6, 1,000 points each
// Each benchmark iteration is one complete fit_ndm() call with FitOptions{} (plus model and
// fit_alpha), i.e. including the regression initial guess, the Ceres solve, the covariance
// and the R^2 table. The counters report the Ceres solve alone (solve_s = FitReport::seconds),
// its iteration count and whether it converged; the label is the Ceres termination type.
#include "pnc/damage/fit.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/damage/synth.hpp"

#include <benchmark/benchmark.h>

#include <exception>
#include <string>

namespace {

using pnc::damage::FitOptions;
using pnc::damage::FitReport;
using pnc::damage::Model;
using pnc::damage::StressStrainData;
using pnc::damage::SynthOptions;

StressStrainData make_data(Model m) {
  SynthOptions o;
  if (m == Model::pnc) {
    o.cases = {1, 2, 3, 4, 5, 6};
    o.points = 333;
  } else {
    o.cases = {2, 6};
    o.points = 1000;
  }
  o.noise_sd = 2e6; // Pa
  o.seed = 1;
  return pnc::damage::synthesize(pnc::damage::dissertation_parameters(m), o);
}

template <Model M, bool FitAlpha> void BM_fit(benchmark::State& state) {
  StressStrainData data;
  try {
    data = make_data(M);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  FitOptions opt;
  opt.model = M;
  opt.alpha_mode = FitAlpha ? pnc::damage::AlphaMode::fit : pnc::damage::AlphaMode::hold;
  FitReport rep;
  try {
    for (auto _ : state) {
      rep = pnc::damage::fit_ndm(data, opt);
      // (the pointer, not rep.final_cost: benchmark 1.7.1's DoNotOptimize(double&) lets GCC
      // clobber the double in place, which corrupted the reported counter)
      benchmark::DoNotOptimize(&rep);
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  state.counters["points"] = static_cast<double>(data.points());
  state.counters["residuals"] = rep.residuals;
  state.counters["free_params"] = rep.free_parameters;
  state.counters["ceres_iter"] = rep.iterations;
  state.counters["converged"] = rep.converged ? 1 : 0;
  state.counters["solve_s"] = rep.seconds;
  state.counters["final_cost"] = rep.final_cost;
  state.counters["alpha"] = rep.params.alpha();
  state.SetLabel(rep.termination);
}

constexpr Model pnc_ = Model::pnc;
constexpr Model pp_ = Model::pp;

} // namespace

BENCHMARK_TEMPLATE(BM_fit, pnc_, false)
    ->Name("fit/pnc/6cases_x333")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_TEMPLATE(BM_fit, pnc_, true)
    ->Name("fit/pnc/6cases_x333/fit_alpha")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_TEMPLATE(BM_fit, pp_, false)
    ->Name("fit/pp/2cases_x1000")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_TEMPLATE(BM_fit, pp_, true)
    ->Name("fit/pp/2cases_x1000/fit_alpha")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
