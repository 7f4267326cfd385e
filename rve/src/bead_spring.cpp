// Glassy bead-spring polymer (model "kg"): force field, LAMMPS commands, builder (units real).
#include "pnc/rve/bead_spring.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/units.hpp"
#include "pnc/core/version.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace pnc::rve {

using Vec = std::array<double, 3>;

namespace {

constexpr double pi = 3.14159265358979323846;

double u01(std::mt19937_64& g) {
  return static_cast<double>(g() >> 11) * 0x1.0p-53;
}

/// Cell list over a cubic periodic box (edge L), cells at least `w_min` wide.
class Cells {
public:
  Cells(double L, double w_min) : L_(L) {
    n_ = std::max(1, static_cast<int>(std::floor(L / w_min)));
    w_ = L / n_;
    cells_.resize(static_cast<std::size_t>(n_) * n_ * n_);
  }
  int coord(double x) const {
    double u = std::fmod(x, L_);
    if (u < 0) u += L_;
    return std::min(n_ - 1, static_cast<int>(u / w_));
  }
  std::size_t index(int i, int j, int k) const {
    auto w = [&](int c) { return ((c % n_) + n_) % n_; };
    return (static_cast<std::size_t>(w(i)) * n_ + w(j)) * n_ + w(k);
  }
  std::size_t cell_of(const Vec& p) const { return index(coord(p[0]), coord(p[1]), coord(p[2])); }
  void insert(int i, const Vec& p) { cells_[cell_of(p)].push_back(i); }
  void erase(int i, const Vec& p) {
    auto& v = cells_[cell_of(p)];
    v.erase(std::find(v.begin(), v.end(), i));
  }
  /// Smallest squared minimum-image distance from p to a stored bead other than `skip`.
  double nearest2(const std::vector<Vec>& x, const Vec& p, int skip) const {
    double best = std::numeric_limits<double>::infinity();
    const int c[3] = {coord(p[0]), coord(p[1]), coord(p[2])};
    const int span = n_ >= 3 ? 1 : 0; // fewer than 3 cells: one cell holds all
    std::vector<std::size_t> seen;
    for (int dx = -span; dx <= span; ++dx)
      for (int dy = -span; dy <= span; ++dy)
        for (int dz = -span; dz <= span; ++dz) {
          const std::size_t k = index(c[0] + dx, c[1] + dy, c[2] + dz);
          if (std::find(seen.begin(), seen.end(), k) != seen.end()) continue;
          seen.push_back(k);
          for (int j : cells_[k]) {
            if (j == skip) continue;
            double r2 = 0;
            for (int a = 0; a < 3; ++a) {
              double d = x[j][a] - p[a];
              d -= L_ * std::round(d / L_);
              r2 += d * d;
            }
            best = std::min(best, r2);
          }
        }
    return best;
  }

private:
  double L_, w_;
  int n_;
  std::vector<std::vector<int>> cells_;
};

} // namespace

double BeadSpringForceField::tau_fs() const {
  const double m_kg = bead_mass * units::kg_per_g_mol;
  const double eps_j = epsilon * units::joule_per_kcal_mol;
  return sigma * 1e-10 * std::sqrt(m_kg / eps_j) * 1e15;
}

double BeadSpringForceField::stress_unit_pa() const {
  const double eps_j = epsilon * units::joule_per_kcal_mol;
  return eps_j / std::pow(sigma * 1e-10, 3);
}

double BeadSpringForceField::reduced_density(double g_cm3) const {
  return g_cm3 * md::avogadro_per_A3_cm3 / bead_mass * sigma * sigma * sigma;
}

void BeadSpringForceField::validate(const std::string& source) const {
  auto pos = [&](const char* name, double v) {
    if (!(v > 0.0) || !std::isfinite(v))
      fail(source, name, fmt::format("{}", v), "must be a finite number > 0");
  };
  pos("forcefield.sigma", sigma);
  pos("forcefield.epsilon", epsilon);
  pos("forcefield.bead_mass", bead_mass);
  pos("forcefield.fene_K_reduced", fene_K_reduced);
  pos("forcefield.fene_R0_sigma", fene_R0_sigma);
  pos("forcefield.bond_length_sigma", bond_length_sigma);
  if (!(cutoff_sigma >= std::pow(2.0, 1.0 / 6.0) && cutoff_sigma <= 5.0))
    fail(source, "forcefield.cutoff_sigma", fmt::format("{}", cutoff_sigma),
         "must be in [2^(1/6), 5] (2^(1/6): purely repulsive WCA; 2.5: a glass with cohesion)");
  if (!(fene_R0_sigma > 1.0 && fene_R0_sigma <= 3.0))
    fail(source, "forcefield.fene_R0_sigma", fmt::format("{}", fene_R0_sigma),
         "must be in (1, 3] sigma");
  if (!(bond_length_sigma >= 0.8 && bond_length_sigma < fene_R0_sigma))
    fail(source, "forcefield.bond_length_sigma", fmt::format("{}", bond_length_sigma),
         fmt::format("must be in [0.8, fene_R0_sigma = {}) sigma: a built bond must be shorter "
                     "than the FENE range R0",
                     fene_R0_sigma));
}

