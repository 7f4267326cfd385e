#pragma once
// Test helper: a plan of four units that do no work (pnc/campaign/campaign.hpp), for the tests
// of the plan layer and its executors (tests/campaign/) and of `pnc run-unit` / `pnc status`
// (tests/rve/test_campaign_cli.cpp), and the scratch folder each of their tests writes a plan into.
#include "pnc/campaign/campaign.hpp"

#include "temp_dir.hpp"

#include <filesystem>
#include <string>

namespace pnc::test {

/// a1, a2 (one group), b needs a1, fit (join) needs a2 and b.
inline campaign::Plan toy_plan() {
  campaign::Plan p;
  p.command = "toy";
  p.parameters = {{"x", 1}};
  p.units = {{"a/u_1", "a", "a", {}, false, 1, {}, {"a1"}},
             {"a/u_2", "a", "a", {}, false, 1, {}, {"a2"}},
             {"b", "b", "b", {"a/u_1"}, false, 2, {"a1"}, {"b"}},
             {"fit", "fit", "fit", {"a/u_2", "b"}, true, 1, {}, {}}};
  return p;
}

/// A fresh, empty folder for one test's plan: <temp>/pnc_<tag>_XXXXXX, new per call (fresh_dir,
/// temp_dir.hpp).
inline std::filesystem::path plan_dir(const std::string& tag) {
  return fresh_dir(tag);
}

} // namespace pnc::test
