// The error contract of `pnc` as a user meets it (docs/errors.md, core/error.hpp): every exit
// code from a real case through the built executable, one line "pnc: error: ..." on stderr,
// command-line mistakes answered with the nearest valid names, --help showing defaults, and
// a plot that cannot be drawn a warning, not an error. pnc runs with an argument vector
// (fork + execve, no shell); stdout and stderr go to files.
#include "common/temp_dir.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using pnc::test::slurp;

namespace {

struct PncRun {
  int code = -1; ///< exit status (-1: killed by a signal)
  std::string out, err;
};

int lines(const std::string& s) {
  int n = 0;
  for (char c : s)
    n += c == '\n';
  return n;
}

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

class PncErrors : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = pnc::test::fresh_dir(
        "errors_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string p(const std::string& n) const { return (dir_ / n).string(); }

  /// Starts pnc with `args` in the test directory, `env` added to the environment.
  pid_t start(const std::vector<std::string>& args,
              const std::vector<std::string>& env = {}) const {
    const std::string out = p("stdout.txt"), err = p("stderr.txt");
    const pid_t pid = ::fork();
    if (pid == 0) {
      if (::chdir(dir_.c_str()) != 0) ::_exit(126);
      const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      if (o < 0 || e < 0) ::_exit(126);
      ::dup2(o, 1);
      ::dup2(e, 2);
      for (const auto& kv : env)
        ::putenv(const_cast<char*>(kv.c_str()));
      std::vector<char*> argv{const_cast<char*>(PNC_EXE)};
      for (const auto& a : args)
        argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv(PNC_EXE, argv.data());
      ::_exit(127);
    }
    return pid;
  }
  PncRun finish(pid_t pid) const {
    int st = 0;
    while (::waitpid(pid, &st, 0) < 0) {
    }
    return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, slurp(p("stdout.txt")), slurp(p("stderr.txt"))};
  }
  PncRun run(const std::vector<std::string>& args, const std::vector<std::string>& env = {}) const {
    return finish(start(args, env));
  }
  fs::path dir_;
};

} // namespace

// ------------------------------------------------------------------ command-line mistakes

TEST_F(PncErrors, UnknownSubcommandNamesTheNearestValidNames) {
  PncRun r = run({"fitt"});
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, "pnc: error: unknown subcommand 'fitt' (did you mean: fit?)\n");
  EXPECT_EQ(r.out, "");
  // nested: the subcommand of `pnc card`
  r = run({"card", "shwo", "c.h5"});
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, "pnc: error: unknown subcommand 'shwo' of 'pnc card' (did you mean: show?)\n");
  // nothing near: the valid names listed
  r = run({"card", "tablez"});
  EXPECT_TRUE(has(r.err, "(did you mean: tables?)")) << r.err;
  r = run({"zzzzzzzz"});
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.err, "unknown subcommand 'zzzzzzzz' (valid: ")) << r.err;
  EXPECT_TRUE(has(r.err, "fit") && has(r.err, "synth") && has(r.err, "card")) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
}

TEST_F(PncErrors, UnknownOptionNamesTheNearestOption) {
  const PncRun r = run({"fit", "--dta", "d.csv", "--out", "c.h5"});
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, "pnc: error: unknown option '--dta' for 'pnc fit' (did you mean: --data?)\n");
  EXPECT_FALSE(fs::exists(p("c.h5")));
  const PncRun s = run({"synth", "--model", "pp", "--point", "5", "--out", "d.csv"});
  EXPECT_EQ(s.code, 1);
  EXPECT_TRUE(has(s.err, "unknown option '--point' for 'pnc synth' (did you mean: --points?)"))
      << s.err;
}

// Every other CLI11 parse error: one line "pnc: error: ...", exit 1 (not CLI11's own codes
// 105-110), the help command to run named, nothing on stdout.
TEST_F(PncErrors, EveryParseErrorIsOneLineAndExitsOne) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{}, "subcommand"},                                                      // none given
      {{"fit", "--out", "c.h5"}, "--data"},                                    // required option
      {{"fit", "--data", "d.csv", "--out", "c.h5", "--loss", "l1"}, "--loss"}, // not a member
      {{"synth", "--points", "many", "--out", "d.csv"}, "--points"},           // not a number
      {{"synth", "--points", "2", "--out", "d.csv"}, "--points"},              // out of range
      {{"card", "show", "a.h5", "b.h5"}, "b.h5"},                              // extra argument
      {{"card"}, "subcommand"}};                                               // none given
  for (const auto& [args, named] : cases) {
    std::string cmd;
    for (const auto& a : args)
      cmd += a + " ";
    const PncRun r = run(args);
    EXPECT_EQ(r.code, 1) << cmd << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << cmd << ": " << r.err;
    EXPECT_EQ(r.err.rfind("pnc: error: ", 0), 0u) << cmd << ": " << r.err;
    EXPECT_TRUE(has(r.err, named)) << cmd << ": " << r.err;
    EXPECT_TRUE(has(r.err, "--help'")) << cmd << ": " << r.err;
    EXPECT_EQ(r.out, "") << cmd;
  }
  EXPECT_FALSE(fs::exists(p("d.csv")));
  EXPECT_FALSE(fs::exists(p("c.h5")));
}

