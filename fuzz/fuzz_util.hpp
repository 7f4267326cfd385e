#pragma once
// fuzz/fuzz_util.hpp: what every pnc fuzz target shares (docs/hardening-fuzz.md).
//
// The contract under test: a reader given any bytes either returns or throws pnc::InputError.
// Any other exception, a crash, a sanitizer report or a leak is a bug; the target aborts so
// that libFuzzer keeps the input.
#include "pnc/core/error.hpp"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace pnc::fuzz {

/// One file per fuzzing process (in $TMPDIR or /tmp), rewritten with every input and removed at
/// exit. `suffix` selects the reader where the extension matters (".json", ".toml").
class ScratchFile {
public:
  explicit ScratchFile(const std::string& suffix) {
    const char* dir = std::getenv("TMPDIR");
    std::string tmpl = std::string(dir && *dir ? dir : "/tmp") + "/pnc-fuzz-XXXXXX" + suffix;
    const int fd = mkstemps(tmpl.data(), static_cast<int>(suffix.size()));
    if (fd < 0) {
      std::perror("pnc fuzz: mkstemps");
      std::abort();
    }
    ::close(fd);
    path_ = tmpl;
  }
  ~ScratchFile() { std::remove(path_.c_str()); }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  /// Replaces the file's content with the bytes; returns the path.
  const std::string& write(const std::uint8_t* data, std::size_t size) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
      std::perror("pnc fuzz: cannot write the scratch file");
      std::abort();
    }
    return path_;
  }
  const std::string& path() const { return path_; }

private:
  std::string path_;
};

/// Runs f(); pnc::InputError is the expected way to refuse an input, anything else aborts.
template <class F> void expect_clean(F&& f) {
  try {
    f();
  } catch (const pnc::InputError&) {
    // refused with a message naming source, field, value and rule: fine
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pnc fuzz: an exception other than pnc::InputError escaped: %s\n",
                 e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "pnc fuzz: a non-standard exception escaped\n");
    std::abort();
  }
}

} // namespace pnc::fuzz
