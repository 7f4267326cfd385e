// The pair style of a LAMMPS restart file, as LAMMPS reads it (restart_info.hpp).
#include "pnc/md/restart_info.hpp"

#include "pnc/core/error.hpp"
#include "pnc/md/lammps_path.hpp"
#include "pnc/md/runner.hpp"

#include <filesystem>
#include <fstream>
#include <string>

namespace pnc::md {

namespace fs = std::filesystem;

std::string restart_pair_style(const std::string& restart, const std::string& dir, int ranks) {
  const std::string info = (fs::path(dir) / "restart_check.txt").string();
  const std::string log = (fs::path(dir) / "restart_check.log").string();
  const std::string rs = lammps_path(restart, "restart");
  const std::string out = lammps_path(info, "restart check output");
  // LAMMPS's `info system` line "Atoms = N, types = T, style = <pair style>" (29 Sep 2021)
  const StageOutcome o = run_stage({"restart check", log, {}, ranks}, [&](Lammps& l) {
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

} // namespace pnc::md
