#pragma once
// The assertions of the short Case III runs (docs/escm.md "Cases II and III", D90-D92, D116),
// shared by the LJ-crystal and the polymer MD regions: j is the `pnc gimp couple --json`
// summary (its crack.csv is read from the path it names); h the continuum cell size.
#include "common/read_csv.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace pnc::test {

// (1) Mode II in the continuum: at every evaluation after the first growth the faces behind the
//     tip slide at least 10 x more than they open (|sliding| >= 10 max(opening, 0): by the D39
//     split G_I/J <= 1/101), and every record with an increment has G_II/J >= 0.99 (same bound).
// (2) Growth by the criterion (D40): the first increment happens at the first evaluation with
//     J >= Gc (the record before it has J < Gc) - J of a record is evaluated before its growth.
// (3) The tip stops at the SVC ring (D81): the last tip is h/2 before the block, never past it.
// (4) The MD region slips along the line only after the continuum tip arrived: no column has
//     slipped before the stop, and at the end at least one column has slipped, the entry
//     column by more than h/2 in the sense of the applied shear (upper row moved in -x).
inline void expect_case_three(const nlohmann::json& j) {
  ASSERT_TRUE(j.contains("crack"));
  const auto rows = read_csv(j["crack_csv"].get<std::string>());
  const auto& c = j["crack"];
  const double h = j["cell_size_m"].get<double>(); // = a0
  const double Gc = c["Gc_J_per_m2"].get<double>();
  const int nmax = c["max_increments"].get<int>();
  ASSERT_GE(nmax, 1);
  const double stop = c["stop_tip_x_m"].get<double>();
  ASSERT_GT(rows.size(), 10u);
  // (1), (2)
  int growths = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& row = rows[k];
    if (row.at("increments") < 1) continue;
    EXPECT_GE(std::abs(row.at("sliding_m")), 10 * std::max(row.at("opening_m"), 0.0))
        << row.at("time_s");
    ASSERT_GT(std::abs(row.at("sliding_m")), 0.0) << row.at("time_s");
    if (k > 0 && row.at("increments") > rows[k - 1].at("increments")) {
      ++growths;
      EXPECT_GE(row.at("J_J_per_m2"), Gc) << row.at("time_s");
      EXPECT_GE(row.at("GII_J_per_m2") / row.at("J_J_per_m2"), 0.99) << row.at("time_s");
      if (rows[k - 1].at("increments") == 0) {
        EXPECT_LT(rows[k - 1].at("J_J_per_m2"), Gc);
      }
    }
  }
  EXPECT_EQ(growths, nmax); // one increment per evaluation (D40)
  // (3)
  EXPECT_EQ(c["last"]["increments"].get<int>(), nmax);
  EXPECT_NEAR(c["last"]["tip_x_m"].get<double>(), stop, 1e-6 * h);
  for (const auto& row : rows)
    EXPECT_LE(row.at("tip_x_m"), stop + 1e-6 * h);
  // (4)
  ASSERT_FALSE(c["time_tip_reached_stop_s"].is_null());
  ASSERT_FALSE(c["time_first_slipped_column_s"].is_null());
  const double t_stop = c["time_tip_reached_stop_s"].get<double>();
  for (const auto& row : rows) {
    if (row.at("time_s") < t_stop) {
      EXPECT_EQ(row.at("md_slipped_columns"), 0.0) << row.at("time_s");
    }
  }
  EXPECT_GT(c["time_first_slipped_column_s"].get<double>(), t_stop);
  EXPECT_GE(c["last"]["md_slipped_columns"].get<int>(), 1);
  EXPECT_LE(c["last"]["md_entry_sliding_m"].get<double>(), -0.5 * h);
}

} // namespace pnc::test
