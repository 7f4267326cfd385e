// The private channel between a stage child and its LAMMPS server (private_channel.hpp).
#include "pnc/md/private_channel.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/fd_io.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace pnc::md {

namespace {

std::string parent_dir(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

/// Where the private directory goes: $TMPDIR when absolute and the socket path fits in
/// sun_path, else /tmp.
std::string base_directory() {
  const char* t = std::getenv("TMPDIR");
  const std::string tail = "/pnc-lmp-XXXXXX/s";
  if (t && t[0] == '/') {
    std::string b = t;
    while (b.size() > 1 && b.back() == '/')
      b.pop_back();
    if (b.size() + tail.size() < sizeof(sockaddr_un::sun_path)) return b;
  }
  return "/tmp";
}

bool fill_address(const std::string& path, sockaddr_un& a) {
  if (path.empty() || path.size() >= sizeof(a.sun_path)) return false;
  a = sockaddr_un{};
  a.sun_family = AF_UNIX;
  std::memcpy(a.sun_path, path.data(), path.size());
  return true;
}

/// Reads exactly `n` bytes before `deadline_ms` (steady clock) passes; false otherwise.
bool read_with_deadline(int fd, char* p, std::size_t n, int timeout_ms) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (n > 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          end - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) return false;
    pollfd q{fd, POLLIN, 0};
    const int r = poll(&q, 1, static_cast<int>(left));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    const ssize_t got = recv(fd, p, n, 0);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    p += got;
    n -= static_cast<std::size_t>(got);
  }
  return true;
}

bool equal_constant_time(const char* a, const char* b, std::size_t n) {
  unsigned char d = 0;
  for (std::size_t i = 0; i < n; ++i)
    d = static_cast<unsigned char>(d | (a[i] ^ b[i]));
  return d == 0;
}

} // namespace

std::string random_token() {
  static_assert(kTokenChars / 2 <= 32, "random_hex gives at most 32 bytes");
  return random_hex(kTokenChars / 2);
}

bool is_same_or_descendant(pid_t pid, pid_t ancestor) {
  for (int depth = 0; depth < 64 && pid > 0; ++depth) {
    if (pid == ancestor) return true;
    if (pid == 1) return false;
    std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
    std::string stat((std::istreambuf_iterator<char>(f)), {});
    const auto close_paren = stat.rfind(')'); // the command name may hold blanks and ')'
    if (close_paren == std::string::npos) return false;
    std::istringstream rest(stat.substr(close_paren + 1));
    char state = 0;
    long ppid = 0;
    if (!(rest >> state >> ppid)) return false;
    pid = static_cast<pid_t>(ppid);
  }
  return false;
}

bool in_our_slurm_job(pid_t pid) {
  const char* ours = std::getenv("SLURM_JOB_ID");
  if (!ours || !*ours) return false;
  std::ifstream f("/proc/" + std::to_string(pid) + "/environ"); // owner-readable only
  std::string env((std::istreambuf_iterator<char>(f)), {});
  const std::string want = std::string("SLURM_JOB_ID=") + ours;
  std::size_t at = 0;
  while (at < env.size()) {
    const auto end = env.find('\0', at);
    if (env.compare(at, (end == std::string::npos ? env.size() : end) - at, want) == 0) return true;
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return false;
}

PrivateListener::PrivateListener() : token_(random_token()) {
  std::string templ = base_directory() + "/pnc-lmp-XXXXXX";
  if (!mkdtemp(templ.data())) // mkdtemp creates the directory with mode 0700
    fail(templ, "", "",
         std::string("cannot create the private socket directory: ") + strerror(errno));
  dir_ = templ;
  path_ = dir_ + "/s";
  sockaddr_un a{};
  fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0 || !fill_address(path_, a)) {
    const std::string why = fd_ < 0 ? strerror(errno) : "path too long";
    close();
    fail(path_, "", "", "cannot create the server socket: " + why);
  }
  // umask 0177 while binding: the socket file is created 0600, never wider even for a moment
  const mode_t old = umask(0177);
  const int b = bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
  const int e = errno;
  umask(old);
  if (b != 0 || chmod(path_.c_str(), 0600) != 0 || listen(fd_, 16) != 0) {
    const std::string why = strerror(b != 0 ? e : errno);
    close();
    fail(path_, "", "", "cannot open the server socket: " + why);
  }
}

PrivateListener::~PrivateListener() {
  close();
}

void PrivateListener::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!path_.empty()) ::unlink(path_.c_str());
  if (!dir_.empty()) ::rmdir(dir_.c_str());
  path_.clear();
  dir_.clear();
}

int PrivateListener::accept_one(pid_t ancestor, int timeout_ms, int token_timeout_ms) {
  if (fd_ < 0) return -1;
  pollfd p{fd_, POLLIN, 0};
  if (poll(&p, 1, timeout_ms) <= 0) return -1;
  const int c = accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC);
  if (c < 0) return -1;
  auto refuse = [&](const std::string& why) {
    ::close(c);
    ++refused_;
    last_refusal_ = why;
    return -1;
  };
  ucred cred{};
  socklen_t len = sizeof cred;
  if (getsockopt(c, SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0)
    return refuse(std::string("SO_PEERCRED failed: ") + strerror(errno));
  if (cred.uid != geteuid()) return refuse("peer uid " + std::to_string(cred.uid) + " is not ours");
  if (ancestor > 0 && !is_same_or_descendant(cred.pid, ancestor))
    return refuse("peer pid " + std::to_string(cred.pid) + " does not descend from pid " +
                  std::to_string(ancestor));
  if (ancestor <= 0 && !in_our_slurm_job(cred.pid)) // srun's tasks descend from slurmstepd
    return refuse("peer pid " + std::to_string(cred.pid) + " is not a task of our Slurm job");
  char got[kTokenChars];
  if (!read_with_deadline(c, got, sizeof got, token_timeout_ms))
    return refuse("peer pid " + std::to_string(cred.pid) + " sent no token");
  if (!equal_constant_time(got, token_.data(), kTokenChars))
    return refuse("peer pid " + std::to_string(cred.pid) + " sent a wrong token");
  return c;
}

int connect_private(const std::string& socket_path, const std::string& token, std::string& why) {
  const std::string dir = parent_dir(socket_path);
  struct stat st {};
  if (lstat(dir.c_str(), &st) != 0) {
    why = "cannot inspect the socket directory '" + dir + "': " + strerror(errno);
    return -1;
  }
  if (!S_ISDIR(st.st_mode)) {
    why = "the socket directory '" + dir + "' is not a directory (or is a symbolic link)";
    return -1;
  }
  if (st.st_uid != geteuid() || (st.st_mode & 077) != 0) {
    why = "the socket directory '" + dir +
          "' must be owned by this user and have no group/other permissions";
    return -1;
  }
  sockaddr_un a{};
  if (!fill_address(socket_path, a)) {
    why = "the socket path is empty or too long";
    return -1;
  }
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0 || connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    why = std::string("cannot connect: ") + strerror(errno);
    if (fd >= 0) ::close(fd);
    return -1;
  }
  ucred cred{};
  socklen_t len = sizeof cred;
  if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0 || cred.uid != geteuid()) {
    why = "the listening process does not run as this user";
    ::close(fd);
    return -1;
  }
  const char* p = token.data();
  std::size_t n = token.size();
  while (n > 0) {
    const ssize_t w = send(fd, p, n, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      why = std::string("cannot send the token: ") + strerror(errno);
      ::close(fd);
      return -1;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return fd;
}

} // namespace pnc::md
