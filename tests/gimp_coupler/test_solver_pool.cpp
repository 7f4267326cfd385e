// The GIMP solver's thread pool (gimp_coupler/src/solver_pool.hpp, D355, D406): every run()
// calls fn(t) once for each t and returns only after all calls, with the workers' writes
// visible to the caller (the hand-over through the polled atomics and through the blocking
// path alike); the first exception (lowest t) is rethrown and the pool stays usable; a pool
// is destroyed while its workers poll or block.
#include "solver_pool.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using pnc::gimp::ThreadPool;

namespace {

// spin_us: 0 (block at once) and the default poll
const double kSpins[] = {0.0, ThreadPool::kSpinUs};

} // namespace

TEST(GimpThreadPool, EveryRunCallsEachThreadOnceAndPublishesItsWrites) {
  for (int T : {1, 2, 3, 4})
    for (double spin : kSpins) {
      ThreadPool pool(T, spin);
      std::vector<long> count(static_cast<std::size_t>(T), 0), value(static_cast<std::size_t>(T));
      for (long r = 0; r < 1000; ++r) {
        pool.run([&](int t) {
          ++count[static_cast<std::size_t>(t)];
          value[static_cast<std::size_t>(t)] = r * 10 + t; // plain writes, read after run()
        });
        for (int t = 0; t < T; ++t)
          ASSERT_EQ(value[static_cast<std::size_t>(t)], r * 10 + t)
              << "T = " << T << ", spin " << spin << " us, run " << r;
      }
      for (int t = 0; t < T; ++t)
        EXPECT_EQ(count[static_cast<std::size_t>(t)], 1000) << "T = " << T << ", t = " << t;
    }
}

TEST(GimpThreadPool, TheLowestThreadsExceptionIsRethrownAndThePoolGoesOn) {
  for (double spin : kSpins) {
    ThreadPool pool(3, spin);
    try {
      pool.run([](int t) {
        if (t >= 1) throw std::runtime_error("thread " + std::to_string(t));
      });
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "thread 1");
    }
    int sum = 0;
    std::vector<int> v(3, 0);
    pool.run([&](int t) { v[static_cast<std::size_t>(t)] = t + 1; });
    for (int x : v)
      sum += x;
    EXPECT_EQ(sum, 6);
  }
}

TEST(GimpThreadPool, DestroyedWhileItsWorkersPollOrBlock) {
  for (double spin : kSpins) {
    {
      ThreadPool pool(2, spin);
      pool.run([](int) {});
    } // right after a run: the worker is polling (or blocked with spin 0)
    {
      ThreadPool pool(2, spin);
      pool.run([](int) {});
      std::this_thread::sleep_for(std::chrono::milliseconds(20)); // past any poll: blocked
    }
  }
  SUCCEED(); // a hang here is the failure (ctest timeout)
}
