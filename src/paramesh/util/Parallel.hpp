// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Parallel.hpp
/// A minimal parallel-for over [0, n) with dynamic scheduling. The first exception thrown by a
/// task stops the hand-out of new tasks and is rethrown in the caller after all workers joined.
#pragma once
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace paramesh {

/// CPUs a cgroup CPU limit allows: `cpu.max` text of cgroup v2 ("200000 100000" -> 2, rounded up;
/// "max 100000" -> 0 = no limit), or 0 when the text cannot be read as a limit.
int cpusFromCgroupMax(const std::string& cpuMax);

/// CPUs this process may really use: the scheduler affinity mask, capped by a cgroup CPU quota
/// (v2 cpu.max or v1 cfs_quota_us / cfs_period_us), falling back to hardware_concurrency. In a
/// container hardware_concurrency reports the host's CPUs; using more threads than the quota
/// allows makes the kernel throttle the whole process, GUI thread included.
int availableCpus();

/// Number of worker threads to use for a requested count (0 = the CPUs this process may use).
inline int resolveThreads(int requested) {
  if (requested > 0) return requested;
  return availableCpus();
}

/// Runs f(i) for i in [0,n) on `threads` threads; tasks are taken in order of `order` when given
/// (e.g. largest first), else 0..n-1.
template <class F>
void parallelFor(int n, int threads, F&& f, const std::vector<int>* order = nullptr) {
  threads = std::max(1, std::min(threads, n));
  std::atomic<int> next{0};
  std::atomic<bool> stop{false};
  std::exception_ptr err;
  std::mutex mu;
  auto work = [&]() {
    for (;;) {
      if (stop.load()) return;
      const int k = next.fetch_add(1);
      if (k >= n) return;
      const int i = order ? (*order)[k] : k;
      try {
        f(i);
      } catch (...) {
        std::lock_guard<std::mutex> g(mu);
        if (!err) err = std::current_exception();
        stop = true;
        return;
      }
    }
  };
  if (threads == 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    for (int t = 0; t < threads - 1; ++t) pool.emplace_back(work);
    work();
    for (auto& th : pool) th.join();
  }
  if (err) std::rethrow_exception(err);
}

}  // namespace paramesh
