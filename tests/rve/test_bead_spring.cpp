// The glassy bead-spring polymer (model kg): the builder's guarantees (bond lengths inside the
// FENE range, excluded volume, exact density, determinism) checked by independent O(N^2)
// computations, and the force-field commands against closed forms of FENE + WCA and LJ 12-6
// evaluated in the test (LAMMPS single-point energies and forces in a child process).
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/rve/bead_spring.hpp"
#include "pnc/rve/recipe.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

using namespace pnc::rve;
using namespace pnc::md;
using V3 = std::array<double, 3>;

namespace {

double dist(const V3& a, const V3& b, double L) {
  double r2 = 0;
  for (int k = 0; k < 3; ++k) {
    double d = b[k] - a[k];
    if (L > 0) d -= L * std::round(d / L);
    r2 += d * d;
  }
  return std::sqrt(r2);
}

BuildSpec small_spec(std::uint64_t seed) {
  BuildSpec b;
  b.chains = 24;
  b.beads_per_chain = 20;
  b.density = 0.9;
  b.min_distance = 3.5;
  b.seed = seed;
  return b;
}

/// Closed forms written out here (independent of bead_spring.cpp): FENE with the WCA core for
/// the bonds, LJ 12-6 (cut, not shifted) for every pair that is not a bond.
struct Energies {
  double bond = 0, pair = 0;
  double total() const { return bond + pair; }
};
Energies closed_form(const std::vector<V3>& x, const std::vector<std::array<int, 2>>& bonds,
                     double eps, double sig, double K, double R0, double rc) {
  Energies e;
  auto lj = [&](double r) {
    const double s6 = std::pow(sig / r, 6);
    return 4 * eps * (s6 * s6 - s6);
  };
  for (const auto& b : bonds) {
    const double r = dist(x[b[0]], x[b[1]], 0);
    e.bond += -0.5 * K * R0 * R0 * std::log(1 - r * r / (R0 * R0));
    if (r < std::pow(2.0, 1.0 / 6.0) * sig) e.bond += lj(r) + eps;
  }
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      bool bonded = false;
      for (const auto& b : bonds)
        bonded |= (b[0] == static_cast<int>(i) && b[1] == static_cast<int>(j)) ||
                  (b[1] == static_cast<int>(i) && b[0] == static_cast<int>(j));
      const double r = dist(x[i], x[j], 0);
      if (!bonded && r < rc) e.pair += lj(r);
    }
  return e;
}

} // namespace

TEST(RveBeadSpring, UnitMappingOfTheDefaults) {
  const BeadSpringForceField ff;
  // eps / k_B = 400 K; tau = sigma sqrt(m / eps) and eps / sigma^3 from SI constants here.
  // k_B in kcal/mol/K is LAMMPS's real-unit value 0.0019872067 (what its thermostats use),
  // 1.2e-6 above CODATA's: relative tolerance 1e-5
  EXPECT_NEAR(ff.temperature_unit(), 400.0, 1e-9);
  const double NA = 6.02214076e23, m = 80e-3 / NA, eps = 400 * 1.380649e-23, s = 5e-10;
  EXPECT_NEAR(ff.tau_fs(), s * std::sqrt(m / eps) * 1e15, 1e-5 * ff.tau_fs());
  EXPECT_NEAR(ff.stress_unit_pa(), eps / (s * s * s), 1e-5 * ff.stress_unit_pa());
  EXPECT_NEAR(ff.fene_K(), 30 * ff.epsilon / 25.0, 1e-12);
  EXPECT_NEAR(ff.fene_R0(), 7.5, 1e-12);
  // sigma^3 N/V from g/cm^3: 0.9 g/cm^3 of 80 g/mol beads of 5 A
  EXPECT_NEAR(ff.reduced_density(0.9), 0.9 * 0.602214076 / 80 * 125, 1e-12);
}

