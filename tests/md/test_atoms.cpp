// Per-atom access by atom id (md/atoms.hpp) against LAMMPS's own readings of the same atoms:
// positions and velocities against lammps_gather_atoms, unpacked image flags against
// `compute property/atom ix iy iz` (LAMMPS unpacking its own flags), and writes that LAMMPS
// then reports back. Every LAMMPS call runs in a stage child; the child writes what it read
// to a file and the parent compares (exact: these are copies, no arithmetic).
#include "pnc/md/atoms.hpp"
#include "pnc/md/runner.hpp"

#include "common/temp_dir.hpp"

#include <lammps/library.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

using namespace pnc::md;
namespace fs = std::filesystem;

namespace {
fs::path tmpdir(const std::string& tag) {
  return pnc::test::fresh_dir("test_md_atoms_" + tag);
}

/// A 4x4x4 fcc LJ crystal (256 atoms) whose atoms were moved by several box lengths, so that
/// the image flags are non-zero and differ per axis, with random velocities.
void crystal(Lammps& l) {
  l.cmds({"units lj", "atom_modify map array", "lattice fcc 0.8442", "region box block 0 4 0 4 0 4",
          "create_box 1 box", "create_atoms 1 box", "mass 1 1.0", "pair_style lj/cut 2.5",
          "pair_coeff 1 1 1.0 1.0", "velocity all create 1.0 5 loop geom", "group half id <= 100",
          "displace_atoms half move 13.0 -7.5 21.0 units box", "run 0 post no"});
}

/// Per-atom ix iy iz by atom id from LAMMPS's compute property/atom.
std::vector<double> lammps_image(Lammps& l) {
  l.cmd("compute pnc_img all property/atom ix iy iz");
  l.cmd("run 0 post no");
  void* h = l.handle();
  const int n = static_cast<int>(lammps_get_natoms(h));
  auto** a =
      static_cast<double**>(lammps_extract_compute(h, "pnc_img", LMP_STYLE_ATOM, LMP_TYPE_ARRAY));
  const int* id = static_cast<int*>(lammps_extract_atom(h, "id"));
  std::vector<double> out(3 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      out[3 * static_cast<std::size_t>(id[i] - 1) + static_cast<std::size_t>(c)] = a[i][c];
  l.cmd("uncompute pnc_img");
  return out;
}

std::vector<double> lammps_gathered(Lammps& l, const char* name) {
  const int n = static_cast<int>(lammps_get_natoms(l.handle()));
  std::vector<double> out(3 * static_cast<std::size_t>(n));
  std::string nm = name;
  lammps_gather_atoms(l.handle(), nm.data(), 1, 3, out.data());
  return out;
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return INFINITY;
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

double max_abs(const std::vector<double>& a) {
  double m = 0;
  for (double v : a)
    m = std::max(m, std::fabs(v));
  return m;
}
} // namespace

TEST(MdAtoms, ImageFlagsPackAndUnpackLikeLammps) {
  for (int ix : {-512, -3, 0, 7, 511})
    for (int iy : {-512, -1, 0, 2, 511})
      for (int iz : {-512, 0, 5, 511}) {
        const auto f = ImageFlags::unpack(ImageFlags::pack(ix, iy, iz));
        EXPECT_EQ(f[0], ix);
        EXPECT_EQ(f[1], iy);
        EXPECT_EQ(f[2], iz);
      }
  // LAMMPS's IMGMAX 512, IMGBITS 10: the zero image is 512 | 512 << 10 | 512 << 20
  EXPECT_EQ(ImageFlags::pack(0, 0, 0), 512 | (512 << 10) | (512 << 20));
}

TEST(MdAtoms, GatherAndScatterByIdAgreeWithLammpsOwnReadings) {
  const auto d = tmpdir("agree");
  const std::string res = (d / "result.txt").string();
  const auto out = run_stage({"atoms", (d / "atoms.log").string(), {}}, [&](Lammps& l) {
    crystal(l);
    std::ofstream f(res);
    f.precision(17);
    const auto im = lammps_image(l);
    f << "image_max " << max_abs(im) << '\n';
    f << "image " << max_abs_diff(gather_local(l.handle(), "image", 3), im) << '\n';
    f << "x " << max_abs_diff(gather_local(l.handle(), "x", 3), lammps_gathered(l, "x")) << '\n';
    f << "v " << max_abs_diff(gather_local(l.handle(), "v", 3), lammps_gathered(l, "v")) << '\n';
    const auto ty = gather_local(l.handle(), "type", 1);
    f << "types " << ty.size() << ' ' << max_abs_diff(ty, std::vector<double>(ty.size(), 1.0))
      << '\n';
    // write: shifted image flags and scaled velocities, as LAMMPS then reports them
    auto im2 = im;
    for (std::size_t k = 0; k < im2.size(); ++k)
      im2[k] += static_cast<double>(k % 5) - 2.0;
    scatter_local(l.handle(), "image", im2);
    f << "image_written " << max_abs_diff(lammps_image(l), im2) << '\n';
    auto v2 = gather_local(l.handle(), "v", 3);
    for (double& v : v2)
      v = -2.0 * v + 0.25;
    scatter_local(l.handle(), "v", v2);
    f << "v_written " << max_abs_diff(lammps_gathered(l, "v"), v2) << '\n';
    try {
      scatter_local(l.handle(), "x", std::vector<double>(5, 0.0));
      f << "short_refused no\n";
    } catch (const std::logic_error& e) {
      f << "short_refused " << (std::string(e.what()).find("3 per atom") != std::string::npos)
        << '\n';
    }
  });
  ASSERT_TRUE(out.ok) << out.error;
  std::ifstream in(res);
  std::map<std::string, double> r;
  for (std::string k; in >> k;) {
    double v;
    in >> v;
    if (k == "types") {
      double m;
      in >> m;
      r["types_diff"] = m;
    }
    r[k] = v;
  }
  EXPECT_GE(r.at("image_max"), 2.0); // the moves crossed the box more than once
  EXPECT_EQ(r.at("image"), 0.0);
  EXPECT_EQ(r.at("x"), 0.0);
  EXPECT_EQ(r.at("v"), 0.0);
  EXPECT_EQ(r.at("types"), 256.0);
  EXPECT_EQ(r.at("types_diff"), 0.0);
  EXPECT_EQ(r.at("image_written"), 0.0);
  EXPECT_EQ(r.at("v_written"), 0.0);
  EXPECT_EQ(r.at("short_refused"), 1.0);
}
