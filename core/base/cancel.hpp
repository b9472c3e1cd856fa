// SPDX-License-Identifier: MIT
// A request, from another thread, to stop a run early: a client that went away, a deadline, the
// console's Cancel. Simulations check it between steps (settle and probes alike); a cancelled run
// ends without a verdict and nothing of it is cached.
#pragma once

#include <atomic>
#include <string_view>

namespace pb {

/// Set (to true) by whoever wants the work to stop; read by the runs that were given it.
using CancelFlag = std::atomic<bool>;

/// True if `flag` is given and set.
inline bool is_cancelled(const CancelFlag* flag) {
  return flag != nullptr && flag->load(std::memory_order_relaxed);
}

/// The reason a cancelled run gives (SimResult::reason starts with it; settle's error names it).
inline constexpr std::string_view kCancelledReason = "cancelled";

}  // namespace pb
