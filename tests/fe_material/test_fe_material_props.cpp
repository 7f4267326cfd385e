// Tests of ABI 1.1 of the material plugin (decisions D211, D213), part 2: the property and
// state-index queries, the C++ wrapper through a dlopen()ed plugin, the symbol versions, and
// a host compiled against the frozen ABI 1.0 header (tests/fe_material/abi_v1/) running
// against this library. Part 1: test_fe_material_v2.cpp.
#include "v2_support.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <random>

#include <dlfcn.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace {

using namespace pnc_v2_test;

// ------------------------------------------------------------------ properties
double prop(const pnc_material* m, const std::string& name) {
  int st = -1;
  const double v = pnc_material_property(m, name.c_str(), &st);
  EXPECT_EQ(st, PNC_MATERIAL_OK) << name;
  return v;
}

// Brute-force lower bound of the largest P-wave modulus: the largest eigenvalue of the
// acoustic tensor over a fine grid of directions.
double sampled_p_wave_max(const Mat6& C, int n) {
  static const int v[3][3] = {{0, 5, 4}, {5, 1, 3}, {4, 3, 2}};
  double best = 0;
  for (int a = 0; a <= n; ++a)
    for (int b = 0; b < 2 * n; ++b) {
      const double th = std::acos(-1.0) * a / n, ph = std::acos(-1.0) * b / n;
      const Eigen::Vector3d d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                              std::cos(th));
      Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
      for (int i = 0; i < 3; ++i)
        for (int kk = 0; kk < 3; ++kk)
          for (int j = 0; j < 3; ++j)
            for (int l = 0; l < 3; ++l)
              G(i, kk) += C(v[i][j], v[kk][l]) * d[j] * d[l];
      best = std::max(best, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(G).eigenvalues()[2]);
    }
  return best;
}

