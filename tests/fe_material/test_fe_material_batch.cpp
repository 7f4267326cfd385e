// Tests of ABI 1.2 of the material plugin (pnc_material.h "ABI 1.2", docs/plugin.md, decisions
// D260-D262): pnc_material_integrate_batch against pnc_material_integrate2 point by point. The
// batched route evaluates the kernel's expressions in the kernel's order, so stress, end state
// and tangent must be equal bit for bit; the stored energy sums the same six products in an
// order of its own (bound derived below); the dissipated energy is the kernel's or exactly 0.
#include "batch_support.hpp"

#include <dlfcn.h>

namespace {

using namespace pnc_v2_test;
using namespace pnc_batch_test;

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
        // every path is exercised: fast elastic and unloading points, and damage growth in
        // the growth pass, pnc and pp, plane and general strains alike (D399, D403, D419; a
        // stress-only request needs no principal direction, so none goes to the kernel)
        const auto st = paths_of(p, b);
        EXPECT_GT(st.elastic, 100u) << what;
        EXPECT_GT(st.unloading, 10u) << what;
        EXPECT_GT(st.growth, 30u) << what;
        EXPECT_EQ(st.kernel, 0u) << what;
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
        // the damage growth takes the growth pass, block-diagonal (plane strains aligned or
        // rotated about x3) and general strains alike, pnc (D399, D403) and pp (D419) points
        const auto st = paths_of(p, b);
        EXPECT_GT(st.growth, 15u) << what;
        EXPECT_EQ(st.kernel, 0u) << what;
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
  // pnc: mode 2 is capped at lambda_max; pp: its one mode is lambda_max (D419)
  for (const Model model : {Model::pnc, Model::pp}) {
    const NdmParameters p = params(model, false);
    const std::string what = std::string("repeated, ") + pnc::damage::model_name(model);
    auto m = make(p);
    std::vector<Point> pts;
    for (const double g12 : {0.02, 0.04, -0.03}) {
      // (pp's damage onset is at a larger stretch: a larger e22 loads it into damage)
      const double e11 = 0.005, e22 = model == Model::pnc ? 0.12 : 0.4;
      const double a = 1 + e11, b = 1 + e22;
      const double smax = 0.5 * (std::sqrt((a + b) * (a + b) + g12 * g12) +
                                 std::sqrt((a - b) * (a - b) + g12 * g12));
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
    expect_batch_equals_single(m.get(), pts, PNC_MATERIAL_TANGENT_CONSISTENT, what);
    Blocks again(pts, pnc_material_n_state(m.get()));
    const auto st = paths_of(p, again); // stress only: no direction needed, the growth pass
    EXPECT_EQ(st.growth, pts.size()) << what;
    const auto sk = pnc::damage::integrate_batch(
        pnc::damage::prepare(p), batch_view(again, pnc::damage::TangentKind::consistent));
    EXPECT_EQ(sk.kernel, pts.size()) << what; // the consistent tangent needs the direction
    EXPECT_EQ(sk.growth, 0u) << what;
  }
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
