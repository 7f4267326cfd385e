// The pnc command line as a user meets it: --help, --json, plots, exit codes, and bad input
// that names the file and field and leaves no partial output.
#include "common/temp_dir.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

struct Result {
  int code;
  std::string out, err;
};

class Cli : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = pnc::test::fresh_dir(
        "cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string p(const std::string& n) const { return (dir_ / n).string(); }

  Result run(const std::string& args) const {
    const std::string errf = p("stderr.txt");
    const std::string cmd =
        "cd '" + dir_.string() + "' && '" PNC_EXE "' " + args + " 2>'" + errf + "'";
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
  std::vector<std::string> listing() const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(dir_))
      v.push_back(e.path().filename().string());
    std::sort(v.begin(), v.end());
    return v;
  }
  fs::path dir_;
};

int lines(const std::string& s) {
  int n = 0;
  for (char c : s)
    n += c == '\n';
  return n;
}

} // namespace

TEST_F(Cli, HelpOnEverySubcommand) {
  for (const char* sub : {"", "fit", "card", "card show", "card tables", "synth"}) {
    const Result r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
  EXPECT_NE(run("fit --help").out.find("--json"), std::string::npos);
  EXPECT_NE(run("").code, 0); // a subcommand is required
}

TEST_F(Cli, SynthFitShowWithJson) {
  Result s = run("synth --model pnc --points 80 --noise-mpa 2 --seed 4 --out d.csv --json");
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_EQ(nlohmann::json::parse(s.out)["points"], 480);
  Result f = run("fit --data d.csv --model pnc --out card.h5 --no-plots --json");
  ASSERT_EQ(f.code, 0) << f.err;
  EXPECT_EQ(lines(f.out), 1) << "--json prints exactly one JSON object on stdout";
  const auto j = nlohmann::json::parse(f.out);
  EXPECT_TRUE(j["fit"]["converged"].get<bool>());
  EXPECT_EQ(j["constants"]["C22"]["units"], "Pa");
  // the fit of dissertation-made data finds C22 = 1.153 GPa within 5 of its std errors
  const double c22 = j["constants"]["C22"]["value"], se = j["constants"]["C22"]["std_error"];
  EXPECT_LT(std::abs(c22 - 1.153e9), 5 * se);
  EXPECT_EQ(j["fit"]["r2"].size(), 12u);
  Result c = run("card show card.h5 --json");
  ASSERT_EQ(c.code, 0) << c.err;
  const auto k = nlohmann::json::parse(c.out);
  EXPECT_TRUE(k["moduli"].contains("E2_as_printed"));
  EXPECT_NE(c.err.find("E2 as printed (the source's determinant-ratio formula"), std::string::npos);
}

TEST_F(Cli, FitIsotropicDerivesC44AndB4AndIsRefusedForTheComposite) {
  // decision D396; the tables' pure polymer is far from isotropic (C44 0.109 GPa against
  // (C11 - C12)/2 = 0.056 GPa), so its isotropic card cannot be plainly usable
  ASSERT_EQ(run("synth --model pp --out d.csv").code, 0);
  const Result f = run("fit --data d.csv --model pp --isotropic --out card.h5 --no-plots --json");
  ASSERT_EQ(f.code, 0) << f.err;
  const auto j = nlohmann::json::parse(f.out);
  EXPECT_TRUE(j["fit"]["isotropic"].get<bool>());
  EXPECT_EQ(j["constants"]["C44"]["status"], "derived");
  EXPECT_EQ(j["constants"]["B4"]["status"], "derived");
  const double c11 = j["constants"]["C11"]["value"], c12 = j["constants"]["C12"]["value"];
  EXPECT_NEAR(j["constants"]["C44"]["value"].get<double>(), (c11 - c12) / 2, 1e-9 * c11);
  EXPECT_NE(j["verdict"]["level"], "usable");
  const Result c = run("card show card.h5 --json");
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_TRUE(nlohmann::json::parse(c.out)["fit"]["isotropic"].get<bool>());
  const Result bad = run("fit --data d.csv --model pnc --isotropic --out c2.h5 --no-plots");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.err.find("--isotropic"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("model pp, not of pnc"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(p("c2.h5")));
  // the library's rule on FitOptions::prior, reported on the flag that set it
  const Result other = run("fit --data d.csv --model pnc --prior card.h5 --out c3.h5 --no-plots");
  EXPECT_NE(other.code, 0);
  EXPECT_NE(other.err.find("--prior"), std::string::npos) << other.err;
  EXPECT_NE(other.err.find("another model than pnc"), std::string::npos) << other.err;
  EXPECT_FALSE(fs::exists(p("c3.h5")));
}

TEST_F(Cli, FitDrawsOneFigureOfEveryCase) {
  ASSERT_EQ(run("synth --model pp --points 60 --max-extension 0.3 --out d.h5").code, 0);
  const Result f = run("fit --data d.h5 --model pp --out pp.h5 --json");
  ASSERT_EQ(f.code, 0) << f.err;
  const auto j = nlohmann::json::parse(f.out);
  ASSERT_EQ(j["plots"].size(), 1u) << f.err; // pp_plots/fit.png: cases 2 and 6 in one grid
  for (const auto& png : j["plots"]) {
    const std::string path = (dir_ / png.get<std::string>()).string();
    std::ifstream in(path, std::ios::binary);
    char magic[8] = {0};
    in.read(magic, 8);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG") << path;
    EXPECT_GT(fs::file_size(path), 5000u) << path;
  }
}

// A negative shear (case 9, D424) in the fit's figure: the model line runs along the case, from
// zero to the data's last (most negative) shear, in the panel of sigma12 of case 9.
TEST_F(Cli, FitFigureOfANegativeShearRunsAlongTheCase) {
  ASSERT_EQ(run("synth --model pp --cases 2,9 --points 30 --out d.csv").code, 0);
  const Result f = run("fit --data d.csv --model pp --out pp.h5 --json");
  ASSERT_EQ(f.code, 0) << f.err;
  const auto jobs = nlohmann::json::parse(pnc::test::slurp(p("pp_plots/figures.json")));
  const nlohmann::json* panel = nullptr;
  for (const auto& pn : jobs["figures"][0]["panels"])
    if (pn["title"].get<std::string>().rfind("case 9 (negative simple shear 1-2): σ12", 0) == 0)
      panel = &pn;
  ASSERT_NE(panel, nullptr) << jobs.dump();
  std::vector<double> data_x, line_x;
  for (const auto& s : (*panel)["series"])
    for (const auto& x : s["x"])
      (s["label"] == "NDM fit" ? line_x : data_x).push_back(x.get<double>());
  ASSERT_FALSE(data_x.empty());
  ASSERT_FALSE(line_x.empty());
  const double last = *std::min_element(data_x.begin(), data_x.end());
  EXPECT_LT(last, 0.0);
  EXPECT_EQ(*std::max_element(line_x.begin(), line_x.end()), 0.0);
  EXPECT_NEAR(*std::min_element(line_x.begin(), line_x.end()), last, 1e-12);
}

TEST_F(Cli, BadCsvGivesOneLineErrorAndNoCard) {
  std::ofstream(p("bad.csv"))
      << "case,e11,e22,e33,g23,g13,g12,s11_MPa,s22_MPa,s33_MPa,s23_MPa,s13_MPa,s12_MPa\n"
         "1,0.01,0,0,0,0,0,1,oops,3,0,0,0\n";
  const Result r = run("fit --data bad.csv --out card.h5");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("pnc: error: bad.csv: field 's22_MPa (line 2)': value 'oops'", 0), 0u)
      << r.err;
  EXPECT_EQ(listing(), std::vector<std::string>{"bad.csv"}) << "no card, no temporary file";
}

TEST_F(Cli, BadCardAndBadOptionsAreRefused) {
  std::ofstream(p("junk.h5")) << "junk";
  Result r = run("card show junk.h5");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("junk.h5"), std::string::npos);
  r = run("fit --data x.csv --out c.h5 --loss l1");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("--loss"), std::string::npos) << r.err;
  r = run("synth --model pnc --cases 1,10 --out d.csv"); // 1..9 are registered (D424)
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("'10'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("d.csv")));
}

