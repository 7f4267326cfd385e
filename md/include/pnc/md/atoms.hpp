#pragma once
// pnc/md/atoms.hpp: per-atom arrays of an in-process LAMMPS instance, ordered by atom id.
//
// Units: those of the instance (pnc's stages use LAMMPS `real`: x in Angstrom, v in
// Angstrom/fs, f in kcal/(mol Angstrom)); image flags are integer box counts; types are the
// LAMMPS atom types. Layout: `count` values per atom, atom id k at [(k - 1) count, k count).
//
// Both calls read or write the local arrays of the process's LAMMPS directly, so every atom
// must be local: one MPI rank, atom ids 1..natoms (checked: atoms on other ranks, a LAMMPS build
// with other id or image-flag sizes, or a missing per-atom array are a pnc::ToolError naming
// LAMMPS; an atom id outside 1..natoms is a pnc::InputError naming the id and the rule; a
// `name`/`count` pair the calls do not serve, a size mismatch, is std::logic_error, a bug). Unlike
// lammps_gather_atoms / lammps_scatter_atoms they never go through the atom map, which can name a
// ghost copy of an atom, and they move image flags unpacked (D327).
#include <array>
#include <string>
#include <vector>

namespace pnc::md {

/// LAMMPS's packed image flags with a 32-bit imageint: 10 bits per axis, offset 512, x lowest.
struct ImageFlags {
  static constexpr int bits = 10, offset = 512, mask = 1023;
  static std::array<int, 3> unpack(int packed) {
    const auto u = static_cast<unsigned>(packed);
    return {static_cast<int>(u & mask) - offset, static_cast<int>((u >> bits) & mask) - offset,
            static_cast<int>(u >> (2 * bits)) - offset};
  }
  static int pack(int ix, int iy, int iz) {
    return (ix + offset) | ((iy + offset) << bits) | ((iz + offset) << (2 * bits));
  }
};

/// The per-atom quantity `name` by atom id: "x", "v", "f" (count 3, doubles), "image" (count
/// 3, the unpacked flags as doubles) or "type" (count 1). `lmp` is a LAMMPS handle.
std::vector<double> gather_local(void* lmp, const std::string& name, int count);

/// Writes "x", "v", "f" or "image" (3 values per atom, by atom id, flags unpacked) into the
/// local arrays.
void scatter_local(void* lmp, const std::string& name, const std::vector<double>& values);

} // namespace pnc::md
