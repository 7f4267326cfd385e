// VTU/PVD frames, CSV histories and HDF5 checkpoints of the GIMP solver (output.hpp).
#include "pnc/gimp_coupler/output.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/params.hpp"
#include "pnc/core/run_dir.hpp"
#include "pnc/core/version.hpp"
#include "pnc/core/vtu.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <sstream>

namespace pnc::gimp {

std::string base64(const unsigned char* data, std::size_t n) {
  static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < n; i += 3) {
    const std::uint32_t v = (std::uint32_t(data[i]) << 16) | (std::uint32_t(data[i + 1]) << 8) |
                            std::uint32_t(data[i + 2]);
    out += tbl[(v >> 18) & 63];
    out += tbl[(v >> 12) & 63];
    out += tbl[(v >> 6) & 63];
    out += tbl[v & 63];
  }
  if (i < n) {
    std::uint32_t v = std::uint32_t(data[i]) << 16;
    if (i + 1 < n) v |= std::uint32_t(data[i + 1]) << 8;
    out += tbl[(v >> 18) & 63];
    out += tbl[(v >> 12) & 63];
    out += i + 1 < n ? tbl[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i)
    s += (i ? "," : "") + v[i];
  return s;
}
std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ',') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!s.empty()) out.push_back(cur);
  return out;
}

} // namespace

template <int D>
void write_vtu(const std::string& path, const Solver<D>& s, bool binary,
               const std::vector<std::string>& material_names) {
  const auto& P = s.particles;
  const std::size_t n = P.size();
  vtu::Frame f;
  f.comment = "pnc gimp particles; SI units; " + version_string() + "; materials:";
  for (std::size_t i = 0; i < material_names.size(); ++i)
    f.comment += ' ' + std::to_string(i) + '=' + material_names[i];
  f.field = {{"time_s", "s", s.time}};
  f.points.resize(n, {0.0, 0.0, 0.0});
  vtu::PointArray u{"displacement_m", "m", 3, std::vector<double>(3 * n, 0.0), {}};
  vtu::PointArray v{"velocity_m_per_s", "m/s", 3, std::vector<double>(3 * n, 0.0), {}};
  vtu::PointArray sig{"stress_Pa", "Pa", 6, {}, {}};
  vtu::PointArray eps{"strain_1", "1", 6, {}, {}};
  sig.values.reserve(6 * n);
  eps.values.reserve(6 * n);
  vtu::PointArray rho{"density_kg_per_m3", "kg/m^3", 1, {}, {}};
  vtu::PointArray V{"volume_m3", "m^3", 1, {}, {}};
  vtu::PointArray m{"mass_kg", "kg", 1, {}, {}};
  vtu::PointArray W{"strain_energy_density_J_per_m3", "J/m^3", 1, {}, {}};
  vtu::PointArray mat{"material_index", "index", 1, {}, {}};
  for (std::size_t p = 0; p < n; ++p) {
    for (int a = 0; a < D; ++a) {
      f.points[p][static_cast<std::size_t>(a)] = P.x[p][a];
      u.values[3 * p + static_cast<std::size_t>(a)] = P.x[p][a] - P.x0[p][a];
      v.values[3 * p + static_cast<std::size_t>(a)] = P.v[p][a];
    }
    const Mat3 F = to3<D>(P.F[p]);
    const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
    double sr[9], er[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        sr[3 * i + j] = P.sigma[p](i, j);
        er[3 * i + j] = E(i, j);
      }
    const auto s6 = vtu::symmetric6(sr), e6 = vtu::symmetric6(er);
    sig.values.insert(sig.values.end(), s6.begin(), s6.end());
    eps.values.insert(eps.values.end(), e6.begin(), e6.end());
    rho.values.push_back(P.m[p] / P.V[p]);
    V.values.push_back(P.V[p]);
    m.values.push_back(P.m[p]);
    W.values.push_back(P.W[p]);
    mat.labels.push_back(P.mat[p]);
  }
  f.arrays = {std::move(u), std::move(v), std::move(sig), std::move(eps), std::move(rho),
              std::move(V), std::move(m), std::move(W),   std::move(mat)};
  // State variables, by name over all materials (the damage laws' kappa and D: stretch and
  // damage, dimensionless); 0 for particles of other laws.
  std::vector<std::string> names;
  for (const auto& mt : s.materials)
    for (const auto& nm : mt->state_names())
      if (std::find(names.begin(), names.end(), nm) == names.end()) names.push_back(nm);
  for (const auto& nm : names) {
    vtu::PointArray a{nm + "_1", "1", 1, std::vector<double>(n, 0.0), {}};
    for (std::size_t p = 0; p < n; ++p) {
      const auto sn = s.materials[static_cast<std::size_t>(P.mat[p])]->state_names();
      for (std::size_t k = 0; k < sn.size(); ++k)
        if (sn[k] == nm) a.values[p] = P.state[p * static_cast<std::size_t>(P.state_stride) + k];
    }
    f.arrays.push_back(std::move(a));
  }
  vtu::write_vtu(path, f, {binary ? vtu::Encoding::base64 : vtu::Encoding::ascii, 10});
}

