// Montmorillonite platelet (Table 3.1, Tables 6.2-6.5) and the composite RVE (units real).
#include "pnc/rve/clay.hpp"

#include "pnc/core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace pnc::rve {

using Vec = std::array<double, 3>;

namespace {

constexpr double pi = 3.14159265358979323846;

bool is_oct_oxygen(const std::string& l) {
  return l == "O3" || l == "OH";
}
bool is_surface_oxygen(const std::string& l) {
  return l == "O1" || l == "O2";
}

double wrap01(double v) {
  v -= std::floor(v);
  return v >= 1.0 - 1e-12 ? 0.0 : v;
}

} // namespace

const std::vector<ClaySite>& clay_asymmetric_unit() {
  static const std::vector<ClaySite> au = {
      {"Al", {0.000, 0.333, 0.000}}, {"O1", {0.481, 0.500, 0.320}}, {"O2", {0.172, 0.728, 0.335}},
      {"O3", {0.348, 0.691, 0.110}}, {"OH", {0.419, 0.000, 0.105}}, {"H", {0.320, 0.000, 0.170}},
      {"Si", {0.417, 0.329, 0.270}}};
  return au;
}

std::vector<ClaySite> clay_unit_cell() {
  std::vector<ClaySite> out;
  for (const auto& s : clay_asymmetric_unit()) {
    const double x = s.frac[0], y = s.frac[1], z = s.frac[2];
    const Vec ops[4] = {{x, y, z}, {-x, y, -z}, {-x, -y, -z}, {x, -y, z}};
    for (const Vec& o : ops)
      for (double t : {0.0, 0.5}) {
        Vec f{wrap01(o[0] + t), wrap01(o[1] + t), o[2]};
        f[2] -= std::floor(f[2] + 0.5); // z in [-1/2, 1/2): one layer centred at z = 0
        bool dup = false;
        for (const auto& e : out) {
          if (e.label != s.label) continue;
          double d = 0;
          for (int k = 0; k < 3; ++k) {
            double dk = e.frac[k] - f[k];
            dk -= std::round(dk);
            d = std::max(d, std::fabs(dk));
          }
          if (d < 1e-3) dup = true;
        }
        if (!dup) out.push_back({s.label, f});
      }
  }
  return out;
}

std::array<double, 2> ClayForceField::lj(int ti, int tj, const md::PolymerForceField& pff) const {
  if (ti > tj) std::swap(ti, tj);
  if (ti == type_H || tj == type_H) return {1.0, 0.0};
  if (ti == type_C && tj == type_C) return {pff.sigma, pff.epsilon};
  if (ti == type_C && tj == type_Si) return C_Si;
  if (ti == type_C && tj == type_Al) return C_Al;
  if (ti == type_C && tj == type_O) return C_O;
  if (ti == type_Si && tj == type_Si) return Si_Si;
  if (ti == type_Si && tj == type_Al) return Si_Al;
  if (ti == type_Si && tj == type_O) return O_Si;
  if (ti == type_Al && tj == type_Al) return Al_Al;
  if (ti == type_Al && tj == type_O) return O_Al;
  return O_O;
}

double clay_type_mass(int type) {
  switch (type) {
  case type_Si:
    return 28.0855;
  case type_Al:
    return 26.9815385;
  case type_O:
    return 15.999;
  case type_H:
    return 1.008;
  default:
    fail("<clay>", "type", std::to_string(type), "is not a clay atom type (2..5)");
  }
}

double Platelet::mass() const {
  double m = 0;
  for (int t : type)
    m += clay_type_mass(t);
  return m;
}

