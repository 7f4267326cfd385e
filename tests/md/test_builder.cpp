// Builder: requested density and chain count, bond geometry, no overlaps, determinism.
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/md/builder.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace pnc::md;

namespace {
double dist(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}
} // namespace

TEST(MdBuilder, DensityChainsGeometryAndMinimumDistance) {
  const PolymerForceField ff;
  for (double rho : {0.9, 1.55}) {
    BuildSpec spec;
    spec.chains = 75; // the dissertation's 1500 beads
    spec.density = rho;
    spec.seed = 7;
    const System s = build_polymer(spec, ff);
    ASSERT_EQ(s.x.size(), 1500u);
    EXPECT_NEAR(s.density(), rho, 1e-12 * rho);
    int max_mol = 0;
    for (int m : s.mol)
      max_mol = std::max(max_mol, m);
    EXPECT_EQ(max_mol, 75);
    EXPECT_EQ(s.bonds.size(), 75u * 19);
    EXPECT_EQ(s.angles.size(), 75u * 18);
    EXPECT_EQ(s.dihedrals.size(), 75u * 17);
    for (const auto& b : s.bonds)
      EXPECT_NEAR(dist(s.x[b[1]], s.x[b[2]]), ff.l0, 1e-9);
    for (const auto& a : s.angles) {
      // 1-3 distance fixes the bond angle: 2 l0 sin(theta0/2)
      EXPECT_NEAR(dist(s.x[a[1]], s.x[a[3]]), 2 * ff.l0 * std::sin(ff.theta0_deg * M_PI / 360),
                  1e-9);
    }
    // Stated minimum distance: no two beads other than 1-2/1-3 neighbours closer than 2.0 A.
    EXPECT_GE(min_nonbonded_distance(s), spec.min_distance - 1e-12);
  }
}

TEST(MdBuilder, DeterministicPerSeed) {
  const PolymerForceField ff;
  BuildSpec spec;
  spec.chains = 10;
  spec.seed = 42;
  const System a = build_polymer(spec, ff), b = build_polymer(spec, ff);
  ASSERT_EQ(a.x.size(), b.x.size());
  for (std::size_t i = 0; i < a.x.size(); ++i)
    EXPECT_EQ(a.x[i], b.x[i]);
  spec.seed = 43;
  const System c = build_polymer(spec, ff);
  EXPECT_NE(a.x[0], c.x[0]);
}

TEST(MdBuilder, ImpossibleDensityIsAnInputErrorNamingTheField) {
  BuildSpec spec;
  spec.chains = 20;
  spec.density = 2.9;
  spec.min_distance = 3.5;
  spec.max_chain_restarts = 50;
  try {
    build_polymer(spec, PolymerForceField{});
    FAIL() << "expected InputError";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().field, "build.density");
  }
  spec.density = -1;
  EXPECT_THROW(spec.validate("recipe.json"), pnc::InputError);
}

TEST(MdBuilder, DataFileAndRecord) {
  const auto dir = pnc::test::fresh_dir("test_rve_builder");
  BuildSpec spec;
  spec.chains = 5;
  const PolymerForceField ff;
  const System s = build_polymer(spec, ff);
  write_data_file((dir / "a.data").string(), s, "test");
  write_build_record((dir / "a.h5").string(), s, spec, ff, "{\"x\":1}");
  std::ifstream f(dir / "a.data");
  std::string text((std::istreambuf_iterator<char>(f)), {});
  EXPECT_NE(text.find("100 atoms"), std::string::npos);
  EXPECT_NE(text.find("95 bonds"), std::string::npos);
  EXPECT_NE(text.find("Dihedrals"), std::string::npos);
  pnc::h5::File h((dir / "a.h5").string(), pnc::h5::File::Mode::read);
  EXPECT_NEAR(h.read_scalar("/result/density"), spec.density, 1e-12);
  EXPECT_EQ(h.read_matrix("/result/positions").rows(), 100);
  EXPECT_EQ(h.read_string("/recipe"), "{\"x\":1}");
  std::filesystem::remove_all(dir);
}
