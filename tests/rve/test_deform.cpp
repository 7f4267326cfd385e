// Deformation driver: elastic constants of an FCC Lennard-Jones crystal at low T through
// the same driver the RVE uses, against T = 0 lattice sums with the same cutoff; resume
// after a kill reproduces the uninterrupted run; moving average and block errors.
#include "pnc/core/error.hpp"
#include "pnc/damage/cases.hpp"
#include "pnc/md/forcefield.hpp"
#include "pnc/rve/deform.hpp"

#include "common/lammps_banner.hpp"
#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <H5Cpp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace pnc::rve;
using namespace pnc::md;
namespace fs = std::filesystem;

namespace {

// Argon-like LJ in real units; the cutoff lies between the 4th and 5th neighbour shells.
constexpr double eps = 0.238, sig = 3.405, rc = 2.3 * 3.405, mass = 39.948;
constexpr double pa_per_kcal_mol_A3 = 68568.415 * 101325.0;

struct Born {
  double a0, C11, C12, C44; // A, Pa
};

/// T = 0 lattice sums with the cut (unshifted-force) LJ: lattice constant of zero pressure,
/// then the Born elastic constants C_ijkl = 1/(2 Omega) sum (phi'' - phi'/r) x_i x_j x_k x_l / r^2.
Born lattice_sums() {
  auto sum = [](double a, auto&& f) {
    const int m = static_cast<int>(std::ceil(2 * rc / a)) + 1;
    for (int i = -m; i <= m; ++i)
      for (int j = -m; j <= m; ++j)
        for (int k = -m; k <= m; ++k) {
          if ((i + j + k) % 2 != 0 || (i == 0 && j == 0 && k == 0)) continue;
          const double x = i * a / 2, y = j * a / 2, z = k * a / 2;
          const double r = std::sqrt(x * x + y * y + z * z);
          if (r < rc) f(x, y, z, r);
        }
  };
  auto d1 = [](double r) {
    return 4 * eps *
           (-12 * std::pow(sig, 12) / std::pow(r, 13) + 6 * std::pow(sig, 6) / std::pow(r, 7));
  };
  auto d2 = [](double r) {
    return 4 * eps *
           (156 * std::pow(sig, 12) / std::pow(r, 14) - 42 * std::pow(sig, 6) / std::pow(r, 8));
  };
  auto virial = [&](double a) {
    double w = 0;
    sum(a, [&](double, double, double, double r) { w += r * d1(r); });
    return w;
  };
  double lo = 1.4 * sig, hi = 1.7 * sig; // virial < 0 (compressed) at lo, > 0 at hi
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (virial(mid) < 0 ? lo : hi) = mid;
  }
  Born b{0.5 * (lo + hi), 0, 0, 0};
  const double omega = b.a0 * b.a0 * b.a0 / 4;
  sum(b.a0, [&](double x, double y, double, double r) {
    const double g = (d2(r) - d1(r) / r) / (r * r);
    b.C11 += g * x * x * x * x;
    b.C12 += g * x * x * y * y;
    b.C44 += g * x * y * x * y;
  });
  const double s = pa_per_kcal_mol_A3 / (2 * omega);
  b.C11 *= s;
  b.C12 *= s;
  b.C44 *= s;
  return b;
}

fs::path tmpdir(const std::string& tag) {
  return pnc::test::fresh_dir("test_rve_deform_" + tag);
}

std::vector<std::string> lj_ff() {
  return {"pair_style lj/cut " + std::to_string(rc), "pair_coeff 1 1 0.238 3.405"};
}

