// SPDX-License-Identifier: MIT
// Simulations counted as they end, for whoever waits on a long call (the console's progress line).
#pragma once

#include <algorithm>
#include <atomic>
#include <functional>
#include <utility>

namespace pb {

/// Counts the simulations of one call as they end, against those it plans: exact for a failure
/// map (its cells), an estimate for an envelope search (its searches adapt; see
/// Analyzer::set_progress). Thread-safe: axis threads and batch workers report at once; the
/// callback runs on the reporting thread, after each change, with done <= planned.
class ProgressCounter {
 public:
  using Callback = std::function<void(int done, int planned)>;

  explicit ProgressCounter(Callback callback) : callback_(std::move(callback)) {}

  /// Plans `n` more simulations.
  void plan(int n) {
    planned_ += n;
    report();
  }
  /// One simulation (or `n`) ended. A count past the plan raises the plan with it.
  void finished(int n = 1) {
    done_ += n;
    report();
  }
  /// The call ended: nothing more is planned than was done.
  void settle() {
    planned_ = done_.load();
    report();
  }
  int done() const { return done_.load(); }
  int planned() const { return std::max(planned_.load(), done_.load()); }

 private:
  void report() const {
    if (!callback_) return;
    const int done = done_.load();  // the plan read after: never below it
    callback_(done, std::max(planned_.load(), done));
  }

  Callback callback_;
  std::atomic<int> done_{0};
  std::atomic<int> planned_{0};
};

}  // namespace pb
