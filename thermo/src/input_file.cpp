// Reading a thermo input file (input_file.hpp).
#include "input_file.hpp"

#include "pnc/core/params.hpp"

namespace pnc::thermo::detail {

nlohmann::json read_input_json(const std::string& path, const std::string& what) {
  return read_input_file(path, what, "--input"); // D357
}

} // namespace pnc::thermo::detail