TEST_F(Cli, CardTablesReproduceTable612) {
  const Result t = run("card tables --model pnc --out t.h5");
  ASSERT_EQ(t.code, 0) << t.err;
  const auto j = nlohmann::json::parse(run("card show t.h5 --json").out);
  EXPECT_NEAR(j["moduli"]["E2_as_printed"].get<double>() / 1e9, 0.567, 0.0005);
  EXPECT_NEAR(j["moduli"]["E2"].get<double>() / 1e9, 0.600, 0.0005);
}

// ---------------------------------------------------------------- the card verdict
namespace {
// Curves that a noise-dominated MD run hands to the fit: a stress offset (30 MPa) that
// sigma = C eps cannot have, scattered by +-1 MPa, with hardly any strain dependence.
void write_offset_csv(const std::string& path, double stress_scale) {
  std::ofstream f(path);
  f << "case,e11,e22,e33,g23,g13,g12,s11_MPa,s22_MPa,s33_MPa,s23_MPa,s13_MPa,s12_MPa\n";
  for (int c = 1; c <= 6; ++c)
    for (int k = 1; k <= 20; ++k) {
      double e[6] = {0, 0, 0, 0, 0, 0};
      e[c - 1] = (c <= 3 ? 0.2 : 0.4) * k / 20; // Voigt index of case c is c - 1
      f << c;
      for (double v : e)
        f << ',' << v;
      for (int i = 0; i < 6; ++i)
        f << ',' << stress_scale * (30 + ((k * 7 + i * 3 + c) % 5 - 2) * 0.5);
      f << '\n';
    }
}
} // namespace

