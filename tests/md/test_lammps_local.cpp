// The in-process calls of pnc::md::Lammps (runner.hpp, lammps_local.cpp; D346), the layer the
// ESCM coupler reaches LAMMPS through: an instance opened without MPI, typed settings and
// globals, the local per-atom arrays against the id-ordered gather, a fix's global scalar
// against its definition, the fix-external callback against Newton's law, and the errors for
// names LAMMPS does not know. A LAMMPS error ends the process that hosts LAMMPS, so every
// instance lives in a stage child (run_stage); the child writes what it read to a file and the
// parent checks it.
#include "pnc/core/error.hpp"
#include "pnc/md/runner.hpp"

#include "common/lammps_banner.hpp"
#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace pnc::md;
namespace fs = std::filesystem;

namespace {
fs::path tmpdir(const std::string& tag) {
  return pnc::test::fresh_dir("test_md_local_" + tag);
}

/// Runs `body` on an instance of its own (open_in_process) inside a stage child and returns
/// the "key value" lines it wrote to its stream.
std::map<std::string, double> in_child(const std::string& tag,
                                       const std::function<void(Lammps&, std::ostream&)>& body) {
  const auto d = tmpdir(tag);
  const std::string res = (d / "result.txt").string();
  const std::string log = (d / "own.log").string();
  const auto out = run_stage({tag, (d / "stage.log").string(), {}}, [&](Lammps&) {
    std::ofstream f(res);
    f.precision(17);
    auto l = Lammps::open_in_process({"pnc", "-screen", "none", "-log", log, "-nocite"},
                                     "testing the in-process calls");
    body(*l, f);
  });
  EXPECT_TRUE(out.ok) << out.error;
  std::map<std::string, double> r;
  std::ifstream in(res);
  for (std::string k; in >> k;)
    in >> r[k];
  return r;
}

/// A 4x4x4 fcc LJ crystal (4 atoms per cell: 256 atoms) of mass 2 with random velocities;
/// `boundary` e.g. "p f p", `pair` the pair_style and pair_coeff commands.
void crystal(Lammps& l, const std::string& boundary, const std::vector<std::string>& pair) {
  l.cmds({"units lj", "boundary " + boundary, "atom_modify map array", "lattice fcc 0.8442",
          "region box block 0 4 0 4 0 4", "create_box 1 box", "create_atoms 1 box", "mass 1 2.0"});
  l.cmds(pair);
  l.cmds({"velocity all create 1.0 5 loop geom", "run 0 post no"});
}
const std::vector<std::string> kLj = {"pair_style lj/cut 2.5", "pair_coeff 1 1 1.0 1.0"};
const std::vector<std::string> kNone = {"pair_style zero 2.5", "pair_coeff * *"};
} // namespace

