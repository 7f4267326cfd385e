// pnc_lammps_server: LAMMPS on the ranks of an mpirun, serving one stage child of pnc
// (lammps_server.hpp). Started by the runner, not by users:
//   mpirun -np K pnc_lammps_server SOCKET_PATH [LAMMPS command-line args...]
// with the channel's token in $PNC_LAMMPS_TOKEN (private_channel.hpp).
#include "pnc/md/lammps_server.hpp"

#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: mpirun -np K pnc_lammps_server SOCKET_PATH [LAMMPS args...]\n"
                 "(started by pnc for stages on K > 1 ranks; not meant to be run by hand)\n");
    return 2;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  return pnc::md::serve_lammps(argv[1], args);
}