Platelet build_platelet(int cells_a, int cells_b, bool periodic, const ClayLattice& lat) {
  if (cells_a < 1) fail("<clay>", "clay.cells_a", std::to_string(cells_a), "must be >= 1");
  if (cells_b < 1) fail("<clay>", "clay.cells_b", std::to_string(cells_b), "must be >= 1");
  const double beta = lat.beta_deg * pi / 180.0;
  const auto cell = clay_unit_cell();
  Platelet p;
  std::vector<Vec> X; // crystal frame
  for (int i = 0; i < cells_a; ++i)
    for (int j = 0; j < cells_b; ++j)
      for (const auto& s : cell) {
        const double xi = s.frac[0] + i, eta = s.frac[1] + j, zeta = s.frac[2];
        X.push_back({xi * lat.a + zeta * lat.c * std::cos(beta), eta * lat.b,
                     zeta * lat.c * std::sin(beta)});
        p.site.push_back(s.label);
        int t = type_O;
        if (s.label == "Si") t = type_Si;
        if (s.label == "Al") t = type_Al;
        if (s.label == "H") t = type_H;
        p.type.push_back(t);
      }
  const double PX = cells_a * lat.a, PY = cells_b * lat.b;
  auto sep2 = [&](int i, int j) {
    double dx = X[j][0] - X[i][0], dy = X[j][1] - X[i][1];
    const double dz = X[j][2] - X[i][2];
    if (periodic) {
      dx -= PX * std::round(dx / PX);
      dy -= PY * std::round(dy / PY);
    }
    return dx * dx + dy * dy + dz * dz;
  };
  const int n = static_cast<int>(X.size());
  // bonds by distance (decision D23)
  std::vector<std::array<int, 3>> bonds;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      const std::string &li = p.site[i], &lj = p.site[j];
      const double r2 = sep2(i, j);
      if (li == "Al" && is_oct_oxygen(lj) && r2 < 2.4 * 2.4) bonds.push_back({bond_Al_O1, i, j});
      if (li == "OH" && lj == "H" && r2 < 1.3 * 1.3) bonds.push_back({bond_O1_H, i, j});
      if (li == "Si" && is_surface_oxygen(lj) && r2 < 1.9 * 1.9)
        bonds.push_back({bond_Si_O2, i, j});
      if (li == "Si" && is_oct_oxygen(lj) && r2 < 1.9 * 1.9) bonds.push_back({bond_Si_O1, i, j});
    }
  // finite platelet: remove atoms without bonds (edge atoms whose partners were cut off)
  std::vector<int> nb(static_cast<std::size_t>(n), 0);
  for (const auto& b : bonds) {
    ++nb[b[1]];
    ++nb[b[2]];
  }
  std::vector<int> newidx(static_cast<std::size_t>(n), -1);
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (periodic || nb[i] > 0) newidx[i] = m++;
  p.removed_isolated = n - m;
  {
    std::vector<Vec> X2;
    std::vector<int> t2;
    std::vector<std::string> s2;
    for (int i = 0; i < n; ++i)
      if (newidx[i] >= 0) {
        X2.push_back(X[i]);
        t2.push_back(p.type[i]);
        s2.push_back(p.site[i]);
      }
    X.swap(X2);
    p.type.swap(t2);
    p.site.swap(s2);
  }
  for (auto& b : bonds)
    p.bonds.push_back({b[0], newidx[b[1]], newidx[b[2]]});
  // neighbour lists from the bonds
  std::vector<std::vector<int>> nbr(static_cast<std::size_t>(m));
  for (const auto& b : p.bonds) {
    nbr[b[1]].push_back(b[2]);
    nbr[b[2]].push_back(b[1]);
  }
  for (auto& v : nbr)
    std::sort(v.begin(), v.end());
  auto label = [&](int i) -> const std::string& { return p.site[i]; };
  auto cosang = [&](int i, int j, int k) {
    Vec u{}, w{};
    for (int a = 0; a < 3; ++a) {
      u[a] = X[i][a] - X[j][a];
      w[a] = X[k][a] - X[j][a];
      if (periodic && a < 2) {
        const double P = a == 0 ? PX : PY;
        u[a] -= P * std::round(u[a] / P);
        w[a] -= P * std::round(w[a] / P);
      }
    }
    return (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) /
           std::sqrt((u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) *
                     (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]));
  };
  // angles of Table 6.3 around each centre j (i < k for symmetric ones)
  for (int j = 0; j < m; ++j) {
    const auto& v = nbr[j];
    for (std::size_t a = 0; a < v.size(); ++a)
      for (std::size_t b = a + 1; b < v.size(); ++b) {
        int i = v[a], k = v[b];
        const std::string &lj = label(j), &li = label(i), &lk = label(k);
        if (is_oct_oxygen(lj)) {
          // Al-O1-H, Si-O1-Al, Al-O1-Al
          auto is = [&](int q, const char* l) { return label(q) == l; };
          if ((is(i, "Al") && is(k, "H")) || (is(i, "H") && is(k, "Al"))) {
            if (is(i, "H")) std::swap(i, k);
            p.angles.push_back({angle_Al_O1_H, i, j, k});
          } else if ((is(i, "Si") && is(k, "Al")) || (is(i, "Al") && is(k, "Si"))) {
            if (is(i, "Al")) std::swap(i, k);
            p.angles.push_back({angle_Si_O1_Al, i, j, k});
          } else if (is(i, "Al") && is(k, "Al")) {
            p.angles.push_back({angle_Al_O1_Al, i, j, k});
          }
        } else if (lj == "Si") {
          if (is_surface_oxygen(li) && is_oct_oxygen(lk))
            p.angles.push_back({angle_O2_Si_O1, i, j, k});
          else if (is_oct_oxygen(li) && is_surface_oxygen(lk))
            p.angles.push_back({angle_O2_Si_O1, k, j, i});
        } else if (lj == "Al") {
          if (is_oct_oxygen(li) && is_oct_oxygen(lk)) {
            const double deg = std::acos(std::clamp(cosang(i, j, k), -1.0, 1.0)) * 180 / pi;
            p.angles.push_back({deg < 135 ? angle_O1_Al_O1_90 : angle_O1_Al_O1_180, i, j, k});
          }
        }
      }
  }
  // torsions O2-Si-O1-Al
  for (const auto& b : p.bonds) {
    if (b[0] != bond_Si_O1) continue;
    const int si = b[1], o1 = b[2];
    for (int o2 : nbr[si])
      if (is_surface_oxygen(label(o2)))
        for (int al : nbr[o1])
          if (label(al) == "Al") p.dihedrals.push_back({dihedral_O2_Si_O1_Al, o2, si, o1, al});
  }
  // box frame: x1 = X, x3 = Y, x2 = -Z; centred at the origin (cell-based in-plane extent)
  double zmin = 1e300, zmax = -1e300;
  for (const auto& q : X) {
    zmin = std::min(zmin, q[2]);
    zmax = std::max(zmax, q[2]);
  }
  p.length = PX;
  p.width = PY;
  p.thickness = zmax - zmin;
  for (const auto& q : X)
    p.x.push_back({q[0] - 0.5 * PX, -(q[2] - 0.5 * (zmin + zmax)), q[1] - 0.5 * PY});
  return p;
}

