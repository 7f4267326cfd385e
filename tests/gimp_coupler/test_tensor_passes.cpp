// The row kernels of the uGIMP step (gimp_coupler/src/tensor_passes.hpp, D404) against the
// transfers written node by node in long double (80-bit, 11 more bits than double) from the
// same per-axis weights: every output within the floating-point summation bound
//   |computed - exact| <= gamma_n * (sum of |terms|),  gamma_n = n u / (1 - n u), u = 2^-53,
// with n = (number of terms) + (rounded factors per term) (Higham, Accuracy and Stability of
// Numerical Algorithms, 2nd ed., section 3.1). The long-double reference is itself within
// 2^-11 of that bound of the exact sums, far below it. Also: the baseline and AVX2 copies give
// the same bits, and the node-by-node double path (assemble_stencil) meets the same bound, so
// the bound is the accuracy of the transfers and not one tuned to the new kernels.
#include "pnc/core/cpu.hpp"
#include "pnc/gimp_coupler/weights.hpp"
#include "tensor_passes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

using namespace pnc::gimp;

namespace {

constexpr double u = 0x1p-53;

double gamma(int n) {
  return n * u / (1.0 - n * u);
}

/// A grid of 9^D nodes with cell size h, a particle inside with half-lengths in (0, h/2], its
/// axis weights, and random node fields and particle data of both signs.
template <int D> struct Setup {
  using Vec = Eigen::Matrix<double, D, 1>;
  Grid<D> g;
  AxisWeights<D> aw;
  AxisValues<D> av; // aw as the solver caches it (D422)
  AxisSlopes<D> ad;
  std::vector<double> m, v, vn, v0, p, fi, fe; // D doubles per node except m
  double mp = 0, V = 0, sigma[9] = {}, vel[D] = {}, fext[D] = {};

  explicit Setup(std::mt19937& rng) {
    std::uniform_real_distribution<double> U(-1.0, 1.0), pos(0.0, 1.0);
    g.h = 2e-3;
    for (int a = 0; a < D; ++a) {
      g.origin[a] = -1e-3 * (a + 1);
      g.n[a] = 9;
    }
    Vec x, l;
    for (int a = 0; a < D; ++a) {
      l[a] = g.h * (0.02 + 0.48 * pos(rng));
      x[a] = g.origin[a] + g.h * (2.0 + 4.0 * pos(rng));
    }
    EXPECT_TRUE(compute_axis_weights(g, x, l, aw));
    const SplitRecords<D> rec = split(aw);
    av = rec.values;
    ad = rec.slopes;
    const auto nn = static_cast<std::size_t>(g.nodes());
    auto fill = [&](std::vector<double>& f, std::size_t n, double scale) {
      f.resize(n);
      for (double& y : f)
        y = scale * U(rng);
    };
    fill(m, nn, 1e-3);
    fill(v, D * nn, 2.0);
    fill(vn, D * nn, 2.0);
    fill(v0, D * nn, 2.0);
    fill(p, D * nn, 1e-3);
    fill(fi, D * nn, 50.0);
    fill(fe, D * nn, 50.0);
    mp = 1e-6 * (1.0 + pos(rng));
    V = 1e-9 * (1.0 + pos(rng));
    for (double& s : sigma)
      s = 1e7 * U(rng);
    for (int a = 0; a < D; ++a) {
      vel[a] = 3.0 * U(rng);
      fext[a] = 0.1 * U(rng);
    }
  }
};

/// The stencil's nodes with S and grad S in long double (exact products of the axis weights
/// to 64 bits).
template <int D> struct ExactStencil {
  static constexpr int N = Stencil<D>::size;
  std::int64_t node[N];
  long double S[N], dS[N][D];
  ExactStencil(const Grid<D>& g, const AxisWeights<D>& aw) {
    Stencil<D> st;
    assemble_stencil(g, aw, st); // node order: axis 0 fastest
    for (int k = 0; k < N; ++k) {
      node[k] = st.node[k];
      int idx[3] = {k % 3, (k / 3) % 3, k / 9};
      S[k] = 1.0L;
      for (int a = 0; a < D; ++a)
        S[k] *= aw.w[a][idx[a]];
      for (int c = 0; c < D; ++c) {
        dS[k][c] = 1.0L;
        for (int a = 0; a < D; ++a)
          dS[k][c] *= a == c ? aw.dw[a][idx[a]] : aw.w[a][idx[a]];
      }
    }
  }
};

/// |got - exact| <= gamma(n) * abs_sum, with the numbers in the failure message.
void expect_within(double got, long double exact, long double abs_sum, int n, const char* what) {
  const long double err = std::fabs(static_cast<long double>(got) - exact);
  const long double tol = gamma(n) * abs_sum;
  EXPECT_LE(err, tol) << what << ": got " << got << ", exact " << static_cast<double>(exact)
                      << ", |terms| " << static_cast<double>(abs_sum) << ", bound n = " << n;
}

template <int D> void check_copy(const detail::RowKernels<D>& rk, int seed) {
  constexpr int N = Stencil<D>::size;
  std::mt19937 rng(static_cast<unsigned>(seed));
  for (int trial = 0; trial < 200; ++trial) {
    Setup<D> s(rng);
    const ExactStencil<D> ex(s.g, s.aw);
    // gather: grad v and the G2P sums (products of up to D + 1 rounded factors and a
    // difference: n = N + D + 3)
    double grad[D][D], vs_p[D], dv_p[D];
    rk.gradient(s.g, s.av, s.ad, s.v.data(), grad);
    rk.velocities(s.g, s.av, s.v.data(), s.vn.data(), s.v0.data(), vs_p, dv_p);
    for (int a = 0; a < D; ++a) {
      long double xs = 0, xa = 0, ds = 0, da = 0;
      for (int k = 0; k < N; ++k) {
        const std::size_t q = D * static_cast<std::size_t>(ex.node[k]) + a;
        xs += ex.S[k] * s.v[q];
        xa += std::fabs(ex.S[k] * s.v[q]);
        const long double dv = static_cast<long double>(s.vn[q]) - s.v0[q];
        ds += ex.S[k] * dv;
        da += std::fabs(ex.S[k]) * (std::fabs(s.vn[q]) + std::fabs(s.v0[q]));
      }
      expect_within(vs_p[a], xs, xa, N + D + 3, "sum S v*");
      expect_within(dv_p[a], ds, da, N + D + 3, "sum S (vn - v0)");
      for (int c = 0; c < D; ++c) {
        long double gs = 0, ga = 0;
        for (int k = 0; k < N; ++k) {
          const long double t = s.v[D * static_cast<std::size_t>(ex.node[k]) + a] * ex.dS[k][c];
          gs += t;
          ga += std::fabs(t);
        }
        expect_within(grad[a][c], gs, ga, N + D + 3, "grad v");
      }
    }
    // scatter: each node entry = its old value + up to D + 1 products of up to D + 3 rounded
    // factors (n = 2 D + 5)
    for (bool external : {false, true}) {
      std::vector<double> m = s.m, p = s.p, fi = s.fi, fe = s.fe;
      const detail::P2GParticle<D> in{s.mp, s.V, s.vel, s.sigma, s.fext};
      rk.scatter(s.g, s.av, s.ad, in, external,
                 detail::NodeArrays{m.data(), p.data(), fi.data(), fe.data()});
      std::vector<double> fi2 = s.fi;
      rk.scatter_force(s.g, s.av, s.ad, s.sigma, s.V, fi2.data());
      for (int k = 0; k < N; ++k) {
        const auto n = static_cast<std::size_t>(ex.node[k]);
        const long double mS = ex.S[k] * s.mp;
        expect_within(m[n], s.m[n] + mS, std::fabs(s.m[n]) + std::fabs(mS), 2 * D + 5, "m");
        for (int a = 0; a < D; ++a) {
          const std::size_t q = D * n + a;
          const long double pS = ex.S[k] * (static_cast<long double>(s.mp) * s.vel[a]);
          expect_within(p[q], s.p[q] + pS, std::fabs(s.p[q]) + std::fabs(pS), 2 * D + 5, "p");
          long double f = s.fi[q], fa = std::fabs(s.fi[q]);
          for (int c = 0; c < D; ++c) {
            const long double t = static_cast<long double>(s.sigma[a + 3 * c]) * s.V * ex.dS[k][c];
            f -= t;
            fa += std::fabs(t);
          }
          expect_within(fi[q], f, fa, 2 * D + 5, "f^int (P2G)");
          expect_within(fi2[q], f, fa, 2 * D + 5, "f^int (force scatter)");
          const long double e = ex.S[k] * s.fext[a];
          if (external)
            expect_within(fe[q], s.fe[q] + e, std::fabs(s.fe[q]) + std::fabs(e), 2 * D + 5, "fe");
          else
            EXPECT_EQ(fe[q], s.fe[q]) << "fe written without external forces";
        }
      }
      // nodes outside the stencil are untouched
      std::vector<char> in_stencil(s.m.size(), 0);
      for (int k = 0; k < N; ++k)
        in_stencil[static_cast<std::size_t>(ex.node[k])] = 1;
      for (std::size_t n = 0; n < s.m.size(); ++n)
        if (!in_stencil[n]) {
          EXPECT_EQ(m[n], s.m[n]);
          for (int a = 0; a < D; ++a)
            EXPECT_EQ(fi[D * n + a], s.fi[D * n + a]);
        }
    }
    if (::testing::Test::HasFailure()) return;
  }
}

template <int D> void check_stencil_path_meets_the_bound(int seed) {
  constexpr int N = Stencil<D>::size;
  std::mt19937 rng(static_cast<unsigned>(seed));
  for (int trial = 0; trial < 200; ++trial) {
    Setup<D> s(rng);
    const ExactStencil<D> ex(s.g, s.aw);
    Stencil<D> st;
    assemble_stencil(s.g, s.aw, st);
    for (int a = 0; a < D; ++a)
      for (int c = 0; c < D; ++c) {
        double g = 0.0;
        long double gs = 0, ga = 0;
        for (int k = 0; k < N; ++k) {
          const double x = s.v[D * static_cast<std::size_t>(st.node[k]) + a];
          g += x * st.dS[k][c];
          gs += x * ex.dS[k][c];
          ga += std::fabs(x * ex.dS[k][c]);
        }
        expect_within(g, gs, ga, N + D + 3, "grad v, node by node");
      }
  }
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// The baseline copy against copy `copy` (1 = AVX2, 2 = AVX-512), bit for bit.
template <int D> void check_copies_agree(int seed, int copy) {
  const auto& k0 = detail::row_kernels<D>(0);
  const auto& k1 = detail::row_kernels<D>(copy);
  std::mt19937 rng(static_cast<unsigned>(seed));
  for (int trial = 0; trial < 100; ++trial) {
    Setup<D> s(rng);
    double g0[D][D], g1[D][D], x0[D], x1[D], d0[D], d1[D];
    k0.gradient(s.g, s.av, s.ad, s.v.data(), g0);
    k1.gradient(s.g, s.av, s.ad, s.v.data(), g1);
    k0.velocities(s.g, s.av, s.v.data(), s.vn.data(), s.v0.data(), x0, d0);
    k1.velocities(s.g, s.av, s.v.data(), s.vn.data(), s.v0.data(), x1, d1);
    for (int a = 0; a < D; ++a) {
      EXPECT_TRUE(same_bits(x0[a], x1[a]));
      EXPECT_TRUE(same_bits(d0[a], d1[a]));
      for (int c = 0; c < D; ++c)
        EXPECT_TRUE(same_bits(g0[a][c], g1[a][c]));
    }
    std::vector<double> m0 = s.m, p0 = s.p, f0 = s.fi, e0 = s.fe;
    std::vector<double> m1 = s.m, p1 = s.p, f1 = s.fi, e1 = s.fe;
    const detail::P2GParticle<D> in{s.mp, s.V, s.vel, s.sigma, s.fext};
    k0.scatter(s.g, s.av, s.ad, in, true,
               detail::NodeArrays{m0.data(), p0.data(), f0.data(), e0.data()});
    k1.scatter(s.g, s.av, s.ad, in, true,
               detail::NodeArrays{m1.data(), p1.data(), f1.data(), e1.data()});
    k0.scatter_force(s.g, s.av, s.ad, s.sigma, s.V, f0.data());
    k1.scatter_force(s.g, s.av, s.ad, s.sigma, s.V, f1.data());
    EXPECT_EQ(std::memcmp(m0.data(), m1.data(), m0.size() * sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(p0.data(), p1.data(), p0.size() * sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(f0.data(), f1.data(), f0.size() * sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(e0.data(), e1.data(), e0.size() * sizeof(double)), 0);
  }
}

} // namespace

// The AVX2 copy is called explicitly only where the configure check found AVX2
// (tests/CMakeLists.txt), as in test_weights_simd.cpp; the dispatched copy always.
TEST(GimpTensorPasses, RowKernelsMatchTheExactTransfersWithinTheSummationBound2D) {
  check_copy<2>(detail::row_kernels<2>(0), 1);
  check_copy<2>(detail::row_kernels<2>(), 2);
}

TEST(GimpTensorPasses, RowKernelsMatchTheExactTransfersWithinTheSummationBound3D) {
  check_copy<3>(detail::row_kernels<3>(0), 3);
  check_copy<3>(detail::row_kernels<3>(), 4);
}

TEST(GimpTensorPasses, TheNodeByNodePathMeetsTheSameBound) {
  check_stencil_path_meets_the_bound<2>(5);
  check_stencil_path_meets_the_bound<3>(6);
}

#if PNC_HAVE_AVX2_COPY && PNC_TEST_CPU_HAS_AVX2
TEST(GimpTensorPasses, BaselineAndAvx2CopiesGiveTheSameBits) {
  check_copies_agree<2>(7, 1);
  check_copies_agree<3>(8, 1);
}
#endif

#if PNC_HAVE_AVX2_COPY && PNC_TEST_CPU_HAS_AVX512
TEST(GimpTensorPasses, BaselineAndAvx512CopiesGiveTheSameBits) {
  check_copies_agree<2>(9, 2);
  check_copies_agree<3>(10, 2);
}
#endif

TEST(GimpTensorPasses, TheChosenCopyIsTheWidestTheCpuHas) {
  const int copy = pnc::cpu_has_avx512() ? 2 : pnc::cpu_has_avx2() ? 1 : 0;
  EXPECT_EQ(&detail::row_kernels<2>(), &detail::row_kernels<2>(copy));
  EXPECT_EQ(&detail::row_kernels<3>(), &detail::row_kernels<3>(copy));
  EXPECT_EQ(&detail::row_kernels<3>(1) != &detail::row_kernels<3>(0), PNC_HAVE_AVX2_COPY == 1);
  EXPECT_EQ(&detail::row_kernels<3>(2) != &detail::row_kernels<3>(1), PNC_HAVE_AVX2_COPY == 1);
}
