#include "pnc/core/run_dir.hpp"

#include "pnc/core/atomic_file.hpp"
#include "pnc/core/error.hpp"
#include "pnc/core/params.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <set>

namespace pnc {

namespace fs = std::filesystem;

namespace {

/// "pid N: command" from the holder's lock file (best effort: the holder may be writing it).
std::string holder(int fd) {
  std::string text(4096, '\0');
  const ssize_t n = ::pread(fd, text.data(), text.size(), 0);
  text.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  std::string pid = "unknown", cmd;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(at, end - at);
    if (line.rfind("pid ", 0) == 0) pid = line.substr(4);
    if (line.rfind("command ", 0) == 0) cmd = line.substr(8);
    at = end + 1;
  }
  return "pid " + pid + (cmd.empty() ? std::string() : ": " + cmd);
}

} // namespace

std::string RunDirLock::lock_path(const std::string& dir) {
  return (fs::path(dir) / ".pnc.lock").string();
}

RunDirLock::RunDirLock(const std::string& dir, const std::string& command,
                       const std::string& field) {
  make_output_directory(dir, field);
  const std::string path = lock_path(dir);
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd_ < 0)
    fail(dir, field, dir,
         errno == ELOOP ? "its lock file " + path + " is a symbolic link (refused)"
                        : "cannot open its lock file " + path + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    fd_ = -1;
    fail(dir, field, dir, "its lock file " + path + " is not a regular file");
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    const std::string who = err == EWOULDBLOCK ? holder(fd_) : std::string();
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK)
      fail(dir, field, dir,
           "is in use by another pnc process (" + who +
               "): one run directory takes one process; wait for it to end or use another " +
               field + " directory");
    fail(dir, field, dir, "cannot lock " + path + ": " + std::strerror(err));
  }
  const std::string text = "pid " + std::to_string(::getpid()) + "\ncommand " + command + "\n";
  if (::ftruncate(fd_, 0) != 0 ||
      ::pwrite(fd_, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
    // the lock holds without the note; another process then reads "pid unknown"
  }
}

RunDirLock::~RunDirLock() {
  if (fd_ >= 0)
    ::close(fd_); // releases the lock (children forked meanwhile hold it until they end)
}

void refuse_existing_run(const std::string& dir, bool resume,
                         const std::vector<std::string>& markers, const std::string& field) {
  if (resume) return;
  for (const std::string& m : markers) {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(fs::path(dir) / m, ec)))
      fail(dir, field, dir,
           "already holds a run (" + m + "): add --resume to continue it, or use a new " + field +
               " directory");
  }
}

namespace {

/// The first place where `a` and `b` differ (both differ somewhere): its path below `at` and
/// the two values there ("<absent>" for a missing key).
struct Difference {
  std::string key, was, is;
};

Difference first_difference(const nlohmann::json& a, const nlohmann::json& b,
                            const std::string& at) {
  const auto join = [&](const std::string& k) { return at.empty() ? k : at + "." + k; };
  if (a.is_object() && b.is_object()) {
    std::set<std::string> keys;
    for (const nlohmann::json* o : {&a, &b})
      for (auto it = o->begin(); it != o->end(); ++it)
        keys.insert(it.key());
    for (const std::string& k : keys) {
      const bool in_a = a.contains(k), in_b = b.contains(k);
      if (in_a && in_b && a.at(k) == b.at(k)) continue;
      if (in_a && in_b) return first_difference(a.at(k), b.at(k), join(k));
      return {join(k), in_a ? a.at(k).dump() : "<absent>", in_b ? b.at(k).dump() : "<absent>"};
    }
  }
  if (a.is_array() && b.is_array() && a.size() == b.size())
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i] != b[i]) return first_difference(a[i], b[i], at + "[" + std::to_string(i) + "]");
  return {at, a.dump(), b.dump()};
}

} // namespace

void require_same_input(const std::string& src, const nlohmann::json& stored,
                        const nlohmann::json& now, const std::string& stored_in,
                        const std::string& may_change, const std::string& flag) {
  if (stored == now) return;
  const Difference d = first_difference(stored, now, "");
  fail(src, d.key, clip(d.is),
       "differs from the input this run was started with (" + clip(d.was) + ", stored in " +
           stored_in + "): " + flag + " continues a run only with the same input" +
           (may_change.empty() ? std::string() : " (" + may_change + " may change)") +
           "; restore the value or start a new run in another --out directory");
}

} // namespace pnc
