// Tests of the material plugin, part 2: the umat_ entry (argument checks, plane strain), the
// card verdict and the state and result checks of both entries. Part 1: test_fe_material.cpp.
#include "fe_material_support.hpp"

using namespace fe_material_test;

namespace {

// ------------------------------------------------------------------ umat_
class FeMaterialUmat : public ::testing::Test {
protected:
  NdmParameters p = params(Model::pnc, false);
  std::vector<double> props = umat_props(p, false);
  UmatCall call;
  std::array<double, 6> stress{}, stran{}, dstran{0.01, 0, 0, 0, 0, 0};
  std::array<double, 36> ddsdde{};
  std::vector<double> statev = std::vector<double>(6, 0.0);
  void SetUp() override {
    // configuration errors in the non-exiting mode (the default "stop" mode: test_umat_stop.cpp)
    setenv("PNC_UMAT_ON_CONFIG_ERROR", "cutback", 1);
    call.nprops = static_cast<int>(props.size());
    call.nstatv = 6;
    call.pnewdt = 1e36;
    stress.fill(-7);
    ddsdde.fill(-7);
    std::fill(statev.begin(), statev.end(), -7);
  }
  // Runs umat_ expecting a rejection; returns the stderr line.
  std::string rejected() {
    ::testing::internal::CaptureStderr();
    call(stress.data(), statev.data(), ddsdde.data(), stran.data(), dstran.data(), props.data());
    const std::string out = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(call.pnewdt, 0.5);
    for (double s : stress)
      EXPECT_EQ(s, -7);
    for (double s : statev)
      EXPECT_EQ(s, -7);
    for (double s : ddsdde)
      EXPECT_EQ(s, -7);
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_EQ(out.rfind("UMAT material 'PNC-CARD' (element 7, point 2): argument '", 0), 0u) << out;
    return out;
  }
};

TEST_F(FeMaterialUmat, WrongNpropsIsNamed) {
  call.nprops = 20;
  const std::string out = rejected();
  EXPECT_NE(out.find("argument 'NPROPS': value '20'"), std::string::npos) << out;
  EXPECT_NE(out.find("model pnc needs 23 (model code + 22 constants C11..alpha) or 32"),
            std::string::npos)
      << out;
}

TEST_F(FeMaterialUmat, WrongNstatvIsNamed) {
  call.nstatv = 2;
  const std::string out = rejected();
  EXPECT_NE(out.find("argument 'NSTATV': value '2'"), std::string::npos) << out;
  EXPECT_NE(out.find("model pnc has 6 state variables (kappa1 kappa2 kappa3 D1 D2 D3)"),
            std::string::npos)
      << out;
}

TEST_F(FeMaterialUmat, WrongModelCodeNtensAndConstantsAreNamed) {
  props[0] = 3;
  EXPECT_NE(rejected().find("argument 'PROPS(1)': value '3': the model code must be 1 (pnc)"),
            std::string::npos);
  SetUp();
  props[0] = 1;
  call.ntens = 3;
  call.nshr = 1;
  call.ndi = 2;
  EXPECT_NE(rejected().find("argument 'NTENS': value '3': must be 6 (3-D) or 4"),
            std::string::npos);
  SetUp();
  call.ntens = 6;
  call.nshr = 1;
  call.ndi = 3;
  EXPECT_NE(rejected().find("argument 'NDI, NSHR': value '3, 1': must be 3, 3"), std::string::npos);
  SetUp();
  call.nshr = 3;
  props[23 - 1] = 0.0; // alpha = PROPS(23)
  const std::string a = rejected();
  EXPECT_NE(a.find("argument 'PROPS(23) = alpha': value '0.000000'"), std::string::npos) << a;
  EXPECT_NE(a.find("must be > 0"), std::string::npos) << a;
  SetUp();
  props[22] = p["alpha"];
  props[1 + 3] = 2.5e9; // C12 = PROPS(5): C0 indefinite
  const std::string c = rejected();
  EXPECT_NE(c.find("argument 'PROPS(2..23) = C0 (C11..C33, C12, C13, C23)'"), std::string::npos)
      << c;
  EXPECT_NE(c.find("positive definite"), std::string::npos) << c;
  SetUp();
  props[1 + 3] = p["C12"];
  props.insert(props.end(), {1, 0, 0, 0, 1, 0, 0, 0, -1}); // det R = -1
  call.nprops = 32;
  EXPECT_NE(rejected().find("argument 'PROPS(24..32) = platelet rotation R'"), std::string::npos);
}

TEST_F(FeMaterialUmat, NonFiniteStrainIsNamed) {
  std::fill(statev.begin(), statev.end(), 0.0);
  dstran[4] = std::numeric_limits<double>::quiet_NaN();
  ::testing::internal::CaptureStderr();
  call(stress.data(), statev.data(), ddsdde.data(), stran.data(), dstran.data(), props.data());
  const std::string out = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(call.pnewdt, 0.5);
  EXPECT_NE(out.find("argument 'STRAN(5) / DSTRAN(5)': value '0 / nan': strains must be finite"),
            std::string::npos)
      << out;
  EXPECT_EQ(stress[0], -7);
  EXPECT_EQ(statev[0], 0.0);
}

TEST_F(FeMaterialUmat, ZeroStatevIsTheVirginState) {
  std::fill(statev.begin(), statev.end(), 0.0);
  dstran = {0.12, 0, 0, 0.01, 0, 0};
  call(stress.data(), statev.data(), ddsdde.data(), stran.data(), dstran.data(), props.data());
  EXPECT_EQ(call.pnewdt, 1e36);
  std::vector<double> s2(6, 0.0);
  pnc::damage::state_to_array(Model::pnc, NdmState{}, s2.data());
  std::array<double, 6> stress2{};
  std::array<double, 36> dd2{};
  call(stress2.data(), s2.data(), dd2.data(), stran.data(), dstran.data(), props.data());
  EXPECT_EQ(statev, s2);
  EXPECT_EQ(stress, stress2);
  EXPECT_EQ(ddsdde, dd2);
  EXPECT_GT(statev[3], 0.0); // D1 > 0 at e11 = 0.12
  // SSE = 1/2 sigma . eps (secant energy density).
  EXPECT_NEAR(call.sse, 0.5 * (stress[0] * 0.12 + stress[3] * 0.01), 1e-12 * std::abs(call.sse));
}

TEST_F(FeMaterialUmat, PlaneStrainMatchesThe3DKernel) {
  for (bool rotated : {false, true}) {
    // Plane strain needs x3 to stay a principal material direction: rotate about x3 only.
    NdmParameters pr = p;
    if (rotated) pr.R = rotation_zx(25.0, 0.0);
    const std::vector<double> pprops = umat_props(pr, rotated);
    UmatCall c4;
    c4.ntens = 4;
    c4.nshr = 1;
    c4.nprops = static_cast<int>(pprops.size());
    c4.nstatv = 6;
    std::vector<double> sv(6, 0.0);
    std::array<double, 4> s4{}, e4{}, d4{};
    std::array<double, 16> K4{};
    Voigt dir;
    dir << 1.0, -0.4, 0, 0, 0, 0.7; // e11, e22, g12 only: e33 = g13 = g23 = 0
    const auto path = strain_path(dir, 0.15);
    const auto ref = run_kernel(pr, path);
    EXPECT_TRUE(path_damages(ref, Model::pnc));
    for (std::size_t i = 0; i < path.size(); ++i) {
      ASSERT_EQ(path[i][k33], 0.0);
      for (std::size_t a = 0; a < 4; ++a)
        d4[a] = path[i][kAbaqus4[a]] - e4[a];
      c4(s4.data(), sv.data(), K4.data(), e4.data(), d4.data(), pprops.data());
      ASSERT_EQ(c4.pnewdt, 1e36);
      const double ss = ref[i].stress.cwiseAbs().maxCoeff();
      const double sk = ref[i].K.cwiseAbs().maxCoeff();
      for (std::size_t a = 0; a < 4; ++a) {
        EXPECT_LE(std::abs(s4[a] - ref[i].stress[kAbaqus4[a]]), kRelTol * ss) << i << " " << a;
        for (std::size_t b = 0; b < 4; ++b)
          EXPECT_LE(std::abs(K4[a + 4 * b] - ref[i].K(kAbaqus4[a], kAbaqus4[b])), kRelTol * sk)
              << i << " " << a << " " << b;
        e4[a] += d4[a];
      }
      for (std::size_t k = 0; k < 6; ++k)
        EXPECT_LE(std::abs(sv[k] - ref[i].state[k]), kRelTol) << i << " " << k;
    }
    // sigma_33 is reported (plane strain); it is not zero.
    EXPECT_NE(s4[2], 0.0);
  }
}

} // namespace

