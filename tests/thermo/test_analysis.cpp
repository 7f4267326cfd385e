// Numerics of thermo/ against closed forms: quadrature, error propagation, block averages,
// FEP of a Gaussian, fits, the LJ lambda derivative, the discrete bending stiffness, and the
// deformation of the box.
#include "pnc/core/error.hpp"
#include "pnc/thermo/analysis.hpp"
#include "pnc/thermo/persistence.hpp"
#include "pnc/thermo/ti.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

using namespace pnc::thermo;

TEST(ThermoQuadrature, ThreePointGaussIsTable61) {
  const Quadrature q = gauss_legendre(3);
  ASSERT_EQ(q.nodes.size(), 3u);
  // exact: 0.5 -+ sqrt(15)/10, weights 5/18, 8/18, 5/18 (Table 6.1's values x 1/2, rounded)
  EXPECT_NEAR(q.nodes[0], 0.5 - std::sqrt(15.0) / 10, 1e-14);
  EXPECT_NEAR(q.nodes[1], 0.5, 1e-14);
  EXPECT_NEAR(q.nodes[2], 0.5 + std::sqrt(15.0) / 10, 1e-14);
  EXPECT_NEAR(q.weights[0], 5.0 / 18, 1e-14);
  EXPECT_NEAR(q.weights[1], 8.0 / 18, 1e-14);
  // the printed table to its 3 digits
  EXPECT_NEAR(q.nodes[0], 0.113, 5e-4);
  EXPECT_NEAR(q.nodes[2], 0.887, 5e-4);
  EXPECT_NEAR(2 * q.weights[0], 0.556, 5e-4);
  EXPECT_NEAR(2 * q.weights[1], 0.889, 5e-4);
}

TEST(ThermoQuadrature, GaussIsExactToDegree2nMinus1AndTrapezoidErrorIsKnown) {
  for (int n = 1; n <= 8; ++n) {
    const Quadrature q = gauss_legendre(n, -0.5, 2.0);
    for (int p = 0; p <= 2 * n - 1; ++p) {
      double s = 0;
      for (std::size_t i = 0; i < q.nodes.size(); ++i)
        s += q.weights[i] * std::pow(q.nodes[i], p);
      const double exact = (std::pow(2.0, p + 1) - std::pow(-0.5, p + 1)) / (p + 1);
      EXPECT_NEAR(s, exact, 1e-12 * std::max(1.0, std::fabs(exact))) << n << " " << p;
    }
  }
  // composite trapezoid on x^2 over [0,1] with spacing h: error h^2/6 exactly
  for (int n : {2, 3, 5, 11}) {
    const Quadrature q = trapezoid(n);
    double s = 0;
    for (std::size_t i = 0; i < q.nodes.size(); ++i)
      s += q.weights[i] * q.nodes[i] * q.nodes[i];
    const double h = 1.0 / (n - 1);
    EXPECT_NEAR(s - 1.0 / 3, h * h / 6, 1e-14);
  }
  EXPECT_THROW(make_rule("simpson", 3, "test"), pnc::InputError);
}

TEST(ThermoQuadrature, ErrorPropagation) {
  const Quadrature q = gauss_legendre(3);
  const Estimate e = integrate(q, {1, 2, 3}, {0.1, 0.2, 0.3});
  EXPECT_NEAR(e.value, 5.0 / 18 * 1 + 8.0 / 18 * 2 + 5.0 / 18 * 3, 1e-14);
  EXPECT_NEAR(e.se,
              std::sqrt(std::pow(5.0 / 18 * 0.1, 2) + std::pow(8.0 / 18 * 0.2, 2) +
                        std::pow(5.0 / 18 * 0.3, 2)),
              1e-14);
}