std::vector<std::string> bead_spring_commands(const BeadSpringForceField& ff) {
  // decision D136: FENE carries the bonded pair's WCA core, so the pair style skips 1-2 pairs
  return {
      fmt::format("pair_style lj/cut {:.10g}", ff.cutoff()),
      fmt::format("pair_coeff * * {:.12g} {:.12g}", ff.epsilon, ff.sigma),
      "pair_modify shift no tail no",
      "bond_style fene",
      fmt::format("bond_coeff 1 {:.12g} {:.12g} {:.12g} {:.12g}", ff.fene_K(), ff.fene_R0(),
                  ff.epsilon, ff.sigma),
      "special_bonds lj 0.0 1.0 1.0",
  };
}

double bead_spring_pair_energy(const BeadSpringForceField& ff, double r) {
  if (r >= ff.cutoff()) return 0.0;
  const double s6 = std::pow(ff.sigma / r, 6);
  return 4.0 * ff.epsilon * (s6 * s6 - s6);
}

double bead_spring_bond_energy(const BeadSpringForceField& ff, double r) {
  const double R0 = ff.fene_R0();
  if (r >= R0) return std::numeric_limits<double>::infinity();
  double e = -0.5 * ff.fene_K() * R0 * R0 * std::log(1.0 - (r / R0) * (r / R0));
  if (r < std::pow(2.0, 1.0 / 6.0) * ff.sigma) {
    const double s6 = std::pow(ff.sigma / r, 6);
    e += 4.0 * ff.epsilon * (s6 * s6 - s6) + ff.epsilon;
  }
  return e;
}

md::System build_bead_spring(const md::BuildSpec& spec, const BeadSpringForceField& ff) {
  spec.validate("<build>");
  ff.validate("<build>");
  md::System s;
  s.type_mass = {ff.bead_mass};
  s.bond_types = 1;
  s.angle_types = 0;
  s.dihedral_types = 0;
  const double V =
      spec.chains * spec.beads_per_chain * ff.bead_mass / (spec.density * md::avogadro_per_A3_cm3);
  const double L = std::cbrt(V);
  s.hi = {L, L, L};
  grow_bead_spring_chains(s, spec, ff, 0.0);
  return s;
}

void grow_bead_spring_chains(md::System& s, const md::BuildSpec& spec,
                             const BeadSpringForceField& ff, double obstacle_min_distance) {
  const double b = ff.bond_length();
  if (!(spec.min_distance < b))
    fail("<build>", "build.min_distance", fmt::format("{}", spec.min_distance),
         fmt::format("must be below the bond length {:.3f} A (0.97 sigma)", b));
  const int nb = spec.beads_per_chain;
  const double L = s.hi[0] - s.lo[0];
  Cells cells(L, spec.min_distance);
  // atoms already in the box (the platelet, platelet.hpp) are obstacles at their own distance
  const std::size_t n_obst = s.x.size();
  std::vector<Vec> obst(n_obst);
  for (std::size_t i = 0; i < n_obst; ++i)
    for (int a = 0; a < 3; ++a)
      obst[i][a] = s.x[i][a] - s.lo[a];
  // no obstacles: one cell (a cell list at a vanishing width would not fit in memory)
  Cells ocells(L, n_obst == 0 ? L : std::max(obstacle_min_distance, 1e-2 * L));
  for (std::size_t i = 0; i < n_obst; ++i)
    ocells.insert(static_cast<int>(i), obst[i]);
  const double o2 = obstacle_min_distance * obstacle_min_distance;
  // the chains' beads, positions relative to lo (indices into `x`, atom index - n_obst)
  std::vector<Vec> x;
  std::mt19937_64 g(spec.seed);
  const double d2 = spec.min_distance * spec.min_distance;
  int restarts = 0;
  for (int c = 0; c < spec.chains; ++c) {
    const int first = static_cast<int>(x.size());
    int placed = 0, failures = 0;
    while (placed < nb) {
      bool ok = false;
      Vec p{};
      for (int t = 0; t < spec.max_trials && !ok; ++t) {
        if (placed == 0) {
          p = {u01(g) * L, u01(g) * L, u01(g) * L};
        } else {
          const double z = 2.0 * u01(g) - 1.0, phi = 2.0 * pi * u01(g);
          const double rr = std::sqrt(std::max(0.0, 1.0 - z * z));
          const Vec& q = x[static_cast<std::size_t>(first + placed - 1)];
          p = {q[0] + b * rr * std::cos(phi), q[1] + b * rr * std::sin(phi), q[2] + b * z};
        }
        ok = cells.nearest2(x, p, placed == 0 ? -1 : first + placed - 1) >= d2 &&
             (n_obst == 0 || ocells.nearest2(obst, p, -1) >= o2);
      }
      if (ok) {
        x.push_back(p);
        cells.insert(first + placed, p);
        ++placed;
        continue;
      }
      // dead end: back up (the whole chain after max_chain_restarts / 10 local failures)
      ++failures;
      const int back = failures % 10 == 0 ? placed : std::min(placed, spec.backtrack);
      for (int k = 0; k < back; ++k) {
        const int i = first + placed - 1;
        cells.erase(i, x.back());
        x.pop_back();
        --placed;
      }
      if (placed == 0 && ++restarts > spec.max_chain_restarts)
        fail("<build>", "build.density", fmt::format("{}", spec.density),
             fmt::format("the random walk found no room for chain {} of {} after {} restarts "
                         "with min_distance {} A: lower the density or min_distance",
                         c + 1, spec.chains, spec.max_chain_restarts, spec.min_distance));
    }
  }
  for (int c = 0; c < spec.chains; ++c)
    for (int i = 0; i < nb; ++i) {
      const std::size_t k = static_cast<std::size_t>(c) * nb + i;
      s.x.push_back({x[k][0] + s.lo[0], x[k][1] + s.lo[1], x[k][2] + s.lo[2]});
      s.mol.push_back(c + 1);
      s.type.push_back(1);
      const int atom = static_cast<int>(n_obst + k);
      if (i + 1 < nb) s.bonds.push_back({1, atom, atom + 1});
    }
}

