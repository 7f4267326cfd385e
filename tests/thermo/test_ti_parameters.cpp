// The input file of `pnc thermo ti --input` (thermo/src/ti_parameters.cpp, decisions
// D301-D303, D332): its keys read back field by field, the command line overrides a key, bad
// input is refused naming the file, the key and the rule, and the slurm section reaches the
// SlurmSpec the submission gets (its `mpi`, up to the sbatch command lines). The CLI test runs
// a tiny TI twice (one state, 2 nodes, ~100 steps).
#include "common/run_command.hpp"
#include "common/slurm_stand_ins.hpp"
#include "common/temp_dir.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/params.hpp"
#include "pnc/thermo/ti_parameters.hpp"

#include "tiny_polymer.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using pnc::thermo::TiInput;

namespace {

/// Every field a TI input sets, compared one by one (exact: the values are copied, not
/// computed).
void expect_same(const TiInput& a, const TiInput& b) {
  EXPECT_EQ(a.spec.rule, b.spec.rule);
  EXPECT_EQ(a.spec.points, b.spec.points);
  EXPECT_EQ(a.spec.vol, b.spec.vol);
  EXPECT_EQ(a.spec.dev, b.spec.dev);
  EXPECT_EQ(a.spec.path.eps0, b.spec.path.eps0);
  EXPECT_EQ(a.spec.path.eps1, b.spec.path.eps1);
  EXPECT_EQ(a.spec.path.sig0, b.spec.path.sig0);
  EXPECT_EQ(a.spec.path.sig1, b.spec.path.sig1);
  EXPECT_EQ(a.spec.path.cutoff, b.spec.path.cutoff);
  EXPECT_EQ(a.spec.dhdl_method, b.spec.dhdl_method);
  EXPECT_EQ(a.spec.sampling.timestep_fs, b.spec.sampling.timestep_fs);
  EXPECT_EQ(a.spec.sampling.equil_steps, b.spec.sampling.equil_steps);
  EXPECT_EQ(a.spec.sampling.prod_steps, b.spec.sampling.prod_steps);
  EXPECT_EQ(a.spec.sampling.sample_every, b.spec.sampling.sample_every);
  EXPECT_EQ(a.spec.sampling.blocks, b.spec.sampling.blocks);
  EXPECT_EQ(a.spec.sampling.temperature, b.spec.sampling.temperature);
  EXPECT_EQ(a.spec.seed, b.spec.seed);
  EXPECT_EQ(a.spec.jobs, b.spec.jobs);
  EXPECT_EQ(a.spec.ranks, b.spec.ranks);
  EXPECT_EQ(a.executor, b.executor);
  EXPECT_EQ(a.slurm.partition, b.slurm.partition);
  EXPECT_EQ(a.slurm.account, b.slurm.account);
  EXPECT_EQ(a.slurm.time, b.slurm.time);
  EXPECT_EQ(a.slurm.template_path, b.slurm.template_path);
  EXPECT_EQ(a.slurm.mpi, b.slurm.mpi);
}

// Every key at a value other than its default (the slurm section too): a key that were not
// read would show as its default.
const char* const kEveryKey = R"(rule = "trapezoid"
points = 2
vol = [0.0]
dev = []
eps0 = 0.02
eps1 = 0.1
sig0 = 1.0
sig1 = 2.9
cutoff = 7.0
dhdl = "pairs"
timestep = 1.0
equil_steps = 20
prod_steps = 60
sample_every = 10
blocks = 3
temperature = 310.0
seed = 5
jobs = 2
ranks = 2
executor = "slurm"

[slurm]
partition = "short"
account = "proj-1"
time = "0:30:00"
template = "job.sh"
mpi = "pmi2"
)";

/// The input of kEveryKey, set field by field.
TiInput every_key_input() {
  TiInput in;
  in.spec.rule = "trapezoid";
  in.spec.points = 2;
  in.spec.vol = {0.0};
  in.spec.dev = {};
  in.spec.path.eps0 = 0.02;
  in.spec.path.eps1 = 0.1;
  in.spec.path.sig0 = 1.0;
  in.spec.path.sig1 = 2.9;
  in.spec.path.cutoff = 7.0;
  in.spec.dhdl_method = "pairs";
  in.spec.sampling.timestep_fs = 1.0;
  in.spec.sampling.equil_steps = 20;
  in.spec.sampling.prod_steps = 60;
  in.spec.sampling.sample_every = 10;
  in.spec.sampling.blocks = 3;
  in.spec.sampling.temperature = 310.0;
  in.spec.seed = 5;
  in.spec.jobs = 2;
  in.spec.ranks = 2;
  in.executor = "slurm";
  in.slurm.partition = "short";
  in.slurm.account = "proj-1";
  in.slurm.time = "0:30:00";
  in.slurm.template_path = "job.sh";
  in.slurm.mpi = "pmi2";
  return in;
}