TEST_F(Cli, NotUsableCardIsWrittenMarkedAndExitsFour) {
  write_offset_csv(p("noise.csv"), 1.0);
  const Result f = run("fit --data noise.csv --model pnc --out card.h5 --no-plots --json");
  EXPECT_EQ(f.code, 4) << f.err; // documented: a card written with the verdict "not usable"
  ASSERT_TRUE(fs::exists(p("card.h5")));
  const auto j = nlohmann::json::parse(f.out);
  EXPECT_EQ(j["verdict"]["level"], "not usable");
  EXPECT_NE(f.err.find("NOT USABLE"), std::string::npos) << f.err;
  const Result c = run("card show card.h5 --json");
  EXPECT_EQ(c.code, 0) << c.err;
  EXPECT_NE(c.err.find("verdict: not usable"), std::string::npos) << c.err;
  EXPECT_EQ(nlohmann::json::parse(c.out)["verdict"]["level"], "not usable");
}

TEST_F(Cli, StressesInPascalAreRefusedAsAUnitMistake) {
  // Synthetic curves of the tables' law, their Pa values under MPa column names.
  ASSERT_EQ(run("synth --model pnc --points 30 --noise-mpa 1 --seed 3 --out d.csv").code, 0);
  std::ifstream in(p("d.csv"));
  std::ofstream out(p("pa.csv"));
  std::string line;
  while (std::getline(in, line)) {
    for (std::size_t at = 0;
         line.rfind("case", 0) == 0 && (at = line.find("_Pa", at)) != std::string::npos; at += 4)
      line.replace(at, 3, "_MPa");
    out << line << '\n';
  }
  out.close();
  const Result r = run("fit --data pa.csv --out card.h5 --no-plots");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("Pa instead of MPa"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("card.h5")));
}

