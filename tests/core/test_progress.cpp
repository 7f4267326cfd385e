// pnc::Progress and pnc::Phase (core/progress.hpp, D344, D345) with an injected clock: the line
// format, the ETA against hand-computed values, rate limiting, the last line, the unknown ETA,
// a zero total, and that the lines reach pnc.log.
#include "pnc/core/error.hpp"
#include "pnc/core/progress.hpp"
#include "pnc/core/run_log.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

/// A clock the test moves by hand, and the states a Progress printed.
struct Fake {
  double t = 0;
  std::vector<pnc::ProgressState> lines;
  pnc::ProgressOptions options(double every_s = 0, int lanes = 1) {
    pnc::ProgressOptions o;
    o.every_s = every_s;
    o.lanes = lanes;
    o.clock = [this] { return t; };
    o.sink = [this](const pnc::ProgressState& s) { lines.push_back(s); };
    return o;
  }
};

} // namespace

TEST(Progress, DurationsAreWrittenInSecondsMinutesOrHours) {
  EXPECT_EQ(pnc::format_duration(0), "0.0 s");
  EXPECT_EQ(pnc::format_duration(4.24), "4.2 s");
  EXPECT_EQ(pnc::format_duration(9.96), "10 s");
  EXPECT_EQ(pnc::format_duration(59.4), "59 s");
  EXPECT_EQ(pnc::format_duration(59.6), "1 min 00 s");
  EXPECT_EQ(pnc::format_duration(725), "12 min 05 s");
  EXPECT_EQ(pnc::format_duration(3600), "1 h 00 min");
  EXPECT_EQ(pnc::format_duration(3 * 3600 + 7 * 60 + 10), "3 h 07 min");
  EXPECT_EQ(pnc::format_duration(std::nan("")), "unknown");
}

TEST(Progress, TheLineHasWhatDoneTotalUnitPercentElapsedEtaAndDetail) {
  pnc::ProgressState s{"pnc thermo ti", "lambda points", 3, 5, 64, 42.7, "ref lambda 0.5"};
  EXPECT_EQ(pnc::format_progress(s), "pnc thermo ti: 3/5 lambda points (60.0%), elapsed 1 min "
                                     "04 s, ETA 43 s; ref lambda 0.5");
  s = {"pnc gimp", "s simulated", 2.4e-05, 5e-05, 3, std::nan(""), ""};
  EXPECT_EQ(pnc::format_progress(s),
            "pnc gimp: 2.4e-05/5e-05 s simulated (48.0%), elapsed 3.0 s, ETA unknown");
}

// rate = work of this session / its wall time; ETA = work left / rate
TEST(Progress, EtaIsTheWorkLeftOverTheRateOfTheWorkDone) {
  Fake f;
  pnc::Progress p("run", 10, "steps", f.options());
  EXPECT_TRUE(std::isnan(p.eta_s())) << "nothing done yet";
  f.t = 4;
  ASSERT_TRUE(p.advance(2, "two"));
  ASSERT_EQ(f.lines.size(), 1u);
  EXPECT_DOUBLE_EQ(f.lines[0].elapsed_s, 4);
  EXPECT_DOUBLE_EQ(f.lines[0].eta_s, 4.0 / 2 * 8);
  EXPECT_EQ(f.lines[0].detail, "two");
  f.t = 10;
  p.set(5);
  EXPECT_DOUBLE_EQ(f.lines.back().eta_s, 10.0 / 5 * 5);
  EXPECT_DOUBLE_EQ(p.done(), 5);
}

TEST(Progress, ReusedWorkCountsAsDoneButNotInTheRate) {
  Fake f;
  pnc::Progress p("resume", 10, "points", f.options());
  p.skip(4, "reused");
  ASSERT_EQ(f.lines.size(), 1u);
  EXPECT_TRUE(std::isnan(f.lines[0].eta_s)) << "no work of this session done yet";
  EXPECT_NE(pnc::format_progress(f.lines[0])
                .find("4/10 points (40.0%), elapsed 0.0 s, "
                      "ETA unknown; reused"),
            std::string::npos)
      << pnc::format_progress(f.lines[0]);
  f.t = 3;
  p.advance(2);
  EXPECT_DOUBLE_EQ(f.lines.back().eta_s, 3.0 / 2 * 4) << "not 3 s / 6 points";
}

// 5 points, 2 at a time, 10 s per round: rounds {1,2} {3,4} {5}
TEST(Progress, ParallelLanesCountRoundsThatEndTogether) {
  Fake f;
  pnc::Progress p("ti", 5, "points", f.options(0, 2));
  f.t = 10;
  p.advance(1);
  EXPECT_DOUBLE_EQ(f.lines.back().eta_s, 20) << "rounds {3,4} and {5} left";
  p.advance(1);
  EXPECT_DOUBLE_EQ(f.lines.back().eta_s, 20);
  f.t = 20;
  p.advance(1);
  EXPECT_DOUBLE_EQ(f.lines.back().eta_s, 10) << "2 rounds took 20 s; one round left";
  p.advance(1);
  EXPECT_DOUBLE_EQ(f.lines.back().eta_s, 10);
  f.t = 30;
  p.advance(1);
  EXPECT_DOUBLE_EQ(f.lines.back().eta_s, 0);
}

