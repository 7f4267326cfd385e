#pragma once
// Test helper of the thermo tests: a 108-atom LJ fluid (units real: fcc 6.4 A, 3 x 3 x 3 cells,
// mass 21 g/mol) on the LJ coupling path `p` at temperature T (K) with a Langevin thermostat,
// sampled by lj_sampling (method "virial" or "pairs"). `displace` (A, 0: none) moves every atom
// by a random vector that depends on its position only (the same on any MPI rank count).
#include "pnc/md/runner.hpp"
#include "pnc/thermo/ti.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <string>

namespace pnc::test {

inline thermo::LambdaSystem lj_fluid(const thermo::LjPath& p, double T,
                                     const std::string& method = "virial", double displace = 0) {
  thermo::LambdaSystem sys = thermo::lj_sampling(p, 1e-4, method);
  sys.setup = [p, T, displace](md::Lammps& l, double lambda, std::uint64_t seed) {
    l.cmd("units real");
    l.cmd("atom_style atomic");
    l.cmd("lattice fcc 6.4");
    l.cmd("region pnc_b block 0 3 0 3 0 3");
    l.cmd("create_box 1 pnc_b");
    l.cmd("create_atoms 1 box");
    if (displace > 0)
      l.cmd(fmt::format("displace_atoms all random {0} {0} {0} 4821 units box", displace));
    l.cmd("mass 1 21.0");
    l.cmd(fmt::format("pair_style lj/cut {}", p.cutoff));
    l.cmd("pair_modify shift no tail no");
    l.cmd(fmt::format("pair_coeff * * {:.15g} {:.15g} {:.15g}", p.eps(lambda), p.sig(lambda),
                      p.cutoff));
    l.cmd(fmt::format("velocity all create {} {} dist gaussian", T, seed));
    l.cmd("fix pnc_nve all nve");
    l.cmd(fmt::format("fix pnc_lan all langevin {0} {0} 100.0 {1} zero yes", T, seed + 3));
    l.cmd("compute pnc_pl all pair/local dist");
    l.cmd("thermo 100000");
  };
  return sys;
}

} // namespace pnc::test