TEST(MdLammpsLocal, LocalArraysSettingsAndGlobalsAgreeWithTheGather) {
  const auto r = in_child("agree", [](Lammps& l, std::ostream& f) {
    crystal(l, "p f p", kLj);
    const long n = l.natoms();
    f << "natoms " << n << '\n';
    f << "nlocal " << l.extract_setting("nlocal") << '\n';
    f << "dimension " << l.extract_setting("dimension") << '\n';
    f << "units_lj " << (l.extract_global_string("units") == "lj") << '\n';
    const auto per = l.periodic();
    f << "periodic " << per[0] << per[1] << per[2] << '\n';
    const auto ids = l.gather_ids();
    long id_off = 0;
    for (std::size_t k = 0; k < ids.size(); ++k)
      id_off += ids[k] != static_cast<AtomId>(k + 1);
    f << "ids " << ids.size() << ' ' << "ids_off " << id_off << '\n';
    // the local arrays, put in id order, against LAMMPS's own gather by id (exact copies)
    const LocalAtoms a = l.local_atoms();
    const auto gx = l.gather("x", 3), gv = l.gather("v", 3), gf = l.gather("f", 3);
    double dx = 0, dv = 0, df = 0, fmax = 0;
    for (int i = 0; i < a.n; ++i)
      for (int c = 0; c < 3; ++c) {
        const std::size_t o = 3 * static_cast<std::size_t>(a.id[i] - 1) + c;
        dx = std::max(dx, std::fabs(a.x[i][c] - gx[o]));
        dv = std::max(dv, std::fabs(a.v[i][c] - gv[o]));
        df = std::max(df, std::fabs(a.f[i][c] - gf[o]));
        fmax = std::max(fmax, std::fabs(gf[o]));
      }
    f << "local_n " << a.n << "\ndx " << dx << "\ndv " << dv << "\ndf " << df << "\nfmax " << fmax
      << '\n';
    // fix addforce's global scalar is -sum(F . x_unwrapped) over its group (LAMMPS docs); no atom
    // crossed a boundary, so x is the unwrapped position
    l.cmd("fix add all addforce 0.5 -0.25 0.0");
    l.cmd("run 0 post no");
    const auto x = l.gather("x", 3);
    double expect = 0, scale = 0;
    for (std::size_t k = 0; k < x.size(); k += 3) {
      expect -= 0.5 * x[k] - 0.25 * x[k + 1];
      scale += 0.5 * std::fabs(x[k]) + 0.25 * std::fabs(x[k + 1]);
    }
    f << "addforce_err " << std::fabs(l.fix_scalar("add") - expect) << "\naddforce_scale " << scale
      << '\n';
  });
  EXPECT_EQ(r.at("natoms"), 256.0); // 4 atoms per fcc cell, 4^3 cells
  EXPECT_EQ(r.at("nlocal"), 256.0); // one process holds every atom
  EXPECT_EQ(r.at("dimension"), 3.0);
  EXPECT_EQ(r.at("units_lj"), 1.0);
  EXPECT_EQ(r.at("periodic"), 101.0); // boundary p f p
  EXPECT_EQ(r.at("ids"), 256.0);
  EXPECT_EQ(r.at("ids_off"), 0.0);
  EXPECT_EQ(r.at("local_n"), 256.0);
  EXPECT_EQ(r.at("dx"), 0.0);
  EXPECT_EQ(r.at("dv"), 0.0);
  EXPECT_EQ(r.at("df"), 0.0);
  EXPECT_GT(r.at("fmax"), 0.0); // the boundary f cut the crystal: forces are not all zero
  // 256 terms summed in two orders: rounding of the sum, 256 * eps relative to sum |terms|
  EXPECT_LE(r.at("addforce_err"), 256 * 2.3e-16 * r.at("addforce_scale"));
}

// A constant external force F on atoms without interactions: velocity Verlet gives v = N dt F / m
// after N steps (lj units: force/mass is an acceleration), up to the rounding of N additions.
TEST(MdLammpsLocal, ExternalForceCallbackSeesEveryAtomAtEveryStep) {
  const auto r = in_child("external", [](Lammps& l, std::ostream& f) {
    crystal(l, "p p p", kNone);
    l.cmds({"velocity all set 0.0 0.0 0.0", "fix nve all nve", "timestep 0.005",
            "fix ext all external pf/callback 1 1"});
    const Step start = static_cast<Step>(l.thermo("step"));
    long calls = 0, bad_n = 0, bad_ids = 0;
    l.set_external_force("ext", [&](Step step, int n, const AtomId* id, double**, double** fx) {
      if (step > start) { // not the set-up call of the run
        ++calls;
        bad_n += n != 256;
        std::set<AtomId> seen(id, id + n);
        bad_ids += seen.size() != 256 || *seen.begin() != 1 || *seen.rbegin() != 256;
      }
      for (int i = 0; i < n; ++i) {
        fx[i][0] = 0.3;
        fx[i][1] = -0.1;
        fx[i][2] = 0.0;
      }
    });
    l.cmd("run 40");
    f << "calls " << calls << "\nbad_n " << bad_n << "\nbad_ids " << bad_ids << '\n';
    const auto v = l.gather("v", 3);
    double ex = 0, ey = 0, ez = 0;
    for (std::size_t k = 0; k < v.size(); k += 3) {
      ex = std::max(ex, std::fabs(v[k] - 40 * 0.005 * 0.3 / 2.0));
      ey = std::max(ey, std::fabs(v[k + 1] + 40 * 0.005 * 0.1 / 2.0));
      ez = std::max(ez, std::fabs(v[k + 2]));
    }
    f << "ex " << ex << "\ney " << ey << "\nez " << ez << '\n';
  });
  EXPECT_EQ(r.at("calls"), 40.0);
  EXPECT_EQ(r.at("bad_n"), 0.0);
  EXPECT_EQ(r.at("bad_ids"), 0.0);
  // v is the sum of 80 half-step increments dt/2 F/m: 80 additions, each rounding by at most
  // u = 2^-53 of a sum below |v|, plus a few roundings of the increment and of the expected value
  const double u = std::ldexp(1.0, -53);
  EXPECT_LE(r.at("ex"), (80 + 6) * u * 0.03);
  EXPECT_LE(r.at("ey"), (80 + 6) * u * 0.01);
  EXPECT_EQ(r.at("ez"), 0.0);
}

