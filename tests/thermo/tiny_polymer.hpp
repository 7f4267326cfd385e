#pragma once
// Test helper of the thermo tests: a tiny coarse-grained PP melt (12 chains x 10 beads,
// 0.9 g/cm^3, minimised, velocities at 300 K) written as a LAMMPS restart in `d`.
#include "pnc/rve/builder.hpp"
#include "pnc/rve/runner.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>

namespace pnc::test {

inline std::string tiny_polymer_restart(const std::filesystem::path& d) {
  rve::BuildSpec b;
  b.chains = 12;
  b.beads_per_chain = 10;
  b.density = 0.9;
  const rve::PolymerForceField ff;
  const std::string data = (d / "rve.data").string(), rs = (d / "rve.restart").string();
  rve::write_data_file(data, rve::build_polymer(b, ff), "thermo test");
  const auto o = rve::run_stage({"prep", (d / "prep.log").string(), {}}, [&](rve::Lammps& l) {
    l.cmd("units real");
    l.cmd("atom_style molecular");
    l.cmd("read_data " + data);
    l.cmds(rve::polymer_forcefield_commands(ff));
    l.cmd("minimize 1e-4 1e-6 200 2000");
    l.cmd("velocity all create 300 5 dist gaussian");
    l.cmd("write_restart " + rs);
  });
  if (!o.ok) throw std::runtime_error(o.error);
  return rs;
}

} // namespace pnc::test
