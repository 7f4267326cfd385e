// Tests of the pnc material plugin, part 1: the C ABI, umat_ and the dlopen() route must reproduce
// pnc::damage::integrate() along damaging strain paths; bad input must be named clearly. Part 2
// (umat_ checks, card verdict, state and result checks): test_fe_material_umat.cpp.
#include "fe_material_support.hpp"

using namespace fe_material_test;

namespace {

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

} // namespace
