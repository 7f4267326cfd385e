#include "pnc/core/csv.hpp"

#include "pnc/core/error.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace pnc {

namespace {
std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream ss(line);
  while (std::getline(ss, cell, ','))
    cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}
} // namespace

std::size_t CsvTable::column(const std::string& name) const {
  for (std::size_t j = 0; j < header.size(); ++j)
    if (header[j] == name) return j;
  fail(source, name, "", "required column is missing from the header");
}

CsvTable read_csv(const std::string& path) {
  std::ifstream f(path);
  if (!f) fail(path, "", "", "cannot open for reading");
  CsvTable t;
  t.source = path;
  std::string line;
  int lineno = 0;
  while (std::getline(f, line)) {
    ++lineno;
    // A UTF-8 byte order mark (spreadsheet exports) is not part of the first line.
    if (lineno == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    const std::string s = trim(line);
    if (s.empty() || s[0] == '#') continue;
    auto cells = split(s);
    if (t.header.empty()) {
      for (std::size_t j = 0; j < cells.size(); ++j) {
        if (cells[j].empty())
          fail(path, "header (line " + std::to_string(lineno) + ")",
               "column " + std::to_string(j + 1), "every column needs a name");
        for (std::size_t k = 0; k < j; ++k)
          if (cells[k] == cells[j])
            fail(path, cells[j],
                 "columns " + std::to_string(k + 1) + " and " + std::to_string(j + 1),
                 "duplicated column name in the header (line " + std::to_string(lineno) +
                     "): every column must be named once");
      }
      t.header = cells;
      continue;
    }
    if (cells.size() != t.header.size()) {
      fail(path, "line " + std::to_string(lineno), std::to_string(cells.size()) + " cells",
           "every row must have as many cells as the header (" + std::to_string(t.header.size()) +
               ")");
    }
    std::vector<double> row(cells.size());
    for (std::size_t j = 0; j < cells.size(); ++j) {
      const char* b = cells[j].c_str();
      char* e = nullptr;
      errno = 0;
      const double v = std::strtod(b, &e);
      if (cells[j].empty() || *e != '\0' || errno == ERANGE || !std::isfinite(v)) {
        fail(path, t.header[j] + " (line " + std::to_string(lineno) + ")", cells[j],
             "cell must be a finite number");
      }
      row[j] = v;
    }
    t.rows.push_back(std::move(row));
    t.line_numbers.push_back(lineno);
  }
  if (t.header.empty()) fail(path, "", "", "file is empty: a header line is required");
  return t;
}

} // namespace pnc
