// SPDX-License-Identifier: MIT
// Friction against temperature, per surface pair, with the frost-melt transition penalty.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/contract/pallet_config.hpp"

namespace pb {

/// The temperatures the friction tables cover: a pallet's body_temp_c (validation), the service's
/// friction routes and the CLI's friction verb accept these, C.
inline constexpr double kMinTempC = -40.0;
inline constexpr double kMaxTempC = 40.0;

struct FrictionPoint {
  double temp_c = 0.0;
  double mu_s = 0.0;  ///< static
  double mu_d = 0.0;  ///< dynamic (kinetic)
};

/// One surface pair, "lower/upper" by convention ("wood_pallet/rubber_belt", "carton/carton"):
/// control points sorted by temperature, interpolated linearly, clamped outside their range.
struct SurfacePair {
  std::string key;
  std::string description;
  std::string source;  ///< where the numbers come from, or the assumption they state
  std::vector<FrictionPoint> points;
};

/// The frost-melt regime: a frozen load moved into a warmer zone grows frost that melts into a
/// lubricating film. Inside the danger zone the multiplier falls linearly from 1 at the zone's
/// edges to `min_multiplier` at its centre, and recovers linearly to 1 over `recovery_s` after the
/// temperature change (the reference's model, applied to every surface pair here).
struct FrostMeltPenalty {
  double zone_lo_c = -2.0;
  double zone_hi_c = 8.0;
  double min_multiplier = 0.65;
  double recovery_s = 600.0;

  /// Multiplier in [min_multiplier, 1].
  double multiplier(double temp_c, double seconds_since_change) const;
};

struct FrictionValue {
  double mu_s = 0.0;
  double mu_d = 0.0;
  double penalty = 1.0;  ///< the frost-melt multiplier already applied to mu_s and mu_d
};

/// A point of a chart: steady and effective (penalised) friction at one temperature.
struct FrictionSample {
  double temp_c = 0.0;
  FrictionValue steady;     ///< no penalty
  FrictionValue effective;  ///< with the penalty at the given seconds since the change
};

/// The three contacts of a pallet scene and their friction.
struct ContactFriction {
  std::string belt_pallet_key;  ///< e.g. "wood_pallet/rubber_belt"
  std::string item_pallet_key;  ///< e.g. "carton/wood_pallet"
  std::string item_item_key;    ///< "carton/carton"
  FrictionValue belt_pallet;
  FrictionValue item_pallet;
  FrictionValue item_item;
};

class FrictionModel {
 public:
  /// Reads the reference's table format: {"surface_pairs": {key: {"description", "source"?,
  /// "control_points": [{"temp_c","mu_s","mu_d"}...]}}, "transition_penalty"?: {...}}. Several
  /// documents may be merged: `add` appends pairs (a duplicate key is an error) and takes the
  /// penalty from the first document that has one.
  static Result<FrictionModel> from_json_text(std::string_view text);
  Diagnostics add_json_text(std::string_view text);

  /// resources/friction_table.json (belt pairs, the reference's data) merged with
  /// resources/friction_items.json (item/pallet and item/item pairs, ours), parsed once.
  static const FrictionModel& builtin();

  std::vector<std::string> pair_keys() const;
  const SurfacePair* find(std::string_view key) const;
  const FrostMeltPenalty& penalty() const { return penalty_; }

  /// Steady-state friction (penalty 1), or nullopt for an unknown pair.
  std::optional<FrictionValue> steady(std::string_view key, double temp_c) const;
  /// Steady friction times the frost-melt multiplier.
  std::optional<FrictionValue> effective(std::string_view key, double temp_c,
                                         double seconds_since_change) const;
  /// Samples from t0 to t1 (inclusive, within rounding) every `step` degrees; empty for an
  /// unknown pair or a non-positive step.
  std::vector<FrictionSample> curve(std::string_view key, double t0, double t1, double step,
                                    double seconds_since_change) const;

  /// The friction of a pallet's three contacts at its body temperature and seconds since the
  /// change; an error names the missing pair (e.g. a plastic pallet on steel rollers).
  Result<ContactFriction> for_pallet(const PalletConfig& config) const;

 private:
  std::vector<SurfacePair> pairs_;
  FrostMeltPenalty penalty_;
  bool has_penalty_ = false;
};

}  // namespace pb
