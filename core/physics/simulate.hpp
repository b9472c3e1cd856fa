// SPDX-License-Identifier: MIT
// Settle once, then probe: run one conveyor profile from the rest state, detect failures as they
// happen, stop as soon as the outcome is decided, and never return a verdict from a run MuJoCo
// has silently broken.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/physics/engine.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/sim_types.hpp"

namespace pb {

/// Owns one mjData for a scene and reuses it for every probe (creating one costs milliseconds).
/// Not thread-safe: one Simulator per thread; the Scene must outlive it.
class Simulator {
 public:
  /// Fails if MuJoCo cannot allocate the data.
  static Result<Simulator> create(const Scene& scene);

  /// Lets the load come to rest on a still belt and holds it there. A load that crosses a detector
  /// (`thresholds`, against the as-built poses) or is still moving after max_time_s cannot stand:
  /// the rest state then carries `cannot_stand` (a build defect, not a conveyor failure). Fails
  /// when the run is unstable.
  Result<RestState> settle(const SettleOptions& options = {},
                           const DetectorThresholds& thresholds = {});

  /// Runs `profile` from `rest` (bodies given the profile's initial speed, riding along).
  SimResult run(const RestState& rest, const ConveyorProfile& profile,
                const SimOptions& options = {});

  const Scene& scene() const { return *scene_; }
  /// What its mjData holds resident, bytes (MuJoCo 2.2 preallocates it whole: the main buffer and
  /// the stack; of the buffer's njmax x njmax matrix one block, engine.hpp: make_data).
  double data_bytes() const;

 private:
  Simulator(const Scene& scene, DataPtr data) : scene_(&scene), data_(std::move(data)) {}

  const Scene* scene_;
  DataPtr data_;
};

}  // namespace pb
