// Each force-field term: LAMMPS's energy (and the total forces) on a hand-built
// configuration against an independent closed-form evaluation of the printed forms
// (docs/theory.md §3.1) with the unit reading of decision D13.
#include "pnc/core/hdf5_io.hpp"
#include "pnc/md/builder.hpp"
#include "pnc/md/runner.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>

using namespace pnc::md;
using V3 = std::array<double, 3>;

namespace {

V3 sub(const V3& a, const V3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const V3& a, const V3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const V3& a) {
  return std::sqrt(dot(a, a));
}

struct Terms {
  double bond = 0, angle = 0, tors = 0, lj = 0;
  double total() const { return bond + angle + tors + lj; }
};

/// Closed forms of docs/theory.md §3.1, physical constants (k_l, k_theta: no LAMMPS halving),
/// polymer torsion convention: omega = 0 is trans.
Terms closed_form(const std::vector<V3>& x, const std::vector<int>& mol,
                  const PolymerForceField& ff) {
  Terms t;
  // one chain: atoms 0..3 (mol 1); others single beads
  for (int i = 0; i < 3; ++i)
    t.bond += 0.5 * ff.k_l * std::pow(norm(sub(x[i + 1], x[i])) - ff.l0, 2);
  for (int i = 0; i < 2; ++i) {
    const V3 a = sub(x[i], x[i + 1]), b = sub(x[i + 2], x[i + 1]);
    const double c = dot(a, b) / (norm(a) * norm(b));
    t.angle += 0.5 * ff.k_theta * std::pow(c - std::cos(ff.theta0_deg * M_PI / 180), 2);
  }
  {
    const V3 b1 = sub(x[1], x[0]), b2 = sub(x[2], x[1]), b3 = sub(x[3], x[2]);
    const V3 n1 = cross(b1, b2), n2 = cross(b2, b3);
    // IUPAC dihedral phi: 0 = cis, 180 = trans; polymer omega = phi - 180 deg.
    const double cphi = dot(n1, n2) / (norm(n1) * norm(n2));
    const double comega = -cphi;
    for (int n = 0; n < 4; ++n)
      t.tors += ff.C[n] * std::pow(comega, n);
  }
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      if (mol[i] == mol[j]) continue; // 4-bead chain: every intra pair is 1-2, 1-3 or 1-4
      const double r = norm(sub(x[i], x[j]));
      if (r >= ff.cutoff()) continue;
      const double s6 = std::pow(ff.sigma / r, 6);
      t.lj += 4 * ff.epsilon * (s6 * s6 - s6);
    }
  return t;
}

System hand_system(const std::vector<V3>& x, const std::vector<int>& mol) {
  System s;
  s.hi = {50, 50, 50};
  s.type_mass = {21.0};
  s.x = x;
  s.mol = mol;
  s.type.assign(x.size(), 1);
  s.bonds = {{1, 0, 1}, {1, 1, 2}, {1, 2, 3}};
  s.angles = {{1, 0, 1, 2}, {1, 1, 2, 3}};
  s.dihedrals = {{1, 0, 1, 2, 3}};
  return s;
}

struct LammpsEval {
  Terms e;
  std::vector<double> f;
};

LammpsEval lammps_eval(const System& s, const PolymerForceField& ff, const std::string& tag) {
  const auto dir = pnc::test::fresh_dir("test_rve_ff_" + tag);
  const std::string data = (dir / "s.data").string(), res = (dir / "r.h5").string();
  write_data_file(data, s, "hand-built");
  StageSpec st{"ff energy", (dir / "lammps.log").string(), {}};
  const auto out = run_stage(st, [&](Lammps& l) {
    l.cmd("units real");
    l.cmd("atom_style molecular");
    l.cmd("read_data " + data);
    l.cmds(polymer_forcefield_commands(ff));
    l.cmd("thermo_style custom step pe ebond eangle edihed evdwl");
    l.cmd("run 0");
    pnc::h5::File h(res, pnc::h5::File::Mode::truncate);
    h.write_vector("/e",
                   {l.thermo("ebond"), l.thermo("eangle"), l.thermo("edihed"), l.thermo("evdwl")});
    h.write_vector("/f", l.gather("f", 3));
  });
  EXPECT_TRUE(out.ok) << out.error;
  pnc::h5::File h(res, pnc::h5::File::Mode::read);
  const auto e = h.read_vector("/e");
  LammpsEval r{{e[0], e[1], e[2], e[3]}, h.read_vector("/f")};
  std::filesystem::remove_all(dir);
  return r;
}

} // namespace

