// SPDX-License-Identifier: MIT
// One probe's per-step logic as a small state machine, shared by the serial Simulator and by
// batched runs (Batch step hooks): the belt command from the profile, the divergence and
// fall-through guards, the instability checks, the failure detector and the early stop once the
// load co-moves with the belt after the profile's last breakpoint.
#pragma once

#include <mujoco/mujoco.h>

#include <array>
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

/// A creeping load (SimOptions::skip_creeping) is steady once, for this long, every body's velocity
/// relative to the belt stayed within these tolerances of where it was at the window's start (and
/// its drift is small: kCreepDriftM).
/// Measured at 1 ms on a curve's arc: a load that creeps under it changes its bodies' velocities
/// by 1e-6 to 3e-4 m/s and 1e-6 to 1e-3 rad/s in 50 ms (tall-unwrapped-tower at 0.14 g, a 72-carton
/// brick at 0.19 g); one that sways or rattles near its limit by 2e-3 to 2e-2 m/s and 4e-3 to
/// 0.1 rad/s (the tower at 0.219 g, asymmetric-load at 0.286 g). The window is long against a
/// tower's sway, so a sway cannot pass it between two of its turning points.
inline constexpr double kSteadyCreepWindowS = 0.1;
inline constexpr double kSteadyCreepTolMps = 5e-4;
inline constexpr double kSteadyCreepTolRadps = 3e-3;
/// The fastest a steadily creeping body may move relative to the belt (MuJoCo's soft contacts
/// creep at 1-3 mm/s under a sustained load inside the cone); faster is a slide.
inline constexpr double kSteadyCreepMps = 0.005;
/// A creeping load jumps only while its peak ratio (SimResult::peak_ratio) plus the most its creep
/// can add to any detector's reading over the jump stays below this: a load whose creep could carry
/// it near a threshold is stepped, so a jump never decides a verdict.
inline constexpr double kCreepJumpMaxRatio = 0.5;
/// A jump carries each body's creep at its window's last mean velocity. The window's drift (the
/// change between its halves' means) must not move a body by more than this over the jump.
inline constexpr double kCreepDriftM = 5e-4;
inline constexpr double kCreepDriftRad = 1e-3;
/// Where the drift allows less than the rest of the phase, the jump is cut to what it allows
/// (ProbeRun::creep_span_s, at least a window long), once the phase has lasted kCutJumpSettleS and
/// where no pair used kCutJumpConeUse of its friction cone in the window (max_cone_use). A load
/// that rattles keeps a drift window after window: a 96-carton brick's safe 0.135 g curve, whose
/// items jitter by about 0.7 mm/s within a window while they creep at 2 mm/s, stepped its whole
/// 2 s arc until session 35. A load settling into its creep after a demand's onset loses its
/// drift a window or two later and then jumps to the phase's end (the curated loads' curves,
/// 0.2-0.35 s into the phase): a cut jump before that carries the settling on, to be waited out
/// again after it (tall-unwrapped-tower at 0.219 g: 952 steps jumped whole, 880 in two cut jumps
/// from 0.28 s). A pallet near its belt's onset rattles its cone use across kConeSaturated, and
/// each crossing adds to the slip that breaks it loose (kBreakLooseM), so a cut jump there skips
/// exposure: session 31's cut jumps without the cone bound held four curve probes that fail
/// stepped (their limits half a step higher; hold-out pallet h3105 at 0.361 g broke loose 0.3 s
/// after such a window).
inline constexpr double kCutJumpSettleS = 0.5;
inline constexpr double kCutJumpConeUse = 0.9;

