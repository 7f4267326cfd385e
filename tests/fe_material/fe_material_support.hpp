#pragma once
// Shared fixtures and helpers of the plugin tests test_fe_material.cpp and
// test_fe_material_umat.cpp: parameters and cards, strain paths, the kernel, C ABI, C++ wrapper
// and umat_ routes of one path, and the comparison of their steps. Internal to the tests.
#include "common/temp_dir.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/ndm.hpp"
#include "pnc/damage/reference.hpp"
#include "pnc/fe_material/material.hpp"
#include "pnc/fe_material/pnc_material.h"
#include "pnc/fe_material/umat.h"
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
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

namespace fe_material_test {

constexpr double kRelTol = 1e-12;

// ------------------------------------------------------------------ fixtures and helpers
inline fs::path temp_dir();

// Removes this process's temporary cards at the end of the run.
class TempDirCleanup : public ::testing::Environment {
public:
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(temp_dir(), ec);
  }
};
inline const ::testing::Environment* const kCleanup =
    ::testing::AddGlobalTestEnvironment(new TempDirCleanup);

inline fs::path temp_dir() {
  static const fs::path dir = pnc::test::fresh_dir("fe_material");
  return dir;
}

inline Eigen::Matrix3d rotation_zx(double deg_z, double deg_x) {
  const double pi = std::acos(-1.0);
  const double a = deg_z * pi / 180, b = deg_x * pi / 180;
  Eigen::Matrix3d Rz, Rx;
  Rz << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  Rx << 1, 0, 0, 0, std::cos(b), -std::sin(b), 0, std::sin(b), std::cos(b);
  return Rz * Rx;
}

inline NdmParameters params(Model m, bool rotated) {
  NdmParameters p = pnc::damage::dissertation_parameters(m);
  if (rotated) p.R = rotation_zx(30.0, 20.0);
  return p;
}

inline std::string card_path(Model m, bool rotated) {
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
inline std::vector<Voigt> strain_path(const Voigt& dir, double peak) {
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

inline std::vector<Voigt> directions() {
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

inline double peak_for(Model m) {
  return m == Model::pnc ? 0.15 : 0.25;
}

// Per-step result of one route.
struct Step {
  Voigt stress;
  Matrix6 K; // d sigma / d eps, kernel order
  std::vector<double> state;
};

inline void expect_close(const Step& got, const Step& ref, const std::string& what) {
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
inline std::vector<Step> run_kernel(const NdmParameters& p, const std::vector<Voigt>& path) {
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
inline std::vector<Step> run_c(const pnc_material* m, pnc_material_integrate_fn integrate,
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
inline std::vector<Step> run_wrapper(const Material& mat, const std::vector<Voigt>& path) {
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

inline std::vector<double> umat_props(const NdmParameters& p, bool with_rotation) {
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

inline std::vector<Step> run_umat(const NdmParameters& p, bool with_rotation,
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

inline std::string plugin_path() {
  return PNC_MATERIAL_PLUGIN_PATH;
}

inline bool path_damages(const std::vector<Step>& ref, Model m) {
  const std::size_t nk = m == Model::pnc ? 3 : 1;
  for (const auto& s : ref)
    for (std::size_t k = 0; k < nk; ++k)
      if (s.state[nk + k] != 0.0) return true;
  return false;
}

inline std::string c_error(const std::string& card) {
  char err[1024] = "untouched";
  pnc_material* m = pnc_material_create(card.c_str(), err, sizeof err);
  EXPECT_EQ(m, nullptr);
  pnc_material_destroy(m);
  return err;
}

} // namespace fe_material_test