TEST(RveBeadSpring, BuilderBondsExcludedVolumeDensityDeterminism) {
  const BeadSpringForceField ff;
  const BuildSpec spec = small_spec(7);
  const System s = build_bead_spring(spec, ff);
  const int n = spec.chains * spec.beads_per_chain;
  ASSERT_EQ(static_cast<int>(s.x.size()), n);
  ASSERT_EQ(static_cast<int>(s.bonds.size()), spec.chains * (spec.beads_per_chain - 1));
  EXPECT_TRUE(s.angles.empty());
  EXPECT_TRUE(s.dihedrals.empty());
  // density exact: mass over the box volume
  EXPECT_NEAR(s.density(), spec.density, 1e-12 * spec.density);
  const double L = s.length()[0];
  EXPECT_NEAR(n * ff.bead_mass / (L * L * L * avogadro_per_A3_cm3), spec.density, 1e-12);
  // every bond at 0.97 sigma (unwrapped positions: no minimum image), inside the FENE range
  for (const auto& b : s.bonds) {
    const double r = dist(s.x[b[1]], s.x[b[2]], 0);
    EXPECT_NEAR(r, ff.bond_length(), 1e-9);
    EXPECT_LT(r, ff.fene_R0());
    EXPECT_EQ(s.mol[b[1]], s.mol[b[2]]);
  }
  // excluded volume: all pairs but bonds, minimum image, O(N^2) here
  double dmin = 1e9;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (j == i + 1 && s.mol[i] == s.mol[j]) continue;
      dmin = std::min(dmin, dist(s.x[i], s.x[j], L));
    }
  EXPECT_GE(dmin, spec.min_distance);
  EXPECT_NEAR(min_unbonded_distance(s), dmin, 1e-9);
  // deterministic per seed, different for another seed
  const System again = build_bead_spring(spec, ff);
  EXPECT_EQ(again.x, s.x);
  const System other = build_bead_spring(small_spec(8), ff);
  EXPECT_NE(other.x, s.x);
}

TEST(RveBeadSpring, BuilderRefusesImpossibleRequests) {
  const BeadSpringForceField ff;
  BuildSpec spec = small_spec(1);
  spec.min_distance = 5.0; // above the 4.85 A bond
  EXPECT_THROW(build_bead_spring(spec, ff), pnc::InputError);
  BeadSpringForceField bad = ff;
  bad.bond_length_sigma = 1.6; // beyond R0 = 1.5 sigma: FENE undefined at the start
  try {
    bad.validate("r.json");
    ADD_FAILURE() << "expected an InputError";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().field, "forcefield.bond_length_sigma");
  }
  spec = small_spec(1);
  spec.min_distance = 3.9;
  spec.density = 2.5; // rho* 2.35: no room
  spec.max_chain_restarts = 20;
  EXPECT_THROW(build_bead_spring(spec, ff), pnc::InputError);
}

TEST(RveBeadSpring, LammpsEnergiesAndForcesMatchClosedForms) {
  const BeadSpringForceField ff;
  const double s = ff.sigma;
  // a 4-bead chain with bonds at 0.9, 1.05 (both inside the WCA core) and 1.3 sigma (FENE
  // only), and two free beads: one inside the LJ well of bead 0, one beyond the cutoff of all
  const std::vector<V3> x = {{30.0, 30.0, 30.0},
                             {30.0 + 0.9 * s, 30.0, 30.0},
                             {30.0 + 0.9 * s, 30.0 + 1.05 * s, 30.0},
                             {30.0 + 0.9 * s + 0.6 * s, 30.0 + 1.05 * s, 30.0 + 1.15 * s},
                             {30.0 - 0.7 * s, 30.0 - 1.0 * s, 30.0 + 0.3 * s},
                             {30.0 - 6.0 * s, 30.0 + 6.0 * s, 30.0 - 5.5 * s}};
  const std::vector<std::array<int, 2>> bonds = {{0, 1}, {1, 2}, {2, 3}};
  const auto ref = closed_form(x, bonds, ff.epsilon, s, ff.fene_K(), ff.fene_R0(), ff.cutoff());
  EXPECT_GT(ref.bond, 1.0);
  EXPECT_LT(ref.pair, -0.01); // attractive tails (1-3, 1-4 and the free bead) are counted
  // the library's closed forms agree with the test's
  double lib = 0;
  for (const auto& b : bonds)
    lib += bead_spring_bond_energy(ff, dist(x[b[0]], x[b[1]], 0));
  EXPECT_NEAR(lib, ref.bond, 1e-10 * ref.bond);

  System sys;
  sys.hi = {120, 120, 120};
  sys.type_mass = {ff.bead_mass};
  sys.x = x;
  sys.mol = {1, 1, 1, 1, 2, 3};
  sys.type.assign(x.size(), 1);
  sys.bonds = {{1, 0, 1}, {1, 1, 2}, {1, 2, 3}};
  sys.angle_types = 0;
  sys.dihedral_types = 0;
  const auto dir = pnc::test::fresh_dir("test_rve_kg_ff");
  const std::string data = (dir / "s.data").string(), res = (dir / "r.h5").string();
  write_data_file(data, sys, "hand-built bead-spring");
  const auto out = run_stage({"kg energy", (dir / "lammps.log").string(), {}}, [&](Lammps& l) {
    l.cmd("units real");
    l.cmd("atom_style molecular");
    l.cmd("read_data " + data);
    l.cmds(bead_spring_commands(ff));
    l.cmd("thermo_style custom step pe ebond evdwl");
    l.cmd("run 0");
    pnc::h5::File h(res, pnc::h5::File::Mode::truncate);
    h.write_vector("/e", {l.thermo("ebond"), l.thermo("evdwl")});
    h.write_vector("/f", l.gather("f", 3));
  });
  ASSERT_TRUE(out.ok) << out.error;
  pnc::h5::File h(res, pnc::h5::File::Mode::read);
  const auto e = h.read_vector("/e"), f = h.read_vector("/f");
  EXPECT_NEAR(e[0], ref.bond, 1e-9 * std::max(1.0, ref.bond));
  EXPECT_NEAR(e[1], ref.pair, 1e-9 * std::max(1.0, std::fabs(ref.pair)));
  const double hstep = 1e-5;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      auto xp = x, xm = x;
      xp[i][a] += hstep;
      xm[i][a] -= hstep;
      const double fd =
          -(closed_form(xp, bonds, ff.epsilon, s, ff.fene_K(), ff.fene_R0(), ff.cutoff()).total() -
            closed_form(xm, bonds, ff.epsilon, s, ff.fene_K(), ff.fene_R0(), ff.cutoff()).total()) /
          (2 * hstep);
      EXPECT_NEAR(f[3 * i + a], fd, 1e-5 * std::max(1.0, std::fabs(fd)))
          << "atom " << i << " axis " << a;
    }
  std::filesystem::remove_all(dir);
}

