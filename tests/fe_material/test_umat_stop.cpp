// Tests of the UMAT entry points' configuration-error policy (docs/decisions.md D165), of the
// second name pnc_umat_ (D164) and of the PROPS metadata of the C ABI (D163).
#include "pnc/fe_material/material.hpp"
#include "pnc/fe_material/pnc_material.h"
#include "pnc/fe_material/umat.h"

#include "pnc/damage/reference.hpp"

#include <gtest/gtest.h>

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

using pnc::damage::Model;
using Umat = decltype(&umat_);

// The Abaqus argument list around one entry point (umat_ or pnc_umat_), 3-D (NTENS = 6).
struct Call {
  Umat fn = &umat_;
  int ndi = 3, nshr = 3, ntens = 6, nstatv = 6, nprops = 23, noel = 3, npt = 1, one = 1;
  double sse = 0, spd = 0, scd = 0, rpl = 0, pnewdt = 1.0, dtime = 1, temp = 0, celent = 1;
  std::array<double, 36> scratch{};
  std::array<double, 9> drot{1, 0, 0, 0, 1, 0, 0, 0, 1};
  char cmname[80];
  Call() {
    std::fill(std::begin(cmname), std::end(cmname), ' ');
    std::copy_n("PNC", 3, cmname);
  }
  void operator()(double* stress, double* statev, double* ddsdde, const double* stran,
                  const double* dstran, const double* props) {
    fn(stress, statev, ddsdde, &sse, &spd, &scd, &rpl, scratch.data(), scratch.data(),
       scratch.data(), stran, dstran, scratch.data(), &dtime, &temp, &temp, scratch.data(),
       scratch.data(), cmname, &ndi, &nshr, &ntens, &nstatv, props, &nprops, scratch.data(),
       drot.data(), &pnewdt, &celent, drot.data(), drot.data(), &noel, &npt, &one, &one, &one, &one,
       sizeof cmname);
  }
};

// PROPS of the dissertation's pnc constants written out by the documented layout
// (docs/plugin.md "PROPS"), independently of the plugin's metadata.
std::vector<double> documented_props(const pnc::damage::NdmParameters& p, bool rotation) {
  std::vector<double> props = {p.model == Model::pnc ? 1.0 : 2.0};
  for (std::size_t i = 0; i < p.size(); ++i)
    props.push_back(p.k[i]);
  if (rotation)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        props.push_back(p.R(r, c));
  return props;
}

void refused_configuration_call(const char* mode) {
  if (mode)
    setenv("PNC_UMAT_ON_CONFIG_ERROR", mode, 1);
  else
    unsetenv("PNC_UMAT_ON_CONFIG_ERROR");
  const auto props = documented_props(pnc::damage::dissertation_parameters(Model::pnc), false);
  Call call;
  call.nprops = 20; // wrong: 23 or 32
  std::array<double, 6> stress{}, statev{}, stran{}, dstran{0.01, 0, 0, 0, 0, 0};
  std::array<double, 36> ddsdde{};
  call(stress.data(), statev.data(), ddsdde.data(), stran.data(), dstran.data(), props.data());
}

} // namespace

TEST(FeMaterialUmatStop, ConfigurationErrorStopsByDefaultLikeXit) {
  EXPECT_EXIT(refused_configuration_call(nullptr), ::testing::ExitedWithCode(PNC_UMAT_EXIT_CONFIG),
              "UMAT material 'PNC' \\(element 3, point 1\\): argument 'NPROPS': value '20': .*"
              "configuration error: stopping the analysis \\(exit status 78; "
              "PNC_UMAT_ON_CONFIG_ERROR=cutback requests PNEWDT = 0.5 instead\\)");
  EXPECT_EXIT(refused_configuration_call("stop"), ::testing::ExitedWithCode(78), "stopping");
  // an unknown mode is named and stops (the safe choice)
  EXPECT_EXIT(refused_configuration_call("maybe"), ::testing::ExitedWithCode(78),
              "PNC_UMAT_ON_CONFIG_ERROR='maybe' is neither 'stop' nor 'cutback'");
}

TEST(FeMaterialUmatStop, CutbackModeLowersPnewdtForConfigurationErrors) {
  EXPECT_EXIT(
      {
        refused_configuration_call("cutback");
        std::exit(0); // reached only when the call returned
      },
      ::testing::ExitedWithCode(0), "requesting a smaller increment \\(PNEWDT = 0.5\\)");
}