// D342: `pnc synth` writes the stresses in Pa under names that say so; the same curves in
// MPa columns, or under the bare names of older files (read as MPa, with a warning), give
// the same card.
TEST_F(Cli, SynthFitGivesTheSameCardFromEverySpellingOfTheStressColumns) {
  ASSERT_EQ(run("synth --model pp --points 40 --noise-mpa 1 --seed 5 --out si.csv").code, 0);
  std::ifstream in(p("si.csv"));
  std::string line, header;
  std::vector<std::string> rows;
  while (std::getline(in, line))
    if (line.rfind("case", 0) == 0)
      header = line;
    else if (!line.empty() && line[0] != '#')
      rows.push_back(line);
  ASSERT_EQ(header, "case,e11,e22,e33,g23,g13,g12,s11_Pa,s22_Pa,s33_Pa,s23_Pa,s13_Pa,s12_Pa,"
                    "sd11_Pa,sd22_Pa,sd33_Pa,sd23_Pa,sd13_Pa,sd12_Pa");
  for (const auto& [name, suffix] : {std::pair{"mpa.csv", "_MPa"}, std::pair{"legacy.csv", ""}}) {
    std::string h = header;
    for (std::size_t at = 0; (at = h.find("_Pa", at)) != std::string::npos;)
      h.replace(at, 3, suffix);
    std::ofstream out(p(name));
    out.precision(17);
    out << h << '\n';
    for (const auto& r : rows) {
      std::stringstream ss(r);
      std::string cell;
      for (int col = 0; std::getline(ss, cell, ','); ++col)
        if (col < 7)
          out << (col ? "," : "") << cell;
        else
          out << ',' << std::stod(cell) / 1e6; // Pa -> MPa, 17 significant digits
      out << '\n';
    }
  }
  nlohmann::json card[3];
  const char* files[3] = {"si.csv", "mpa.csv", "legacy.csv"};
  for (int i = 0; i < 3; ++i) {
    const Result f = run(std::string("fit --data ") + files[i] + " --model pp --out c" +
                         std::to_string(i) + ".h5 --no-plots --json");
    ASSERT_EQ(f.code, 0) << files[i] << ": " << f.err;
    card[i] = nlohmann::json::parse(f.out)["constants"];
    const bool warned = f.err.find("pnc: warning: legacy.csv: columns s11,s22,s33,s23,s13,s12,"
                                   "sd11,sd22,sd33,sd23,sd13,sd12 have no unit suffix and are "
                                   "read as MPa (deprecated;") != std::string::npos;
    EXPECT_EQ(warned, i == 2) << files[i] << ": " << f.err;
  }
  ASSERT_FALSE(card[0].empty());
  for (const auto& [name, c] : card[0].items()) {
    const double a = c["value"], b = card[1][name]["value"], legacy = card[2][name]["value"];
    // the same text and the same MPa -> Pa conversion: the same doubles, the same fit
    EXPECT_EQ(legacy, b) << name;
    // Pa and MPa texts of one value read to doubles at most 1 ulp apart; the fit moves by
    // (condition) x 1e-16, or, if that flips the solver's stop, by one last step, which
    // changes the cost by < function_tolerance (1e-12) x cost (~ N/2 = 120 for 240 points):
    // |da|/SE ~ sqrt(2 x 1e-12 x 120) = 1.5e-5. 1e-4 SE bounds both.
    if (c["std_error"].is_number())
      EXPECT_LE(std::abs(a - b), 1e-4 * c["std_error"].get<double>()) << name;
    else
      EXPECT_EQ(a, b) << name;
  }
}

TEST_F(Cli, CardShowReportsTheFirstStrengthPeak) {
  // Table 6.13: the nanocomposite's strength 189.37 MPa is the first local maximum of
  // sigma22 in case 2 (the stress rises again later); 3-digit constants: 0.2 %.
  ASSERT_EQ(run("card tables --model pnc --out t.h5").code, 0);
  const auto j = nlohmann::json::parse(run("card show t.h5 --json").out);
  bool found = false;
  for (const auto& s : j["strengths"])
    if (s["case"] == 2) {
      ASSERT_FALSE(s["peak_Pa"].is_null());
      EXPECT_NEAR(s["peak_Pa"].get<double>() / 1e6, 189.37, 189.37 * 2e-3);
      found = true;
    }
  EXPECT_TRUE(found);
  EXPECT_EQ(j["verdict"]["level"], "usable");
}

