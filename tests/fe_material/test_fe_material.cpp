// Tests of the pnc material plugin: the C ABI, umat_ and the dlopen() route must reproduce
// pnc::damage::integrate() along damaging strain paths; bad input must be named clearly.
#include "pnc/fe_material/material.hpp"
#include "pnc/fe_material/pnc_material.h"
#include "pnc/fe_material/umat.h"

#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/ndm.hpp"
#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

extern "C" int run_c_path(const char* card, double* out_stress, double* out_state,
                          int* out_n_state);

namespace fs = std::filesystem;
using pnc::damage::Matrix6;
using pnc::damage::Model;
using pnc::damage::NdmParameters;
using pnc::damage::NdmState;
using pnc::damage::Voigt;
using pnc::fe_material::Material;
using pnc::fe_material::Plugin;

namespace {

constexpr double kRelTol = 1e-12;

// ------------------------------------------------------------------ fixtures and helpers
fs::path temp_dir();

// Removes this process's temporary cards at the end of the run.
class TempDirCleanup : public ::testing::Environment {
public:
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(temp_dir(), ec);
  }
};
const ::testing::Environment* const kCleanup =
    ::testing::AddGlobalTestEnvironment(new TempDirCleanup);

fs::path temp_dir() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("pnc_fe_material_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

Eigen::Matrix3d rotation_zx(double deg_z, double deg_x) {
  const double pi = std::acos(-1.0);
  const double a = deg_z * pi / 180, b = deg_x * pi / 180;
  Eigen::Matrix3d Rz, Rx;
  Rz << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  Rx << 1, 0, 0, 0, std::cos(b), -std::sin(b), 0, std::sin(b), std::cos(b);
  return Rz * Rx;
}

NdmParameters params(Model m, bool rotated) {
  NdmParameters p = pnc::damage::dissertation_parameters(m);
  if (rotated) p.R = rotation_zx(30.0, 20.0);
  return p;
}

std::string card_path(Model m, bool rotated) {
  const fs::path path = temp_dir() / (std::string("card_") + pnc::damage::model_name(m) +
                                      (rotated ? "_rot" : "") + ".h5");
  if (!fs::exists(path))
    pnc::damage::write_card(path.string(),
                            pnc::damage::card_from_parameters(params(m, rotated), "test"),
                            "test_fe_material");
  return path.string();
}

// Strain path (global frame, engineering Voigt 11,22,33,23,13,12): load along `dir` to a
// peak principal strain `peak`, unload to a third of it, reload to 1.2 x peak.
std::vector<Voigt> strain_path(const Voigt& dir, double peak) {
  Eigen::Matrix3d e;
  e << dir[0], dir[5] / 2, dir[4] / 2, dir[5] / 2, dir[1], dir[3] / 2, dir[4] / 2, dir[3] / 2,
      dir[2];
  const double emax = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(e).eigenvalues().maxCoeff();
  const Voigt d = dir * (peak / emax);
  std::vector<Voigt> path;
  const std::array<double, 3> target = {1.0, 1.0 / 3.0, 1.2};
  const std::array<int, 3> steps = {12, 6, 8};
  double t = 0;
  for (int s = 0; s < 3; ++s)
    for (int k = 1; k <= steps[s]; ++k) {
      const double tk = t + (target[s] - t) * k / steps[s];
      path.push_back(d * tk);
      if (k == steps[s]) t = tk;
    }
  return path;
}

std::vector<Voigt> directions() {
  std::vector<Voigt> out;
  Voigt d;
  d << 1, 0, 0, 0, 0, 0; // extension along x1
  out.push_back(d);
  d << -0.3, 1, -0.2, 0, 0, 0; // extension along x2 with lateral contraction
  out.push_back(d);
  d << 0.1, 0.2, 1, 0, 0, 0.3; // mostly x3
  out.push_back(d);
  d << 0, 0, 0, 0, 0, 1; // simple shear 1-2
  out.push_back(d);
  d << 0.2, -0.1, 0.05, 0.6, -0.4, 0.3; // general
  out.push_back(d);
  return out;
}

double peak_for(Model m) {
  return m == Model::pnc ? 0.15 : 0.25;
}

// Per-step result of one route.
struct Step {
  Voigt stress;
  Matrix6 K; // d sigma / d eps, kernel order
  std::vector<double> state;
};

void expect_close(const Step& got, const Step& ref, const std::string& what) {
  const double ss = std::max(1.0, ref.stress.cwiseAbs().maxCoeff());
  const double sk = std::max(1.0, ref.K.cwiseAbs().maxCoeff());
  for (int i = 0; i < 6; ++i) {
    EXPECT_LE(std::abs(got.stress[i] - ref.stress[i]), kRelTol * ss)
        << what << " stress[" << i << "] " << got.stress[i] << " vs " << ref.stress[i];
    for (int j = 0; j < 6; ++j)
      EXPECT_LE(std::abs(got.K(i, j) - ref.K(i, j)), kRelTol * sk)
          << what << " K(" << i << "," << j << ") " << got.K(i, j) << " vs " << ref.K(i, j);
  }
  ASSERT_EQ(got.state.size(), ref.state.size()) << what;
  for (std::size_t i = 0; i < ref.state.size(); ++i)
    EXPECT_LE(std::abs(got.state[i] - ref.state[i]),
              kRelTol * std::max(1.0, std::abs(ref.state[i])))
        << what << " state[" << i << "]";
}

// The reference: pnc::damage::integrate() directly.
std::vector<Step> run_kernel(const NdmParameters& p, const std::vector<Voigt>& path) {
  std::vector<Step> out;
  NdmState s0, s1;
  Voigt prev = Voigt::Zero();
  pnc::damage::ErrorBuffer err;
  for (const Voigt& e : path) {
    Step st;
    EXPECT_EQ(pnc::damage::integrate(p, s0, s1, prev, e - prev, st.stress, &st.K, err),
              pnc::damage::Status::ok)
        << err.msg;
    st.state.resize(pnc::damage::state_size(p.model));
    pnc::damage::state_to_array(p.model, s1, st.state.data());
    out.push_back(st);
    s0 = s1;
    prev = e;
  }
  return out;
}

// The C ABI (or any route to it through a function table).
std::vector<Step> run_c(const pnc_material* m, pnc_material_integrate_fn integrate,
                        const std::vector<Voigt>& path) {
  std::vector<Step> out;
  std::vector<double> s0(static_cast<std::size_t>(pnc_material_n_state(m)));
  pnc_material_init_state(m, s0.data());
  Voigt prev = Voigt::Zero();
  for (const Voigt& e : path) {
    Step st;
    st.state.resize(s0.size());
    const Voigt de = e - prev;
    std::array<double, 36> K{};
    char err[256];
    EXPECT_EQ(integrate(m, s0.data(), st.state.data(), prev.data(), de.data(), st.stress.data(),
                        K.data(), err, sizeof err),
              PNC_MATERIAL_OK)
        << err;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        st.K(i, j) = K[static_cast<std::size_t>(6 * i + j)]; // row-major
    out.push_back(st);
    s0 = st.state;
    prev = e;
  }
  return out;
}

// The C++ wrapper (linked or plugin).
std::vector<Step> run_wrapper(const Material& mat, const std::vector<Voigt>& path) {
  std::vector<Step> out;
  std::vector<double> s0 = mat.initial_state();
  pnc::fe_material::Voigt6 prev{};
  for (const Voigt& e : path) {
    Step st;
    pnc::fe_material::Voigt6 eps{}, deps{}, sig{};
    pnc::fe_material::Tangent36 K{};
    for (std::size_t i = 0; i < 6; ++i) {
      eps[i] = e[static_cast<Eigen::Index>(i)];
      deps[i] = eps[i] - prev[i];
    }
    mat.integrate(s0, st.state, prev, deps, sig, &K);
    for (int i = 0; i < 6; ++i) {
      st.stress[i] = sig[static_cast<std::size_t>(i)];
      for (int j = 0; j < 6; ++j)
        st.K(i, j) = K[static_cast<std::size_t>(6 * i + j)];
    }
    out.push_back(st);
    s0 = st.state;
    prev = eps;
  }
  return out;
}

// ---- umat_ helpers: Abaqus order 11,22,33,12,13,23 written out by component name.
enum Kernel { k11 = 0, k22 = 1, k33 = 2, k23 = 3, k13 = 4, k12 = 5 };
constexpr std::array<int, 6> kAbaqus6 = {k11, k22, k33, k12, k13, k23};
constexpr std::array<int, 4> kAbaqus4 = {k11, k22, k33, k12};

std::vector<double> umat_props(const NdmParameters& p, bool with_rotation) {
  std::vector<double> props = {p.model == Model::pnc ? 1.0 : 2.0};
  for (std::size_t i = 0; i < p.size(); ++i)
    props.push_back(p.k[i]);
  if (with_rotation)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        props.push_back(p.R(r, c));
  return props;
}

struct UmatCall {
  int ndi = 3, nshr = 3, ntens = 6, nstatv = 0, nprops = 0, noel = 7, npt = 2;
  int layer = 1, kspt = 1, kstep = 1, kinc = 1;
  double sse = 0, spd = 0, scd = 0, rpl = 0, drpldt = 0, pnewdt = 1e36;
  std::array<double, 6> ddsddt{}, drplde{}, coords{}, time{}, predef{}, dpred{};
  std::array<double, 9> drot{1, 0, 0, 0, 1, 0, 0, 0, 1}, dfgrd0{}, dfgrd1{};
  double dtime = 1, temp = 293, dtemp = 0, celent = 1;
  char cmname[80];
  UmatCall() {
    std::fill(std::begin(cmname), std::end(cmname), ' ');
    std::copy_n("PNC-CARD", 8, cmname);
  }
  void operator()(double* stress, double* statev, double* ddsdde, const double* stran,
                  const double* dstran, const double* props) {
    umat_(stress, statev, ddsdde, &sse, &spd, &scd, &rpl, ddsddt.data(), drplde.data(), &drpldt,
          stran, dstran, time.data(), &dtime, &temp, &dtemp, predef.data(), dpred.data(), cmname,
          &ndi, &nshr, &ntens, &nstatv, props, &nprops, coords.data(), drot.data(), &pnewdt,
          &celent, dfgrd0.data(), dfgrd1.data(), &noel, &npt, &layer, &kspt, &kstep, &kinc,
          sizeof cmname);
  }
};

std::vector<Step> run_umat(const NdmParameters& p, bool with_rotation,
                           const std::vector<Voigt>& path) {
  std::vector<Step> out;
  const std::vector<double> props = umat_props(p, with_rotation);
  UmatCall call;
  call.nprops = static_cast<int>(props.size());
  call.nstatv = static_cast<int>(pnc::damage::state_size(p.model));
  std::vector<double> statev(static_cast<std::size_t>(call.nstatv), 0.0); // Abaqus: zeros
  std::array<double, 6> stran{}, dstran{}, stress{};
  std::array<double, 36> ddsdde{};
  for (const Voigt& e : path) {
    Step st;
    for (int a = 0; a < 6; ++a) {
      const std::size_t au = static_cast<std::size_t>(a);
      dstran[au] = e[kAbaqus6[au]] - stran[au];
    }
    call(stress.data(), statev.data(), ddsdde.data(), stran.data(), dstran.data(), props.data());
    EXPECT_EQ(call.pnewdt, 1e36) << "umat_ rejected the input";
    for (int a = 0; a < 6; ++a) {
      const std::size_t au = static_cast<std::size_t>(a);
      st.stress[kAbaqus6[au]] = stress[au];
      for (int b = 0; b < 6; ++b) // DDSDDE(a,b) column-major
        st.K(kAbaqus6[au], kAbaqus6[static_cast<std::size_t>(b)]) =
            ddsdde[au + 6 * static_cast<std::size_t>(b)];
      stran[au] += dstran[au];
    }
    st.state = statev;
    out.push_back(st);
  }
  return out;
}

std::string plugin_path() {
  return PNC_MATERIAL_PLUGIN_PATH;
}

bool path_damages(const std::vector<Step>& ref, Model m) {
  const std::size_t nk = m == Model::pnc ? 3 : 1;
  for (const auto& s : ref)
    for (std::size_t k = 0; k < nk; ++k)
      if (s.state[nk + k] != 0.0) return true;
  return false;
}

std::string c_error(const std::string& card) {
  char err[1024] = "untouched";
  pnc_material* m = pnc_material_create(card.c_str(), err, sizeof err);
  EXPECT_EQ(m, nullptr);
  pnc_material_destroy(m);
  return err;
}

// ------------------------------------------------------------------ equivalence tests
struct Route {
  Model model;
  bool rotated;
};
void PrintTo(const Route& r, std::ostream* os) {
  *os << pnc::damage::model_name(r.model) << (r.rotated ? ", rotated platelet" : ", aligned");
}

class FeMaterialEquivalence : public ::testing::TestWithParam<Route> {};

TEST_P(FeMaterialEquivalence, AllRoutesMatchTheKernel) {
  const Route r = GetParam();
  const NdmParameters p = params(r.model, r.rotated);
  const std::string card = card_path(r.model, r.rotated);

  char err[512] = {0};
  pnc_material* cm = pnc_material_create(card.c_str(), err, sizeof err);
  ASSERT_NE(cm, nullptr) << err;
  std::vector<double> k(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    k[i] = p.k[i];
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R_rows = p.R;
  pnc_material* cc = pnc_material_create_from_constants(
      pnc::damage::model_name(r.model), k.data(), static_cast<int>(k.size()), R_rows.data(), err,
      sizeof err); // row-major R
  ASSERT_NE(cc, nullptr) << err;
  const Material linked = Material::from_card(card);
  const Plugin plugin(plugin_path());
  const Material loaded = plugin.from_card(card);

  for (const Voigt& dir : directions()) {
    const auto path = strain_path(dir, peak_for(r.model));
    const auto ref = run_kernel(p, path);
    EXPECT_TRUE(path_damages(ref, r.model)) << "path does not reach damage: " << dir.transpose();
    std::ostringstream tag;
    tag << pnc::damage::model_name(r.model) << (r.rotated ? " rotated" : "") << " dir "
        << dir.transpose() << " step ";
    const auto c_card = run_c(cm, &pnc_material_integrate, path);
    const auto c_const = run_c(cc, &pnc_material_integrate, path);
    const auto umat = run_umat(p, r.rotated, path);
    const auto wrap = run_wrapper(linked, path);
    const auto plug = run_wrapper(loaded, path);
    const auto plug_c = run_c(loaded.get(), plugin.api().integrate, path);
    ASSERT_EQ(c_card.size(), ref.size());
    for (std::size_t i = 0; i < ref.size(); ++i) {
      const std::string t = tag.str() + std::to_string(i);
      expect_close(c_card[i], ref[i], "C ABI (card): " + t);
      expect_close(c_const[i], ref[i], "C ABI (constants): " + t);
      expect_close(umat[i], ref[i], "umat_: " + t);
      expect_close(wrap[i], ref[i], "Material (linked): " + t);
      expect_close(plug[i], ref[i], "Plugin (dlopen): " + t);
      expect_close(plug_c[i], ref[i], "Plugin C table: " + t);
    }
  }
  pnc_material_destroy(cm);
  pnc_material_destroy(cc);
}

INSTANTIATE_TEST_SUITE_P(FeMaterial, FeMaterialEquivalence,
                         ::testing::Values(Route{Model::pnc, false}, Route{Model::pnc, true},
                                           Route{Model::pp, false}, Route{Model::pp, true}),
                         [](const ::testing::TestParamInfo<Route>& param_info) {
                           return std::string(pnc::damage::model_name(param_info.param.model)) +
                                  (param_info.param.rotated ? "_rotated" : "_aligned");
                         });

TEST(FeMaterialCApi, ReportsWhatItLoaded) {
  const std::string card = card_path(Model::pnc, true);
  EXPECT_EQ(pnc_material_abi_version(), PNC_MATERIAL_ABI_VERSION);
  char err[256];
  pnc_material* m = pnc_material_create(card.c_str(), err, sizeof err);
  ASSERT_NE(m, nullptr) << err;
  EXPECT_STREQ(pnc_material_model(m), "pnc");
  ASSERT_EQ(pnc_material_n_constants(m), 22);
  const NdmParameters p = params(Model::pnc, true);
  const auto& names = pnc::damage::constant_names(Model::pnc);
  for (int i = 0; i < 22; ++i) {
    EXPECT_EQ(pnc_material_constant_name(m, i), names[static_cast<std::size_t>(i)]);
    EXPECT_EQ(pnc_material_constant(m, i), p.k[static_cast<std::size_t>(i)]);
  }
  EXPECT_EQ(pnc_material_constant_name(m, 22), nullptr);
  EXPECT_TRUE(std::isnan(pnc_material_constant(m, -1)));
  double R[9];
  pnc_material_rotation(m, R);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(R[3 * r + c], p.R(r, c));
  ASSERT_EQ(pnc_material_n_state(m), 6);
  const char* want[] = {"kappa1", "kappa2", "kappa3", "D1", "D2", "D3"};
  for (int i = 0; i < 6; ++i)
    EXPECT_STREQ(pnc_material_state_name(m, i), want[i]);
  EXPECT_EQ(pnc_material_state_name(m, 6), nullptr);
  double s[6];
  pnc_material_init_state(m, s);
  EXPECT_EQ(std::vector<double>(s, s + 6), (std::vector<double>{1, 1, 1, 0, 0, 0}));
  pnc_material_destroy(m);
  pnc_material_destroy(nullptr); // allowed
}

TEST(FeMaterialCApi, WorksFromC) {
  const std::string card = card_path(Model::pnc, false);
  double stress[6], state[16];
  int n = 0;
  ASSERT_EQ(run_c_path(card.c_str(), stress, state, &n), PNC_MATERIAL_OK);
  ASSERT_EQ(n, 6);
  // Same path and the same floating-point sequence through the kernel.
  const NdmParameters p = params(Model::pnc, false);
  NdmState s0, s1;
  Voigt eps = Voigt::Zero(), de = Voigt::Zero(), sig;
  pnc::damage::ErrorBuffer err;
  const double targets[3] = {0.15, 0.05, 0.15};
  const int steps[3] = {15, 10, 10};
  for (int seg = 0; seg < 3; ++seg) {
    const double step = (targets[seg] - eps[0]) / steps[seg];
    for (int k = 0; k < steps[seg]; ++k) {
      de[0] = step;
      ASSERT_EQ(pnc::damage::integrate(p, s0, s1, eps, de, sig, nullptr, err),
                pnc::damage::Status::ok);
      eps[0] += step;
      s0 = s1;
    }
  }
  double ref_state[6];
  pnc::damage::state_to_array(Model::pnc, s0, ref_state);
  EXPECT_GT(ref_state[3], 0.0) << "the C path must reach damage";
  for (int i = 0; i < 6; ++i) {
    EXPECT_LE(std::abs(stress[i] - sig[i]), kRelTol * sig.cwiseAbs().maxCoeff()) << i;
    EXPECT_LE(std::abs(state[i] - ref_state[i]), kRelTol) << i;
  }
}

TEST(FeMaterialCApi, SharedAcrossThreads) {
  const std::string card = card_path(Model::pnc, true);
  const Material mat = Material::from_card(card);
  const auto dirs = directions();
  std::vector<std::vector<Step>> serial, parallel(dirs.size());
  for (const auto& d : dirs)
    serial.push_back(run_wrapper(mat, strain_path(d, 0.15)));
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < dirs.size(); ++i)
    threads.emplace_back([&, i] { parallel[i] = run_wrapper(mat, strain_path(dirs[i], 0.15)); });
  for (auto& t : threads)
    t.join();
  for (std::size_t i = 0; i < dirs.size(); ++i)
    for (std::size_t k = 0; k < serial[i].size(); ++k)
      expect_close(parallel[i][k], serial[i][k], "thread " + std::to_string(i));
}

TEST(FeMaterialCApi, IntegrateRejectsNonFiniteStrainAndLeavesOutputs) {
  char err[512] = {0};
  pnc_material* m = pnc_material_create(card_path(Model::pp, false).c_str(), err, sizeof err);
  ASSERT_NE(m, nullptr) << err;
  double s0[2] = {1, 0}, s1[2] = {-7, -7}, stress[6] = {-7, -7, -7, -7, -7, -7};
  const double e0[6] = {0, 0, 0, 0, 0, 0};
  const double de[6] = {0.01, std::numeric_limits<double>::quiet_NaN(), 0, 0, 0, 0};
  EXPECT_EQ(pnc_material_integrate(m, s0, s1, e0, de, stress, nullptr, err, sizeof err),
            PNC_MATERIAL_BAD_INPUT);
  EXPECT_NE(std::string(err).find("strain0 + dstrain"), std::string::npos) << err;
  EXPECT_NE(std::string(err).find("nan"), std::string::npos) << err;
  EXPECT_NE(std::string(err).find("not finite"), std::string::npos) << err;
  EXPECT_EQ(s1[0], -7);
  EXPECT_EQ(stress[0], -7);
  EXPECT_EQ(pnc_material_integrate(nullptr, s0, s1, e0, de, stress, nullptr, err, sizeof err),
            PNC_MATERIAL_BAD_ARGUMENT);
  // A tiny buffer is truncated, never overrun; a null buffer is allowed.
  char tiny[8];
  EXPECT_EQ(pnc_material_integrate(m, s0, s1, e0, de, stress, nullptr, tiny, sizeof tiny),
            PNC_MATERIAL_BAD_INPUT);
  EXPECT_EQ(std::string(tiny), "pnc_mat");
  EXPECT_EQ(pnc_material_integrate(m, s0, s1, e0, de, stress, nullptr, nullptr, 0),
            PNC_MATERIAL_BAD_INPUT);
  pnc_material_destroy(m);
}

// ------------------------------------------------------------------ card errors
TEST(FeMaterialErrors, MissingCardFile) {
  const std::string path = (temp_dir() / "no_such_card.h5").string();
  const std::string msg = c_error(path);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("field 'card_path'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("No such file or directory"), std::string::npos) << msg;
  try {
    (void)Material::from_card(path);
    ADD_FAILURE() << "no exception";
  } catch (const pnc::fe_material::Error& e) {
    EXPECT_EQ(std::string(e.what()), msg);
  }
  const std::string not_hdf5 = (temp_dir() / "not_a_card.h5").string();
  std::ofstream(not_hdf5) << "C11 = 1e9\n";
  const std::string msg2 = c_error(not_hdf5);
  EXPECT_NE(msg2.find(not_hdf5), std::string::npos) << msg2;
  EXPECT_NE(msg2.find("not an HDF5 file"), std::string::npos) << msg2;
  char err[256];
  EXPECT_EQ(pnc_material_create(nullptr, err, sizeof err), nullptr);
  EXPECT_NE(std::string(err).find("card_path"), std::string::npos) << err;
}

// Copies a card through pnc::h5::File, leaving out one dataset (or changing one constant).
void copy_card(const std::string& from, const std::string& to, const std::string& skip,
               const std::string& change = "", double value = 0) {
  pnc::h5::File in(from, pnc::h5::File::Mode::read);
  pnc::h5::File out(to, pnc::h5::File::Mode::truncate);
  out.write_string("/model/law", in.read_string("/model/law"));
  out.set_attr("/model", "variant", *in.attr_string("/model", "variant"));
  out.set_attr("/model", "card_version", *in.attr_double("/model", "card_version"));
  for (const std::string& name : in.children("/constants")) {
    const std::string ds = "/constants/" + name;
    if (ds == skip) continue;
    out.write_scalar(ds, ds == change ? value : in.read_scalar(ds));
    out.set_attr(ds, "units", *in.attr_string(ds, "units"));
  }
  out.write_matrix("/platelet_rotation", in.read_matrix("/platelet_rotation"));
}

TEST(FeMaterialErrors, CardWithAMissingConstant) {
  const std::string broken = (temp_dir() / "card_without_A5.h5").string();
  copy_card(card_path(Model::pnc, false), broken, "/constants/A5");
  const std::string msg = c_error(broken);
  EXPECT_NE(msg.find(broken), std::string::npos) << msg;
  EXPECT_NE(msg.find("/constants/A5"), std::string::npos) << msg;
  EXPECT_NE(msg.find("required dataset is missing"), std::string::npos) << msg;
  // The same through the plugin route.
  try {
    (void)Plugin(plugin_path()).from_card(broken);
    ADD_FAILURE() << "no exception";
  } catch (const pnc::fe_material::Error& e) {
    EXPECT_EQ(std::string(e.what()), msg);
  }
}

TEST(FeMaterialErrors, CardWhoseC0IsNotPositiveDefinite) {
  // write_card validates, so the bad card is written with pnc::h5::File directly.
  const std::string bad = (temp_dir() / "card_c0_indefinite.h5").string();
  copy_card(card_path(Model::pnc, false), bad, "", "/constants/C12", 2.5e9);
  const std::string msg = c_error(bad);
  EXPECT_NE(msg.find(bad), std::string::npos) << msg;
  EXPECT_NE(msg.find("C0 (C11..C33, C12, C13, C23)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("eigenvalues"), std::string::npos) << msg;
  EXPECT_NE(msg.find("positive definite"), std::string::npos) << msg;
}

TEST(FeMaterialErrors, BadConstantsGiveNamedErrors) {
  NdmParameters p = params(Model::pp, false);
  std::vector<double> k(p.k.begin(), p.k.begin() + 7);
  char err[512];
  EXPECT_EQ(pnc_material_create_from_constants("pp", k.data(), 6, nullptr, err, sizeof err),
            nullptr);
  EXPECT_NE(std::string(err).find("field 'n': value '6'"), std::string::npos) << err;
  EXPECT_NE(std::string(err).find("C11 C12 C44 B1 B2 B4 alpha"), std::string::npos) << err;
  EXPECT_EQ(pnc_material_create_from_constants("ppx", k.data(), 7, nullptr, err, sizeof err),
            nullptr);
  EXPECT_NE(std::string(err).find("value 'ppx'"), std::string::npos) << err;
  k[6] = -1.0;
  EXPECT_EQ(pnc_material_create_from_constants("pp", k.data(), 7, nullptr, err, sizeof err),
            nullptr);
  EXPECT_NE(std::string(err).find("pnc_material_create_from_constants: field 'alpha'"),
            std::string::npos)
      << err;
  EXPECT_NE(std::string(err).find("must be > 0"), std::string::npos) << err;
  k[6] = 0.9;
  const double not_a_rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 2};
  EXPECT_EQ(pnc_material_create_from_constants("pp", k.data(), 7, not_a_rotation, err, sizeof err),
            nullptr);
  EXPECT_NE(std::string(err).find("platelet_rotation"), std::string::npos) << err;
  EXPECT_THROW((void)Material::from_constants("pp", {1.0}), pnc::fe_material::Error);
}

// ------------------------------------------------------------------ plugin loading
TEST(FeMaterialPlugin, NamesThePathAndTheMissingSymbol) {
  try {
    Plugin("/nonexistent/libpnc_material.so");
    ADD_FAILURE() << "no exception";
  } catch (const pnc::fe_material::Error& e) {
    EXPECT_NE(std::string(e.what()).find("'/nonexistent/libpnc_material.so'"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot load"), std::string::npos) << e.what();
  }
  try {
    Plugin("libm.so.6"); // a real library, but not a pnc material
    ADD_FAILURE() << "no exception";
  } catch (const pnc::fe_material::Error& e) {
    EXPECT_NE(std::string(e.what()).find("'libm.so.6'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("symbol 'pnc_material_abi_version' is missing"),
              std::string::npos)
        << e.what();
  }
}

TEST(FeMaterialPlugin, ExportsOnlyTheAbi) {
  void* h = dlopen(plugin_path().c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(h, nullptr) << dlerror();
  EXPECT_NE(dlsym(h, "pnc_material_integrate"), nullptr);
  EXPECT_NE(dlsym(h, "umat_"), nullptr);
  // pnc::damage::model_name(Model) and pnc::damage::integrate(...) stay inside the plugin.
  EXPECT_EQ(dlsym(h, "_ZN3pnc6damage10model_nameENS0_5ModelE"), nullptr);
  EXPECT_EQ(dlsym(h, "_ZN3pnc6damage10state_sizeENS0_5ModelE"), nullptr);
  dlclose(h);
}

TEST(FeMaterialPlugin, MaterialKeepsThePluginAliveAndReports) {
  std::unique_ptr<Material> mat;
  {
    Plugin plugin(plugin_path());
    EXPECT_EQ(plugin.abi_version(), PNC_MATERIAL_ABI_VERSION);
    const NdmParameters p = params(Model::pp, false);
    mat = std::make_unique<Material>(
        plugin.from_constants("pp", std::vector<double>(p.k.begin(), p.k.begin() + 7)));
  }
  EXPECT_EQ(mat->model(), "pp");
  EXPECT_EQ(mat->library(), plugin_path());
  EXPECT_EQ(mat->state_names(), (std::vector<std::string>{"kappa", "D"}));
  EXPECT_EQ(mat->constant_names(),
            (std::vector<std::string>{"C11", "C12", "C44", "B1", "B2", "B4", "alpha"}));
  EXPECT_EQ(mat->constant("alpha"), params(Model::pp, false)["alpha"]);
  EXPECT_THROW((void)mat->constant("A5"), pnc::fe_material::Error);
  Material moved = std::move(*mat);
  EXPECT_EQ(mat->get(), nullptr);
  std::vector<double> s0 = moved.initial_state(), s1;
  pnc::fe_material::Voigt6 e0{}, de{0.3, 0, 0, 0, 0, 0}, sig{};
  moved.integrate(s0, s1, e0, de, sig);
  EXPECT_GT(s1[1], 0.0); // damaged
  de[2] = std::numeric_limits<double>::infinity();
  try {
    moved.integrate(s0, s1, e0, de, sig);
    ADD_FAILURE() << "no exception";
  } catch (const pnc::fe_material::Error& e) {
    EXPECT_EQ(e.status(), PNC_MATERIAL_BAD_INPUT);
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
  EXPECT_THROW(moved.integrate(std::vector<double>(3), s1, e0, de, sig), pnc::fe_material::Error);
}

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
