// Point-cloud VTU frames and PVD collections (vtu.hpp, D236).
#include "pnc/core/vtu.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/html_page.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace pnc::vtu {

namespace {

/// Names, units and file names go into XML attributes unescaped: refuse what would need it.
/// `=` is refused too in names and units: the field data "units" lists "name=unit".
void check_text(const std::string& path, const std::string& field, const std::string& s,
                bool allow_equals = false) {
  if (s.empty()) fail(path, field, s, "must not be empty");
  for (char c : s)
    if (c == '"' || c == '<' || c == '>' || c == '&' || (c == '=' && !allow_equals) ||
        static_cast<unsigned char>(c) < 0x20)
      fail(path, field, s,
           allow_equals ? "must not contain quotes, <, >, & or control characters"
                        : "must not contain quotes, <, >, &, = or control characters");
}

class Writer {
public:
  explicit Writer(const Options& o) : o_(o) { s_.precision(o.precision); }
  std::ostringstream& os() { return s_; }

  void doubles(const std::string& name, int ncomp, const double* v, std::size_t n) {
    head("Float64", name, ncomp, n);
    if (o_.encoding == Encoding::base64) {
      encode(v, n * sizeof(double));
    } else {
      const std::size_t c = static_cast<std::size_t>(ncomp);
      for (std::size_t i = 0; i < n; ++i)
        s_ << v[i] << ((i + 1) % c ? ' ' : '\n');
    }
    s_ << "</DataArray>\n";
  }
  void ints(const std::string& name, const std::int32_t* v, std::size_t n) {
    head("Int32", name, 1, n);
    if (o_.encoding == Encoding::base64) {
      encode(v, n * sizeof(std::int32_t));
    } else {
      for (std::size_t i = 0; i < n; ++i)
        s_ << v[i] << '\n';
    }
    s_ << "</DataArray>\n";
  }
  void types(std::size_t n) {
    head("UInt8", "types", 1, n);
    const std::vector<unsigned char> t(n, 1); // VTK_VERTEX
    if (o_.encoding == Encoding::base64) {
      encode(t.data(), n);
    } else {
      for (std::size_t i = 0; i < n; ++i)
        s_ << "1\n";
    }
    s_ << "</DataArray>\n";
  }
  /// A vtkStringArray in VTK's ASCII form: the bytes of each string and a 0, as integers.
  void strings(const std::string& name, const std::vector<std::string>& v) {
    s_ << "<Array type=\"String\" Name=\"" << name << "\" NumberOfTuples=\"" << v.size()
       << "\" format=\"ascii\">\n";
    for (const auto& x : v) {
      for (unsigned char c : x)
        s_ << int(c) << ' ';
      s_ << "0\n";
    }
    s_ << "</Array>\n";
  }

private:
  void head(const char* type, const std::string& name, int ncomp, std::size_t nvalues) {
    s_ << "<DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfTuples=\""
       << nvalues / static_cast<std::size_t>(ncomp) << "\"";
    if (ncomp > 1) s_ << " NumberOfComponents=\"" << ncomp << "\"";
    s_ << " format=\"" << (o_.encoding == Encoding::base64 ? "binary" : "ascii") << "\">\n";
  }
  void encode(const void* p, std::size_t nbytes) {
    std::string buf(4 + nbytes, '\0');
    const auto nb = static_cast<std::uint32_t>(nbytes);
    std::memcpy(buf.data(), &nb, 4);
    if (nbytes) std::memcpy(buf.data() + 4, p, nbytes);
    s_ << pnc::html::base64(buf) << '\n';
  }
  Options o_;
  std::ostringstream s_;
};

void check_frame(const std::string& path, const Frame& f, const Options& opt) {
  const std::size_t n = f.points.size();
  if (opt.precision < 1 || opt.precision > 17)
    fail(path, "precision", std::to_string(opt.precision), "must be 1 to 17 digits");
  // the inline binary header is a UInt32 byte count: the largest array must fit
  constexpr std::size_t max_bytes = std::numeric_limits<std::uint32_t>::max();
  if (opt.encoding == Encoding::base64 && 9 * n * sizeof(double) > max_bytes)
    fail(path, "points", std::to_string(n),
         "too many points for base64 output with a UInt32 header (use ASCII)");
  for (const PointArray& a : f.arrays) {
    check_text(path, "point array name", a.name);
    check_text(path, "unit of '" + a.name + "'", a.unit);
    if (!a.labels.empty()) {
      if (a.components != 1 || !a.values.empty())
        fail(path, a.name, std::to_string(a.components),
             "an integer array has 1 component and no floating-point values");
      if (a.labels.size() != n)
        fail(path, a.name, std::to_string(a.labels.size()),
             "needs one label per point (" + std::to_string(n) + ")");
      continue;
    }
    if (a.components != 1 && a.components != 3 && a.components != 6 && a.components != 9)
      fail(path, a.name, std::to_string(a.components),
           "components must be 1, 3, 6 (symmetric tensor) or 9 (tensor)");
    if (a.values.size() != n * static_cast<std::size_t>(a.components))
      fail(path, a.name, std::to_string(a.values.size()),
           "needs points x components = " + std::to_string(n) + " x " +
               std::to_string(a.components) + " values");
  }
  for (const FieldScalar& s : f.field) {
    check_text(path, "field data name", s.name);
    check_text(path, "unit of '" + s.name + "'", s.unit);
  }
}

/// The shortest text that reads back as the same double.
std::string shortest(double x) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

} // namespace

