#pragma once
// The thread pool of the GIMP solver and its helpers (private to the solver's sources:
// solver.cpp, solver_step.cpp, solver_crack.cpp).
#include "pnc/gimp_coupler/solver.hpp"

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace pnc::gimp {

/// A persistent pool of T - 1 worker threads with blocking (not spinning) hand-over, so that
/// it behaves on a machine whose cores are shared with other jobs. run(fn) calls fn(t) for
/// t = 0..T-1 (t = 0 on the calling thread) and rethrows the first exception (lowest t).
class ThreadPool {
public:
  explicit ThreadPool(int T) : T_(T), err_(static_cast<std::size_t>(T)) {
    for (int t = 1; t < T; ++t)
      workers_.emplace_back([this, t] { work(t); });
  }
  ~ThreadPool() {
    {
      std::lock_guard<std::mutex> lk(mu_);
      stop_ = true;
      ++gen_;
    }
    cv_.notify_all();
    for (auto& w : workers_)
      w.join();
  }
  int size() const { return T_; }
  void run(const std::function<void(int)>& fn) {
    {
      std::lock_guard<std::mutex> lk(mu_);
      fn_ = &fn;
      pending_ = T_ - 1;
      ++gen_;
    }
    cv_.notify_all();
    call(fn, 0);
    {
      std::unique_lock<std::mutex> lk(mu_);
      done_.wait(lk, [this] { return pending_ == 0; });
      fn_ = nullptr;
    }
    for (auto& e : err_)
      if (e) {
        auto x = e;
        for (auto& f : err_)
          f = nullptr;
        std::rethrow_exception(x);
      }
  }

private:
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
      const std::function<void(int)>* fn;
      {
        std::unique_lock<std::mutex> lk(mu_);
        cv_.wait(lk, [&] { return gen_ != seen; });
        seen = gen_;
        if (stop_) return;
        fn = fn_;
      }
      call(*fn, t);
      {
        std::lock_guard<std::mutex> lk(mu_);
        if (--pending_ == 0) done_.notify_one();
      }
    }
  }
  int T_;
  std::vector<std::exception_ptr> err_;
  std::vector<std::thread> workers_;
  std::mutex mu_;
  std::condition_variable cv_, done_;
  const std::function<void(int)>* fn_ = nullptr;
  int pending_ = 0;
  unsigned long gen_ = 0;
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