// AR(1) series x_t = rho x_{t-1} + noise with stationary variance s^2: the variance of the
// mean of n samples is s^2/n (1+rho)/(1-rho) for n >> correlation time. Over 200 independent
// series the block estimates must average to the true se within the scatter expected for
// a standard-deviation estimate from 20 blocks (relative sd ~ 1/sqrt(2*19) = 0.16, /sqrt(200)).
TEST(ThermoStats, BlockAverageOfCorrelatedSeriesMatchesTheAr1Formula) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 1);
  const double rho = 0.9, s = 2.0;
  const int n = 20000;
  const double se_true = s / std::sqrt(n) * std::sqrt((1 + rho) / (1 - rho));
  double mean_ratio = 0, mean_sq = 0;
  const int reps = 200;
  for (int r = 0; r < reps; ++r) {
    std::vector<double> x(n);
    double v = s * g(rng);
    for (int i = 0; i < n; ++i) {
      v = rho * v + s * std::sqrt(1 - rho * rho) * g(rng);
      x[i] = v;
    }
    const Estimate e = block_mean(x, 20);
    mean_ratio += e.se / se_true;
    mean_sq += e.value * e.value;
  }
  mean_ratio /= reps;
  // E[sd estimate]/sd ~ 1 - 1/(4 dof) = 0.987 for 19 dof; tolerance 4 x 0.16/sqrt(200) = 0.045
  EXPECT_NEAR(mean_ratio, 0.987, 0.045);
  // and the means scatter with the true se: mean square / se^2 ~ 1 (chi^2_200/200, sd 0.1)
  EXPECT_NEAR(mean_sq / reps / (se_true * se_true), 1.0, 0.4);
}

// FEP of Gaussian du ~ N(mu, s^2): -kT ln <exp(-du/kT)> = mu - s^2 / (2 kT) exactly.
TEST(ThermoStats, FepOfGaussianEnergyDifference) {
  std::mt19937_64 rng(3);
  const double kT = 0.596, mu = 1.3, s = 0.4;
  std::normal_distribution<double> g(mu, s);
  std::vector<double> du(200000);
  for (auto& v : du)
    v = g(rng);
  const Estimate e = fep(du, kT, 20);
  EXPECT_NEAR(e.value, mu - s * s / (2 * kT), 4 * e.se);
  EXPECT_GT(e.se, 0);
  EXPECT_LT(e.se, 0.01);
}

TEST(ThermoStats, PolyfitRecoversExactPolynomialAndTQuantiles) {
  const std::vector<double> x = {0, 1, 2, 3, 4};
  std::vector<double> y;
  for (double v : x)
    y.push_back(1.5 - 0.5 * v + 0.25 * v * v);
  const PolyFit f = polyfit(x, y, {}, 2, true);
  EXPECT_NEAR(f.c[0], 1.5, 1e-12);
  EXPECT_NEAR(f.c[1], -0.5, 1e-12);
  EXPECT_NEAR(f.c[2], 0.25, 1e-12);
  EXPECT_EQ(f.dof, 2);
  EXPECT_NEAR(t95(3), 3.182, 1e-3);
  EXPECT_NEAR(t95(1000), 1.96, 1e-12);
}

// slope of y = 3 x + AR(1) noise: estimate within 4 of its own standard errors, and the
// standard error close to the one of the closed form for white noise when rho = 0.
TEST(ThermoStats, BlockSlopeOfNoisyLine) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0, 1);
  const int n = 4000;
  std::vector<double> x(n), y(n);
  for (int i = 0; i < n; ++i) {
    x[i] = i * 0.001;
    y[i] = 3 * x[i] + 0.5 * g(rng);
  }
  const Estimate e = block_slope(x, y, 20);
  double mx = 0;
  for (double v : x)
    mx += v / n;
  double sxx = 0;
  for (double v : x)
    sxx += (v - mx) * (v - mx);
  const double se_white = 0.5 / std::sqrt(sxx);
  EXPECT_NEAR(e.value, 3.0, 4 * se_white);
  // 20 blocks: relative sd of the s.e. estimate ~ 1/sqrt(2*18) = 0.17; 3 sd
  EXPECT_NEAR(e.se / se_white, 1.0, 0.5);
}

