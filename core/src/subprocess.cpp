// Programs run with an argument vector (see subprocess.hpp): fork + execvp, no shell.
#include "pnc/core/subprocess.hpp"

#include "pnc/core/error.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace pnc {

namespace {

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

} // namespace

SubprocessResult run_subprocess(const std::vector<std::string>& argv) {
  if (argv.empty() || argv[0].empty())
    fail("<subprocess>", "argv", "", "a program to run is required");
  // Everything the child needs is built before fork: after fork only async-signal-safe calls.
  std::vector<std::string> copy = argv;
  std::vector<char*> args;
  for (auto& a : copy)
    args.push_back(a.data());
  args.push_back(nullptr);
  int out[2] = {-1, -1}, err[2] = {-1, -1};
  if (::pipe2(out, O_CLOEXEC) != 0 || ::pipe2(err, O_CLOEXEC) != 0) {
    const std::string why = std::strerror(errno);
    close_fd(out[0]);
    close_fd(out[1]);
    fail(argv[0], "", "", "cannot create a pipe: " + why);
  }
  std::fflush(nullptr); // no duplicated stdio buffers in the child
  const pid_t pid = ::fork();
  if (pid < 0) {
    const std::string why = std::strerror(errno);
    for (int* fd : {&out[0], &out[1], &err[0], &err[1]})
      close_fd(*fd);
    fail(argv[0], "", "", "fork() failed: " + why);
  }
  if (pid == 0) {
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) ::dup2(null, 0);
    ::dup2(out[1], 1);
    ::dup2(out[1], 2);
    ::execvp(args[0], args.data());
    const int e = errno;
    ssize_t ignored = ::write(err[1], &e, sizeof e); // the parent reports why
    (void)ignored;
    ::_exit(127);
  }
  close_fd(out[1]);
  close_fd(err[1]);
  SubprocessResult r;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(out[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    r.output.append(buf, static_cast<std::size_t>(n));
  }
  close_fd(out[0]);
  int exec_errno = 0;
  ssize_t got;
  do {
    got = ::read(err[0], &exec_errno, sizeof exec_errno);
  } while (got < 0 && errno == EINTR);
  close_fd(err[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (got == static_cast<ssize_t>(sizeof exec_errno)) {
    r.started = false;
    r.error = std::strerror(exec_errno);
    return r;
  }
  r.started = true;
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  return r;
}

} // namespace pnc
