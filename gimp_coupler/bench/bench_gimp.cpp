// Benchmarks of the uGIMP step (gimp_coupler/bench/README.md): particle-steps per second for
// 2-D and 3-D with the hyperelastic polymer law, 1e4..1e6 particles, 1 and 2 threads, and a
// streaming loop over the same particle arrays (the memory-bandwidth ceiling).
#include "pnc/gimp_coupler/fracture.hpp"
#include "pnc/gimp_coupler/solver.hpp"

#include <benchmark/benchmark.h>

#include <sys/resource.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

using namespace pnc::gimp;

namespace {

/// Minor page faults of the process so far (all threads).
long minor_faults() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_minflt;
}

/// A block of N (about) particles, 2 per cell per axis, in a grid with a 2-cell margin (or,
/// with `wide`, a background grid 3 times the block per axis, empty beyond it, as when a body
/// may move or break up across a larger domain), small random-ish velocities so that stresses
/// are non-zero; the left face is fixed.
template <int D>
std::unique_ptr<Solver<D>> make_block(long n_target, int threads, bool wide = false) {
  using Vec = Eigen::Matrix<double, D, 1>;
  auto s = std::make_unique<Solver<D>>();
  const int ppc = 2;
  const long per_cell = D == 2 ? 4 : 8;
  const long cells_total = std::max(1L, n_target / per_cell);
  // Aspect 4:1(:1) block.
  const double side = std::pow(static_cast<double>(cells_total) / 4.0, 1.0 / D);
  std::array<int, D> nc{};
  for (int a = 0; a < D; ++a)
    nc[a] = std::max(1, static_cast<int>(std::lround(a == 0 ? 4 * side : side)));
  s->grid.h = 1e-3;
  for (int a = 0; a < D; ++a) {
    s->grid.origin[a] = -2e-3;
    s->grid.n[a] = (wide ? 3 * nc[a] : nc[a]) + 5;
  }
  s->materials.push_back(std::make_shared<HyperelasticPolymer>(1200, 1.8e8, 1.48e7));
  const double d = s->grid.h / ppc, V = std::pow(d, D);
  std::array<int, D> k{};
  std::array<int, D> np{};
  for (int a = 0; a < D; ++a)
    np[a] = nc[a] * ppc;
  while (true) {
    Vec x;
    for (int a = 0; a < D; ++a)
      x[a] = (k[a] + 0.5) * d;
    Vec v = Vec::Zero();
    v[0] = 1.0 * std::sin(3.0 * x[0] / (nc[0] * 1e-3));
    s->particles.add(x, Vec::Constant(0.5 * d), 1200 * V, V, 0, v);
    int a = 0;
    for (; a < D; ++a) {
      if (++k[a] < np[a]) break;
      k[a] = 0;
    }
    if (a == D) break;
  }
  NodeBC<D> wall;
  wall.lo = Vec::Constant(-1.0);
  wall.hi = Vec::Constant(1.0);
  wall.hi[0] = 0.0;
  wall.mask.fill(true);
  s->bcs.push_back(wall);
  s->threads = threads;
  s->initialize();
  return s;
}

// Three warm-up steps, then one step per iteration at half the stable time step; the counters
// every step benchmark reports (particles, threads, particle-steps/s in all and per thread) and,
// with count_faults, the minor page faults per timed step (the first-touch test of the README's
// bimodal step cost, D356).
template <int D>
void time_steps(benchmark::State& st, Solver<D>& s, int threads, bool count_faults) {
  const double dt = 0.5 * s.stable_dt();
  for (int i = 0; i < 3; ++i)
    s.step(dt); // warm-up
  const long faults0 = minor_faults();
  for (auto _ : st)
    s.step(dt);
  const auto n = static_cast<double>(s.particles.size());
  st.counters["particles"] = n;
  if (count_faults)
    st.counters["faults_per_step"] =
        static_cast<double>(minor_faults() - faults0) /
        static_cast<double>(std::max<benchmark::IterationCount>(1, st.iterations()));
  st.counters["threads"] = static_cast<double>(threads);
  st.counters["psteps_per_s"] =
      benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["psteps_per_s_per_thread"] = benchmark::Counter(
      n / static_cast<double>(threads), benchmark::Counter::kIsIterationInvariantRate);
}

template <int D> void BM_Step(benchmark::State& st) {
  auto s = make_block<D>(st.range(0), static_cast<int>(st.range(1)));
  if constexpr (D == 2) {
    if (st.range(2)) { // an edge crack from the top face to mid-height at x = 40 % of the block
      double xmax = 0, ymax = 0;
      for (const auto& x : s->particles.x) {
        xmax = std::max(xmax, x[0]);
        ymax = std::max(ymax, x[1]);
      }
      Crack c;
      c.points = {Eigen::Vector2d(0.4 * xmax + 1e-7, ymax + 1e-3),
                  Eigen::Vector2d(0.4 * xmax + 1e-7, 0.5 * ymax + 1e-7)};
      s->cracks.push_back(c);
      s->initialize();
    }
  }
  time_steps(st, *s, static_cast<int>(st.range(1)), true);
}

/// BM_Step's block (no crack) in a background grid 3 times its size per axis (D410: the thread
/// copies are zeroed and summed over the nodes the particles touch, not the whole grid).
template <int D> void BM_StepWideGrid(benchmark::State& st) {
  auto s = make_block<D>(st.range(0), static_cast<int>(st.range(1)), true);
  time_steps(st, *s, static_cast<int>(st.range(1)), false);
}

