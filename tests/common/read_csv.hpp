#pragma once
// A CSV file with a header row as rows of column name -> value (numbers only), for the tests
// that read the coupled runs' logs (crack.csv, energy.csv).
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace pnc::test {

inline std::vector<std::map<std::string, double>> read_csv(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::string line;
  std::getline(f, line);
  std::vector<std::string> names;
  {
    std::istringstream h(line);
    std::string n;
    while (std::getline(h, n, ','))
      names.push_back(n);
  }
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(f, line)) {
    std::istringstream l(line);
    std::string v;
    std::map<std::string, double> r;
    for (std::size_t k = 0; k < names.size() && std::getline(l, v, ','); ++k)
      r[names[k]] = std::stod(v);
    rows.push_back(r);
  }
  return rows;
}

} // namespace pnc::test