void ClaySpec::validate(const std::string& source) const {
  if (cells_a < 1) fail(source, "clay.cells_a", std::to_string(cells_a), "must be >= 1");
  if (cells_b < 1) fail(source, "clay.cells_b", std::to_string(cells_b), "must be >= 1");
  if (cells_a * cells_b > 200)
    fail(source, "clay.cells_a", std::to_string(cells_a),
         "cells_a * cells_b must be <= 200 (a platelet of at most 5600 atoms)");
  if (!(aspect_ratio >= 0) || !std::isfinite(aspect_ratio))
    fail(source, "clay.aspect_ratio", fmt::format("{}", aspect_ratio),
         "must be >= 0 (0 = use cells_a)");
  if (!(min_distance > 0 && min_distance < 6))
    fail(source, "clay.min_distance", fmt::format("{}", min_distance), "must be in (0, 6) A");
  if (!(gap_x > 0 && gap_x < 200))
    fail(source, "clay.gap_x", fmt::format("{}", gap_x), "must be in (0, 200) A");
}

std::array<double, 3> composite_box(const md::BuildSpec& spec, const md::PolymerForceField& ff,
                                    const ClaySpec& clay, const std::string& source) {
  const ClayLattice lat;
  const double length = clay.cells_a * lat.a, width = clay.cells_b * lat.b;
  // thickness of the t-o-t layer (atom centres): from the unit cell
  double zmin = 1e300, zmax = -1e300;
  for (const auto& s : clay_unit_cell()) {
    zmin = std::min(zmin, s.frac[2]);
    zmax = std::max(zmax, s.frac[2]);
  }
  const double thick = (zmax - zmin) * lat.c * std::sin(lat.beta_deg * pi / 180);
  const double vpoly =
      spec.chains * spec.beads_per_chain * ff.bead_mass / (spec.density * md::avogadro_per_A3_cm3);
  const double Lx = length + clay.gap_x;
  const double Lyz = std::sqrt((vpoly + length * width * thick) / Lx);
  if (Lyz < width + clay.gap_x)
    fail(source, "clay.cells_b", std::to_string(clay.cells_b),
         fmt::format("the platelet width {:.2f} A plus gap_x {:.2f} A must fit in the box width "
                     "{:.2f} A (x3) at the build density; use fewer cells_b or more chains",
                     width, clay.gap_x, Lyz));
  if (Lyz < thick + 2 * clay.min_distance + 2 * ff.sigma)
    fail(source, "build.chains", std::to_string(spec.chains),
         fmt::format("the box ({:.2f} A along x2) is too thin for the platelet ({:.2f} A) and "
                     "a polymer layer; use more chains or a shorter platelet (clay.cells_a)",
                     Lyz, thick));
  return {Lx, Lyz, Lyz};
}

