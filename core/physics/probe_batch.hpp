// SPDX-License-Identifier: MIT
// Many probes from one rest state in one batched call: each a ProbeRun (the serial Simulator's
// per-step logic) on a Batch worker. The failure map, the k-section search and the uncertainty
// estimate run their probes through it.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/physics/batch.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/simulate.hpp"

namespace pb {

/// Lets a caller expand per-simulation parameters of a batch before it runs (Batch::expand);
/// returns why it could not.
using BatchConfigure = std::function<std::optional<std::string>(Batch& batch)>;

/// Runs one probe (ProbeRun: the serial Simulator's logic) per profile from `rest`, all in one
/// batched call on `threads` workers (0: every CPU). Result k is profile k's; an engine error or
/// instability of one simulation makes its result unstable with the reason. Fails when the batch
/// itself cannot be made or run, and when `o.cancel` was set (a message starting "cancelled"):
/// runs stopped part-way are no results.
Result<std::vector<SimResult>> run_probes_batched(const Scene& scene, const RestState& rest,
                                                  const std::vector<ConveyorProfile>& profiles,
                                                  const SimOptions& options, int threads = 0,
                                                  const BatchConfigure& configure = {},
                                                  int* threads_used = nullptr);

}  // namespace pb
