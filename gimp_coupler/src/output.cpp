// VTU/PVD frames, CSV histories and HDF5 checkpoints of the GIMP solver (output.hpp).
#include "pnc/gimp_coupler/output.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/hdf5_io.hpp"
#include "pnc/core/version.hpp"

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

/// One DataArray: name, number of components, values (double) or ints.
class VtuWriter {
public:
  explicit VtuWriter(bool binary) : binary_(binary) { s_ << std::setprecision(10); }
  void array(const std::string& name, int ncomp, const std::vector<double>& v) {
    s_ << "<DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"" << ncomp
       << "\" format=\"" << (binary_ ? "binary" : "ascii") << "\">\n";
    if (binary_) {
      encode(v.data(), v.size() * sizeof(double));
    } else {
      for (std::size_t i = 0; i < v.size(); ++i)
        s_ << v[i] << ((i + 1) % 9 ? ' ' : '\n');
    }
    s_ << "\n</DataArray>\n";
  }
  void iarray(const std::string& name, const std::vector<std::int32_t>& v,
              const char* type = "Int32") {
    s_ << "<DataArray type=\"" << type << "\" Name=\"" << name << "\" format=\""
       << (binary_ ? "binary" : "ascii") << "\">\n";
    if (binary_) {
      encode(v.data(), v.size() * sizeof(std::int32_t));
    } else {
      for (std::size_t i = 0; i < v.size(); ++i)
        s_ << v[i] << ((i + 1) % 20 ? ' ' : '\n');
    }
    s_ << "\n</DataArray>\n";
  }
  void uarray(const std::string& name, const std::vector<std::uint8_t>& v) {
    s_ << "<DataArray type=\"UInt8\" Name=\"" << name << "\" format=\""
       << (binary_ ? "binary" : "ascii") << "\">\n";
    if (binary_) {
      encode(v.data(), v.size());
    } else {
      for (std::size_t i = 0; i < v.size(); ++i)
        s_ << int(v[i]) << ((i + 1) % 20 ? ' ' : '\n');
    }
    s_ << "\n</DataArray>\n";
  }
  std::ostringstream& os() { return s_; }

private:
  void encode(const void* p, std::size_t nbytes) {
    // VTK "binary" inline format: base64 of a UInt32 byte count followed by the data.
    std::vector<unsigned char> buf(4 + nbytes);
    const auto nb = static_cast<std::uint32_t>(nbytes);
    std::memcpy(buf.data(), &nb, 4);
    if (nbytes) std::memcpy(buf.data() + 4, p, nbytes);
    s_ << base64(buf.data(), buf.size());
  }
  bool binary_;
  std::ostringstream s_;
};

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
  VtuWriter w(binary);
  auto& o = w.os();
  o << "<?xml version=\"1.0\"?>\n<!-- pnc gimp particles; SI units; " << version_string()
    << "; materials:";
  for (std::size_t i = 0; i < material_names.size(); ++i)
    o << ' ' << i << '=' << material_names[i];
  o << " -->\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" "
       "header_type=\"UInt32\">\n<UnstructuredGrid>\n<FieldData>\n";
  w.array("TIME", 1, {s.time});
  o << "</FieldData>\n<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n";
  auto vec3 = [&](auto get) {
    std::vector<double> v(3 * n, 0.0);
    for (std::size_t p = 0; p < n; ++p) {
      const auto x = get(p);
      for (int a = 0; a < D; ++a)
        v[3 * p + a] = x[a];
    }
    return v;
  };
  o << "<Points>\n";
  w.array("Points", 3, vec3([&](std::size_t p) { return P.x[p]; }));
  o << "</Points>\n<Cells>\n";
  {
    std::vector<std::int32_t> conn(n), off(n);
    std::vector<std::uint8_t> types(n, 1); // VTK_VERTEX
    for (std::size_t p = 0; p < n; ++p) {
      conn[p] = static_cast<std::int32_t>(p);
      off[p] = static_cast<std::int32_t>(p + 1);
    }
    w.iarray("connectivity", conn);
    w.iarray("offsets", off);
    w.uarray("types", types);
  }
  o << "</Cells>\n<PointData Vectors=\"velocity\" Tensors=\"stress\">\n";
  w.array("displacement", 3,
          vec3([&](std::size_t p) -> typename Solver<D>::Vec { return P.x[p] - P.x0[p]; }));
  w.array("velocity", 3, vec3([&](std::size_t p) { return P.v[p]; }));
  {
    std::vector<double> sig(9 * n), eps(9 * n);
    for (std::size_t p = 0; p < n; ++p) {
      const Mat3 F = to3<D>(P.F[p]);
      const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          sig[9 * p + 3 * i + j] = P.sigma[p](i, j);
          eps[9 * p + 3 * i + j] = E(i, j);
        }
    }
    w.array("stress", 9, sig);
    w.array("strain", 9, eps);
  }
  {
    std::vector<double> rho(n), V(n), m(n), W(n);
    std::vector<std::int32_t> mat(n);
    for (std::size_t p = 0; p < n; ++p) {
      rho[p] = P.m[p] / P.V[p];
      V[p] = P.V[p];
      m[p] = P.m[p];
      W[p] = P.W[p];
      mat[p] = P.mat[p];
    }
    w.array("density", 1, rho);
    w.array("volume", 1, V);
    w.array("mass", 1, m);
    w.array("strain_energy_density", 1, W);
    w.iarray("material", mat);
  }
  // State variables, by name over all materials.
  std::vector<std::string> names;
  for (const auto& mt : s.materials)
    for (const auto& nm : mt->state_names())
      if (std::find(names.begin(), names.end(), nm) == names.end()) names.push_back(nm);
  for (const auto& nm : names) {
    std::vector<double> v(n, 0.0);
    for (std::size_t p = 0; p < n; ++p) {
      const auto sn = s.materials[static_cast<std::size_t>(P.mat[p])]->state_names();
      for (std::size_t k = 0; k < sn.size(); ++k)
        if (sn[k] == nm) v[p] = P.state[p * static_cast<std::size_t>(P.state_stride) + k];
    }
    w.array(nm, 1, v);
  }
  o << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  write_text_atomically(path, o.str());
}

void write_pvd(const std::string& path, const std::vector<std::string>& files,
               const std::vector<double>& times) {
  std::ostringstream o;
  o << std::setprecision(12);
  o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (std::size_t i = 0; i < files.size(); ++i)
    o << "  <DataSet timestep=\"" << times[i] << "\" part=\"0\" file=\"" << files[i] << "\"/>\n";
  o << "</Collection>\n</VTKFile>\n";
  write_text_atomically(path, o.str());
}

void History::write_csv(const std::string& path) const {
  std::ostringstream o;
  o << std::setprecision(12);
  o << "# pnc gimp history; time in s, energies and works in J, reactions in N\n";
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
    const auto& P = s.particles;
    const auto n = static_cast<Eigen::Index>(P.size());
    f.write_string("/format", "pnc gimp checkpoint 1");
    f.write_string("/software", version_string());
    f.write_string("/input_hash", x.input_hash);
    f.write_scalar("/dimension", D);
    f.write_scalar("/time", s.time);
    f.set_attr("/time", "units", "s");
    f.write_scalar("/steps", static_cast<double>(s.steps));
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
  if (!x.input_hash.empty() && hash != x.input_hash)
    fail(path, "/input_hash", hash,
         "the input file changed since this checkpoint was written (expected " + x.input_hash +
             "); start a new run without --resume");
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
