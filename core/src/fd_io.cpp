// POSIX helpers shared by pnc's writers (see fd_io.hpp).
#include "pnc/core/fd_io.hpp"

#include "pnc/core/error.hpp"

#include <sys/random.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace pnc {

bool write_fully(int fd, std::string_view bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

std::string random_hex(std::size_t bytes) {
  unsigned char b[32];
  if (bytes > sizeof b) bytes = sizeof b;
  std::size_t got = 0;
  while (got < bytes) {
    const ssize_t n = getrandom(b + got, bytes - got, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      fail("<getrandom>", "", "", std::string("no random bytes: ") + std::strerror(errno));
    got += static_cast<std::size_t>(n);
  }
  static const char* hex = "0123456789abcdef";
  std::string s;
  for (std::size_t i = 0; i < bytes; ++i) {
    s += hex[b[i] >> 4];
    s += hex[b[i] & 15];
  }
  return s;
}

} // namespace pnc
