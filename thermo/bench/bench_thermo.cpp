// Cost of the dH/dlambda evaluation relative to the MD steps it samples (docs/thermo.md, Speed).
// Runs in one supervised LAMMPS child on an equilibrated polymer restart:
//   t_plain : `run N` in one piece (NVE + Langevin, the TI's integrator)
//   t_chunk : the same N steps as N/every runs of `every` steps (`pre no post no`), no sampling
//   t_sample: the same chunks, each followed by one sample (compute pair/local dist + the
//             pair sums for lambda and both neighbouring nodes): lj_sampling method "pairs"
//   t_virial: the N steps as lj_sampling method "virial" runs them (the default, D64):
//             one run (in 5 pieces) with fix vector of the pair energy and pair virial
// and prints the overheads relative to t_plain. Units: LAMMPS real.
// usage: bench_thermo RESTART [steps=10000] [every=100, the TI default] [repetitions=3]
#include "pnc/md/forcefield.hpp"
#include "pnc/md/runner.hpp"
#include "pnc/thermo/ti.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_thermo RESTART [steps=10000] [every=100] [repetitions=3]\n");
    return 1;
  }
  const std::string restart = argv[1];
  const long steps = argc > 2 ? std::atol(argv[2]) : 10000;
  const int every = argc > 3 ? std::atoi(argv[3]) : 100;
  const int reps = argc > 4 ? std::atoi(argv[4]) : 3;
  const auto o = pnc::md::run_stage({"bench", "bench_thermo.log", {}}, [&](pnc::md::Lammps& l) {
    using clk = std::chrono::steady_clock;
    auto secs = [](clk::time_point a) {
      return std::chrono::duration<double>(clk::now() - a).count();
    };
    pnc::thermo::TiSpec spec;
    spec.dhdl_method = "pairs";
    const auto sys = pnc::thermo::polymer_system(spec, {"ref", 0, "ref"}, restart,
                                                 pnc::md::polymer_forcefield_commands({}));
    const auto vir = pnc::thermo::lj_sampling(spec.path, spec.fd_h, "virial");
    sys.setup(l, 0.5, 7);
    l.cmd("timestep 0.5");
    l.cmd("thermo 100000");
    l.cmd("run 1000");
    // each variant `reps` times, interleaved; the minimum is reported (the machine is shared)
    double plain = 1e30, chunk = 1e30, sampled = 1e30, virial = 1e30, acc = 0, accv = 0;
    std::size_t nv = 1;
    for (int rep = 0; rep < reps; ++rep) {
      auto t = clk::now();
      l.cmd(fmt::format("run {}", steps));
      plain = std::min(plain, secs(t));
      t = clk::now();
      l.cmd(fmt::format("run {}", every));
      for (long k = 1; k < steps / every; ++k)
        l.cmd(fmt::format("run {} pre no post no", every));
      chunk = std::min(chunk, secs(t));
      t = clk::now();
      acc = 0;
      l.cmd(fmt::format("run {}", every));
      acc += sys.sample(l, 0.5, 0.1127, 0.8873).dhdl;
      for (long k = 1; k < steps / every; ++k) {
        l.cmd(fmt::format("run {} pre no post no", every));
        acc += sys.sample(l, 0.5, 0.1127, 0.8873).dhdl;
      }
      sampled = std::min(sampled, secs(t));
      t = clk::now();
      const auto vs = vir.production(l, 0.5, 0.1127, 0.8873, steps, every);
      virial = std::min(virial, secs(t));
      accv = 0;
      for (const auto& v : vs)
        accv += v.dhdl;
      nv = vs.size();
    }
    std::printf("atoms %ld, %ld steps, sample every %d steps (mean dH/dl %.3f kcal/mol)\n",
                l.natoms(), steps, every, acc / static_cast<double>(steps / every));
    std::printf("plain run:            %.3f s  (%.1f steps/s)\n", plain,
                static_cast<double>(steps) / plain);
    std::printf("chunked, no sampling: %.3f s  (+%.1f %% vs plain)\n", chunk,
                100 * (chunk / plain - 1));
    std::printf("chunked + dH/dl:      %.3f s  (+%.1f %% vs plain; dH/dl alone +%.1f %%)\n",
                sampled, 100 * (sampled / plain - 1), 100 * (sampled - chunk) / plain);
    std::printf("virial method:        %.3f s  (+%.1f %% vs plain; mean dH/dl %.3f kcal/mol)\n",
                virial, 100 * (virial / plain - 1), accv / static_cast<double>(nv));
    std::printf("(minimum of %d interleaved repetitions each)\n", reps);
    std::fflush(stdout);
  });
  if (!o.ok) {
    std::fprintf(stderr, "bench_thermo: %s\n", o.error.c_str());
    return 1;
  }
  return 0;
}
