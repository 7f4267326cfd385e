#pragma once
// Shared helpers of the ABI 1.2 (batched entry) tests, test_fe_material_batch.cpp and
// test_fe_material_batch_isa.cpp: test points on every path, the structure-of-arrays blocks of a
// batch with sentinels, and the point-by-point comparison with the single-point entry (stress,
// state and tangent bit for bit, stored energy within the bound of two summation orders).
// Internal to the tests.
#include "v2_support.hpp"

#include <cfloat>
#include <cstdint>
#include <random>

namespace pnc_batch_test {

using namespace pnc_v2_test;

// One point of a test batch: strain at the start, increment, start state (flat, n_state).
struct Point {
  Vec6 e0, de;
  std::vector<double> s0;
};

enum class Kind { elastic, damaging, unloading };

// The end state of the path 0 -> e through integrate2 (the single-point route, the reference).
inline std::vector<double> state_after(const pnc_material* m, const Vec6& e) {
  const std::vector<double> v = virgin(m);
  const Out o = call(m, v.data(), Vec6::Zero(), e, PNC_MATERIAL_TANGENT_NONE);
  EXPECT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
  return std::vector<double>(o.state1.begin(), o.state1.begin() + static_cast<long>(v.size()));
}

// A strain past the damage onset of the model (pnc: mode stretch alpha lambda_c = 1.07 along
// x2; pp: largest principal stretch 1.17), with random shears; zero out-of-plane components
// (e33 = g23 = g13 = 0) when `plane`.
inline Vec6 damaging_strain(Model model, std::mt19937_64& g, bool plane) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec6 e;
  e << 0.01 * u(g), (model == Model::pnc ? 0.12 : 0.22) + 0.01 * u(g), 0.01 * u(g), 0.02 * u(g),
      0.02 * u(g), 0.02 * u(g);
  if (plane) e[2] = e[3] = e[4] = 0.0;
  return e;
}

// n points: `share` of them elastic (small strain, virgin), damaging (loading past a history at
// 98 % of the strain) and unloading (back to 70 % of the history); every fifth point a plane
// strain, every seventh elastic one a pure extension (the kernel's tie case of the cap).
// `plane_every` = 1: every point a plane strain; 0: none, and no pure extension (no
// block-diagonal strain at all in an aligned frame).
inline std::vector<Point> make_points(const pnc_material* m, Model model, std::size_t n,
                                      unsigned seed, double elastic = 0.7, double damaging = 0.2,
                                      int plane_every = 5) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), pick(0.0, 1.0);
  std::vector<Point> pts;
  for (std::size_t i = 0; i < n; ++i) {
    const bool plane = plane_every > 0 && i % static_cast<std::size_t>(plane_every) == 0;
    const double r = pick(g);
    Point p;
    if (r < elastic) {
      Vec6 e;
      for (int k = 0; k < 6; ++k)
        e[k] = 0.01 * u(g);
      if (plane) e[2] = e[3] = e[4] = 0.0;
      if (plane_every > 0 && i % 7 == 0) { // pure extension along x1, x2 or x3
        e.setZero();
        e[static_cast<long>(i % 3)] = 0.02;
      }
      p.e0 = 0.9 * e;
      p.de = e - p.e0;
      p.s0 = virgin(m);
    } else {
      const Vec6 e = damaging_strain(model, g, plane);
      const bool loading = r < elastic + damaging;
      p.s0 = state_after(m, loading ? Vec6(0.98 * e) : e);
      p.e0 = loading ? Vec6(0.98 * e) : e;
      p.de = (loading ? e : Vec6(0.7 * e)) - p.e0;
    }
    pts.push_back(p);
  }
  return pts;
}

// The blocks of a batch (component k of point i at k * ld + i) with sentinels everywhere.
struct Blocks {
  std::size_t n, ld;
  int ns;
  std::vector<double> e0, de, s0, s1, sig, K, stored, diss;
  std::vector<int> status;
  Blocks(const std::vector<Point>& pts, int n_state, std::size_t pad = 0)
      : n(pts.size()), ld(pts.size() + pad), ns(n_state), e0(6 * ld, 0.0), de(6 * ld, 0.0),
        s0(static_cast<std::size_t>(ns) * ld, 1.0), s1(s0.size(), -99.0), sig(6 * ld, -99.0),
        K(36 * ld, -99.0), stored(ld, -99.0), diss(ld, -99.0), status(ld, -99) {
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < 6; ++k) {
        e0[k * ld + i] = pts[i].e0[static_cast<long>(k)];
        de[k * ld + i] = pts[i].de[static_cast<long>(k)];
      }
      for (std::size_t k = 0; k < static_cast<std::size_t>(ns); ++k)
        s0[k * ld + i] = pts[i].s0[k];
    }
  }
  pnc_material_point_soa view(int request, char* err, std::size_t err_len) {
    pnc_material_point_soa b;
    pnc_material_point_soa_init(&b);
    b.tangent_request = request;
    b.ld = ld;
    b.strain0 = e0.data();
    b.dstrain = de.data();
    b.state0 = s0.data();
    b.state1 = s1.data();
    b.stress = sig.data();
    b.tangent = request == PNC_MATERIAL_TANGENT_NONE ? nullptr : K.data();
    b.status = status.data();
    b.stored_energy = stored.data();
    b.dissipated_energy = diss.data();
    b.err = err;
    b.err_len = err_len;
    return b;
  }
};