/// The InputError of parsing `toml` as file "ti.toml" ("" when none is thrown).
pnc::ErrorContext refusal(const std::string& toml) {
  try {
    pnc::thermo::parse_ti_input(pnc::parse_toml(toml, "ti.toml"), "ti.toml");
  } catch (const pnc::InputError& e) {
    return e.context();
  }
  return {};
}

pnc::test::CommandResult pnc_run(const std::string& args, const fs::path& err) {
  return pnc::test::run_command(std::string(PNC_EXE) + " " + args + " 2>" + err.string());
}

nlohmann::json json_file(const fs::path& p) {
  return nlohmann::json::parse(pnc::test::slurp(p), nullptr, false);
}

} // namespace

// A file with every key reads back to the values written, field by field, and every key has
// its own command-line option.
TEST(ThermoTiInput, AFileWithEveryKeyReadsBackFieldByField) {
  const TiInput in = pnc::thermo::parse_ti_input(pnc::parse_toml(kEveryKey, "ti.toml"), "ti.toml");
  expect_same(in, every_key_input());
  EXPECT_TRUE(in.slurm.given);
  std::set<std::string> options;
  const pnc::Parameters declared = pnc::thermo::ti_input_parameters();
  for (const auto& p : declared.parameters())
    EXPECT_TRUE(options.insert(pnc::thermo::ti_option_of(p.path)).second) << p.path;
  EXPECT_EQ(options.size(), 25u); // 20 TI keys + 5 slurm keys: kEveryKey sets each
  EXPECT_EQ(pnc::thermo::ti_option_of("slurm.mpi"), "--mpi"); // D332: as pnc characterize's
}

// The commented TOML template (`pnc thermo ti-parameters --format toml`) read back gives the
// defaults of TiInput{}; an empty file too.
TEST(ThermoTiInput, TheTemplateAndAnEmptyFileGiveTheDefaults) {
  const std::string toml = pnc::thermo::ti_input_parameters().to_toml();
  expect_same(pnc::thermo::parse_ti_input(pnc::parse_toml(toml, "t.toml"), "t.toml"), TiInput{});
  expect_same(pnc::thermo::parse_ti_input(nlohmann::json::object(), "e.json"), TiInput{});
}

// D301: each key given on the command line replaces the file's; the others, the slurm section
// included, stay the file's. The result's slurm member is the SlurmSpec `pnc thermo ti` hands
// to the submission (app/cmd_thermo_ti.cpp: run_plan_slurm(..., in.slurm, ...)).
TEST(ThermoTiInput, AGivenOptionOverridesTheFileAndTheSlurmSectionReachesTheSubmission) {
  TiInput in = every_key_input(), cli;
  cli.spec.seed = 9;
  cli.spec.vol = {0.0, 0.004};
  cli.slurm.time = "2:00:00";
  cli.slurm.mpi = "pmi1";
  cli.executor = "local";
  pnc::thermo::override_ti_input(in, cli, {"seed", "vol", "slurm.time", "slurm.mpi", "executor"});
  TiInput want = every_key_input();
  want.spec.seed = 9;
  want.spec.vol = {0.0, 0.004};
  want.slurm.time = "2:00:00";
  want.slurm.mpi = "pmi1";
  want.executor = "local";
  expect_same(in, want);
  EXPECT_EQ(in.slurm.partition, "short");
  EXPECT_EQ(in.slurm.template_path, "job.sh");
  EXPECT_THROW(pnc::thermo::override_ti_input(in, cli, {"no_such_key"}), std::out_of_range);
}