// --out is judged as the user gave it: a link, fifo or directory is never replaced, an empty
// name or a path under a regular file is a bad input (exit 1) naming the path and the rule,
// never an internal error and never a temporary file name.
TEST_F(Cli, OutputThatIsNotARegularFileIsRefused) {
  std::ofstream(p("victim.txt")) << "keep";
  fs::create_symlink(p("victim.txt"), p("link.csv"));
  ASSERT_EQ(::mkfifo(p("fifo.csv").c_str(), 0644), 0);
  for (const char* out : {"link.csv", "fifo.csv"}) {
    const Result r = run(std::string("synth --model pp --points 10 --out ") + out);
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind(std::string("pnc: error: ") + out + ": field '--out'", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("regular file"), std::string::npos) << r.err;
  }
  EXPECT_TRUE(fs::is_symlink(p("link.csv")));
  EXPECT_TRUE(fs::is_fifo(p("fifo.csv")));
  std::ifstream v(p("victim.txt"));
  std::string s;
  v >> s;
  EXPECT_EQ(s, "keep");
  const Result c = run("card tables --model pp --out link.csv");
  EXPECT_EQ(c.code, 1) << c.err;
  EXPECT_TRUE(fs::is_symlink(p("link.csv")));
  EXPECT_EQ(listing(), (std::vector<std::string>{"fifo.csv", "link.csv", "victim.txt"}));
}

TEST_F(Cli, EmptyOrUnwritableOutputIsABadInputNamingThePath) {
  std::ofstream(p("file.txt")) << "a file";
  Result r = run("synth --model pp --points 10 --out ''");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("field '--out'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("must not be empty"), std::string::npos) << r.err;
  // a directory that cannot exist (its parent is a regular file): root cannot write there either
  for (const char* cmd : {"synth --model pp --points 10 --out file.txt/out.h5",
                          "card tables --model pp --out file.txt/out.h5",
                          "fit --data file.txt --out file.txt/out.h5"}) {
    r = run(cmd);
    EXPECT_EQ(r.code, 1) << cmd << ": " << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.rfind("pnc: error: file.txt/out.h5: field '--out'", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("not a directory"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(".tmp"), std::string::npos) << "names the temporary file: " << r.err;
  }
#ifdef PNC_TEST_HAVE_RVE // built with the rve commands (tests/app/CMakeLists.txt)
  r = run("rve build --chains 2 --beads 4 --out file.txt/rve");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("pnc: error: file.txt/rve: field '--out'", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("not a directory"), std::string::npos) << r.err;
#endif
  EXPECT_EQ(listing(), std::vector<std::string>{"file.txt"});
}

// ------------------------------------------------------------------ hardening
namespace {
std::string deep_json(int levels) {
  return std::string(static_cast<std::size_t>(levels), '[') +
         std::string(static_cast<std::size_t>(levels), ']');
}
bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}
} // namespace

// Numeric options have stated ranges; NaN and infinities are refused (CLI::Range lets NaN
// through), before anything is computed or written.
TEST_F(Cli, SynthNumbersOutsideTheirRangeOrNonFiniteAreRefused) {
  for (const char* bad :
       {"--points 2e9", "--points 2000000000", "--noise-mpa inf", "--noise-mpa nan",
        "--noise-mpa -1", "--max-extension nan", "--max-shear inf"}) {
    const Result r = run(std::string("synth --model pp ") + bad + " --out d.csv");
    EXPECT_NE(r.code, 0) << bad;
    EXPECT_NE(r.code, 2) << bad << ": " << r.err; // not an internal error
    const std::string opt = std::string(bad).substr(0, std::string(bad).find(' '));
    EXPECT_TRUE(has(r.err, opt)) << bad << ": " << r.err;
    EXPECT_FALSE(fs::exists(p("d.csv"))) << bad;
  }
  EXPECT_EQ(run("synth --model pp --points 5 --noise-mpa 0 --out d.csv").code, 0);
}

TEST_F(Cli, FitAndCardShowRefuseNonFiniteOptions) {
  for (const char* bad :
       {"fit --data x.csv --out c.h5 --alpha nan", "fit --data x.csv --out c.h5 --loss-scale inf",
        "fit --data x.csv --out c.h5 --loss-scale nan", "card show c.h5 --max-strain nan"}) {
    const Result r = run(bad);
    EXPECT_NE(r.code, 0) << bad;
    EXPECT_TRUE(has(r.err, "FINITE") || has(r.err, "not finite")) << bad << ": " << r.err;
  }
}

// rve build: the bead count has a range (no std::bad_alloc from a huge request).
TEST_F(Cli, RveBuildRefusesHugeBeadCounts) {
  for (const char* bad : {"--beads 1e9", "--chains 1e9", "--density nan"}) {
    const Result r = run(std::string("rve build ") + bad + " --out o");
    EXPECT_NE(r.code, 0) << bad;
    EXPECT_NE(r.code, 2) << bad << ": " << r.err;
    EXPECT_FALSE(has(r.err, "bad_alloc")) << r.err;
  }
  const Result r = run("rve build --chains 100000 --beads 10000 --out o");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "field 'build.chains'")) << r.err;
  EXPECT_TRUE(has(r.err, "at most 1000000")) << r.err;
  EXPECT_FALSE(fs::exists(p("o/rve.data")));
}