TEST(Progress, AtMostOneLinePerIntervalAndTheLastLineAlways) {
  Fake f;
  pnc::Progress p("run", 6, "steps", f.options(2.0));
  f.t = 1;
  EXPECT_FALSE(p.advance(1)) << "1 s since the start";
  f.t = 2.5;
  EXPECT_TRUE(p.advance(1));
  f.t = 3;
  EXPECT_FALSE(p.advance(1));
  f.t = 4.4;
  EXPECT_FALSE(p.advance(1)) << "1.9 s since the last line";
  f.t = 4.5;
  EXPECT_TRUE(p.advance(1));
  f.t = 4.6;
  EXPECT_TRUE(p.advance(1)) << "the line that completes the work";
  f.t = 4.7;
  EXPECT_FALSE(p.advance(0)) << "completion is printed once";
  ASSERT_EQ(f.lines.size(), 3u);
  EXPECT_DOUBLE_EQ(f.lines[0].done, 2);
  EXPECT_DOUBLE_EQ(f.lines[1].done, 5);
  EXPECT_DOUBLE_EQ(f.lines[2].done, 6);
  EXPECT_DOUBLE_EQ(f.lines[2].eta_s, 0);
}

TEST(Progress, AZeroTotalIsCompleteAtOnce) {
  Fake f;
  pnc::Progress p("nothing", 0, "files", f.options(10));
  EXPECT_DOUBLE_EQ(p.eta_s(), 0);
  EXPECT_TRUE(p.advance(0));
  EXPECT_FALSE(p.advance(0));
  ASSERT_EQ(f.lines.size(), 1u);
  EXPECT_EQ(pnc::format_progress(f.lines[0]),
            "nothing: 0/0 files (100.0%), elapsed 0.0 s, ETA 0.0 s");
}

TEST(Progress, BadAmountsAreInputErrorsNamingTheField) {
  Fake f;
  try {
    pnc::Progress("x", -1, "steps", f.options());
    FAIL() << "no error";
  } catch (const pnc::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("total"), std::string::npos) << e.what();
  }
  EXPECT_THROW(pnc::Progress("x", std::nan(""), "steps", f.options()), pnc::InputError);
  EXPECT_THROW(pnc::Progress("x", 1, "steps", f.options(0, 0)), pnc::InputError);
  pnc::Progress p("x", 5, "steps", f.options());
  p.set(3);
  EXPECT_THROW(p.set(2), pnc::InputError);
  EXPECT_THROW(p.advance(-1), pnc::InputError);
}

TEST(Progress, ADisabledProgressPrintsNothingButStillCounts) {
  Fake f;
  auto o = f.options();
  o.enabled = false;
  pnc::Progress p("quiet", 2, "steps", o);
  f.t = 1;
  EXPECT_FALSE(p.advance(2));
  EXPECT_TRUE(f.lines.empty());
  EXPECT_DOUBLE_EQ(p.done(), 2);
}

TEST(Progress, APhaseIsAnnouncedAndItsEndTimed) {
  double t = 100;
  std::vector<std::string> out;
  pnc::Phase ph(
      "pnc x", "plotting 2 figures", true, [&](const std::string& l) { out.push_back(l); },
      [&] { return t; });
  ASSERT_EQ(out, std::vector<std::string>{"pnc x: plotting 2 figures ..."});
  t = 165;
  ph.done("plotted 2 figures");
  ph.done("again");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1], "pnc x: plotted 2 figures in 1 min 05 s");
  pnc::Phase quiet("pnc x", "writing", false, [&](const std::string& l) { out.push_back(l); });
  quiet.done("written");
  EXPECT_EQ(out.size(), 2u);
}

// the default sink is std::cerr, so an active run log copies the lines into pnc.log
TEST(Progress, LinesGoToStderrAndIntoTheRunLog) {
  const auto d = pnc::test::fresh_dir("progress_log");
  std::ostringstream term;
  std::streambuf* old = std::cerr.rdbuf(term.rdbuf());
  pnc::start_run_log(d.string(), "pnc demo");
  double t = 0;
  pnc::ProgressOptions o;
  o.clock = [&] { return t; };
  pnc::Progress p("pnc demo", 2, "steps", o);
  t = 1;
  p.advance(1);
  pnc::Phase ph("pnc demo", "writing", true, {}, [&] { return t; });
  pnc::finish_run_log(0);
  std::cerr.rdbuf(old);
  const std::string line = "pnc demo: 1/2 steps (50.0%), elapsed 1.0 s, ETA 1.0 s";
  EXPECT_EQ(term.str(), line + "\npnc demo: writing ...\n");
  std::ifstream f(pnc::run_log_path(d.string()));
  const std::string log((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(log.find(" err " + line + "\n"), std::string::npos) << log;
  EXPECT_NE(log.find(" err pnc demo: writing ...\n"), std::string::npos) << log;
}
