// Reading a thermo input file (input_file.hpp).
#include "input_file.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <filesystem>

namespace pnc::thermo::detail {

nlohmann::json read_input_json(const std::string& path, const std::string& what) {
  const auto ext = std::filesystem::path(path).extension().string();
  if (ext != ".json" && ext != ".toml")
    fail(path, "--input", ext, what + " ends in .json or .toml");
  const std::string text = read_text_file(path, what);
  return ext == ".toml" ? parse_toml(text, path) : parse_json(text, path);
}

} // namespace pnc::thermo::detail
