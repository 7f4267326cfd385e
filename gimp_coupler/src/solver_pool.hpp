#pragma once
// The thread pool of the GIMP solver and its helpers (private to the solver's sources:
// solver.cpp, solver_step.cpp, solver_crack.cpp).
#include "pnc/gimp_coupler/solver.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace pnc::gimp {

/// A persistent pool of T - 1 worker threads. A hand-over first polls an atomic for a bounded
/// time (spin_us, default kSpinUs microseconds) and then blocks on a condition variable
/// (D406): the wake-up of a blocked thread costs tens of microseconds, comparable to a whole
/// pass of 10^4 particles, while unbounded spinning made OpenMP's barriers 100x slower on a
/// machine whose cores are shared with other jobs (gimp_coupler/bench/README.md).
/// run(fn) calls fn(t) for t = 0..T-1 (t = 0 on the calling thread) and rethrows the first
/// exception (lowest t).
class ThreadPool {
public:
  /// Polls for up to `spin_us` microseconds before blocking; 0 blocks at once.
  explicit ThreadPool(int T, double spin_us = kSpinUs)
      : T_(T), spin_(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                   std::chrono::duration<double, std::micro>(spin_us))),
        err_(static_cast<std::size_t>(T)) {
    for (int t = 1; t < T; ++t)
      workers_.emplace_back([this, t] { work(t); });
  }
  ~ThreadPool() {
    {
      std::lock_guard<std::mutex> lk(mu_);
      stop_ = true;
      gen_.fetch_add(1, std::memory_order_release);
    }
    cv_.notify_all();
    for (auto& w : workers_)
      w.join();
  }
  static constexpr double kSpinUs = 50.0;
  int size() const { return T_; }
  void run(const std::function<void(int)>& fn) {
    {
      std::lock_guard<std::mutex> lk(mu_);
      fn_ = &fn;
      pending_.store(T_ - 1, std::memory_order_relaxed);
      gen_.fetch_add(1, std::memory_order_release); // publishes fn_ and pending_
    }
    cv_.notify_all();
    call(fn, 0);
    if (!poll([this] { return pending_.load(std::memory_order_acquire) == 0; })) {
      std::unique_lock<std::mutex> lk(mu_);
      done_.wait(lk, [this] { return pending_.load(std::memory_order_acquire) == 0; });
    }
    fn_ = nullptr;
    for (auto& e : err_)
      if (e) {
        auto x = e;
        for (auto& f : err_)
          f = nullptr;
        std::rethrow_exception(x);
      }
  }

private:
  /// Polls `ready` for up to spin_ with a pause between polls; true once it holds.
  template <class Pred> bool poll(Pred ready) const {
    if (spin_.count() <= 0) return ready();
    const auto until = std::chrono::steady_clock::now() + spin_;
    while (true) {
      for (int k = 0; k < 32; ++k) { // the clock read every 32 polls
        if (ready()) return true;
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
      }
      if (std::chrono::steady_clock::now() >= until) return ready();
    }
  }
  void call(const std::function<void(int)>& fn, int t) {
    try {
      fn(t);
    } catch (...) {
      err_[static_cast<std::size_t>(t)] = std::current_exception();
    }
  }
  void work(int t) {
    unsigned long seen = 0;
    while (true) {
      auto fresh = [&] { return gen_.load(std::memory_order_acquire) != seen; };
      if (!poll(fresh)) {
        std::unique_lock<std::mutex> lk(mu_);
        cv_.wait(lk, fresh);
      }
      seen = gen_.load(std::memory_order_acquire);
      // stop_ and fn_ were written before gen_'s release increment (~ThreadPool, run()), which
      // the acquire load above has seen: no mutex needed to read them
      if (stop_) return;
      call(*fn_, t);
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
        std::lock_guard<std::mutex> lk(mu_); // no lost wake-up: run() tests under the mutex
        done_.notify_one();
      }
    }
  }
  int T_;
  std::chrono::steady_clock::duration spin_;
  std::vector<std::exception_ptr> err_;
  std::vector<std::thread> workers_;
  std::mutex mu_;
  std::condition_variable cv_, done_;
  const std::function<void(int)>* fn_ = nullptr;
  std::atomic<int> pending_{0};
  std::atomic<unsigned long> gen_{0};
  bool stop_ = false;
};

namespace detail {

/// Runs fn(t) for t = 0..T-1 on the pool (or fn(0) without one).
template <class Fn> void par(ThreadPool* pool, Fn&& fn) {
  if (!pool) {
    fn(0);
    return;
  }
  const std::function<void(int)> f = std::ref(fn);
  pool->run(f);
}

/// Static block partition of [0, n) among T threads.
inline std::pair<std::size_t, std::size_t> block(int t, int T, std::size_t n) {
  const auto tt = static_cast<std::size_t>(t), TT = static_cast<std::size_t>(T);
  return {n * tt / TT, n * (tt + 1) / TT};
}

} // namespace detail

} // namespace pnc::gimp
