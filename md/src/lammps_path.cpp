// A file path as one literal LAMMPS word (see lammps_path.hpp).
#include "pnc/md/lammps_path.hpp"

#include "pnc/core/error.hpp"

namespace pnc::md {

std::string lammps_path(const std::string& path, const std::string& field) {
  if (path.empty()) fail("<lammps path>", field, "", "a file path must not be empty");
  for (const char c : path) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f)
      fail(path, field, "",
           "a path given to LAMMPS must not contain control characters (newline, tab, ...)");
    if (u >= 0x80)
      fail(path, field, "",
           "a path given to LAMMPS must be ASCII (LAMMPS rewrites non-ASCII characters)");
    if (c == '*' || c == '%')
      fail(path, field, "",
           std::string("a path given to LAMMPS must not contain '") + c +
               "' (LAMMPS expands it in restart, dump and data file names)");
  }
  const bool single = path.find('\'') != std::string::npos;
  const bool dbl = path.find('"') != std::string::npos;
  if (!single) return "'" + path + "'";
  if (!dbl) return "\"" + path + "\"";
  if (path.find("\"\"") == std::string::npos && path.front() != '"' && path.back() != '"')
    return "\"\"\"" + path + "\"\"\"";
  fail(path, field, "",
       "a path given to LAMMPS that holds both quote kinds must not hold two adjacent double "
       "quotes nor start or end with one (it cannot be quoted for LAMMPS)");
}

} // namespace pnc::md
