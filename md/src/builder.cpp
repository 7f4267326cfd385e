// Self-avoiding random-walk builder of the coarse-grained polypropylene RVE (units real).
#include "pnc/md/builder.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/version.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

namespace pnc::md {

using Vec = std::array<double, 3>;

namespace {

constexpr double pi = 3.14159265358979323846;

double u01(std::mt19937_64& g) {
  return static_cast<double>(g() >> 11) * 0x1.0p-53;
}

Vec add(const Vec& a, const Vec& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec scale(const Vec& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec normalized(const Vec& a) {
  return scale(a, 1.0 / std::sqrt(dot(a, a)));
}

Vec random_unit(std::mt19937_64& g) {
  const double z = 2.0 * u01(g) - 1.0, phi = 2.0 * pi * u01(g);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Cell list on an orthogonal periodic box for "any bead within d of p" queries.
class CellList {
public:
  CellList(const System& s, double cell_min) : s_(s) {
    const Vec L = s.length();
    for (int a = 0; a < 3; ++a) {
      n_[a] = std::max(1, static_cast<int>(std::floor(L[a] / cell_min)));
      w_[a] = L[a] / n_[a];
    }
    cells_.resize(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]);
  }
  std::size_t cell_of(const Vec& p) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a)
      c[a] = coord(p, a);
    return index(c);
  }
  void insert(int i) { cells_[cell_of(s_.x[i])].push_back(i); }
  void erase(int i) {
    auto& v = cells_[cell_of(s_.x[i])];
    v.erase(std::find(v.begin(), v.end(), i));
  }
  /// Calls f(j, r2) for every stored bead j in the 27 (or fewer, deduplicated) cells around p.
  template <class F> void around(const Vec& p, F&& f) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a)
      c[a] = coord(p, a);
    std::vector<std::size_t> seen;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const std::size_t k = index({c[0] + dx, c[1] + dy, c[2] + dz});
          if (std::find(seen.begin(), seen.end(), k) != seen.end()) continue;
          seen.push_back(k);
          for (int j : cells_[k]) {
            const Vec d = s_.min_image(p, s_.x[j]);
            f(j, dot(d, d));
          }
        }
  }

private:
  int coord(const Vec& p, int a) const {
    const double L = s_.hi[a] - s_.lo[a];
    double u = std::fmod(p[a] - s_.lo[a], L);
    if (u < 0) u += L;
    return std::min(n_[a] - 1, static_cast<int>(u / w_[a]));
  }
  std::size_t index(std::array<int, 3> c) const {
    for (int a = 0; a < 3; ++a)
      c[a] = ((c[a] % n_[a]) + n_[a]) % n_[a];
    return (static_cast<std::size_t>(c[0]) * n_[1] + c[1]) * n_[2] + c[2];
  }
  const System& s_;
  std::array<int, 3> n_{};
  Vec w_{};
  std::vector<std::vector<int>> cells_;
};

} // namespace

void BuildSpec::validate(const std::string& source) const {
  if (chains < 1 || chains > 100000)
    fail(source, "build.chains", std::to_string(chains), "must be in 1..100000");
  if (beads_per_chain < 4 || beads_per_chain > 10000)
    fail(source, "build.beads_per_chain", std::to_string(beads_per_chain),
         "must be in 4..10000 (a torsion needs 4 beads)");
  // Memory and LAMMPS time grow with the bead count: 1e6 beads is ~700 times the paper's RVE.
  if (static_cast<long long>(chains) * beads_per_chain > 1000000)
    fail(source, "build.chains", std::to_string(chains),
         "chains x beads_per_chain = " +
             std::to_string(static_cast<long long>(chains) * beads_per_chain) +
             " beads: at most 1000000 in one RVE");
  if (!(density > 0.05 && density < 3.0))
    fail(source, "build.density", fmt::format("{}", density), "must be in (0.05, 3) g/cm^3");
  if (!(min_distance > 0.0 && min_distance < 4.0))
    fail(source, "build.min_distance", fmt::format("{}", min_distance), "must be in (0, 4) A");
  if (max_trials < 1) fail(source, "build.max_trials", std::to_string(max_trials), "must be >= 1");
}

double System::volume() const {
  const Vec L = length();
  return L[0] * L[1] * L[2];
}

double System::mass() const {
  double m = 0;
  for (int t : type)
    m += type_mass[t - 1];
  return m;
}