void write_pvd(const std::string& path, const std::vector<std::string>& files,
               const std::vector<double>& times) {
  std::vector<vtu::PvdEntry> e;
  for (std::size_t i = 0; i < files.size(); ++i)
    e.push_back({files[i], times[i]}); // the physical time increases strictly (one step or more)
  vtu::write_pvd(path, e);
}

void History::write_csv(const std::string& path) const {
  std::ostringstream o;
  o << std::setprecision(12);
  // D335: the unit is in each column name; the comment says only how to read the suffixes
  o << "# pnc gimp history; SI, the unit ends each column name (_s, _m, _J_per_m2; 2-D per metre "
       "of thickness: _J_per_m, _N_per_m; 3-D: _J, _N)\n";
  o << join(columns) << '\n';
  for (const auto& r : rows) {
    for (std::size_t i = 0; i < r.size(); ++i)
      o << (i ? "," : "") << r[i];
    o << '\n';
  }
  write_text_atomically(path, o.str());
}

template <int D>
void write_checkpoint(const std::string& path, const Solver<D>& s, const CheckpointExtra& x) {
  AtomicOutput out(path);
  {
    h5::File f(out.temp_path(), h5::File::Mode::truncate);
    h5::write_provenance(f);
    const auto& P = s.particles;
    const auto n = static_cast<Eigen::Index>(P.size());
    f.write_string("/format", "pnc gimp checkpoint 1");
    f.write_string("/input_hash", x.input_hash);
    f.write_string("/input", x.input); // D339
    f.write_scalar("/dimension", D);
    f.write_scalar("/time", s.time);
    f.set_attr("/time", "units", "s");
    f.write_scalar("/steps", s.steps);
    f.write_scalar("/energy/initial", s.energy.initial);
    f.write_scalar("/energy/kinetic", s.energy.kinetic);
    f.write_scalar("/energy/strain", s.energy.strain);
    f.write_scalar("/energy/external_work", s.energy.external_work);
    f.write_scalar("/energy/boundary_work", s.energy.boundary_work);
    f.write_scalar("/energy/damping_work", s.energy.damping_work);
    for (const char* e : {"/energy/initial", "/energy/kinetic", "/energy/strain",
                          "/energy/external_work", "/energy/boundary_work", "/energy/damping_work"})
      f.set_attr(e, "units", "J");
    // Cracks (they grow): points (m), tip flags, increments; the tips of t = 0.
    for (std::size_t c = 0; c < s.cracks.size(); ++c) {
      const Crack& cr = s.cracks[c];
      const std::string g = "/cracks/" + std::to_string(c);
      if constexpr (D == 3) { // D42: planar polygon, front flags
        h5::RowMatrix pts(static_cast<Eigen::Index>(cr.corners.size()), 3);
        for (std::size_t k = 0; k < cr.corners.size(); ++k)
          pts.row(static_cast<Eigen::Index>(k)) = cr.corners[k].transpose();
        f.write_matrix(g + "/corners", pts);
        f.set_attr(g + "/corners", "units", "m");
        f.write_vector(g + "/front", std::vector<double>(cr.front.begin(), cr.front.end()));
      } else {
        h5::RowMatrix pts(static_cast<Eigen::Index>(cr.points.size()), 2);
        for (std::size_t k = 0; k < cr.points.size(); ++k)
          pts.row(static_cast<Eigen::Index>(k)) = cr.points[k].transpose();
        f.write_matrix(g + "/points", pts);
        f.set_attr(g + "/points", "units", "m");
      }
      f.write_vector(g + "/tips_increments",
                     {double(cr.tip[0]), double(cr.tip[1]), double(cr.increments)});
    }
    {
      std::vector<double> it(x.initial_tips.begin(), x.initial_tips.end());
      f.write_vector("/cracks_initial_tips", it.empty() ? std::vector<double>{-1.0} : it);
    }
    auto vecs = [&](const std::string& name, const auto& v, const char* units) {
      h5::RowMatrix m(n, D);
      for (Eigen::Index p = 0; p < n; ++p)
        m.row(p) = v[static_cast<std::size_t>(p)].transpose();
      f.write_matrix(name, m);
      f.set_attr(name, "units", units);
    };
    vecs("/particles/x", P.x, "m");
    vecs("/particles/x0", P.x0, "m");
    vecs("/particles/v", P.v, "m/s");
    vecs("/particles/l", P.l, "m");
    h5::RowMatrix F(n, D * D), sig(n, 9), sc(n, 4), st(n, std::max(P.state_stride, 1));
    st.setZero();
    for (Eigen::Index p = 0; p < n; ++p) {
      const auto q = static_cast<std::size_t>(p);
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j)
          F(p, D * i + j) = P.F[q](i, j);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          sig(p, 3 * i + j) = P.sigma[q](i, j);
      sc(p, 0) = P.m[q];
      sc(p, 1) = P.V0[q];
      sc(p, 2) = P.W[q];
      sc(p, 3) = P.mat[q];
      for (int k = 0; k < P.state_stride; ++k)
        st(p, k) =
            P.state[q * static_cast<std::size_t>(P.state_stride) + static_cast<std::size_t>(k)];
    }
    f.write_matrix("/particles/F", F);
    f.write_matrix("/particles/sigma", sig);
    f.set_attr("/particles/sigma", "units", "Pa");
    f.write_matrix("/particles/m_V0_W_mat", sc);
    f.set_attr("/particles/m_V0_W_mat", "units", "kg, m^3, J/m^3, 1");
    f.write_matrix("/particles/state", st);
    f.write_scalar("/particles/state_stride", P.state_stride);
    f.write_scalar("/output/next_time", x.next_output_time);
    f.write_string("/output/frame_files", join(x.frame_files));
    f.write_vector("/output/frame_times", x.frame_times);
    f.write_string("/history/columns", join(x.history.columns));
    h5::RowMatrix hm(static_cast<Eigen::Index>(x.history.rows.size()),
                     static_cast<Eigen::Index>(x.history.columns.size()));
    for (Eigen::Index r = 0; r < hm.rows(); ++r)
      for (Eigen::Index c = 0; c < hm.cols(); ++c)
        hm(r, c) = x.history.rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
    f.write_matrix("/history/rows", hm);
  }
  out.commit();
}

