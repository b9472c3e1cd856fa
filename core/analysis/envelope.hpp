// SPDX-License-Identifier: MIT
// The safe envelope of one pallet: measured start-up acceleration, stop deceleration and lateral
// (curve) limits, and the speed the line's stops and curves allow, each with the failure mode
// that governs it. Bisection seeded by closed-form quasi-static bounds, so few probes are needed.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/contract/safety_result.hpp"
#include "core/physics/quasi_static.hpp"
#include "core/physics/simulate.hpp"
#include "core/physics/step.hpp"

namespace pb {

/// What the line does to a pallet besides starting it: how hard it stops and how tight it turns.
struct LineDescription {
  double estop_decel_mps2 = 2.0;  ///< emergency-stop deceleration of the line
  double curve_radius_m = 3.0;    ///< tightest curve
  double curve_angle_deg = 90.0;  ///< its angle

  bool operator==(const LineDescription&) const = default;
};

/// Search ranges and precision (the reference's ranges; our precision).
struct SearchConfig {
  double speed_min_mps = 0.1, speed_max_mps = 2.0, speed_precision_mps = 0.05;
  double accel_min_mps2 = 0.1, accel_max_mps2 = 5.0, accel_precision_mps2 = 0.1;
  double decel_min_mps2 = 0.1, decel_max_mps2 = 5.0, decel_precision_mps2 = 0.1;
  double lateral_min_g = 0.01, lateral_max_g = 0.5, lateral_precision_g = 0.01;
  /// Probes end once the load moves with the belt again after the belt's motion stops changing
  /// (nothing can change after that), or this long after it at most: a load still sliding when
  /// the belt settles must be followed until it stops.
  double hold_s = 3.0;
  double max_ramp_s = 2.0;  ///< an acceleration probe ramps to speed_max, or for this long at most
  /// true: start each axis just above its closed-form bound and step out until bracketed; false:
  /// the reference system's plain bisection over the whole range.
  bool seed_with_closed_form = true;
  /// Probes evaluated at once per search round (k-section: one run_probes_batched call on k
  /// threads per round); 1 = serial bisection, 0 = one per logical CPU. With k > 1 the walk that
  /// brackets a limit probes its next k points a round, and the bracket is narrowed by k points of
  /// the bisection's own grid: the same limits and modes as k = 1 when failure is monotone (same
  /// doubles, bitwise the same probes), in fewer rounds (log_{k+1} instead of log2) with more
  /// simulations. On 2 cores it saved little wall time for much more CPU (core/README.md,
  /// "k-section"), so the default stays serial (and batch studies, which fill every core, keep 1).
  int parallel_probes = 1;
  /// Threads that search the four axes (start-up, stop, curve, e-stop speed) side by side, each on
  /// its own mjData; 0 = one per axis, 1 = one axis after another. The same probes and limits
  /// either way (each probe loads the whole rest state); the wall time drops towards that of the
  /// slowest axis. One per axis even on 2 cores: the axes' costs are uneven, and the scheduler
  /// balances four threads better than a queue does two (core/README.md, "Axes side by side").
  /// Batch studies, which fill every core with pallets, use 1.
  int axis_threads = 0;
  /// The memory the searches' simulations may take together, the models' own mjData included: an
  /// axis thread other than the calling one, and a probe run ahead, each need an mjData of their
  /// own for their model, and a large load's is tens of MB resident (engine.hpp: make_data), so a
  /// thread takes an axis only where the budget holds its model's mjData, and the calling thread,
  /// on the models' own, takes the rest, the largest model's axes first; a probe run from the start
  /// (the stop's check) takes only what the threads leave (core/README.md, "Axis threads within a
  /// memory budget").
  double axis_memory_bytes = 640.0 * 1024 * 1024;
  /// Axes answered from others where the physics says they must agree (search_envelope): a
  /// mirror-symmetric load's stop from its start-up, the e-stop speed from the stop search, and
  /// faster e-stops from one that failed within its deceleration (AxisTask::same_until).
  /// false searches every axis on its own (the reference configuration, the judge, does).
  bool derive_axes = true;
  /// With the axes on threads of their own (axis_threads != 1) and k = 1: a search that would
  /// leave a core idle (the other axes done) runs, beside each probe, the probe it takes next on
  /// one outcome of it (failed first, then safe, as cores allow). The search consumes probes as the
  /// serial one does, so limits, modes and the probe list are the same with it on or off; only the
  /// wall time changes (Envelope::speculative counts the probes run ahead for nothing).
  bool speculate = true;
  /// ... once the search's last probe took this long (ms): starting a thread and an mjData cost
  /// about as much as a reduced-model probe (core/README.md, "Probes run ahead on spare cores").
  double speculate_after_ms = 20.0;

