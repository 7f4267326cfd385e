// A tiny glass-platelet composite (model kg_platelet) through the stage functions of
// `pnc characterize`: build, the glass protocol with the platelet (equilibrate_glass), static
// strain cases 1-3. Checked against physics, not against a previous run:
//  * the glass is denser than the built melt and less dense than the T = 0 LJ crystal;
//  * the platelet keeps its shape: at 80 K every bond length within 6 thermal standard
//    deviations sqrt(k_B T / (2 K)) of its rest length (a bond's own spring alone; the network
//    only stiffens it); no polymer bead comes within 0.8 sigma_wp of it (LJ 179 eps, 900 k_B T);
//  * it is stiff against the glass: between the 0 K states of case 1 at strains e and 2e its
//    edge bonds along x1 stretch by less than half the strain difference (a dilute inclusion of
//    stiffness ratio r = C_p / C_m carries 1 / (1 + (r - 1) S) of the strain; the bond network has
//    C_p ~ 2 K / a = 600 eps/sigma^3 along an edge against C11 ~ 70 eps/sigma^3 of the glass,
//    r ~ 9, and a flat inclusion's in-plane Eshelby factor S ~ 1.6 t / d ~ 0.3-0.5 here: <= 0.3);
//  * orthotropy in the direction a stiff platelet predicts: under uniaxial strain (lateral
//    box held), the platelet lying in the x1-x3 plane is strained in its plane by cases 1 and 3
//    (the stiff phase in parallel with the glass: Voigt-like, stiffening) but not by case 2,
//    which pulls the glass layers above and below it in series (Reuss-like: the platelet's
//    share of the strain is ~ 0), so C11 > C22 and C33 > C22.
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/units.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/rve/bead_spring.hpp"
#include "pnc/rve/deform.hpp"
#include "pnc/rve/platelet.hpp"
#include "pnc/rve/recipe.hpp"

#include "common/temp_dir.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;
using namespace pnc::rve;
using namespace pnc::md;

namespace {

// 400 polymer beads + a 6 x 6 x 2 platelet (edge 5 sigma, 0.6 of the box): 472 beads; melt
// 16 tau, quench 65 tau, glass hold 16 + 8 tau at 20 fs
const char* tiny_text = R"({
  "name": "tiny_platelet", "seed": 3, "model": "kg_platelet",
  "build": { "chains": 20, "beads_per_chain": 20, "density": 0.9, "min_distance": 3.5 },
  "platelet": { "beads_side": 6, "layers": 2, "epsilon_wp_reduced": 1.0 },
  "equilibrate": { "timestep_fs": 20.0, "temperature": 80.0, "hot_temperature": 400.0,
                   "damp_fs": 2000.0, "pushoff_steps": 1000, "hot_steps": 2000,
                   "cool_steps": 8000, "pdamp_fs": 20000.0, "npt_steps": 2000,
                   "final_steps": 1000 },
  "deform": { "cases": [1, 2, 3], "strain_max": 0.004, "steps": 1, "timestep_fs": 20.0,
              "temperature": 0.0 },
  "analysis": { "stress": "total" }
})";

struct Shape {
  double max_edge_dev = 0, max_diag_dev = 0; ///< max |r - r0| / r0 over the bonds of a kind
  double x1_edge_strain = 0;                 ///< mean r / r0 - 1 of the edge bonds along x1
  double min_polymer_platelet = 0;           ///< A
};

/// Platelet bond lengths (atoms 1..n of the data file: the builder puts the platelet first)
/// and the smallest polymer-platelet distance in `restart`, minimum image in its box.
Shape measure(const std::string& restart, const Recipe& r, const fs::path& dir,
              const std::string& tag) {
  const System plate = build_platelet(r.platelet, r.kg, {0, 0, 0}, 1);
  const std::string res = (dir / (tag + ".h5")).string();
  const auto out =
      run_stage({"measure " + tag, (dir / (tag + ".log")).string(), {}}, [&](Lammps& l) {
        l.cmd("units real");
        l.cmd("atom_style molecular");
        l.cmd("read_restart " + lammps_path(restart, "restart"));
        l.cmds(kg_platelet_commands(r.kg, r.platelet));
        const auto b = l.box();
        const auto x = l.gather("x", 3);
        pnc::h5::File h(res, pnc::h5::File::Mode::truncate);
        h.write_vector("/x", x);
        h.write_vector("/box", {b.length(0), b.length(1), b.length(2), b.xy, b.xz, b.yz});
      });
  EXPECT_TRUE(out.ok) << out.error;
  pnc::h5::File h(res, pnc::h5::File::Mode::read);
  const auto x = h.read_vector("/x");
  const auto L = h.read_vector("/box");
  EXPECT_EQ(L[3], 0.0); // cases 1-3 keep the box orthogonal
  auto dist = [&](std::size_t i, std::size_t j, double* dx1) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
      double d = x[3 * j + a] - x[3 * i + a];
      d -= L[a] * std::round(d / L[a]);
      if (a == 0 && dx1) *dx1 = d;
      d2 += d * d;
    }
    return std::sqrt(d2);
  };
  Shape s;
  const double a = r.platelet.spacing_sigma * r.kg.sigma;
  int nx1 = 0;
  for (const auto& b : plate.bonds) {
    const double r0 = b[0] == 2 ? a : a * std::sqrt(2.0);
    const double len = dist(b[1], b[2], nullptr);
    double& m = b[0] == 2 ? s.max_edge_dev : s.max_diag_dev;
    m = std::max(m, std::fabs(len - r0) / r0);
    const bool along_x1 = b[0] == 2 && std::fabs(plate.x[b[2]][0] - plate.x[b[1]][0]) > 0.5 * a;
    if (along_x1) {
      s.x1_edge_strain += len / r0 - 1;
      ++nx1;
    }
  }
  s.x1_edge_strain /= nx1;
  s.min_polymer_platelet = 1e300;
  const std::size_t np = plate.x.size(), n = x.size() / 3;
  for (std::size_t i = np; i < n; ++i)
    for (std::size_t j = 0; j < np; ++j)
      s.min_polymer_platelet = std::min(s.min_polymer_platelet, dist(i, j, nullptr));
  return s;
}

} // namespace