TEST(MdLammpsLocal, UnknownNamesAreRefusedNamingTheQuantity) {
  const auto d = tmpdir("names_msg");
  const std::string res = (d / "messages.txt").string();
  const auto r = in_child("names", [&](Lammps& l, std::ostream& f) {
    crystal(l, "p p p", kNone);
    std::ofstream m(res);
    auto note = [&](const std::string& key, const std::function<void()>& call) {
      try {
        call();
        m << key << "\tno error\n";
      } catch (const pnc::InputError& e) {
        m << key << '\t' << e.what() << '\n';
      }
    };
    note("setting", [&] { l.extract_setting("pnc_no_such_setting"); });
    note("global", [&] { l.extract_global_string("pnc_no_such_global"); });
    note("not_string", [&] { l.extract_global_string("dt"); }); // a double, not a string
    note("fix_scalar", [&] { l.fix_scalar("pnc_no_such_fix"); });
    note("callback", [&] { l.set_external_force("pnc_no_fix", ExternalForce{}); });
    f << "done 1\n";
  });
  EXPECT_EQ(r.at("done"), 1.0);
  std::map<std::string, std::string> msg;
  std::ifstream in(res);
  for (std::string line; std::getline(in, line);)
    msg[line.substr(0, line.find('\t'))] = line.substr(line.find('\t') + 1);
  ASSERT_EQ(msg.size(), 5u);
  EXPECT_NE(msg.at("setting").find("pnc_no_such_setting"), std::string::npos) << msg.at("setting");
  EXPECT_NE(msg.at("global").find("pnc_no_such_global"), std::string::npos) << msg.at("global");
  EXPECT_NE(msg.at("not_string").find("'dt'"), std::string::npos) << msg.at("not_string");
  EXPECT_NE(msg.at("fix_scalar").find("pnc_no_such_fix"), std::string::npos)
      << msg.at("fix_scalar");
  EXPECT_NE(msg.at("callback").find("pnc_no_fix"), std::string::npos) << msg.at("callback");
}

// The in-process calls on an instance without a LAMMPS handle in this process (as a stage-server
// instance has none): a bug in the caller, refused before any LAMMPS call.
TEST(MdLammpsLocal, InProcessCallsRefuseAnInstanceWithoutHandle) {
  Lammps l(static_cast<void*>(nullptr));
  EXPECT_THROW(l.extract_setting("nlocal"), std::logic_error);
  EXPECT_THROW(l.local_atoms(), std::logic_error);
  EXPECT_THROW(l.set_external_force("ext", ExternalForce{}), std::logic_error);
}

// D366: the linked LAMMPS's version, asked in a stage child as the case driver asks it (a
// one-rank stage's child holds an in-process LAMMPS, a two-rank stage's child only the socket to
// the server), is the release date the installed `lmp` prints in its banner (the same package).
TEST(MdLammpsLocal, LinkedVersionIsTheReleaseDateTheInstalledLmpPrints) {
  const std::string date = pnc::test::lmp_banner_date();
  ASSERT_EQ(date.size(), 8u) << "no release date in the banner of `lmp -h`";
  const auto d = tmpdir("version");
  for (int ranks : {1, 2}) {
    const std::string res = (d / ("version_" + std::to_string(ranks) + ".txt")).string();
    const StageSpec spec{
        "version", (d / ("stage_" + std::to_string(ranks) + ".log")).string(), {}, ranks};
    const auto out = run_stage(spec, [&](Lammps& l) { std::ofstream(res) << l.version() << "\n"; });
    ASSERT_TRUE(out.ok) << out.error;
    std::ifstream in(res);
    std::string version;
    in >> version;
    EXPECT_EQ(version, date) << ranks << " rank(s)";
  }
  fs::remove_all(d);
}
