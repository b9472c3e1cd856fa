// SPDX-License-Identifier: MIT
// Settle once, then probe: run one conveyor profile from the rest state, detect failures as they
// happen, stop as soon as the outcome is decided, and never return a verdict from a run MuJoCo
// has silently broken.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/conveyor_profile.hpp"
#include "core/detectors.hpp"
#include "core/diagnostic.hpp"
#include "core/engine.hpp"
#include "core/scene.hpp"
#include "core/trace.hpp"

namespace pb {

/// The MuJoCo state a probe starts from (2.2.2 has no mj_getState; these are the fields that make
/// a restart bitwise equal to a continued run), plus the detector baselines.
struct RestState {
  std::vector<double> qpos;
  std::vector<double> qvel;
  std::vector<double> qacc_warmstart;
  Pose pallet;
  std::vector<Pose> items;
  double settle_time_s = 0.0;
  double residual_speed_mps = 0.0;  ///< fastest body when it was declared at rest
};

struct SettleOptions {
  double rest_speed_mps = 0.002;  ///< every body slower than this (and ...)
  double rest_spin_radps = 0.02;  ///< ... turning slower than this: at rest
  double min_time_s = 0.05;
  double max_time_s = 3.0;  ///< a load still moving then is a build defect
  double check_every_s = 0.01;
};

enum class Outcome { safe, failed, unstable };
std::string_view to_string(Outcome outcome);

struct SimOptions {
  DetectorThresholds thresholds;
  bool fail_fast = true;   ///< stop at the first failure
  bool early_stop = true;  ///< stop once the load co-moves with the belt after the last breakpoint
  double comove_speed_mps = 0.001;  ///< co-moving: every body within this of the belt's velocity
  double comove_spin_radps = 0.01;
  bool record_trace = true;  ///< keep every step's poses (replays, plots); off for searches
  /// Event-driven skipping: once every body has co-moved with the belt (and accelerated with it:
  /// relative accelerations below comove_speed_mps / skip_dwell_s, angular ones below
  /// comove_spin_radps / skip_dwell_s, so no slow rock at its turning point) for `skip_dwell_s`
  /// within one phase of the profile whose command is affine in time (constant velocity or constant
  /// acceleration, lateral included), jump analytically to one step before the phase's next
  /// breakpoint: every body and the belt get the belt's rigid motion (positions += the belt's
  /// travel, velocities += its velocity change, orientations and relative velocities kept). The
  /// detectors' measures are invariant under that motion. After the last breakpoint the early
  /// stop decides instead (when on).
  bool skip_comoving = true;
  double skip_dwell_s = 0.02;
};

struct SimResult {
  Outcome outcome = Outcome::safe;
  std::optional<FailureEvent> failure;
  std::string reason;  ///< why the run is unstable (empty otherwise)
  Trace trace;
  int steps = 0;               ///< profile steps reached (stepped + skipped)
  int steps_skipped = 0;       ///< of `steps`, jumped analytically (skip_comoving)
  double skipped_s = 0.0;      ///< profile time jumped analytically
  double sim_time_s = 0.0;     ///< profile time reached
  bool stopped_early = false;  ///< co-moving after the last breakpoint: nothing could change
  double wall_ms = 0.0;
};

/// Owns one mjData for a scene and reuses it for every probe (creating one costs milliseconds).
/// Not thread-safe: one Simulator per thread; the Scene must outlive it.
class Simulator {
 public:
  /// Fails if MuJoCo cannot allocate the data.
  static Result<Simulator> create(const Scene& scene);

  /// Lets the load come to rest on a still belt. Fails (a build defect, not a conveyor failure)
  /// if it is still moving after max_time_s, or if the run is unstable.
  Result<RestState> settle(const SettleOptions& options = {});

  /// Runs `profile` from `rest` (bodies given the profile's initial speed, riding along).
  SimResult run(const RestState& rest, const ConveyorProfile& profile,
                const SimOptions& options = {});

  const Scene& scene() const { return *scene_; }
  /// What its mjData holds, bytes (MuJoCo 2.2 preallocates it whole: the main buffer, with its
  /// njmax x njmax matrix, and the stack).
  double data_bytes() const;

 private:
  Simulator(const Scene& scene, DataPtr data) : scene_(&scene), data_(std::move(data)) {}

  const Scene* scene_;
  DataPtr data_;
};

}  // namespace pb