std::array<double, 6> symmetric6(const double* m) {
  return {m[0], m[4], m[8], m[1], m[5], m[2]};
}

void write_vtu(const std::string& path, const Frame& f, const Options& opt) {
  check_frame(path, f, opt);
  const std::size_t n = f.points.size();
  Writer w(opt);
  auto& o = w.os();
  o << "<?xml version=\"1.0\"?>\n";
  if (!f.comment.empty()) { // XML forbids "--" inside a comment
    std::string c = f.comment;
    for (auto at = c.find("--"); at != std::string::npos; at = c.find("--", at))
      c.replace(at, 2, "- -");
    o << "<!-- " << c << " -->\n";
  }
  o << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" "
       "header_type=\"UInt32\">\n<UnstructuredGrid>\n<FieldData>\n";
  std::vector<std::string> units;
  for (const FieldScalar& s : f.field) {
    w.doubles(s.name, 1, &s.value, 1);
    units.push_back(s.name + "=" + s.unit);
  }
  for (const PointArray& a : f.arrays)
    units.push_back(a.name + "=" + a.unit);
  units.emplace_back("Points=m");
  w.strings("units", units);
  o << "</FieldData>\n<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n";
  o << "<Points>\n";
  w.doubles("Points", 3, n ? f.points[0].data() : nullptr, 3 * n);
  o << "</Points>\n<Cells>\n";
  {
    std::vector<std::int32_t> conn(n), off(n);
    for (std::size_t p = 0; p < n; ++p) {
      conn[p] = static_cast<std::int32_t>(p);
      off[p] = static_cast<std::int32_t>(p + 1);
    }
    w.ints("connectivity", conn.data(), n);
    w.ints("offsets", off.data(), n);
    w.types(n);
  }
  o << "</Cells>\n<PointData>\n";
  for (const PointArray& a : f.arrays) {
    if (!a.labels.empty())
      w.ints(a.name, a.labels.data(), n);
    else
      w.doubles(a.name, a.components, a.values.data(), a.values.size());
  }
  o << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  write_text_atomically(path, o.str());
}

void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries) {
  std::ostringstream o;
  o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const PvdEntry& e = entries[i];
    check_text(path, "file of entry " + std::to_string(i), e.file, true);
    if (!std::isfinite(e.timestep))
      fail(path, "timestep of entry " + std::to_string(i), std::to_string(e.timestep),
           "must be finite");
    if (i > 0 && !(e.timestep > entries[i - 1].timestep)) {
      std::ostringstream v;
      v.precision(17);
      v << e.timestep << " after " << entries[i - 1].timestep;
      fail(path, "timestep of entry " + std::to_string(i), v.str(),
           "timesteps must increase strictly (use the step index or the arc length of the "
           "load path as pseudo-time when the load goes back)");
    }
    o << "  <DataSet timestep=\"" << shortest(e.timestep) << "\" part=\"0\" file=\"" << e.file
      << "\"/>\n";
  }
  o << "</Collection>\n</VTKFile>\n";
  write_text_atomically(path, o.str());
}

} // namespace pnc::vtu
