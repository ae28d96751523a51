// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Timer.hpp
/// Wall-clock stopwatch for per-stage timings in the report.
#pragma once
#include <chrono>

namespace paramesh {

class Timer {
 public:
  Timer() : t0_(std::chrono::steady_clock::now()) {}
  /// Seconds since construction or the last reset().
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }
  void reset() { t0_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace paramesh