md::System build_composite(const md::BuildSpec& spec, const md::PolymerForceField& ff,
                           const ClaySpec& clay, CompositeInfo* info) {
  spec.validate("<build>");
  ff.validate("<build>");
  clay.validate("<build>");
  const auto L = composite_box(spec, ff, clay, "<build>");
  const Platelet p = build_platelet(clay.cells_a, clay.cells_b);
  md::System s;
  s.hi = L;
  s.type_mass = {ff.bead_mass, clay_type_mass(type_Si), clay_type_mass(type_Al),
                 clay_type_mass(type_O), clay_type_mass(type_H)};
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    s.x.push_back({p.x[i][0] + 0.5 * L[0], p.x[i][1] + 0.5 * L[1], p.x[i][2] + 0.5 * L[2]});
    s.type.push_back(p.type[i]);
    s.mol.push_back(spec.chains + 1);
  }
  md::grow_chains(s, spec, ff, clay.min_distance);
  s.bonds.insert(s.bonds.end(), p.bonds.begin(), p.bonds.end());
  s.angles.insert(s.angles.end(), p.angles.begin(), p.angles.end());
  s.dihedrals.insert(s.dihedrals.end(), p.dihedrals.begin(), p.dihedrals.end());
  s.bond_types = 5;
  s.angle_types = 7;
  s.dihedral_types = 2;
  if (info) {
    CompositeInfo& c = *info;
    c.clay_atoms = static_cast<int>(p.x.size());
    c.polymer_beads = spec.chains * spec.beads_per_chain;
    c.clay_mass = p.mass();
    c.polymer_mass = c.polymer_beads * ff.bead_mass;
    c.clay_volume = p.bounding_volume();
    c.box_volume = s.volume();
    c.volume_fraction = c.clay_volume / c.box_volume;
    c.weight_fraction = c.clay_mass / (c.clay_mass + c.polymer_mass);
    c.length = p.length;
    c.width = p.width;
    c.thickness = p.thickness;
    c.aspect_ratio = p.length / p.width;
  }
  return s;
}