double min_unbonded_distance(const md::System& s) {
  const double L = s.hi[0] - s.lo[0];
  // cells of min(L/3, 10 A): distances below the cell width are exact, larger ones bounded below
  Cells cells(L, std::max(std::min(L / 3.0, 10.0), 1e-3));
  std::vector<Vec> x(s.x.size());
  for (std::size_t i = 0; i < s.x.size(); ++i)
    for (int a = 0; a < 3; ++a)
      x[i][a] = s.x[i][a] - s.lo[a];
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < x.size(); ++i) {
    // beads inserted so far that are not i's bonded predecessor (bonds join i-1, i in a chain)
    const int prev = (i > 0 && s.mol[i - 1] == s.mol[i]) ? static_cast<int>(i) - 1 : -1;
    best = std::min(best, cells.nearest2(x, x[i], prev));
    cells.insert(static_cast<int>(i), x[i]);
  }
  return std::sqrt(best);
}

void write_bead_spring_record(const std::string& path, const md::System& s,
                              const md::BuildSpec& spec, const BeadSpringForceField& ff,
                              const std::string& recipe_json) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    md::write_build_common(f, s, spec, recipe_json,
                           "random walk with excluded volume, fixed bond length, uniform "
                           "directions, cubic periodic box, mt19937_64");
    f.set_attr("/", "model", "kg (glassy bead-spring polymer)");
    f.write_scalar("/forcefield/sigma", ff.sigma);
    f.set_attr("/forcefield/sigma", "units", "A");
    f.write_scalar("/forcefield/epsilon", ff.epsilon);
    f.set_attr("/forcefield/epsilon", "units", "kcal/mol");
    f.write_scalar("/forcefield/bead_mass", ff.bead_mass);
    f.set_attr("/forcefield/bead_mass", "units", "g/mol");
    f.write_scalar("/forcefield/fene_K", ff.fene_K());
    f.set_attr("/forcefield/fene_K", "units", "kcal/mol/A^2");
    f.write_scalar("/forcefield/fene_R0", ff.fene_R0());
    f.set_attr("/forcefield/fene_R0", "units", "A");
    f.write_scalar("/forcefield/cutoff", ff.cutoff());
    f.set_attr("/forcefield/cutoff", "units", "A");
    f.write_scalar("/forcefield/temperature_unit", ff.temperature_unit());
    f.set_attr("/forcefield/temperature_unit", "units", "K (eps / k_B)");
    f.write_scalar("/forcefield/tau", ff.tau_fs());
    f.set_attr("/forcefield/tau", "units", "fs (sigma sqrt(m / eps))");
    f.write_scalar("/forcefield/stress_unit", ff.stress_unit_pa());
    f.set_attr("/forcefield/stress_unit", "units", "Pa (eps / sigma^3)");
    std::string cmds;
    for (const auto& c : bead_spring_commands(ff))
      cmds += c + "\n";
    f.write_string("/forcefield/lammps_commands", cmds);
    f.write_scalar("/result/reduced_density", ff.reduced_density(s.density()));
    f.set_attr("/result/reduced_density", "units", "sigma^-3");
    f.write_scalar("/result/min_unbonded_distance", min_unbonded_distance(s));
    f.set_attr("/result/min_unbonded_distance", "units", "A");
  }
  out.commit();
}

} // namespace pnc::rve
