#pragma once
// Test helper of the thermo tests: a tiny coarse-grained PP melt (12 chains x 10 beads,
// 0.9 g/cm^3, minimised, velocities at 300 K) written as a LAMMPS restart in `d`.
#include "pnc/md/builder.hpp"
#include "pnc/md/runner.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>

namespace pnc::test {

inline std::string tiny_polymer_restart(const std::filesystem::path& d) {
  md::BuildSpec b;
  b.chains = 12;
  b.beads_per_chain = 10;
  b.density = 0.9;
  const md::PolymerForceField ff;
  const std::string data = (d / "rve.data").string(), rs = (d / "rve.restart").string();
  md::write_data_file(data, md::build_polymer(b, ff), "thermo test");
  const auto o = md::run_stage({"prep", (d / "prep.log").string(), {}}, [&](md::Lammps& l) {
    l.cmd("units real");
    l.cmd("atom_style molecular");
    l.cmd("read_data " + data);
    l.cmds(md::polymer_forcefield_commands(ff));
    l.cmd("minimize 1e-4 1e-6 200 2000");
    l.cmd("velocity all create 300 5 dist gaussian");
    l.cmd("write_restart " + rs);
  });
  if (!o.ok) throw std::runtime_error(o.error);
  return rs;
}

} // namespace pnc::test