// ---------------------------------------------------------------- card verdict
namespace {
std::string not_usable_card() {
  const fs::path path = temp_dir() / "card_not_usable.h5";
  pnc::damage::Card c = pnc::damage::card_from_parameters(params(Model::pnc, false), "test");
  c.verdict = {};
  c.verdict.refuse("case 2 sigma22: R^2 = -11: worse than the mean");
  pnc::damage::write_card(path.string(), c, "test_fe_material");
  return path.string();
}
} // namespace

TEST(FeMaterialVerdict, ANotUsableCardIsRefusedUnlessTheHostAsks) {
  const std::string bad = not_usable_card();
  char err[1024] = {0};
  ASSERT_EQ(std::getenv("PNC_ALLOW_NOT_USABLE_CARD"), nullptr);
  EXPECT_EQ(pnc_material_create(bad.c_str(), err, sizeof err), nullptr);
  const std::string msg = err;
  EXPECT_NE(msg.find(bad), std::string::npos) << msg;
  EXPECT_NE(msg.find("not usable"), std::string::npos) << msg;
  EXPECT_NE(msg.find("R^2 = -11"), std::string::npos) << msg; // the card's own reason
  pnc_material* m =
      pnc_material_create_ex(bad.c_str(), PNC_MATERIAL_ALLOW_NOT_USABLE, err, sizeof err);
  ASSERT_NE(m, nullptr) << err;
  EXPECT_STREQ(pnc_material_verdict(m), "not usable");
  pnc_material_destroy(m);
  // the user's explicit request through the environment
  ::setenv("PNC_ALLOW_NOT_USABLE_CARD", "1", 1);
  m = pnc_material_create(bad.c_str(), err, sizeof err);
  ::unsetenv("PNC_ALLOW_NOT_USABLE_CARD");
  EXPECT_NE(m, nullptr) << err;
  pnc_material_destroy(m);
  // through the dlopen()ed plugin and the C++ wrapper
  Plugin plugin(plugin_path());
  EXPECT_THROW((void)plugin.from_card(bad), pnc::fe_material::Error);
  EXPECT_EQ(plugin.from_card(bad, true).verdict(), "not usable");
  EXPECT_EQ(plugin.from_card(card_path(Model::pnc, false)).verdict(), "usable");
}

