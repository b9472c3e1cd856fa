// SPDX-License-Identifier: MIT
#include "ui/models/dial_game.hpp"

#include <algorithm>
#include <cmath>

#include "core/physics/detectors.hpp"

namespace pb::ui {

DialZone dial_zone(double value, double limit) {
  if (!(limit > 0.0) || value > limit) return DialZone::failing;
  if (value >= kDialedInFraction * limit) return DialZone::marginal;
  return DialZone::safe;
}

namespace {

/// Fraction of a limit; a non-positive limit counts as fully dared (there was no room at all).
double fraction_of(double value, double limit) {
  if (!(limit > 0.0)) return 1.0;
  return std::max(0.0, value / limit);
}

char grade_for(double fraction) {
  if (fraction >= 0.95) return 'S';
  if (fraction >= kDialedInFraction) return 'A';
  if (fraction >= 0.60) return 'B';
  return 'C';
}

int percent(double fraction) {
  return static_cast<int>(std::lround(100.0 * fraction));
}

}  // namespace

DialScore score_dispatch(const ConveyorProfile& dialled, bool survived, FailureMode mode,
                         const SafetyResult& envelope, SlideKind how) {
  DialScore s;
  s.speed_fraction = fraction_of(dialled.target_speed_mps, envelope.max_speed_mps);
  s.accel_fraction = fraction_of(dialled.accel_mps2, envelope.max_accel_mps2);
  const double dared = std::min(s.speed_fraction, s.accel_fraction);
  s.fraction = std::clamp(dared, 0.0, 1.0);
  if (envelope.verdict == Verdict::reject) {
    s.verdict = DialScore::Verdict::reject;
    s.grade = 'F';
    s.failure_mode = survived ? envelope.dominant_failure_mode : mode;
    s.headline = survived ? "Survived this one, but the solver rejects the pallet: re-wrap it"
                          : "Crashed, and no motion was safe: reject and re-wrap";
    return s;
  }
  if (!survived) {
    s.verdict = DialScore::Verdict::crashed;
    s.grade = 'F';
    s.failure_mode = mode;
    s.failure_slide = how;
    s.headline = "The dispatch failed: " + std::string(mode_words(mode, how));
    return s;
  }
  s.points = percent(s.fraction);
  s.grade = grade_for(s.fraction);
  if (dared > 1.0) {
    s.verdict = DialScore::Verdict::beyond_limit;
    s.headline = "Survived beyond the solver's limit (" + std::to_string(percent(dared)) +
                 " %): lucky, the limit is the search's safe side";
  } else if (s.fraction >= kDialedInFraction) {
    s.verdict = DialScore::Verdict::dialed_in;
    s.headline = "Dialed in: " + std::to_string(s.points) + " % of the limit";
  } else {
    s.verdict = DialScore::Verdict::cautious;
    s.headline =
        "Survived at " + std::to_string(s.points) + " % of the limit: throughput left on the belt";
  }
  return s;
}

void DialGame::dispatch(const ConveyorProfile& profile) {
  *this = DialGame{};
  profile_ = profile;
}

void DialGame::setEnvelope(const SafetyResult& envelope) {
  if (dispatched()) envelope_ = envelope;
}

void DialGame::setOutcome(bool survived, FailureMode mode, SlideKind how) {
  if (!dispatched()) return;
  survived_ = survived;
  mode_ = survived ? FailureMode::no_failure : mode;
  how_ = survived ? SlideKind::item_slid : how;
}

void DialGame::replayFinished() {
  if (dispatched() && survived_.has_value()) replay_done_ = true;
}

bool DialGame::revealed() const {
  return dispatched() && envelope_.has_value() && survived_.has_value() && replay_done_;
}

std::optional<SafetyResult> DialGame::envelope() const {
  if (!revealed()) return std::nullopt;
  return envelope_;
}

std::optional<DialScore> DialGame::score() const {
  if (!revealed()) return std::nullopt;
  return score_dispatch(*profile_, *survived_, mode_, *envelope_, how_);
}

}  // namespace pb::ui