// Deeply nested inputs of every JSON reader: one line naming the file and the limit, exit 1,
// never a signal (SIGSEGV printed the whole value recursively before).
TEST_F(Cli, DeeplyNestedInputsAreOneLineErrors) {
  const std::string deep = deep_json(60000);
  std::ofstream(p("deep.json")) << deep;
  std::ofstream(p("deep_obj.json")) << "{\"dimension\": 2, \"title\": " << deep << "}";
  std::ofstream(p("deep.toml")) << "name = " << deep << "\n";
  // every JSON/TOML-reading subcommand of this build (tests/app/CMakeLists.txt); `fit` reads
  // CSV and HDF5 only
  std::vector<std::string> cmds;
#ifdef PNC_TEST_HAVE_RVE
  cmds.insert(cmds.end(), {"characterize deep.json --out o", "characterize deep.toml --out o"});
#endif
#ifdef PNC_TEST_HAVE_GIMP_COUPLER
  cmds.insert(cmds.end(), {"gimp run deep.json --out o", "gimp run deep_obj.json --out o"});
#ifdef PNC_TEST_HAVE_ESCM
  cmds.push_back("gimp couple deep_obj.json --out o");
#endif
#endif
  ASSERT_FALSE(cmds.empty()) << "this build has no JSON-reading subcommand";
  for (const std::string& c : cmds) {
    const Result r = run(c);
    EXPECT_EQ(r.code, 1) << c << ": " << r.err.substr(0, 300);
    EXPECT_EQ(lines(r.err), 1) << c;
    EXPECT_TRUE(has(r.err, "nest deeper than 64")) << c << ": " << r.err.substr(0, 300);
    EXPECT_LT(r.err.size(), 600u) << c;
  }
}

// gimp run: a time span beyond the stated range is refused before any step; a number beyond
// a double is an input error (exit 1), not an internal error (exit 2).
TEST_F(Cli, GimpRunRefusesEndlessTimeAndOverflowingNumbers) {
  const std::string input = R"({"dimension": 2,
    "grid": {"cells": [8, 8], "cell_size": 0.1},
    "materials": [{"name": "m", "type": "linear_elastic", "density": 1000, "E": 1e9, "nu": 0.3}],
    "bodies": [{"material": "m", "shape": "box", "min": [0.2, 0.2], "max": [0.6, 0.6]}],
    "time": {"end": END}})";
  auto with_end = [&](const std::string& end) {
    std::string t = input;
    t.replace(t.find("END"), 3, end);
    return t;
  };
  std::ofstream(p("long.json")) << with_end("1e300");
  std::ofstream(p("huge.json")) << with_end("1e400");
  Result r = run("gimp run long.json --out o");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "long.json: field 'time.end'")) << r.err;
  r = run("gimp run huge.json --out o2");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "huge.json: not valid JSON")) << r.err;
}

// thermo ti: the LJ cut-off has a range; 1e300 and NaN are refused while parsing the command
// line (before any LAMMPS run).
TEST_F(Cli, ThermoTiRefusesAnAbsurdCutoff) {
  for (const char* bad : {"1e300", "nan", "inf", "0"}) {
    const Result r = run(std::string("thermo ti --demo --out o --cutoff ") + bad);
    EXPECT_NE(r.code, 0) << bad;
    EXPECT_TRUE(has(r.err, "--cutoff")) << bad << ": " << r.err;
    EXPECT_FALSE(fs::exists(p("o"))) << bad;
  }
}
