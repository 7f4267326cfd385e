// The input files of `pnc thermo persistence --input` and `pnc thermo work --input`
// (thermo/src/persistence_parameters.cpp, work_parameters.cpp; decisions D321, D322) and the
// command-line options that take their checks, help and defaults from the declarations
// (app/cli_parameters.hpp, D320). Every key reads back field by field, the command line
// overrides a key (D301), bad input is refused naming the file, the key, the value and the rule,
// and an option outside its declared range is refused with the declaration's own rule. The
// CLI run of the persistence test is two tiny harmonic chains (~2 s each).
#include "common/run_command.hpp"
#include "common/temp_dir.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/params.hpp"
#include "pnc/thermo/persistence_parameters.hpp"
#include "pnc/thermo/ti_parameters.hpp"
#include "pnc/thermo/work_parameters.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>

namespace fs = std::filesystem;
using pnc::thermo::PersistenceSpec;
using pnc::thermo::WorkInput;

namespace {

/// Every field a persistence input sets, compared one by one (exact: the values are copied).
void expect_same(const PersistenceSpec& a, const PersistenceSpec& b) {
  EXPECT_EQ(a.chain, b.chain);
  EXPECT_EQ(a.beads, b.beads);
  EXPECT_EQ(a.angle_K, b.angle_K);
  EXPECT_EQ(a.bond_K, b.bond_K);
  EXPECT_EQ(a.supports, b.supports);
  EXPECT_EQ(a.spring_k, b.spring_k);
  EXPECT_EQ(a.rates, b.rates);
  EXPECT_EQ(a.pull_distance, b.pull_distance);
  EXPECT_EQ(a.timestep_fs, b.timestep_fs);
  EXPECT_EQ(a.hold_steps, b.hold_steps);
  EXPECT_EQ(a.sample_every, b.sample_every);
  EXPECT_EQ(a.blocks, b.blocks);
  EXPECT_EQ(a.temperature, b.temperature);
  EXPECT_EQ(a.seed, b.seed);
}

// Every key at a value other than its default: a key that were not read would show as its
// default. A tiny harmonic chain: 2 rates x (100 hold + 250 or 500 pull steps).
const char* const kEveryPersistenceKey = R"(chain = "harmonic"
beads = 5
angle_k = 400.0
bond_k = 250.0
supports = "roller"
spring_k = 100.0
rates = [0.002, 0.004]
pull_distance = 1.0
timestep = 1.0
hold_steps = 100
sample_every = 2
blocks = 4
temperature = 290.0
seed = 3
)";

/// The same settings as command-line options but the seed (each test gives its own).
const char* const kEveryPersistenceOption =
    "--chain harmonic --beads 5 --angle-k 400 --bond-k 250 --supports roller --spring-k 100 "
    "--rates 0.002,0.004 --pull-distance 1 --timestep 1 --hold-steps 100 --sample-every 2 "
    "--blocks 4 --temperature 290";

PersistenceSpec every_persistence_key() {
  PersistenceSpec s;
  s.chain = "harmonic";
  s.beads = 5;
  s.angle_K = 400.0;
  s.bond_K = 250.0;
  s.supports = "roller";
  s.spring_k = 100.0;
  s.rates = {0.002, 0.004};
  s.pull_distance = 1.0;
  s.timestep_fs = 1.0;
  s.hold_steps = 100;
  s.sample_every = 2;
  s.blocks = 4;
  s.temperature = 290.0;
  s.seed = 3;
  return s;
}

/// The InputError of `parse(toml)` for a file "f.toml" (empty context when none is thrown).
template <class Parse> pnc::ErrorContext refusal(const std::string& toml, Parse parse) {
  try {
    parse(pnc::parse_toml(toml, "f.toml"), "f.toml");
  } catch (const pnc::InputError& e) {
    return e.context();
  }
  return {};
}

struct Case {
  std::string toml, field, value_part, rule_part;
};

template <class Parse> void expect_refusals(const std::vector<Case>& cases, Parse parse) {
  for (const auto& c : cases) {
    const pnc::ErrorContext e = refusal(c.toml, parse);
    EXPECT_EQ(e.source, "f.toml") << c.toml;
    EXPECT_EQ(e.field, c.field) << c.toml;
    EXPECT_NE(e.value.find(c.value_part), std::string::npos) << c.toml << " -> " << e.value;
    EXPECT_NE(e.rule.find(c.rule_part), std::string::npos) << c.toml << " -> " << e.rule;
  }
}

