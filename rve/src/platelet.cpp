// Model nanocomposite: the bead-spring glass with one stiff platelet (model "kg_platelet",
// decisions D170-D174). Units real (A, g/mol, kcal/mol); platelet parameters in reduced units.
#include "pnc/rve/platelet.hpp"
#include "pnc/rve/recipe.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"
#include "pnc/core/units.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pnc::rve {

using Vec = std::array<double, 3>;

void PlateletSpec::validate(const std::string& source) const {
  auto range = [&](const char* name, double v, double lo, double hi, bool lo_open,
                   const char* why) {
    const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
    if (!ok)
      fail(source, std::string("platelet.") + name, fmt::format("{}", v),
           fmt::format("must be in {}{}, {}] ({})", lo_open ? "(" : "[", lo, hi, why));
  };
  if (beads_side < 2 || beads_side > 60)
    fail(source, "platelet.beads_side", std::to_string(beads_side), "must be in 2..60");
  if (layers < 2 || layers > 4)
    fail(source, "platelet.layers", std::to_string(layers),
         "must be in 2..4 (a single layer of centrally bonded beads has no bending stiffness; "
         "decision D170)");
  range("spacing_sigma", spacing_sigma, 0.8, 1.2, false,
        "sigma; denser than 0.8 sigma gains nothing, wider than 1.2 sigma lets a polymer bead "
        "sit in the lattice's hollows");
  range("epsilon_wp_reduced", epsilon_wp_reduced, 0.0, 5.0, true, "eps; the adhesion");
  range("sigma_wp_sigma", sigma_wp_sigma, 0.8, 1.5, false, "sigma");
  range("bond_K_reduced", bond_K_reduced, 10.0, 2000.0, false, "eps/sigma^2");
  range("min_distance_sigma", min_distance_sigma, 0.8, 1.5, false,
        "sigma; polymer bead to platelet bead at the build");
}

double kg_platelet_box(const md::BuildSpec& spec, const BeadSpringForceField& ff,
                       const PlateletSpec& p) {
  const double n = static_cast<double>(spec.chains) * spec.beads_per_chain +
                   static_cast<double>(p.layers) * p.beads_side * p.beads_side;
  return std::cbrt(n * ff.bead_mass / (spec.density * md::avogadro_per_A3_cm3));
}

void check_kg_platelet_box(const md::BuildSpec& spec, const BeadSpringForceField& ff,
                           const PlateletSpec& p, const std::string& source) {
  const double L = kg_platelet_box(spec, ff, p);
  const double a = p.spacing_sigma * ff.sigma;
  const double edge = (p.beads_side - 1) * a, thick = (p.layers - 1) * a;
  if (edge > 0.75 * L || L - edge < 2.0 * ff.sigma)
    fail(source, "platelet.beads_side", std::to_string(p.beads_side),
         fmt::format("the platelet edge ({} - 1) x {:.3g} A = {:.2f} A must be <= 3/4 of the "
                     "box edge {:.2f} A at the build and leave >= 2 sigma of polymer to its "
                     "periodic image (decision D172): fewer beads_side or more chains",
                     p.beads_side, a, edge, L));
  if (thick > 0.5 * L)
    fail(source, "platelet.layers", std::to_string(p.layers),
         fmt::format("the platelet thickness {:.2f} A must be <= half the box edge {:.2f} A", thick,
                     L));
  const double rc = std::max(ff.cutoff(), ff.cutoff_sigma * p.sigma_wp_sigma * ff.sigma);
  if (2 * rc >= L)
    fail(source, "build.chains", std::to_string(spec.chains),
         fmt::format("the box ({:.2f} A at the build density) must exceed twice the largest LJ "
                     "cutoff ({:.2f} A): use more chains",
                     L, 2 * rc));
}

md::System build_platelet(const PlateletSpec& p, const BeadSpringForceField& ff, const Vec& centre,
                          int mol) {
  md::System s;
  const double a = p.spacing_sigma * ff.sigma;
  const int n = p.beads_side, m = p.layers;
  const double h = 0.5 * (n - 1) * a, t = 0.5 * (m - 1) * a;
  auto id = [&](int i, int k, int j) { return (k * n + j) * n + i; }; // i: x1, j: x3, k: x2
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        s.x.push_back({centre[0] - h + i * a, centre[1] - t + k * a, centre[2] - h + j * a});
        s.type.push_back(2);
        s.mol.push_back(mol);
      }
  // edges (type 2, |d| = a) and face diagonals (type 3, |d| = a sqrt 2): every lattice vector
  // with components in {-1, 0, 1} and one or two of them non-zero, counted once (d > 0 first)
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int nz = (di != 0) + (dj != 0) + (dk != 0);
              if (nz == 0 || nz == 3) continue;
              // lexicographically positive displacements only (each pair once)
              const bool positive = dk > 0 || (dk == 0 && (dj > 0 || (dj == 0 && di > 0)));
              if (!positive) continue;
              const int i2 = i + di, j2 = j + dj, k2 = k + dk;
              if (i2 < 0 || i2 >= n || j2 < 0 || j2 >= n || k2 < 0 || k2 >= m) continue;
              s.bonds.push_back({nz == 1 ? 2 : 3, id(i, k, j), id(i2, k2, j2)});
            }
  return s;
}