TEST(FeMaterialUmatStop, BadIncrementNeverStops) {
  unsetenv("PNC_UMAT_ON_CONFIG_ERROR"); // default mode: stop on configuration errors only
  const auto props = documented_props(pnc::damage::dissertation_parameters(Model::pnc), false);
  Call call;
  std::array<double, 6> stress{}, statev{}, stran{}, dstran{0.01, 0, 0, 0, NAN, 0};
  std::array<double, 36> ddsdde{};
  ::testing::internal::CaptureStderr();
  call(stress.data(), statev.data(), ddsdde.data(), stran.data(), dstran.data(), props.data());
  const std::string out = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(call.pnewdt, 0.5) << out;
  EXPECT_NE(out.find("strains must be finite"), std::string::npos) << out;
}

TEST(FeMaterialUmatStop, PncUmatIsTheSameFunctionAsUmat) {
  void* h = dlopen(PNC_MATERIAL_PLUGIN_PATH, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(h, nullptr) << dlerror();
  void* a = dlsym(h, "umat_");
  void* b = dlsym(h, "pnc_umat_");
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(a, b); // an alias, not a copy
  dlclose(h);
  // and through the linked library: identical results on a damaging increment
  const auto props = documented_props(pnc::damage::dissertation_parameters(Model::pnc), false);
  std::array<double, 6> s1{}, s2{}, v1{}, v2{}, stran{}, dstran{0.3, 0.01, 0, 0.02, 0, 0};
  std::array<double, 36> k1{}, k2{};
  Call c1, c2;
  c2.fn = &pnc_umat_;
  c1(s1.data(), v1.data(), k1.data(), stran.data(), dstran.data(), props.data());
  c2(s2.data(), v2.data(), k2.data(), stran.data(), dstran.data(), props.data());
  EXPECT_EQ(c1.pnewdt, 1.0);
  EXPECT_GT(v1[3], 0.0); // damaged
  EXPECT_EQ(s1, s2);
  EXPECT_EQ(v1, v2);
  EXPECT_EQ(k1, k2);
}

TEST(FeMaterialPropsMetadata, LayoutMatchesTheDocumentedTable) {
  for (Model m : {Model::pnc, Model::pp}) {
    const auto p = pnc::damage::dissertation_parameters(m);
    auto mat = pnc::fe_material::Material::from_constants(
        pnc::damage::model_name(m), std::vector<double>(p.k.begin(), p.k.begin() + p.size()));
    EXPECT_EQ(mat.umat_props(false), documented_props(p, false));
    EXPECT_EQ(mat.umat_props(true), documented_props(p, true));
    const std::size_t n = p.size() + 10;
    const auto names = mat.umat_prop_names(n);
    const auto units = mat.umat_prop_units(n);
    EXPECT_EQ(names.front(), "model_code");
    EXPECT_EQ(names[1], "C11");
    EXPECT_EQ(names[p.size()], "alpha");
    EXPECT_EQ(names[p.size() + 1], "R11");
    EXPECT_EQ(names.back(), "R33");
    EXPECT_EQ(units[1], "Pa");
    EXPECT_EQ(units[p.size()], "1");
    EXPECT_EQ(units.back(), "1");
    EXPECT_EQ(pnc_material_umat_prop_name(mat.get(), static_cast<int>(n)), nullptr);
    EXPECT_EQ(pnc_material_umat_prop_name(mat.get(), -1), nullptr);
    if (m == Model::pp) {
      const std::vector<std::string> pp = {"model_code", "C11", "C12", "C44",
                                           "B1",         "B2",  "B4",  "alpha"};
      EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 8), pp);
    }
  }
  // a rotated material carries R in PROPS even without the flag
  auto p = pnc::damage::dissertation_parameters(Model::pnc);
  const double c = std::cos(0.4), s = std::sin(0.4);
  const std::array<double, 9> R = {c, -s, 0, s, c, 0, 0, 0, 1};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      p.R(r, k) = R[static_cast<std::size_t>(3 * r + k)];
  auto mat = pnc::fe_material::Material::from_constants(
      "pnc", std::vector<double>(p.k.begin(), p.k.begin() + p.size()), &R);
  EXPECT_EQ(mat.umat_props(false), documented_props(p, true));
  double small[5];
  EXPECT_EQ(pnc_material_umat_props(mat.get(), 0u, small, 5), -1);
  EXPECT_EQ(pnc_material_umat_nprops(nullptr, 0u), 0);
}
