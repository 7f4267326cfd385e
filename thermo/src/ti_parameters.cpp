// The keys of a `pnc thermo ti --input` file, each declared once (pnc/core/parameters.hpp):
// name, type, default (the values of TiSpec), range, unit and one line of text. The ranges are
// those of the command-line options (app/cmd_thermo_ti.cpp); the rules between keys are
// TiSpec::validate's. Units: LAMMPS real (kcal/mol, A, fs, K); strains dimensionless.
#include "pnc/thermo/ti_parameters.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/params.hpp"

#include <filesystem>
#include <memory>

namespace pnc::thermo {

namespace {

// LAMMPS runs at most 2^31 - 1 steps in one `run` command.
constexpr std::int64_t kMaxSteps = 2000000000;
// A strain list holds at most this many states (each state is `points` LAMMPS runs).
constexpr std::size_t kMaxStates = 1000;

// The options' names and units (LAMMPS real, D303), their ranges (app/cmd_thermo_ti.cpp).
void declare_ti(Parameters& p, TiInput& in) {
  auto& s = in.spec;
  p.string("rule", s.rule,
           {{"gauss", "Gauss-Legendre nodes; Table 6.1 with 3 points"},
            {"trapezoid", "equally spaced nodes including lambda = 0 and 1"}},
           "quadrature rule over lambda (D61)");
  p.integer("points", s.points, 1, 64, "", "quadrature points (lambda nodes) per state");
  p.reals("vol", s.vol, RealRange::closed(-0.1, 0.1), 0, kMaxStates, "1",
          "alpha values of the volumetric states F = (1 + alpha) I; [] for none");
  p.reals("dev", s.dev, RealRange::closed(-0.1, 0.1), 0, kMaxStates, "1",
          "beta values of the deviatoric states F = I + beta (1 - delta_ij); [] for none");
  p.real("eps0", s.path.eps0, RealRange::open_closed(0, 100), "kcal/mol",
         "LJ epsilon at lambda = 0 (D60)");
  p.real("eps1", s.path.eps1, RealRange::open_closed(0, 100), "kcal/mol",
         "LJ epsilon at lambda = 1 (D60)");
  p.real("sig0", s.path.sig0, RealRange::open_closed(0, 10), "A", "LJ sigma at lambda = 0 (D60)");
  p.real("sig1", s.path.sig1, RealRange::open_closed(0, 10), "A", "LJ sigma at lambda = 1 (D60)");
  p.real("cutoff", s.path.cutoff, RealRange::open_closed(0, 30), "A",
         "LJ cut-off at every lambda (D62)")
      .remark("at least max(sig0, sig1)");
  p.string("dhdl", s.dhdl_method,
           {{"virial", "one run, from the pair energy and the pair virial"},
            {"pairs", "pair-distance sums after every sample interval"}},
           "how dH/dlambda is sampled (D64)");
  p.real("timestep", s.sampling.timestep_fs, RealRange::open_closed(0, 10), "fs", "MD time step");
  p.integer("equil_steps", s.sampling.equil_steps, 0, kMaxSteps, "",
            "steps discarded per lambda point");
  p.integer("prod_steps", s.sampling.prod_steps, 1, kMaxSteps, "",
            "steps averaged per lambda point")
      .remark("at least sample_every x blocks");
  p.integer("sample_every", s.sampling.sample_every, 1, 1000000, "",
            "steps between dH/dlambda samples (D64)");
  p.integer("blocks", s.sampling.blocks, 3, 10000, "", "blocks of the standard errors");
  p.real("temperature", s.sampling.temperature, RealRange::open_closed(0, 1e4), "K",
         "temperature of the Langevin thermostat and of kT in the FEP estimates");
  p.integer("seed", s.seed, 1, 800000000, "", "thermostat seed (LAMMPS seeds)");
  p.integer("jobs", s.jobs, 1, 64, "", "lambda points run at the same time (local executor)");
  p.integer("ranks", s.ranks, 1, 4096, "",
            "MPI ranks of LAMMPS per lambda point (D324); under Slurm the tasks of each unit job");
  p.string("executor", in.executor,
           {{"local", "children of this process, jobs at a time"},
            {"slurm", "one Slurm job array, then the analysis; docs/cluster.md"}},
           "who runs the (state, lambda) units");
}

} // namespace

Parameters ti_input_parameters(TiInput& in) {
  Parameters p("pnc thermo ti input");
  declare_ti(p, in);
  campaign::declare_slurm_section(
      p, in.slurm,
      "the Slurm executor (docs/cluster.md, D245, D301): where and how "
      "long the (state, lambda) unit jobs run, `ranks` tasks each (D324), "
      "srun's MPI plugin (D332); the command-line options override it",
      false);
  return p;
}

Parameters ti_input_parameters() {
  auto in = std::make_shared<TiInput>();
  Parameters p = ti_input_parameters(*in);
  p.hold(in);
  return p;
}

TiInput parse_ti_input(const nlohmann::json& j, const std::string& source) {
  TiInput in;
  if (!j.is_object()) fail(source, "", show_json(j), "must be a JSON object (a TOML table)");
  ti_input_parameters(in).read(j, source);
  in.spec.validate(source); // the rules between keys
  for (auto it = j.begin(); it != j.end(); ++it)
    in.file_keys.push_back(it.key());
  return in;
}

TiInput read_ti_input(const std::string& path) {
  const auto ext = std::filesystem::path(path).extension().string();
  if (ext != ".json" && ext != ".toml")
    fail(path, "--input", ext, "a TI input file ends in .json or .toml");
  const std::string text = read_text_file(path, "the TI input");
  return parse_ti_input(ext == ".toml" ? parse_toml(text, path) : parse_json(text, path), path);
}

void override_ti_input(TiInput& in, const TiInput& given, const std::vector<std::string>& keys) {
  TiInput g = given; // the declarations bind non-const variables
  const Parameters to = ti_input_parameters(in);
  const Parameters from = ti_input_parameters(g);
  for (const auto& k : keys)
    to.at(k).store(from.at(k).load());
}

std::string ti_option_of(const std::string& key) {
  if (key == "slurm.template") return "--sbatch-template";
  std::string k = key.rfind("slurm.", 0) == 0 ? key.substr(6) : key;
  for (char& c : k)
    if (c == '_') c = '-';
  return "--" + k;
}

} // namespace pnc::thermo
