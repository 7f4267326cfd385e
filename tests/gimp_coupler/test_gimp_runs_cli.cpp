// `pnc gimp run` and its run directory (core/run_dir.hpp, app/run_control.hpp): one process per
// --out directory (a second one is refused at once, naming the holder), an existing run needs
// --resume, and SIGINT/SIGTERM stop the run at a step boundary with a checkpoint, exit code
// 128 + signal and one line naming the command that continues it; the continued run ends
// bit for bit where the uninterrupted one ends; pnc.log keeps what both sessions printed.
#include "common/run_command.hpp"
#include "common/spawn.hpp"
#include "common/temp_dir.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using pnc::test::slurp;

namespace {

const std::string exe = PNC_EXE;

/// The plate example on one thread, to `end` seconds of simulated time, as dir/in.json.
std::string plate_input(const fs::path& dir, double end) {
  std::ifstream f(std::string(PNC_SOURCE_DIR) + "/examples/gimp/plate_hole_tension.json");
  nlohmann::json j = nlohmann::json::parse(f);
  j["time"]["end"] = end;
  j["threads"] = 1;
  const std::string p = (dir / "in.json").string(); // dir: a fresh_dir
  std::ofstream(p) << j.dump(2);
  return p;
}

std::string run_args(const std::string& in, const fs::path& out) {
  return exe + " gimp run " + in + " --out " + out.string() + " --no-plot";
}

// About 5 s of wall time on one core here (1.8 s was too short after D404/D405 made the step
// 2.7x faster): it must outlast the first progress line (2 s) on a faster machine too, and be
// short for a test.
constexpr double kLongEnd = 8e-4;

} // namespace

TEST(GimpRunDir, SecondProcessOnTheSameDirectoryIsRefusedWhileTheFirstRuns) {
  const fs::path d = pnc::test::fresh_dir("gimp_lock");
  const std::string in = plate_input(d, kLongEnd);
  const fs::path out = d / "out";
  const pid_t first =
      pnc::test::spawn(run_args(in, out) + " --quiet 2>" + (d / "first.txt").string());
  // the lock file names its holder once the first process has the directory
  ASSERT_TRUE(
      pnc::test::wait_for_text((out / ".pnc.lock").string(), "pid " + std::to_string(first), 20));
  // a second process is refused at once (also with --resume), naming the directory and the
  // holder's pid and command
  const auto second = pnc::test::run_command(run_args(in, out) + " --resume --quiet 2>&1");
  EXPECT_EQ(second.code, 1) << second.out;
  EXPECT_NE(second.out.find(out.string()), std::string::npos) << second.out;
  EXPECT_NE(second.out.find("pid " + std::to_string(first)), std::string::npos) << second.out;
  EXPECT_NE(second.out.find("gimp run"), std::string::npos) << second.out;
  // so is a coupled run into the same directory
  const auto couple = pnc::test::run_command(exe + " gimp couple " + in + " --out " + out.string() +
                                             " --resume 2>&1");
  EXPECT_NE(couple.code, 0) << couple.out;
  EXPECT_NE(couple.out.find("pid " + std::to_string(first)), std::string::npos) << couple.out;

  // SIGTERM stops the first one: exit 128 + 15, the resume command named
  ::kill(first, SIGTERM);
  const auto e = pnc::test::wait_for(first, 30);
  ASSERT_TRUE(e.ended);
  EXPECT_EQ(e.code, 128 + SIGTERM) << slurp((d / "first.txt").string());
  EXPECT_NE(slurp((d / "first.txt").string()).find("pnc: interrupted by SIGTERM"),
            std::string::npos);
  // the lock ends with its process: the directory can be continued at once
  const auto third =
      pnc::test::run_command(run_args(in, out) + " --resume --quiet --max-steps " + "100000 2>&1");
  EXPECT_EQ(third.code, 0) << third.out;
  if (!::testing::Test::HasFailure()) fs::remove_all(d); // kept for a look on failure
}

TEST(GimpRunDir, ExistingRunWithoutResumeIsRefusedNamingResume) {
  const fs::path d = pnc::test::fresh_dir("gimp_existing");
  const std::string in = plate_input(d, 2e-5);
  const fs::path out = d / "out";
  const auto a = pnc::test::run_command(run_args(in, out) + " --quiet --max-steps 3 2>&1");
  ASSERT_EQ(a.code, 0) << a.out;
  const std::string ckpt = slurp((out / "checkpoint.h5").string());
  const auto b = pnc::test::run_command(run_args(in, out) + " --quiet 2>&1");
  EXPECT_EQ(b.code, 1) << b.out;
  EXPECT_NE(b.out.find(out.string()), std::string::npos) << b.out;
  EXPECT_NE(b.out.find("--resume"), std::string::npos) << b.out;
  EXPECT_EQ(slurp((out / "checkpoint.h5").string()), ckpt) << "the refused run wrote";
  // with --resume it continues
  const auto c = pnc::test::run_command(run_args(in, out) + " --quiet --resume 2>&1");
  EXPECT_EQ(c.code, 0) << c.out;
  if (!::testing::Test::HasFailure()) fs::remove_all(d); // kept for a look on failure
}

