// The linked LAMMPS's version (lammps_version.hpp).
#include "pnc/md/lammps_version.hpp"
#include "pnc/md/runner.hpp"

#include <lammps/library.h>

namespace pnc::md {

int linked_lammps_version() {
  static const int version = [] {
    const auto l = Lammps::open_in_process({"pnc", "-screen", "none", "-log", "none", "-nocite"},
                                           "asking LAMMPS its version");
    return lammps_version(l->handle());
  }();
  return version;
}

} // namespace pnc::md
