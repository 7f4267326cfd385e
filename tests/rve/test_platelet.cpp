// The glass with one platelet (model kg_platelet, platelet.hpp): the builder (bond network
// counted independently, no polymer bead closer to the platelet than the rule, the box at the
// build density, determinism), the frequency bound of the bond network against the exact
// normal modes, and the recipe's errors (file, field, value, rule).
#include "pnc/core/error.hpp"
#include "pnc/rve/platelet.hpp"
#include "pnc/rve/recipe.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

using namespace pnc::rve;
using namespace pnc::md;
using json = nlohmann::json;

namespace {

pnc::ErrorContext error_of(const json& j) {
  try {
    parse_recipe(j, "r.json");
  } catch (const pnc::InputError& e) {
    return e.context();
  }
  ADD_FAILURE() << "no error for " << j.dump();
  return {};
}

json tiny() {
  json j = preset_json("demo_glass_pnc");
  j["build"]["chains"] = 20;
  j["build"]["beads_per_chain"] = 20;
  j["platelet"]["beads_side"] = 6;
  return j;
}

} // namespace

TEST(RvePlatelet, BuildCountsClearanceDensityAndDeterminism) {
  const Recipe r = parse_recipe(tiny(), "tiny");
  PlateletInfo info;
  const System s = build_kg_platelet(r.build, r.kg, r.platelet, &info);
  const int n = r.platelet.beads_side, m = r.platelet.layers;
  EXPECT_EQ(info.platelet_beads, n * n * m);
  EXPECT_EQ(info.polymer_beads, r.build.chains * r.build.beads_per_chain);
  EXPECT_EQ(static_cast<int>(s.x.size()), info.platelet_beads + info.polymer_beads);
  // bonds counted per kind: cube edges along x1 and x3 in each layer, along x2 between layers;
  // two diagonals per face: x1-x3 faces in each layer, x1-x2 and x2-x3 faces between layers
  int edges = 0, diagonals = 0, fene = 0;
  for (const auto& b : s.bonds)
    (b[0] == 1 ? fene : b[0] == 2 ? edges : diagonals)++;
  EXPECT_EQ(edges, m * 2 * n * (n - 1) + (m - 1) * n * n);
  EXPECT_EQ(diagonals, m * 2 * (n - 1) * (n - 1) + (m - 1) * 4 * n * (n - 1));
  EXPECT_EQ(fene, r.build.chains * (r.build.beads_per_chain - 1));
  // every platelet bond at its rest length, every FENE bond at the built length
  const double a = r.platelet.spacing_sigma * r.kg.sigma;
  for (const auto& b : s.bonds) {
    const auto d = s.min_image(s.x[b[1]], s.x[b[2]]);
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double want = b[0] == 1 ? r.kg.bond_length() : b[0] == 2 ? a : a * std::sqrt(2.0);
    EXPECT_NEAR(len, want, 1e-9 * want);
  }
  // the builder's rules: no polymer bead centre closer than min_distance_sigma sigma to the
  // platelet, none closer than build.min_distance to another non-bonded bead
  EXPECT_GE(min_polymer_platelet_distance(s), r.platelet.min_distance_sigma * r.kg.sigma);
  EXPECT_GE(min_unbonded_distance(s), std::min(r.build.min_distance, a));
  // every bead counts at the build density (D172): mass / volume is the recipe's density
  EXPECT_NEAR(s.density(), r.build.density, 1e-12 * r.build.density);
  EXPECT_LE(info.edge_A, 0.75 * info.box_A);
  // deterministic for a given seed, another seed another walk
  const System again = build_kg_platelet(r.build, r.kg, r.platelet);
  EXPECT_EQ(again.x, s.x);
  BuildSpec other = r.build;
  other.seed = 2;
  EXPECT_NE(build_kg_platelet(other, r.kg, r.platelet).x, s.x);
}