/// The step of a block whose particles were added in a shuffled order (as after much motion
/// or an unordered input), with the cell sort (D354) every `range(1)` steps (0: never).
template <int D> void BM_StepShuffled(benchmark::State& st) {
  auto s = make_block<D>(st.range(0), 1);
  auto& P = s->particles;
  std::vector<std::size_t> perm(P.size());
  for (std::size_t k = 0; k < perm.size(); ++k)
    perm[k] = k;
  std::uint64_t r = 12345;
  for (std::size_t k = perm.size() - 1; k > 0; --k) { // Fisher-Yates with a fixed LCG
    r = r * 6364136223846793005ULL + 1442695040888963407ULL;
    std::swap(perm[k], perm[static_cast<std::size_t>((r >> 33) % (k + 1))]);
  }
  auto shuffled = std::make_unique<Solver<D>>();
  shuffled->grid = s->grid;
  shuffled->materials = s->materials;
  shuffled->bcs = s->bcs;
  for (std::size_t k : perm)
    shuffled->particles.add(P.x[k], P.l[k], P.m[k], P.V0[k], P.mat[k], P.v[k]);
  shuffled->sort_every = static_cast<int>(st.range(1));
  shuffled->initialize();
  time_steps(st, *shuffled, 1, false);
}

/// One J / G_I / G_II evaluation (crack_tips, D38-D39) of the edge-cracked 2-D block of
/// BM_Step/N/1/1 after a few steps: compare with its step time (evaluated every
/// `fracture_every` = 10 steps by default).
void BM_CrackTips(benchmark::State& st) {
  auto s = make_block<2>(st.range(0), 1);
  double xmax = 0, ymax = 0;
  for (const auto& x : s->particles.x) {
    xmax = std::max(xmax, x[0]);
    ymax = std::max(ymax, x[1]);
  }
  Crack c;
  c.points = {Eigen::Vector2d(0.4 * xmax + 1e-7, ymax + 1e-3),
              Eigen::Vector2d(0.4 * xmax + 1e-7, 0.5 * ymax + 1e-7)};
  s->cracks.push_back(c);
  s->initialize();
  const double dt = 0.5 * s->stable_dt();
  for (int i = 0; i < 3; ++i)
    s->step(dt);
  for (auto _ : st) {
    const auto tips = crack_tips(*s);
    benchmark::DoNotOptimize(tips.data());
  }
  st.counters["particles"] = static_cast<double>(s->particles.size());
}

/// The bandwidth ceiling: one pass that reads and writes every particle array a step touches
/// (x, v, F, sigma, W, V) with trivial arithmetic, no grid.
template <int D> void BM_Stream(benchmark::State& st) {
  auto s = make_block<D>(st.range(0), 1);
  auto& P = s->particles;
  const double dt = 1e-9;
  for (auto _ : st) {
    for (std::size_t p = 0; p < P.size(); ++p) {
      P.x[p] += dt * P.v[p];
      P.v[p] *= 1.0 - 1e-12;
      P.F[p] *= 1.0 + 1e-15;
      P.sigma[p] *= 1.0 - 1e-15;
      P.W[p] += dt;
      P.V[p] = P.V0[p] * P.F[p](0, 0);
    }
    benchmark::ClobberMemory();
  }
  const auto n = static_cast<double>(P.size());
  st.counters["particles"] = n;
  st.counters["psteps_per_s"] =
      benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
}

/// Cost of the material law alone (hyperelastic, one particle update).
void BM_HyperelasticUpdate(benchmark::State& st) {
  const HyperelasticPolymer m(1200, 1.8e8, 1.48e7);
  Mat3 F;
  F << 1.01, 0.002, 0, -0.001, 0.995, 0, 0, 0, 1;
  Mat3 sig;
  double W;
  for (auto _ : st) {
    m.update(F, F, nullptr, nullptr, sig, W);
    benchmark::DoNotOptimize(sig);
    F(0, 0) += 1e-12;
  }
}

} // namespace

BENCHMARK_TEMPLATE(BM_Step, 2)
    ->ArgsProduct({{10000, 100000, 1000000}, {1, 2}, {0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// The same 2-D step with an edge crack (two velocity fields, contact): cost ratio.
BENCHMARK_TEMPLATE(BM_Step, 2)
    ->ArgsProduct({{10000, 100000}, {1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_TEMPLATE(BM_StepWideGrid, 2)
    ->ArgsProduct({{10000, 100000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_TEMPLATE(BM_StepWideGrid, 3)
    ->ArgsProduct({{10000, 100000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_CrackTips)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Step, 3)
    ->ArgsProduct({{10000, 100000, 1000000}, {1, 2}, {0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_TEMPLATE(BM_Stream, 2)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Stream, 3)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HyperelasticUpdate);
BENCHMARK_TEMPLATE(BM_StepShuffled, 2)
    ->ArgsProduct({{100000}, {0, 10}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_TEMPLATE(BM_StepShuffled, 3)
    ->ArgsProduct({{100000}, {0, 10}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// --ftz (our flag, removed before Google Benchmark reads the rest): flush-to-zero and
// denormals-are-zero in MXCSR, for the denormal hypothesis of the README's bimodal step cost
// (D356).
int main(int argc, char** argv) {
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    if (i > 0 && std::strcmp(argv[i], "--ftz") == 0) {
      _mm_setcsr(_mm_getcsr() | 0x8040); // FTZ (bit 15) | DAZ (bit 6)
      continue;
    }
    args.push_back(argv[i]);
  }
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