// Unknown keys (with the allowed ones and the nearest), wrong types, values out of range and
// broken rules between keys are refused naming the file, the key, the value and the rule.
TEST(ThermoTiInput, BadKeysAndValuesAreRefusedNamingFileKeyAndRule) {
  struct Case {
    std::string toml, field, value_part, rule_part;
  };
  const Case cases[] = {
      {"sampl_every = 10\n", "sampl_every", "", "sample_every"},
      {"points = \"3\"\n", "points", "3", "integer in [1, 64]"},
      {"points = 2.5\n", "points", "2.5", "integer in [1, 64]"},
      {"temperature = -1.0\n", "temperature", "-1", "(0, 10000] K"},
      {"vol = [0.2]\n", "vol", "0.2", "[-0.1, 0.1]"},
      {"dhdl = \"exact\"\n", "dhdl", "exact", "\"virial\""},
      {"executor = \"pbs\"\n", "executor", "pbs", "\"slurm\""},
      {"[slurm]\ntime = \"soon\"\n", "slurm.time", "soon", "Slurm time limit"},
      {"[slurm]\nranks = 2\n", "slurm.ranks", "", "template"}, // the TI key is `ranks` (D324)
      {"[slurm]\nmpi = \"-pmix\"\n", "slurm.mpi", "-pmix", "not starting with '-'"}, // D332
      {"[slurm]\nmpi = \"\"\n", "slurm.mpi", "", "srun's MPI plugin"},
      {"[slurm]\nmpi = 2\n", "slurm.mpi", "2", "string"},
      {"ranks = 0\n", "ranks", "0", "integer in [1, 4096]"},
      {"vol = []\ndev = []\n", "vol/dev", "", "at least one deformation state"},
      {"blocks = 10\nprod_steps = 60\n", "prod_steps", "60", "sample_every * blocks"},
  };
  for (const auto& c : cases) {
    const pnc::ErrorContext e = refusal(c.toml);
    EXPECT_EQ(e.source, "ti.toml") << c.toml;
    EXPECT_EQ(e.field, c.field) << c.toml;
    EXPECT_NE(e.value.find(c.value_part), std::string::npos) << c.toml << " -> " << e.value;
    EXPECT_NE(e.rule.find(c.rule_part), std::string::npos) << c.toml << " -> " << e.rule;
  }
}

// The file and the command line give the same run: a tiny TI with every key set by options
// (run A) and by the file (run B, with --seed overriding the file's seed 5: D301) writes the
// same ti_spec.json, field by field, and the same executor, jobs and ranks into plan.json. A bad
// combination of file and option is refused naming both.
TEST(ThermoTiInput, TheFileAndTheSameOptionsGiveTheSameRunAndAnOptionOverridesTheFile) {
  const fs::path d = pnc::test::fresh_dir("test_ti_input");
  const std::string rs = pnc::test::tiny_polymer_restart(d);
  const fs::path f = d / "ti.toml";
  std::ofstream(f) << kEveryKey;
  const std::string opts = "--rule trapezoid --points 2 --vol 0 --dev none --eps0 0.02 --eps1 0.1 "
                           "--sig0 1.0 --sig1 2.9 --cutoff 7.0 --dhdl pairs --timestep 1.0 "
                           "--equil-steps 20 --prod-steps 60 --sample-every 10 --blocks 3 "
                           "--temperature 310 --seed 7 --jobs 2 --ranks 2 --executor local";
  const auto a =
      pnc_run("thermo ti --restart " + rs + " --no-plots --out " + (d / "a").string() + " " + opts,
              d / "a.err");
  ASSERT_EQ(a.code, 0) << pnc::test::slurp(d / "a.err");
  const auto b = pnc_run("thermo ti --restart " + rs + " --no-plots --out " + (d / "b").string() +
                             " --input " + f.string() + " --seed 7 --executor local",
                         d / "b.err");
  ASSERT_EQ(b.code, 0) << pnc::test::slurp(d / "b.err");
  const auto sa = json_file(d / "a" / "ti_spec.json"), sb = json_file(d / "b" / "ti_spec.json");
  ASSERT_TRUE(sa.is_object());
  EXPECT_EQ(sa.size(), sb.size());
  for (const auto& [k, v] : sa.items())
    EXPECT_EQ(v, sb.value(k, nlohmann::json())) << k;
  EXPECT_EQ(sb["seed"], 7);
  EXPECT_EQ(sb["rule"], "trapezoid");
  const auto pa = json_file(d / "a" / "plan.json")["parameters"];
  const auto pb = json_file(d / "b" / "plan.json")["parameters"];
  for (const char* k : {"executor", "jobs", "ranks"})
    EXPECT_EQ(pa[k], pb[k]) << k;
  EXPECT_EQ(pb["jobs"], 2);
  EXPECT_EQ(pb["ranks"], 2);
  // D324: every lambda point unit runs on the 2 ranks (its Slurm job's --ntasks), the analysis
  // on one
  for (const auto& u : json_file(d / "b" / "plan.json")["units"])
    EXPECT_EQ(u["ranks"], u["kind"] == "lambda_point" ? 2 : 1) << u["id"];
  EXPECT_EQ(pb["input"], fs::absolute(f).string());
  // --blocks 10 from the command line with the file's prod_steps 60 < 10 x 10: refused before
  // anything runs, naming the file
  const auto c = pnc_run("thermo ti --restart " + rs + " --out " + (d / "c").string() +
                             " --input " + f.string() + " --blocks 10 --executor local",
                         d / "c.err");
  EXPECT_EQ(c.code, 1);
  const std::string ce = pnc::test::slurp(d / "c.err");
  EXPECT_NE(ce.find(f.string() + " with the command line"), std::string::npos) << ce;
  EXPECT_NE(ce.find("prod_steps"), std::string::npos) << ce;
  EXPECT_FALSE(fs::exists(d / "c" / "ti_spec.json"));
  fs::remove_all(d);
}