Vec System::min_image(const Vec& a, const Vec& b) const {
  Vec d{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  for (int k = 0; k < 3; ++k) {
    const double L = hi[k] - lo[k];
    d[k] -= L * std::round(d[k] / L);
  }
  return d;
}

System build_polymer(const BuildSpec& spec, const PolymerForceField& ff) {
  spec.validate("<build>");
  ff.validate("<build>");
  System s;
  s.type_mass = {ff.bead_mass};
  const double V =
      spec.chains * spec.beads_per_chain * ff.bead_mass / (spec.density * avogadro_per_A3_cm3);
  const double L = std::cbrt(V);
  s.hi = {L, L, L};
  grow_chains(s, spec, ff, spec.min_distance);
  return s;
}

void grow_chains(System& s, const BuildSpec& spec, const PolymerForceField& ff,
                 double obstacle_min_distance) {
  const int N = spec.beads_per_chain;
  const int n0 = static_cast<int>(s.x.size()); // obstacles (clay atoms) already in s
  const int total = spec.chains * N;
  const Vec Lb = s.length();
  s.x.reserve(static_cast<std::size_t>(n0 + total));
  CellList cells(s, std::max(spec.min_distance, obstacle_min_distance));
  for (int i = 0; i < n0; ++i)
    cells.insert(i);
  std::mt19937_64 gen(spec.seed);
  const double d2min = spec.min_distance * spec.min_distance;
  const double d2obs = obstacle_min_distance * obstacle_min_distance;
  const double ct = std::cos(pi - ff.theta0_deg * pi / 180.0);
  const double st = std::sin(pi - ff.theta0_deg * pi / 180.0);

  for (int c = 0; c < spec.chains; ++c) {
    const int first = n0 + c * N;
    auto ok = [&](const Vec& p, int b) {
      bool good = true;
      cells.around(p, [&](int j, double r2) {
        if (!good) return;
        if (j < n0) {
          if (r2 < d2obs) good = false;
          return;
        }
        if (r2 >= d2min) return;
        if (j >= first && b - (j - first) <= 2) return; // own 1-2 / 1-3 neighbour
        good = false;
      });
      return good;
    };
    int failures = 0;
    int b = 0;
    while (b < N) {
      Vec p{};
      bool placed = false;
      for (int t = 0; t < spec.max_trials && !placed; ++t) {
        if (b == 0) {
          p = {s.lo[0] + u01(gen) * Lb[0], s.lo[1] + u01(gen) * Lb[1], s.lo[2] + u01(gen) * Lb[2]};
        } else if (b == 1) {
          p = add(s.x[first], scale(random_unit(gen), ff.l0));
        } else {
          const Vec u = normalized({s.x[first + b - 1][0] - s.x[first + b - 2][0],
                                    s.x[first + b - 1][1] - s.x[first + b - 2][1],
                                    s.x[first + b - 1][2] - s.x[first + b - 2][2]});
          Vec a = std::fabs(u[0]) < 0.9 ? Vec{1, 0, 0} : Vec{0, 1, 0};
          const Vec e1 = normalized(cross(u, a));
          const Vec e2 = cross(u, e1);
          const double phi = 2.0 * pi * u01(gen);
          const Vec v =
              add(scale(u, ct), scale(add(scale(e1, std::cos(phi)), scale(e2, std::sin(phi))), st));
          p = add(s.x[first + b - 1], scale(v, ff.l0));
        }
        placed = ok(p, b);
      }
      if (placed) {
        s.x.push_back(p);
        s.mol.push_back(c + 1);
        s.type.push_back(1);
        cells.insert(first + b);
        ++b;
        continue;
      }
      if (++failures > spec.max_chain_restarts)
        fail("<build>", "build.density", fmt::format("{}", spec.density),
             fmt::format("chain {} could not be grown without beads closer than min_distance "
                         "= {} A; lower the density or min_distance",
                         c + 1, spec.min_distance));
      const int back = (b <= spec.backtrack) ? b : spec.backtrack;
      for (int k = 0; k < back; ++k) {
        cells.erase(first + b - 1);
        s.x.pop_back();
        s.mol.pop_back();
        s.type.pop_back();
        --b;
      }
    }
    for (int i = 0; i + 1 < N; ++i)
      s.bonds.push_back({1, first + i, first + i + 1});
    for (int i = 0; i + 2 < N; ++i)
      s.angles.push_back({1, first + i, first + i + 1, first + i + 2});
    for (int i = 0; i + 3 < N; ++i)
      s.dihedrals.push_back({1, first + i, first + i + 1, first + i + 2, first + i + 3});
  }
}

double min_nonbonded_distance(const System& s) {
  const double search = 5.0;
  CellList cells(s, search);
  double best2 = search * search;
  // chain position index within its molecule, assuming consecutive numbering per molecule
  std::vector<int> pos(s.x.size(), 0);
  for (std::size_t i = 1; i < s.x.size(); ++i)
    pos[i] = (s.mol[i] != 0 && s.mol[i] == s.mol[i - 1]) ? pos[i - 1] + 1 : 0;
  // exclude 1-2 and 1-3 bonded neighbours (same molecule, index distance <= 2 along the chain)
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    cells.around(s.x[i], [&](int j, double r2) {
      if (static_cast<std::size_t>(j) >= i) return;
      if (s.type[i] != 1 && s.type[j] != 1) return; // clay-clay pairs: not beads
      if (s.mol[i] != 0 && s.mol[i] == s.mol[j] && std::abs(pos[i] - pos[j]) <= 2) return;
      best2 = std::min(best2, r2);
    });
    cells.insert(static_cast<int>(i));
  }
  return std::sqrt(best2);
}