// The bound of platelet_omega_bound holds for the exact normal modes of the free network (the
// largest eigenvalue of the mass-weighted stiffness matrix, built here from the bonds), and the
// preset's timesteps are below 1 / bound (decision D173).
TEST(RvePlatelet, FrequencyBoundHoldsAndThePresetTimestepIsBelowIt) {
  PlateletSpec p;
  p.beads_side = 4;
  p.layers = 2;
  const BeadSpringForceField ff;
  const System plate = build_platelet(p, ff, {0, 0, 0}, 1);
  const auto n = static_cast<Eigen::Index>(plate.x.size());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  const double k = 2.0 * p.bond_K_reduced * ff.epsilon / (ff.sigma * ff.sigma); // kcal/mol/A^2
  for (const auto& b : plate.bonds) {
    Eigen::Vector3d e(plate.x[b[2]][0] - plate.x[b[1]][0], plate.x[b[2]][1] - plate.x[b[1]][1],
                      plate.x[b[2]][2] - plate.x[b[1]][2]);
    e.normalize();
    const Eigen::Matrix3d kee = k * e * e.transpose();
    const Eigen::Index i = 3 * b[1], j = 3 * b[2];
    H.block<3, 3>(i, i) += kee;
    H.block<3, 3>(j, j) += kee;
    H.block<3, 3>(i, j) -= kee;
    H.block<3, 3>(j, i) -= kee;
  }
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues();
  const double omega_max = std::sqrt(ev.maxCoeff() / ff.bead_mass * 4.184e-4); // 1/fs
  const double bound = platelet_omega_bound(plate, p, ff);
  EXPECT_GE(bound, omega_max * (1 - 1e-12));
  EXPECT_LE(bound, 2.0 * omega_max); // and not uselessly loose (2x: the two blocks of a bond)
  // the network is rigid: exactly 6 zero modes (3 translations, 3 rotations)
  int zero = 0;
  for (Eigen::Index i = 0; i < ev.size(); ++i)
    zero += std::fabs(ev[i]) < 1e-9 * ev.maxCoeff() ? 1 : 0;
  EXPECT_EQ(zero, 6);
  const Recipe r = parse_recipe(preset_json("demo_glass_pnc"), "demo_glass_pnc");
  const System pr = build_platelet(r.platelet, r.kg, {0, 0, 0}, 1);
  EXPECT_LE(platelet_omega_bound(pr, r.platelet, r.kg) * r.equilibrate.timestep_fs, 1.0);
  EXPECT_LE(platelet_omega_bound(pr, r.platelet, r.kg) * r.deform.timestep_fs, 1.0);
}

TEST(RvePlatelet, RecipeDefaultsAndErrorsNameFileFieldValueRule) {
  const Recipe r = parse_recipe(preset_json("demo_glass_pnc"), "demo_glass_pnc");
  EXPECT_EQ(r.model, "kg_platelet");
  EXPECT_EQ(r.cases, (std::vector<int>{1, 2, 3, 4, 5, 6}));
  json j = tiny();
  j["deform"].erase("cases");
  EXPECT_EQ(parse_recipe(j, "x").cases, (std::vector<int>{1, 2, 3, 4, 5, 6})); // the default
  struct Bad {
    json recipe;
    const char* field;
    const char* value;
  };
  std::vector<Bad> bad;
  auto with = [&](const char* section, const char* key, json v) {
    json t = tiny();
    t[section][key] = std::move(v);
    return t;
  };
  {
    json t = preset_json("demo_glass");
    t["platelet"] = json::object();
    bad.push_back({t, "platelet", "{}"});
  }
  bad.push_back({with("platelet", "wings", 2), "platelet.wings", "2"});
  bad.push_back({with("platelet", "layers", 1), "platelet.layers", "1"});
  bad.push_back({with("platelet", "spacing_sigma", "one"), "platelet.spacing_sigma", "\"one\""});
  bad.push_back({with("platelet", "beads_side", 9), "platelet.beads_side", "9"});
  bad.push_back({with("platelet", "epsilon_wp_reduced", 0.0), "platelet.epsilon_wp_reduced", "0"});
  bad.push_back({with("platelet", "bond_K_reduced", 2000.0), "equilibrate.timestep_fs", "20"});
  // sigma 4.5 A: 0.8 sigma = 3.6 A below build.min_distance 3.9 A (the builder's bound is
  // < 4 A): the platelet must exclude at least what a polymer bead does
  bad.push_back({with("build", "min_distance", 3.9), "platelet.min_distance_sigma", "0.8"});
  bad.back().recipe["platelet"]["min_distance_sigma"] = 0.8;
  bad.back().recipe["forcefield"]["sigma"] = 4.5;
  for (const auto& b : bad) {
    const auto e = error_of(b.recipe);
    EXPECT_EQ(e.source, "r.json") << b.field;
    EXPECT_EQ(e.field, b.field) << e.rule;
    EXPECT_EQ(e.value, b.value) << e.rule;
    EXPECT_FALSE(e.rule.empty()) << b.field;
  }
}
