// uGIMP weights: partition of unity, gradient consistency, linear reproduction, continuity.
#include "pnc/gimp_coupler/weights.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace pnc::gimp;

TEST(GimpWeights, OneDimensionalTableContinuousAndDerivativeMatches) {
  const double L = 0.2;
  for (double l : {0.01, 0.05, 0.1}) {
    // Continuity at every breakpoint of the table.
    for (double xb : {-L - l, -L + l, -l, l, L - l, L + l}) {
      const double e = 1e-12;
      EXPECT_NEAR(ugimp_weight(xb - e, L, l).S, ugimp_weight(xb + e, L, l).S, 1e-10);
      EXPECT_NEAR(ugimp_weight(xb - e, L, l).dS, ugimp_weight(xb + e, L, l).dS, 1e-8 / L);
    }
    // dS/dx equals the central difference of S.
    for (double xi = -L - l + 1e-4; xi < L + l; xi += 0.0031) {
      const double h = 1e-7;
      const double fd = (ugimp_weight(xi + h, L, l).S - ugimp_weight(xi - h, L, l).S) / (2 * h);
      EXPECT_NEAR(ugimp_weight(xi, L, l).dS, fd, 1e-5 / L) << "xi=" << xi << " l=" << l;
    }
    EXPECT_DOUBLE_EQ(ugimp_weight(0.0, L, l).S, 1.0 - l / (2 * L));
  }
}

template <int D> void check_consistency(double lfrac) {
  Grid<D> g;
  g.h = 0.1;
  for (int a = 0; a < D; ++a) {
    g.origin[a] = -0.3 + 0.1 * a;
    g.n[a] = 8;
  }
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  const Vec l = Vec::Constant(lfrac * g.h);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec> xs;
  for (int k = 0; k < 200; ++k) {
    Vec x;
    for (int a = 0; a < D; ++a)
      x[a] = g.origin[a] + g.h * (1.0 + 5.0 * u(rng));
    xs.push_back(x);
  }
  // Particles exactly on nodes, on cell faces, with their edge on a node, and next to faces.
  for (double off : {0.0, 1e-15, -1e-15, lfrac, -lfrac, 0.5, 0.5 - lfrac, 0.5 + lfrac}) {
    Vec x;
    for (int a = 0; a < D; ++a)
      x[a] = g.origin[a] + g.h * (3.0 + off);
    xs.push_back(x);
    x[0] = g.origin[0] + g.h * (2.0 + off + 1e-13);
    xs.push_back(x);
  }
  Stencil<D> st;
  for (const Vec& x : xs) {
    ASSERT_TRUE(compute_stencil(g, x, l, st));
    double sum = 0.0;
    Vec dsum = Vec::Zero(), xsum = Vec::Zero();
    Mat xg = Mat::Zero();
    for (int k = 0; k < Stencil<D>::size; ++k) {
      EXPECT_GE(st.S[k], 0.0);
      const Vec X = g.position(st.node[k]);
      sum += st.S[k];
      dsum += st.dS[k];
      xsum += st.S[k] * X;
      xg += X * st.dS[k].transpose();
    }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    EXPECT_LT(dsum.norm() * g.h, 1e-12);
    EXPECT_LT((xsum - x).norm() / g.h, 1e-12); // linear reproduction sum S_i X_i = x
    EXPECT_LT((xg - Mat::Identity()).norm(), 1e-12) << x.transpose();
  }
}

TEST(GimpWeights, PartitionOfUnityAndGradientConsistency2D) {
  for (double f : {0.5, 0.25, 1.0 / 6.0, 0.125})
    check_consistency<2>(f);
}
TEST(GimpWeights, PartitionOfUnityAndGradientConsistency3D) {
  for (double f : {0.5, 0.25, 0.125})
    check_consistency<3>(f);
}

TEST(GimpWeights, ParticleOutsideGridIsReported) {
  Grid<2> g;
  g.h = 1.0;
  g.n = {4, 4};
  Stencil<2> st;
  const Eigen::Vector2d l(0.25, 0.25);
  EXPECT_TRUE(compute_stencil(g, Eigen::Vector2d(0.25, 0.25), l, st));
  EXPECT_TRUE(compute_stencil(g, Eigen::Vector2d(2.75, 2.75), l, st)); // support ends on last node
  EXPECT_FALSE(compute_stencil(g, Eigen::Vector2d(0.2, 1.5), l, st));
  EXPECT_FALSE(compute_stencil(g, Eigen::Vector2d(1.5, 2.9), l, st));
  EXPECT_FALSE(compute_stencil(g, Eigen::Vector2d(std::nan(""), 1.0), l, st));
}
