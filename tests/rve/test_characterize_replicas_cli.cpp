// pnc characterize --replicas (decision D418): a run's replica count from the command line, and
// --resume with a larger one adds replicas to a run and keeps the ones run.
#include "pnc/rve/replicas.hpp"

#include "characterize_support.hpp"
#include "common/temp_dir.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {
using pnc::test::run_pnc;
using pnc::test::slurp;

/// The replica count of a run's statistics (one slope per replica and case).
std::size_t replicas_of(const nlohmann::json& summary) {
  return summary["statistics"]["cases"][0]["replica_slopes_Pa"].size();
}
} // namespace

// A run of 2 replicas (the recipe has 1: --replicas overrides it) continued with --replicas 3
// runs only the third, with the seed a run of 3 from the start gives it (replica_build_seed),
// and fits the three; the files of the first two are not touched. Fewer replicas, a run of one
// replica, and another change of the recipe are refused, naming the field and the rule.
TEST(RveCharacterizeReplicasCli, ResumeWithMoreReplicasAddsThemAndKeepsTheOnesRun) {
  const auto d = pnc::test::fresh_dir("test_rve_char_more_replicas");
  auto recipe = nlohmann::json::parse(pnc::test::tiny_recipe);
  recipe["equilibrate"]["hot_steps"] = 500; // as the two-replica test: the machinery is tested
  recipe["equilibrate"]["npt_steps"] = 500;
  recipe["deform"]["reference_holds"] = 1;
  std::ofstream(d / "tiny.json") << recipe.dump();
  const std::string out = (d / "out").string();
  const std::string base = "characterize " + (d / "tiny.json").string() + " --out " + out;
  const auto first = run_pnc(base + " --replicas 2 --json --no-plots 2>" + (d / "e1").string());
  ASSERT_TRUE(first.code == 0 || first.code == 3 || first.code == 4)
      << first.code << slurp((d / "e1").string());
  EXPECT_EQ(replicas_of(nlohmann::json::parse(first.out)), 2u);
  EXPECT_FALSE(fs::exists(fs::path(out) / "replica_3"));
  std::vector<fs::path> kept;
  for (const char* rep : {"replica_1", "replica_2"})
    for (const char* f : {"build/rve.data", "equilibrate/final.h5", "cases/case_2/checkpoint.h5",
                          "cases/case_6/checkpoint.h5"})
      kept.push_back(fs::path(out) / rep / f);
  std::vector<fs::file_time_type> times;
  for (const auto& p : kept)
    times.push_back(fs::last_write_time(p));

  // fewer replicas than the run has: refused before anything runs
  const auto fewer = run_pnc(base + " --replicas 1 --resume --no-plots 2>&1");
  EXPECT_EQ(fewer.code, 1);
  EXPECT_NE(fewer.out.find("field 'run.replicas': value '1'"), std::string::npos) << fewer.out;
  EXPECT_NE(fewer.out.find("is fewer than the 2 replicas this run was started with"),
            std::string::npos)
      << fewer.out;
  // another change with the count: refused naming that key, the count named as what may change
  auto other = recipe;
  other["deform"]["steps"] = 4;
  std::ofstream(d / "other.json") << other.dump();
  const auto changed = run_pnc("characterize " + (d / "other.json").string() + " --out " + out +
                               " --replicas 3 --resume --no-plots 2>&1");
  EXPECT_EQ(changed.code, 1);
  EXPECT_NE(changed.out.find("field 'deform.steps': value '4'"), std::string::npos) << changed.out;
  EXPECT_NE(changed.out.find("(run.replicas, to add replicas (D418) may change)"),
            std::string::npos)
      << changed.out;

  // three: only the third replica runs, with its own seed
  const auto more =
      run_pnc(base + " --replicas 3 --resume --json --no-plots 2>" + (d / "e2").string());
  const std::string err = slurp((d / "e2").string());
  ASSERT_TRUE(more.code == 0 || more.code == 3 || more.code == 4) << more.code << err;
  EXPECT_EQ(replicas_of(nlohmann::json::parse(more.out)), 3u);
  EXPECT_NE(err.find("--resume adds replicas 3..3 to the 2 of this run"), std::string::npos) << err;
  EXPECT_NE(err.find("seed " + std::to_string(pnc::rve::replica_build_seed(3, 3))),
            std::string::npos)
      << err;
  for (const int rep : {1, 2}) // replicas 1 and 2 are not built again
    EXPECT_EQ(err.find("seed " + std::to_string(pnc::rve::replica_build_seed(3, rep))),
              std::string::npos)
        << err;
  for (std::size_t i = 0; i < kept.size(); ++i)
    EXPECT_EQ(fs::last_write_time(kept[i]), times[i]) << kept[i];
  for (const char* f : {"build/rve.data", "cases/case_2/checkpoint.h5"})
    EXPECT_TRUE(fs::exists(fs::path(out) / "replica_3" / f)) << f;
  EXPECT_NE(slurp(out + "/replica_3/build/rve.data"), slurp(out + "/replica_1/build/rve.data"));
  EXPECT_EQ(nlohmann::json::parse(slurp(out + "/recipe.json"))["run"]["replicas"], 3);
  // the addition is recorded: a count extended after a result was seen is told apart (D418)
  const auto hist = nlohmann::json::parse(slurp(out + "/replica_history.json"));
  ASSERT_EQ(hist.size(), 1u);
  EXPECT_EQ(hist[0]["from"], 2);
  EXPECT_EQ(hist[0]["to"], 3);
  const std::string told = nlohmann::json::parse(more.out)["statistics"]["replica_history"];
  EXPECT_EQ(told.rfind("2 at first, 3-3 added by --resume (", 0), 0u) << told;
  EXPECT_NE(slurp(out + "/report.md").find("Replicas added to the run (D418): 2 at first"),
            std::string::npos);
  EXPECT_NE(slurp(out + "/report.html").find("2 at first, 3-3 added by --resume"),
            std::string::npos);

  // a run of one replica keeps its files in the run folder: it cannot be extended
  const fs::path one = d / "one";
  fs::create_directories(one);
  auto stored = nlohmann::json::parse(slurp(out + "/recipe.json"));
  stored["run"]["replicas"] = 1;
  std::ofstream(one / "recipe.json") << stored.dump(2) << "\n";
  const auto single = run_pnc("characterize " + (d / "tiny.json").string() + " --out " +
                              one.string() + " --replicas 2 --resume --no-plots 2>&1");
  EXPECT_EQ(single.code, 1);
  EXPECT_NE(single.out.find("a run of one replica keeps its files in the run folder itself"),
            std::string::npos)
      << single.out;
  EXPECT_FALSE(fs::exists(one / "replica_2"));
  fs::remove_all(d);
}
