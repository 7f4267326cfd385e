#pragma once
// pnc/core/csv.hpp: a strict reader for numeric CSV tables with a header line.
//
// Rules: the first non-empty line is the header (comma-separated names, surrounding
// whitespace ignored, each name non-empty and used once; a leading UTF-8 byte order mark is
// skipped); every following non-empty line has as many cells as the header and
// every cell is a finite decimal number. Lines starting with '#' are comments. Any
// violation throws pnc::InputError naming the file, the line and column, and the cell.
#include <string>
#include <vector>

namespace pnc {

struct CsvTable {
  std::string source;
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows; ///< rows[i][j]: row i, column j
  std::vector<int> line_numbers;         ///< 1-based line of each row in the file

  /// Index of a column; throws InputError naming the file and the missing column.
  std::size_t column(const std::string& name) const;
};

CsvTable read_csv(const std::string& path);

} // namespace pnc
