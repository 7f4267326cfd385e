// The input of `pnc gimp run` as TOML (D357): chosen by the extension, read into the same JSON
// as its JSON twin, so the run is the same bit for bit and a run started from one resumes from
// the other; a TOML error names the file and the line, a bad value its key.
#include "test_input_util.hpp"

#include "pnc/core/params.hpp"
#include "pnc/gimp_coupler/output.hpp"

#include <fstream>
#include <iterator>

using namespace pnc::gimp;
using namespace pnc::gimp::test;

namespace {

const fs::path kExamples = fs::path(PNC_SOURCE_DIR) / "examples" / "gimp";

std::string file_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void write(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

/// The InputError of reading the file `p` in 2-D (an empty context when it is accepted).
pnc::ErrorContext error_of_file(const fs::path& p) {
  Solver<2> s;
  try {
    (void)load_input<2>(p.string(), s);
  } catch (const pnc::InputError& e) {
    return e.context();
  }
  ADD_FAILURE() << p << " was accepted";
  return {};
}

/// The particle positions and velocities of a checkpoint (2-D).
using Vec2 = Eigen::Matrix<double, 2, 1>;
std::pair<std::vector<Vec2>, std::vector<Vec2>> particle_state(const fs::path& input,
                                                               const fs::path& ckpt) {
  Solver<2> s;
  (void)load_input<2>(input.string(), s);
  s.initialize();
  CheckpointExtra x;
  read_checkpoint<2>(ckpt.string(), s, x);
  return {s.particles.x, s.particles.v};
}

} // namespace

// The shipped TOML example holds exactly the values of its JSON twin (types included: dump()
// prints 1200 and 1200.0 differently), and to_toml() writes every JSON example as TOML that
// reads back to the same JSON (arrays of objects as [[...]] tables, D357).
TEST(GimpInputToml, ShippedTomlExampleIsItsJsonTwinAndEveryExampleConverts) {
  const json t = pnc::read_input_file((kExamples / "plate_hole_tension.toml").string(), "toml");
  const json j = pnc::read_input_file((kExamples / "plate_hole_tension.json").string(), "json");
  EXPECT_EQ(t.dump(), j.dump());
  int n = 0;
  for (const auto& f : fs::directory_iterator(kExamples)) {
    if (f.path().extension() != ".json") continue;
    const json e = pnc::parse_json(file_text(f.path()), f.path().string());
    EXPECT_EQ(pnc::parse_toml(pnc::to_toml(e), "converted.toml").dump(), e.dump()) << f.path();
    ++n;
  }
  EXPECT_GE(n, 6);
}

// A shipped example run from its JSON file, from the shipped TOML file and from to_toml() of
// the JSON: the same input, so the same run bit for bit (20 steps; history, energies, every
// particle's position and velocity in the checkpoint).
TEST(GimpInputToml, TomlExampleRunsBitForBitAsItsJsonTwin) {
  const fs::path d = tmpdir("toml_twin");
  const std::string json_text = file_text(kExamples / "plate_hole_tension.json");
  write(d / "in.json", json_text);
  write(d / "in.toml", file_text(kExamples / "plate_hole_tension.toml"));
  write(d / "converted.toml", pnc::to_toml(pnc::parse_json(json_text, "in.json")));
  RunOptions o;
  o.progress = false;
  o.plot = false;
  o.stop_after_steps = 20;
  std::vector<RunSummary> s;
  for (const char* in : {"in.json", "in.toml", "converted.toml"}) {
    o.input = (d / in).string();
    o.out_dir = (d / ("out_" + std::string(in))).string();
    s.push_back(run(o));
  }
  const auto ref = particle_state(d / "in.json", d / "out_in.json" / "checkpoint.h5");
  ASSERT_FALSE(ref.first.empty());
  for (std::size_t k = 1; k < s.size(); ++k) {
    EXPECT_EQ(s[k].steps, 20);
    EXPECT_EQ(s[k].steps, s[0].steps);
    EXPECT_EQ(s[k].time, s[0].time);
    EXPECT_EQ(s[k].energy.kinetic, s[0].energy.kinetic);
    EXPECT_EQ(s[k].energy.strain, s[0].energy.strain);
    EXPECT_EQ(s[k].energy.external_work, s[0].energy.external_work);
    const fs::path out = fs::path(s[k].checkpoint).parent_path();
    EXPECT_EQ(file_text(out / "history.csv"), file_text(d / "out_in.json" / "history.csv"));
    const auto got = particle_state(d / "in.json", out / "checkpoint.h5");
    EXPECT_TRUE(got == ref) << out;
  }
}

// Resume compares the input as values (D339): a run started from TOML continues from the JSON
// conversion of the same input and ends as the uninterrupted run; a changed value is refused
// naming its key.
TEST(GimpInputToml, RunStartedFromTomlResumesFromItsJsonConversion) {
  const fs::path d = tmpdir("toml_resume");
  write(d / "in.json", base_input().dump(2));
  write(d / "in.toml", pnc::to_toml(base_input()));
  json changed = base_input();
  changed["time"]["cfl"] = 0.3;
  write(d / "changed.json", changed.dump(2));
  RunOptions o;
  o.progress = false;
  o.plot = false;
  o.input = (d / "in.json").string();
  o.out_dir = (d / "straight").string();
  const RunSummary a = run(o);
  o.input = (d / "in.toml").string();
  o.out_dir = (d / "split").string();
  o.stop_after_steps = 7;
  const RunSummary b1 = run(o);
  ASSERT_EQ(b1.steps, 7);
  ASSERT_GT(a.steps, 7);
  o.stop_after_steps = 0;
  o.resume = true;
  o.input = (d / "changed.json").string();
  try {
    (void)run(o);
    ADD_FAILURE() << "a changed time.cfl was accepted on --resume";
  } catch (const pnc::InputError& e) {
    EXPECT_EQ(e.context().field, "time.cfl") << e.what();
  }
  o.input = (d / "in.json").string();
  const RunSummary b = run(o);
  EXPECT_TRUE(b.resumed);
  EXPECT_EQ(b.steps, a.steps);
  EXPECT_EQ(b.energy.kinetic, a.energy.kinetic);
  EXPECT_EQ(b.energy.strain, a.energy.strain);
  EXPECT_TRUE(particle_state(d / "in.json", d / "split" / "checkpoint.h5") ==
              particle_state(d / "in.json", d / "straight" / "checkpoint.h5"));
}

// A TOML syntax error names the file and the line; a bad value names the file, the key, the
// value and the rule as for JSON; a file that is neither .json nor .toml is refused.
TEST(GimpInputToml, TomlErrorsNameTheFileLineKeyValueAndRule) {
  const fs::path d = tmpdir("toml_errors");
  write(d / "syntax.toml", "dimension = 2\n\n[grid]\ncells = [24, 8\ncell_size = 0.05\n");
  const pnc::ErrorContext syn = error_of_file(d / "syntax.toml");
  EXPECT_EQ(syn.source, (d / "syntax.toml").string());
  EXPECT_NE(syn.rule.find("not valid TOML"), std::string::npos) << syn.rule;
  EXPECT_NE(syn.rule.find(" 4 | cells = [24, 8"), std::string::npos) << "no line: " << syn.rule;

  json j = base_input();
  j["grid"]["cell_size"] = -0.05;
  write(d / "value.toml", pnc::to_toml(j));
  const pnc::ErrorContext val = error_of_file(d / "value.toml");
  EXPECT_EQ(val.source, (d / "value.toml").string());
  EXPECT_EQ(val.field, "grid.cell_size");
  EXPECT_EQ(val.value, "-0.05");
  EXPECT_NE(val.rule.find("must be"), std::string::npos) << val.rule;
  // the same error as the JSON file gives, apart from the file name
  write(d / "value.json", j.dump());
  const pnc::ErrorContext valj = error_of_file(d / "value.json");
  EXPECT_EQ(valj.field, val.field);
  EXPECT_EQ(valj.value, val.value);
  EXPECT_EQ(valj.rule, val.rule);

  j = base_input();
  j["materials"][0]["nu"] = 0.7;
  write(d / "table.toml", pnc::to_toml(j));
  EXPECT_EQ(error_of_file(d / "table.toml").field, "materials[0].nu");

  write(d / "in.yaml", base_input().dump());
  const pnc::ErrorContext ext = error_of_file(d / "in.yaml");
  EXPECT_EQ(ext.field, "input");
  EXPECT_EQ(ext.value, ".yaml");
  EXPECT_EQ(ext.rule, "a GIMP input file ends in .json or .toml");
  EXPECT_THROW((void)input_dimension((d / "in.yaml").string()), pnc::InputError);
  EXPECT_EQ(input_dimension((d / "value.toml").string()), 2);
}
