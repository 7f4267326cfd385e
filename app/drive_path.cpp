// Reading the path file of `pnc material drive`: TOML and CSV are turned into the JSON form,
// and one validator (parse_path) checks it (docs/drive.md, docs/decisions.md D166).
#include "drive_path.hpp"

#include "pnc/core/csv.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <set>

namespace pnc::app {

const std::array<const char*, 6> kStrainNames = {"e11", "e22", "e33", "g23", "g13", "g12"};
const std::array<const char*, 6> kStressNames = {"s11", "s22", "s33", "s23", "s13", "s12"};

namespace {

using nlohmann::json;

constexpr int kMaxSteps = 100000;             // per segment
constexpr long long kMaxTotalSteps = 1000000; // per path
constexpr double kMaxStrain = 1.0;            // small-strain law: |strain| <= 1
constexpr double kMaxStress = 1e12;           // Pa

long long sum_steps(const std::vector<DriveSegment>& s) {
  long long n = 0;
  for (const auto& g : s)
    n += g.steps;
  return n;
}

json read_toml(const std::string& path, const std::string& text) {
  // ASCII only: component names and numbers need nothing else
  for (std::size_t i = 0; i < text.size(); ++i)
    if (static_cast<unsigned char>(text[i]) >= 0x80)
      fail(path, "",
           fmt::format("byte 0x{:02x} at offset {}", static_cast<unsigned char>(text[i]), i),
           "a path file is plain ASCII text");
  return parse_toml(text, path); // the TOML-to-JSON conversion all pnc inputs share
}

// CSV: a header `steps,<components...>`; one row per segment, every named component set.
json read_csv_path(const std::string& path) {
  const CsvTable t = read_csv(path);
  json segs = json::array();
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    json s = json::object();
    for (std::size_t c = 0; c < t.header.size(); ++c) {
      const double v = t.rows[r][c];
      if (t.header[c] == "steps" && v == std::floor(v) && std::abs(v) < 1e15)
        s["steps"] = static_cast<std::int64_t>(v);
      else
        s[t.header[c]] = v;
    }
    segs.push_back(s);
  }
  if (t.rows.empty()) fail(path, "", "", "the CSV path has a header but no segment rows");
  return json{{"segment", segs}};
}

void no_other_keys(const json& o, const std::set<std::string>& allowed, const std::string& src,
                   const std::string& where) {
  for (const auto& [k, v] : o.items())
    if (!allowed.count(k)) {
      std::string list;
      for (const auto& a : allowed)
        list += (list.empty() ? "" : ", ") + a;
      fail(src, where.empty() ? k : where + "." + k, show_json(v),
           "unknown key (allowed here: " + list + ")");
    }
}

std::array<double, 9> parse_rotation(const json& r, const std::string& src) {
  if (!r.is_object())
    fail(src, "rotation", show_json(r), "must be a table with axis + angle_deg, or matrix");
  no_other_keys(r, {"axis", "angle_deg", "matrix"}, src, "rotation");
  Eigen::Matrix3d Q;
  if (r.contains("matrix")) {
    if (r.contains("axis") || r.contains("angle_deg"))
      fail(src, "rotation", show_json(r), "give either matrix or axis + angle_deg, not both");
    const json& m = r["matrix"];
    if (!m.is_array() || m.size() != 3)
      fail(src, "rotation.matrix", show_json(m), "must be 3 rows of 3 numbers");
    for (int i = 0; i < 3; ++i) {
      const json& row = m[static_cast<std::size_t>(i)];
      if (!row.is_array() || row.size() != 3)
        fail(src, fmt::format("rotation.matrix[{}]", i + 1), show_json(row),
             "must be a row of 3 numbers");
      for (int j = 0; j < 3; ++j)
        Q(i, j) = get_number(row[static_cast<std::size_t>(j)], src,
                             fmt::format("rotation.matrix[{}][{}]", i + 1, j + 1), -1.0, 1.0);
    }
    const double orth = (Q.transpose() * Q - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (orth > 1e-9 || Q.determinant() < 0)
      fail(src, "rotation.matrix", show_json(m),
           fmt::format("must be a proper rotation (Q^T Q = I to 1e-9, det Q = +1); "
                       "max |Q^T Q - I| = {:.3g}, det = {:.6g}",
                       orth, Q.determinant()));
  } else {
    if (!r.contains("axis") || !r.contains("angle_deg"))
      fail(src, "rotation", show_json(r), "needs both axis and angle_deg (or matrix)");
    const json& a = r["axis"];
    if (!a.is_array() || a.size() != 3)
      fail(src, "rotation.axis", show_json(a), "must be 3 numbers");
    Eigen::Vector3d n;
    for (int i = 0; i < 3; ++i)
      n[i] = get_number(a[static_cast<std::size_t>(i)], src,
                        fmt::format("rotation.axis[{}]", i + 1), -1e6, 1e6);
    if (n.norm() < 1e-12) fail(src, "rotation.axis", show_json(a), "must not be the zero vector");
    const double deg = get_number(r["angle_deg"], src, "rotation.angle_deg", -360, 360);
    // the platelet is turned by P (active, right-hand rule); Q = P^T (D166)
    const Eigen::Matrix3d P =
        Eigen::AngleAxisd(deg * std::acos(-1.0) / 180.0, n.normalized()).toRotationMatrix();
    Q = P.transpose();
  }
  std::array<double, 9> out{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      out[static_cast<std::size_t>(3 * i + j)] = Q(i, j);
  return out;
}

DriveSegment parse_segment(const json& s, std::size_t index, const DriveSegment& prev,
                           const std::string& src) {
  const std::string where = fmt::format("segment[{}]", index + 1);
  if (!s.is_object()) fail(src, where, show_json(s), "a segment is a table of steps and targets");
  DriveSegment g = prev;
  g.label.clear();
  if (!s.contains("steps"))
    fail(src, where + ".steps", "", "missing: every segment needs its number of steps");
  g.steps = get_integer_as<int>(s["steps"], src, where + ".steps", 1, kMaxSteps);
  for (const auto& [k, v] : s.items()) {
    if (k == "steps") continue;
    if (k == "label") {
      if (!v.is_string()) fail(src, where + ".label", show_json(v), "must be a string");
      g.label = clip(v.get<std::string>(), 200);
      continue;
    }
    int idx = -1;
    char kind = 0;
    for (int i = 0; i < 6; ++i) {
      if (k == kStrainNames[static_cast<std::size_t>(i)]) idx = i, kind = 'e';
      if (k == kStressNames[static_cast<std::size_t>(i)]) idx = i, kind = 's';
    }
    if (idx < 0) {
      if (k == "e23" || k == "e13" || k == "e12")
        fail(src, where + "." + k, show_json(v),
             "shear strains are engineering shear: name them g" + k.substr(1) + " (= 2 " + k + ")");
      fail(src, where + "." + k, show_json(v),
           "unknown key: a segment has steps, label and targets e11 e22 e33 g23 g13 g12 "
           "(strain) or s11 s22 s33 s23 s13 s12 (stress, Pa)");
    }
    const std::size_t ui = static_cast<std::size_t>(idx);
    const char* other = kind == 'e' ? kStressNames[ui] : kStrainNames[ui];
    if (s.contains(other))
      fail(src, where + "." + k, show_json(v),
           std::string("a component is driven in strain or in stress, not both (") + other +
               " is also given)");
    g.kind[ui] = kind;
    g.target[ui] = kind == 'e' ? get_number(v, src, where + "." + k, -kMaxStrain, kMaxStrain)
                               : get_number(v, src, where + "." + k, -kMaxStress, kMaxStress);
  }
  return g;
}

DrivePath parse_path(const json& j, const std::string& src) {
  if (!j.is_object()) fail(src, "", show_json(j), "a path file is a table (object)");
  no_other_keys(j, {"segment", "rotation", "newton", "description"}, src, "");
  DrivePath p;
  p.source = src;
  if (j.contains("description") && !j["description"].is_string())
    fail(src, "description", show_json(j["description"]), "must be a string");
  if (j.contains("rotation")) {
    p.rotation = parse_rotation(j["rotation"], src);
    p.rotated = p.rotation != std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1};
  }
  if (j.contains("newton")) {
    const json& n = j["newton"];
    if (!n.is_object()) fail(src, "newton", show_json(n), "must be a table");
    no_other_keys(n, {"strain_tol", "max_iterations"}, src, "newton");
    if (n.contains("strain_tol"))
      p.newton_strain_tol = get_number(n["strain_tol"], src, "newton.strain_tol", 1e-16, 1e-6);
    if (n.contains("max_iterations"))
      p.newton_max_iterations =
          get_integer_as<int>(n["max_iterations"], src, "newton.max_iterations", 1, 200);
  }
  if (!j.contains("segment"))
    fail(src, "segment", "", "missing: a path needs at least one segment");
  const json& segs = j["segment"];
  if (!segs.is_array() || segs.empty())
    fail(src, "segment", show_json(segs), "must be a non-empty array of segments");
  DriveSegment prev;
  prev.kind.fill('e'); // start: every component strain-controlled at zero
  for (std::size_t i = 0; i < segs.size(); ++i) {
    prev = parse_segment(segs[i], i, prev, src);
    p.segments.push_back(prev);
    if (sum_steps(p.segments) > kMaxTotalSteps)
      fail(src, fmt::format("segment[{}].steps", i + 1), std::to_string(prev.steps),
           fmt::format("a path has at most {} steps in all", kMaxTotalSteps));
  }
  return p;
}

} // namespace

long long DrivePath::total_steps() const {
  return sum_steps(segments);
}

DrivePath read_drive_path(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext != ".toml" && ext != ".json" && ext != ".csv")
    fail(path, "", ext, "a path file ends in .toml, .json or .csv");
  if (ext == ".csv") return parse_path(read_csv_path(path), path);
  const std::string text = read_text_file(path, "the path file");
  return parse_path(ext == ".toml" ? read_toml(path, text) : parse_json(text, path), path);
}

} // namespace pnc::app
