#pragma once
// Test helpers for the commands that print a parameter layer's declarations (`pnc gimp
// parameters`, `pnc gimp couple-parameters`, ...): the JSON form lists sections[] with
// parameters[] of {name, rule, ...} (core/include/pnc/core/parameters.hpp).
#include "common/run_command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace pnc::test {

/// name -> rule of every entry that `command --format json` prints; a failed command or output
/// that is not JSON is a test failure (and an empty map).
inline std::map<std::string, std::string> declared_rules(const std::string& command) {
  std::map<std::string, std::string> rules;
  const CommandResult r = run_command(command + " --format json");
  EXPECT_EQ(r.code, 0) << command << "\n" << r.out;
  const auto j = nlohmann::json::parse(r.out, nullptr, false);
  if (r.code != 0 || j.is_discarded() || !j.contains("sections")) {
    ADD_FAILURE() << command << " --format json printed no declarations:\n" << r.out;
    return rules;
  }
  for (const auto& s : j.at("sections"))
    for (const auto& p : s.at("parameters"))
      rules[p.at("name").get<std::string>()] = p.at("rule").get<std::string>();
  return rules;
}

/// `command` exits 0 and prints `needle` on stdout.
inline void expect_prints(const std::string& command, const std::string& needle) {
  const CommandResult r = run_command(command);
  EXPECT_EQ(r.code, 0) << command;
  EXPECT_NE(r.out.find(needle), std::string::npos) << command << " printed:\n" << r.out;
}

} // namespace pnc::test