std::string make_crystal(const fs::path& d, double a0) {
  const std::string restart = (d / "start.restart").string();
  const auto out = run_stage({"crystal", (d / "crystal.log").string(), {}}, [&](Lammps& l) {
    l.cmds({"units real", "atom_style atomic", "boundary p p p",
            "lattice fcc " + std::to_string(a0), "region b block 0 4 0 4 0 4", "create_box 1 b",
            "create_atoms 1 box", "mass 1 " + std::to_string(mass)});
    l.cmds(lj_ff());
    l.cmd("velocity all set 0 0 0");
    l.cmd("write_restart " + restart);
  });
  EXPECT_TRUE(out.ok) << out.error;
  return restart;
}

DeformSpec crystal_spec(const std::string& start, int case_id) {
  DeformSpec s;
  s.case_id = case_id;
  s.atom_style = "atomic";
  s.start_state = start;
  s.force_field = lj_ff();
  s.timestep_fs = 2.0;
  s.temperature = 0.01;
  s.damp_fs = 200;
  s.hold_steps = 1000;
  s.sample_every = 10;
  s.blocks = 5;
  s.strain_max = 0.005;
  s.steps = 5;
  s.seed = 11;
  return s;
}

/// Least-squares slope at t = 0 of y = s0 + C t + D t^2.
double slope(const Eigen::VectorXd& t, const Eigen::VectorXd& y) {
  Eigen::MatrixXd A(t.size(), 3);
  A.col(0).setOnes();
  A.col(1) = t;
  A.col(2) = t.array().square();
  return A.colPivHouseholderQr().solve(y)(1);
}

} // namespace

TEST(RveDeform, FccLennardJonesElasticConstantsMatchLatticeSums) {
  const Born b = lattice_sums();
  // sanity of the reference itself: LJ fcc at T = 0 is near a0 = 1.54 sigma, C12 = C44 (Cauchy)
  EXPECT_NEAR(b.a0 / sig, 1.54, 0.02);
  EXPECT_NEAR(b.C12, b.C44, 1e-9 * b.C44);
  const auto d = tmpdir("fcc");
  const std::string start = make_crystal(d, b.a0);
  const auto o1 = run_case(crystal_spec(start, 1), (d / "case_1").string(), false);
  ASSERT_TRUE(o1.ok) << o1.error;
  const auto o6 = run_case(crystal_spec(start, 6), (d / "case_6").string(), false);
  ASSERT_TRUE(o6.ok) << o6.error;
  const CaseResult r1 = read_case((d / "case_1").string());
  const CaseResult r6 = read_case((d / "case_6").string());
  ASSERT_EQ(r1.rows_done, 6); // reference hold + 5 strain steps
  const double C11 = slope(r1.strain.col(0), r1.stress_virial.col(0));
  const double C12 = slope(r1.strain.col(0), r1.stress_virial.col(1));
  const double C13 = slope(r1.strain.col(0), r1.stress_virial.col(2));
  const double C44 = slope(r6.strain.col(5), r6.stress_virial.col(5));
  std::cerr << "FCC LJ (GPa): C11 " << C11 * 1e-9 << " vs " << b.C11 * 1e-9 << ", C12 "
            << C12 * 1e-9 << " vs " << b.C12 * 1e-9 << ", C44 " << C44 * 1e-9 << " vs "
            << b.C44 * 1e-9 << "\n";
  // Stated tolerance: 1 % (thermal and finite-strain effects at 0.01 K and <= 0.5 % strain
  // are far smaller; the tolerance guards sign, factor-2 and unit errors).
  EXPECT_NEAR(C11, b.C11, 0.01 * b.C11) << "C11 (GPa) " << C11 * 1e-9 << " vs " << b.C11 * 1e-9;
  EXPECT_NEAR(C12, b.C12, 0.01 * b.C12) << "C12 (GPa) " << C12 * 1e-9 << " vs " << b.C12 * 1e-9;
  EXPECT_NEAR(C13, b.C12, 0.01 * b.C12);
  EXPECT_NEAR(C44, b.C44, 0.01 * b.C44) << "C44 (GPa) " << C44 * 1e-9 << " vs " << b.C44 * 1e-9;
  // stress sign: extension gives tension (positive), and the kinetic term is negligible here
  EXPECT_GT(r1.stress_virial(5, 0), 0);
  EXPECT_NEAR(r1.stress_total(5, 0), r1.stress_virial(5, 0), 1e-3 * r1.stress_virial(5, 0));
  EXPECT_LT(std::fabs(r1.stress_virial(0, 0)), 0.01 * r1.stress_virial(1, 0)); // zero-strain row
  EXPECT_EQ(r1.thermo.rows(), 6);
  fs::remove_all(d);
}