TEST(RvePlateletCli, TinyCompositeKeepsItsPlateletAndIsStifferInPlaneThanAlongTheNormal) {
  const auto d = pnc::test::fresh_dir("test_rve_platelet");
  const Recipe r = parse_recipe(nlohmann::json::parse(tiny_text), "tiny");
  PlateletInfo info;
  const System s = build_kg_platelet(r.build, r.kg, r.platelet, &info);
  const std::string data = (d / "rve.data").string();
  write_data_file(data, s, "tiny platelet");
  const EquilibratedState e = equilibrate_glass(data, r.kg, r.equilibrate, (d / "eq").string(),
                                                false, "{}", 1, &r.platelet);
  // every bead weighs bead_mass: the reduced density counts polymer and platelet beads
  const double rho = r.kg.reduced_density(e.density);
  EXPECT_GT(rho, r.kg.reduced_density(r.build.density)); // quenched at P = 0 from the melt
  EXPECT_LT(rho, 1.09);                                  // the T = 0 LJ fcc crystal at P = 0
  EXPECT_NEAR(e.temperature, 80.0, 0.05 * 80.0);

  const Shape hot = measure(e.restart, r, d, "glass");
  const double kT = pnc::units::kB_kcal_mol_K * e.temperature;
  const double K = r.platelet.bond_K_reduced * r.kg.epsilon / (r.kg.sigma * r.kg.sigma);
  const double a = r.platelet.spacing_sigma * r.kg.sigma;
  const double sd_edge = std::sqrt(kT / (2 * K)) / a; // relative, one bond's spring alone
  EXPECT_LT(hot.max_edge_dev, 6 * sd_edge);
  EXPECT_LT(hot.max_diag_dev, 6 * sd_edge / std::sqrt(2.0));
  EXPECT_GE(hot.min_polymer_platelet, 0.8 * r.platelet.sigma_wp_sigma * r.kg.sigma);
  std::cerr << fmt::format("80 K glass: rho* {:.4f}, max bond deviation edges {:.4f} diagonals "
                           "{:.4f} (6 sd = {:.4f}), min polymer-platelet {:.3f} A\n",
                           rho, hot.max_edge_dev, hot.max_diag_dev, 6 * sd_edge,
                           hot.min_polymer_platelet);

  double C[3] = {0, 0, 0};
  for (int id = 1; id <= 3; ++id) {
    DeformSpec ds = r.deform;
    ds.case_id = id;
    ds.seed = 11;
    ds.start_state = e.restart;
    ds.force_field = kg_platelet_commands(r.kg, r.platelet);
    const std::string cdir = (d / fmt::format("case_{}", id)).string();
    const auto o = run_case(ds, cdir, false);
    ASSERT_TRUE(o.ok) << o.error;
    const CaseResult c = read_case(cdir);
    ASSERT_EQ(c.rows_done, 2);
    const int v = id - 1;
    C[v] = (c.stress_total(1, v) - c.stress_total(0, v)) / ds.strain_max; // Pa
  }
  // the platelet's share of the strain: case 1 once more to twice the strain; the difference of
  // its x1 edges' elongation between the two 0 K states over the strain difference (the
  // residual stress of the quenched glass on the platelet cancels in the difference)
  double edge_strain[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    std::string cdir = (d / "case_1").string(); // k = 0: the case 1 run above
    if (k == 1) {
      DeformSpec ds = r.deform;
      ds.case_id = 1;
      ds.seed = 11;
      ds.strain_max = 2 * r.deform.strain_max;
      ds.start_state = e.restart;
      ds.force_field = kg_platelet_commands(r.kg, r.platelet);
      cdir = (d / "case_1_twice").string();
      ASSERT_TRUE(run_case(ds, cdir, false).ok);
    }
    edge_strain[k] =
        measure((fs::path(cdir) / "state_1.restart").string(), r, d, fmt::format("c1_{}", k))
            .x1_edge_strain;
  }
  const double share = (edge_strain[1] - edge_strain[0]) / r.deform.strain_max;
  std::cerr << fmt::format("case 1: platelet x1 edges {:.3e} at strain {}, {:.3e} at {}: share "
                           "of the box strain {:.3f}\n",
                           edge_strain[0], r.deform.strain_max, edge_strain[1],
                           2 * r.deform.strain_max, share);
  EXPECT_LT(std::fabs(share), 0.5);
  std::cerr << fmt::format("static C11 {:.3f}, C22 {:.3f}, C33 {:.3f} GPa\n", C[0] * 1e-9,
                           C[1] * 1e-9, C[2] * 1e-9);
  EXPECT_GT(C[1], 0.0);
  EXPECT_GT(C[0], C[1]);
  EXPECT_GT(C[2], C[1]);
  fs::remove_all(d);
}