TEST_F(PncErrors, HelpShowsDefaultsAndHelpAndVersionExitZero) {
  const PncRun h = run({"synth", "--help"});
  EXPECT_EQ(h.code, 0) << h.err;
  EXPECT_EQ(h.err, "");
  // the defaults of SynthArgs (app/commands.hpp) appear on their options' lines
  auto line_of = [](const std::string& text, const std::string& opt) {
    const auto at = text.find("  " + opt + " ");
    if (at == std::string::npos) return std::string();
    return text.substr(at, text.find('\n', at) - at);
  };
  EXPECT_TRUE(has(line_of(h.out, "--points"), "200")) << h.out;
  EXPECT_TRUE(has(line_of(h.out, "--noise-mpa"), "2")) << h.out;
  EXPECT_TRUE(has(line_of(h.out, "--model"), "pnc")) << h.out;
  const PncRun f = run({"fit", "--help"});
  EXPECT_EQ(f.code, 0);
  EXPECT_TRUE(has(line_of(f.out, "--max-iterations"), "200")) << f.out;
  EXPECT_TRUE(has(line_of(f.out, "--loss"), "none")) << f.out;
  const PncRun v = run({"--version"});
  EXPECT_EQ(v.code, 0);
  EXPECT_TRUE(has(v.out, "pnc")) << v.out;
}

// ------------------------------------------------------------------ each exit code, for real

TEST_F(PncErrors, BadInputFileExitsOneNamingFileFieldValue) {
  std::ofstream(p("bad.csv"))
      << "case,e11,e22,e33,g23,g13,g12,s11_Pa,s22_Pa,s33_Pa,s23_Pa,s13_Pa,s12_Pa\n"
         "1,0.01,0,0,0,0,0,1e6,2e6,3e6,0,0,zero\n";
  const PncRun r = run({"fit", "--data", "bad.csv", "--out", "c.h5", "--no-plots"});
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("pnc: error: bad.csv: field 's12_Pa (line 2)': value 'zero'", 0), 0u)
      << r.err;
}

// A solver stopped after one iteration has not converged: exit 3, the card written (the
// verdict of a card from dissertation-made data is not "not usable", which would be 4).
TEST_F(PncErrors, FitStoppedBeforeConvergenceExitsThree) {
  ASSERT_EQ(run({"synth", "--model", "pp", "--points", "40", "--seed", "2", "--out", "d.csv"}).code,
            0);
  const PncRun r = run({"fit", "--data", "d.csv", "--model", "pp", "--out", "c.h5", "--no-plots",
                        "--max-iterations", "1", "--json"});
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_TRUE(has(r.err, "pnc: error: the fit did not converge")) << r.err;
  EXPECT_TRUE(fs::exists(p("c.h5")));
  const auto j = nlohmann::json::parse(r.out); // --json: still one object on stdout
  EXPECT_FALSE(j["fit"]["converged"].get<bool>());
  EXPECT_NE(j["verdict"]["level"], "not usable");
}

// No python3-matplotlib (here: an interpreter that fails): the card is written, the command
// succeeds, one warning line says the plot is missing.
TEST_F(PncErrors, PlotThatCannotBeDrawnIsAWarning) {
  ASSERT_EQ(run({"synth", "--model", "pp", "--points", "40", "--out", "d.csv"}).code, 0);
  const PncRun r = run({"fit", "--data", "d.csv", "--model", "pp", "--out", "c.h5", "--json"},
                       {"PNC_PYTHON=/bin/false"});
  EXPECT_EQ(r.code, 0) << r.err;
  // the figure pipeline's one line (app/figures.cpp), naming the script that failed
  EXPECT_TRUE(has(r.err, "pnc fit: warning: figures not drawn: ")) << r.err;
  EXPECT_TRUE(has(r.err, "plot_figures.py: plotting failed")) << r.err;
  std::size_t warnings = 0;
  for (std::size_t at = r.err.find("warning"); at != std::string::npos;
       at = r.err.find("warning", at + 1))
    ++warnings;
  EXPECT_EQ(warnings, 1u) << r.err;
  EXPECT_FALSE(has(r.err, "pnc: error")) << r.err;
  EXPECT_TRUE(fs::exists(p("c.h5")));
  EXPECT_EQ(nlohmann::json::parse(r.out)["plots"].size(), 0u);
}

