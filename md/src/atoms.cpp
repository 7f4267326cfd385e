// Per-atom arrays by atom id, read from and written to the local arrays (atoms.hpp).
#include "pnc/md/atoms.hpp"

#include "pnc/core/error.hpp"

#include <lammps/library.h>

#include <cstdint>
#include <stdexcept>

namespace pnc::md {

namespace {
#if defined(LAMMPS_BIGBIG)
using lmp_tag = std::int64_t;
#else
using lmp_tag = int;
#endif

constexpr const char* kDoing = "per-atom access by atom id";

/// Number of atoms; throws unless every atom is local with ids 1..n and image flags are 32 bit.
int local_atoms(void* lmp) {
  const auto n = static_cast<long>(lammps_get_natoms(lmp));
  const long nlocal = lammps_extract_setting(lmp, "nlocal");
  if (nlocal != n)
    fail_tool("LAMMPS", kDoing,
              std::to_string(nlocal) + " of " + std::to_string(n) +
                  " atoms on this process: every atom must be on one MPI rank",
              "");
  if (lammps_extract_setting(lmp, "imageint") != 4)
    fail_tool("LAMMPS", kDoing, "this LAMMPS build's image flags are not 32 bit", "");
  if (lammps_extract_setting(lmp, "tagint") != static_cast<int>(sizeof(lmp_tag)))
    fail_tool("LAMMPS", kDoing, "this LAMMPS build's atom id size differs from pnc's", "");
  return static_cast<int>(n);
}

std::size_t slot(const lmp_tag* id, int i, int count, int n) {
  if (id[i] < 1 || id[i] > n)
    fail("<LAMMPS system>", "atom id", std::to_string(id[i]),
         "must be in 1.." + std::to_string(n) + " (ids consecutive from 1; " + kDoing + ")");
  return static_cast<std::size_t>(id[i] - 1) * static_cast<std::size_t>(count);
}
} // namespace

std::vector<double> gather_local(void* lmp, const std::string& name, int count) {
  const int n = local_atoms(lmp);
  const bool image = name == "image", type = name == "type";
  if ((image && count != 3) || (type && count != 1) || (!image && !type && count != 3))
    throw std::logic_error("gather_local: '" + name + "' with " + std::to_string(count) +
                           " values per atom");
  const auto* id = static_cast<lmp_tag*>(lammps_extract_atom(lmp, "id"));
  std::vector<double> out(static_cast<std::size_t>(n) * static_cast<std::size_t>(count));
  for (int i = 0; i < n; ++i) {
    const std::size_t o = slot(id, i, count, n);
    if (image) {
      const auto f = ImageFlags::unpack(static_cast<int*>(lammps_extract_atom(lmp, "image"))[i]);
      for (int c = 0; c < 3; ++c)
        out[o + static_cast<std::size_t>(c)] = f[static_cast<std::size_t>(c)];
    } else if (type) {
      out[o] = static_cast<int*>(lammps_extract_atom(lmp, "type"))[i];
    } else {
      auto** a = static_cast<double**>(lammps_extract_atom(lmp, name.c_str()));
      if (!a) fail_tool("LAMMPS", kDoing, "no per-atom array '" + name + "'", "");
      for (int c = 0; c < 3; ++c)
        out[o + static_cast<std::size_t>(c)] = a[i][c];
    }
  }
  return out;
}

void scatter_local(void* lmp, const std::string& name, const std::vector<double>& v) {
  const int n = local_atoms(lmp);
  if (v.size() != 3 * static_cast<std::size_t>(n))
    throw std::logic_error("scatter_local: '" + name + "' has " + std::to_string(v.size()) +
                           " values, 3 per atom need " + std::to_string(3 * n));
  const auto* id = static_cast<lmp_tag*>(lammps_extract_atom(lmp, "id"));
  for (int i = 0; i < n; ++i) {
    const std::size_t o = slot(id, i, 3, n);
    if (name == "image") {
      static_cast<int*>(lammps_extract_atom(lmp, "image"))[i] = ImageFlags::pack(
          static_cast<int>(v[o]), static_cast<int>(v[o + 1]), static_cast<int>(v[o + 2]));
    } else {
      auto** a = static_cast<double**>(lammps_extract_atom(lmp, name.c_str()));
      if (!a) fail_tool("LAMMPS", kDoing, "no per-atom array '" + name + "'", "");
      for (int c = 0; c < 3; ++c)
        a[i][c] = v[o + static_cast<std::size_t>(c)];
    }
  }
}

} // namespace pnc::md
