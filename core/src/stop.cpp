#include "pnc/core/stop.hpp"

#include <sys/mman.h>

#include <atomic>
#include <new>

namespace pnc {

struct StopToken::Shared {
  std::atomic<int> signal{0};
  std::atomic<int> count{0};
};
static_assert(std::atomic<int>::is_always_lock_free, "request() must be async-signal-safe");

StopToken::StopToken() {
  // shared with children forked later: a request in the parent is seen by them
  void* p =
      ::mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  s_ = new (p) Shared;
}

StopToken::~StopToken() {
  s_->~Shared();
  ::munmap(s_, sizeof(Shared));
}

void StopToken::request(int sig) noexcept {
  int none = 0;
  s_->signal.compare_exchange_strong(none, sig);
  s_->count.fetch_add(1);
}

bool StopToken::requested() const noexcept {
  return s_->count.load() > 0;
}

int StopToken::signal() const noexcept {
  return s_->signal.load();
}

int StopToken::count() const noexcept {
  return s_->count.load();
}

void StopToken::reset() noexcept {
  s_->signal.store(0);
  s_->count.store(0);
}

StopToken& process_stop() {
  static StopToken token;
  return token;
}

Interrupted::Interrupted(int signal, std::string detail)
    : std::runtime_error("interrupted: " + detail), signal_(signal), detail_(std::move(detail)) {}

void throw_if_stopped(const std::string& detail) {
  const StopToken& t = process_stop();
  if (t.requested()) throw Interrupted(t.signal(), detail);
}

} // namespace pnc