template <int D> void read_checkpoint(const std::string& path, Solver<D>& s, CheckpointExtra& x) {
  h5::File f(path, h5::File::Mode::read);
  if (f.read_string("/format") != "pnc gimp checkpoint 1")
    fail(path, "/format", f.read_string("/format"), "not a pnc gimp checkpoint (version 1)");
  if (static_cast<int>(f.read_scalar("/dimension")) != D)
    fail(path, "/dimension", std::to_string(f.read_scalar("/dimension")),
         "must match the input's dimension");
  const std::string hash = f.read_string("/input_hash");
  if (f.exists("/input")) { // the expanded inputs, compared as JSON values (D339)
    const std::string stored = f.read_string("/input");
    if (!x.input.empty() && !stored.empty())
      require_same_input(x.input_source.empty() ? path : x.input_source,
                         parse_json(stored, path + ": /input"), parse_json(x.input, x.input_source),
                         path);
    if (x.input.empty()) x.input = stored;
  } else if (!x.input_hash.empty() && hash != x.input_hash) { // a checkpoint before D339
    fail(path, "/input_hash", hash,
         "the input file changed since this checkpoint was written (expected " + x.input_hash +
             "); start a new run without --resume");
  }
  auto& P = s.particles;
  const auto X = f.read_matrix("/particles/x");
  if (static_cast<std::size_t>(X.rows()) != P.size() || X.cols() != D)
    fail(path, "/particles/x", std::to_string(X.rows()) + " rows",
         "must hold the input's " + std::to_string(P.size()) + " particles");
  const auto X0 = f.read_matrix("/particles/x0"), Vv = f.read_matrix("/particles/v"),
             L = f.read_matrix("/particles/l"), F = f.read_matrix("/particles/F"),
             sig = f.read_matrix("/particles/sigma"), sc = f.read_matrix("/particles/m_V0_W_mat"),
             st = f.read_matrix("/particles/state");
  P.state_stride = static_cast<int>(f.read_scalar("/particles/state_stride"));
  P.state.assign(P.size() * static_cast<std::size_t>(P.state_stride), 0.0);
  for (std::size_t q = 0; q < P.size(); ++q) {
    const auto p = static_cast<Eigen::Index>(q);
    P.x[q] = X.row(p).transpose();
    P.x0[q] = X0.row(p).transpose();
    P.v[q] = Vv.row(p).transpose();
    P.l[q] = L.row(p).transpose();
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j)
        P.F[q](i, j) = F(p, D * i + j);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        P.sigma[q](i, j) = sig(p, 3 * i + j);
    P.m[q] = sc(p, 0);
    P.V0[q] = sc(p, 1);
    P.W[q] = sc(p, 2);
    P.mat[q] = static_cast<int>(sc(p, 3));
    P.V[q] = P.V0[q] * P.F[q].determinant();
    for (int k = 0; k < P.state_stride; ++k)
      P.state[q * static_cast<std::size_t>(P.state_stride) + static_cast<std::size_t>(k)] =
          st(p, k);
  }
  s.time = f.read_scalar("/time");
  s.steps = static_cast<long>(f.read_scalar("/steps"));
  s.energy.initial = f.read_scalar("/energy/initial");
  s.energy.kinetic = f.read_scalar("/energy/kinetic");
  s.energy.strain = f.read_scalar("/energy/strain");
  s.energy.external_work = f.read_scalar("/energy/external_work");
  s.energy.boundary_work = f.read_scalar("/energy/boundary_work");
  s.energy.damping_work =
      f.exists("/energy/damping_work") ? f.read_scalar("/energy/damping_work") : 0.0;
  for (std::size_t c = 0; c < s.cracks.size(); ++c) {
    const std::string g = "/cracks/" + std::to_string(c);
    const std::string key = D == 3 ? g + "/corners" : g + "/points";
    if (!f.exists(key))
      fail(path, key, "<missing>", "the input has " + std::to_string(s.cracks.size()) + " cracks");
    const auto pts = f.read_matrix(key);
    Crack& cr = s.cracks[c];
    if constexpr (D == 3) { // D42
      cr.corners.clear();
      for (Eigen::Index k = 0; k < pts.rows(); ++k)
        cr.corners.emplace_back(pts(k, 0), pts(k, 1), pts(k, 2));
      const auto fr = f.read_vector(g + "/front");
      cr.front.assign(fr.size(), 0);
      for (std::size_t k = 0; k < fr.size(); ++k)
        cr.front[k] = static_cast<int>(fr[k]);
      const std::string why = check_planar_crack(cr);
      if (!why.empty()) fail(path, key, "<corners>", why);
    } else {
      cr.points.clear();
      for (Eigen::Index k = 0; k < pts.rows(); ++k)
        cr.points.emplace_back(pts(k, 0), pts(k, 1));
    }
    const auto ti = f.read_vector(g + "/tips_increments");
    cr.tip = {static_cast<int>(ti.at(0)), static_cast<int>(ti.at(1))};
    cr.increments = static_cast<int>(ti.at(2));
  }
  x.initial_tips.clear();
  if (f.exists("/cracks_initial_tips"))
    for (double v : f.read_vector("/cracks_initial_tips"))
      if (v >= 0) x.initial_tips.push_back(static_cast<int>(v));
  x.input_hash = hash;
  x.next_output_time = f.read_scalar("/output/next_time");
  x.frame_files = split(f.read_string("/output/frame_files"));
  x.frame_times = f.read_vector("/output/frame_times");
  x.history.columns = split(f.read_string("/history/columns"));
  const auto hm = f.read_matrix("/history/rows");
  x.history.rows.clear();
  for (Eigen::Index r = 0; r < hm.rows(); ++r) {
    std::vector<double> row(static_cast<std::size_t>(hm.cols()));
    for (Eigen::Index c = 0; c < hm.cols(); ++c)
      row[static_cast<std::size_t>(c)] = hm(r, c);
    x.history.rows.push_back(row);
  }
}

template void write_vtu<2>(const std::string&, const Solver<2>&, bool,
                           const std::vector<std::string>&);
template void write_vtu<3>(const std::string&, const Solver<3>&, bool,
                           const std::vector<std::string>&);
template void write_checkpoint<2>(const std::string&, const Solver<2>&, const CheckpointExtra&);
template void write_checkpoint<3>(const std::string&, const Solver<3>&, const CheckpointExtra&);
template void read_checkpoint<2>(const std::string&, Solver<2>&, CheckpointExtra&);
template void read_checkpoint<3>(const std::string&, Solver<3>&, CheckpointExtra&);

} // namespace pnc::gimp