// ------------------------------------------------------------------ state and result checks
// Both entry points validate the state they are given and the result they hand back with one
// shared check (abi_util.hpp): a non-finite state entry, or a finite strain so large that the
// stress overflows a double (hydrostatic compression of 1e300: no damage, sigma = C0 eps), is
// an error; nothing is written to the caller's arrays.
TEST(FeMaterialHardening, NonFiniteStateOrResultIsAnErrorInBothEntries) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  char err[512] = {0};
  pnc_material* m = pnc_material_create(card_path(Model::pnc, false).c_str(), err, sizeof err);
  ASSERT_NE(m, nullptr) << err;
  const double e0[6] = {0, 0, 0, 0, 0, 0}, de[6] = {0.01, 0, 0, 0, 0, 0};
  const double crush[6] = {-1e300, -1e300, -1e300, 0, 0, 0};
  auto untouched = [](const double* x, int n) {
    return std::all_of(x, x + n, [](double v) { return v == -7; });
  };
  for (double bad : {nan, inf, -inf})
    for (int i = 0; i < 6; ++i) {
      double s0[6], s1[6], stress[6], K[36];
      pnc_material_init_state(m, s0);
      s0[i] = bad;
      std::fill(s1, s1 + 6, -7);
      std::fill(stress, stress + 6, -7);
      std::fill(K, K + 36, -7);
      EXPECT_EQ(pnc_material_integrate(m, s0, s1, e0, de, stress, K, err, sizeof err),
                PNC_MATERIAL_BAD_INPUT);
      EXPECT_NE(std::string(err).find("argument 'state0[" + std::to_string(i) + "]'"),
                std::string::npos)
          << err;
      EXPECT_NE(std::string(err).find("state variables must be finite"), std::string::npos);
      EXPECT_TRUE(untouched(s1, 6) && untouched(stress, 6) && untouched(K, 36));
    }
  double s0[6], s1[6], stress[6], K[36];
  pnc_material_init_state(m, s0);
  std::fill(s1, s1 + 6, -7);
  std::fill(stress, stress + 6, -7);
  std::fill(K, K + 36, -7);
  for (double* tangent : {K, static_cast<double*>(nullptr)}) {
    EXPECT_EQ(pnc_material_integrate(m, s0, s1, e0, crush, stress, tangent, err, sizeof err),
              PNC_MATERIAL_BAD_INPUT);
    EXPECT_NE(std::string(err).find("non-finite result"), std::string::npos) << err;
    EXPECT_TRUE(untouched(s1, 6) && untouched(stress, 6) && untouched(K, 36));
  }
  // The same strain and state through umat_: rejected with the same rules.
  const std::vector<double> props = umat_props(params(Model::pnc, false), false);
  UmatCall call;
  call.nprops = static_cast<int>(props.size());
  call.nstatv = 6;
  std::array<double, 6> ustress{}, stran{}, statev{};
  std::array<double, 36> ddsdde{};
  const std::array<double, 6> dcrush = {-1e300, -1e300, -1e300, 0, 0, 0};
  for (int round = 0; round < 2; ++round) {
    ustress.fill(-7);
    ddsdde.fill(-7);
    statev.fill(0.0);
    if (round == 0) statev[4] = inf;
    call.pnewdt = 1e36;
    ::testing::internal::CaptureStderr();
    call(ustress.data(), statev.data(), ddsdde.data(), stran.data(),
         round == 0 ? de : dcrush.data(), props.data());
    const std::string out = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(call.pnewdt, 0.5) << out;
    EXPECT_NE(out.find(round == 0 ? "argument 'STATEV(5)': value 'inf': state variables must be "
                                    "finite"
                                  : "non-finite result"),
              std::string::npos)
        << out;
    EXPECT_TRUE(untouched(ustress.data(), 6) && untouched(ddsdde.data(), 36)) << out;
  }
  pnc_material_destroy(m);
}