// A user's force field with a long-range solver (PPPM) on a shear case: the box turns
// triclinic before the first row and LAMMPS wants the solver defined again on it. The crystal
// carries zero charges, so the Coulomb part adds nothing and C44 is the LJ lattice sum's.
TEST(RveDeform, ShearCaseWithPppmRedefinesTheSolverOnTheTriclinicBox) {
  const Born b = lattice_sums();
  const auto d = tmpdir("pppm");
  const std::string start = (d / "start.restart").string();
  const std::vector<std::string> ff = {"pair_style lj/cut/coul/long " + std::to_string(rc),
                                       "pair_coeff 1 1 0.238 3.405", "kspace_style pppm 1e-4",
                                       "kspace_modify gewald 0.3 mesh 8 8 8"};
  const auto made = run_stage({"crystal", (d / "crystal.log").string(), {}}, [&](Lammps& l) {
    l.cmds({"units real", "atom_style charge", "boundary p p p",
            "lattice fcc " + std::to_string(b.a0), "region b block 0 4 0 4 0 4", "create_box 1 b",
            "create_atoms 1 box", "mass 1 " + std::to_string(mass), "set type 1 charge 0.0"});
    l.cmds(ff);
    l.cmd("velocity all set 0 0 0");
    l.cmd("write_restart " + start);
  });
  ASSERT_TRUE(made.ok) << made.error;
  DeformSpec s = crystal_spec(start, 6);
  s.atom_style = "charge";
  s.force_field = ff;
  const auto o6 = run_case(s, (d / "case_6").string(), false);
  ASSERT_TRUE(o6.ok) << o6.error;
  const CaseResult r6 = read_case((d / "case_6").string());
  ASSERT_EQ(r6.rows_done, 6);
  const double C44 = slope(r6.strain.col(5), r6.stress_virial.col(5));
  // the tolerance of the LJ-only test above (1 %: sign, factor and unit errors)
  EXPECT_NEAR(C44, b.C44, 0.01 * b.C44) << "C44 (GPa) " << C44 * 1e-9 << " vs " << b.C44 * 1e-9;
  fs::remove_all(d);
}

TEST(RveDeform, ResumeAfterKillEqualsUninterruptedRun) {
  const Born b = lattice_sums();
  const auto d = tmpdir("resume");
  const std::string start = make_crystal(d, b.a0 * 1.01);
  DeformSpec s = crystal_spec(start, 2);
  s.temperature = 40; // a thermally noisy state: any difference in the path would show
  s.hold_steps = 300;
  s.steps = 4;
  s.strain_max = 0.02;
  const auto full = run_case(s, (d / "full").string(), false);
  ASSERT_TRUE(full.ok) << full.error;
  DeformSpec k = s;
  k.abort_after_step = 2;
  const auto killed = run_case(k, (d / "killed").string(), false);
  EXPECT_FALSE(killed.ok);
  EXPECT_EQ(killed.signal, 9);
  const CaseResult part = read_case((d / "killed").string()); // finished steps survived
  EXPECT_EQ(part.rows_done, 3);                               // rows 0, 1, 2
  const auto resumed = run_case(s, (d / "killed").string(), true);
  ASSERT_TRUE(resumed.ok) << resumed.error;
  // the resumed child ran only steps 3 and 4
  std::ifstream log(d / "killed" / "lammps.log");
  std::string line;
  int runs = 0;
  while (std::getline(log, line))
    runs += line.rfind("run 300", 0) == 0;
  EXPECT_EQ(runs, 2);
  const CaseResult a = read_case((d / "full").string());
  const CaseResult r = read_case((d / "killed").string());
  ASSERT_EQ(r.rows_done, 5);
  EXPECT_EQ(a.strain, r.strain);
  EXPECT_EQ(a.stress_virial, r.stress_virial);
  EXPECT_EQ(a.stress_total, r.stress_total);
  EXPECT_EQ(a.stress_virial_se, r.stress_virial_se);
  EXPECT_EQ(a.thermo, r.thermo);
  EXPECT_GT(a.thermo(4, 0), 10.0); // it really was hot
  fs::remove_all(d);
}

