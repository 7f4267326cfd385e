// Equilibration protocol on a tiny RVE (short stages): every stage logs its end criterion,
// no bead overlaps after the push-off, density/pressure/void measure reported; NVT keeps the
// build density; resume skips finished stages.
#include "pnc/core/hdf5_io.hpp"
#include "pnc/md/builder.hpp"
#include "pnc/rve/equilibrate.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <filesystem>

using namespace pnc::rve;
using namespace pnc::md;
namespace fs = std::filesystem;

namespace {
EquilibrateSpec short_spec() {
  EquilibrateSpec s;
  s.pushoff_steps = 1000;
  s.hot_steps = 2000;
  s.cool_steps = 1000;
  s.langevin_chunk_steps = 500;
  s.langevin_max_chunks = 3;
  s.npt_steps = 2000;
  s.final_steps = 500;
  s.seed = 5;
  return s;
}
} // namespace

TEST(RveEquilibrate, ShortProtocolNptAndNvt) {
  const auto d = pnc::test::fresh_dir("test_rve_equil");
  const PolymerForceField ff;
  BuildSpec b;
  b.chains = 8; // 160 beads, box 18.6 A > 2 x cutoff
  b.density = 0.9;
  b.seed = 3;
  const System sys = build_polymer(b, ff);
  const std::string data = (d / "rve.data").string();
  write_data_file(data, sys, "tiny");
  for (const std::string ens : {"nvt", "npt"}) {
    EquilibrateSpec s = short_spec();
    s.ensemble = ens;
    const auto dir = (d / ens).string();
    const EquilibratedState e = equilibrate(data, ff, s, dir, false, "{}");
    ASSERT_EQ(e.criteria.size(), 5u);
    for (const auto& c : e.criteria)
      EXPECT_FALSE(c.empty());
    // no overlaps after the push-off: its criterion held and was recorded
    pnc::h5::File po((fs::path(dir) / "pushoff.h5").string(), pnc::h5::File::Mode::read);
    EXPECT_NE(po.read_string("/criterion").find(">="), std::string::npos)
        << po.read_string("/criterion");
    EXPECT_GE(e.min_distance, 0.75 * ff.sigma);
    EXPECT_GE(e.void_fraction, 0.0);
    EXPECT_LE(e.void_fraction, 1.0);
    EXPECT_NEAR(e.temperature, 300, 60);
    EXPECT_TRUE(fs::exists(e.restart));
    if (ens == "nvt") {
      EXPECT_NEAR(e.density, 0.9, 1e-6); // LAMMPS uses its own N_A digits
      // the D20 observation: at 0.9 g/cm3 the melt is under tension (P < 0)
      EXPECT_LT(e.pressure_virial, 0);
    } else {
      EXPECT_GT(e.density, 0.95); // the melt shrinks at zero pressure with sigma = 2.95 A
    }
    std::cerr << ens << ": density " << e.density << " g/cm3, P " << e.pressure_total
              << " atm (virial " << e.pressure_virial << "), void " << e.void_fraction << ", dmin "
              << e.min_distance << "\n";
  }
  // resume: all stages are found done, nothing re-run
  const auto t0 = fs::last_write_time(d / "npt" / "final.h5");
  EquilibrateSpec s = short_spec();
  equilibrate(data, ff, s, (d / "npt").string(), true, "{}");
  EXPECT_EQ(fs::last_write_time(d / "npt" / "final.h5"), t0);
  fs::remove_all(d);
}

TEST(RveEquilibrate, VoidFractionOfKnownConfigurations) {
  const double lo[3] = {0, 0, 0}, hi[3] = {10, 10, 10};
  EXPECT_DOUBLE_EQ(void_fraction({}, lo, hi, 1.0, 1.0), 1.0);
  // one bead with probe radius covering the whole (periodic) box
  EXPECT_DOUBLE_EQ(void_fraction({5, 5, 5}, lo, hi, 9.0, 1.0), 0.0);
  // a single bead, probe 2: the grid points within 2 A of it (sphere of ~33.5 A^3 / 1000)
  const double f = void_fraction({5, 5, 5}, lo, hi, 2.0, 0.5);
  EXPECT_NEAR(1.0 - f, 4.0 / 3.0 * M_PI * 8 / 1000, 0.006);
}