void write_data_file(const std::string& path, const System& s, const std::string& title) {
  // the title is the data file's first line: a newline in it would start the header early
  for (const char c : title)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      fail(path, "title", title,
           "the data-file title must be one line of printable characters (no control character)");
  AtomicOutput out(path);
  {
    std::ofstream f(out.temp_path());
    if (!f) fail(path, "", "", "cannot open for writing");
    const bool charged = !s.charge.empty();
    f << "LAMMPS data file: " << title << " (pnc " << version() << ", units real)\n\n";
    f << s.x.size() << " atoms\n"
      << s.bonds.size() << " bonds\n"
      << s.angles.size() << " angles\n"
      << s.dihedrals.size() << " dihedrals\n\n";
    f << s.type_mass.size() << " atom types\n"
      << s.bond_types << " bond types\n"
      << s.angle_types << " angle types\n"
      << s.dihedral_types << " dihedral types\n\n";
    f << fmt::format("{:.12g} {:.12g} xlo xhi\n{:.12g} {:.12g} ylo yhi\n{:.12g} {:.12g} zlo zhi\n",
                     s.lo[0], s.hi[0], s.lo[1], s.hi[1], s.lo[2], s.hi[2]);
    if (s.xy != 0 || s.xz != 0 || s.yz != 0)
      f << fmt::format("{:.12g} {:.12g} {:.12g} xy xz yz\n", s.xy, s.xz, s.yz);
    f << "\nMasses\n\n";
    for (std::size_t t = 0; t < s.type_mass.size(); ++t)
      f << fmt::format("{} {:.12g}\n", t + 1, s.type_mass[t]);
    f << "\nAtoms # " << (charged ? "full" : "molecular") << "\n\n";
    const Vec L = s.length();
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      Vec w{};
      std::array<long, 3> img{};
      for (int a = 0; a < 3; ++a) {
        img[a] = static_cast<long>(std::floor((s.x[i][a] - s.lo[a]) / L[a]));
        w[a] = s.x[i][a] - static_cast<double>(img[a]) * L[a];
        if (w[a] >= s.hi[a]) {
          w[a] -= L[a];
          ++img[a];
        } // rounding at the upper face
      }
      if (charged)
        f << fmt::format("{} {} {} {:.10g} {:.12g} {:.12g} {:.12g} {} {} {}\n", i + 1, s.mol[i],
                         s.type[i], s.charge[i], w[0], w[1], w[2], img[0], img[1], img[2]);
      else
        f << fmt::format("{} {} {} {:.12g} {:.12g} {:.12g} {} {} {}\n", i + 1, s.mol[i], s.type[i],
                         w[0], w[1], w[2], img[0], img[1], img[2]);
    }
    if (!s.bonds.empty()) {
      f << "\nBonds\n\n";
      for (std::size_t k = 0; k < s.bonds.size(); ++k)
        f << fmt::format("{} {} {} {}\n", k + 1, s.bonds[k][0], s.bonds[k][1] + 1,
                         s.bonds[k][2] + 1);
    }
    if (!s.angles.empty()) {
      f << "\nAngles\n\n";
      for (std::size_t k = 0; k < s.angles.size(); ++k)
        f << fmt::format("{} {} {} {} {}\n", k + 1, s.angles[k][0], s.angles[k][1] + 1,
                         s.angles[k][2] + 1, s.angles[k][3] + 1);
    }
    if (!s.dihedrals.empty()) {
      f << "\nDihedrals\n\n";
      for (std::size_t k = 0; k < s.dihedrals.size(); ++k)
        f << fmt::format("{} {} {} {} {} {}\n", k + 1, s.dihedrals[k][0], s.dihedrals[k][1] + 1,
                         s.dihedrals[k][2] + 1, s.dihedrals[k][3] + 1, s.dihedrals[k][4] + 1);
    }
    f.close();
    if (!f) fail(path, "", "", "write failed (disk full?)");
  }
  out.commit();
}

