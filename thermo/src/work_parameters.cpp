// The keys of a `pnc thermo work --input` file, declared once (pnc/core/parameters.hpp, D322);
// the command-line options take their checks and help from here (app/cli_parameters.hpp,
// D320). No units apply (directory paths).
#include "pnc/thermo/work_parameters.hpp"

#include "input_file.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/parameters.hpp"
#include "pnc/core/params.hpp"

#include <filesystem>
#include <memory>

namespace pnc::thermo {

Parameters work_input_parameters(WorkInput& in) {
  Parameters p("pnc thermo work input");
  p.strings("from", in.from, 1, 2,
            "`pnc characterize` output directories: one, or two at different temperatures "
            "(the entropic/energetic split); in a file relative to its folder (D322)")
      .no_default("--from gives them (one of the two is needed)")
      .also("each a non-empty path",
            [](const nlohmann::json& v, const std::string& source, const std::string& field) {
              for (std::size_t i = 0; i < v.size(); ++i)
                if (v[i].get_ref<const std::string&>().empty())
                  fail(source, field + "[" + std::to_string(i) + "]", "",
                       "must be a non-empty path (a `pnc characterize` output directory)");
            });
  return p;
}

Parameters work_input_parameters() {
  auto in = std::make_shared<WorkInput>();
  Parameters p = work_input_parameters(*in);
  p.hold(in);
  return p;
}

WorkInput parse_work_input(const nlohmann::json& j, const std::string& source) {
  WorkInput in;
  if (!j.is_object()) fail(source, "", show_json(j), "must be a JSON object (a TOML table)");
  work_input_parameters(in).read(j, source);
  return in;
}

WorkInput read_work_input(const std::string& path) {
  WorkInput in = parse_work_input(detail::read_input_json(path, "the work input file"), path);
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  for (auto& d : in.from)
    if (std::filesystem::path(d).is_relative()) d = (folder / d).lexically_normal().string();
  return in;
}

void override_work_input(WorkInput& in, const WorkInput& given,
                         const std::vector<std::string>& keys) {
  detail::override_keys(in, given, keys, [](WorkInput& w) { return work_input_parameters(w); });
}

} // namespace pnc::thermo