  /// Each limit a search found safe is run once more along another numerical path (the solve warm
  /// started differently: SimOptions::extrapolate_warmstart); if that run fails, the load's fate
  /// there hangs on round-off, the value counts as failing and the search goes on below it. Off
  /// by default, for its cost (measured in core/README.md, "Limits that hang on round-off").
  bool confirm_limits = false;
  /// A limit of a load whose items can move whose own probe came this near failing
  /// (SimResult::peak_ratio) is confirmed as confirm_limits confirms every limit: near its
  /// threshold such a load's fate can hang on round-off (core/README.md, "Limits that hang on
  /// round-off"). Above 1: none is.
  double confirm_from_peak = 0.9;
  /// A walk down from a failing probe doubles its steps at once where that probe failed early in
  /// its demand (before kEarlyFailure of it had passed: the limit is likely far below), and steps
  /// singly again after the next late failure (AxisSearch). Off: the walk's fixed steps (three
  /// single ones, then doubling). Measured in core/README.md, "The walk".
  bool hasten_walk = true;
  /// A search of a load whose items can move probes its answer once more a step below, and walks
  /// down again from a failure there, at most this many times (AxisSearch: a band of demands where
  /// the load fails and holds by turns). 3 from session 14 to 31; 0 since session 32: on 126
  /// unwrapped pallets no check failed, so every one was a simulation for nothing
  /// (core/README.md, "The answer was checked a step below").
  int band_checks = 0;

