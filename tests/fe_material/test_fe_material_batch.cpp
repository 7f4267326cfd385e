// Tests of ABI 1.2 of the material plugin (pnc_material.h "ABI 1.2", docs/plugin.md, decisions
// D260-D262): pnc_material_integrate_batch against pnc_material_integrate2 point by point. The
// batched route evaluates the kernel's expressions in the kernel's order, so stress, end state
// and tangent must be equal bit for bit; the stored energy sums the same six products in an
// order of its own (bound derived below); the dissipated energy is the kernel's or exactly 0.
#include "v2_support.hpp"

#include <dlfcn.h>

#include <cfloat>
#include <cstdint>
#include <random>

namespace {

using namespace pnc_v2_test;

// One point of a test batch: strain at the start, increment, start state (flat, n_state).
struct Point {
  Vec6 e0, de;
  std::vector<double> s0;
};

enum class Kind { elastic, damaging, unloading };

// The end state of the path 0 -> e through integrate2 (the single-point route, the reference).
std::vector<double> state_after(const pnc_material* m, const Vec6& e) {
  const std::vector<double> v = virgin(m);
  const Out o = call(m, v.data(), Vec6::Zero(), e, PNC_MATERIAL_TANGENT_NONE);
  EXPECT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
  return std::vector<double>(o.state1.begin(), o.state1.begin() + static_cast<long>(v.size()));
}

// A strain past the damage onset of the model (pnc: mode stretch alpha lambda_c = 1.07 along
// x2; pp: largest principal stretch 1.17), with random shears; zero out-of-plane components
// (e33 = g23 = g13 = 0) when `plane`.
Vec6 damaging_strain(Model model, std::mt19937_64& g, bool plane) {
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
std::vector<Point> make_points(const pnc_material* m, Model model, std::size_t n, unsigned seed,
                               double elastic = 0.7, double damaging = 0.2, int plane_every = 5) {
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

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Point i of the batch against integrate2 on the same inputs: stress, state, tangent bit for
// bit; stored energy within the bound of two summation orders of the same six products
// (each order errs by at most 5 u sum |sigma_k eps_k| (n - 1 = 5 additions), u = 2^-53, so
// the two differ by at most 10 u of it; the factor 1/2 is exact); dissipated energy exact.
void expect_point_equal(const pnc_material* m, const std::vector<Point>& pts, const Blocks& b,
                        std::size_t i, int request, const std::string& what) {
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
pnc::damage::NdmBatch batch_view(Blocks& b, pnc::damage::TangentKind kind) {
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
pnc::damage::NdmBatchStats paths_of(const NdmParameters& p, const Blocks& b) {
  Blocks copy = b;
  return pnc::damage::integrate_batch(pnc::damage::prepare(p),
                                      batch_view(copy, pnc::damage::TangentKind::none));
}

// One batched call over pts with `request`, which must succeed for every point, and each point
// against the single-point entry, bit for bit.
void expect_batch_equals_single(const pnc_material* m, const std::vector<Point>& pts, int request,
                                const std::string& what) {
  Blocks b(pts, pnc_material_n_state(m));
  char err[512] = {0};
  pnc_material_point_soa v = b.view(request, err, sizeof err);
  ASSERT_EQ(pnc_material_integrate_batch(m, b.n, &v), PNC_MATERIAL_OK) << what << ": " << err;
  EXPECT_EQ(v.n_failed, 0u) << what;
  for (std::size_t i = 0; i < b.n; ++i)
    expect_point_equal(m, pts, b, i, request, what);
}

// ------------------------------------------------------------------ equality
TEST(FeMaterialBatch, EqualsTheSinglePointEntryOnEveryPathModelFrameAndRequest) {
  for (const Case& c : kCases) {
    const NdmParameters p = params(c.model, c.rotated);
    auto m = make(p);
    const int ns = pnc_material_n_state(m.get());
    const auto pts = make_points(m.get(), c.model, 300, 11);
    for (int request = PNC_MATERIAL_TANGENT_NONE; request <= PNC_MATERIAL_TANGENT_CONSISTENT;
         ++request) {
      Blocks b(pts, ns);
      char err[512] = {0};
      pnc_material_point_soa v = b.view(request, err, sizeof err);
      ASSERT_EQ(pnc_material_integrate_batch(m.get(), b.n, &v), PNC_MATERIAL_OK) << err;
      EXPECT_EQ(v.n_failed, 0u);
      EXPECT_EQ(v.first_failed, b.n);
      const std::string what = name_of(c) + " request " + std::to_string(request);
      for (std::size_t i = 0; i < b.n; ++i)
        expect_point_equal(m.get(), pts, b, i, request, what);
      if (request == PNC_MATERIAL_TANGENT_NONE) {
        // every path is exercised: fast elastic and unloading points, and damage growth: in
        // the growth pass for the pnc law, plane and general strains alike (D399, D403; a
        // stress-only request needs no principal direction, so none goes to the kernel), in
        // the kernel for pp
        const auto st = paths_of(p, b);
        EXPECT_GT(st.elastic, 100u) << what;
        EXPECT_GT(st.unloading, 10u) << what;
        if (c.model == Model::pnc) {
          EXPECT_GT(st.growth, 30u) << what;
          EXPECT_EQ(st.kernel, 0u) << what;
        } else {
          EXPECT_GT(st.kernel, 30u) << what;
          EXPECT_EQ(st.growth, 0u) << what;
        }
        EXPECT_EQ(st.elastic + st.unloading + st.growth + st.kernel, b.n) << what;
      }
    }
  }
}

// The batch's stretch pass takes one of three loops per chunk of 32 points (D352): every point
// block-diagonal (plane strains, aligned or rotated about x3), none (general strains, aligned
// or rotated in 3-D) or a mix (the test above). Each must give integrate2's numbers.
TEST(FeMaterialBatch, EqualsTheSinglePointEntryWhenAChunkIsAllPlaneOrAllGeneral) {
  const Eigen::Matrix3d about_x3 = rotation_zx(25.0, 0.0), in_3d = rotation_zx(30.0, 20.0);
  const struct {
    int plane_every;
    const Eigen::Matrix3d* R;
    const char* what;
  } runs[] = {{1, nullptr, "all plane, aligned"},
              {1, &about_x3, "all plane, rotated about x3"},
              {0, nullptr, "all general, aligned"},
              {0, &in_3d, "all general, rotated"}};
  for (Model model : {Model::pnc, Model::pp})
    for (const auto& r : runs) {
      NdmParameters p = params(model, false);
      if (r.R) p.R = *r.R;
      auto m = make(p);
      const auto pts = make_points(m.get(), model, 160, 352, 0.7, 0.2, r.plane_every);
      for (int request : {PNC_MATERIAL_TANGENT_NONE, PNC_MATERIAL_TANGENT_CONSISTENT}) {
        Blocks b(pts, pnc_material_n_state(m.get()));
        char err[512] = {0};
        pnc_material_point_soa v = b.view(request, err, sizeof err);
        ASSERT_EQ(pnc_material_integrate_batch(m.get(), b.n, &v), PNC_MATERIAL_OK) << err;
        EXPECT_EQ(v.n_failed, 0u);
        const std::string what = std::string(pnc::damage::model_name(model)) + " " + r.what +
                                 " request " + std::to_string(request);
        for (std::size_t i = 0; i < b.n; ++i)
          expect_point_equal(m.get(), pts, b, i, request, what);
        // the damage growth of pnc points takes the growth pass, block-diagonal (plane strains
        // aligned or rotated about x3) and general strains alike (D399, D403); pp's the kernel
        const auto st = paths_of(p, b);
        if (model == Model::pnc) {
          EXPECT_GT(st.growth, 15u) << what;
          EXPECT_EQ(st.kernel, 0u) << what;
        } else {
          EXPECT_EQ(st.growth, 0u) << what;
          EXPECT_GT(st.kernel, 15u) << what;
        }
      }
    }
}

// A block-diagonal strain whose capped mode grows at a repeated lambda_max: 1 + e33 equal to
// the largest singular value of the in-plane block of F, so that C = F^T F has a double largest
// eigenvalue and its direction is not unique. The growth pass hands the point to the kernel
// (Eigen's solver for the direction, D399); the numbers are integrate2's either way.
// The batch's stretch pass for general strains (D402) forms lambda_max in two vectorised halves
// around its cosine. Degenerate strains (C block-diagonal in each plane, repeated eigenvalues,
// r clamped at +-1, zero) must still give the single-point entry's bits: at rest, elastic and
// loading into damage, in chunks of general strains alone and mixed with block-diagonal ones.
TEST(FeMaterialBatch, DegenerateStrainsGiveTheSinglePointBitsThroughTheGeneralStretchPass) {
  std::vector<Vec6> shapes(15);
  shapes[0] << 0, 0, 0, 0, 0, 0;                      // zero
  shapes[1] << 0.03, 0.03, 0.03, 0, 0, 0;             // hydrostatic
  shapes[2] << 0.03, 0.03, -0.01, 0, 0, 0;            // equibiaxial
  shapes[3] << 0, 0, 0, 0, 0, 0.04;                   // pure shear in x1-x2
  shapes[4] << 0.02, 0.02, 0.02, 1e-12, 0, 0;         // nearly hydrostatic
  shapes[5] << 0.01, 0.01, 0.01, 0.02, 0.02, 0.02;    // double root below the top
  shapes[6] << 1e-9, -1e-9, 0, 3e-10, 0, 0;           // tiny
  shapes[7] << 0.02, 0.03, -0.01, 0.04, 0, 0;         // g23 alone: C01 = C02 = 0
  shapes[8] << 0.02, -0.01, 0.03, 0, 0.04, 0;         // g13 alone: C01 = C12 = 0
  shapes[9] << 0.01, 0.03, 0.0, 0.03, 0.02, 0;        // g23 and g13: C01 = 0, the cubic
  shapes[10] << 0.0, 0.03, 0.0, 0.03, 0, 0;           // g23 with the x2 extension
  shapes[11] << 0.03, 0.03, 0.03, 0.0, 0.02, 0.0;     // hydrostatic and g13
  shapes[12] << -0.01, 0.04, -0.01, 0.01, 0.01, 0.01; // all shears, x2 the largest
  shapes[13] << 0.02, -0.01, 0.0, 0, 0, 0.03;         // plane strain
  shapes[14] << 0.01, 0.01, 0.0, 0, 0, 0.0;           // equibiaxial plane
  for (const Model model : {Model::pnc, Model::pp})
    for (const bool general_only : {true, false}) {
      const NdmParameters p = params(model, false);
      auto m = make(p);
      std::vector<Point> pts;
      for (const Vec6& e : shapes)
        for (const double scale : {1.0, 4.0, 8.0}) {
          if (general_only && e[3] == 0.0 && e[4] == 0.0) continue; // block-diagonal
          const Vec6 x = scale * e;
          Point at_rest; // elastic from a virgin state
          at_rest.s0 = virgin(m.get());
          at_rest.e0 = 0.9 * x;
          at_rest.de = x - at_rest.e0;
          Point loading; // loading past a history at 98 % of the strain
          loading.s0 = state_after(m.get(), Vec6(0.98 * x));
          loading.e0 = 0.98 * x;
          loading.de = x - loading.e0;
          pts.push_back(at_rest);
          pts.push_back(loading);
        }
      const std::string what = std::string(pnc::damage::model_name(model)) +
                               (general_only ? " general strains only" : " mixed");
      for (int request : {PNC_MATERIAL_TANGENT_NONE, PNC_MATERIAL_TANGENT_CONSISTENT})
        expect_batch_equals_single(m.get(), pts, request, what);
      const auto st = paths_of(p, Blocks(pts, pnc_material_n_state(m.get())));
      EXPECT_GT(st.kernel + st.growth, 0u) << what; // some points' damage grows
      EXPECT_GT(st.elastic, 0u) << what;
    }
}

// The growth pass for general strains (D403): every mode of a 3-D strain may be sheared and
// capped, the third one included (a block-diagonal strain leaves it neither). Points whose third
// mode loads into damage, capped or not, with the consistent tangent: the single-point bits,
// through the growth pass.
TEST(FeMaterialBatch, AGrowingThirdModeOfAGeneralStrainTakesTheGrowthPassWithTheKernelsBits) {
  const NdmParameters p = params(Model::pnc, false);
  auto m = make(p);
  std::vector<Point> pts;
  int capped = 0, uncapped = 0;
  for (const double g : {0.0, 0.01, 0.03, 0.06})
    for (const double e33 : {0.12, 0.18}) {
      Vec6 e;
      e << 0.004, -0.002, e33, g, 0.5 * g, 0.2 * g; // g23, g13, g12
      const pnc::damage::ModeStretch ms = pnc::damage::mode_stretches(Model::pnc, e, false);
      (ms.lambda[2] == ms.lambda_max && g > 0.0 ? capped : uncapped) += 1;
      Point pt;
      pt.s0 = state_after(m.get(), Vec6(0.98 * e));
      pt.e0 = 0.98 * e;
      pt.de = e - pt.e0;
      pts.push_back(pt);
    }
  EXPECT_GT(capped, 0);   // a shear lifts the third mode's uncapped stretch above lambda_max
  EXPECT_GT(uncapped, 0); // the pure extensions
  expect_batch_equals_single(m.get(), pts, PNC_MATERIAL_TANGENT_CONSISTENT, "third mode");
  Blocks again(pts, pnc_material_n_state(m.get()));
  const auto st = pnc::damage::integrate_batch(
      pnc::damage::prepare(p), batch_view(again, pnc::damage::TangentKind::consistent));
  EXPECT_EQ(st.growth, pts.size()); // every point's damage grows, none goes to the kernel
  EXPECT_EQ(st.kernel, 0u);
}

TEST(FeMaterialBatch, ACappedModeGrowingAtARepeatedLargestStretchGoesToTheKernel) {
  const NdmParameters p = params(Model::pnc, false);
  auto m = make(p);
  std::vector<Point> pts;
  for (const double g12 : {0.02, 0.04, -0.03}) {
    const double e11 = 0.005, e22 = 0.12;
    const double a = 1 + e11, b = 1 + e22;
    const double smax =
        0.5 * (std::sqrt((a + b) * (a + b) + g12 * g12) + std::sqrt((a - b) * (a - b) + g12 * g12));
    Vec6 e;
    e << e11, e22, smax - 1.0, 0.0, 0.0, g12;
    // mode 2 (x2) is capped here: its uncapped stretch e22 + t + sqrt(1 + t^2) exceeds smax
    ASSERT_GT(e22 + 0.5 * std::abs(g12) + std::sqrt(1 + 0.25 * g12 * g12), smax);
    Point pt;
    pt.s0 = state_after(m.get(), Vec6(0.98 * e));
    pt.e0 = 0.98 * e;
    pt.de = e - pt.e0;
    pts.push_back(pt);
  }
  expect_batch_equals_single(m.get(), pts, PNC_MATERIAL_TANGENT_CONSISTENT, "repeated");
  Blocks again(pts, pnc_material_n_state(m.get()));
  const auto st = paths_of(p, again); // stress only: no direction needed, the growth pass
  EXPECT_EQ(st.growth, pts.size());
  const auto sk = pnc::damage::integrate_batch(
      pnc::damage::prepare(p), batch_view(again, pnc::damage::TangentKind::consistent));
  EXPECT_EQ(sk.kernel, pts.size()); // the consistent tangent needs the direction: the kernel
  EXPECT_EQ(sk.growth, 0u);
}

TEST(FeMaterialBatch, SizesZeroOneOddAndLargeWithPaddedBlocksAndInPlaceState) {
  const NdmParameters p = params(Model::pnc, true);
  auto m = make(p);
  const int ns = pnc_material_n_state(m.get());
  // n = 0: nothing to do, the arrays may be NULL
  pnc_material_point_soa empty;
  pnc_material_point_soa_init(&empty);
  empty.tangent_request = PNC_MATERIAL_TANGENT_CONSISTENT;
  EXPECT_EQ(pnc_material_integrate_batch(m.get(), 0, &empty), PNC_MATERIAL_OK);
  EXPECT_EQ(empty.n_failed, 0u);
  EXPECT_EQ(empty.first_failed, 0u);
  // 1, odd sizes across the chunk boundary (32), and a large batch; ld > n
  for (const std::size_t n :
       {std::size_t{1}, std::size_t{31}, std::size_t{33}, std::size_t{97}, std::size_t{5001}}) {
    const auto pts = make_points(m.get(), Model::pnc, n, static_cast<unsigned>(n));
    Blocks b(pts, ns, 3);
    char err[512] = {0};
    pnc_material_point_soa v = b.view(PNC_MATERIAL_TANGENT_CONSISTENT, err, sizeof err);
    ASSERT_EQ(pnc_material_integrate_batch(m.get(), n, &v), PNC_MATERIAL_OK) << err;
    const std::size_t stride = n > 200 ? 37 : 1; // every point of the small ones
    for (std::size_t i = 0; i < n; i += stride)
      expect_point_equal(m.get(), pts, b, i, PNC_MATERIAL_TANGENT_CONSISTENT,
                         "n = " + std::to_string(n));
    // the padding past n is not touched
    for (std::size_t k = 0; k < 6; ++k)
      for (std::size_t i = n; i < b.ld; ++i)
        EXPECT_EQ(b.sig[k * b.ld + i], -99.0);
    for (std::size_t i = n; i < b.ld; ++i) {
      EXPECT_EQ(b.K[35 * b.ld + i], -99.0);
      EXPECT_EQ(b.status[i], -99);
    }
    // state1 == state0 (in place) gives the same end state
    std::vector<double> inplace = b.s0;
    v.state0 = inplace.data();
    v.state1 = inplace.data();
    ASSERT_EQ(pnc_material_integrate_batch(m.get(), n, &v), PNC_MATERIAL_OK) << err;
    for (std::size_t k = 0; k < static_cast<std::size_t>(ns); ++k)
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_TRUE(same_bits(inplace[k * b.ld + i], b.s1[k * b.ld + i])) << "n = " << n;
  }
}

// ------------------------------------------------------------------ failures
// Failed points in the first chunk of 32: every other point of that chunk still gets its
// numbers, through each of the batch's writes (elastic, unloading, kernel and, for the aligned
// pnc law with plane strains, growth-pass points; D399, D401).
TEST(FeMaterialBatch, BadPointsAreReportedAndTheOthersAreComputed) {
  const struct {
    Model model;
    bool rotated;
    int plane_every;
  } setups[] = {{Model::pnc, true, 5}, {Model::pnc, false, 1}, {Model::pp, true, 5}};
  for (const auto& setup : setups) {
    const Model model = setup.model;
    const NdmParameters par = params(model, setup.rotated);
    auto m = make(par);
    const int ns = pnc_material_n_state(m.get());
    auto pts = make_points(m.get(), model, 70, 5, 0.7, 0.2, setup.plane_every);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    pts[17].de[2] = nan;                                     // a non-finite strain
    pts[40].s0[0] = std::numeric_limits<double>::infinity(); // a non-finite state
    pts[41].e0 << 1e300, 1e300, 0, 0, 0, 1e300;              // a result that overflows
    pts[41].de.setZero();
    Blocks b(pts, ns);
    char err[512] = {0};
    pnc_material_point_soa v = b.view(PNC_MATERIAL_TANGENT_CONSISTENT, err, sizeof err);
    ASSERT_EQ(pnc_material_integrate_batch(m.get(), b.n, &v), PNC_MATERIAL_BAD_INPUT);
    EXPECT_EQ(v.n_failed, 3u);
    EXPECT_EQ(v.first_failed, 17u);
    const std::string msg = err;
    EXPECT_NE(msg.find("pnc_material_integrate_batch"), std::string::npos) << msg;
    EXPECT_NE(msg.find("dstrain[component 2, point 17]"), std::string::npos) << msg;
    EXPECT_NE(msg.find("nan"), std::string::npos) << msg;
    EXPECT_NE(msg.find("finite"), std::string::npos) << msg;
    for (const std::size_t bad : {std::size_t{17}, std::size_t{40}, std::size_t{41}}) {
      // the single-point entry refuses the same points
      const Out o = call(m.get(), pts[bad].s0.data(), pts[bad].e0, pts[bad].de,
                         PNC_MATERIAL_TANGENT_CONSISTENT);
      EXPECT_EQ(o.status, PNC_MATERIAL_BAD_INPUT) << bad;
      EXPECT_EQ(b.status[bad], PNC_MATERIAL_BAD_INPUT) << bad;
      for (std::size_t k = 0; k < 6; ++k)
        EXPECT_EQ(b.sig[k * b.ld + bad], -99.0) << bad;
      for (std::size_t k = 0; k < static_cast<std::size_t>(ns); ++k)
        EXPECT_EQ(b.s1[k * b.ld + bad], -99.0) << bad;
      for (std::size_t rc = 0; rc < 36; ++rc)
        EXPECT_EQ(b.K[rc * b.ld + bad], -99.0) << bad;
      EXPECT_EQ(b.stored[bad], -99.0);
      EXPECT_EQ(b.diss[bad], -99.0);
    }
    for (std::size_t i = 0; i < b.n; ++i)
      if (i != 17 && i != 40 && i != 41)
        expect_point_equal(m.get(), pts, b, i, PNC_MATERIAL_TANGENT_CONSISTENT, "with bad points");
    // the paths of the first chunk alone: its failed point and the others
    const std::vector<Point> first(pts.begin(), pts.begin() + 32);
    const auto st = paths_of(par, Blocks(first, ns));
    EXPECT_EQ(st.failed, 1u);
    EXPECT_EQ(st.first_failed, 17u);
    EXPECT_EQ(st.elastic + st.unloading + st.growth + st.kernel + st.failed, 32u);
    EXPECT_GT(st.elastic, 0u);
    EXPECT_GT(st.unloading + st.growth + st.kernel, 0u);
    if (model == Model::pnc && setup.plane_every == 1) {
      EXPECT_GT(st.growth, 0u);
    }
  }
}

TEST(FeMaterialBatch, BadArgumentsAreRefusedWithTheFieldAndNothingWritten) {
  auto m = make(params(Model::pnc, false));
  const auto pts = make_points(m.get(), Model::pnc, 4, 3);
  Blocks b(pts, 6);
  char err[512] = {0};
  auto expect = [&](pnc_material_point_soa v, const pnc_material* mat, std::size_t n, int status,
                    const char* field) {
    err[0] = '\0';
    EXPECT_EQ(pnc_material_integrate_batch(mat, n, &v), status) << field;
    EXPECT_NE(std::string(err).find(field), std::string::npos) << err;
    EXPECT_EQ(b.sig[0], -99.0) << field;
    EXPECT_EQ(b.status[0], -99) << field;
  };
  EXPECT_EQ(pnc_material_integrate_batch(m.get(), 4, nullptr), PNC_MATERIAL_BAD_ARGUMENT);
  pnc_material_point_soa v = b.view(PNC_MATERIAL_TANGENT_CONSISTENT, err, sizeof err);
  expect(v, nullptr, 4, PNC_MATERIAL_BAD_ARGUMENT, "'m'");
  v.version = PNC_MATERIAL_POINT_SOA_VERSION + 1;
  expect(v, m.get(), 4, PNC_MATERIAL_BAD_ARGUMENT, "batch.version");
  v = b.view(7, err, sizeof err);
  expect(v, m.get(), 4, PNC_MATERIAL_BAD_ARGUMENT, "batch.tangent_request");
  v = b.view(PNC_MATERIAL_TANGENT_CONSISTENT, err, sizeof err);
  expect(v, m.get(), 5, PNC_MATERIAL_BAD_ARGUMENT, "batch.ld");
  v.tangent = nullptr;
  expect(v, m.get(), 4, PNC_MATERIAL_BAD_ARGUMENT, "tangent");
  v = b.view(PNC_MATERIAL_TANGENT_NONE, err, sizeof err);
  v.dt = -1.0;
  expect(v, m.get(), 4, PNC_MATERIAL_BAD_INPUT, "batch.dt");
  v.dt = std::numeric_limits<double>::quiet_NaN();
  expect(v, m.get(), 4, PNC_MATERIAL_BAD_INPUT, "batch.dt");
}

// ------------------------------------------------------------------ layout versions
TEST(FeMaterialBatch, AnOlderSmallerStructIsAcceptedAndOnlyItsBytesAreTouched) {
  auto m = make(params(Model::pp, false));
  auto pts = make_points(m.get(), Model::pp, 40, 9);
  Blocks b(pts, 2);
  char err[512] = {0};
  pnc_material_point_soa v = b.view(PNC_MATERIAL_TANGENT_SECANT, err, sizeof err);
  // ends after `tangent`: no status array, energies, counters or message
  v.size = static_cast<uint32_t>(offsetof(pnc_material_point_soa, status));
  v.n_failed = 1234;
  v.first_failed = 5678;
  ASSERT_EQ(pnc_material_integrate_batch(m.get(), b.n, &v), PNC_MATERIAL_OK);
  for (std::size_t i = 0; i < b.n; ++i) {
    EXPECT_EQ(b.status[i], -99);
    EXPECT_EQ(b.stored[i], -99.0);
    EXPECT_EQ(b.diss[i], -99.0);
    const Out o =
        call(m.get(), pts[i].s0.data(), pts[i].e0, pts[i].de, PNC_MATERIAL_TANGENT_SECANT);
    for (std::size_t k = 0; k < 6; ++k)
      EXPECT_TRUE(same_bits(b.sig[k * b.ld + i], o.stress[k])) << i;
  }
  EXPECT_EQ(v.n_failed, 1234u);
  EXPECT_EQ(v.first_failed, 5678u);
  // with a failing point: BAD_INPUT, still no write past `size`
  b.e0[0] = std::numeric_limits<double>::quiet_NaN();
  err[0] = '\0';
  EXPECT_EQ(pnc_material_integrate_batch(m.get(), b.n, &v), PNC_MATERIAL_BAD_INPUT);
  EXPECT_EQ(err[0], '\0');
  EXPECT_EQ(v.n_failed, 1234u);
  // too small to reach the arrays: refused
  v.size = static_cast<uint32_t>(offsetof(pnc_material_point_soa, tangent));
  EXPECT_EQ(pnc_material_integrate_batch(m.get(), b.n, &v), PNC_MATERIAL_BAD_ARGUMENT);
}

TEST(FeMaterialBatch, TheSymbolCarriesMinorTwoAndTheWrapperReachesIt) {
  void* h = dlopen(PNC_MATERIAL_PLUGIN_PATH, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(h, nullptr) << dlerror();
  const std::string v1 = "PNC_MATERIAL_" + std::to_string(PNC_MATERIAL_ABI_VERSION);
  EXPECT_NE(dlvsym(h, "pnc_material_integrate_batch", (v1 + ".2").c_str()), nullptr);
  EXPECT_EQ(dlvsym(h, "pnc_material_integrate_batch", (v1 + ".1").c_str()), nullptr);
  EXPECT_EQ(dlvsym(h, "pnc_material_integrate_batch", v1.c_str()), nullptr);
  dlclose(h);
  EXPECT_GE(PNC_MATERIAL_ABI_VERSION_MINOR, 2); // 2 added the batch; later minors keep it
  // through a dlopen()ed plugin and the C++ wrapper
  const pnc::fe_material::Plugin plugin(PNC_MATERIAL_PLUGIN_PATH);
  EXPECT_EQ(plugin.abi_version_minor(), PNC_MATERIAL_ABI_VERSION_MINOR);
  const NdmParameters p = params(Model::pnc, true);
  std::array<double, 9> R{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      R[static_cast<std::size_t>(3 * r + c)] = p.R(r, c);
  const auto mat =
      plugin.from_constants("pnc", std::vector<double>(p.k.begin(), p.k.begin() + 22), &R);
  auto m = make(p);
  auto pts = make_points(m.get(), Model::pnc, 9, 4);
  pts[6].e0[1] = std::numeric_limits<double>::infinity();
  Blocks b(pts, 6);
  pnc_material_point_soa v = b.view(PNC_MATERIAL_TANGENT_ELASTIC, nullptr, 0);
  try {
    mat.integrate_batch(b.n, v);
    ADD_FAILURE() << "no exception";
  } catch (const pnc::fe_material::Error& e) {
    EXPECT_EQ(e.status(), PNC_MATERIAL_BAD_INPUT);
    EXPECT_NE(std::string(e.what()).find("strain0[component 1, point 6]"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(v.err, nullptr); // the caller's (absent) buffer is restored
  EXPECT_EQ(b.status[6], PNC_MATERIAL_BAD_INPUT);
  for (std::size_t i = 0; i < b.n; ++i)
    if (i != 6) expect_point_equal(m.get(), pts, b, i, PNC_MATERIAL_TANGENT_ELASTIC, "wrapper");
}

} // namespace

// ------------------------------------------------------------------ instruction sets
// The batch is compiled for SSE2, AVX2 and AVX-512 from one source without fused multiply-adds
// (D386, D413): the copies must give the same bits for every output on every path, including the
// mixed, all-plane and all-general chunks and the points that fail.
//
// One policy for the vector copies (tests/CMakeLists.txt): where the configure check finds the
// instruction set the copy is compared with the baseline bit for bit; elsewhere an explicit
// request for it must be refused by name instead of running an illegal instruction.
namespace {

using pnc::damage::BatchIsa;

[[maybe_unused]] void expect_request_refused(BatchIsa isa, const char* name) {
  EXPECT_FALSE(pnc::damage::batch_isa_available(isa));
  auto m = make(params(Model::pnc, false));
  auto pts = make_points(m.get(), Model::pnc, 8, 386, 0.7, 0.2, 1);
  Blocks b(pts, pnc_material_n_state(m.get()), 3);
  const pnc::damage::NdmBatch view = batch_view(b, pnc::damage::TangentKind::none);
  try {
    pnc::damage::integrate_batch(pnc::damage::prepare(params(Model::pnc, false)), view, isa);
    ADD_FAILURE() << "the " << name << " copy ran on a CPU without " << name;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

[[maybe_unused]] void expect_same_bits_as_baseline(BatchIsa isa, const char* name) {
  ASSERT_TRUE(pnc::damage::batch_isa_available(isa))
      << "the configure check found " << name << ", the library has no " << name
      << " copy or does not see it";
  const Eigen::Matrix3d in_3d = rotation_zx(30.0, 20.0);
  for (const Model model : {Model::pnc, Model::pp})
    for (const int plane_every : {5, 1, 0})
      for (const bool rotated : {false, true}) {
        NdmParameters p = params(model, false);
        if (rotated) p.R = in_3d;
        auto m = make(p);
        auto pts = make_points(m.get(), model, 150, 386, 0.7, 0.2, plane_every);
        pts[33].de[1] = std::numeric_limits<double>::quiet_NaN(); // a failing point
        const pnc::damage::PreparedNdm q = pnc::damage::prepare(p);
        const std::string what = std::string(name) + ": " + pnc::damage::model_name(model) +
                                 " plane_every " + std::to_string(plane_every) +
                                 (rotated ? " rotated" : "");
        for (const auto kind :
             {pnc::damage::TangentKind::none, pnc::damage::TangentKind::consistent}) {
          Blocks out[2] = {Blocks(pts, pnc_material_n_state(m.get()), 3),
                           Blocks(pts, pnc_material_n_state(m.get()), 3)};
          pnc::damage::NdmBatchStats st[2];
          for (int v = 0; v < 2; ++v) {
            Blocks& b = out[v];
            st[v] = pnc::damage::integrate_batch(q, batch_view(b, kind),
                                                 v == 0 ? BatchIsa::baseline : isa);
          }
          EXPECT_EQ(st[0].elastic, st[1].elastic) << what;
          EXPECT_EQ(st[0].unloading, st[1].unloading) << what;
          EXPECT_EQ(st[0].kernel, st[1].kernel) << what;
          EXPECT_EQ(st[0].growth, st[1].growth) << what;
          EXPECT_EQ(st[0].failed, 1u) << what;
          EXPECT_EQ(st[1].failed, 1u) << what;
          EXPECT_EQ(st[1].first_failed, 33u) << what;
          EXPECT_GT(st[1].elastic, 50u) << what; // the fast paths are exercised
          EXPECT_GT(st[1].kernel + st[1].growth, 10u) << what;
          // every damage growth of an aligned pnc plane strain takes the growth pass (D399)
          if (model == Model::pnc && plane_every == 1 && !rotated) {
            EXPECT_EQ(st[1].kernel, 0u) << what;
          }
          const auto same = [&](const std::vector<double>& a, const std::vector<double>& b,
                                const char* field) {
            ASSERT_EQ(a.size(), b.size());
            for (std::size_t i = 0; i < a.size(); ++i)
              ASSERT_TRUE(same_bits(a[i], b[i]))
                  << what << " " << field << "[" << i << "]: " << a[i] << " vs " << b[i];
          };
          same(out[0].sig, out[1].sig, "sigma");
          same(out[0].s1, out[1].s1, "state1");
          same(out[0].K, out[1].K, "K");
          same(out[0].stored, out[1].stored, "stored");
          same(out[0].diss, out[1].diss, "dissipated");
          EXPECT_EQ(out[0].status, out[1].status) << what;
        }
      }
}

} // namespace

#if PNC_TEST_CPU_HAS_AVX2
TEST(FeMaterialBatch, TheAvx2AndBaselineCopiesGiveTheSameBits) {
  expect_same_bits_as_baseline(BatchIsa::avx2, "AVX2");
}
#else
TEST(FeMaterialBatch, AnAvx2RequestIsRefusedOnACpuWithoutAvx2) {
  expect_request_refused(BatchIsa::avx2, "AVX2");
}
#endif

#if PNC_TEST_CPU_HAS_AVX512
TEST(FeMaterialBatch, TheAvx512AndBaselineCopiesGiveTheSameBits) {
  expect_same_bits_as_baseline(BatchIsa::avx512, "AVX-512");
}
#else
TEST(FeMaterialBatch, AnAvx512RequestIsRefusedOnACpuWithoutAvx512) {
  expect_request_refused(BatchIsa::avx512, "AVX-512");
}
#endif