pnc::test::CommandResult pnc_run(const std::string& args) {
  return pnc::test::run_command(std::string(PNC_EXE) + " " + args);
}

/// The option of a declared key as the commands name it: "--" + the key with '_' as '-'.
std::string option_of(const std::string& key) {
  std::string o = "--" + key;
  for (char& c : o)
    if (c == '_') c = '-';
  return o;
}

/// A value outside the declared range of `p` (a number or a string entry), "" when none.
std::string out_of_range(const pnc::Parameter& p) {
  using L = std::numeric_limits<std::int64_t>;
  switch (p.type) {
  case pnc::ParamType::integer:
    return p.int_max < L::max() ? std::to_string(p.int_max + 1) : std::to_string(p.int_min - 1);
  case pnc::ParamType::real:
    return std::isfinite(p.range.hi) ? std::to_string(2 * p.range.hi + 1)
                                     : std::to_string(p.range.lo - 1);
  case pnc::ParamType::string:
    return p.choices.empty() ? "" : "no-such-choice";
  default:
    return "";
  }
}

/// For every number and choice key of `declared`: `pnc <command> OPTION BAD` is refused (exit
/// 1) before anything runs, naming the option, the value and the declaration's rule() word for
/// word; `--help` shows that rule (without "must be ") and the declared default on the option's
/// line. Returns how many keys were checked.
int expect_options_follow(const pnc::Parameters& declared, const std::string& command,
                          const std::function<std::string(const std::string&)>& option) {
  const fs::path out = pnc::test::fresh_dir("test_thermo_options") / "out";
  const auto help = pnc_run(command + " --help");
  EXPECT_EQ(help.code, 0);
  int checked = 0;
  for (const auto& p : declared.parameters()) {
    const std::string bad = out_of_range(p);
    if (bad.empty()) continue;
    ++checked;
    const std::string opt = option(p.path);
    const auto r = pnc_run(command + " " + opt + " " + bad + " --out " + out.string() + " 2>&1");
    EXPECT_EQ(r.code, 1) << opt << ": " << r.out;
    EXPECT_NE(r.out.find(opt + ": value '" + bad + "': " + p.rule()), std::string::npos)
        << opt << ": " << r.out << "\nrule: " << p.rule();
    EXPECT_FALSE(fs::exists(out)) << opt;
    // the help line: "  --points INT=3   quadrature points ...: an integer in [1, 64]"
    const auto at = help.out.find("  " + opt + " ");
    EXPECT_NE(at, std::string::npos) << opt;
    if (at == std::string::npos) continue;
    const auto next = help.out.find("\n  --", at + 3);
    const std::string line = help.out.substr(at, next - at);
    EXPECT_NE(line.find(p.rule().substr(std::string("must be ").size())), std::string::npos)
        << line;
    EXPECT_NE(line.find("=" + (p.default_value.is_string() ? p.default_value.get<std::string>()
                                                           : p.default_value.dump())),
              std::string::npos)
        << line;
  }
  return checked;
}

} // namespace

// A file with every key reads back to the values written, field by field; the commented TOML
// template (`pnc thermo persistence-parameters --format toml`) and an empty file give the
// defaults of PersistenceSpec{}.
TEST(ThermoPersistenceInput, AFileWithEveryKeyReadsBackAndTheTemplateGivesTheDefaults) {
  const PersistenceSpec s = pnc::thermo::parse_persistence_input(
      pnc::parse_toml(kEveryPersistenceKey, "p.toml"), "p.toml");
  expect_same(s, every_persistence_key());
  EXPECT_EQ(pnc::thermo::persistence_input_parameters().parameters().size(), 14u);
  const auto t = pnc_run("thermo persistence-parameters --format toml");
  ASSERT_EQ(t.code, 0);
  expect_same(pnc::thermo::parse_persistence_input(pnc::parse_toml(t.out, "t.toml"), "t.toml"),
              PersistenceSpec{});
  expect_same(pnc::thermo::parse_persistence_input(nlohmann::json::object(), "e.json"),
              PersistenceSpec{});
}

