// Montmorillonite platelet: C2/m expansion and composition, coordination and bond lengths,
// each clay force-field term through LAMMPS vs closed forms of Tables 6.2-6.5, composite
// fractions and the polymer-clay minimum distance.
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/rve/clay.hpp"
#include "pnc/rve/recipe.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <random>

using namespace pnc::rve;
using namespace pnc::md;
using V3 = std::array<double, 3>;

namespace {
double dist(const V3& a, const V3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}
} // namespace

TEST(RveClay, UnitCellIsTwoFormulaUnitsOfAl2Si4O10OH2) {
  std::map<std::string, int> n;
  for (const auto& s : clay_unit_cell())
    ++n[s.label];
  // Si8 Al4 O24 H4 = 2 x Al2Si4O10(OH)2
  EXPECT_EQ(n["Si"], 8);
  EXPECT_EQ(n["Al"], 4);
  EXPECT_EQ(n["O1"] + n["O2"] + n["O3"] + n["OH"], 24);
  EXPECT_EQ(n["OH"], 4);
  EXPECT_EQ(n["H"], 4);
  EXPECT_EQ(n["Si"], 2 * n["Al"]);
}

TEST(RveClay, PeriodicLayerCoordinationAndBondLengths) {
  const Platelet p = build_platelet(3, 2, true);
  ASSERT_EQ(p.x.size(), 6u * 40u);
  std::vector<int> nO(p.x.size(), 0), nH(p.x.size(), 0);
  const std::map<int, double> l0 = {
      {bond_Al_O1, 1.955}, {bond_O1_H, 0.988}, {bond_Si_O2, 1.626}, {bond_Si_O1, 1.62}};
  const double Px = 3 * 5.20, Pz = 2 * 9.20;
  double worst = 0;
  for (const auto& b : p.bonds) {
    V3 d{p.x[b[2]][0] - p.x[b[1]][0], p.x[b[2]][1] - p.x[b[1]][1], p.x[b[2]][2] - p.x[b[1]][2]};
    d[0] -= Px * std::round(d[0] / Px);
    d[2] -= Pz * std::round(d[2] / Pz);
    const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    worst = std::max(worst, std::fabs(r - l0.at(b[0])));
    // Stated tolerance: the crystal's bond lengths within 0.10 A of Table 6.2's l0
    EXPECT_NEAR(r, l0.at(b[0]), 0.10) << "bond type " << b[0];
    const bool i_o = p.type[b[1]] == type_O, j_o = p.type[b[2]] == type_O;
    if (j_o) ++nO[b[1]];
    if (i_o) ++nO[b[2]];
    if (p.type[b[2]] == type_H) ++nH[b[1]];
  }
  std::cout << "largest |l - l0| of the crystal: " << worst << " A\n";
  int nsi = 0, nal = 0, nh = 0;
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    if (p.type[i] == type_Si) {
      ++nsi;
      EXPECT_EQ(nO[i], 4) << "Si " << i;
    }
    if (p.type[i] == type_Al) {
      ++nal;
      EXPECT_EQ(nO[i], 6) << "Al " << i;
    }
    if (p.site[i] == "OH") {
      EXPECT_EQ(nH[i], 1);
    }
    if (p.type[i] == type_H) ++nh;
  }
  EXPECT_EQ(nsi, 2 * nal);
  EXPECT_EQ(nh, nal);
  // every angle / torsion type of Tables 6.3-6.4 occurs
  std::map<int, int> at;
  for (const auto& a : p.angles)
    ++at[a[0]];
  for (int t = angle_Al_O1_H; t <= angle_O1_Al_O1_180; ++t)
    EXPECT_GT(at[t], 0) << "angle type " << t;
  EXPECT_GT(p.dihedrals.size(), 0u);
  // platelet along x1, normal x2, width x3
  EXPECT_NEAR(p.length, 3 * 5.20, 1e-12);
  EXPECT_NEAR(p.width, 2 * 9.20, 1e-12);
  EXPECT_GT(p.thickness, 6.0);
  EXPECT_LT(p.thickness, 7.5);
}

