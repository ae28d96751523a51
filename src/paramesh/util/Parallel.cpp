// SPDX-License-Identifier: LGPL-2.1-or-later
#include "paramesh/util/Parallel.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#if defined(__linux__)
#include <sched.h>
#endif

namespace paramesh {

namespace {

std::string readSmallFile(const char* path) {
  std::ifstream in(path);
  if (!in) return {};
  std::string s;
  std::getline(in, s);
  return s;
}

int cpusFromQuotaPeriod(double quota, double period) {
  if (!(quota > 0) || !(period > 0)) return 0;
  return std::max(1, (int)std::ceil(quota / period - 1e-9));
}

}  // namespace

int cpusFromCgroupMax(const std::string& cpuMax) {
  std::istringstream in(cpuMax);
  std::string quota;
  double period = 0;
  if (!(in >> quota >> period) || quota == "max") return 0;
  try {
    size_t used = 0;
    const double q = std::stod(quota, &used);
    if (used != quota.size()) return 0;
    return cpusFromQuotaPeriod(q, period);
  } catch (...) {
    return 0;
  }
}

int availableCpus() {
  unsigned h = std::thread::hardware_concurrency();
  int n = h > 0 ? (int)h : 1;
#if defined(__linux__)
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) {
    const int c = CPU_COUNT(&set);
    if (c > 0) n = std::min(n, c);
  }
  int quota = cpusFromCgroupMax(readSmallFile("/sys/fs/cgroup/cpu.max"));
  if (quota == 0) {  // cgroup v1
    const std::string q = readSmallFile("/sys/fs/cgroup/cpu/cpu.cfs_quota_us");
    const std::string p = readSmallFile("/sys/fs/cgroup/cpu/cpu.cfs_period_us");
    if (!q.empty() && !p.empty()) quota = cpusFromCgroupMax(q + " " + p);
  }
  if (quota > 0) n = std::min(n, quota);
#endif
  return std::max(1, n);
}

}  // namespace paramesh
