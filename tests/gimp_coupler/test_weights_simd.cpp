// The branch-free uGIMP weights (weights_simd.hpp, D376, D377): the baseline and the AVX2 builds
// equal the if-chain ugimp_weight bit for bit (both run the same operations in the same order;
// only the selection of the piece differs), at and next to every breakpoint, for NaN and +-inf,
// for l = L/2 (coinciding breakpoints), and the batched per-axis weights of whole particles equal
// the per-node ugimp_weight of the same offsets.
#include "pnc/core/cpu.hpp"
#include "pnc/gimp_coupler/stencil_weights.hpp"
#include "pnc/gimp_coupler/weights.hpp"
#include "pnc/gimp_coupler/weights_simd.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace pnc::gimp;

namespace {

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Offsets xi for cell size L and half-length l: each breakpoint, its neighbours one and two ulps
// away, random points over the whole support and beyond, zero, NaN and +-inf.
std::vector<double> probe_points(double L, double l, std::mt19937& rng) {
  std::vector<double> xs;
  const double inf = std::numeric_limits<double>::infinity();
  for (double xb : {-L - l, -L + l, -l, l, L - l, L + l, 0.0, -0.0}) {
    double lo = xb, hi = xb;
    xs.push_back(xb);
    for (int k = 0; k < 2; ++k) {
      lo = std::nextafter(lo, -inf);
      hi = std::nextafter(hi, inf);
      xs.push_back(lo);
      xs.push_back(hi);
    }
  }
  std::uniform_real_distribution<double> u(-1.5 * L - l, 1.5 * L + l);
  for (int k = 0; k < 997; ++k) // odd count: the vector loops' remainders run too
    xs.push_back(u(rng));
  xs.push_back(std::numeric_limits<double>::quiet_NaN());
  xs.push_back(inf);
  xs.push_back(-inf);
  return xs;
}

using Kernel = void (*)(std::size_t, const double*, const double*, double, double*, double*);

void expect_equals_table(Kernel kernel, const char* build) {
  std::mt19937 rng(11);
  for (double L : {1e-3, 0.2, 3.0})
    for (double lfrac : {1e-3, 0.1, 0.25, 1.0 / 3.0, 0.5}) { // 0.5: l = L/2, breakpoints coincide
      const double l = lfrac * L;
      const std::vector<double> xs = probe_points(L, l, rng);
      const std::vector<double> ls(xs.size(), l);
      std::vector<double> S(xs.size()), dS(xs.size());
      kernel(xs.size(), xs.data(), ls.data(), L, S.data(), dS.data());
      int bad = 0;
      for (std::size_t k = 0; k < xs.size() && bad < 5; ++k) {
        const Weight1D r = ugimp_weight(xs[k], L, l);
        const bool nan_both = std::isnan(r.S) && std::isnan(S[k]);
        if ((!nan_both && !same_bits(r.S, S[k])) || !same_bits(r.dS, dS[k])) {
          ++bad;
          ADD_FAILURE() << build << ": xi = " << xs[k] << ", L = " << L << ", l = " << l
                        << ": S = " << S[k] << " vs " << r.S << ", dS = " << dS[k] << " vs "
                        << r.dS;
        }
      }
    }
}

} // namespace

TEST(GimpWeightsSimd, BaselineBuildEqualsTableBitForBit) {
  expect_equals_table(simd::ugimp_weights_default, "baseline");
}

#if PNC_HAVE_AVX2_COPY && PNC_TEST_CPU_HAS_AVX2
// The AVX2 build is called explicitly; compiled only where the configure check found AVX2
// (tests/CMakeLists.txt; tests/core/test_cpu.cpp checks that the library agrees).
TEST(GimpWeightsSimd, Avx2BuildEqualsTableBitForBit) {
  expect_equals_table(simd::ugimp_weights_avx2, "avx2");
}
#endif

#if PNC_HAVE_AVX2_COPY && PNC_TEST_CPU_HAS_AVX512
// The same for the AVX-512 build (D414).
TEST(GimpWeightsSimd, Avx512BuildEqualsTableBitForBit) {
  expect_equals_table(simd::ugimp_weights_avx512, "avx512");
}
#endif

TEST(GimpWeightsSimd, DispatchEqualsTableBitForBit) {
  expect_equals_table(ugimp_weights, "dispatch");
}

