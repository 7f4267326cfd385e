#include "pnc/core/atomic_file.hpp"

#include "pnc/core/error.hpp"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace pnc {

AtomicOutput::AtomicOutput(std::string final_path) : final_(std::move(final_path)) {
  std::ostringstream s;
  s << final_ << ".tmp." << ::getpid();
  temp_ = s.str();
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) std::remove(temp_.c_str());
}

void AtomicOutput::commit() {
  if (std::rename(temp_.c_str(), final_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(temp_.c_str());
    fail(final_, "", "", "cannot move the finished output into place: " + why);
  }
  committed_ = true;
}

void write_text_atomically(const std::string& path, const std::string& text) {
  AtomicOutput out(path);
  {
    std::ofstream f(out.temp_path(), std::ios::binary);
    if (!f) fail(path, "", "", "cannot open for writing: " + std::string(std::strerror(errno)));
    f << text;
    f.flush();
    if (!f) fail(path, "", "", "write failed");
  }
  out.commit();
}

std::string file_fnv1a64(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) fail(path, "", "", "cannot open for reading");
  std::uint64_t h = 0xcbf29ce484222325ULL; // FNV-1a 64 offset basis
  char buf[1 << 16];
  while (f) {
    f.read(buf, sizeof buf);
    const std::streamsize n = f.gcount();
    for (std::streamsize i = 0; i < n; ++i) {
      h ^= static_cast<unsigned char>(buf[i]);
      h *= 1099511628211ULL;
    }
  }
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

} // namespace pnc
