// SPDX-License-Identifier: MIT
// The dial game's rules, headless: the player dials a speed and a start-up acceleration and
// dispatches; the solver's envelope is computed meanwhile but revealed only once the replay has
// ended; the score is the fraction of the solver's limit the player dared (the reference game:
// "survive at 85 %+ of the ceiling and you're dialed in, crash and you're buying yogurt").
// No widgets: DialPanel shows it, tests drive it directly.
#pragma once

#include <optional>
#include <string>

#include "core/base/enums.hpp"
#include "core/contract/conveyor_profile.hpp"
#include "core/contract/safety_result.hpp"

namespace pb::ui {

/// Where a dialled value sits against the solver's limit on its axis.
///  - safe:     below kDialedInFraction of the limit (safe, with margin to spare);
///  - marginal: from kDialedInFraction of the limit up to the limit (safe, close to the edge);
///  - failing:  above the limit (the solver found a failure there).
enum class DialZone { safe, marginal, failing };

/// "Dialed in" from 85 % of the solver's limit.
inline constexpr double kDialedInFraction = 0.85;

/// The zone of `value` for an axis whose solver limit is `limit` (a limit <= 0: every value fails).
DialZone dial_zone(double value, double limit);

/// The verdict of one dispatch once the envelope is revealed.
struct DialScore {
  enum class Verdict {
    dialed_in,     ///< survived at >= 85 % of the limit on both axes
    cautious,      ///< survived below 85 % of the limit on an axis
    crashed,       ///< the dispatch failed (a detector fired)
    reject,        ///< the solver says no motion is safe: the pallet must not ride at all
    beyond_limit,  ///< survived above the solver's limit (the limit is a conservative search)
  };
  Verdict verdict = Verdict::cautious;
  double speed_fraction = 0.0;  ///< dialled speed / solver speed limit (capped at 1 in `fraction`)
  double accel_fraction = 0.0;  ///< dialled accel / solver accel limit
  double fraction = 0.0;        ///< the fraction dared: min of the two, in [0, 1]
  int points = 0;               ///< round(100 * fraction) if survived, else 0
  char grade = 'C';             ///< S >= 95 %, A >= 85 %, B >= 60 %, C below, F crashed / reject
  FailureMode failure_mode = FailureMode::no_failure;  ///< what failed, when crashed
  SlideKind failure_slide = SlideKind::item_slid;      ///< how, for a top_item_slide
  std::string headline;                                ///< "Dialed in: 91 % of the limit"
};

/// Scores a finished dispatch against the revealed envelope; a failed one failed with `mode`
/// (a top_item_slide as `how` says: detectors.hpp's slide_kind).
DialScore score_dispatch(const ConveyorProfile& dialled, bool survived, FailureMode mode,
                         const SafetyResult& envelope, SlideKind how = SlideKind::item_slid);

/// One round of the game: dispatched, then the dispatch's outcome, the envelope and the end of the
/// replay arrive in any order. The envelope (and the score) is revealed only when all three are in.
class DialGame {
 public:
  /// Starts a round; forgets the previous one.
  void dispatch(const ConveyorProfile& profile);
  /// The solver's envelope for the dispatched pallet (kept hidden until revealed()).
  void setEnvelope(const SafetyResult& envelope);
  /// The dispatch's own run ended: survived, or failed with `mode` (a top_item_slide as `how`
  /// says).
  void setOutcome(bool survived, FailureMode mode = FailureMode::no_failure,
                  SlideKind how = SlideKind::item_slid);
  /// The replay finished playing.
  void replayFinished();

  bool dispatched() const { return profile_.has_value(); }
  /// True once the envelope, the outcome and the end of the replay are all in.
  bool revealed() const;
  /// The envelope, only once revealed.
  std::optional<SafetyResult> envelope() const;
  /// The score, only once revealed.
  std::optional<DialScore> score() const;

 private:
  std::optional<ConveyorProfile> profile_;
  std::optional<SafetyResult> envelope_;
  std::optional<bool> survived_;
  FailureMode mode_ = FailureMode::no_failure;
  SlideKind how_ = SlideKind::item_slid;
  bool replay_done_ = false;
};

}  // namespace pb::ui