double min_polymer_clay_distance(const md::System& s) {
  double best = 1e300;
  std::vector<std::size_t> clay;
  for (std::size_t i = 0; i < s.x.size(); ++i)
    if (s.type[i] != type_C) clay.push_back(i);
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (s.type[i] != type_C) continue;
    for (std::size_t j : clay) {
      const Vec d = s.min_image(s.x[i], s.x[j]);
      best = std::min(best, std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
  }
  return best;
}

std::vector<std::string> composite_forcefield_commands(const md::PolymerForceField& ff,
                                                       const ClayForceField& c) {
  std::vector<std::string> cmds;
  double rmax = ff.cutoff();
  for (int i = 1; i <= 5; ++i)
    for (int j = i; j <= 5; ++j)
      rmax = std::max(rmax, c.cutoff_sigma * c.lj(i, j, ff)[0]);
  cmds.push_back(fmt::format("pair_style lj/cut {:.10g}", rmax));
  for (int i = 1; i <= 5; ++i)
    for (int j = i; j <= 5; ++j) {
      const auto se = c.lj(i, j, ff);
      const double rc = (i == 1 && j == 1) ? ff.cutoff() : c.cutoff_sigma * se[0];
      cmds.push_back(
          fmt::format("pair_coeff {} {} {:.12g} {:.12g} {:.12g}", i, j, se[1], se[0], rc));
    }
  cmds.push_back("pair_modify shift no tail no");
  cmds.push_back("bond_style harmonic");
  cmds.push_back(fmt::format("bond_coeff 1 {:.12g} {:.12g}", ff.lammps_bond_K(), ff.l0));
  // Table 6.2: E = kl (l - l0)^2 as printed -> LAMMPS K = kl
  cmds.push_back(fmt::format("bond_coeff {} {:.12g} {:.12g}", bond_Al_O1, c.Al_O1[1], c.Al_O1[0]));
  cmds.push_back(fmt::format("bond_coeff {} {:.12g} {:.12g}", bond_O1_H, c.O1_H[1], c.O1_H[0]));
  cmds.push_back(fmt::format("bond_coeff {} {:.12g} {:.12g}", bond_Si_O2, c.Si_O2[1], c.Si_O2[0]));
  cmds.push_back(fmt::format("bond_coeff {} {:.12g} {:.12g}", bond_Si_O1, c.Si_O1[1], c.Si_O1[0]));
  cmds.push_back("angle_style cosine/squared");
  cmds.push_back(fmt::format("angle_coeff 1 {:.12g} {:.12g}", ff.lammps_angle_K(), ff.theta0_deg));
  const std::pair<int, std::array<double, 2>> ang[] = {
      {angle_Al_O1_H, c.Al_O1_H},         {angle_Si_O1_Al, c.Si_O1_Al},
      {angle_O2_Si_O1, c.O2_Si_O1},       {angle_Al_O1_Al, c.Al_O1_Al},
      {angle_O1_Al_O1_90, c.O1_Al_O1_90}, {angle_O1_Al_O1_180, c.O1_Al_O1_180}};
  for (const auto& [t, v] : ang) // E = k (cos t - cos t0)^2 as printed -> K = k
    cmds.push_back(fmt::format("angle_coeff {} {:.12g} {:.12g}", t, v[1], v[0]));
  const auto A = ff.lammps_dihedral_A();
  cmds.push_back("dihedral_style multi/harmonic");
  cmds.push_back(fmt::format("dihedral_coeff 1 {:.12g} {:.12g} {:.12g} {:.12g} {:.12g}", A[0], A[1],
                             A[2], A[3], A[4]));
  // V [1 + cos(0 phi - 0)] = 2V: constant, no force
  cmds.push_back(
      fmt::format("dihedral_coeff {} {:.12g} 0 0 0 0", dihedral_O2_Si_O1_Al, 2 * c.torsion_V));
  cmds.push_back("special_bonds lj 0.0 0.0 0.0");
  cmds.push_back("group pnc_poly type 1");
  cmds.push_back("group pnc_clay type 2 3 4 5");
  return cmds;
}

} // namespace pnc::rve