void write_build_common(h5::File& f, const System& s, const BuildSpec& spec,
                        const std::string& recipe_json, const std::string& method) {
  h5::write_provenance(f);
  f.set_attr("/", "format", "pnc-rve-build");
  f.set_attr("/", "units", "LAMMPS real: A, g/mol, kcal/mol; density g/cm^3");
  f.write_string("/recipe", recipe_json);
  f.write_scalar("/spec/chains", spec.chains);
  f.write_scalar("/spec/beads_per_chain", spec.beads_per_chain);
  f.write_scalar("/spec/density", spec.density);
  f.set_attr("/spec/density", "units", "g/cm^3");
  f.write_string("/spec/seed", std::to_string(spec.seed));
  f.write_scalar("/spec/min_distance", spec.min_distance);
  f.set_attr("/spec/min_distance", "units", "A");
  f.write_string("/spec/method", method);
  f.write_scalar("/result/atoms", s.x.size());
  f.write_scalar("/result/bonds", s.bonds.size());
  f.write_scalar("/result/density", s.density());
  f.set_attr("/result/density", "units", "g/cm^3");
  f.write_vector("/result/box",
                 {s.lo[0], s.lo[1], s.lo[2], s.hi[0], s.hi[1], s.hi[2], s.xy, s.xz, s.yz});
  f.set_attr("/result/box", "units", "A (xlo ylo zlo xhi yhi zhi xy xz yz)");
  h5::RowMatrix X(static_cast<Eigen::Index>(s.x.size()), 3);
  for (std::size_t i = 0; i < s.x.size(); ++i)
    for (int a = 0; a < 3; ++a)
      X(static_cast<Eigen::Index>(i), a) = s.x[i][a];
  f.write_matrix("/result/positions", X);
  f.set_attr("/result/positions", "units", "A (unwrapped)");
}

void write_build_record(const std::string& path, const System& s, const BuildSpec& spec,
                        const PolymerForceField& ff, const std::string& recipe_json) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    write_build_common(f, s, spec, recipe_json,
                       "self-avoiding random walk, fixed l0 and theta0, uniform torsion, periodic "
                       "orthogonal box (cubic without clay), mt19937_64");
    f.write_scalar("/forcefield/bead_mass", ff.bead_mass);
    f.write_scalar("/forcefield/k_l", ff.k_l);
    f.set_attr("/forcefield/k_l", "units", "kcal/mol/A^2");
    f.write_scalar("/forcefield/l0", ff.l0);
    f.write_scalar("/forcefield/k_theta", ff.k_theta);
    f.set_attr("/forcefield/k_theta", "units", "kcal/mol");
    f.write_scalar("/forcefield/theta0_deg", ff.theta0_deg);
    f.write_vector("/forcefield/C", {ff.C.begin(), ff.C.end()});
    f.set_attr("/forcefield/C", "units", "kcal/mol");
    f.write_scalar("/forcefield/epsilon", ff.epsilon);
    f.set_attr("/forcefield/epsilon", "units", "kcal/mol");
    f.write_scalar("/forcefield/sigma", ff.sigma);
    f.write_scalar("/forcefield/cutoff", ff.cutoff());
    std::string cmds;
    for (const auto& c : polymer_forcefield_commands(ff))
      cmds += c + "\n";
    f.write_string("/forcefield/lammps_commands", cmds);
    f.write_scalar("/result/angles", s.angles.size());
    f.write_scalar("/result/dihedrals", s.dihedrals.size());
    f.write_scalar("/result/min_nonbonded_distance", min_nonbonded_distance(s));
    f.set_attr("/result/min_nonbonded_distance", "units", "A");
    f.write_integers("/result/molecule", {s.mol.begin(), s.mol.end()});
    f.write_integers("/result/type", {s.type.begin(), s.type.end()});
  }
  out.commit();
}

} // namespace pnc::md