TEST(GimpRunDir, SigintStopsWithTheResumeCommandAndTheResumedRunIsBitForBit) {
  const fs::path d = pnc::test::fresh_dir("gimp_sigint");
  const std::string in = plate_input(d, kLongEnd);
  const auto straight = pnc::test::run_command(run_args(in, d / "a") + " --quiet 2>&1");
  ASSERT_EQ(straight.code, 0) << straight.out;

  const fs::path out = d / "b";
  const std::string err = (d / "b_err.txt").string();
  const pid_t pid = pnc::test::spawn(run_args(in, out) + " 2>" + err);
  // running: the first progress line (every 2 s) comes after the t = 0 checkpoint
  ASSERT_TRUE(pnc::test::wait_for_text(err, "s simulated (", 30)) << slurp(err);
  ::kill(pid, SIGINT);
  const auto e = pnc::test::wait_for(pid, 30);
  ASSERT_TRUE(e.ended);
  const std::string msg = slurp(err);
  EXPECT_EQ(e.code, 128 + SIGINT) << msg;
  EXPECT_NE(msg.find("pnc: interrupted by SIGINT"), std::string::npos) << msg;
  EXPECT_NE(msg.find("continue with: " + exe + " gimp run " + in + " --out " + out.string() +
                     " --no-plot --resume"),
            std::string::npos)
      << msg;
  EXPECT_FALSE(fs::exists(out / "summary.json")) << "stopped before the end";
  // ... but a report saying so first: the reason, where it stopped, what is valid, how to go on
  const std::string md = slurp((out / "report.md").string());
  const auto banner = md.find("Did not finish: interrupted by SIGINT");
  ASSERT_NE(banner, std::string::npos) << md;
  EXPECT_LT(banner, md.find("What was run")) << md;
  EXPECT_NE(md.find("Stopped after step "), std::string::npos) << md;
  EXPECT_NE(md.find(" s."), std::string::npos) << "the time with its unit\n" << md;
  EXPECT_NE(md.find("`checkpoint.h5`: the whole state after step"), std::string::npos) << md;
  EXPECT_NE(md.find("`history.csv`: steps 0 to"), std::string::npos) << md;
  EXPECT_NE(md.find("--no-plot --resume`"), std::string::npos) << md;
  const std::string page = slurp((out / "report.html").string());
  EXPECT_NE(page.find("Did not finish: interrupted by SIGINT"), std::string::npos);
  EXPECT_NE(msg.find("report (stopped early): " + (out / "report.html").string()),
            std::string::npos)
      << msg;

  const auto resumed =
      pnc::test::run_command(run_args(in, out) + " --quiet --resume --json 2>/dev/null");
  ASSERT_EQ(resumed.code, 0) << resumed.out;
  const auto j = nlohmann::json::parse(resumed.out);
  EXPECT_TRUE(j["resumed"].get<bool>());
  EXPECT_GT(j["steps_this_run"].get<long>(), 0);
  EXPECT_LT(j["steps_this_run"].get<long>(), j["steps"].get<long>());
  EXPECT_EQ(slurp((out / "report.md").string()).find("Did not finish"), std::string::npos)
      << "the finished run's report replaces the stopped one";
  EXPECT_EQ(slurp((d / "a" / "history.csv").string()), slurp((out / "history.csv").string()));
  EXPECT_EQ(slurp((d / "a" / "particles.pvd").string()), slurp((out / "particles.pvd").string()));

  // pnc.log keeps both sessions: what the stopped run printed, its exit code, then the resumed
  // run's (core/run_log.hpp)
  const std::string log = slurp((out / "pnc.log").string());
  const auto stopped_end = log.find("--- pnc finished: exit code " + std::to_string(128 + SIGINT));
  const auto second = log.find("--resume --json", log.find("started in"));
  EXPECT_NE(log.find(" err pnc gimp: "), std::string::npos) << log;
  EXPECT_NE(log.find("s simulated ("), std::string::npos) << "the progress line (D344)\n" << log;
  EXPECT_NE(log.find(" err pnc: interrupted by SIGINT"), std::string::npos) << log;
  ASSERT_NE(stopped_end, std::string::npos) << log;
  EXPECT_NE(second, std::string::npos) << log;
  EXPECT_LT(stopped_end, second) << log;
  EXPECT_NE(log.find(" out {"), std::string::npos) << "the --json output is copied too\n" << log;
  EXPECT_NE(log.rfind("--- pnc finished: exit code 0\n"), std::string::npos) << log;
  if (!::testing::Test::HasFailure()) fs::remove_all(d); // kept for a look on failure
}