// `pnc thermo ti-parameters` prints the declarations: JSON with every key (the 25 of
// kEveryKey), a TOML template that reads back to the defaults, and refuses an unknown format.
TEST(ThermoTiInput, TiParametersPrintsEveryKey) {
  const std::string exe(PNC_EXE);
  auto r = pnc::test::run_command(exe + " thermo ti-parameters --format json");
  ASSERT_EQ(r.code, 0);
  const auto j = nlohmann::json::parse(r.out, nullptr, false);
  ASSERT_TRUE(j.is_object());
  std::set<std::string> names;
  for (const auto& s : j["sections"])
    for (const auto& p : s["parameters"])
      names.insert(p["name"].get<std::string>()); // the dotted path
  EXPECT_EQ(names.size(), 25u);
  for (const char* k :
       {"equil_steps", "dhdl", "ranks", "executor", "slurm.time", "slurm.template", "slurm.mpi"})
    EXPECT_EQ(names.count(k), 1u) << k;
  r = pnc::test::run_command(exe + " thermo ti-parameters --format toml");
  ASSERT_EQ(r.code, 0);
  expect_same(pnc::thermo::parse_ti_input(pnc::parse_toml(r.out, "t.toml"), "t.toml"), TiInput{});
  r = pnc::test::run_command(exe + " thermo ti-parameters --format yaml 2>/dev/null");
  EXPECT_NE(r.code, 0);
}

// D332: the slurm section's `mpi` (srun's MPI plugin) reaches the jobs: every sbatch of a
// `pnc thermo ti --executor slurm` exports PNC_SRUN_MPI=<it>, the variable the unit's stages
// launch srun with (md/src/runner.cpp). Without a cluster: stand-ins for sbatch, scontrol and
// squeue record the submission (the jobs never run, so the restart file may be empty). The
// file's value; the option --mpi over it (D301); the default pmix without either; a bad
// option refused before anything is submitted, naming the option, the value and the rule.
TEST(ThermoTiInput, TheSlurmMpiKeyReachesEveryJobOfTheSubmission) {
  const fs::path d = pnc::test::fresh_dir("test_ti_mpi_key");
  const std::string path = pnc::test::slurm_stand_ins(d);
  std::ofstream(d / "rs.restart") << "";
  std::ofstream(d / "ti.toml") << "vol = [0.0]\ndev = []\npoints = 2\n[slurm]\nmpi = \"pmi2\"\n";
  const std::string base =
      "thermo ti --restart " + (d / "rs.restart").string() + " --executor slurm --no-plots --out ";
  const auto exports_of = [&](const std::string& args, const std::string& out) {
    fs::remove(d / "sbatch.args");
    const auto r = pnc::test::run_command(path + PNC_EXE + " " + base + (d / out).string() + " " +
                                          args + " 2>" + (d / "err").string());
    EXPECT_EQ(r.code, 0) << pnc::test::slurp(d / "err");
    std::vector<std::string> mpi; // the PNC_SRUN_MPI value of each sbatch call
    std::istringstream lines(pnc::test::slurp(d / "sbatch.args"));
    for (std::string line; std::getline(lines, line);) {
      const std::string key = ",PNC_SRUN_MPI=";
      const auto at = line.find(key);
      mpi.push_back(at == std::string::npos
                        ? "<none>"
                        : line.substr(at + key.size(), line.find(' ', at) - at - key.size()));
    }
    return mpi;
  };
  using V = std::vector<std::string>;
  // two jobs: the array of the 2 points, then the analysis
  EXPECT_EQ(exports_of("--input " + (d / "ti.toml").string(), "a"), V({"pmi2", "pmi2"}));
  EXPECT_EQ(exports_of("--input " + (d / "ti.toml").string() + " --mpi pmi1", "b"),
            V({"pmi1", "pmi1"}));
  EXPECT_EQ(exports_of("--vol 0 --dev none --points 2", "c"), V({"pmix", "pmix"}));
  fs::remove(d / "sbatch.args");
  const auto r = pnc::test::run_command(path + PNC_EXE + " " + base + (d / "e").string() +
                                        " --mpi=-x 2>" + (d / "err").string());
  EXPECT_NE(r.code, 0);
  const std::string err = pnc::test::slurp(d / "err");
  EXPECT_NE(err.find("--mpi: value '-x': must be 1 to 64 characters"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d / "sbatch.args"));
  fs::remove_all(d);
}