/// Deciding a pallet slip before its threshold (SimOptions::project_pallet_slip): the pair's
/// kinetic friction is taken this much stronger than mu_d g (a rocking load swings the belt's
/// normal force by a few per cent), and the slip must have sped up over the last kProjectWindowS
/// (its second half's mean rate at least its first half's).
inline constexpr double kProjectFrictionMargin = 1.05;
inline constexpr double kProjectWindowS = 0.05;

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
  // The load's (pallet's and items') mass and its first moments Σ m x, Σ m y, Σ m z (world).
  struct LoadMoments {
    double mass = 0.0;
    double moment[3] = {0.0, 0.0, 0.0};
  };
  LoadMoments load_moments(const mjModel& model, const mjData& data) const;
  // The turning axis of a curve (TurningFrame): the pallet's as-built centre, carried by the belt.
  void turning_axis(const mjData& data, double axis[2]) const;
  // Plans a jump from step k_ (see SimOptions::skip_comoving) once the load has been steady long
  // enough: the steps to skip, or 0.
  int plan_skip() const;
  // Whether the load creeps steadily (SimOptions::skip_creeping): updates the creep window with
  // this step's velocities and says whether it has lasted kSteadyCreepWindowS.
  bool creeping_steadily(const mjModel& m, const mjData& d, double belt_vx, double belt_vy);
  // After a window (creeping_steadily): sets creep_v_ to the window's last half's mean velocities
  // and returns the longest span (s) over which the window's drift (the change from its first
  // half's means) moves no body by more than kCreepDriftM nor turns one by more than
  // kCreepDriftRad.
  double creep_span_s();
  // Whether the belt's command is affine in time from step k_ over the next n + 1 steps (a phase
  // in which the belt's frame accelerates, and turns, at a constant rate).
  bool command_affine(int n) const;
  // Where the pallet's slip on its belt, `slip` (m) at time t, can no longer stop short of its
  // threshold (SimOptions::project_pallet_slip): the latest time it crosses it, by the slowest
  // slide the friction allows; nullopt otherwise. Keeps the window of slips this needs.
  std::optional<double> slip_certain(const mjModel& m, const mjData& d, double t, double slip);
  // The most the creep (creep_v_) can add to any detector's reading over its threshold in `span`.
  double creep_reach(double span) const;
  // The travel (x, y) over the first `j` steps of the pending jump (of skip_n_) of the belt
  // (`lag` 0) or of a body carried with it, read `lag` steps behind.
  std::array<double, 2> jump_travel(int j, int lag) const;
  // The belt's state `j` steps into the pending jump, from `belt` where it starts.
  Trace::BeltState jumped(const Trace::BeltState& belt, int j) const;
  // Moves `p`, the pose of body `body` (0 the pallet, then the items), by the first `j` steps of
  // the pending jump: the belt's travel, and the creep's when the jump carries it.
  void shift(Pose& p, std::size_t body, int j) const;
  // Updates the detector with the item poses in items_ at time t, and the peak ratio with its
  // readings; the failure it found, if any.
  std::optional<FailureEvent> detect(double t, const Trace::BeltState& belt, const Pose& pallet,
                                     DetectorReadings& readings);

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
  // The pending jump: the belt's command where it starts, and its change over the jump.
  double skip_v0x_ = 0.0, skip_v0y_ = 0.0, skip_dvx_ = 0.0, skip_dvy_ = 0.0;
  // The creep window: each body's velocity relative to the belt at its start and at the last step
  // (6 a body, the pallet first, then the items: linear in the world frame, angular in the body's,
  // as in qvel), and the steps it has lasted; a pending jump that carries the creep (skip_creep_)
  // moves each body on at its last velocity.
  std::vector<double> creep_v0_, creep_v_;
  std::vector<double> creep_sums_;  ///< 12 a body: the window's first half's sums, its second's
  int creep_needed_ = 1, creep_steps_ = 0;
  double creep_cone_use_ = 0.0;  ///< the most of its cone a pair used in the window (max_cone_use)
  bool skip_creep_ = false;
  // Deciding a pallet slip early: the slips of the steps in a row that qualified, the steps the
  // window needs, whether the belt runs steady after the last breakpoint, and the phase whose
  // command was found affine to its end (-1: none).
  std::vector<double> slip_window_;
  int project_needed_ = 1;
  bool steady_after_last_ = false;
  int affine_phase_ = -1;
  bool done_ = false;
  std::vector<Pose> items_;
  std::vector<Pose> jumped_items_;       // the items' poses within a jump, for the trace
  std::optional<TurningFrame> turning_;  ///< a curve's: the belt's frame turns with it
};

}  // namespace pb