TEST(RveDeform, MovingAverageAndBlockErrors) {
  Eigen::Matrix<double, Eigen::Dynamic, 6> m(5, 6);
  for (int i = 0; i < 5; ++i)
    m.row(i).setConstant(i);
  const auto a = moving_average(m, 3);
  EXPECT_DOUBLE_EQ(a(0, 0), 0.5);
  EXPECT_DOUBLE_EQ(a(2, 0), 2.0);
  EXPECT_DOUBLE_EQ(a(4, 0), 3.5);
  EXPECT_THROW(
      pnc::damage::deformation_case(static_cast<int>(pnc::damage::deformation_cases().size()) + 1),
      pnc::InputError);
}

namespace {

std::string stored_version(const fs::path& ckpt) {
  H5::H5File f(ckpt.string(), H5F_ACC_RDONLY);
  std::string v;
  f.openDataSet("/lammps_version").read(v, H5::StrType(H5::PredType::C_S1, H5T_VARIABLE));
  return v;
}

void store_version(const fs::path& ckpt, const std::string& v) {
  H5::H5File f(ckpt.string(), H5F_ACC_RDWR);
  f.unlink("/lammps_version");
  const H5::StrType st(H5::PredType::C_S1, H5T_VARIABLE);
  f.createDataSet("/lammps_version", st, H5::DataSpace(H5S_SCALAR)).write(v, st);
}

} // namespace

// D366: the checkpoint names the LAMMPS that runs the case, and a resume with another one is
// refused; the constant of before (a date with a note) resumes with the same LAMMPS.
TEST(RveDeform, CheckpointNamesTheRunningLammpsAndAnotherVersionIsNotResumed) {
  const std::string date = pnc::test::lmp_banner_date();
  ASSERT_EQ(date.size(), 8u) << "no release date in the banner of `lmp -h`";
  const auto d = tmpdir("version");
  DeformSpec s = crystal_spec(make_crystal(d, lattice_sums().a0), 1);
  s.hold_steps = 100;
  s.steps = 2;
  s.abort_after_step = 0; // a checkpoint with the reference row
  const std::string dir = (d / "case").string();
  EXPECT_FALSE(run_case(s, dir, false).ok);
  const fs::path ckpt = d / "case" / "checkpoint.h5";
  EXPECT_EQ(stored_version(ckpt), date);

  s.abort_after_step = -1;
  const std::string other = std::to_string(std::stol(date) - 1); // a release of the day before
  store_version(ckpt, other);
  const auto refused = run_case(s, dir, true);
  EXPECT_FALSE(refused.ok);
  for (const std::string& part :
       {ckpt.string(), std::string("/lammps_version"), other, date, std::string("--resume")})
    EXPECT_NE(refused.error.find(part), std::string::npos) << part << " in: " << refused.error;

  store_version(ckpt, date + " (Debian 20220106)"); // the form written before D366
  const auto resumed = run_case(s, dir, true);
  ASSERT_TRUE(resumed.ok) << resumed.error;
  EXPECT_EQ(read_case(dir).rows_done, 3);
  EXPECT_EQ(stored_version(ckpt), date);
  fs::remove_all(d);
}