md::System build_kg_platelet(const md::BuildSpec& spec, const BeadSpringForceField& ff,
                             const PlateletSpec& p, PlateletInfo* info) {
  spec.validate("<build>");
  ff.validate("<build>");
  p.validate("<build>");
  check_kg_platelet_box(spec, ff, p, "<build>");
  const double L = kg_platelet_box(spec, ff, p);
  md::System s = build_platelet(p, ff, {0.5 * L, 0.5 * L, 0.5 * L}, spec.chains + 1);
  s.hi = {L, L, L};
  s.type_mass = {ff.bead_mass, ff.bead_mass};
  s.bond_types = 3;
  s.angle_types = 0;
  s.dihedral_types = 0;
  const md::System plate = s;
  grow_bead_spring_chains(s, spec, ff, p.min_distance_sigma * ff.sigma);
  if (info) {
    const double a = p.spacing_sigma * ff.sigma;
    info->platelet_beads = static_cast<int>(plate.x.size());
    info->polymer_beads = static_cast<int>(s.x.size() - plate.x.size());
    info->platelet_bonds = static_cast<int>(plate.bonds.size());
    info->edge_A = (p.beads_side - 1) * a;
    info->thickness_A = (p.layers - 1) * a;
    info->box_A = L;
    info->volume_fraction =
        static_cast<double>(info->platelet_beads) / static_cast<double>(s.x.size());
    info->omega_bound_per_fs = platelet_omega_bound(plate, p, ff);
  }
  return s;
}

double platelet_omega_bound(const md::System& plate, const PlateletSpec& p,
                            const BeadSpringForceField& ff) {
  // K in kcal/mol/A^2; k = 2 K the bond's spring constant; m in g/mol; omega in 1/fs:
  // kcal/mol/A^2 / (g/mol) = 4184 J / (1e-3 kg) / 1e-20 m^2 = 4.184e26 s^-2 = 4.184e-4 fs^-2
  const double K = p.bond_K_reduced * ff.epsilon / (ff.sigma * ff.sigma);
  std::vector<Eigen::Matrix3d> blocks(plate.x.size(), Eigen::Matrix3d::Zero());
  for (const auto& b : plate.bonds) {
    Eigen::Vector3d e;
    for (int c = 0; c < 3; ++c)
      e[c] = plate.x[b[2]][c] - plate.x[b[1]][c];
    e.normalize();
    const Eigen::Matrix3d kee = 2.0 * K * e * e.transpose();
    blocks[b[1]] += kee;
    blocks[b[2]] += kee;
  }
  double lmax = 0;
  for (const auto& B : blocks)
    lmax = std::max(lmax, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(B).eigenvalues()[2]);
  // (kcal/mol/A^2)/(g/mol) in s^-2, times (1e-15 s/fs)^2
  constexpr double per_fs2 =
      units::joule_per_kcal_mol / units::m2_per_angstrom2 / units::kg_per_g_mol * 1e-30;
  return std::sqrt(2.0 * lmax / ff.bead_mass * per_fs2);
}