// --resume compares the input canonically (D339): the same input with other whitespace and key
// order continues the run; a changed value is refused naming the file, the key and both values.
TEST(GimpRunDir, ResumeComparesTheInputAsValuesNotBytes) {
  const fs::path d = pnc::test::fresh_dir("gimp_canonical");
  const std::string in = plate_input(d, 2e-5);
  const fs::path out = d / "out";
  const auto a = pnc::test::run_command(run_args(in, out) + " --quiet --max-steps 3 2>&1");
  ASSERT_EQ(a.code, 0) << a.out;
  nlohmann::json j;
  std::ifstream(in) >> j;

  // a value changed: refused before anything is written
  nlohmann::json changed = j;
  changed["time"]["end"] = 3e-5;
  std::ofstream(in) << changed.dump(2);
  const std::string ckpt = slurp((out / "checkpoint.h5").string());
  const auto b = pnc::test::run_command(run_args(in, out) + " --quiet --resume 2>&1");
  EXPECT_EQ(b.code, 1) << b.out;
  EXPECT_NE(b.out.find(in), std::string::npos) << b.out;
  EXPECT_NE(b.out.find("time.end"), std::string::npos) << b.out;
  EXPECT_NE(b.out.find("3e-05"), std::string::npos) << b.out;
  EXPECT_NE(b.out.find("2e-05"), std::string::npos) << b.out;
  EXPECT_EQ(slurp((out / "checkpoint.h5").string()), ckpt) << "the refused run wrote";

  // the same values, keys in reverse order, other indentation and line breaks: continues
  std::string text = "{\n";
  std::vector<std::string> keys;
  for (const auto& [k, v] : j.items())
    keys.push_back(k);
  for (auto k = keys.rbegin(); k != keys.rend(); ++k)
    text += "      \"" + *k + "\" :\n\t" + j[*k].dump(3) + (k + 1 == keys.rend() ? "\n" : ",\n");
  std::ofstream(in) << text + "}\n\n";
  ASSERT_EQ(nlohmann::json::parse(slurp(in)), j) << text;
  const auto c = pnc::test::run_command(run_args(in, out) + " --quiet --resume --json 2>/dev/null");
  ASSERT_EQ(c.code, 0) << c.out;
  EXPECT_TRUE(nlohmann::json::parse(c.out)["resumed"].get<bool>()) << c.out;
  if (!::testing::Test::HasFailure()) fs::remove_all(d); // kept for a look on failure
}

// No python3-matplotlib (an interpreter whose `import matplotlib` fails): the run is written,
// exit code 0, and the missing plot is a warning in the summary (D337).
TEST(GimpRunDir, MissingMatplotlibIsAWarningAndTheRunIsWritten) {
  const fs::path d = pnc::test::fresh_dir("gimp_nompl");
  const std::string in = plate_input(d, 2e-5);
  fs::create_directories(d / "nompl/matplotlib");
  std::ofstream(d / "nompl/matplotlib/__init__.py")
      << "raise ModuleNotFoundError(\"No module named 'matplotlib'\")\n";
  const fs::path out = d / "out";
  const auto r = pnc::test::run_command(
      "PYTHONPATH='" + (d / "nompl").string() + "' " + exe + " gimp run " + in + " --out " +
      out.string() + " --quiet --max-steps 3 --json 2>" + (d / "err.txt").string());
  ASSERT_EQ(r.code, 0) << r.out << slurp((d / "err.txt").string());
  EXPECT_TRUE(fs::exists(out / "checkpoint.h5"));
  EXPECT_TRUE(fs::exists(out / "history.csv"));
  EXPECT_FALSE(fs::exists(out / "energy.png"));
  const std::string err = slurp((d / "err.txt").string());
  EXPECT_NE(err.find("warning: "), std::string::npos) << err;
  EXPECT_NE(err.find("matplotlib"), std::string::npos) << err;
  EXPECT_EQ(err.find("pnc: error"), std::string::npos) << err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["plot"].is_null()) << r.out;
  if (!::testing::Test::HasFailure()) fs::remove_all(d); // kept for a look on failure
}