TEST(FeMaterialV2, PropertiesAgreeWithTheConstants) {
  for (const Case& c : kCases) {
    const NdmParameters p = params(c.model, c.rotated);
    auto m = make(p);
    const Mat6 C0 = global_stiffness(p, {0, 0, 0});
    const int modes = c.model == Model::pnc ? 3 : 1;
    const double tol = 1e-13 * C0.norm(); // rounding of T^T C T
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const std::string ij = std::to_string(i + 1) + std::to_string(j + 1);
        EXPECT_NEAR(prop(m.get(), "elastic_stiffness_" + ij), C0(i, j), tol) << ij;
        for (int mode = 0; mode < modes; ++mode) {
          std::array<double, 3> unit{0, 0, 0};
          unit[static_cast<std::size_t>(mode)] = 1.0;
          const Mat6 M = global_stiffness(p, unit) - C0;
          EXPECT_NEAR(prop(m.get(), "damage_stiffness_" + std::to_string(mode + 1) + "_" + ij),
                      M(i, j), tol)
              << mode << " " << ij;
        }
      }
    double C36[36], M36[36];
    ASSERT_EQ(pnc_material_elastic_stiffness(m.get(), C36), PNC_MATERIAL_OK);
    EXPECT_EQ(C36[1], prop(m.get(), "elastic_stiffness_12"));
    ASSERT_EQ(pnc_material_damage_stiffness(m.get(), modes - 1, M36), PNC_MATERIAL_OK);
    EXPECT_EQ(M36[7], prop(m.get(), "damage_stiffness_" + std::to_string(modes) + "_22"));
    EXPECT_EQ(pnc_material_damage_stiffness(m.get(), modes, M36), PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(pnc_material_damage_stiffness(m.get(), -1, M36), PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(prop(m.get(), "n_damage_modes"), modes);
    EXPECT_NEAR(prop(m.get(), "critical_stretch"), lambda_c(), 1e-15);
    EXPECT_NEAR(prop(m.get(), "damage_onset_stretch"), p.alpha() * lambda_c(), 1e-15);
    // Moduli by compliance inversion of C0 (docs/theory.md 1.5).
    const Mat6 S = C0.inverse();
    const double E = 1e-12 * C0.norm();
    EXPECT_NEAR(prop(m.get(), "youngs_modulus_1"), 1 / S(0, 0), E);
    EXPECT_NEAR(prop(m.get(), "youngs_modulus_3"), 1 / S(2, 2), E);
    EXPECT_NEAR(prop(m.get(), "shear_modulus_12"), 1 / S(5, 5), E);
    EXPECT_NEAR(prop(m.get(), "poisson_ratio_12"), -S(0, 1) / S(0, 0), 1e-12);
    EXPECT_NEAR(prop(m.get(), "poisson_ratio_31"), -S(2, 0) / S(2, 2), 1e-12);
    // The largest P-wave modulus: at least every sampled direction's, and within the
    // sampling error (1-degree grid: relative 1e-3 of the curvature) above the best of them;
    // independent of the platelet rotation.
    const double M = prop(m.get(), "p_wave_modulus_max");
    const double sampled = sampled_p_wave_max(C0, 180);
    EXPECT_GE(M, sampled * (1 - 1e-14)) << name_of(c);
    EXPECT_LE(M, sampled * (1 + 1e-3)) << name_of(c);
    auto aligned = make(params(c.model, false));
    EXPECT_NEAR(M, prop(aligned.get(), "p_wave_modulus_max"), 1e-12 * M) << name_of(c);
    if (c.model == Model::pp) {
      // Cubic symmetry (the pp reading: C22 = C33 = C11, C55 = C66 = C44) with anisotropy
      // 2 C44 / (C11 - C12) > 1: the fastest longitudinal wave runs along <111>,
      // M = (C11 + 2 C12 + 4 C44) / 3, faster than along an axis (C11).
      const double c11 = p["C11"], c12 = p["C12"], c44 = p["C44"];
      ASSERT_GT(2 * c44 / (c11 - c12), 1.0);
      EXPECT_NEAR(M, (c11 + 2 * c12 + 4 * c44) / 3, 1e-12 * M);
      EXPECT_GT(M, c11 * 1.1);
    } else {
      // The nanocomposite card: the axis x1 (C11) is the fastest direction.
      EXPECT_NEAR(M, p["C11"], 1e-12 * M);
    }
  }
  // An isotropic material (C44 = (C11 - C12) / 2): M = C11 in every direction.
  NdmParameters iso = params(Model::pp, false);
  iso["C44"] = 0.5 * (iso["C11"] - iso["C12"]);
  auto mi = make(iso);
  EXPECT_NEAR(prop(mi.get(), "p_wave_modulus_max"), iso["C11"], 1e-12 * iso["C11"]);
}

TEST(FeMaterialV2, PropertyEnumerationUnknownNamesAndStateIndices) {
  auto m = make(params(Model::pnc, true));
  const int n = pnc_material_n_properties(m.get());
  EXPECT_EQ(n, 36 + 3 * 36 + 4 + 3 + 3 + 6);
  for (int i = 0; i < n; ++i) {
    const char* name = pnc_material_property_name(m.get(), i);
    const char* units = pnc_material_property_units(m.get(), i);
    ASSERT_NE(name, nullptr) << i;
    ASSERT_NE(units, nullptr) << i;
    EXPECT_TRUE(std::string(units) == "Pa" || std::string(units) == "1") << name;
    int st = -1;
    EXPECT_TRUE(std::isfinite(pnc_material_property(m.get(), name, &st))) << name;
    EXPECT_EQ(st, PNC_MATERIAL_OK);
  }
  EXPECT_EQ(pnc_material_property_name(m.get(), n), nullptr);
  EXPECT_EQ(pnc_material_property_name(m.get(), -1), nullptr);
  int st = 0;
  EXPECT_TRUE(std::isnan(pnc_material_property(m.get(), "wave_speed", &st)));
  EXPECT_EQ(st, PNC_MATERIAL_UNKNOWN_NAME);
  EXPECT_TRUE(std::isnan(pnc_material_property(m.get(), nullptr, &st)));
  EXPECT_EQ(st, PNC_MATERIAL_UNKNOWN_NAME);
  EXPECT_TRUE(std::isnan(pnc_material_property(nullptr, "n_damage_modes", &st)));
  EXPECT_EQ(st, PNC_MATERIAL_BAD_ARGUMENT);
  EXPECT_TRUE(std::isnan(pnc_material_property(m.get(), "damage_stiffness_4_11", nullptr)));

  EXPECT_EQ(pnc_material_state_index(m.get(), "kappa1"), 0);
  EXPECT_EQ(pnc_material_state_index(m.get(), "kappa3"), 2);
  EXPECT_EQ(pnc_material_state_index(m.get(), "D2"), 4);
  EXPECT_EQ(pnc_material_state_index(m.get(), "kappa"), -1);
  EXPECT_EQ(pnc_material_state_index(m.get(), nullptr), -1);
  auto pp = make(params(Model::pp, false));
  EXPECT_EQ(pnc_material_state_index(pp.get(), "kappa"), 0);
  EXPECT_EQ(pnc_material_state_index(pp.get(), "D"), 1);
  EXPECT_EQ(pnc_material_state_index(pp.get(), "kappa1"), 0); // one loop over modes for both
  EXPECT_EQ(pnc_material_state_index(pp.get(), "D1"), 1);
  EXPECT_EQ(pnc_material_state_index(pp.get(), "kappa2"), -1);
  EXPECT_EQ(pnc_material_n_properties(pp.get()), 36 + 36 + 4 + 3 + 3 + 6);

  for (Model md : {Model::pnc, Model::pp}) {
    const auto& names = pnc::damage::constant_names(md);
    const char* mn = pnc::damage::model_name(md);
    ASSERT_EQ(pnc_material_model_n_constants(mn), static_cast<int>(names.size()));
    for (std::size_t i = 0; i < names.size(); ++i)
      EXPECT_EQ(pnc_material_model_constant_name(mn, static_cast<int>(i)), names[i]);
    EXPECT_EQ(pnc_material_model_constant_name(mn, static_cast<int>(names.size())), nullptr);
  }
  EXPECT_EQ(pnc_material_model_n_constants("steel"), 0);
  EXPECT_EQ(pnc_material_model_n_constants(nullptr), 0);
  EXPECT_EQ(pnc_material_model_constant_name("steel", 0), nullptr);
}

TEST(FeMaterialV2, PropertiesAreComputedOnceWhenThreadsAskAtTheSameTime) {
  // The properties are computed at the first query (double-checked locking): 8 threads asking a
  // fresh material at once must all see the values one thread sees later.
  auto m = make(params(Model::pnc, true));
  std::vector<double> got(8, 0.0);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i)
    threads.emplace_back(
        [&, i] { got[i] = pnc_material_property(m.get(), "p_wave_modulus_max", nullptr); });
  for (auto& t : threads)
    t.join();
  const double ref = pnc_material_property(m.get(), "p_wave_modulus_max", nullptr);
  EXPECT_TRUE(std::isfinite(ref));
  for (const double v : got)
    EXPECT_EQ(v, ref);
}

