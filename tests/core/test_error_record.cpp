// core/error_record.hpp: an error recorded in one process is thrown again in another with the
// same kind, message and exit code (what a failed unit of a run folder hands to the driver).
#include "pnc/core/error.hpp"
#include "pnc/core/error_record.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <limits>
#include <string>

namespace {
struct Thrown {
  int code = -1;
  std::string what;
};

Thrown thrown_by(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return {pnc::exit_code_of(e), e.what()};
  }
  return {};
}

/// Records the exception `f` throws (through JSON text, as a state file stores it) and throws
/// it again.
Thrown round_trip(const std::function<void()>& f) {
  nlohmann::json rec;
  try {
    f();
  } catch (const std::exception& e) {
    rec = nlohmann::json::parse(pnc::error_record(e).dump());
  }
  return thrown_by([&] { pnc::rethrow_error_record(rec); });
}
} // namespace

TEST(ErrorRecord, EveryKindComesBackWithItsMessageAndExitCode) {
  const std::function<void()> kinds[] = {
      [] { pnc::fail("r.toml", "deform.steps", "0", "must be an integer in [1, 100000]"); },
      [] { pnc::fail_simulation("RVE box", 120, 0.25, "ps", "volume grew 3x"); },
      [] {
        pnc::fail_simulation("crack 1", -1, std::numeric_limits<double>::quiet_NaN(), "",
                             "left the grid");
      },
      [] { pnc::fail_tool("LAMMPS", "running stage equilibrate/a", "ERROR: x", "a/lammps.log"); },
      [] { throw std::logic_error("an internal slip"); },
  };
  const int codes[] = {1, 6, 6, 7, 2};
  for (int i = 0; i < 5; ++i) {
    const Thrown direct = thrown_by(kinds[i]);
    const Thrown again = round_trip(kinds[i]);
    EXPECT_EQ(direct.code, codes[i]) << i;
    EXPECT_EQ(again.code, direct.code) << i;
    EXPECT_EQ(again.what, direct.what) << i;
  }
}

TEST(ErrorRecord, AMalformedRecordStillThrowsWithoutCrashing) {
  const nlohmann::json bad[] = {nlohmann::json(),
                                nlohmann::json(3),
                                nlohmann::json::array(),
                                {{"exit_code", "7"}},
                                {{"exit_code", 7}, {"tool", 5}},
                                {{"exit_code", 6}, {"step", "x"}, {"time", "y"}}};
  for (const auto& r : bad) {
    const Thrown t = thrown_by([&] { pnc::rethrow_error_record(r); });
    EXPECT_GE(t.code, 1) << r.dump();
    EXPECT_FALSE(t.what.empty()) << r.dump();
  }
  // a record with its kind but no parts keeps the kind
  EXPECT_EQ(thrown_by([] { pnc::rethrow_error_record({{"exit_code", 7}}); }).code, 7);
}
