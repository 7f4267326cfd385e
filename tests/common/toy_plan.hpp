#pragma once
// Test helper: a plan of four units that do no work (pnc/campaign/campaign.hpp), for the tests
// of the plan layer and its executors (tests/campaign/) and of `pnc run-unit` / `pnc status`
// (tests/rve/test_campaign_cli.cpp).
#include "pnc/campaign/campaign.hpp"

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

} // namespace pnc::test