// D301: each key given on the command line replaces the file's; the others stay the file's.
TEST(ThermoPersistenceInput, AGivenOptionOverridesTheFileKeyByKey) {
  PersistenceSpec in = every_persistence_key(), cli;
  cli.seed = 9;
  cli.rates = {0.001, 0.002, 0.003};
  pnc::thermo::override_persistence_input(in, cli, {"seed", "rates"});
  PersistenceSpec want = every_persistence_key();
  want.seed = 9;
  want.rates = {0.001, 0.002, 0.003};
  expect_same(in, want);
  EXPECT_THROW(pnc::thermo::override_persistence_input(in, cli, {"rate"}), std::out_of_range);
}

// Unknown keys (with the nearest allowed one), wrong types, values out of range and the rule
// between keys are refused naming the file, the key, the value and the rule.
TEST(ThermoPersistenceInput, BadKeysAndValuesAreRefusedNamingFileKeyAndRule) {
  expect_refusals(
      {
          {"beds = 4\n", "beds", "", "beads"},
          {"beads = \"4\"\n", "beads", "4", "integer in [3, 200]"},
          {"beads = 201\n", "beads", "201", "integer in [3, 200]"},
          {"timestep = 20.0\n", "timestep", "20", "(0, 10] fs"},
          {"rates = [0.1]\n", "rates", "0.1", "2 to 1000"},
          {"rates = [0.1, -0.2]\n", "rates", "-0.2", "> 0 A/fs"},
          {"chain = \"pe\"\n", "chain", "pe", "\"harmonic\""},
          {"seed = 0\n", "seed", "0", "[1, 800000000]"},
          // the rule between keys: 2 A at 0.025 A/fs and 0.5 fs is 160 samples < 2 x 100 blocks
          {"blocks = 100\n", "rates", "0.025", "fewer than 2 x blocks"},
      },
      pnc::thermo::parse_persistence_input);
  EXPECT_THROW(pnc::thermo::read_persistence_input("p.yaml"), pnc::InputError);
}

// The file and the same options give the same run: the tiny harmonic chain of
// kEveryPersistenceKey set by options (run A) and by the file (run B, --seed 7 overriding the
// file's seed 3, D301) prints the same --json numbers, bit for bit (one serial LAMMPS run per
// rate, same seeds); a key the file set but the run ignored would change them.
TEST(ThermoPersistenceInput, TheFileAndTheSameOptionsGiveTheSameRun) {
  const fs::path d = pnc::test::fresh_dir("test_persistence_input");
  const fs::path f = d / "p.toml";
  std::ofstream(f) << kEveryPersistenceKey;
  const std::string opts = std::string(kEveryPersistenceOption) + " --seed 7";
  const auto a = pnc_run("thermo persistence " + opts + " --no-plots --json --out " +
                         (d / "a").string() + " 2>" + (d / "a.err").string());
  ASSERT_EQ(a.code, 0) << pnc::test::slurp(d / "a.err");
  const auto b =
      pnc_run("thermo persistence --input " + f.string() + " --seed 7 --no-plots --json --out " +
              (d / "b").string() + " 2>" + (d / "b.err").string());
  ASSERT_EQ(b.code, 0) << pnc::test::slurp(d / "b.err");
  auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  for (const char* k : {"h5", "report", "wall_s"}) {
    ja.erase(k);
    jb.erase(k);
  }
  ASSERT_EQ(ja["rates"].size(), 2u);
  EXPECT_EQ(ja["chain"], "harmonic");
  EXPECT_EQ(ja["temperature_K"], 290.0);
  EXPECT_EQ(ja, jb);
  // a file key against an option: --blocks 100 with the file's rates is refused before any
  // run, the source named as the file with the command line
  const auto c = pnc_run("thermo persistence --input " + f.string() + " --blocks 100 --out " +
                         (d / "c").string() + " 2>&1");
  EXPECT_EQ(c.code, 1);
  EXPECT_NE(c.out.find(f.string() + " with the command line"), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("fewer than 2 x blocks"), std::string::npos) << c.out;
  EXPECT_FALSE(fs::exists(d / "c" / "rate_0.h5"));
  fs::remove_all(d);
}

