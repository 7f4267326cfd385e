// escm_tension: Case I analogue of the source's ESCM cases (docs/escm.md; simple tension with the
// MD region at the centre), with an LJ FCC crystal as the MD region and the continuum calibrated to
// it (docs/escm.md; the polymer MD region of the dissertation is not done).
//
//   escm_tension OUTDIR [--short]
//
// Specimen 40 x 20 cells (h = a0 = 5.28 A), MD block 14 x 14 cells at the centre (2 SVC + 1
// IVC rings, INT 8 x 8 cells), slab 3 a0; left edge x-fixed, right edge pulled to 1 % strain
// over 40 ps (short: 0.5 % over 10 ps), then held; 0 K, damped (0.7 critical).
// Writes OUTDIR/energy.csv (formats.md "ESCM energy log"), OUTDIR/atoms_<k>.vtu,
// OUTDIR/profile.csv (time, x_m, ux_m, source: continuum particle or MD cell, along the
// middle row of the block) and, if /usr/bin/python3 has matplotlib, profile.png, energy.png
// (scripts/plot_escm.py).
#include "pnc/gimp_coupler/escm.hpp"
#include "pnc/gimp_coupler/escm_lj.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/plot.hpp"
#include "pnc/core/progress.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

using namespace pnc::gimp;
using namespace pnc::gimp::escm;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: escm_tension OUTDIR [--short]\n");
    return 1;
  }
  const std::string out = argv[1];
  const bool quick = argc > 2 && std::string(argv[2]) == "--short";
  pnc::make_output_directory(out, "OUT");
  const double eps = 0.2381, sig = 3.405, mass = 39.948, rc = 2.5 * sig;
  const LjFcc lj = lj_fcc(eps, sig, rc, mass);
  const double h = lj.a0_A * units::m_per_A;
  const int ncx = quick ? 30 : 40, ncy = quick ? 16 : 20, nb = quick ? 10 : 14, nz = 3;
  const int bx0 = (ncx - nb) / 2, by0 = (ncy - nb) / 2;
  Solver<2> s;
  s.grid.h = h;
  s.grid.origin = Eigen::Vector2d(-2 * h, -2 * h);
  s.grid.n = {ncx + 5, ncy + 5};
  s.materials.push_back(std::make_shared<LinearElastic>(lj.density, lj.E(), lj.nu()));
  for (int j = 0; j < ncy; ++j)
    for (int i = 0; i < ncx; ++i)
      s.particles.add(Eigen::Vector2d((i + 0.5) * h, (j + 0.5) * h),
                      Eigen::Vector2d::Constant(0.5 * h), lj.density * h * h, h * h, 0);
  NodeBC<2> left, corner, right;
  left.lo = Eigen::Vector2d(-0.1 * h, -10 * h);
  left.hi = Eigen::Vector2d(0.1 * h, 100 * h);
  left.mask = {true, false};
  corner.lo = Eigen::Vector2d(-0.1 * h, -0.1 * h);
  corner.hi = Eigen::Vector2d(0.1 * h, 0.1 * h);
  corner.mask = {false, true};
  right.lo = Eigen::Vector2d((ncx - 0.1) * h, -10 * h);
  right.hi = Eigen::Vector2d((ncx + 1.1) * h, 100 * h); // incl. the padding column (D77)
  right.mask = {true, false};
  s.bcs = {left, corner, right};
  const double strain = quick ? 5e-3 : 1e-2, t_load = quick ? 10e-12 : 40e-12;
  const double t_settle = quick ? 4e-12 : 10e-12, t_hold = quick ? 10e-12 : 30e-12;
  const double L = ncx * h;
  const double omega1 = M_PI * std::sqrt(lj.strip_modulus() / lj.density) / L;
  const double damping = 2 * 0.7 * omega1;
  Config c;
  c.md_setup = lj_fcc_block_commands(lj, nb, nb, nz, mass, eps, sig, rc);
  c.md_offset = Eigen::Vector2d(bx0 * h + 0.25 * h, by0 * h + 0.25 * h);
  c.svc_rings = 2;
  c.substeps = 20;
  c.dt = 20 * 4e-15;
  c.interior_damp_fs = 1.0 / damping / units::s_per_fs;
  c.ivc_damp_fs = c.interior_damp_fs;
  c.continuum_damping = damping;
  c.lammps_log = out + "/lammps.log";
  Coupler cp(s, c);
  cp.setup();
  const double t_end = t_settle + t_load + t_hold;
  const long nsteps = std::lround(t_end / c.dt);
  const long frame_every = std::max(1L, nsteps / 8);
  std::ostringstream prof;
  prof.precision(10);
  prof << "time_s,x_m,ux_m,source\n";
  const int jmid = by0 + nb / 2; // middle row of the block (an INT row)
  auto profile = [&] {
    for (std::size_t p = 0; p < s.particles.size(); ++p) {
      const auto& x0 = s.particles.x0[p];
      if (static_cast<int>(std::floor(x0[1] / h)) != jmid) continue;
      prof << s.time << ',' << x0[0] << ',' << s.particles.x[p][0] - x0[0] << ",continuum\n";
    }
    std::vector<int> ids;
    std::vector<Eigen::Vector3d> x, v;
    cp.atoms(ids, x, v);
    std::map<int, std::pair<double, std::pair<double, int>>> acc; // i -> (x0 sum, (u sum, n))
    for (std::size_t k = 0; k < x.size(); ++k) {
      const Eigen::Vector2d x0 = cp.to_continuum(cp.atoms_initial()[k]);
      if (static_cast<int>(std::floor(x0[1] / h)) != jmid) continue;
      auto& a = acc[static_cast<int>(std::floor(x0[0] / h))];
      a.first += x0[0];
      a.second.first += (cp.to_continuum(x[k]) - x0)[0];
      a.second.second += 1;
    }
    for (const auto& [i, a] : acc)
      prof << s.time << ',' << a.first / a.second.second << ',' << a.second.first / a.second.second
           << ",md\n";
  };
  const auto w0 = std::chrono::steady_clock::now();
  pnc::Progress bar("escm_tension", static_cast<double>(nsteps), "steps"); // D344
  for (long k = 0; k < nsteps; ++k) {
    const double tl = s.time + 0.5 * c.dt - t_settle;
    s.bcs[2].velocity[0] = (tl > 0 && tl < t_load)
                               ? strain * L / t_load * (1 - std::cos(2 * M_PI * tl / t_load))
                               : 0.0;
    cp.step();
    if ((k + 1) % frame_every == 0 || k + 1 == nsteps) {
      const long f = (k + 1) / frame_every;
      cp.write_atoms_vtu(out + "/atoms_" + std::to_string(f) + ".vtu");
      profile();
      char t_ps[48];
      std::snprintf(t_ps, sizeof t_ps, "t = %.1f ps", s.time * 1e12);
      bar.set(static_cast<double>(k + 1), t_ps);
    }
  }
  pnc::write_text_atomically(out + "/profile.csv", prof.str());
  cp.write_energy_csv(out + "/energy.csv");
  const auto& t = cp.timing();
  std::printf("steps %ld, wall %.2f s; outside LAMMPS %.1f %%; left reaction %.4e N/m\n", nsteps,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count(),
              100 * t.outside_share(), s.bcs[0].reaction[0]);
  // scripts/plot_escm.py (build tree or installed) through pnc's plot runner
  // (pnc/core/plot.hpp): no python3-matplotlib, or no script, is a warning
  try {
    (void)pnc::run_plot_script("plot_escm.py", {out});
  } catch (const pnc::InputError& e) {
    std::fprintf(stderr, "plots not written: %s\n", e.what());
  }
  return 0;
}
