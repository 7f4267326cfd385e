#pragma once
// pnc/core/atomic_file.hpp: outputs appear whole or not at all, and only where a regular
// file may be replaced.
//
// AtomicOutput creates a fresh temporary file next to the final one (same directory, name
// `.<final name>.tmp.<random>`, created exclusively with O_EXCL|O_NOFOLLOW, mode 0644 less
// the umask) and hands out its path; writers (HDF5, std::ofstream) open it by name and
// truncate it. commit() fsyncs the file, renames it into place (rename(2) is atomic on one
// file system) and fsyncs the directory. If the object is destroyed without commit() (an
// exception, a bad input discovered late), the temporary file is removed, so a failed
// command never leaves a partial output behind.
//
// Rules on the final path (checked when the object is made and again at commit, with
// lstat, so a symbolic link is judged itself and never followed): it is not empty, its
// directory exists and is a directory, and if something exists at the path it is a regular
// file (not a symbolic link, device, fifo, socket or directory). A violation is a
// pnc::InputError naming the user's path and the rule, never the temporary file.
#include <string>

namespace pnc {

class AtomicOutput {
public:
  /// Checks `final_path` (rules above) and creates the temporary file. Throws InputError.
  explicit AtomicOutput(std::string final_path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// The temporary file (exists, empty until written); open it by name and truncate.
  const std::string& temp_path() const { return temp_; }
  const std::string& final_path() const { return final_; }
  /// fsyncs the temporary file, renames it onto the final path, fsyncs the directory.
  /// Throws InputError (naming the final path) on failure; the temporary file is removed.
  void commit();

private:
  std::string final_;
  std::string temp_;
  bool committed_ = false;
};

/// Throws InputError (source `path`, field `field`) unless `path` may receive an output file
/// by rename: the rules above. Creates nothing.
void check_output_file(const std::string& path, const std::string& field = "--out");

/// Creates directory `dir` and its parents as needed (like mkdir -p, mode 0777 less the
/// umask). Throws InputError (source `dir`, field `field`) naming the rule when `dir` is empty,
/// when it or a parent exists but is not a directory, or when it cannot be created or is not
/// writable.
void make_output_directory(const std::string& dir, const std::string& field = "--out");

/// Writes `text` to `path` atomically.
void write_text_atomically(const std::string& path, const std::string& text);

/// 64-bit FNV-1a hash of a file's bytes, as 16 hex digits (data provenance, not security).
std::string file_fnv1a64(const std::string& path);

} // namespace pnc
