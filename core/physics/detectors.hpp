// SPDX-License-Identifier: MIT
// The four ways a pallet fails on a conveyor, detected on poses relative to the rest state.
// The same detector runs online inside a simulation (fail-fast) and over a recorded Trace.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/enums.hpp"
#include "core/base/pose.hpp"
#include "core/physics/trace.hpp"

namespace pb {

struct PalletConfig;

struct DetectorThresholds {
  double tip_deg = 8.0;         ///< pallet tilt off vertical
  double item_slide_m = 0.05;   ///< any item's displacement in the pallet frame
  double load_shift_m = 0.02;   ///< largest change of an item-to-item distance
  double pallet_slip_m = 0.30;  ///< belt travel minus pallet travel (horizontal)

  bool operator==(const DetectorThresholds&) const = default;
};

struct FailureEvent {
  FailureMode mode = FailureMode::no_failure;
  double time_s = 0.0;
  double value = 0.0;      ///< the measured quantity (deg or m) when it crossed the threshold
  std::vector<int> items;  ///< the item(s) involved: one for a slide, two for a shift, none else
  /// top_item_slide: how far the item had turned out of level relative to the pallet since rest
  /// (deg), which tells a carton that tipped from one that slid flat (item_tipped).
  double item_tilt_deg = 0.0;
  /// top_item_slide of a load of two or more items: the least any item had moved on the pallet
  /// (m), which tells a load that slid on its pallet as one from an item that left it
  /// (load_slid_as_one). 0 for a single item.
  double least_item_move_m = 0.0;
  /// A pallet slip decided before it crossed its threshold, at `time_s`, when the slide could no
  /// longer stop short of it (SimOptions::project_pallet_slip); `value` is then the threshold.
  bool projected = false;

  bool operator==(const FailureEvent&) const = default;
};

/// A failure mode in a supervisor's words ("the load tips over", "an item slides off"), never an
/// identifier: what every panel and every sentence meant for a person says. For a
/// top_item_slide, `how` says how it went (slide_kind below): "an item tips over", "the load
/// slides on its pallet".
std::string_view mode_words(FailureMode mode, SlideKind how = SlideKind::item_slid);

/// Whether a top_item_slide's item tipped rather than slid: its turn out of level, times half its
/// diagonal (the farthest its centre can sit from the edge it pivots on), accounts for at least
/// half of how far its centre moved. A carton sliding flat turns a degree or two; one tipping
/// over an edge moves its centre mostly by turning (a 0.2 x 0.2 x 1 m carton: 5.6 deg at 5 cm).
/// The detectors' contract keeps the mode (the reference's tip_over is the pallet's tilt); this
/// is how it is told.
bool item_tipped(const FailureEvent& event, const Vec3& item_dims_m);

/// Whether a top_item_slide was the whole load sliding on its pallet as one: every item moved at
/// least kLoadAsOne of the farthest's move. Cartons that grip their pallet less than the pallet
/// grips its belt (h4022 in docs/studies/unwrapped-holdout-2) slide off a pallet that holds, all
/// together; the remedy is what holds the load to its pallet (a wrap, an anti-slip sheet), not a
/// restack. A column tipping as one is not: its bottom carton moves a fraction of its top's.
inline constexpr double kLoadAsOne = 0.7;
bool load_slid_as_one(const FailureEvent& event);

/// How a failure event's top_item_slide went on `config`'s load: load_as_one (load_slid_as_one),
/// item_tipped (item_tipped, with its item's dimensions) or item_slid; item_slid for any other
/// mode.
SlideKind slide_kind(const FailureEvent& event, const PalletConfig& config);

/// What a failure event measured, without its mode or time: "item 7 moved 5.1 cm on the pallet".
std::string what_moved(const FailureEvent& event);

/// One line for a person: "top_item_slide at 0.412 s: item 7 moved 5.1 cm on the pallet".
std::string describe(const FailureEvent& event);

// Each detector on its own, for tests and plots. They return the measured value and, where it
// applies, the item(s) that produced it.
struct Measure {
  double value = 0.0;
  int a = -1;
  int b = -1;
};
/// Tilt of the pallet off vertical (deg).
Measure measure_tilt(const Pose& pallet);
/// Largest displacement of an item in the pallet frame since rest (m); `a` = the item.
Measure measure_item_slide(const Pose& pallet0, std::span<const Pose> items0, const Pose& pallet,
                           std::span<const Pose> items);
/// Largest |d_ij(t) - d_ij(rest)| over item pairs (m); `a`, `b` = the pair.
Measure measure_load_shift(std::span<const Pose> items0, std::span<const Pose> items);
/// Horizontal distance between belt travel and pallet travel since rest (m).
Measure measure_pallet_slip(const Pose& pallet0, const Pose& pallet, double belt_x, double belt_y);

/// What each detector measured in one frame (update's out-parameter).
struct DetectorReadings {
  double tilt_deg = 0.0;
  double item_slide_m = 0.0;
  double pallet_slip_m = 0.0;
  double load_shift_m = 0.0;
};

/// The online detector: baselines are the rest state; update() returns the first failure, at the
/// first frame any threshold is crossed (value > threshold). When several cross in the same frame,
/// the one furthest past its threshold (relative to the threshold) wins.
class FailureDetector {
 public:
  FailureDetector(const DetectorThresholds& thresholds, const Pose& pallet0,
                  std::span<const Pose> items0);

  std::optional<FailureEvent> update(double t, const Trace::BeltState& belt, const Pose& pallet,
                                     std::span<const Pose> items,
                                     DetectorReadings* readings = nullptr) const;

  const DetectorThresholds& thresholds() const { return thresholds_; }

 private:
  DetectorThresholds thresholds_;
  Pose pallet0_;
  std::vector<Pose> items0_;
  std::vector<double> rest_distances_;  ///< upper triangle, row-major
};

/// Runs the detector over a trace whose first frame is the rest state; nullopt if nothing fails.
std::optional<FailureEvent> first_failure(const Trace& trace, const DetectorThresholds& thresholds);

}  // namespace pb
