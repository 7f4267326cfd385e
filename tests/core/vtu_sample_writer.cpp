// Writes the sample frames that read_vtu.py reads back with VTK's own readers (D236):
// OUTDIR/ascii.vtu, OUTDIR/base64.vtu and OUTDIR/series.pvd (three frames, base64). The data
// are the closed forms read_vtu.py checks against: point i (i = 0..4) at
// (0.5 i, -i, 0.25 i) m; displacement_m (1e-3 i, 2e-3 i, -1e-3 i); stress_Pa symmetric with
// XX = 1e6 (i + 1), YY = 2e6, ZZ = -3e6, XY = 4e5 i, YZ = 5e5, XZ = -6e5 i;
// deformation_gradient_1 row-major with entry (r, c) = r + 3 c + 0.1 i; damage_1 = 0.2 i;
// material_index = i % 2; field data time_s = 0.125 and load_N = -7.5.
#include "pnc/core/atomic_file.hpp"
#include "pnc/core/vtu.hpp"

#include <iostream>
#include <string>

namespace {
pnc::vtu::Frame sample(double time, double load) {
  pnc::vtu::Frame f;
  f.comment = "pnc vtu sample";
  pnc::vtu::PointArray u{"displacement_m", "m", 3, {}, {}};
  pnc::vtu::PointArray s{"stress_Pa", "Pa", 6, {}, {}};
  pnc::vtu::PointArray F{"deformation_gradient_1", "1", 9, {}, {}};
  pnc::vtu::PointArray d{"damage_1", "1", 1, {}, {}};
  pnc::vtu::PointArray m{"material_index", "index", 1, {}, {}};
  for (int i = 0; i < 5; ++i) {
    f.points.push_back({0.5 * i, -1.0 * i, 0.25 * i});
    u.values.insert(u.values.end(), {1e-3 * i, 2e-3 * i, -1e-3 * i});
    const double full[9] = {1e6 * (i + 1), 4e5 * i,  -6e5 * i, 4e5 * i, 2e6,
                            5e5,           -6e5 * i, 5e5,      -3e6};
    const auto s6 = pnc::vtu::symmetric6(full);
    s.values.insert(s.values.end(), s6.begin(), s6.end());
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        F.values.push_back(r + 3 * c + 0.1 * i);
    d.values.push_back(0.2 * i);
    m.labels.push_back(i % 2);
  }
  f.arrays = {u, s, F, d, m};
  f.field = {{"time_s", "s", time}, {"load_N", "N", load}};
  return f;
}
} // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: vtu_sample_writer OUTDIR\n";
    return 1;
  }
  const std::string d = argv[1];
  pnc::make_output_directory(d, "OUTDIR");
  using pnc::vtu::Encoding;
  pnc::vtu::write_vtu(d + "/ascii.vtu", sample(0.125, -7.5), {Encoding::ascii, 17});
  pnc::vtu::write_vtu(d + "/base64.vtu", sample(0.125, -7.5), {Encoding::base64, 17});
  // A load that goes back (snap-back): the pseudo-time is the step index.
  const double loads[3] = {1.0, 2.0, 1.5};
  std::vector<pnc::vtu::PvdEntry> pvd;
  for (int k = 0; k < 3; ++k) {
    const std::string name = "frame_" + std::to_string(k) + ".vtu";
    pnc::vtu::write_vtu(d + "/" + name, sample(0.125, loads[k]), {Encoding::base64, 17});
    pvd.push_back({name, static_cast<double>(k)});
  }
  pnc::vtu::write_pvd(d + "/series.pvd", pvd);
  return 0;
}