TEST(FeMaterialV2, TheCxxWrapperThroughThePluginReachesAbi11) {
  const pnc::fe_material::Plugin plugin(PNC_MATERIAL_PLUGIN_PATH);
  EXPECT_EQ(plugin.abi_version_minor(), PNC_MATERIAL_ABI_VERSION_MINOR);
  EXPECT_EQ(plugin.model_constant_names("pp"),
            (std::vector<std::string>{"C11", "C12", "C44", "B1", "B2", "B4", "alpha"}));
  EXPECT_THROW(plugin.model_constant_names("steel"), pnc::fe_material::Error);
  const NdmParameters p = params(Model::pnc, true);
  const auto mat = plugin.from_constants("pnc", std::vector<double>(p.k.begin(), p.k.begin() + 22));
  EXPECT_EQ(mat.n_damage_modes(), 3);
  EXPECT_EQ(mat.state_index("D3"), 5);
  EXPECT_THROW((void)mat.state_index("D4"), pnc::fe_material::Error);
  EXPECT_THROW((void)mat.property("nope"), pnc::fe_material::Error);
  EXPECT_EQ(mat.property_names().size(), mat.property_units().size());
  const auto C = mat.elastic_stiffness();
  EXPECT_EQ(C[0], mat.property("elastic_stiffness_11"));
  EXPECT_THROW((void)mat.damage_stiffness(3), pnc::fe_material::Error);
  std::vector<double> s0 = mat.initial_state(), s1(6);
  const std::array<double, 6> z{}, e{0.01, 0.2, 0, 0, 0, 0};
  std::array<double, 6> sig{};
  std::array<double, 36> K{};
  const auto en = mat.integrate2(s0.data(), s1.data(), z.data(), e.data(), sig.data(), K.data(),
                                 PNC_MATERIAL_TANGENT_SECANT, 1e-3);
  double work = 0;
  for (int i = 0; i < 6; ++i)
    work += 0.5 * sig[static_cast<std::size_t>(i)] * e[static_cast<std::size_t>(i)];
  EXPECT_NEAR(en.stored, work, 1e-14 * std::abs(work));
  EXPECT_GT(en.dissipated, 0.0);
  try {
    mat.integrate2(s0.data(), s1.data(), z.data(), e.data(), sig.data(), nullptr,
                   PNC_MATERIAL_TANGENT_CONSISTENT);
    ADD_FAILURE() << "no exception";
  } catch (const pnc::fe_material::Error& err) {
    EXPECT_EQ(err.status(), PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_NE(std::string(err.what()).find("tangent"), std::string::npos) << err.what();
  }
}

// ------------------------------------------------------------------ ABI compatibility
// ABI 1.3: D_K(kappa) as the host asks for it is the damage integrate2 writes into the state
// (a zero-strain increment from a state whose kappaK is kappa: the full kernel path), the
// closed form of the law (docs/theory.md: D = 1 + k (2 x^-13 - x^-7), x = kappa / alpha, past
// the onset alpha lambda_c, k = 1 / |2 lc^-13 - lc^-7|), and its slope the derivative of that
// curve (central differences).
TEST(FeMaterialV2, DamageOfStretchIsTheLawIntegrate2Applies) {
  const double lc = lambda_c(), kk = 1.0 / std::fabs(2 * std::pow(lc, -13) - std::pow(lc, -7));
  for (const Case& c : kCases) {
    const NdmParameters p = params(c.model, c.rotated);
    auto m = make(p);
    const int modes = static_cast<int>(prop(m.get(), "n_damage_modes"));
    const double onset = prop(m.get(), "damage_onset_stretch");
    for (int mode = 0; mode < modes; ++mode) {
      const std::string K = std::to_string(mode + 1);
      const int ik = pnc_material_state_index(m.get(), ("kappa" + K).c_str());
      const int id = pnc_material_state_index(m.get(), ("D" + K).c_str());
      ASSERT_GE(ik, 0);
      ASSERT_GE(id, 0);
      for (double f : {0.5, 1.0, 1.0 + 1e-9, 1.01, 1.1, 1.5, 3.0, 10.0}) {
        const double kappa = f * onset;
        const std::string at = name_of(c) + " mode " + K + " kappa " + std::to_string(kappa);
        double D = -1, slope = -1;
        ASSERT_EQ(pnc_material_damage_of_stretch(m.get(), mode, kappa, &D, &slope), PNC_MATERIAL_OK)
            << at;
        std::vector<double> s0 = virgin(m.get());
        s0[static_cast<std::size_t>(ik)] = kappa;
        const Out o =
            call(m.get(), s0.data(), Vec6::Zero(), Vec6::Zero(), PNC_MATERIAL_TANGENT_NONE);
        ASSERT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
        EXPECT_EQ(D, o.state1[static_cast<std::size_t>(id)]) << at; // one routine: equal
        const double x = kappa / p.alpha();
        const double closed = x > lc ? 1 + kk * (2 * std::pow(x, -13) - std::pow(x, -7)) : 0.0;
        EXPECT_NEAR(D, closed, 1e-14) << at;
        if (f <= 1.0) {
          EXPECT_EQ(D, 0.0) << at;
          EXPECT_EQ(slope, 0.0) << at;
        } else if (f > 1.0 + 1e-6) { // central differences away from the kink at the onset
          const double h = 1e-6 * kappa;
          double Dp = 0, Dm = 0;
          ASSERT_EQ(pnc_material_damage_of_stretch(m.get(), mode, kappa + h, &Dp, nullptr), 0);
          ASSERT_EQ(pnc_material_damage_of_stretch(m.get(), mode, kappa - h, &Dm, nullptr), 0);
          // truncation ~h^2 |d3D/dkappa3| / 6 and rounding ~1e-16 / h: both far below 1e-7
          EXPECT_NEAR(slope, (Dp - Dm) / (2 * h), 1e-7 * (1 + std::fabs(slope))) << at;
        }
      }
    }
    // refused arguments write nothing
    double D = 7, slope = 7;
    for (int mode : {-1, modes})
      EXPECT_EQ(pnc_material_damage_of_stretch(m.get(), mode, onset, &D, &slope),
                PNC_MATERIAL_BAD_ARGUMENT);
    for (double kappa : {std::nan(""), -1.0, std::numeric_limits<double>::infinity()})
      EXPECT_EQ(pnc_material_damage_of_stretch(m.get(), 0, kappa, &D, &slope),
                PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(pnc_material_damage_of_stretch(m.get(), 0, onset, nullptr, &slope),
              PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(pnc_material_damage_of_stretch(nullptr, 0, onset, &D, &slope),
              PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(D, 7.0);
    EXPECT_EQ(slope, 7.0);
  }
}

// ABI 1.3: the mode stretches of a strain are the kappa integrate2 writes from a state with
// kappa = 0 (bit for bit: the next test), and their gradient is the derivative of that map
// (central differences of the query).
TEST(FeMaterialV2, ModeStretchIsTheStretchIntegrate2ComparesAndItsGradient) {
  for (const Case& c : kCases) {
    auto m = make(params(c.model, c.rotated));
    const int modes = static_cast<int>(prop(m.get(), "n_damage_modes"));
    for (const Vec6& e : strains()) {
      double lambda[3] = {-1, -1, -1}, grad[18] = {};
      ASSERT_EQ(pnc_material_mode_stretch(m.get(), e.data(), lambda, grad), PNC_MATERIAL_OK);
      std::vector<double> s0 = virgin(m.get());
      for (int k = 0; k < modes; ++k)
        s0[static_cast<std::size_t>(
            pnc_material_state_index(m.get(), ("kappa" + std::to_string(k + 1)).c_str()))] = 0.0;
      const Out o = call(m.get(), s0.data(), Vec6::Zero(), e, PNC_MATERIAL_TANGENT_NONE);
      ASSERT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
      for (int k = 0; k < modes; ++k) {
        const std::string at = name_of(c) + " mode " + std::to_string(k + 1);
        const int ik = pnc_material_state_index(m.get(), ("kappa" + std::to_string(k + 1)).c_str());
        // rounding of T eps (a sum of six products) and of the stretch: a few 1e-16
        EXPECT_NEAR(lambda[k], o.state1[static_cast<std::size_t>(ik)], 1e-14) << at;
        for (int j = 0; j < 6; ++j) {
          const double h = 1e-6;
          Vec6 ep = e, em = e;
          ep[j] += h;
          em[j] -= h;
          double lp[3], lm[3];
          ASSERT_EQ(pnc_material_mode_stretch(m.get(), ep.data(), lp, nullptr), 0);
          ASSERT_EQ(pnc_material_mode_stretch(m.get(), em.data(), lm, nullptr), 0);
          // truncation ~h^2 |d3 lambda| / 6 and rounding ~1e-16 / h: both below 1e-8 for
          // strains away from a switch of the stretch's branch (strains() are)
          EXPECT_NEAR(grad[6 * k + j], (lp[k] - lm[k]) / (2 * h), 1e-7) << at << " j " << j;
        }
      }
    }
    // refusals write nothing
    double lambda[3] = {7, 7, 7};
    Vec6 bad = Vec6::Zero();
    bad[2] = std::nan("");
    EXPECT_EQ(pnc_material_mode_stretch(m.get(), bad.data(), lambda, nullptr),
              PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(pnc_material_mode_stretch(nullptr, Vec6::Zero().eval().data(), lambda, nullptr),
              PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(pnc_material_mode_stretch(m.get(), nullptr, lambda, nullptr),
              PNC_MATERIAL_BAD_ARGUMENT);
    EXPECT_EQ(lambda[0], 7.0);
  }
}

// D351: the query and the integration form the platelet-frame strain and the stretches by
// the same routines, so from kappa = 0 the kappa that integrate2 writes (max(lambda, 0) =
// lambda) is the queried lambda exactly, for plane strains (the kernel's plane columns) and
// general ones, aligned, rotated about x3 (block-diagonal local strain) and rotated in 3-D.
TEST(FeMaterialV2, ModeStretchQueryAndIntegrationAgreeBitForBit) {
  std::mt19937_64 g(351);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  const Eigen::Matrix3d frames[] = {Eigen::Matrix3d::Identity(), rotation_zx(25.0, 0.0),
                                    rotation_zx(30.0, 20.0)};
  for (Model model : {Model::pnc, Model::pp})
    for (const Eigen::Matrix3d& R : frames) {
      NdmParameters p = params(model, false);
      p.R = R;
      auto m = make(p);
      const int modes = static_cast<int>(prop(m.get(), "n_damage_modes"));
      std::vector<double> s0 = virgin(m.get());
      for (int k = 0; k < modes; ++k)
        s0[static_cast<std::size_t>(k)] = 0.0; // kappa1..n come first (state_names)
      for (int i = 0; i < 200; ++i) {
        Vec6 e;
        for (int j = 0; j < 6; ++j)
          e[j] = u(g);
        if (i % 2 == 0) e[2] = e[3] = e[4] = 0.0; // plane strain in x1-x2
        double lambda[3] = {-1, -1, -1};
        ASSERT_EQ(pnc_material_mode_stretch(m.get(), e.data(), lambda, nullptr), PNC_MATERIAL_OK);
        const Out o = call(m.get(), s0.data(), Vec6::Zero(), e, PNC_MATERIAL_TANGENT_NONE);
        ASSERT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
        for (int k = 0; k < modes; ++k)
          ASSERT_EQ(lambda[k], o.state1[static_cast<std::size_t>(k)])
              << pnc::damage::model_name(model) << " point " << i << " mode " << k + 1;
      }
    }
}

TEST(FeMaterialAbi, NewSymbolsCarryTheMinorVersionAndV1SymbolsKeepTheirs) {
  void* h = dlopen(PNC_MATERIAL_PLUGIN_PATH, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(h, nullptr) << dlerror();
  const std::string v1 = "PNC_MATERIAL_" + std::to_string(PNC_MATERIAL_ABI_VERSION);
  const std::string v11 = v1 + ".1";
  for (const char* s : {"pnc_material_integrate", "pnc_material_create", "pnc_material_umat_props",
                        "umat_", "pnc_umat_"})
    EXPECT_NE(dlvsym(h, s, v1.c_str()), nullptr) << s << "@" << v1;
  for (const char* s :
       {"pnc_material_integrate2", "pnc_material_property", "pnc_material_state_index",
        "pnc_material_abi_version_minor", "pnc_material_model_constant_name"}) {
    EXPECT_NE(dlvsym(h, s, v11.c_str()), nullptr) << s << "@" << v11;
    EXPECT_EQ(dlvsym(h, s, v1.c_str()), nullptr) << s << " must not be in " << v1;
  }
  const std::string v13 = v1 + ".3";
  EXPECT_NE(dlvsym(h, "pnc_material_damage_of_stretch", v13.c_str()), nullptr) << v13;
  EXPECT_EQ(dlvsym(h, "pnc_material_damage_of_stretch", v11.c_str()), nullptr) << v11;
  EXPECT_NE(dlvsym(h, "pnc_material_mode_stretch", v13.c_str()), nullptr) << v13;
  dlclose(h);
}

// Runs the C program built against the frozen ABI 1.0 header (abi_v1/pnc_material_v1.h) and
// linked to this library; it prints the stress and state after a loading-unloading-reloading
// path. The same path through integrate2 must give the same numbers: one kernel routine
// behind both entries (D210), so the floating-point sequence is the same and they are equal.
TEST(FeMaterialAbi, AHostBuiltAgainstTheV1HeaderRunsWithTheSameResults) {
  const std::filesystem::path out_dir = pnc::test::fresh_dir("abi_v1");
  const std::string out_name = (out_dir / "host_out.txt").string();
  const int fd = ::open(out_name.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600); // created exclusively
  const char* const out_path = out_name.c_str();
  ASSERT_GE(fd, 0);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, fd, STDOUT_FILENO);
  const std::string exe = PNC_ABI_V1_HOST;
  for (const char* model : {"pnc", "pp"}) {
    const Model md = std::string(model) == "pnc" ? Model::pnc : Model::pp;
    const NdmParameters p = params(md, false);
    std::vector<std::string> args{exe, model};
    for (std::size_t i = 0; i < p.size(); ++i) {
      char b[40];
      std::snprintf(b, sizeof b, "%.17g", p.k[i]); // round-trips exactly
      args.emplace_back(b);
    }
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    ASSERT_EQ(ftruncate(fd, 0), 0);
    ASSERT_EQ(lseek(fd, 0, SEEK_SET), 0);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ), 0) << exe;
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << exe << " " << model;
    std::ifstream in(out_path);
    std::string word;
    int abi = 0, n = 0;
    in >> word >> abi >> word >> n;
    ASSERT_EQ(abi, PNC_MATERIAL_ABI_VERSION);
    std::vector<double> stress(6), state(static_cast<std::size_t>(n));
    in >> word;
    for (auto& v : stress)
      in >> v;
    in >> word;
    for (auto& v : state)
      in >> v;
    ASSERT_TRUE(in) << "unreadable output of " << exe;
    // The same path, through integrate2.
    auto m = make(p);
    std::vector<double> s0 = virgin(m.get());
    Vec6 e0 = Vec6::Zero();
    const double targets[3] = {0.25, 0.1, 0.25};
    const int steps[3] = {15, 10, 10};
    Out o;
    for (int seg = 0; seg < 3; ++seg) {
      const double step = (targets[seg] - e0[1]) / steps[seg];
      for (int s = 0; s < steps[seg]; ++s) {
        Vec6 de = Vec6::Zero();
        de[1] = step;
        o = call(m.get(), s0.data(), e0, de, PNC_MATERIAL_TANGENT_CONSISTENT);
        ASSERT_EQ(o.status, PNC_MATERIAL_OK) << o.err;
        e0[1] += step;
        for (std::size_t i = 0; i < s0.size(); ++i)
          s0[i] = o.state1[i];
      }
    }
    // pnc: e22 drives the damage of mode 2; pp: its one damage variable (alias "D1")
    const int d_at = pnc_material_state_index(m.get(), std::string(model) == "pnc" ? "D2" : "D1");
    ASSERT_GE(d_at, 0) << model;
    EXPECT_GT(s0[static_cast<std::size_t>(d_at)], 0.0)
        << model << ": the path must damage (mode 2 / the maximum stretch)";
    for (int i = 0; i < 6; ++i)
      EXPECT_EQ(stress[static_cast<std::size_t>(i)], o.stress[static_cast<std::size_t>(i)])
          << model << " stress " << i;
    for (int i = 0; i < n; ++i)
      EXPECT_EQ(state[static_cast<std::size_t>(i)], s0[static_cast<std::size_t>(i)])
          << model << " state " << i;
  }
  posix_spawn_file_actions_destroy(&fa);
  close(fd);
  std::remove(out_path);
  std::filesystem::remove(out_dir);
}

} // namespace