  bool operator==(const SearchConfig&) const = default;
};

enum class Axis { accel, decel, lateral, speed };
std::string_view to_string(Axis axis);

/// What set a speed limit, in a supervisor's words ("the line's e-stop").
std::string_view governor_words(SpeedGovernor by);

/// One simulation of the search.
struct Probe {
  Axis axis = Axis::accel;
  double value = 0.0;  ///< m/s^2, m/s^2, g or m/s
  Outcome outcome = Outcome::safe;
  FailureMode mode = FailureMode::no_failure;
  double failure_time_s = 0.0;
  double wall_ms = 0.0;
  int steps = 0;            ///< steps simulated (profile steps reached minus those jumped)
  double sim_time_s = 0.0;  ///< profile time reached
  double peak_ratio = 0.0;  ///< SimResult::peak_ratio: how near it came to failing (>= 1: failed)
  double load_peak_ratio = 0.0;  ///< SimResult::load_peak_ratio: as near, its pallet's slip aside
  bool confirmation = false;     ///< the run that confirms a limit (SearchConfig::confirm_limits)
  CurveTurn turn = CurveTurn::left;  ///< lateral: the way the curve turned
  /// A top_item_slide's way (detectors.hpp): an item slid or tipped, or the load slid as one.
  SlideKind slide = SlideKind::item_slid;
  bool projected = false;  ///< a pallet slip decided before its threshold (FailureEvent::projected)
};

struct AxisLimit {
  double limit = 0.0;  ///< the largest value found safe (0 if even the floor fails)
  FailureMode mode = FailureMode::no_failure;  ///< what fails just above it
  bool at_ceiling = false;                     ///< safe throughout the search range
  bool at_floor = false;                       ///< fails even at the bottom of the range
  double closed_form =
      0.0;  ///< the closed-form prediction (predict_axis; the seed of a one-body load)
  int probes = 0;
  /// Not searched: derived from another axis's search (search_envelope): the stop from the
  /// start-up's (a mirror-image load, or one whose pallet slips first both ways: then checked with
  /// one probe below the pallet's onset), or the e-stop speed from the stop's.
  bool derived = false;
  /// Lateral: the turn that fails just above the limit. A load that is not its own mirror image
  /// across the belt is searched in a left turn and then checked, and searched lower if need be,
  /// in a right one (search_envelope); the limit is the lower.
  CurveTurn turn = CurveTurn::left;
  /// How the top_item_slide above the limit went (detectors.hpp): an item tipped rather than
  /// slid, and the reason says "an item tips over", or the load slid on its pallet as one
  /// ("the load slides on its pallet").
  SlideKind slide = SlideKind::item_slid;
  /// Lateral, a wrapped load on the reduced level: held at the curve where a pallet broken loose
  /// at the arc's entry slides its allowance by the arc's end, which the rigid model cannot break
  /// loose there (search_envelope); the reason says so.
  bool loose_at_entry = false;
};

struct Envelope {
  SafetyResult result;
  AxisLimit accel, decel, lateral, speed;
  std::vector<Probe> probes;
  RestState rest;
  /// Probes run ahead on spare cores (SearchConfig::speculate), and of those the ones the searches
  /// never needed (not in `probes` nor in sims_run). Both depend on timing, nothing else does.
  int ran_ahead = 0;
  int speculative = 0;
};

/// The probe profiles of each axis, so that a user can replay the probe that failed.
ConveyorProfile accel_probe_profile(double accel_mps2, const SearchConfig& search);
ConveyorProfile decel_probe_profile(double decel_mps2, double speed_mps,
                                    const SearchConfig& search);
/// The turns a load's curves are checked in: a left turn only for a load that is its own mirror
/// image across the belt (mirror_symmetric_across: both turns are one experiment, mirrored), else
/// left and right. The envelope, the failure map and the confidence samples all ask this.
std::vector<CurveTurn> curve_turns(const PalletConfig& config);
ConveyorProfile lateral_probe_profile(double lateral_g, const LineDescription& line,
                                      const SearchConfig& search, CurveTurn turn = CurveTurn::left);
ConveyorProfile stop_probe_profile(double speed_mps, const LineDescription& line,
                                   const SearchConfig& search);

/// Where a probe of one axis is predicted to fail, in the axis's units, and through what
/// (`value` >= the range's top and no_failure when nothing is predicted to fail inside it).
struct AxisPrediction {
  double value = 0.0;
  FailureMode mode = FailureMode::no_failure;
};

/// The closed-form model of a probe: each mechanism as a rigid body. A tip fails at its
/// quasi-static onset g (b/2) / h. A slip fails where its slide reaches what its detector allows
/// (the pallet 0.30 m on the belt, an item 0.05 m on the deck, 0.02 m on another item): a belt
/// acceleration a held for T = step_duration_s(x) leaves a load of static onset mu_s g behind by
/// breakaway_slide_m (quasi_static.hpp: the simulation's friction law, which breaks loose after
/// slipping `break_loose_m` on the static cone and slides at mu_d g; with 0, Coulomb's (a - mu_d
/// g) T^2 / 2 + ((a - mu_d g) T)^2 / (2 mu_d g), the earliest any rigid body fails). The weakest
/// mechanism wins. `unit` converts the axis's values to m/s^2 (g for the curve axis).
AxisPrediction predict_axis(const std::vector<QuasiStaticLimit>& mechanisms, double unit, double lo,
                            double hi, const std::function<double(double)>& step_duration_s,
                            const DetectorThresholds& thresholds,
                            double break_loose_m = kBreakLooseM);

struct AxisPredictions {
  AxisPrediction accel, decel, lateral;
};
/// The three demand axes. A load that moves as one body (QuasiStaticBounds::one_body): predict_axis
/// with each probe's step duration (start-up: the ramp to speed; stop: the e-stop from speed_max;
/// curve: the arc); within one search step of the reference on 14 of 14 wrapped pallets (core/
/// README.md). A load whose items can slide and rock: the weakest onsets, because the rigid-body
/// slide overstated what such a load survives by 2-3.5 steps on the unwrapped curated scenarios
/// (it rocks and slides at once).
AxisPredictions predict_envelope(const QuasiStaticBounds& bounds, const LineDescription& line,
                                 const SearchConfig& search, const DetectorThresholds& thresholds);

/// Searches every axis on a settled scene. In the belt's frame a start-up at a is a pulse of -a for
/// speed_max / a (once a reaches speed_max within max_ramp_s) and the stop from speed_max at d a
/// pulse of +d for speed_max / d: a load that is its own mirror image along the belt
/// (mirror_symmetric_along) with equal start-up and stop ranges answers both from the start-up
/// search, whose probes all were such pulses; otherwise the stop is searched after it. So does a
/// load whose items its pallet carries past its slip onset both ways (no item mechanism below that
/// onset along the belt) where the start-up found its pallet slipping: one body on isotropic
/// Coulomb friction slides alike under either pulse, so the stop takes the start-up's limit and is
/// checked once below the pallet's onset, where an item may fail one way only. Likewise the
/// line's e-stop from speed_max is the stop probe at the line's deceleration: when the stop search
/// found that deceleration safe (failure is monotone along the axis, as every search assumes), the
/// e-stop speed is at its ceiling without a probe. An unstable probe makes the whole envelope fail
/// with
/// its reason (never a verdict); a pallet that fails at the floor of the acceleration or the stop
/// search gets verdict "reject" with the mode.
Result<Envelope> search_envelope(Simulator& simulator, const RestState& rest,
                                 const QuasiStaticBounds& bounds, const LineDescription& line = {},
                                 const SearchConfig& search = {}, const SimOptions& sim = {});

/// A settled model the probes of one plane run on.
struct ProbeModel {
  Simulator* simulator = nullptr;
  const RestState* rest = nullptr;
};

/// The same search with the probes along the belt (start-up, stop, e-stop speed) on `along` and
/// the curve's on `across`: a load with symmetric copies is simulated on a reduced model per plane
/// (symmetry.hpp). `bounds` and the mirror test are those of `config`, the whole load.
/// `found`, if given, hears each of the start-up, stop and curve limits as soon as its search
/// ends (or it is derived), from the thread that searched it, before the envelope is complete (the
/// console replaces its provisional estimate axis by axis).
using AxisFound = std::function<void(Axis axis, const AxisLimit& limit)>;
Result<Envelope> search_envelope(const ProbeModel& along, const ProbeModel& across,
                                 const PalletConfig& config, const QuasiStaticBounds& bounds,
                                 const LineDescription& line, const SearchConfig& search,
                                 const SimOptions& sim, const AxisFound& found = {});

/// The closed-form rung of the fidelity ladder: every limit from the quasi-static bounds (onset of
/// slip or tip, floored to the search precision; the e-stop speed from the slide distance,
/// breakaway_slide_speed_mps: about v^2 / 2 (1 / (mu_d g) - 1 / d)), no simulation, reported with
/// fidelity "closed_form". An estimate, not a bound: a probe allows a finite slide (above the
/// onset) but its onset is a step load that a tall load can rock under (below it), and which wins
/// depends on the load.
Envelope closed_form_envelope(const QuasiStaticBounds& bounds, const LineDescription& line = {},
                              const SearchConfig& search = {},
                              const DetectorThresholds& thresholds = {});

}  // namespace pb
