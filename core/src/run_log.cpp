// The run folder's copy of what pnc printed (pnc/core/run_log.hpp, D235).
#include "pnc/core/run_log.hpp"

#include "pnc/core/error.hpp"
#include "pnc/core/fd_io.hpp"
#include "pnc/core/version.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <streambuf>

namespace pnc {

namespace {

// The log's state is never destroyed: a process that ends with exit() while a log is active
// (LAMMPS ends a stage child that way) flushes std::cout and std::cerr after static objects are
// gone, and their buffers must still be there then. It is one mutex and two small buffers.
std::mutex& g_mutex = *new std::mutex; // guards the descriptor and the line buffers

/// A child forked while another thread held g_mutex would wait for it forever: fork(2) takes
/// the mutex first and both sides release it (registered once, at the first start_run_log).
void hold_across_fork() {
  static const int registered =
      ::pthread_atfork([] { g_mutex.lock(); }, [] { g_mutex.unlock(); }, [] { g_mutex.unlock(); });
  (void)registered;
}

/// "2026-12-03T14:40:01.123Z"
std::string utc_now() {
  using namespace std::chrono;
  const auto now = system_clock::now();
  const std::time_t t = system_clock::to_time_t(now);
  const auto ms = duration_cast<milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  return fmt::format("{}.{:03d}Z", buf, static_cast<int>(ms));
}

/// One write(2) per line; errors are ignored: the log is a copy, and the terminal has the text.
void write_all(int fd, const std::string& s) {
  (void)write_fully(fd, s);
}

/// Forwards everything to the stream's own buffer and collects lines for the log.
class TeeBuf : public std::streambuf {
public:
  TeeBuf(std::streambuf* original, const char* tag, int fd)
      : original_(original), tag_(tag), fd_(fd) {}
  std::streambuf* original() const { return original_; }
  /// Writes a pending partial line (at the end of a session).
  void flush_partial() {
    if (!line_.empty()) emit();
  }

protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    if (original_->sputc(ch) == traits_type::eof()) return traits_type::eof();
    take(&ch, 1);
    return c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    const std::streamsize written = original_->sputn(s, n);
    if (written > 0) take(s, static_cast<std::size_t>(written));
    return written;
  }
  int sync() override { return original_->pubsync(); }

private:
  void take(const char* s, std::size_t n) {
    const std::lock_guard<std::mutex> lock(g_mutex);
    for (std::size_t i = 0; i < n; ++i) {
      if (s[i] == '\n')
        emit();
      else
        line_ += s[i];
    }
  }
  void emit() {
    // progress lines rewritten in place with '\r' keep their last state
    const std::size_t cr = line_.find_last_of('\r');
    const std::string text = cr == std::string::npos ? line_ : line_.substr(cr + 1);
    write_all(fd_, fmt::format("{} {} {}\n", utc_now(), tag_, text));
    line_.clear();
  }

  std::streambuf* original_;
  const char* tag_;
  int fd_;
  std::string line_;
};

struct ActiveLog {
  int fd = -1;
  TeeBuf* out = nullptr; ///< owned; deleted once std::cout uses its own buffer again
  TeeBuf* err = nullptr;
};
ActiveLog& g_log = *new ActiveLog;

/// Flushes both streams, writes their pending partial lines and then `closing` (unless empty)
/// as one more line, all under the lock. Needs an active log.
void flush_pending(const std::string& closing) {
  std::cout.flush();
  std::cerr.flush();
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_log.out->flush_partial();
  g_log.err->flush_partial();
  if (!closing.empty()) write_all(g_log.fd, fmt::format("{} {}\n", utc_now(), closing));
}

void stop_copying() {
  if (g_log.fd < 0) return;
  flush_pending("");
  std::cout.rdbuf(g_log.out->original());
  std::cerr.rdbuf(g_log.err->original());
  ::close(g_log.fd);
  delete g_log.out;
  delete g_log.err;
  g_log = ActiveLog{};
}

} // namespace

std::string run_log_path(const std::string& dir) {
  return (std::filesystem::path(dir) / "pnc.log").string();
}

void start_run_log(const std::string& dir, const std::string& command_line) {
  hold_across_fork();
  stop_copying();
  const std::string path = run_log_path(dir);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0)
    fail(dir, "pnc.log", path,
         errno == ELOOP ? "the run log must not be a symbolic link (refused)"
                        : std::string("cannot open the run log: ") + std::strerror(errno));
  std::error_code ec;
  write_all(fd, fmt::format("{} --- {} (pid {}) started in {}: {}\n", utc_now(), version_string(),
                            static_cast<long>(::getpid()),
                            std::filesystem::current_path(ec).string(), command_line));
  g_log.fd = fd;
  g_log.out = new TeeBuf(std::cout.rdbuf(), "out", fd);
  g_log.err = new TeeBuf(std::cerr.rdbuf(), "err", fd);
  std::cout.rdbuf(g_log.out);
  std::cerr.rdbuf(g_log.err);
}

void finish_run_log(int exit_code) {
  if (g_log.fd < 0) return;
  flush_pending(fmt::format("--- pnc finished: exit code {}", exit_code));
  stop_copying();
}

bool run_log_active() {
  return g_log.fd >= 0;
}

} // namespace pnc
