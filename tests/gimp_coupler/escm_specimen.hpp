#pragma once
// The ESCM test specimen shared by test_escm.cpp and test_escm_validation.cpp: argon-like LJ
// (LAMMPS real units), a continuum of one particle per cell around an LJ FCC atom block.
// Units: continuum SI, MD LAMMPS real.
#include "pnc/gimp_coupler/escm.hpp"
#include "pnc/gimp_coupler/escm_lj.hpp"

#include <memory>

namespace escm_test {

using namespace pnc::gimp;
using namespace pnc::gimp::escm;

// Argon-like LJ (real units).
inline constexpr double kEps = 0.2381, kSig = 3.405, kMass = 39.948;
inline const double kRc = 2.5 * kSig;

/// Specimen of ncx x ncy cells (size h = a0, one particle per cell) with the atom block of
/// bnx x bny cells at cell (bx0, by0) and nz unit cells in z.
struct Spec {
  int ncx = 20, ncy = 12, bx0 = 6, by0 = 2, bnx = 8, bny = 8, nz = 3, svc_rings = 1;
  bool pair_zero = false;
};

inline double h_of(const LjFcc& lj) {
  return lj.a0_A * units::m_per_A;
}

inline void build_continuum(Solver<2>& s, const Spec& sp, const LjFcc& lj) {
  const double h = h_of(lj);
  s.grid.h = h;
  s.grid.origin = Eigen::Vector2d(-2 * h, -2 * h);
  s.grid.n = {sp.ncx + 5, sp.ncy + 5};
  s.materials.push_back(std::make_shared<LinearElastic>(lj.density, lj.E(), lj.nu()));
  for (int j = 0; j < sp.ncy; ++j)
    for (int i = 0; i < sp.ncx; ++i)
      s.particles.add(Eigen::Vector2d((i + 0.5) * h, (j + 0.5) * h),
                      Eigen::Vector2d::Constant(0.5 * h), lj.density * h * h, h * h, 0);
}

inline Config md_config(const Spec& sp, const LjFcc& lj) {
  const double h = h_of(lj);
  Config c;
  c.md_setup = lj_fcc_block_commands(lj, sp.bnx, sp.bny, sp.nz, kMass, kEps, kSig, kRc);
  if (sp.pair_zero) { // no forces: the last two commands (pair_style, pair_coeff) replaced
    c.md_setup.resize(c.md_setup.size() - 2);
    c.md_setup.push_back("pair_style zero 6.0");
    c.md_setup.push_back("pair_coeff * *");
  }
  // LAMMPS site (i + b) a0 lies in continuum cell bx0 + i: origin shifted by a0/4.
  c.md_offset = Eigen::Vector2d(sp.bx0 * h + 0.25 * h, sp.by0 * h + 0.25 * h);
  return c;
}

} // namespace escm_test