TEST(RveBeadSpring, RecipeRulesOfModelKg) {
  const Recipe r = parse_recipe(preset_json("demo_glass"), "demo_glass");
  EXPECT_EQ(r.model, "kg");
  EXPECT_EQ(r.cases, (std::vector<int>{2, 6}));
  EXPECT_EQ(r.stress, "total");
  EXPECT_EQ(r.moving_average, 1);
  // decision D138: alpha fitted from 0.82 (bounded below by 1/lambda_c, D12i), fit range 0.08
  // below the cavitation of case 2 (D12h)
  EXPECT_TRUE(r.fit_alpha);
  EXPECT_FALSE(r.hold_alpha);
  EXPECT_DOUBLE_EQ(r.fit_alpha_start, 0.82);
  EXPECT_DOUBLE_EQ(r.fit_strain_max, 0.08);
  EXPECT_NEAR(r.kg.temperature_unit(), 400.0, 1e-6);
  // the glass at T* = 0.2 and the melt at T* = 1, in real units
  EXPECT_NEAR(r.equilibrate.temperature / r.kg.temperature_unit(), 0.2, 1e-9);
  EXPECT_NEAR(r.equilibrate.hot_temperature / r.kg.temperature_unit(), 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(r.deform.temperature, r.equilibrate.temperature);
  EXPECT_EQ(expanded_json(parse_recipe(expanded_json(r), "x")), expanded_json(r));
  auto field_of = [](nlohmann::json j) {
    try {
      parse_recipe(j, "r.json");
    } catch (const pnc::InputError& e) {
      return e.context().field;
    }
    return std::string("(accepted)");
  };
  nlohmann::json j = preset_json("demo_glass");
  j["equilibrate"]["langevin_max_chunks"] = 3; // the polypropylene protocol's key
  EXPECT_EQ(field_of(j), "equilibrate.langevin_max_chunks");
  j = preset_json("demo_glass");
  j["equilibrate"]["ensemble"] = "nvt";
  EXPECT_EQ(field_of(j), "equilibrate.ensemble");
  j = preset_json("demo_glass");
  j["equilibrate"]["hot_temperature"] = 60.0; // below the glass temperature
  EXPECT_EQ(field_of(j), "equilibrate.hot_temperature");
  j = preset_json("demo_glass");
  j["forcefield"]["k_l"] = 1.0; // a polypropylene key
  EXPECT_EQ(field_of(j), "forcefield.k_l");
  j = preset_json("demo_glass");
  j["deform"]["cases"] = {5, 6}; // no extension case
  EXPECT_EQ(field_of(j), "deform.cases");
  j = preset_json("demo_glass");
  j["fit"]["hold_alpha"] = true; // and fit_alpha: exclusive
  EXPECT_EQ(field_of(j), "fit.hold_alpha");
  j = preset_json("demo_glass");
  j["fit"]["alpha"] = 0.3;
  EXPECT_EQ(field_of(j), "fit.alpha");
  j = preset_json("demo_glass");
  j["forcefield"]["cutoff_sigma"] = 1.0;
  EXPECT_EQ(field_of(j), "forcefield.cutoff_sigma");
  j = preset_json("demo_glass");
  j["fit"]["strain_max"] = -0.1; // the fit range of D12h
  EXPECT_EQ(field_of(j), "fit.strain_max");
  j["fit"]["strain_max"] = 0.04;
  EXPECT_EQ(field_of(j), "(accepted)");
  EXPECT_DOUBLE_EQ(parse_recipe(j, "r.json").fit_strain_max, 0.04);
}