inline bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Point i of the batch against integrate2 on the same inputs: stress, state, tangent bit for
// bit; stored energy within the bound of two summation orders of the same six products
// (each order errs by at most 5 u sum |sigma_k eps_k| (n - 1 = 5 additions), u = 2^-53, so
// the two differ by at most 10 u of it; the factor 1/2 is exact); dissipated energy exact.
inline void expect_point_equal(const pnc_material* m, const std::vector<Point>& pts,
                               const Blocks& b, std::size_t i, int request,
                               const std::string& what) {
  const Point& p = pts[i];
  const Out o = call(m, p.s0.data(), p.e0, p.de, request);
  ASSERT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
  ASSERT_EQ(b.status[i], PNC_MATERIAL_OK) << what << " point " << i;
  double sum = 0.0;
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_TRUE(same_bits(b.sig[k * b.ld + i], o.stress[k]))
        << what << " point " << i << " stress " << k << ": " << b.sig[k * b.ld + i] << " vs "
        << o.stress[k];
    sum += std::abs(o.stress[k] * (p.e0[static_cast<long>(k)] + p.de[static_cast<long>(k)]));
  }
  for (std::size_t k = 0; k < static_cast<std::size_t>(b.ns); ++k)
    EXPECT_TRUE(same_bits(b.s1[k * b.ld + i], o.state1[k]))
        << what << " point " << i << " state " << k << ": " << b.s1[k * b.ld + i] << " vs "
        << o.state1[k];
  if (request != PNC_MATERIAL_TANGENT_NONE) {
    for (std::size_t rc = 0; rc < 36; ++rc)
      EXPECT_TRUE(same_bits(b.K[rc * b.ld + i], o.K[rc]))
          << what << " point " << i << " tangent " << rc << ": " << b.K[rc * b.ld + i] << " vs "
          << o.K[rc];
  }
  EXPECT_LE(std::abs(b.stored[i] - o.stored), 10 * (DBL_EPSILON / 2) * 0.5 * sum)
      << what << " point " << i;
  EXPECT_TRUE(same_bits(b.diss[i], o.dissipated) || (b.diss[i] == 0.0 && o.dissipated == 0.0))
      << what << " point " << i << ": " << b.diss[i] << " vs " << o.dissipated;
}

// The kernel's structure-of-arrays view of a set of blocks.
inline pnc::damage::NdmBatch batch_view(Blocks& b, pnc::damage::TangentKind kind) {
  pnc::damage::NdmBatch view;
  view.n = b.n;
  view.ld = b.ld;
  view.eps0 = b.e0.data();
  view.deps = b.de.data();
  view.state0 = b.s0.data();
  view.state1 = b.s1.data();
  view.sigma = b.sig.data();
  view.K = b.K.data();
  view.stored = b.stored.data();
  view.dissipated = b.diss.data();
  view.status = b.status.data();
  view.kind = kind;
  return view;
}

// The points per path of a stress-only batch over a copy of b's blocks (b is not written).
inline pnc::damage::NdmBatchStats paths_of(const NdmParameters& p, const Blocks& b) {
  Blocks copy = b;
  return pnc::damage::integrate_batch(pnc::damage::prepare(p),
                                      batch_view(copy, pnc::damage::TangentKind::none));
}

// One batched call over pts with `request`, which must succeed for every point, and each point
// against the single-point entry, bit for bit.
inline void expect_batch_equals_single(const pnc_material* m, const std::vector<Point>& pts,
                                       int request, const std::string& what) {
  Blocks b(pts, pnc_material_n_state(m));
  char err[512] = {0};
  pnc_material_point_soa v = b.view(request, err, sizeof err);
  ASSERT_EQ(pnc_material_integrate_batch(m, b.n, &v), PNC_MATERIAL_OK) << what << ": " << err;
  EXPECT_EQ(v.n_failed, 0u) << what;
  for (std::size_t i = 0; i < b.n; ++i)
    expect_point_equal(m, pts, b, i, request, what);
}

} // namespace pnc_batch_test
