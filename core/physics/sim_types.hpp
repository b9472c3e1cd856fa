// SPDX-License-Identifier: MIT
// What one simulation starts from, is told and returns: the rest state a probe loads, the
// settle's and the run's options, the outcome and the run's record. Value types only: the
// Simulator (simulate.hpp) and the stepping of one run (probe_run.hpp) both build on them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/base/cancel.hpp"
#include "core/base/enums.hpp"
#include "core/base/pose.hpp"
#include "core/base/progress.hpp"
#include "core/physics/detectors.hpp"
#include "core/physics/sim_state.hpp"
#include "core/physics/trace.hpp"

namespace pb {

/// A load that cannot stand on a still belt (a build defect, never a conveyor limit): what moved
/// while it was settled and held with the belt standing still.
struct StandFailure {
  /// The first detector crossing against the as-built poses (its time from the start of the
  /// settle); mode no_failure when nothing crossed but the load never came to rest.
  FailureEvent event;
  int item = -1;         ///< where the collapse starts: the lowest item that moved (or the fastest)
  int moved = 0;         ///< items that moved more than half the load-shift threshold
  std::string sentence;  ///< for a supervisor: the item, what it did, what to do
};

/// The MuJoCo state a probe starts from (where the load first came to rest on a still belt), plus
/// the detector baselines.
struct RestState {
  SimState state;
  Pose pallet;
  std::vector<Pose> items;
  double settle_time_s = 0.0;  ///< when it first came to rest (the hold after it not counted)
  double settle_run_s = 0.0;   ///< how long the settle simulated (its first rest, then the hold)
  double residual_speed_mps = 0.0;  ///< fastest body when it was declared at rest
  /// Set when the load cannot stand: then this is not a rest state, and a probe from it is refused
  /// (ProbeRun reports it unstable).
  std::optional<StandFailure> cannot_stand;
};

struct SettleOptions {
  double rest_speed_mps = 0.002;  ///< every body slower than this (and ...)
  double rest_spin_radps = 0.02;  ///< ... turning slower than this: at rest
  double min_time_s = 0.05;
  /// At rest at every check for this long (the belt still) before the load is declared settled: a
  /// carton balanced on an edge passes through rest before it tips. The rest state is where the
  /// load first came to rest; the hold only confirms that it stays there. A load never quiet for a
  /// whole hold by max_time_s, whose items nevertheless all stayed within a quarter of the
  /// load-shift threshold of that state (contact chatter, not motion), is settled too.
  double hold_s = 0.2;
  /// Contact chatter (core/README.md "Settle, then hold"): a load whose bodies stay through the
  /// hold within rest_speed x hold (and rest_spin x hold) of where it first came to rest is
  /// settled at the next check at which it is at rest, though it was not at rest at every check.
  /// false only to measure the rule (simulate_test).
  bool calm_hold = true;
  double max_time_s = 3.0;  ///< a load still moving then cannot stand (a build defect)
  double check_every_s = 0.01;
  /// When set, the settle stops at its next check and fails ("cancelled"). Not owned.
  const CancelFlag* cancel = nullptr;
};

enum class Outcome { safe, failed, unstable };
template <>
struct EnumTable<Outcome> {
  static constexpr std::array<EnumName<Outcome>, 3> names{
      {{Outcome::safe, "safe"}, {Outcome::failed, "failed"}, {Outcome::unstable, "unstable"}}};
};

struct SimOptions {
  DetectorThresholds thresholds;
  bool fail_fast = true;  ///< stop at the first failure
  /// With fail_fast off: after the first failure (the verdict, unchanged) the run follows the
  /// wreck, past the profile's end if need be, until the load moves with the belt again (after at
  /// least 0.25 s) or this long after the failure; an instability meanwhile ends the run and keeps
  /// the verdict (SimResult::aftermath_cut says why). 0: to the profile's end, as before.
  double follow_failure_s = 0.0;
  /// Stop once the load co-moves with the belt after the last breakpoint (only where the belt then
  /// moves at constant velocity: a run that ends mid-ramp or mid-curve is stepped to its end).
  bool early_stop = true;
  /// With early_stop: also stop once the load's energy relative to the belt stays below what any
  /// detector still needs (probe_run.cpp: below_barrier), which decides a run while a slide that
  /// cannot reach its threshold still coasts. Off where the motion is shown (Analyzer::solve's
  /// replay runs until the load co-moves, so the replay shows where the slide ends).
  bool energy_stop = true;
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
  /// With skip_comoving: also jump where the load creeps steadily rather than co-moves. MuJoCo's
  /// soft contacts creep at 1-3 mm/s under a sustained demand inside the friction cone (a curve's
  /// arc, a start-up's ramp), which co-moving (comove_speed_mps) never allows. Once, for
  /// kSteadyCreepWindowS (probe_run.hpp), no pair has broken loose (step.hpp), every body has
  /// moved within kSteadyCreepMps of the belt and spun below comove_spin_radps, and each body's
  /// velocity relative to the belt stayed within kSteadyCreepTolMps (linear) and
  /// kSteadyCreepTolRadps (angular) of where it was at the window's start, the jump carries each
  /// body on at that relative velocity as well as with the belt (the creep's travel is kept, so
  /// the detectors see it at the jump's end), as far as the window's drift allows
  /// (kCutJumpSettleS).
  bool skip_creeping = true;
  /// With fail_fast: a pallet slip is decided once its slide can no longer stop short of the
  /// threshold (probe_run.cpp: ProbeRun::slip_certain; FailureEvent::projected). Only the belt's
  /// pair has broken loose, its load riding the pallet; the demand at the load's centre of mass
  /// (the belt's acceleration, and a curve's turning) beats kProjectFrictionMargin x the pair's
  /// kinetic friction and holds, affine in time, to the phase's end; and the slip has sped up over
  /// the last kProjectWindowS. Then the slide at that margin reaches the threshold (with what it
  /// coasts after the phase, where the belt then runs steady). Off in the reference configuration.
  bool project_pallet_slip = true;
  /// Warm-start each step's constraint solve from the line through the last two steps'
  /// accelerations instead of the last one's. The solve converges to the same answer up to its
  /// tolerance, so this is the same probe along another numerical path: where the load's fate
  /// hangs on round-off, the two can disagree (the limit confirmation runs it; SearchConfig).
  bool extrapolate_warmstart = false;
  double skip_dwell_s = 0.02;
  /// When set, a probe stops after its current step and ends unstable, its reason starting with
  /// kCancelledReason: no verdict (a search that meets one fails). Not owned.
  const CancelFlag* cancel = nullptr;
  /// As `cancel`, for this probe alone: set when its result is no longer wanted (a probe run ahead
  /// of a search, on the outcome that did not happen). Not owned.
  const CancelFlag* abandon = nullptr;
  /// When set, the searches and batched runs given these options count their simulations on it
  /// as they end (a search its path's probes; run_probes_batched every run). Not owned.
  ProgressCounter* progress = nullptr;
};

struct SimResult {
  Outcome outcome = Outcome::safe;
  std::optional<FailureEvent> failure;
  std::string reason;  ///< why the run is unstable (empty otherwise)
  /// Why the aftermath of a failure ended before its time (an instability after the verdict, which
  /// stays failed); empty otherwise.
  std::string aftermath_cut;
  Trace trace;
  /// How near the run came to failing: the largest reading of any detector over its threshold
  /// (tilt over tip_deg, slide over item_slide_m, ...), the largest over the run; >= 1 once failed.
  double peak_ratio = 0.0;
  /// As peak_ratio, over the load's own detectors (a tilt, an item's slide, the load's shift):
  /// without the pallet's slip on its belt.
  double load_peak_ratio = 0.0;
  int steps = 0;           ///< profile steps reached (stepped + skipped)
  int steps_skipped = 0;   ///< of `steps`, jumped analytically (skip_comoving)
  double skipped_s = 0.0;  ///< profile time jumped analytically
  /// Each jump, in order: the step it starts after and the steps it jumped. The trace holds a
  /// frame for every step of it all the same (the belt's motion, and the load carried with it).
  struct Jump {
    int after_step = 0;
    int steps = 0;
  };
  std::vector<Jump> jumps;
  double sim_time_s = 0.0;     ///< profile time reached
  bool stopped_early = false;  ///< co-moving after the last breakpoint: nothing could change
  double wall_ms = 0.0;
};

}  // namespace pb