TEST(MdForceField, UnitReadingAndLammpsCoefficients) {
  const PolymerForceField ff;
  EXPECT_NEAR(ff.k_l, 346.0 / 4.184, 1e-12);
  EXPECT_NEAR(ff.epsilon, 0.498 / 4.184, 1e-12); // printed "0.498 J/mol" read as kJ/mol
  EXPECT_NEAR(ff.k_theta, 520.0 / 4.184, 1e-12); // printed "520 J/mol" read as kJ/mol
  EXPECT_NEAR(ff.C[0], 8.832 / 4.184, 1e-12);    // printed "8, 832 J/mol" = 8.832 kJ/mol
  EXPECT_NEAR(ff.lammps_bond_K(), ff.k_l / 2, 1e-14);
  const auto A = ff.lammps_dihedral_A();
  for (int n = 0; n < 4; ++n)
    EXPECT_DOUBLE_EQ(A[n], (n % 2 ? -1 : 1) * ff.C[n]);
}

TEST(MdForceField, EachTermEnergyAndForcesMatchClosedForm) {
  const PolymerForceField ff;
  const std::vector<V3> x = {{20.0, 20.0, 20.0}, {21.6, 20.0, 20.0}, {22.2, 21.4, 20.1},
                             {23.7, 21.7, 21.0}, {19.5, 23.3, 20.4}, {27.0, 25.0, 24.0}};
  const std::vector<int> mol = {1, 1, 1, 1, 2, 3};
  const Terms ref = closed_form(x, mol, ff);
  // every term is exercised with a non-trivial value
  EXPECT_GT(ref.bond, 0.1);
  EXPECT_GT(ref.angle, 0.1);
  EXPECT_GT(std::fabs(ref.tors), 0.1);
  EXPECT_GT(std::fabs(ref.lj), 0.01);
  const LammpsEval got = lammps_eval(hand_system(x, mol), ff, "general");
  EXPECT_NEAR(got.e.bond, ref.bond, 1e-9 * std::max(1.0, ref.bond));
  EXPECT_NEAR(got.e.angle, ref.angle, 1e-9 * std::max(1.0, ref.angle));
  EXPECT_NEAR(got.e.tors, ref.tors, 1e-9 * std::max(1.0, std::fabs(ref.tors)));
  EXPECT_NEAR(got.e.lj, ref.lj, 1e-9 * std::max(1.0, std::fabs(ref.lj)));
  // forces: central differences of the closed-form total energy
  const double h = 1e-5;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      auto xp = x, xm = x;
      xp[i][a] += h;
      xm[i][a] -= h;
      const double f =
          -(closed_form(xp, mol, ff).total() - closed_form(xm, mol, ff).total()) / (2 * h);
      EXPECT_NEAR(got.f[3 * i + a], f, 1e-5 * std::max(1.0, std::fabs(f)))
          << "atom " << i << " axis " << a;
    }
}

TEST(MdForceField, TransIsOmegaZeroAndCisCostsC0MinusC1PlusC2MinusC3) {
  const PolymerForceField ff;
  const double l = ff.l0, th = ff.theta0_deg * M_PI / 180;
  // planar zig-zag (trans) and planar U (cis), bonds and angles at their rest values
  const V3 p0{20, 20, 20}, p1{20 + l, 20, 20};
  const V3 p2{p1[0] - l * std::cos(th), 20 + l * std::sin(th), 20};
  const V3 trans3{p2[0] + l, p2[1], 20};
  // cis: the 4th bead mirrors bead 0 across the perpendicular bisector of bond 1-2
  const V3 mid{(p1[0] + p2[0]) / 2, (p1[1] + p2[1]) / 2, 20};
  const V3 d = sub(p2, p1);
  const double dn = norm(d);
  const V3 u{d[0] / dn, d[1] / dn, 0};
  const V3 r0 = sub(p0, mid);
  const double along = dot(r0, u);
  const V3 cis{mid[0] + r0[0] - 2 * along * u[0], mid[1] + r0[1] - 2 * along * u[1], 20};
  for (bool is_trans : {true, false}) {
    const std::vector<V3> x = {p0, p1, p2, is_trans ? trans3 : cis, {45, 45, 45}};
    const std::vector<int> mol = {1, 1, 1, 1, 2};
    const LammpsEval got = lammps_eval(hand_system(x, mol), ff, is_trans ? "trans" : "cis");
    const auto& C = ff.C;
    const double expect = is_trans ? C[0] + C[1] + C[2] + C[3] : C[0] - C[1] + C[2] - C[3];
    EXPECT_NEAR(got.e.tors, expect, 1e-8) << (is_trans ? "trans" : "cis");
    EXPECT_NEAR(got.e.bond, 0, 1e-12);
    EXPECT_NEAR(got.e.angle, 0, 1e-12);
  }
  EXPECT_NEAR((ff.C[0] + ff.C[1] + ff.C[2] + ff.C[3]) * 4.184, -0.001, 1e-9); // trans ~ 0
}
