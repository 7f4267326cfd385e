#pragma once
// Shared by the tests of `pnc material drive` and `pnc card export`: a private directory per
// test, running pnc with the plugin of this build, and the undamaged / damaged stiffness
// written out from the card's constants by theory.md eqs. (1.1)-(1.2), independently of the
// code under test.
#include "common/temp_dir.hpp"
#include "pnc/core/csv.hpp"

#include <Eigen/Dense>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace pnc::test {

namespace fs = std::filesystem;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

struct CliResult {
  int code;
  std::string out, err;
};

class MaterialCli : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = pnc::test::fresh_dir(
        "mat_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string p(const std::string& n) const { return (dir_ / n).string(); }

  // pnc with `args` (test-controlled text, no user input) in the test directory; the plugin
  // of this build comes from PNC_MATERIAL_PLUGIN unless `env` says otherwise.
  CliResult run(const std::string& args,
                const std::string& env = "PNC_MATERIAL_PLUGIN='" PNC_PLUGIN "'") const {
    const std::string errf = p("stderr.txt");
    const std::string cmd =
        "cd '" + dir_.string() + "' && env " + env + " '" PNC_EXE "' " + args + " 2>'" + errf + "'";
    FILE* pipe = ::popen(cmd.c_str(), "r");
    std::string out;
    char buf[4096];
    while (std::fgets(buf, sizeof buf, pipe))
      out += buf;
    const int st = ::pclose(pipe);
    std::ifstream e(errf);
    std::stringstream ss;
    ss << e.rdbuf();
    fs::remove(errf);
    return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out, ss.str()};
  }
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(p(name)) << text;
  }
  std::string tables_card(const std::string& model = "pnc") const {
    const std::string card = p("card_" + model + ".h5");
    const CliResult r = run("card tables --model " + model + " --out card_" + model + ".h5");
    EXPECT_EQ(r.code, 0) << r.err;
    return card;
  }
  // Runs `pnc material drive` and reads the CSV it wrote (column name -> values per step).
  std::map<std::string, std::vector<double>> drive(const std::string& card, const std::string& path,
                                                   const std::string& out = "out.csv",
                                                   const std::string& extra = "--no-plot") const {
    const CliResult r =
        run("material drive '" + card + "' --path " + path + " --out " + out + " " + extra);
    EXPECT_EQ(r.code, 0) << r.err;
    return columns(p(out));
  }
  static std::map<std::string, std::vector<double>> columns(const std::string& csv) {
    const CsvTable t = read_csv(csv);
    std::map<std::string, std::vector<double>> c;
    for (std::size_t j = 0; j < t.header.size(); ++j)
      for (const auto& row : t.rows)
        c[t.header[j]].push_back(row[j]);
    return c;
  }
  fs::path dir_;
};

// Constants by name -> C0 + C1(D) of theory.md (1.1)-(1.2), engineering Voigt 11,22,33,23,13,12.
inline Mat6 stiffness(const std::map<std::string, double>& k, const std::array<double, 3>& D) {
  auto c = [&](const char* n) { return k.at(n); };
  Mat6 C = Mat6::Zero();
  C(0, 0) = c("C11") + 2 * c("A1") * D[0];
  C(1, 1) = c("C22") + 2 * c("A5") * D[1];
  C(2, 2) = c("C33") + 2 * c("A9") * D[2];
  C(0, 1) = C(1, 0) = c("C12") + c("A10") * D[0] + c("A11") * D[1];
  C(0, 2) = C(2, 0) = c("C13") + c("A13") * D[0] + c("A15") * D[2];
  C(1, 2) = C(2, 1) = c("C23") + c("A17") * D[1] + c("A18") * D[2];
  C(3, 3) = c("C44") + c("A22") * D[1];
  C(4, 4) = c("C55") + c("A26") * D[2];
  C(5, 5) = c("C66") + c("A24") * D[1];
  return C;
}

} // namespace pnc::test
