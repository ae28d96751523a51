// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Log.hpp
/// Injected log sink and progress/cancel token. The library never writes to stdout/stderr.
#pragma once
#include <atomic>
#include <functional>
#include <mutex>
#include <string>

#include "paramesh/util/Error.hpp"

namespace paramesh {

enum class LogLevel { Debug = 0, Info = 1, Warning = 2, Error = 3 };

/// Receives log lines; called from worker threads under a mutex (the sink need not be thread-safe).
using LogSink = std::function<void(LogLevel, const std::string&)>;

/// Receives progress (fraction in [0,1], stage name). Returning false requests cancellation.
using ProgressCallback = std::function<bool(double, const std::string&)>;

/// Thread-safe logger that forwards to an optional sink.
class Logger {
 public:
  explicit Logger(LogSink sink = {}) : sink_(std::move(sink)) {}
  void log(LogLevel lvl, const std::string& msg) const {
    if (!sink_) return;
    std::lock_guard<std::mutex> g(mu_);
    sink_(lvl, msg);
  }
  void info(const std::string& m) const { log(LogLevel::Info, m); }
  void warn(const std::string& m) const { log(LogLevel::Warning, m); }
  void debug(const std::string& m) const { log(LogLevel::Debug, m); }
  void error(const std::string& m) const { log(LogLevel::Error, m); }

 private:
  LogSink sink_;
  mutable std::mutex mu_;
};

/// Progress reporting + cooperative cancellation, polled by the stages (at least once per face).
class Progress {
 public:
  explicit Progress(ProgressCallback cb = {}) : cb_(std::move(cb)) {}
  /// Reports progress; throws Cancelled when the callback asked to stop or cancel() was called.
  void report(double fraction, const std::string& stage) {
    if (cancelled_.load()) throw Cancelled();
    if (cb_) {
      std::lock_guard<std::mutex> g(mu_);
      if (!cb_(fraction, stage)) cancelled_ = true;
    }
    if (cancelled_.load()) throw Cancelled();
  }
  /// Throws Cancelled if a cancellation was requested (cheap: one atomic load).
  void poll() const {
    if (cancelled_.load(std::memory_order_relaxed)) throw Cancelled();
  }
  void cancel() { cancelled_ = true; }
  bool isCancelled() const { return cancelled_.load(); }
  /// Points the face meshers may insert from now on (0: no limit); over it, spend() cancels.
  void setPointBudget(long points) {
    budget_ = points;
    spent_ = 0;
  }
  /// Counts n inserted points against the budget: over it, every poll() throws Cancelled and
  /// overBudget() tells why (a size far too small for the model, or runaway refinement).
  void spend(long n) const {
    if (budget_ > 0 && spent_.fetch_add(n, std::memory_order_relaxed) + n > budget_) stopOverBudget();
  }
  /// Cancels (as spend() does) when n more points would already exceed the budget: a face whose
  /// boundary encloses far more area than the budget can fill fails before it is meshed.
  void require(long n) const {
    if (budget_ > 0 && spent_.load(std::memory_order_relaxed) + n > budget_) stopOverBudget();
  }
  /// Gives back n points counted by spend() whose work was discarded (a face meshed again).
  void refund(long n) const {
    if (budget_ > 0) spent_.fetch_sub(n, std::memory_order_relaxed);
  }
  bool overBudget() const { return overBudget_.load(); }

 private:
  [[noreturn]] void stopOverBudget() const {
    overBudget_ = true;
    cancelled_ = true;
    throw Cancelled();
  }
  ProgressCallback cb_;
  mutable std::atomic<bool> cancelled_{false};
  long budget_ = 0;
  mutable std::atomic<long> spent_{0};
  mutable std::atomic<bool> overBudget_{false};
  std::mutex mu_;
};

}  // namespace paramesh
