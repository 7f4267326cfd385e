// ESCM Cases II and III: the continuum edge pre-crack and the atomistic separation across its
// line (escm_crack.hpp, docs/escm.md, decisions D80-D84).
#include "pnc/gimp_coupler/escm_crack.hpp"

#include <algorithm>
#include <cmath>

namespace pnc::gimp::escm {

Crack line_edge_crack(double y_line, double x_tip, double h, double Gc, int max_increments) {
  Crack c;
  c.name = "precrack";
  c.points = {Eigen::Vector2d(-h, y_line), Eigen::Vector2d(x_tip, y_line)};
  c.tip = {0, 1}; // the mouth lies outside the body
  c.growth.Gc = Gc;
  c.growth.increment = h;
  c.growth.prescribed = true; // D80: the crack follows the line through the block centre
  c.growth.direction = Eigen::Vector2d::UnitX();
  c.growth.max_increments = max_increments; // D81: stop before the SVC ring
  return c;
}

double lj_inflection(double sigma_A) {
  return std::pow(26.0 / 7.0, 1.0 / 6.0) * sigma_A;
}

BondMonitor::BondMonitor(const Coupler& cp, double y_line_A, double x_entry_A, double cell_A,
                         double r_bond_A, double r_break_A, double slip_A)
    : x0_(cp.atoms_initial()), Lz_(cp.slab_thickness_A()), r_break_(r_break_A), cell_(cell_A),
      slip_(slip_A) {
  const int n = static_cast<int>(x0_.size());
  auto is_free = [&](int i) {
    const Zone z = cp.zone_of(i + 1);
    return z == Zone::ivc || z == Zone::interior;
  };
  auto column = [&](const Eigen::Vector3d& x) {
    return static_cast<int>(std::floor((x[0] - x_entry_A) / cell_A));
  };
  std::vector<int> near; // free atoms within r_bond of the line
  for (int i = 0; i < n; ++i) {
    if (!is_free(i)) continue;
    const double dy = x0_[static_cast<std::size_t>(i)][1] - y_line_A;
    if (std::abs(dy) < r_bond_A) near.push_back(i);
    if (std::abs(dy) < 0.5 * cell_A) {
      row_atom_.push_back(i);
      row_side_.push_back(dy > 0 ? 1 : -1);
      row_column_.push_back(column(x0_[static_cast<std::size_t>(i)]));
    }
  }
  for (int c : row_column_)
    columns_ = std::max(columns_, c + 1);
  for (std::size_t p = 0; p < near.size(); ++p)
    for (std::size_t q = p + 1; q < near.size(); ++q) {
      const Eigen::Vector3d& a = x0_[static_cast<std::size_t>(near[p])];
      const Eigen::Vector3d& b = x0_[static_cast<std::size_t>(near[q])];
      if ((a[1] - y_line_A) * (b[1] - y_line_A) >= 0) continue; // same side
      Eigen::Vector3d d = b - a;
      d[2] -= Lz_ * std::round(d[2] / Lz_);
      if (d.norm() >= r_bond_A) continue;
      bonds_.push_back({near[p], near[q], column(0.5 * (a + b))});
    }
}

AtomisticCrack BondMonitor::measure(const std::vector<Eigen::Vector3d>& x) const {
  AtomisticCrack r;
  r.columns = columns_;
  r.bonds = static_cast<int>(bonds_.size());
  const auto nc = static_cast<std::size_t>(std::max(columns_, 1));
  std::vector<int> total(nc, 0), broken(nc, 0);
  for (const Bond& b : bonds_) {
    Eigen::Vector3d d = x[static_cast<std::size_t>(b.b)] - x[static_cast<std::size_t>(b.a)];
    d[2] -= Lz_ * std::round(d[2] / Lz_);
    const auto c = static_cast<std::size_t>(std::clamp(b.column, 0, columns_ - 1));
    ++total[c];
    if (d.norm() > r_break_) {
      ++broken[c];
      ++r.broken;
    }
  }
  for (std::size_t c = 0; c < nc && total[c] > 0 && 2 * broken[c] >= total[c]; ++c)
    ++r.separated_columns;
  r.length_A = r.separated_columns * cell_;
  // Opening and sliding of the two atom rows next to the line, per column.
  std::vector<Eigen::Vector2d> up(nc, Eigen::Vector2d::Zero()), lo(nc, Eigen::Vector2d::Zero());
  std::vector<int> nup(nc, 0), nlo(nc, 0);
  for (std::size_t k = 0; k < row_atom_.size(); ++k) {
    const auto i = static_cast<std::size_t>(row_atom_[k]);
    const auto c = static_cast<std::size_t>(std::clamp(row_column_[k], 0, columns_ - 1));
    const Eigen::Vector2d u = (x[i] - x0_[i]).head<2>();
    if (row_side_[k] > 0) {
      up[c] += u;
      ++nup[c];
    } else {
      lo[c] += u;
      ++nlo[c];
    }
  }
  bool slipping = slip_ > 0; // D91: contiguous slipped columns from the entry side
  for (std::size_t c = 0; c < nc; ++c) {
    if (nup[c] == 0 || nlo[c] == 0) {
      slipping = false;
      continue;
    }
    const Eigen::Vector2d jump = up[c] / nup[c] - lo[c] / nlo[c];
    if (c == 0) {
      r.entry_opening_A = jump[1];
      r.entry_sliding_A = jump[0];
    }
    r.max_opening_A = std::max(r.max_opening_A, jump[1]);
    r.max_abs_sliding_A = std::max(r.max_abs_sliding_A, std::abs(jump[0]));
    slipping = slipping && std::abs(jump[0]) >= slip_;
    if (slipping) ++r.slipped_columns;
  }
  return r;
}

} // namespace pnc::gimp::escm