// `from` reads as written (field by field), relative paths taken from the file's folder
// (D322); the command line's --from replaces the file's (D301); bad values are refused naming
// the file, the key, the value and the rule.
TEST(ThermoWorkInput, FromReadsBackRelativeToTheFileAndBadValuesAreRefused) {
  const WorkInput w = pnc::thermo::parse_work_input(
      pnc::parse_toml("from = [\"/runs/a\", \"b\"]\n", "w.toml"), "w.toml");
  EXPECT_EQ(w.from, (std::vector<std::string>{"/runs/a", "b"}));
  const fs::path d = pnc::test::fresh_dir("test_work_input");
  std::ofstream(d / "w.toml") << "from = [\"/runs/a\", \"b\", \"../c\"]\n";
  std::ofstream(d / "w2.json") << R"({"from": ["/runs/a", "b"]})";
  EXPECT_THROW(pnc::thermo::read_work_input((d / "w.toml").string()), pnc::InputError);
  const WorkInput r = pnc::thermo::read_work_input((d / "w2.json").string());
  EXPECT_EQ(r.from, (std::vector<std::string>{"/runs/a", (d / "b").string()}));
  WorkInput in = r, cli;
  cli.from = {"x"};
  pnc::thermo::override_work_input(in, cli, {"from"});
  EXPECT_EQ(in.from, cli.from);
  EXPECT_TRUE(pnc::thermo::parse_work_input(nlohmann::json::object(), "e.json").from.empty());
  expect_refusals(
      {
          {"form = [\"a\"]\n", "form", "", "from"},
          {"from = \"a\"\n", "from", "a", "1 to 2 strings"},
          {"from = []\n", "from", "[]", "1 to 2 strings"},
          {"from = [\"a\", \"b\", \"c\"]\n", "from", "", "1 to 2 strings"},
          {"from = [1]\n", "from[0]", "1", "must be a string"},
          {"from = [\"a\", \"\"]\n", "from[1]", "", "non-empty path"},
      },
      pnc::thermo::parse_work_input);
  fs::remove_all(d);
}

// D320: every number and choice option of thermo ti and thermo persistence is refused outside
// its declared range with the declaration's rule word for word, and --help shows that rule and
// the declared default: the command line cannot drift from the file (and the docs tables).
TEST(ThermoOptions, OutOfRangeOptionsAreRefusedWithTheDeclaredRuleAndHelpShowsIt) {
  // the 19 TI keys but the lists vol and dev (the slurm keys: free strings); the 14
  // persistence keys but the list rates
  EXPECT_GE(expect_options_follow(pnc::thermo::ti_input_parameters(), "thermo ti",
                                  pnc::thermo::ti_option_of),
            17);
  EXPECT_EQ(expect_options_follow(pnc::thermo::persistence_input_parameters(), "thermo persistence",
                                  option_of),
            13);
  // list options: an element out of range names the element and its range; a wrong length the
  // list's rule
  auto r = pnc_run("thermo ti --vol 0,0.2 --out /nonexistent/o 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("--vol: value '0.2': must be a number in [-0.1, 0.1]"), std::string::npos)
      << r.out;
  r = pnc_run("thermo persistence --rates 0.1 --out /nonexistent/o 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("--rates: value '[0.1]': " +
                       pnc::thermo::persistence_input_parameters().at("rates").rule()),
            std::string::npos)
      << r.out;
  r = pnc_run("thermo work --from '' --out /nonexistent/o 2>&1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.out.find("--from: value '': must be a non-empty path"), std::string::npos) << r.out;
  // not a number where one is declared, and NaN: refused naming the option, not converted
  r = pnc_run("thermo ti --points 2.5 --eps0 0.1 --out /nonexistent/o 2>&1");
  EXPECT_NE(r.out.find("--points: value '2.5': must be an integer in [1, 64]"), std::string::npos)
      << r.out;
  r = pnc_run("thermo persistence --temperature nan --out /nonexistent/o 2>&1");
  EXPECT_NE(r.out.find("--temperature: value 'nan': must be a finite number"), std::string::npos)
      << r.out;
}
