#pragma once
// pnc/md/lammps_server.hpp: LAMMPS on K MPI ranks behind the same `Lammps` interface.
//
// A stage child (runner.hpp) that needs K > 1 ranks does not host LAMMPS itself: it starts
// `mpirun -np K pnc_lammps_server SOCKET ...` and talks to rank 0 over a private Unix socket
// (private_channel.hpp: a 0600 socket in a 0700 directory, peer credentials and a token). Rank 0
// broadcasts every request to all ranks, which execute it together (every LAMMPS library call used
// here is collective); rank 0 answers. A LAMMPS error ends the server (LAMMPS calls
// exit/MPI_Abort); the stage child then sees the socket close and reports LAMMPS's own ERROR line
// from the stage log. If the stage child dies (kill, crash) the server sees the socket close and
// aborts all ranks: nothing outlives pnc.
//
// Units: whatever the commands set (pnc's stages use LAMMPS `real`).
#include <string>
#include <vector>

namespace pnc::md {

/// Entry point of `pnc_lammps_server`. Reads the token from $PNC_LAMMPS_TOKEN and removes it
/// from the environment, calls MPI_Init, connects rank 0 to the socket file `socket_path`
/// (connect_private: directory and listener checked, token sent; aborts all ranks if that
/// fails), opens LAMMPS on MPI_COMM_WORLD with `lammps_args` (e.g. -log FILE -screen none),
/// serves until the client says quit. Returns the process exit code.
int serve_lammps(const std::string& socket_path, const std::vector<std::string>& lammps_args);

/// World size and rank when this process was started by mpirun/mpiexec (Open MPI or an
/// MPICH-style launcher), read from the environment without initialising MPI; {1, 0} otherwise.
struct LauncherInfo {
  int size = 1, rank = 0;
};
LauncherInfo launcher_from_environment();

} // namespace pnc::md
