#pragma once
// pnc/core/atomic_file.hpp: outputs appear whole or not at all.
//
// AtomicOutput hands out a temporary path next to the final one; commit() renames it into
// place (rename(2) is atomic on one file system). If the object is destroyed without
// commit() (an exception, a bad input discovered late), the temporary file is removed, so a
// failed command never leaves a partial output behind.
#include <string>

namespace pnc {

class AtomicOutput {
public:
  explicit AtomicOutput(std::string final_path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::string& temp_path() const { return temp_; }
  const std::string& final_path() const { return final_; }
  /// Renames the temporary file onto the final path. Throws on failure.
  void commit();

private:
  std::string final_;
  std::string temp_;
  bool committed_ = false;
};

/// Writes `text` to `path` atomically.
void write_text_atomically(const std::string& path, const std::string& text);

/// 64-bit FNV-1a hash of a file's bytes, as 16 hex digits (data provenance, not security).
std::string file_fnv1a64(const std::string& path);

} // namespace pnc
