#pragma once
// What a LAMMPS restart file holds, as LAMMPS itself reads it (md/ is the one layer that talks
// to LAMMPS, D346). No units.
#include <string>

namespace pnc::md {

/// The pair style stored in the LAMMPS restart `restart` (e.g. "lj/cut"), as LAMMPS reads it: a
/// supervised stage child on `ranks` MPI ranks (D324, D333: under mpirun a forked in-process
/// LAMMPS would hang) runs `read_restart` and `info system`, whose line "Atoms = N, types = T,
/// style = <pair style>" is read back (this LAMMPS, 29 Sep 2021, has no library call for the
/// pair style); its log is `dir`/restart_check.log and its scratch file is removed. "" when
/// LAMMPS cannot read the file (its own message is in the log); a pnc::InputError naming the
/// scratch file when LAMMPS printed no such line (another LAMMPS version).
std::string restart_pair_style(const std::string& restart, const std::string& dir, int ranks = 1);

} // namespace pnc::md