#ifdef PNC_TEST_HAVE_RVE
// A LAMMPS input with a bad command: LAMMPS ends the supervised stage; pnc exits 7 with
// LAMMPS's own ERROR line and the log to read, on one line.
TEST_F(PncErrors, LammpsFailureIsAToolErrorWithItsMessageAndLog) {
  std::ofstream(p("bad.in")) << "units real\nno_such_command_xyz 1 2\n";
  const PncRun r = run({"rve", "lammps", "bad.in", "--log", "bad.log"});
  EXPECT_EQ(r.code, 7) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("pnc: error: LAMMPS failed while running input bad.in: ERROR", 0), 0u)
      << r.err;
  EXPECT_TRUE(has(r.err, "no_such_command_xyz")) << r.err;
  EXPECT_TRUE(has(r.err, "(log bad.log)")) << r.err;
  EXPECT_TRUE(has(slurp(p("bad.log")), "no_such_command_xyz")); // the log says the same
  // a missing input is the user's to fix (1), not LAMMPS's failure
  const PncRun m = run({"rve", "lammps", "missing.in"});
  EXPECT_EQ(m.code, 1) << m.err;
  EXPECT_TRUE(has(m.err, "no such LAMMPS input file")) << m.err;
}

// A stage of `pnc characterize` that LAMMPS stops (the user's force field names a pair style
// LAMMPS does not have; pnc's own rules for force-field lines let it through): exit 7, the
// stage, LAMMPS's message and the stage log on one line.
TEST_F(PncErrors, CharacterizeStageStoppedByLammpsIsAToolError) {
  const fs::path ex = fs::path(PNC_SOURCE_DIR) / "examples" / "rve" / "lj_fcc";
  fs::copy_file(ex / "fcc.data", p("fcc.data"));
  std::string recipe = slurp(ex / "recipe.toml");
  const std::string good = "\"pair_style lj/cut 8.5\"";
  ASSERT_NE(recipe.find(good), std::string::npos);
  recipe.replace(recipe.find(good), good.size(), "\"pair_style no_such_style 8.5\"");
  std::ofstream(p("recipe.toml")) << recipe;
  const PncRun r = run({"characterize", "recipe.toml", "--out", "o", "--no-plots"});
  EXPECT_EQ(r.code, 7) << r.err;
  const auto at = r.err.find("pnc: error: ");
  ASSERT_NE(at, std::string::npos) << r.err;
  const std::string line = r.err.substr(at);
  EXPECT_EQ(lines(line), 1) << line;
  EXPECT_EQ(line.rfind("pnc: error: LAMMPS failed while running ", 0), 0u) << line;
  EXPECT_TRUE(has(line, "stage equilibrate/")) << line;
  EXPECT_TRUE(has(line, "ERROR: Unrecognized pair style 'no_such_style'")) << line;
  EXPECT_TRUE(has(line, ".log)")) << line;
}
#endif

#ifdef PNC_TEST_HAVE_GIMP_COUPLER
// SIGINT during a long run: exit 128 + 2 with the command that continues it.
TEST_F(PncErrors, InterruptedRunExitsWith128PlusTheSignal) {
  std::ifstream f(std::string(PNC_SOURCE_DIR) + "/examples/gimp/plate_hole_tension.json");
  nlohmann::json j = nlohmann::json::parse(f);
  j["time"]["end"] = 1.0; // far longer than the test waits
  j["threads"] = 1;
  std::ofstream(p("in.json")) << j.dump();
  const pid_t pid = start({"gimp", "run", "in.json", "--out", "o", "--no-plot"});
  // running: the first progress line comes after the t = 0 checkpoint
  const auto t0 = std::chrono::steady_clock::now();
  while (!has(slurp(p("stderr.txt")), "s simulated (") &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ::kill(pid, SIGINT);
  const PncRun r = finish(pid);
  EXPECT_EQ(r.code, 128 + SIGINT) << r.err;
  EXPECT_TRUE(has(r.err, "pnc: interrupted by SIGINT")) << r.err;
  EXPECT_TRUE(has(r.err, "--resume")) << r.err;
}
#endif