// Whole particles in 3-D (chunks of 64 and a remainder): the batched per-axis weights equal
// ugimp_weight of each node's offset bit for bit, and the first particle that leaves the grid is
// reported.
TEST(GimpWeightsSimd, ManyParticlesEqualPerNodeTable) {
  Grid<3> g;
  g.h = 0.1;
  g.origin = Eigen::Vector3d(-0.3, -0.2, -0.1);
  g.n = {9, 8, 7};
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t n = 64 * 3 + 17;
  std::vector<Eigen::Vector3d> x(n), l(n);
  for (std::size_t p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a) {
      l[p][a] = g.h * (0.05 + 0.45 * u(rng)); // 0 < l <= h/2
      x[p][a] = g.origin[a] + l[p][a] + g.h * (g.n[a] - 1) * u(rng) * 0.7;
    }
  x[70][1] = g.origin[1] + 2.0 * g.h; // on a node
  l[70][1] = 0.5 * g.h;               // support edge on a node too
  std::vector<AxisWeights<3>> aw(n);
  ASSERT_EQ(compute_axis_weights_many(g, n, x.data(), l.data(), aw.data()), n);
  for (std::size_t p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) {
        const double xi = x[p][a] - (g.origin[a] + g.h * (aw[p].i0[a] + k));
        const Weight1D r = ugimp_weight(xi, g.h, l[p][a]);
        ASSERT_TRUE(same_bits(aw[p].w[a][k], r.S) && same_bits(aw[p].dw[a][k], r.dS))
            << "particle " << p << " axis " << a << " node " << k;
      }
  // the split records the solver caches (D422): the same bits
  std::vector<AxisValues<3>> av(n);
  std::vector<AxisSlopes<3>> ad(n);
  ASSERT_EQ(compute_axis_weights_many(g, n, x.data(), l.data(), av.data(), ad.data()), n);
  for (std::size_t p = 0; p < n; ++p)
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(av[p].i0[a], aw[p].i0[a]) << "particle " << p;
      for (int k = 0; k < 3; ++k)
        ASSERT_TRUE(same_bits(av[p].w[a][k], aw[p].w[a][k]) &&
                    same_bits(ad[p].dw[a][k], aw[p].dw[a][k]))
            << "split records, particle " << p << " axis " << a << " node " << k;
    }
  x[130][2] = g.origin[2] + g.h * (g.n[2] - 1); // support beyond the last node
  EXPECT_EQ(compute_axis_weights_many(g, n, x.data(), l.data(), aw.data()), 130u);
  EXPECT_EQ(compute_axis_weights_many(g, n, x.data(), l.data(), av.data(), ad.data()), 130u);
}

// The S-only stencil of G2P (D378) equals the full stencil's nodes and weights bit for bit.
template <int D> void expect_weights_only_equal_full() {
  Grid<D> g;
  g.h = 0.1;
  for (int a = 0; a < D; ++a) {
    g.origin[a] = -0.2 + 0.05 * a;
    g.n[a] = 7 + a;
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  using Vec = Eigen::Matrix<double, D, 1>;
  for (int q = 0; q < 200; ++q) {
    Vec x, l;
    for (int a = 0; a < D; ++a) {
      l[a] = g.h * (0.05 + 0.45 * u(rng));
      x[a] = g.origin[a] + l[a] + g.h * (g.n[a] - 1) * u(rng) * 0.7;
    }
    AxisWeights<D> aw;
    ASSERT_TRUE(compute_axis_weights(g, x, l, aw));
    Stencil<D> full, only, split, values;
    assemble_stencil(g, aw, full);
    assemble_stencil_weights(g, aw, only);
    // from the split records the solver caches (D422)
    const SplitRecords<D> rec = pnc::gimp::split(aw);
    assemble_stencil(g, split_view(rec.values, rec.slopes), split);
    assemble_stencil_weights(g, rec.values, values);
    for (int k = 0; k < Stencil<D>::size; ++k) {
      ASSERT_TRUE(full.node[k] == only.node[k] && same_bits(full.S[k], only.S[k]))
          << D << "-D particle " << q << " node " << k;
      ASSERT_TRUE(full.node[k] == values.node[k] && same_bits(full.S[k], values.S[k]));
      ASSERT_TRUE(full.node[k] == split.node[k] && same_bits(full.S[k], split.S[k]));
      for (int c = 0; c < D; ++c)
        ASSERT_TRUE(same_bits(full.dS[k][c], split.dS[k][c])) << D << "-D node " << k;
    }
  }
}

TEST(GimpWeightsSimd, WeightsOnlyStencilEqualsFullStencil) {
  expect_weights_only_equal_full<2>();
  expect_weights_only_equal_full<3>();
}
