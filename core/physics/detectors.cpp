// SPDX-License-Identifier: MIT
#include "core/physics/detectors.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/contract/pallet_config.hpp"

namespace pb {

namespace {

double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// How far an item has moved in the pallet's frame since rest.
double moved_on_pallet(const Pose& pallet0, const Pose& item0, const Pose& pallet,
                       const Pose& item) {
  return distance(to_frame(pallet, item.pos), to_frame(pallet0, item0.pos));
}

// How far an item has turned out of level relative to the pallet since rest (deg): the pallet's
// up at rest, carried along by the item, as the pallet now sees it.
double turned_out_of_level_deg(const Pose& pallet0, const Pose& item0, const Pose& pallet,
                               const Pose& item) {
  const Vec3 up_in_item = rotate_inverse(item0.quat, rotate(pallet0.quat, Vec3{0.0, 0.0, 1.0}));
  const Vec3 now = rotate_inverse(pallet.quat, rotate(item.quat, up_in_item));
  return std::acos(std::clamp(now[2], -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// Distances between every pair i < j, upper triangle row-major.
std::vector<double> pair_distances(std::span<const Pose> items) {
  std::vector<double> out;
  const std::size_t n = items.size();
  out.reserve(n < 2 ? 0 : n * (n - 1) / 2);
  for (std::size_t i = 0; i < items.size(); ++i) {
    for (std::size_t j = i + 1; j < items.size(); ++j) {
      out.push_back(distance(items[i].pos, items[j].pos));
    }
  }
  return out;
}

// Largest |d_ij - rest_ij| over pairs, with `rest` from pair_distances() of the rest poses.
Measure load_shift(const std::vector<double>& rest, std::span<const Pose> items) {
  Measure out;
  std::size_t k = 0;
  for (std::size_t i = 0; i < items.size(); ++i) {
    for (std::size_t j = i + 1; j < items.size(); ++j, ++k) {
      const double change = std::abs(distance(items[i].pos, items[j].pos) - rest[k]);
      if (change > out.value) out = {change, static_cast<int>(i), static_cast<int>(j)};
    }
  }
  return out;
}

std::string format(const char* pattern, double a, double b = 0.0) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, pattern, a, b);
  return buffer;
}

// The item(s) of a measure, as FailureEvent::items lists them.
std::vector<int> items_of(const Measure& m) {
  std::vector<int> out;
  if (m.a >= 0) out.push_back(m.a);
  if (m.b >= 0) out.push_back(m.b);
  return out;
}

}  // namespace

std::string_view mode_words(FailureMode mode, SlideKind how) {
  switch (mode) {
    case FailureMode::no_failure:
      return "nothing fails in range";
    case FailureMode::tip_over:
      return "the load tips over";
    case FailureMode::top_item_slide:
      switch (how) {
        case SlideKind::item_tipped:
          return "an item tips over";
        case SlideKind::load_as_one:
          return "the load slides on its pallet";
        case SlideKind::item_slid:
          break;
      }
      return "an item slides off";
    case FailureMode::pallet_slip:
      return "the pallet slips on the belt";
    case FailureMode::load_shift:
      return "the load shifts inside";
    case FailureMode::cannot_stand:
      return "the load cannot stand (a build defect)";
  }
  return "an unknown failure";
}

std::string what_moved(const FailureEvent& event) {
  const auto item = [&](std::size_t k) { return std::to_string(event.items[k]); };
  switch (event.mode) {
    case FailureMode::no_failure:
      return "the load stayed within every threshold";
    case FailureMode::tip_over:
      return format("the pallet tilted %.1f deg", event.value);
    case FailureMode::top_item_slide:
      if (event.items.size() != 1) break;
      if (load_slid_as_one(event)) {
        return format("the load moved %.1f cm on the pallet as one (every item at least %.1f cm)",
                      event.value * 100.0, event.least_item_move_m * 100.0);
      }
      return "item " + item(0) + format(" moved %.1f cm on the pallet", event.value * 100.0) +
             (event.item_tilt_deg >= 1.0
                  ? format(", turning %.1f deg out of level", event.item_tilt_deg)
                  : "");
    case FailureMode::load_shift:
      if (event.items.size() != 2) break;
      return "items " + item(0) + " and " + item(1) +
             format(" moved %.1f cm relative to each other", event.value * 100.0);
    case FailureMode::pallet_slip:
      return format("the pallet slipped %.0f cm relative to the belt", event.value * 100.0);
    case FailureMode::cannot_stand:
      return "the load moved with the belt standing still";
  }
  return format("measured %g", event.value);
}

std::string describe(const FailureEvent& event) {
  if (event.mode == FailureMode::no_failure) return "no_failure: " + what_moved(event);
  return std::string(to_string(event.mode)) + format(" at %.3f s: ", event.time_s) +
         what_moved(event);
}

bool load_slid_as_one(const FailureEvent& event) {
  return event.mode == FailureMode::top_item_slide && event.value > 0.0 &&
         event.least_item_move_m >= kLoadAsOne * event.value;
}

bool item_tipped(const FailureEvent& event, const Vec3& item_dims_m) {
  if (event.mode != FailureMode::top_item_slide) return false;
  const double half_diagonal = 0.5 * std::hypot(item_dims_m[0], item_dims_m[1], item_dims_m[2]);
  const double turned = event.item_tilt_deg * std::numbers::pi / 180.0;
  return turned * half_diagonal >= 0.5 * event.value;
}

SlideKind slide_kind(const FailureEvent& event, const PalletConfig& config) {
  if (event.mode != FailureMode::top_item_slide || event.items.size() != 1) {
    return SlideKind::item_slid;
  }
  if (load_slid_as_one(event)) return SlideKind::load_as_one;
  const auto item = static_cast<std::size_t>(event.items[0]);
  if (item < config.items.size() && item_tipped(event, config.items[item].dims_m)) {
    return SlideKind::item_tipped;
  }
  return SlideKind::item_slid;
}

Measure measure_tilt(const Pose& pallet) {
  return {tilt_deg(pallet.quat)};
}

Measure measure_item_slide(const Pose& pallet0, std::span<const Pose> items0, const Pose& pallet,
                           std::span<const Pose> items) {
  Measure out;
  for (std::size_t i = 0; i < items.size() && i < items0.size(); ++i) {
    const double moved = moved_on_pallet(pallet0, items0[i], pallet, items[i]);
    if (moved > out.value) out = {moved, static_cast<int>(i)};
  }
  return out;
}

Measure measure_load_shift(std::span<const Pose> items0, std::span<const Pose> items) {
  return load_shift(pair_distances(items0), items);
}

Measure measure_pallet_slip(const Pose& pallet0, const Pose& pallet, double belt_x, double belt_y) {
  const double pallet_x = pallet.pos[0] - pallet0.pos[0];
  const double pallet_y = pallet.pos[1] - pallet0.pos[1];
  return {std::hypot(belt_x - pallet_x, belt_y - pallet_y)};
}

FailureDetector::FailureDetector(const DetectorThresholds& thresholds, const Pose& pallet0,
                                 std::span<const Pose> items0)
    : thresholds_(thresholds),
      pallet0_(pallet0),
      items0_(items0.begin(), items0.end()),
      rest_distances_(pair_distances(items0)) {}

std::optional<FailureEvent> FailureDetector::update(double t, const Trace::BeltState& belt,
                                                    const Pose& pallet, std::span<const Pose> items,
                                                    DetectorReadings* readings) const {
  struct Candidate {
    FailureMode mode;
    Measure measure;
    double threshold;
  };
  // In FailureMode order: on an exact tie of ratios the earlier entry wins.
  const Candidate candidates[] = {
      {FailureMode::tip_over, measure_tilt(pallet), thresholds_.tip_deg},
      {FailureMode::top_item_slide, measure_item_slide(pallet0_, items0_, pallet, items),
       thresholds_.item_slide_m},
      {FailureMode::pallet_slip, measure_pallet_slip(pallet0_, pallet, belt.x, belt.y),
       thresholds_.pallet_slip_m},
      {FailureMode::load_shift, load_shift(rest_distances_, items), thresholds_.load_shift_m},
  };
  if (readings != nullptr) {
    *readings = {candidates[0].measure.value, candidates[1].measure.value,
                 candidates[2].measure.value, candidates[3].measure.value};
  }
  const Candidate* worst = nullptr;
  double worst_ratio = 0.0;
  for (const Candidate& c : candidates) {
    if (c.measure.value <= c.threshold) continue;
    const double ratio = c.measure.value / c.threshold;
    if (worst == nullptr || ratio > worst_ratio) {
      worst = &c;
      worst_ratio = ratio;
    }
  }
  if (worst == nullptr) return std::nullopt;
  FailureEvent event{worst->mode, t, worst->measure.value, items_of(worst->measure), 0.0};
  if (worst->mode == FailureMode::top_item_slide && worst->measure.a >= 0) {
    const auto i = static_cast<std::size_t>(worst->measure.a);
    event.item_tilt_deg = turned_out_of_level_deg(pallet0_, items0_[i], pallet, items[i]);
    if (items.size() >= 2) {
      double least = event.value;
      for (std::size_t k = 0; k < items.size() && k < items0_.size(); ++k) {
        least = std::min(least, moved_on_pallet(pallet0_, items0_[k], pallet, items[k]));
      }
      event.least_item_move_m = least;
    }
  }
  return event;
}

std::optional<FailureEvent> first_failure(const Trace& trace,
                                          const DetectorThresholds& thresholds) {
  if (trace.empty()) return std::nullopt;
  const FailureDetector detector(thresholds, trace.pallet(0), trace.items(0));
  for (std::size_t f = 1; f < trace.size(); ++f) {
    if (auto event =
            detector.update(trace.time(f), trace.belt(f), trace.pallet(f), trace.items(f))) {
      return event;
    }
  }
  return std::nullopt;
}

}  // namespace pb
