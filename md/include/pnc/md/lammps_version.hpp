#pragma once
// The version of the LAMMPS library pnc is linked with (and so of every LAMMPS instance pnc
// runs, in-process or on the K-rank stage server, which links the same library). md/ is the
// one layer that talks to LAMMPS (D346); the case checkpoints record this version (D366).

namespace pnc::md {

/// The linked LAMMPS's release date as the integer YYYYMMDD (LAMMPS's lammps_version; e.g.
/// 20210929 for "29 Sep 2021"). Asked once per process of an instance of its own (no screen,
/// no log; opened without MPI like a one-rank stage), then remembered. A pnc::ToolError when
/// LAMMPS gives no instance. Meant for stage children (a LAMMPS error would end the caller).
int linked_lammps_version();

} // namespace pnc::md
