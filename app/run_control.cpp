#include "run_control.hpp"

#include "pnc/core/stop.hpp"
#include "pnc/core/version.hpp"

#include <unistd.h>

#include <cctype>
#include <csignal>

namespace pnc::app {

namespace {

std::string g_command_line;
bool g_has_resume = false;

std::string shell_word(const std::string& w) {
  if (w.empty()) return "''";
  bool plain = true;
  for (char c : w)
    plain = plain && (std::isalnum(static_cast<unsigned char>(c)) ||
                      std::string("_./:=,+-@%").find(c) != std::string::npos);
  if (plain) return w;
  std::string q = "'";
  for (char c : w)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

volatile std::sig_atomic_t g_main_pid = 0;
pnc::StopToken* g_token = nullptr;
struct sigaction g_old_int {
}, g_old_term{};

extern "C" void on_stop_signal(int sig) {
  if (static_cast<pid_t>(g_main_pid) != ::getpid()) { // a forked child: die as by default
    std::signal(sig, SIG_DFL);
    ::raise(sig);
    return;
  }
  g_token->request(sig);
  if (g_token->count() >= 3) {
    std::signal(sig, SIG_DFL);
    ::raise(sig);
  }
}

} // namespace

void set_command_line(int argc, char** argv) {
  g_command_line.clear();
  g_has_resume = false;
  for (int i = 0; i < argc; ++i) {
    const std::string w = argv[i];
    g_has_resume = g_has_resume || (i > 0 && w == "--resume");
    g_command_line += (i ? " " : "") + shell_word(w);
  }
  pnc::set_invocation(g_command_line); // the provenance of every file written (hdf5_io.hpp)
}

const std::string& command_line() {
  return g_command_line;
}

std::string resume_command() {
  return g_has_resume ? g_command_line : g_command_line + " --resume";
}

std::string signal_name(int sig) {
  if (sig == SIGINT) return "SIGINT";
  if (sig == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(sig);
}

StopSignals::StopSignals() {
  g_token = &pnc::process_stop(); // the shared mapping exists before anything forks
  g_token->reset();
  g_main_pid = static_cast<std::sig_atomic_t>(::getpid());
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART; // library I/O is not disturbed; the loops poll the token
  sigaction(SIGINT, &sa, &g_old_int);
  sigaction(SIGTERM, &sa, &g_old_term);
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
}

} // namespace pnc::app