namespace {

struct ClayTerms {
  double bond = 0, angle = 0, tors = 0, lj = 0;
};

/// Closed forms of docs/theory.md §3.2 (D23) with the printed parameters (no 1/2), written out here
/// independently of clay.cpp's LAMMPS mapping; the topology is the builder's.
ClayTerms closed_form(const System& s, const PolymerForceField& pff) {
  ClayTerms t;
  const std::map<int, std::pair<double, double>> bond = {
      {2, {1.955, 382.617}}, {3, {0.988, 827.209}}, {4, {1.626, 492.387}}, {5, {1.62, 558.593}}};
  const std::map<int, std::pair<double, double>> angle = {
      {2, {118, 34.933}},   {3, {124.5, 155.754}}, {4, {110.6, 97.493}},
      {5, {109.5, 198.27}}, {6, {90, 80.0}},       {7, {180, 80.0}}};
  for (const auto& b : s.bonds) {
    const auto [l0, k] = bond.at(b[0]);
    t.bond += k * std::pow(dist(s.x[b[1]], s.x[b[2]]) - l0, 2);
  }
  for (const auto& a : s.angles) {
    const auto [th0, k] = angle.at(a[0]);
    V3 u{}, w{};
    for (int c = 0; c < 3; ++c) {
      u[c] = s.x[a[1]][c] - s.x[a[2]][c];
      w[c] = s.x[a[3]][c] - s.x[a[2]][c];
    }
    const double cs =
        (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / (dist(u, {0, 0, 0}) * dist(w, {0, 0, 0}));
    t.angle += k * std::pow(cs - std::cos(th0 * M_PI / 180), 2);
  }
  t.tors = 0.722 * 2 * static_cast<double>(s.dihedrals.size()); // V [1 + cos(0)]
  // LJ: Table 6.5 per element pair (H: none), cutoff 2.5 sigma_ij, bonded 1-2/1-3/1-4 excluded
  auto el = [&](std::size_t i) { return s.type[i]; };
  auto lj = [&](int a, int b) -> std::pair<double, double> {
    if (a > b) std::swap(a, b);
    if (a == 5 || b == 5) return {1, 0};
    if (a == 1 && b == 1) return {pff.sigma, pff.epsilon};
    if (a == 1) return b == 4 ? std::pair{3.33, 0.094} : std::pair{3.96, 0.0395};
    if (a == 2 && b == 2) return {4.05, 0.04};
    if (a == 2 && b == 3) return {4.053, 0.04};
    if (a == 3 && b == 3) return {4.05, 0.04};
    if (b == 4 && a != 4) return {3.404, 0.0955};
    return {2.86, 0.228};
  };
  const std::size_t n = s.x.size();
  std::vector<std::vector<int>> nb(n);
  for (const auto& b : s.bonds) {
    nb[b[1]].push_back(b[2]);
    nb[b[2]].push_back(b[1]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    // topological distance <= 3 from i
    std::vector<int> depth(n, 99);
    std::vector<int> front = {static_cast<int>(i)};
    depth[i] = 0;
    for (int d = 1; d <= 3; ++d) {
      std::vector<int> next;
      for (int q : front)
        for (int r : nb[q])
          if (depth[r] > d) {
            depth[r] = d;
            next.push_back(r);
          }
      front = next;
    }
    for (std::size_t j = i + 1; j < n; ++j) {
      if (depth[j] <= 3) continue;
      const auto [sg, ep] = lj(el(i), el(j));
      const double r = dist(s.x[i], s.x[j]);
      if (ep == 0 || r >= 2.5 * sg) continue;
      const double s6 = std::pow(sg / r, 6);
      t.lj += 4 * ep * (s6 * s6 - s6);
    }
  }
  return t;
}

} // namespace

TEST(RveClay, EachClayTermEnergyThroughLammpsMatchesClosedForm) {
  // one finite cell, positions perturbed (so every term is off its minimum), plus two beads
  const Platelet p = build_platelet(1, 1);
  System s;
  s.hi = {60, 60, 60};
  s.type_mass = {21.0, clay_type_mass(2), clay_type_mass(3), clay_type_mass(4), clay_type_mass(5)};
  std::mt19937_64 g(5);
  std::uniform_real_distribution<double> u(-0.08, 0.08);
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    s.x.push_back({p.x[i][0] + 30 + u(g), p.x[i][1] + 30 + u(g), p.x[i][2] + 30 + u(g)});
    s.type.push_back(p.type[i]);
    s.mol.push_back(1);
  }
  for (const V3& b : {V3{30.5, 36.8, 30.2}, V3{28.0, 23.6, 31.0}}) {
    s.x.push_back(b);
    s.type.push_back(1);
    s.mol.push_back(2);
  }
  s.bonds.assign(p.bonds.begin(), p.bonds.end());
  s.angles.assign(p.angles.begin(), p.angles.end());
  s.dihedrals.assign(p.dihedrals.begin(), p.dihedrals.end());
  s.bond_types = 5;
  s.angle_types = 7;
  s.dihedral_types = 2;
  const PolymerForceField pff;
  const ClayTerms ref = closed_form(s, pff);
  EXPECT_GT(ref.bond, 1.0);
  EXPECT_GT(ref.angle, 1.0);
  EXPECT_GT(ref.tors, 1.0);
  EXPECT_GT(std::fabs(ref.lj), 0.01);

  const auto dir = pnc::test::fresh_dir("test_rve_clay_ff");
  const std::string data = (dir / "s.data").string(), res = (dir / "r.h5").string();
  write_data_file(data, s, "clay cell");
  const auto out = run_stage({"clay energy", (dir / "lammps.log").string(), {}}, [&](Lammps& l) {
    l.cmd("units real");
    l.cmd("atom_style molecular");
    l.cmd("read_data " + data);
    l.cmds(composite_forcefield_commands(pff));
    l.cmd("thermo_style custom step pe ebond eangle edihed evdwl");
    l.cmd("run 0");
    pnc::h5::File h(res, pnc::h5::File::Mode::truncate);
    h.write_vector("/e",
                   {l.thermo("ebond"), l.thermo("eangle"), l.thermo("edihed"), l.thermo("evdwl")});
  });
  ASSERT_TRUE(out.ok) << out.error;
  pnc::h5::File h(res, pnc::h5::File::Mode::read);
  const auto e = h.read_vector("/e");
  std::filesystem::remove_all(dir);
  EXPECT_NEAR(e[0], ref.bond, 1e-8 * std::max(1.0, ref.bond));
  EXPECT_NEAR(e[1], ref.angle, 1e-8 * std::max(1.0, ref.angle));
  EXPECT_NEAR(e[2], ref.tors, 1e-8 * std::max(1.0, ref.tors));
  EXPECT_NEAR(e[3], ref.lj, 1e-8 * std::max(1.0, std::fabs(ref.lj)));
}

TEST(RveClay, CompositeHasRequestedFractionsAndNoBeadNearTheClay) {
  BuildSpec spec;
  spec.chains = 20;
  spec.seed = 3;
  ClaySpec clay;
  clay.cells_a = 3;
  clay.cells_b = 1;
  const PolymerForceField ff;
  CompositeInfo info;
  const System s = build_composite(spec, ff, clay, &info);
  // independent: masses from the element counts, volume from the lattice and positions
  double mclay = 0, ymin = 1e9, ymax = -1e9;
  int nclay = 0;
  for (std::size_t i = 0; i < s.x.size(); ++i)
    if (s.type[i] != 1) {
      ++nclay;
      mclay += std::map<int, double>{{2, 28.0855}, {3, 26.9815385}, {4, 15.999}, {5, 1.008}}.at(
          s.type[i]);
      ymin = std::min(ymin, s.x[i][1]);
      ymax = std::max(ymax, s.x[i][1]);
    }
  const double mpoly = 400 * 21.0;
  const double L[3] = {s.hi[0] - s.lo[0], s.hi[1] - s.lo[1], s.hi[2] - s.lo[2]};
  const double vclay = 3 * 5.20 * 9.20 * (ymax - ymin);
  EXPECT_EQ(info.clay_atoms, nclay);
  EXPECT_NEAR(info.weight_fraction, mclay / (mclay + mpoly), 1e-12);
  EXPECT_NEAR(info.volume_fraction, vclay / (L[0] * L[1] * L[2]), 1e-9);
  // the polymer fills the rest of the box at the build density
  EXPECT_NEAR(mpoly / ((L[0] * L[1] * L[2] - vclay) * avogadro_per_A3_cm3), spec.density, 1e-9);
  EXPECT_NEAR(L[0], 3 * 5.20 + clay.gap_x, 1e-9);
  // Stated minimum distance: no bead closer than clay.min_distance (3.0 A) to a clay atom.
  EXPECT_GE(min_polymer_clay_distance(s), clay.min_distance - 1e-12);
  EXPECT_GE(min_nonbonded_distance(s), spec.min_distance - 1e-12);
  std::cout << "3x1 platelet, 400 beads: " << nclay << " clay atoms, weight fraction "
            << info.weight_fraction << ", volume fraction " << info.volume_fraction << "\n";
  // the paper geometry (1500 beads, 7 x 1 cells)
  spec.chains = 75;
  clay.cells_a = 7;
  CompositeInfo paper;
  build_composite(spec, ff, clay, &paper);
  std::cout << "paper geometry 7x1, 1500 beads: " << paper.clay_atoms << " clay atoms, length "
            << paper.length << " A, width " << paper.width << " A, thickness " << paper.thickness
            << " A, aspect ratio " << paper.aspect_ratio << ", weight fraction "
            << paper.weight_fraction << ", volume fraction " << paper.volume_fraction << "\n";
}

TEST(RveClay, RecipeModelPncPresetsAndErrors) {
  for (const char* name : {"demo_pnc", "paper_pnc"}) {
    const Recipe r = parse_recipe(preset_json(name), name);
    EXPECT_EQ(r.model, "pnc");
    EXPECT_EQ(r.cases, (std::vector<int>{1, 2, 3, 4, 5, 6}));
    EXPECT_EQ(expanded_json(parse_recipe(expanded_json(r), "x")), expanded_json(r));
  }
  const Recipe paper = parse_recipe(preset_json("paper_pnc"), "paper_pnc");
  EXPECT_EQ(paper.build.chains * paper.build.beads_per_chain, 1500);
  EXPECT_EQ(paper.clay.cells_a, 7);
  auto error_of = [](const nlohmann::json& j) {
    try {
      parse_recipe(j, "r.json");
    } catch (const pnc::InputError& e) {
      return e.context();
    }
    ADD_FAILURE() << "expected an InputError for " << j.dump();
    return pnc::ErrorContext{};
  };
  using nlohmann::json;
  // aspect ratio 4.19 with one cell across: cells_a = round(4.19 * 9.20 / 5.20) = 7
  EXPECT_EQ(
      parse_recipe(json{{"model", "pnc"}, {"clay", {{"aspect_ratio", 4.19}}}}, "r").clay.cells_a,
      7);
  auto e = error_of(json{{"model", "pnc"}, {"clay", {{"cells_a", 0}}}});
  EXPECT_EQ(e.field, "clay.cells_a");
  EXPECT_EQ(e.value, "0");
  EXPECT_FALSE(e.rule.empty());
  e = error_of(json{{"model", "pnc"}, {"clay", {{"cells_b", 4}}}});
  EXPECT_EQ(e.field, "clay.cells_b"); // wider than the box
  e = error_of(json{{"model", "pnc"}, {"clay", {{"min_distance", -1.0}}}});
  EXPECT_EQ(e.field, "clay.min_distance");
  e = error_of(json{{"model", "pnc"}, {"clay", {{"cells_a", 7}, {"aspect_ratio", 4.0}}}});
  EXPECT_EQ(e.field, "clay.aspect_ratio");
  e = error_of(json{{"model", "pnc"}, {"clay", {{"cells_c", 1}}}});
  EXPECT_EQ(e.field, "clay.cells_c");
  e = error_of(json{{"model", "pp"}, {"clay", {{"cells_a", 3}}}});
  EXPECT_EQ(e.field, "clay");
  e = error_of(json{{"model", "pnc"}});
  EXPECT_EQ(e.field, "model"); // the platelet must be named
}

TEST(RveClay, EquilibrationFreezesTheClayThenThePolymer) {
  namespace fs = std::filesystem;
  const auto d = pnc::test::fresh_dir("test_rve_clay_equil");
  const PolymerForceField ff;
  BuildSpec b;
  b.chains = 12;
  b.seed = 4;
  ClaySpec clay;
  clay.cells_a = 2;
  const System sys = build_composite(b, ff, clay);
  const std::string data = (d / "rve.data").string();
  write_data_file(data, sys, "tiny composite");
  EquilibrateSpec s;
  s.timestep_fs = 0.5;
  s.pushoff_steps = 500;
  s.hot_steps = 1000;
  s.clay_steps = 500;
  s.cool_steps = 500;
  s.langevin_chunk_steps = 500;
  s.langevin_max_chunks = 2;
  s.npt_steps = 1000;
  s.final_steps = 500;
  s.seed = 5;
  const std::string dir = (d / "eq").string();
  const EquilibratedState e = equilibrate(data, ff, s, dir, false, "{}", true);
  ASSERT_EQ(e.criteria.size(), 6u); // pushoff, hot, clay, cool, langevin, final
  EXPECT_EQ(e.criteria[2].rfind("clay: polymer fixed", 0), 0u) << e.criteria[2];
  EXPECT_NEAR(e.temperature, 300, 80);
  // positions (by atom id) after each stage, gathered from the restart files
  const std::string res = (d / "x.h5").string();
  const auto out = run_stage({"read", (d / "read.log").string(), {}}, [&](Lammps& l) {
    pnc::h5::File h(res, pnc::h5::File::Mode::truncate);
    for (const char* st : {"pushoff", "hot", "clay", "final"}) {
      l.cmd("clear");
      l.cmd("units real");
      l.cmd("atom_style molecular");
      l.cmd("read_restart " + (fs::path(dir) / (std::string(st) + ".restart")).string());
      l.cmd("run 0");
      const auto box = l.box();
      h.write_vector(std::string("/x_") + st, l.gather("x", 3));
      h.write_vector(std::string("/box_") + st,
                     {box.lo[0], box.lo[1], box.lo[2], box.hi[0], box.hi[1], box.hi[2]});
    }
  });
  ASSERT_TRUE(out.ok) << out.error;
  pnc::h5::File h(res, pnc::h5::File::Mode::read);
  const auto x0 = h.read_vector("/x_pushoff"), x1 = h.read_vector("/x_hot"),
             x2 = h.read_vector("/x_clay");
  const auto bx = h.read_vector("/box_hot");
  const int nclay = static_cast<int>(build_platelet(2, 1).x.size());
  auto moved = [&](const std::vector<double>& a, const std::vector<double>& c, int from, int to) {
    double m = 0;
    for (int i = from; i < to; ++i)
      for (int k = 0; k < 3; ++k) {
        double dd = c[3 * i + k] - a[3 * i + k];
        const double L = bx[3 + k] - bx[k];
        dd -= L * std::round(dd / L);
        m = std::max(m, std::fabs(dd));
      }
    return m;
  };
  const int n = static_cast<int>(sys.x.size());
  // clay atoms come first in the data file: frozen from the build through "hot"
  for (int i = 0; i < nclay; ++i)
    for (int k = 0; k < 3; ++k) {
      double dd = x1[3 * i + k] - sys.x[i][k];
      dd -= (bx[3 + k] - bx[k]) * std::round(dd / (bx[3 + k] - bx[k]));
      EXPECT_NEAR(dd, 0.0, 1e-6) << "clay atom " << i;
    }
  EXPECT_GT(moved(x0, x1, nclay, n), 0.5);  // the polymer moved in "hot"
  EXPECT_LT(moved(x1, x2, nclay, n), 1e-9); // ... and is fixed in "clay"
  EXPECT_GT(moved(x1, x2, 0, nclay), 1e-3); // where the clay relaxes
  // NPT acts on x2, x3 only: x1 keeps the build length (platelet + gap)
  const auto bf = h.read_vector("/box_final");
  EXPECT_NEAR(bf[3] - bf[0], sys.hi[0] - sys.lo[0], 1e-6);
  fs::remove_all(d);
}
