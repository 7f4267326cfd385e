#pragma once
// pnc/md/lammps_path.hpp: a file path as one word of a LAMMPS command.
//
// LAMMPS (2022 parser, "Parsing rules" of its manual) splits a command line at blanks,
// drops everything after an unquoted '#', and substitutes '$x', '${name}' and '$(expr)'
// outside quotes. Text between matching single quotes, double quotes or triple double quotes
// ("""...""") is one word, taken literally ('#' and '$' inside quotes are not special).
// Every path that pnc puts into a LAMMPS command (read_data, read_restart, write_restart,
// write_data, ...) goes through lammps_path(), so a blank, '#', '$' or quote in --out,
// --from or --restart can never change how LAMMPS reads the line.
#include <string>

namespace pnc::md {

/// Returns `path` quoted as one literal LAMMPS word: in single quotes when it has no single
/// quote, else in double quotes when it has no double quote, else in triple double quotes
/// when that is unambiguous (no two adjacent double quotes, not starting or ending with one).
/// Throws pnc::InputError (source `path`, field `field`) naming the rule when the path is
/// empty, holds a control character (newline, tab, ...) or a non-ASCII byte (LAMMPS rewrites
/// those), holds '*' or '%' (LAMMPS expands
/// them in restart, dump and data file names: timestep, one file per processor), or holds
/// quotes that cannot be quoted.
std::string lammps_path(const std::string& path, const std::string& field = "path");

} // namespace pnc::md
