// The pair style of a TI's start state, read by LAMMPS from the restart file before any lambda
// point runs (md::restart_pair_style), and the rule that a TI needs one plain lj/cut there
// (decision D394).
#include "pnc/thermo/ti.hpp"

#include "pnc/core/error.hpp"
#include "pnc/md/restart_info.hpp"

#include <string>

namespace pnc::thermo {

void check_ti_pair_style(const std::string& restart, const std::string& dir, int ranks) {
  const std::string style = md::restart_pair_style(restart, dir, ranks);
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
