// SPDX-License-Identifier: MIT
// One probe's per-step logic as a small state machine, shared by the serial Simulator and by
// batched runs (Batch step hooks): the belt command from the profile, the divergence and
// fall-through guards, the instability checks, the failure detector and the early stop once the
// load co-moves with the belt after the profile's last breakpoint.
#pragma once

#include <mujoco/mujoco.h>

#include <optional>
#include <string>
#include <vector>

#include "core/contract/conveyor_profile.hpp"
#include "core/physics/detectors.hpp"
#include "core/physics/scene.hpp"
#include "core/physics/sim_types.hpp"
#include "core/physics/turning_frame.hpp"

namespace pb {

/// A belt that stops following its command, its error growing step after step, has diverged (an
/// explicit velocity drive with kv dt / M >= 2 triples its error every step); a detector would
/// otherwise report the runaway motion as a conveyor failure.
class BeltWatch {
 public:
  std::optional<std::string> check(double error);

 private:
  double last_ = 0.0;
  int growth_ = 0;
};

/// The pose of a body after the last step.
Pose body_pose(const mjData& data, int body);
/// The poses of the scene's items after the last step.
void read_item_poses(const SceneLayout& layout, const mjData& data, std::vector<Pose>& out);
/// The fastest linear speed of the pallet or an item relative to the belt's velocity (and, in
/// `spin`, the fastest angular speed).
double max_relative_speed(const SceneLayout& layout, const mjData& data, double belt_vx,
                          double belt_vy, double* spin);
/// The largest linear acceleration of the pallet or an item relative to the belt's, and (in
/// `spin`) the largest angular acceleration, of the step just taken.
double max_relative_accel(const SceneLayout& layout, const mjData& data, double* spin);
/// The state a probe starts from: `rest` (at t = 0, nothing applied, no warnings) with the belt,
/// the pallet and every item riding along at `initial_speed`, the belt commanded to it.
SimState start_state(const SceneLayout& layout, const RestState& rest, double initial_speed);
/// Puts start_state(layout, rest, initial_speed) into `data`.
void load_rest_state(const SceneLayout& layout, const RestState& rest, double initial_speed,
                     mjData& data);

/// One probe run. Construct, load the start state (load_rest_state with initial_speed()), then
/// per step: before_step(data), pb::step (step.hpp), after_step(model, data) until it returns
/// false. An engine error raised by the step goes to engine_error(). Not thread-safe; one per
/// simulation. The scene and the rest state must outlive it.
class ProbeRun {
 public:
  ProbeRun(const Scene& scene, const RestState& rest, const ConveyorProfile& profile,
           const SimOptions& options);

  double initial_speed() const { return v0_; }
  /// Steps the profile needs at most (the run may stop earlier).
  int max_steps() const { return n_steps_; }
  /// True once the outcome is decided (no more steps).
  bool done() const { return done_; }

  /// Writes the belt command for the step about to run (applying a pending co-moving jump to
  /// `data` first: see SimOptions::skip_comoving).
  void before_step(mjData& data);
  /// Reads the step just taken; false when the run is over (the result is final then).
  bool after_step(const mjModel& model, const mjData& data);
  /// The step raised an engine error (or the batch found the state unstable): the run is over,
  /// unstable with `reason`.
  void engine_error(const std::string& reason);
  /// Ends a run that never stepped (or was stopped from outside) with the final stability check.
  void finish(const mjModel& model, const mjData& data);

  const SimResult& result() const { return r_; }
  SimResult take_result() { return std::move(r_); }

 private:
  void unstable(const std::string& reason);
  // True when the load's energy relative to the belt (kinetic in the belt's frame, potential above
  // where the run started) is below a share of the least work any detector still needs
  // (Scene::barriers against what `readings` leaves of each threshold). Only meaningful after the
  // last breakpoint: the belt's frame is then inertial and the load passive, so it cannot gain the
  // energy a failure needs.
  bool below_barrier(const mjModel& model, const mjData& data, const Trace::BeltState& belt,
                     const DetectorReadings& readings);
  double potential_energy(const mjModel& model, const mjData& data) const;
  // Plans a co-moving jump from step k_ (see SimOptions::skip_comoving): the steps to skip, or 0.
  int plan_skip() const;
  // Shifts `p` by the pending jump's belt travel.
  void shift(Pose& p) const;

  const Scene* scene_;
  ConveyorProfile profile_;
  SimOptions o_;
  SimResult r_;
  FailureDetector detector_;
  BeltWatch belt_watch_;
  double v0_ = 0.0, dt_ = 0.0, last_breakpoint_ = 0.0;
  bool stops_early_ = false;  ///< SimOptions::early_stop, where the run ends on an inertial belt
  double belt_x0_ = 0.0, belt_y0_ = 0.0, fall_through_z_ = 0.0;
  double command_x_ = 0.0, command_y_ = 0.0;
  int n_steps_ = 0, k_ = 0, comove_needed_ = 1, comove_steps_ = 0;
  // Deciding early on energy: steps below the barrier in a row, and how many make it certain.
  int calm_steps_ = 0, calm_needed_ = 1;
  int settled_after_failure_ = 0;  ///< steps the load has moved with the belt since the failure
  double pe0_ = 0.0;
  std::vector<double> vrel_, mv_;
  // The accelerations of the last two steps (SimOptions::extrapolate_warmstart), and how many of
  // them are there.
  std::vector<double> qacc1_, qacc2_;
  int qacc_known_ = 0;
  // Skipping: the profile's breakpoints, the phase of the last step, the co-moving steps within
  // it, and the pending jump (steps, belt travel, belt velocity change) before_step applies.
  std::vector<double> breakpoints_;
  std::size_t phase_ = 0;
  int dwell_needed_ = 1, dwell_steps_ = 0, skip_n_ = 0;
  double skip_dx_ = 0.0, skip_dy_ = 0.0, skip_dvx_ = 0.0, skip_dvy_ = 0.0;
  bool done_ = false;
  std::vector<Pose> items_;
  std::optional<TurningFrame> turning_;  ///< a curve's: the belt's frame turns with it
};

}  // namespace pb
