// core: the one runner of the plot scripts (plot.hpp, D337, D338). A script that cannot be
// drawn is a warning naming the script and the reason; a missing script an InputError naming
// the variable that overrides the lookup; PNC_GIMP_SCRIPTS_DIR a deprecated alias.
#include "pnc/core/error.hpp"
#include "pnc/core/plot.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

/// Sets (or with nullptr unsets) the variables the runner reads; restores them at the end.
struct Env {
  Env(const char* scripts, const char* gimp_scripts, const char* python) {
    put("PNC_SCRIPTS_DIR", scripts);
    put("PNC_GIMP_SCRIPTS_DIR", gimp_scripts);
    put("PNC_PYTHON", python);
  }
  ~Env() {
    for (const char* v : {"PNC_SCRIPTS_DIR", "PNC_GIMP_SCRIPTS_DIR", "PNC_PYTHON"})
      ::unsetenv(v);
  }
  static void put(const char* name, const char* value) {
    if (value)
      ::setenv(name, value, 1);
    else
      ::unsetenv(name);
  }
};

fs::path fresh_dir(const char* tag) {
  return pnc::test::fresh_dir(std::string("plot_") + tag);
}

} // namespace

TEST(PlotRunner, ScriptsVariableIsPncScriptsDirAndTheGimpOneADeprecatedAlias) {
  {
    const Env e(nullptr, nullptr, nullptr);
    EXPECT_STREQ(pnc::plot_scripts_variable(), "PNC_SCRIPTS_DIR");
  }
  {
    const Env e("/a", "/b", nullptr); // both set: the documented one wins
    EXPECT_STREQ(pnc::plot_scripts_variable(), "PNC_SCRIPTS_DIR");
  }
  {
    const Env e("", "/b", nullptr); // set but empty counts as unset (locate.hpp)
    EXPECT_STREQ(pnc::plot_scripts_variable(), "PNC_GIMP_SCRIPTS_DIR");
  }
}

TEST(PlotRunner, TheAliasDirectoryIsUsedAndAScriptRunsWithItsArguments) {
  const fs::path d = fresh_dir("alias");
  // a stand-in script that "draws" the PNG named by its argument, as the real ones report it
  std::ofstream(d / "mine.py") << "import sys\nprint('wrote ' + sys.argv[1])\n";
  const Env e(nullptr, d.c_str(), nullptr);
  const pnc::PlotRun r = pnc::run_plot("mine.py", {"a b;'c'.png"});
  EXPECT_TRUE(r.ok()) << r.warning;
  EXPECT_EQ(r.script, (d / "mine.py").string());
  ASSERT_EQ(r.pngs.size(), 1u) << r.output;
  EXPECT_EQ(r.pngs[0], "a b;'c'.png") << "one argument, no shell";
  fs::remove_all(d);
}

TEST(PlotRunner, AFailingInterpreterIsAWarningNamingTheScript) {
  const Env e(nullptr, nullptr, "/bin/false"); // as a python3 without matplotlib exits 1
  const pnc::PlotRun r = pnc::run_plot("plot_energy.py", {"h.csv", "e.png", "t"});
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(r.pngs.empty());
  EXPECT_NE(r.warning.find("plot_energy.py: plotting failed (exit status 1"), std::string::npos)
      << r.warning;
  EXPECT_NE(r.warning.find("python3-matplotlib"), std::string::npos) << r.warning;
  std::string w;
  EXPECT_TRUE(pnc::run_plot_script("plot_energy.py", {}, &w).empty());
  EXPECT_EQ(w, r.warning);
}

TEST(PlotRunner, AnInterpreterThatCannotStartIsAWarning) {
  const Env e(nullptr, nullptr, "/nonexistent/python3");
  const pnc::PlotRun r = pnc::run_plot("plot_energy.py", {});
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.warning.find("/nonexistent/python3: cannot start the Python interpreter"),
            std::string::npos)
      << r.warning;
}

TEST(PlotRunner, AMissingScriptIsAnInputErrorNamingTheVariableUsed) {
  const fs::path d = fresh_dir("empty");
  for (const bool alias : {false, true}) {
    const Env e(alias ? nullptr : d.c_str(), alias ? d.c_str() : nullptr, nullptr);
    try {
      (void)pnc::run_plot("plot_energy.py", {});
      ADD_FAILURE() << "no error";
    } catch (const pnc::InputError& x) {
      const std::string m = x.what();
      EXPECT_NE(m.find(alias ? "PNC_GIMP_SCRIPTS_DIR" : "PNC_SCRIPTS_DIR"), std::string::npos) << m;
      EXPECT_NE(m.find(d.string()), std::string::npos) << m;
    }
  }
  fs::remove_all(d);
}
