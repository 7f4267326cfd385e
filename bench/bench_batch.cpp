// bench_batch: the plugin's batched entry pnc_material_integrate_batch against the single-point
// entry pnc_material_integrate2 and a bare sigma = C eps loop over the same points
// (bench/README.md "Batched entry"; decisions D260-D263).
//
// The machine this runs on is shared, so absolute times drift: every repetition times the
// three variants back to back (in a rotating order) and the ratios are taken within a
// repetition; the report gives medians and ranges over the repetitions.
//
//   bench_batch [--points N] [--reps R] [--min-time S] [--scenario NAME] [--callgrind]
//
// --callgrind: run every variant once per scenario between callgrind client requests, for
// `valgrind --tool=callgrind --collect-atstart=no` (bench/batch_instructions.sh reads the
// per-variant instruction totals from the dumps, one dump per variant).
#include "pnc/damage/ndm.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/pnc_material.h"

#include <Eigen/Geometry>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_TOGGLE_COLLECT
#define CALLGRIND_DUMP_STATS_AT(name)
#endif

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

using pnc::damage::Model;
using pnc::damage::NdmParameters;
using pnc::damage::Voigt;

// One scenario: a model, a platelet orientation and a kind of strain, with the mix of points
// 70 % elastic, 20 % damaging, 10 % unloading in random order.
struct Scenario {
  const char* name;
  Model model;
  bool rotated;
  bool plane; // e33 = g23 = g13 = 0 (a 2-D plane-strain point)
};
const Scenario kScenarios[] = {
    {"pnc_3d", Model::pnc, false, false},   {"pnc_3d_rotated", Model::pnc, true, false},
    {"pnc_plane", Model::pnc, false, true}, {"pnc_plane_rotated_x3", Model::pnc, true, true},
    {"pp_3d", Model::pp, false, false},
};

