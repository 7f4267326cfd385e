#pragma once
// pnc/core/locate.hpp: finding the files pnc ships (plot scripts, the LAMMPS stage server)
// relative to the running executable, so that an installed tree can be moved (docs/install.md,
// decisions D151-D152). No absolute source or build path is compiled into pnc.
//
// Layout (the same relative paths in the install tree and in the build tree):
//   <root>/bin/pnc                          (build tree: <build>/app/pnc)
//   <root>/share/pnc/scripts/<name>.py      plot scripts (build tree: copied at configure time)
//   <root>/libexec/pnc/pnc_lammps_server    the MPI stage server
// The relative directories come from CMake (GNUInstallDirs) as compile definitions of core.
#include <filesystem>
#include <string>
#include <vector>

namespace pnc {

/// Directory of the running executable, read from /proc/self/exe; empty if it cannot be read.
std::filesystem::path executable_dir();

/// Where pnc looked for a shipped file.
struct Located {
  std::string path;               ///< the file found; empty if none was found
  std::vector<std::string> tried; ///< every candidate, in the order looked at
  std::string looked_in() const;  ///< "looked in: a, b, c"
};

enum class ShippedDir {
  scripts, ///< share/pnc/scripts: the matplotlib plot scripts
  libexec, ///< libexec/pnc: helper executables (pnc_lammps_server)
};

/// The directory of `dir` relative to the install prefix ("share/pnc/scripts", ...).
std::string shipped_relative_dir(ShippedDir dir);

/// Finds the shipped file `name` (D151). If the environment variable `env_dir` (may be null)
/// is set and not empty, it names the directory to use and only `$env_dir/name` is tried.
/// Otherwise, with X the running executable's directory: X/../<dir>/name (installed tree;
/// build-tree executables under app/, rve/, ...) then X/../../<dir>/name (build-tree test
/// executables under tests/<lib>/); for ShippedDir::libexec, X/name first (all binaries
/// copied into one directory). Never throws.
Located locate_shipped(ShippedDir dir, const std::string& name, const char* env_dir);

/// As locate_shipped, but throws pnc::InputError naming the file, the places looked in and
/// the environment variable that overrides them when nothing is found.
std::string require_shipped(ShippedDir dir, const std::string& name, const char* env_dir);

} // namespace pnc
