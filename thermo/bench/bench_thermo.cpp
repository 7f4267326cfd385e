// Cost of the dH/dlambda evaluation relative to the MD steps it samples (docs/thermo.md, Speed).
// Runs in one supervised LAMMPS child on an equilibrated polymer restart:
//   t_plain : `run N` in one piece (NVE + Langevin, the TI's integrator)
//   t_chunk : the same N steps as N/every runs of `every` steps (`pre no post no`), no sampling
//   t_sample: the same chunks, each followed by one sample (compute pair/local dist + the
//             pair sums for lambda and both neighbouring nodes): lj_sampling method "pairs"
//   t_virial: the N steps as lj_sampling method "virial" runs them (the default, D64):
//             one run (in 5 pieces) with fix vector of the pair energy and pair virial
// and prints the overheads relative to t_plain: median and range (min-max) over the interleaved
// repetitions, the overheads from the ratios of the same repetition. Units: LAMMPS real; s.
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
#include <vector>

namespace {
/// Median and range of xs (non-empty), as "median (min-max)" with fmt format f per value.
std::string med_range(std::vector<double> xs, const char* f) {
  std::sort(xs.begin(), xs.end());
  const std::size_t n = xs.size();
  const double med = n % 2 ? xs[n / 2] : 0.5 * (xs[n / 2 - 1] + xs[n / 2]);
  return fmt::format(fmt::runtime(std::string(f) + " (" + f + "-" + f + ")"), med, xs.front(),
                     xs.back());
}
/// Overheads 100 (a_k / b_k - 1) % of the same repetitions.
std::vector<double> overhead(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> r;
  for (std::size_t k = 0; k < a.size(); ++k)
    r.push_back(100 * (a[k] / b[k] - 1));
  return r;
}
} // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_thermo RESTART [steps=10000] [every=100] [repetitions=3]\n");
    return 1;
  }
  const std::string restart = argv[1];
  const long steps = argc > 2 ? std::atol(argv[2]) : 10000;
  const int every = argc > 3 ? std::atoi(argv[3]) : 100;
  const int reps = argc > 4 ? std::atoi(argv[4]) : 3;
  if (reps < 1) {
    std::fprintf(stderr, "bench_thermo: repetitions '%s': must be an integer >= 1\n", argv[4]);
    return 1;
  }
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
    // each variant `reps` times, interleaved; median and range over the repetitions (the
    // machine is shared: a slow phase shows as a wide range, not as a biased minimum)
    std::vector<double> plain, chunk, sampled, virial, speed, dsample;
    double acc = 0, accv = 0;
    std::size_t nv = 1;
    for (int rep = 0; rep < reps; ++rep) {
      auto t = clk::now();
      l.cmd(fmt::format("run {}", steps));
      plain.push_back(secs(t));
      t = clk::now();
      l.cmd(fmt::format("run {}", every));
      for (long k = 1; k < steps / every; ++k)
        l.cmd(fmt::format("run {} pre no post no", every));
      chunk.push_back(secs(t));
      t = clk::now();
      acc = 0;
      l.cmd(fmt::format("run {}", every));
      acc += sys.sample(l, 0.5, 0.1127, 0.8873).dhdl;
      for (long k = 1; k < steps / every; ++k) {
        l.cmd(fmt::format("run {} pre no post no", every));
        acc += sys.sample(l, 0.5, 0.1127, 0.8873).dhdl;
      }
      sampled.push_back(secs(t));
      t = clk::now();
      const auto vs = vir.production(l, 0.5, 0.1127, 0.8873, steps, every);
      virial.push_back(secs(t));
      accv = 0;
      for (const auto& v : vs)
        accv += v.dhdl;
      nv = vs.size();
      speed.push_back(static_cast<double>(steps) / plain.back());
      dsample.push_back(100 * (sampled.back() - chunk.back()) / plain.back());
    }
    std::printf("atoms %ld, %ld steps, sample every %d steps (mean dH/dl %.3f kcal/mol)\n",
                l.natoms(), steps, every, acc / static_cast<double>(steps / every));
    std::printf("plain run:            %s s  (%s steps/s)\n", med_range(plain, "{:.3f}").c_str(),
                med_range(speed, "{:.1f}").c_str());
    std::printf("chunked, no sampling: %s s  (%s %% vs plain)\n",
                med_range(chunk, "{:.3f}").c_str(),
                med_range(overhead(chunk, plain), "{:+.1f}").c_str());
    std::printf("chunked + dH/dl:      %s s  (%s %% vs plain; dH/dl alone %s %%)\n",
                med_range(sampled, "{:.3f}").c_str(),
                med_range(overhead(sampled, plain), "{:+.1f}").c_str(),
                med_range(dsample, "{:+.1f}").c_str());
    std::printf("virial method:        %s s  (%s %% vs plain; mean dH/dl %.3f kcal/mol)\n",
                med_range(virial, "{:.3f}").c_str(),
                med_range(overhead(virial, plain), "{:+.1f}").c_str(),
                accv / static_cast<double>(nv));
    std::printf("(median (min-max) of %d interleaved repetitions each)\n", reps);
    std::fflush(stdout);
  });
  if (!o.ok) {
    std::fprintf(stderr, "bench_thermo: %s\n", o.error.c_str());
    return 1;
  }
  return 0;
}
