// SPDX-License-Identifier: MIT
// The replay of one simulation: poses resampled at a fixed rate (30 Hz), what the console plays and
// the CLI exports. Written as compact arrays: a 3 s replay of 24 items is about 110 KB of JSON.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/base/pose.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/physics/detectors.hpp"
#include "core/physics/trace.hpp"

namespace pb {

/// The outcomes a replay can carry: the load stayed put, a detector fired, or the solver diverged.
inline constexpr std::array<std::string_view, 3> kReplayOutcomes{"safe", "failed", "unstable"};

struct ReplayFrame {
  double t = 0.0;       ///< s since the start of the profile
  double belt_x = 0.0;  ///< belt travel since rest (m)
  double belt_y = 0.0;
  Pose pallet;
  std::vector<Pose> items;  ///< one per item of the pallet, in its order

  bool operator==(const ReplayFrame&) const = default;
};

struct Replay {
  PalletConfig pallet;
  ConveyorProfile profile;
  std::string outcome = "safe";         ///< one of kReplayOutcomes
  std::optional<FailureEvent> failure;  ///< present exactly when outcome is "failed"
  double hz = 30.0;
  std::vector<ReplayFrame> frames;

  bool operator==(const Replay&) const = default;
};

/// Resamples a trace at `hz`: one frame at every t = k / hz from the trace's first time through its
/// last (positions and belt travel interpolated linearly, orientations by slerp, between the two
/// trace frames around t), then the trace's last frame itself if its time is not on that grid;
/// the failure's time, when it is not on the grid, is a frame of its own, so that the moment the
/// detector fired is shown exactly (a failed run goes on after it: Analyzer::solve follows the
/// wreck). An empty trace or a non-positive `hz` gives no frames.
Replay make_replay(const Trace& trace, const PalletConfig& pallet, const ConveyorProfile& profile,
                   std::string outcome, std::optional<FailureEvent> failure, double hz = 30.0);

/// The pallet as built, before any simulation: one frame at t = 0, the pallet on the belt and every
/// item where the configuration puts it (box centres, turned by their yaw), outcome "safe", no
/// profile run. What a view shows of a pallet being edited.
Replay as_built_replay(const PalletConfig& pallet);

/// The replay's state at time `t` (the player's cursor): positions and belt travel interpolated
/// linearly and orientations by slerp (shortest arc) between the two frames around `t`; clamped to
/// the first and last frames (returned exactly). No frames gives a default frame.
ReplayFrame frame_at(const Replay& replay, double t);

/// A failure as every JSON document carries it: null, or {"mode", "time_s", "value", "items"} and
/// for a top_item_slide "item_tilt_deg" and "least_item_move_m" (result_json.hpp's
/// failure_event_to_json adds a description).
Json failure_to_json(const std::optional<FailureEvent>& failure);

/// Writes "schema_version", "pallet", "profile", "outcome", "failure" (failure_to_json), "hz" and
/// "frames": [{"t", "belt": [x, y], "pallet": [x, y, z, qw, qx, qy,
/// qz], "items": [[x, y, z, qw, qx, qy, qz], ...]}]. Positions and belt travel are rounded to
/// 0.01 mm and quaternion components to 1e-6 (display precision; the failure's values and the
/// times stay exact), so to_json(from_json(to_json(r))) == to_json(r).
Json replay_to_json(const Replay& replay);

/// Reads a replay. Every key but "schema_version" is required. Errors (with pointers): wrong JSON
/// types or array lengths, an unknown outcome or failure mode, a failure that does not match the
/// outcome or names an item the pallet does not have, a non-positive hz, a frame whose item count
/// differs from the pallet's, a quaternion off unit length by more than 1e-3, times that do not
/// increase. Unknown keys are warnings. Never throws.
Result<Replay> replay_from_json(const Json& json);

}  // namespace pb