double min_polymer_platelet_distance(const md::System& s) {
  double best = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> plate;
  for (std::size_t i = 0; i < s.x.size(); ++i)
    if (s.type[i] == 2) plate.push_back(i);
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (s.type[i] != 1) continue;
    for (std::size_t j : plate) {
      const auto d = s.min_image(s.x[i], s.x[j]);
      best = std::min(best, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
  }
  return std::sqrt(best);
}

std::vector<std::string> kg_platelet_commands(const BeadSpringForceField& ff,
                                              const PlateletSpec& p) {
  const double a = p.spacing_sigma * ff.sigma;
  const double K = p.bond_K_reduced * ff.epsilon / (ff.sigma * ff.sigma);
  const double swp = p.sigma_wp_sigma * ff.sigma;
  return {
      fmt::format("pair_style lj/cut {:.10g}", ff.cutoff()),
      fmt::format("pair_coeff * * {:.12g} {:.12g}", ff.epsilon, ff.sigma),
      fmt::format("pair_coeff 1 2 {:.12g} {:.12g} {:.10g}", p.epsilon_wp_reduced * ff.epsilon, swp,
                  ff.cutoff_sigma * swp),
      "pair_modify shift no tail no",
      // decision D170: the platelet's shape is its bonds'; its own LJ pairs are not computed
      "neigh_modify exclude type 2 2",
      "bond_style hybrid fene harmonic",
      fmt::format("bond_coeff 1 fene {:.12g} {:.12g} {:.12g} {:.12g}", ff.fene_K(), ff.fene_R0(),
                  ff.epsilon, ff.sigma),
      fmt::format("bond_coeff 2 harmonic {:.12g} {:.12g}", K, a),
      fmt::format("bond_coeff 3 harmonic {:.12g} {:.12g}", K, a * std::sqrt(2.0)),
      "special_bonds lj 0.0 1.0 1.0",
  };
}

std::vector<std::string> kg_platelet_pushoff_pair(const BeadSpringForceField& ff,
                                                  const PlateletSpec& p, double soft_A) {
  const double swp = p.sigma_wp_sigma * ff.sigma;
  return {
      fmt::format("pair_style hybrid soft {:.10g} lj/cut {:.10g}",
                  std::pow(2.0, 1.0 / 6.0) * ff.sigma, ff.cutoff()),
      fmt::format("pair_coeff 1 1 soft {:.10g}", soft_A),
      fmt::format("pair_coeff 1 2 lj/cut {:.12g} {:.12g} {:.10g}",
                  p.epsilon_wp_reduced * ff.epsilon, swp, ff.cutoff_sigma * swp),
      "pair_coeff 2 2 none",
  };
}

void check_platelet_recipe(const Recipe& r, const std::string& source) {
  check_kg_platelet_box(r.build, r.kg, r.platelet, source);
  if (!(r.platelet.min_distance_sigma * r.kg.sigma >= r.build.min_distance))
    fail(source, "platelet.min_distance_sigma", fmt::format("{}", r.platelet.min_distance_sigma),
         fmt::format("must be >= build.min_distance / sigma = {:.3g} (the platelet excludes at "
                     "least what a polymer bead does)",
                     r.build.min_distance / r.kg.sigma));
  const double L = kg_platelet_box(r.build, r.kg, r.platelet);
  const double w = platelet_omega_bound(build_platelet(r.platelet, r.kg, {L / 2, L / 2, L / 2}, 1),
                                        r.platelet, r.kg);
  const std::pair<const char*, double> steps[] = {
      {"equilibrate.timestep_fs", r.equilibrate.timestep_fs},
      {"deform.timestep_fs", r.deform.timestep_fs}};
  for (const auto& [field, dt] : steps)
    if (w * dt > 1.0)
      fail(source, field, fmt::format("{}", dt),
           fmt::format("the platelet's bonds (bond_K_reduced {}) vibrate at up to {:.4g} / fs: "
                       "the timestep must be <= 1 / omega = {:.3g} fs (decision D173), or lower "
                       "platelet.bond_K_reduced",
                       r.platelet.bond_K_reduced, w, 1.0 / w));
}

nlohmann::json platelet_info_json(const PlateletInfo& i, const PlateletSpec& p,
                                  const BeadSpringForceField& ff, double min_pp) {
  return {{"platelet_beads", i.platelet_beads},
          {"polymer_beads", i.polymer_beads},
          {"platelet_bonds", i.platelet_bonds},
          {"beads_side", p.beads_side},
          {"layers", p.layers},
          {"edge_A", i.edge_A},
          {"thickness_A", i.thickness_A},
          {"box_A", i.box_A},
          {"edge_over_box", i.edge_A / i.box_A},
          {"bead_fraction", i.volume_fraction},
          {"epsilon_wp_kcal_mol", p.epsilon_wp_reduced * ff.epsilon},
          {"sigma_wp_A", p.sigma_wp_sigma * ff.sigma},
          {"bond_K_kcal_mol_A2", p.bond_K_reduced * ff.epsilon / (ff.sigma * ff.sigma)},
          {"omega_bound_per_fs", i.omega_bound_per_fs},
          {"min_polymer_platelet_distance_A", min_pp},
          {"definitions",
           "edge and thickness: bead-centre extents along x1 (= x3) and x2 at the build; "
           "bead_fraction: platelet beads / all beads; omega_bound: upper bound of the bond "
           "network's angular frequencies (platelet.hpp, decision D173)"}};
}

} // namespace pnc::rve
