// Atomic, non-clobbering outputs (see atomic_file.hpp for the rules).
#include "pnc/core/atomic_file.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/fd_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace pnc {

namespace {

std::string errno_text(int e) {
  return std::strerror(e);
}

/// The directory part of `path` ("." when there is none) and the last component.
void split(const std::string& path, std::string& dir, std::string& base) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) {
    dir = ".";
    base = path;
  } else {
    dir = slash == 0 ? "/" : path.substr(0, slash);
    base = path.substr(slash + 1);
  }
}

const char* kind_of(mode_t m) {
  if (S_ISLNK(m)) return "a symbolic link";
  if (S_ISDIR(m)) return "a directory";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISFIFO(m)) return "a fifo";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

void fsync_path(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | flags);
  if (fd < 0) return;
  ::fsync(fd); // best effort on file systems without fsync on directories
  ::close(fd);
}

} // namespace

void check_output_file(const std::string& path, const std::string& field) {
  if (path.empty()) fail("<command line>", field, "", "an output file name must not be empty");
  std::string dir, base;
  split(path, dir, base);
  if (base.empty() || base == "." || base == "..")
    fail(path, field, "", "must name a file, not a directory");
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0)
    fail(path, field, "",
         "the output directory '" + dir + "' cannot be used: " + errno_text(errno));
  if (!S_ISDIR(st.st_mode))
    fail(path, field, "", "'" + dir + "' is " + kind_of(st.st_mode) + ", not a directory");
  if (::lstat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    fail(path, field, "",
         std::string("exists and is ") + kind_of(st.st_mode) +
             "; pnc only replaces regular files (remove it or choose another path)");
}

void make_output_directory(const std::string& dir, const std::string& field) {
  if (dir.empty()) fail("<command line>", field, "", "an output directory must not be empty");
  std::string prefix;
  std::size_t pos = 0;
  while (pos <= dir.size()) {
    std::size_t next = dir.find('/', pos);
    if (next == std::string::npos) next = dir.size();
    prefix = dir.substr(0, next);
    pos = next + 1;
    if (prefix.empty()) continue; // leading '/' or "//"
    struct stat st {};
    if (::stat(prefix.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode))
        fail(dir, field, "",
             "cannot be an output directory: '" + prefix + "' is " + kind_of(st.st_mode) +
                 ", not a directory");
      continue;
    }
    if (errno != ENOENT)
      fail(dir, field, "", "cannot be an output directory: '" + prefix + "': " + errno_text(errno));
    if (::mkdir(prefix.c_str(), 0777) != 0 && errno != EEXIST)
      fail(dir, field, "",
           "cannot create the output directory '" + prefix + "': " + errno_text(errno));
  }
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    fail(dir, field, "", "the output directory is not writable: " + errno_text(errno));
}

AtomicOutput::AtomicOutput(std::string final_path) : final_(std::move(final_path)) {
  check_output_file(final_, "");
  std::string dir, base;
  split(final_, dir, base);
  if (base.size() > 200) base.resize(200); // the temporary name stays under NAME_MAX
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string t = (dir == "." && final_.find('/') == std::string::npos) ? "" : dir + "/";
    if (dir == "/") t = "/";
    t += "." + base + ".tmp." + random_hex(8);
    const int fd = ::open(t.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0) {
      ::close(fd);
      temp_ = t;
      return;
    }
    if (errno != EEXIST)
      fail(final_, "", "",
           "cannot create a file in the directory '" + dir + "': " + errno_text(errno));
  }
  fail(final_, "", "", "cannot find an unused temporary name in '" + dir + "'");
}

AtomicOutput::~AtomicOutput() {
  if (!committed_ && !temp_.empty()) ::unlink(temp_.c_str());
}

void AtomicOutput::commit() {
  struct stat st {};
  if (::lstat(temp_.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
    ::unlink(temp_.c_str());
    fail(final_, "", "", "the output was not written (its temporary file is gone)");
  }
  fsync_path(temp_, O_NOFOLLOW);
  try {
    check_output_file(final_, ""); // again: the path may have changed while we wrote
  } catch (...) {
    ::unlink(temp_.c_str());
    throw;
  }
  if (std::rename(temp_.c_str(), final_.c_str()) != 0) {
    const std::string why = errno_text(errno);
    ::unlink(temp_.c_str());
    fail(final_, "", "", "cannot move the finished output into place: " + why);
  }
  committed_ = true;
  std::string dir, base;
  split(final_, dir, base);
  fsync_path(dir, O_DIRECTORY);
}

void write_text_atomically(const std::string& path, const std::string& text) {
  AtomicOutput out(path);
  {
    std::ofstream f(out.temp_path(), std::ios::binary | std::ios::trunc);
    if (!f) fail(path, "", "", "cannot open for writing: " + errno_text(errno));
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
