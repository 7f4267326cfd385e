// Phase check (pnc/rve/phase_check.hpp) on two tiny Lennard-Jones systems whose answer is
// known independently: a liquid well above its melting point (T* = 1.5, rho* = 0.8: relaxes,
// G(t) decays within ~1 LJ time) and an FCC crystal at 10 K (solid; its K from the volume pair
// and G from the shear pair against T = 0 lattice sums with the same cutoff).
#include "pnc/core/units.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/rve/phase_check.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

using namespace pnc::rve;
using namespace pnc::md;
namespace fs = std::filesystem;

namespace {

// Argon-like LJ in real units (tau_LJ = sigma sqrt(m/eps) = 2.16 ps); the cutoff lies between
// the 4th and 5th neighbour shells of the crystal (no shell within 5 % of it).
constexpr double eps = 0.238, sig = 3.405, rc = 2.3 * 3.405, mass = 39.948;
constexpr double pa_per_kcal_mol_A3 = 68568.415 * 101325.0;

double d1(double r) {
  return 4 * eps *
         (-12 * std::pow(sig, 12) / std::pow(r, 13) + 6 * std::pow(sig, 6) / std::pow(r, 7));
}
double d2(double r) {
  return 4 * eps *
         (156 * std::pow(sig, 12) / std::pow(r, 14) - 42 * std::pow(sig, 6) / std::pow(r, 8));
}
template <class F> void lattice(double a, F&& f) {
  const int m = static_cast<int>(std::ceil(2 * rc / a)) + 1;
  for (int i = -m; i <= m; ++i)
    for (int j = -m; j <= m; ++j)
      for (int k = -m; k <= m; ++k) {
        if ((i + j + k) % 2 != 0 || (i == 0 && j == 0 && k == 0)) continue;
        const double x = i * a / 2, y = j * a / 2, z = k * a / 2;
        const double r = std::sqrt(x * x + y * y + z * z);
        if (r < rc) f(x, y, z, r);
      }
}
/// Static (T = 0) virial pressure of the fcc lattice, Pa: P = -1/(6 Omega) sum_R r phi'(r).
double static_pressure(double a) {
  double w = 0;
  lattice(a, [&](double, double, double, double r) { w += r * d1(r); });
  return -w / (6 * a * a * a / 4) * pa_per_kcal_mol_A3;
}
double zero_pressure_a() {
  double lo = 1.4 * sig, hi = 1.7 * sig; // P > 0 at lo, < 0 at hi
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (static_pressure(mid) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
/// Born C44 = 1/(2 Omega) sum (phi'' - phi'/r) x^2 y^2 / r^2, Pa (Bravais lattice: exact at T=0).
double born_c44(double a) {
  double c = 0;
  lattice(a, [&](double x, double y, double, double r) {
    c += (d2(r) - d1(r) / r) / (r * r) * x * x * y * y;
  });
  return c / (2 * a * a * a / 4) * pa_per_kcal_mol_A3;
}

fs::path tmpdir(const std::string& tag) {
  return pnc::test::fresh_dir("test_rve_phase_" + tag);
}
std::vector<std::string> lj_ff() {
  return {"pair_style lj/cut " + std::to_string(rc), "pair_coeff 1 1 0.238 3.405"};
}

/// 4x4x4 fcc cells at lattice constant a, thermalised at T_melt then T (Langevin), as a restart.
std::string make_state(const fs::path& d, double a, double t_melt, double t) {
  const std::string restart = (d / "start.restart").string();
  const auto out = run_stage({"lj", (d / "lj.log").string(), {}}, [&](Lammps& l) {
    l.cmds({"units real", "atom_style atomic", "boundary p p p", "lattice fcc " + std::to_string(a),
            "region b block 0 4 0 4 0 4", "create_box 1 b", "create_atoms 1 box",
            "mass 1 " + std::to_string(mass)});
    l.cmds(lj_ff());
    l.cmds({"timestep 5", "velocity all create " + std::to_string(t_melt) + " 7 dist gaussian",
            "fix n all nve",
            "fix t all langevin " + std::to_string(t_melt) + " " + std::to_string(t) + " 200 9",
            "run 2000", "unfix t",
            "fix t all langevin " + std::to_string(t) + " " + std::to_string(t) + " 200 10",
            "run 1000", "write_restart " + restart});
  });
  EXPECT_TRUE(out.ok) << out.error;
  return restart;
}

PhaseCheckSpec spec() {
  PhaseCheckSpec s;
  s.enabled = true;
  s.steps = 8000;     // 40 ps NVE
  s.sample_every = 2; // 10 fs
  s.blocks = 10;
  s.shear_strain = 0.03;
  s.bulk_strain = 0.02;
  s.cavitation_strain = 0.01;
  s.cavitation_steps = 1000;
  return s;
}
PhaseCheckInput input(const std::string& start, double t) {
  PhaseCheckInput in;
  in.start_state = start;
  in.atom_style = "atomic";
  in.force_field = lj_ff();
  in.temperature = t;
  in.damp_fs = 200;
  in.timestep_fs = 5;
  in.hold_steps = 1000; // 5 ps
  in.hold_sample_every = 5;
  in.probe_A = sig;
  in.seed = 21;
  return in;
}
} // namespace

TEST(RvePhaseCheck, LennardJonesLiquidRelaxesWithinAHold) {
  const auto d = tmpdir("liquid");
  const double a = std::cbrt(4 / 0.8) * sig;       // rho* = 0.8
  const double T = 1.5 * eps * 4184 / 8.314462618; // T* = 1.5 (180 K)
  const std::string start = make_state(d, a, 3 * T, T);
  const PhaseCheckResult r =
      run_phase_check(spec(), input(start, T), (d / "phase").string(), false);
  EXPECT_FALSE(r.solid) << r.summary;
  EXPECT_EQ(r.phase, "relaxes within a hold");
  std::cerr << "LJ liquid: NVE T " << r.nve_T_first_K << " -> " << r.nve_T_last_K << " K\n";
  EXPECT_NEAR(r.temperature_K, T, 0.1 * T); // NVE after the re-thermalisation
  EXPECT_GT(r.G_t0_Pa, kResolvedSigmas * r.G_t0_se_Pa);
  // the stress autocorrelation of this fluid decays within ~0.5 tau_LJ: at 2 ps (0.93 tau)
  // less than 10 % of G(0) is left (plus the statistics)
  const std::size_t k2 = static_cast<std::size_t>(std::lround(2e-12 / r.dt_s));
  ASSERT_LT(k2, r.acf_G_Pa.size());
  EXPECT_LT(std::fabs(r.acf_G_Pa[k2]), 0.1 * r.G_t0_Pa + 4 * r.acf_G_se_Pa[k2]);
  // and no shear stress is left after a step strain: |G_hold| within 4 s.e. of zero
  EXPECT_LT(std::fabs(r.G_hold_Pa), 4 * r.G_hold_se_Pa) << r.G_hold_Pa;
  EXPECT_GT(r.K_Pa, 0.0);
  // the same numbers come back from phase.h5
  const PhaseCheckResult b = read_phase_check((d / "phase").string());
  EXPECT_EQ(b.G_hold_Pa, r.G_hold_Pa);
  EXPECT_EQ(b.phase, r.phase);
  fs::remove_all(d);
}

TEST(RvePhaseCheck, LennardJonesCrystalIsSolidWithTheLatticeBulkAndShearModuli) {
  const auto d = tmpdir("crystal");
  const double a0 = zero_pressure_a(), T = 10;
  const std::string start = make_state(d, a0, 2 * T, T);
  const PhaseCheckSpec s = spec();
  const PhaseCheckResult r = run_phase_check(s, input(start, T), (d / "phase").string(), false);
  EXPECT_TRUE(r.solid) << r.summary;
  // static K from the same +-volume pair on the T = 0 lattice
  const double ap = a0 * std::cbrt(1 + s.bulk_strain), am = a0 * std::cbrt(1 - s.bulk_strain);
  const double K0 = -(static_pressure(ap) - static_pressure(am)) /
                    std::log((1 + s.bulk_strain) / (1 - s.bulk_strain));
  const double G0 = born_c44(a0);
  // thermal terms at fixed volume: the kinetic pressure N k T / V adds exactly N k T / V to K,
  // the anharmonic thermal pressure gamma N k T / V (LJ Grueneisen gamma <~ 3) changes K by
  // about gamma (gamma + 1) N k T / V <~ 12 N k T / V: allowed 20 N k T / V, plus 4 s.e.
  const double nkt_v = 4 / (a0 * a0 * a0) * 1e30 * pnc::units::boltzmann * T;
  std::cerr << "LJ crystal: K " << r.K_Pa * 1e-9 << " +- " << r.K_se_Pa * 1e-9 << " GPa vs static "
            << K0 * 1e-9 << "; G_hold " << r.G_hold_Pa * 1e-9 << " +- " << r.G_hold_se_Pa * 1e-9
            << " vs Born C44 " << G0 * 1e-9 << "; N k T / V " << nkt_v * 1e-9 << " GPa\n";
  EXPECT_NEAR(r.K_Pa, K0, 20 * nkt_v + 4 * r.K_se_Pa);
  EXPECT_NEAR(r.G_hold_Pa, G0, 20 * nkt_v + 4 * r.G_hold_se_Pa);
  EXPECT_FALSE(r.cavitates) << r.summary; // 1 % expansion of a 10 K crystal
  fs::remove_all(d);
}
