// The pair style of a TI's start state, read by LAMMPS from the restart file before any lambda
// point runs, and the rule that a TI needs one plain lj/cut there (decision D394).
#include "pnc/thermo/ti.hpp"

#include "pnc/core/error.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pnc::thermo {

namespace fs = std::filesystem;

std::string restart_pair_style(const std::string& restart, const std::string& dir, int ranks) {
  const std::string info = (fs::path(dir) / "restart_check.txt").string();
  const std::string log = (fs::path(dir) / "restart_check.log").string();
  const std::string rs = md::lammps_path(restart, "restart");
  const std::string out = md::lammps_path(info, "restart check output");
  // LAMMPS's `info system` line "Atoms = N, types = T, style = <pair style>" (29 Sep 2021)
  const md::StageOutcome o = md::run_stage({"restart check", log, {}, ranks}, [&](md::Lammps& l) {
    l.cmd("read_restart " + rs);
    l.cmd("info system out overwrite " + out);
  });
  if (!o.ok) return ""; // unreadable: every lambda point reports LAMMPS's own error (as before)
  std::ifstream f(info);
  std::string style;
  for (std::string line; std::getline(f, line);) {
    const auto at = line.find("style = ");
    if (line.rfind("Atoms", 0) == 0 && at != std::string::npos) {
      style = line.substr(at + 8);
      style.erase(style.find_last_not_of(" \t\r") + 1);
    }
  }
  f.close();
  fs::remove(info);
  if (style.empty())
    fail(info, "style", "", "LAMMPS's `info system` printed no pair style line (LAMMPS version?)");
  return style;
}

void check_ti_pair_style(const std::string& restart, const std::string& dir, int ranks) {
  const std::string style = restart_pair_style(restart, dir, ranks);
  if (style.empty()) return; // LAMMPS could not read the file: the points fail with its message
  for (const char* ok : {"lj/cut", "lj/cut/opt", "lj/cut/omp"})
    if (style == ok) return;
  fail(restart, "pair_style", style,
       "thermo ti replaces the pair style by one lj/cut whose epsilon and sigma it ramps over "
       "lambda (D62); the start state must have that pair style, lj/cut: a Coulomb pair (e.g. "
       "lj/cut/coul/long with its kspace partner) or any other style would be dropped, not "
       "scaled (D394)");
}

} // namespace pnc::thermo
