// bench_escm: wall-time split of ESCM coupled steps (escm.hpp): LAMMPS vs continuum +
// coupling. Timed CLI (not Google Benchmark: one coupled step is ms-long and stateful).
//   bench_escm [block_cells=10] [substeps=20] [steps=200] [nz=3]
// LJ FCC argon-like crystal (rc 2.5 sigma) in a 2-D continuum of (2 block + 10) x (block + 4)
// cells; neumann mode, T = 0 damping. Prints the shares; goal: outside LAMMPS <= 10 %.
#include "pnc/gimp_coupler/escm.hpp"
#include "pnc/gimp_coupler/escm_lj.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>

using namespace pnc::gimp;
using namespace pnc::gimp::escm;

int main(int argc, char** argv) {
  const int nb = argc > 1 ? std::atoi(argv[1]) : 10;
  const int N = argc > 2 ? std::atoi(argv[2]) : 20;
  const int steps = argc > 3 ? std::atoi(argv[3]) : 200;
  const int nz = argc > 4 ? std::atoi(argv[4]) : 3;
  if (nb < 7 || N < 1 || steps < 1 || nz < 2) {
    std::fprintf(stderr, "usage: bench_escm [block_cells>=7] [substeps>=1] [steps>=1] [nz>=2]\n");
    return 1;
  }
  const double eps = 0.2381, sig = 3.405, mass = 39.948, rc = 2.5 * sig;
  const LjFcc lj = lj_fcc(eps, sig, rc, mass);
  const double h = lj.a0_A * units::m_per_A;
  const int ncx = 2 * nb + 10, ncy = nb + 4, bx0 = nb / 2 + 5, by0 = 2;
  Solver<2> s;
  s.grid.h = h;
  s.grid.origin = Eigen::Vector2d(-2 * h, -2 * h);
  s.grid.n = {ncx + 5, ncy + 5};
  s.materials.push_back(std::make_shared<LinearElastic>(lj.density, lj.E(), lj.nu()));
  for (int j = 0; j < ncy; ++j)
    for (int i = 0; i < ncx; ++i)
      s.particles.add(Eigen::Vector2d((i + 0.5) * h, (j + 0.5) * h),
                      Eigen::Vector2d::Constant(0.5 * h), lj.density * h * h, h * h, 0);
  NodeBC<2> left, right;
  left.lo = Eigen::Vector2d(-0.1 * h, -10 * h);
  left.hi = Eigen::Vector2d(0.1 * h, 100 * h);
  left.mask = {true, false};
  right.lo = Eigen::Vector2d((ncx - 0.1) * h, -10 * h);
  right.hi = Eigen::Vector2d((ncx + 1.1) * h, 100 * h);
  right.mask = {true, false};
  right.velocity[0] = 0.5; // m/s, a slow pull
  s.bcs = {left, right};
  Config c;
  c.md_setup = lj_fcc_block_commands(lj, nb, nb, nz, mass, eps, sig, rc);
  c.md_offset = Eigen::Vector2d(bx0 * h + 0.25 * h, by0 * h + 0.25 * h);
  c.svc_rings = 2;
  c.substeps = N;
  c.dt = N * 4e-15;
  c.interior_damp_fs = 1000;
  c.ivc_damp_fs = 1000;
  Coupler cp(s, c);
  cp.setup();
  const auto z = cp.zone_counts();
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k)
    cp.step();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const Timing& t = cp.timing();
  std::printf("atoms: INT %d IVC %d SVC %d; continuum particles %zu; N = %d, %d coupled steps\n",
              z[0], z[1], z[2], s.particles.size(), N, steps);
  std::printf("wall %.3f s = %.3f ms per coupled step\n", wall, 1e3 * wall / steps);
  std::printf("LAMMPS %.3f s | callback %.3f s | continuum %.3f s | other coupling %.3f s\n",
              t.lammps, t.callback, t.continuum, t.coupling);
  std::printf("share outside LAMMPS (continuum + coupling + callback): %.2f %%\n",
              100 * t.outside_share());
  return 0;
}