Eigen::Matrix3d rotation(const Scenario& s) {
  const double deg = 3.14159265358979323846 / 180.0;
  if (!s.rotated) return Eigen::Matrix3d::Identity();
  if (s.plane) // about x3 only: plane strains stay block-diagonal in the platelet frame
    return Eigen::AngleAxisd(30 * deg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return (Eigen::AngleAxisd(20 * deg, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(30 * deg, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

// The points in both layouts: structure of arrays (blocks, ld = n) for the batch and the
// reference loop, one array per point (AoS) for the single-point entry.
struct Data {
  std::size_t n = 0;
  int ns = 0;
  std::vector<double> e0, de, s0, s1, sig, K, stored, diss; // SoA
  std::vector<int> status;
  std::vector<double> a_e0, a_de, a_s0, a_s1, a_sig, a_K; // AoS
  std::size_t elastic = 0, damaging = 0, unloading = 0;   // as generated
};

pnc_material* make_material(const Scenario& s) {
  const NdmParameters p = pnc::damage::dissertation_parameters(s.model);
  const Eigen::Matrix3d R = rotation(s);
  double R9[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      R9[3 * r + c] = R(r, c);
  char err[512];
  pnc_material* m =
      pnc_material_create_from_constants(pnc::damage::model_name(s.model), p.k.data(),
                                         static_cast<int>(p.size()), R9, err, sizeof err);
  if (!m) {
    std::fprintf(stderr, "bench_batch: %s\n", err);
    std::exit(1);
  }
  return m;
}

// integrate2 of one point (AoS arrays); exits on failure (the bench inputs are all valid).
void single(const pnc_material* m, const double* e0, const double* de, const double* s0, double* s1,
            double* sig, double* K, int request) {
  pnc_material_point pt;
  pnc_material_point_init(&pt);
  pt.tangent_request = request;
  pt.state0 = s0;
  pt.state1 = s1;
  pt.strain0 = e0;
  pt.dstrain = de;
  pt.stress = sig;
  pt.tangent = K;
  if (pnc_material_integrate2(m, &pt) != PNC_MATERIAL_OK) {
    std::fprintf(stderr, "bench_batch: integrate2 failed\n");
    std::exit(1);
  }
}

Data make_data(const pnc_material* m, const Scenario& s, std::size_t n, unsigned seed) {
  Data d;
  d.n = n;
  d.ns = pnc_material_n_state(m);
  const std::size_t ns = static_cast<std::size_t>(d.ns);
  d.e0.assign(6 * n, 0.0);
  d.de.assign(6 * n, 0.0);
  d.s0.assign(ns * n, 0.0);
  d.s1.assign(ns * n, 0.0);
  d.sig.assign(6 * n, 0.0);
  d.K.assign(36 * n, 0.0);
  d.stored.assign(n, 0.0);
  d.diss.assign(n, 0.0);
  d.status.assign(n, 0);
  d.a_e0.assign(6 * n, 0.0);
  d.a_de.assign(6 * n, 0.0);
  d.a_s0.assign(ns * n, 0.0);
  d.a_s1.assign(ns * n, 0.0);
  d.a_sig.assign(6 * n, 0.0);
  d.a_K.assign(36 * n, 0.0);
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), pick(0.0, 1.0);
  const double onset_strain = s.model == Model::pnc ? 0.12 : 0.20;
  std::vector<double> virgin(ns), hist(ns), scratch(36);
  pnc_material_init_state(m, virgin.data());
  for (std::size_t i = 0; i < n; ++i) {
    const double r = pick(g);
    Voigt e, e0, de;
    std::vector<double> st = virgin;
    if (r < 0.7) { // elastic: |components| <= 0.005, the last 10 % as the increment
      for (int k = 0; k < 6; ++k)
        e[k] = 0.005 * u(g);
      if (s.plane) e[2] = e[3] = e[4] = 0.0;
      e0 = 0.9 * e;
      ++d.elastic;
    } else { // past the onset along x2 (as bench_ndm's loading scenario)
      e << 0.01 * u(g), onset_strain + 0.01 * u(g), 0.01 * u(g), 0.02 * u(g), 0.02 * u(g),
          0.02 * u(g);
      if (s.plane) e[2] = e[3] = e[4] = 0.0;
      const bool damaging = r < 0.9;
      const Voigt h = damaging ? Voigt(0.98 * e) : e; // the history's largest strain
      const Voigt z = Voigt::Zero();
      double sig[6];
      single(m, z.data(), h.data(), virgin.data(), hist.data(), sig, scratch.data(),
             PNC_MATERIAL_TANGENT_NONE);
      st = hist;
      e0 = h;
      if (!damaging) e = 0.7 * h; // unloading to 70 %
      ++(damaging ? d.damaging : d.unloading);
    }
    de = e - e0;
    for (std::size_t k = 0; k < 6; ++k) {
      d.e0[k * n + i] = d.a_e0[6 * i + k] = e0[static_cast<long>(k)];
      d.de[k * n + i] = d.a_de[6 * i + k] = de[static_cast<long>(k)];
    }
    for (std::size_t k = 0; k < ns; ++k)
      d.s0[k * n + i] = d.a_s0[ns * i + k] = st[k];
  }
  return d;
}

using Clock = std::chrono::steady_clock;

// The three variants over the same points.
void run_batch(const pnc_material* m, Data& d, int request) {
  pnc_material_point_soa b;
  pnc_material_point_soa_init(&b);
  b.tangent_request = request;
  b.ld = d.n;
  b.strain0 = d.e0.data();
  b.dstrain = d.de.data();
  b.state0 = d.s0.data();
  b.state1 = d.s1.data();
  b.stress = d.sig.data();
  b.tangent = request == PNC_MATERIAL_TANGENT_NONE ? nullptr : d.K.data();
  b.status = d.status.data();
  if (pnc_material_integrate_batch(m, d.n, &b) != PNC_MATERIAL_OK) {
    std::fprintf(stderr, "bench_batch: the batch failed\n");
    std::exit(1);
  }
}

void run_single(const pnc_material* m, Data& d, int request) {
  const std::size_t ns = static_cast<std::size_t>(d.ns);
  for (std::size_t i = 0; i < d.n; ++i)
    single(m, &d.a_e0[6 * i], &d.a_de[6 * i], &d.a_s0[ns * i], &d.a_s1[ns * i], &d.a_sig[6 * i],
           request == PNC_MATERIAL_TANGENT_NONE ? nullptr : &d.a_K[36 * i], request);
}

// sigma = C eps (eps = eps0 + deps) and K = C over the same blocks: the floor of any law.
// Compiled, like the batch (D386), for the baseline and for AVX2 (chosen at load time).
__attribute__((noinline, target_clones("avx2", "default"))) void
run_reference(const double* C, Data& d, bool tangent) {
  const std::size_t n = d.n;
  const double* __restrict e0 = d.e0.data();
  const double* __restrict de = d.de.data();
  double* __restrict sig = d.sig.data();
  double* __restrict K = d.K.data();
  // The row's constants in locals, the twelve blocks as named pointers and no alias checks: the
  // loop over points then vectorises (before, the strided form C[6 r + c] * e0[c n + i] did not).
  const double* a[6];
  const double* b[6];
  for (std::size_t k = 0; k < 6; ++k) {
    a[k] = e0 + k * n;
    b[k] = de + k * n;
  }
  const double *a0 = a[0], *a1 = a[1], *a2 = a[2], *a3 = a[3], *a4 = a[4], *a5 = a[5];
  const double *d0 = b[0], *d1 = b[1], *d2 = b[2], *d3 = b[3], *d4 = b[4], *d5 = b[5];
  for (int r = 0; r < 6; ++r) {
    const double* c = C + 6 * r;
    const double c0 = c[0], c1 = c[1], c2 = c[2], c3 = c[3], c4 = c[4], c5 = c[5];
    double* __restrict o = sig + static_cast<std::size_t>(r) * n;
#pragma GCC ivdep // the blocks do not overlap (else GCC wants 12 alias checks, over its limit)
    for (std::size_t i = 0; i < n; ++i)
      o[i] = c0 * (a0[i] + d0[i]) + c1 * (a1[i] + d1[i]) + c2 * (a2[i] + d2[i]) +
             c3 * (a3[i] + d3[i]) + c4 * (a4[i] + d4[i]) + c5 * (a5[i] + d5[i]);
  }
  if (tangent)
    for (std::size_t rc = 0; rc < 36; ++rc)
      for (std::size_t i = 0; i < n; ++i)
        K[rc * n + i] = C[rc];
}

// The batch's outputs against the single-point entry's, bit for bit (stress, state, tangent).
std::size_t mismatches(const Data& d, int request) {
  std::size_t bad = 0;
  const std::size_t n = d.n, ns = static_cast<std::size_t>(d.ns);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < 6; ++k)
      bad += std::memcmp(&d.sig[k * n + i], &d.a_sig[6 * i + k], sizeof(double)) != 0;
    for (std::size_t k = 0; k < ns; ++k)
      bad += std::memcmp(&d.s1[k * n + i], &d.a_s1[ns * i + k], sizeof(double)) != 0;
    if (request != PNC_MATERIAL_TANGENT_NONE)
      for (std::size_t rc = 0; rc < 36; ++rc)
        bad += std::memcmp(&d.K[rc * n + i], &d.a_K[36 * i + rc], sizeof(double)) != 0;
  }
  return bad;
}

struct Stat {
  double median, lo, hi;
};
Stat stat_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t k = v.size();
  const double med = k % 2 ? v[k / 2] : 0.5 * (v[k / 2 - 1] + v[k / 2]);
  return {med, v.front(), v.back()};
}

struct Options {
  std::size_t points = 4096;
  int reps = 15;
  double min_time = 0.05;
  std::string only;
  bool callgrind = false;
};

void bench_scenario(const Scenario& s, const Options& o, int request) {
  pnc_material* m = make_material(s);
  Data d = make_data(m, s, o.points, 20261203u + static_cast<unsigned>(s.model));
  double C[36];
  pnc_material_elastic_stiffness(m, C);
  const bool tangent = request != PNC_MATERIAL_TANGENT_NONE;
  const char* what = request == PNC_MATERIAL_TANGENT_CONSISTENT ? "stress+tangent" : "stress";
  auto variant = [&](int v) {
    if (v == 0) run_reference(C, d, tangent);
    if (v == 1) run_batch(m, d, request);
    if (v == 2) run_single(m, d, request);
  };
  const char* names[3] = {"reference", "batch", "single"};
  if (o.callgrind) {
    for (int v = 0; v < 3; ++v) {
      variant(v); // warm
      CALLGRIND_TOGGLE_COLLECT;
      variant(v);
      CALLGRIND_TOGGLE_COLLECT;
      const std::string tag =
          std::string(s.name) + "/" + what + "/" + names[v] + "/" + std::to_string(d.n);
      CALLGRIND_DUMP_STATS_AT(tag.c_str());
    }
    pnc_material_destroy(m);
    return;
  }
  // calls per sample so that a sample lasts about min_time
  int calls[3];
  for (int v = 0; v < 3; ++v) {
    const auto t0 = Clock::now();
    variant(v);
    const double t = std::chrono::duration<double>(Clock::now() - t0).count();
    calls[v] = std::max(1, static_cast<int>(o.min_time / std::max(t, 1e-9)));
  }
  std::vector<double> ns[3], r_single_batch, r_batch_ref, r_single_ref;
  for (int rep = 0; rep < o.reps; ++rep) {
    double t[3];
    for (int j = 0; j < 3; ++j) {
      const int v = (j + rep) % 3; // rotating order
      const auto t0 = Clock::now();
      for (int c = 0; c < calls[v]; ++c)
        variant(v);
      t[v] = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() /
             (static_cast<double>(calls[v]) * static_cast<double>(d.n));
      ns[v].push_back(t[v]);
    }
    r_single_batch.push_back(t[2] / t[1]);
    r_batch_ref.push_back(t[1] / t[0]);
    r_single_ref.push_back(t[2] / t[0]);
  }
  run_batch(m, d, request);
  run_single(m, d, request);
  const std::size_t bad = mismatches(d, request);
  pnc::damage::NdmParameters p = pnc::damage::dissertation_parameters(s.model);
  p.R = rotation(s);
  pnc::damage::NdmBatch v;
  v.n = d.n;
  v.ld = d.n;
  v.eps0 = d.e0.data();
  v.deps = d.de.data();
  v.state0 = d.s0.data();
  v.state1 = d.s1.data();
  v.sigma = d.sig.data();
  const auto paths = pnc::damage::integrate_batch(pnc::damage::prepare(p), v);
  std::printf("%-22s %-14s n=%zu (generated %zu elastic / %zu damaging / %zu unloading; batch "
              "paths %zu elastic / %zu unloading / %zu growth pass / %zu kernel)\n",
              s.name, what, d.n, d.elastic, d.damaging, d.unloading, paths.elastic, paths.unloading,
              paths.growth, paths.kernel);
  for (int k = 0; k < 3; ++k) {
    const Stat st = stat_of(ns[k]);
    std::printf("  %-10s %8.1f ns/eval [%6.1f, %6.1f]  %7.2f M eval/s\n", names[k], st.median,
                st.lo, st.hi, 1e3 / st.median);
  }
  const Stat a = stat_of(r_single_batch), b = stat_of(r_batch_ref), c = stat_of(r_single_ref);
  std::printf("  ratios (median [range] over %d reps): single/batch %.2f [%.2f, %.2f]  "
              "batch/ref %.1f [%.1f, %.1f]  single/ref %.1f [%.1f, %.1f]\n",
              o.reps, a.median, a.lo, a.hi, b.median, b.lo, b.hi, c.median, c.lo, c.hi);
  std::printf("  batch vs single: %zu of %zu output values differ in any bit\n", bad,
              d.n * (6 + static_cast<std::size_t>(d.ns) + (tangent ? 36 : 0)));
  pnc_material_destroy(m);
}

} // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_batch: option '%s' needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--points")
      o.points = static_cast<std::size_t>(std::strtoull(next(), nullptr, 10));
    else if (a == "--reps")
      o.reps = std::atoi(next());
    else if (a == "--min-time")
      o.min_time = std::atof(next());
    else if (a == "--scenario")
      o.only = next();
    else if (a == "--callgrind")
      o.callgrind = true;
    else {
      std::fprintf(stderr,
                   "bench_batch: unknown option '%s' (--points N, --reps R, --min-time S, "
                   "--scenario NAME, --callgrind)\n",
                   a.c_str());
      return 2;
    }
  }
  if (o.points == 0 || o.reps < 1 || !(o.min_time > 0)) {
    std::fprintf(stderr, "bench_batch: --points and --reps must be >= 1, --min-time > 0\n");
    return 2;
  }
  using pnc::damage::BatchIsa;
  std::printf("batch loops: %s (pnc::damage::BatchIsa, D386, D413)\n",
              pnc::damage::batch_isa_available(BatchIsa::avx512) ? "AVX-512"
              : pnc::damage::batch_isa_available(BatchIsa::avx2) ? "AVX2"
                                                                 : "SSE2");
  for (const Scenario& s : kScenarios) {
    if (!o.only.empty() && o.only != s.name) continue;
    for (const int request : {PNC_MATERIAL_TANGENT_CONSISTENT, PNC_MATERIAL_TANGENT_NONE})
      bench_scenario(s, o, request);
  }
  return 0;
}