// du/dlambda of the pair energy against a central difference of lj_energy along the path.
TEST(ThermoLj, AnalyticLambdaDerivativeMatchesFiniteDifference) {
  const LjPath p; // dissertation path
  for (double l : {0.02, 0.1127, 0.5, 0.8873, 0.99})
    for (double r : {0.9, 1.2, 2.0, 2.9, 3.3, 5.0, 7.0}) {
      const double h = 1e-5;
      const double fd =
          (lj_energy(r, p.eps(l + h), p.sig(l + h)) - lj_energy(r, p.eps(l - h), p.sig(l - h))) /
          (2 * h);
      const double an = lj_dudl(r, l, p);
      // central difference error h^2/6 u''' plus round-off; relative 1e-6 is generous
      EXPECT_NEAR(an, fd, 1e-6 * std::max(1e-3, std::fabs(an))) << l << " " << r;
      const double d[1] = {r};
      EXPECT_NEAR(lj_sums(d, 1, l, p).dudl, an, 1e-12 * std::max(1.0, std::fabs(an)));
    }
  const double far[1] = {p.cutoff + 0.01};
  EXPECT_EQ(lj_sums(far, 1, 0.5, p).pairs, 0);
}

// Straight chain, energy k/2 phi^2 per joint: 4 beads, F/d = 2 k / b^2 by hand (two joints
// bent by d/b each, E = k d^2 / b^2, F = dE/dd); long chains approach the continuum simply
// supported beam with EI = k b under the load of this test -- F spread evenly over the
// beads (the centre of mass is pulled), d the mean deflection: y = w x (L^3 - 2 L x^2 +
// x^3) / (24 EI), mean wL^4/(120 EI), so F/d = 120 EI / L^3 (not the printed ratio's 48 of
// docs/theory.md §4.5 (D67), which is a point load at mid-span with the mid-span deflection). The
// error is O(1/M) (the load and the mean skip the two end beads): doubling M halves it.
TEST(ThermoBending, DiscreteChainStiffness) {
  const double b = 1.53, k = 1000;
  EXPECT_NEAR(discrete_bending_stiffness(4, b, k), 2 * k / (b * b), 1e-9);
  EXPECT_NEAR(discrete_bending_stiffness(3, b, k), 4 * k / (b * b), 1e-9)
      << "3 beads: one joint, phi = 2 d / b, E = 2 k d^2/b^2, F = 4 k d / b^2";
  double prev = 1e9;
  for (int m : {21, 41, 81}) {
    const double L = (m - 1) * b;
    const double cont = 120 * k * b / (L * L * L);
    const double rel = std::fabs(discrete_bending_stiffness(m, b, k) / cont - 1);
    EXPECT_LT(rel, prev * 0.55); // O(1/M)
    prev = rel;
  }
  EXPECT_LT(prev, 0.03);
}

// The box after deform_commands: the metric H'^T H' equals (F H)^T (F H) (same box up to
// a rotation) and the volume is det F V0.
TEST(ThermoDeform, DeviatoricBoxIsRotatedFH) {
  pnc::md::LmpBox box;
  box.lo = {-1, 0, 2};
  box.hi = {19, 21, 24};
  const auto& lo = box.lo;
  const auto& hi = box.hi;
  for (const std::string kind : {"vol", "dev"}) {
    const double s = 5e-3;
    const auto cmds = deform_commands({kind, s, "x"}, box);
    ASSERT_FALSE(cmds.empty());
    // parse "x final a b y final ... [xy final v xz final v yz final v]"
    std::istringstream in(cmds.back());
    std::string w;
    double L[3] = {0, 0, 0}, xy = 0, xz = 0, yz = 0;
    while (in >> w) {
      std::string fin;
      double a, bb;
      if (w == "x" || w == "y" || w == "z") {
        in >> fin >> a >> bb;
        L[w[0] - 'x'] = bb - a;
      } else if (w == "xy") {
        in >> fin >> xy;
      } else if (w == "xz") {
        in >> fin >> xz;
      } else if (w == "yz") {
        in >> fin >> yz;
      }
    }
    Eigen::Matrix3d H, Hn, F = Eigen::Matrix3d::Identity();
    H << 20, 0, 0, 0, 21, 0, 0, 0, 22;
    Hn << L[0], xy, xz, 0, L[1], yz, 0, 0, L[2];
    if (kind == "vol")
      F *= 1 + s;
    else
      F += s * (Eigen::Matrix3d::Ones() - Eigen::Matrix3d::Identity());
    const Eigen::Matrix3d G = (F * H).transpose() * (F * H), Gn = Hn.transpose() * Hn;
    EXPECT_LT((G - Gn).cwiseAbs().maxCoeff(), 1e-9) << kind;
    EXPECT_NEAR(Hn.determinant(), F.determinant() * H.determinant(), 1e-9);
  }
}
