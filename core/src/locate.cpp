// Shipped files relative to the running executable (locate.hpp, decision D151).
#include "pnc/core/locate.hpp"

#include "pnc/core/error.hpp"

#include <cstdlib>
#include <system_error>

#include <unistd.h>

// Relative to the install prefix; set by core/CMakeLists.txt from GNUInstallDirs.
#ifndef PNC_SCRIPTS_RELDIR
#define PNC_SCRIPTS_RELDIR "share/pnc/scripts"
#endif
#ifndef PNC_LIBEXEC_RELDIR
#define PNC_LIBEXEC_RELDIR "libexec/pnc"
#endif

namespace pnc {

namespace fs = std::filesystem;

fs::path executable_dir() {
  std::string buf(4096, '\0');
  const ssize_t n = readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  if (n <= 0 || static_cast<std::size_t>(n) >= buf.size() - 1) return {};
  buf.resize(static_cast<std::size_t>(n));
  return fs::path(buf).parent_path();
}

std::string Located::looked_in() const {
  std::string s = "looked in: ";
  for (std::size_t i = 0; i < tried.size(); ++i)
    s += (i ? ", " : "") + tried[i];
  return s;
}

std::string shipped_relative_dir(ShippedDir dir) {
  return dir == ShippedDir::scripts ? PNC_SCRIPTS_RELDIR : PNC_LIBEXEC_RELDIR;
}

Located locate_shipped(ShippedDir dir, const std::string& name, const char* env_dir) {
  Located r;
  auto try_path = [&r](const fs::path& p) {
    r.tried.push_back(p.lexically_normal().string());
    std::error_code ec;
    if (fs::is_regular_file(p, ec)) {
      r.path = r.tried.back();
      return true;
    }
    return false;
  };
  const char* env = env_dir ? std::getenv(env_dir) : nullptr;
  if (env && *env) {
    try_path(fs::path(env) / name);
    return r;
  }
  const fs::path x = executable_dir();
  if (x.empty()) return r;
  const std::string rel = shipped_relative_dir(dir);
  if (dir == ShippedDir::libexec && try_path(x / name)) return r;
  if (try_path(x / ".." / rel / name)) return r;
  try_path(x / ".." / ".." / rel / name);
  return r;
}

std::string require_shipped(ShippedDir dir, const std::string& name, const char* env_dir) {
  const Located r = locate_shipped(dir, name, env_dir);
  if (!r.path.empty()) return r.path;
  const char* env = env_dir ? std::getenv(env_dir) : nullptr;
  if (env && *env) // the override names the one place to look
    fail(std::string("$") + env_dir, "", env,
         "the directory given by " + std::string(env_dir) + " has no " + name + " (" +
             r.looked_in() + ")");
  std::string rule = "not found (" + r.looked_in() + ")";
  if (env_dir) rule += "; set " + std::string(env_dir) + " to the directory holding it";
  fail("<pnc installation>", "", name, rule + " (install layout: docs/install.md)");
}

} // namespace pnc
