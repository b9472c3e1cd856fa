// SPDX-License-Identifier: MIT
#include "core/contract/conveyor_profile.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/base/text.hpp"
#include "core/contract/json_reader.hpp"

namespace pb {

namespace {

constexpr double kGravity = 9.81;
constexpr double kEumosRise = 0.05;  // s to reach the test acceleration

double curve_duration(const ConveyorProfile& p) {
  if (p.target_speed_mps <= 0.0) return 0.0;
  return p.curve_radius_m * p.curve_angle_deg * std::numbers::pi / 180.0 / p.target_speed_mps;
}

}  // namespace

double ConveyorProfile::initial_speed_mps() const {
  return (shape == ProfileShape::estop || shape == ProfileShape::curve) ? target_speed_mps : 0.0;
}

double ConveyorProfile::lateral_accel_mps2() const {
  return shape == ProfileShape::curve ? target_speed_mps * target_speed_mps / curve_radius_m : 0.0;
}

double ConveyorProfile::velocity_at(double t) const {
  switch (shape) {
    case ProfileShape::constant:
      return t <= 0.0 ? 0.0 : target_speed_mps;
    case ProfileShape::estop:
      if (t < decel_start_s) return target_speed_mps;
      return std::max(0.0, target_speed_mps - decel_mps2 * (t - decel_start_s));
    case ProfileShape::curve:
      return target_speed_mps;
    case ProfileShape::eumos: {
      const double a = eumos_g * kGravity;
      const double jerk = a / kEumosRise;
      if (t <= 0.0) return 0.0;
      if (t < kEumosRise) return 0.5 * jerk * t * t;
      const double v_rise = 0.5 * a * kEumosRise;
      return v_rise + a * (std::min(t, kEumosRise + eumos_hold_s) - kEumosRise);
    }
    case ProfileShape::accel_hold:
    case ProfileShape::ramp_decel:
      break;
  }
  if (t <= 0.0) return 0.0;
  const double ramp_up = target_speed_mps / std::max(accel_mps2, 1e-9);
  double v = t < ramp_up ? accel_mps2 * t : target_speed_mps;
  if (shape == ProfileShape::ramp_decel && t >= decel_start_s) {
    v = std::min(v, std::max(0.0, target_speed_mps - accel_mps2 * (t - decel_start_s)));
  }
  return v;
}

double ConveyorProfile::lateral_velocity_at(double t) const {
  if (shape != ProfileShape::curve) return 0.0;
  const double s = std::clamp(t - curve_start_s, 0.0, curve_duration(*this));
  return (curve_turn == CurveTurn::left ? 1.0 : -1.0) * lateral_accel_mps2() * s;
}

double ConveyorProfile::yaw_rate_at(double t) const {
  if (shape != ProfileShape::curve || curve_radius_m <= 0.0) return 0.0;
  if (t < curve_start_s || t >= curve_start_s + curve_duration(*this)) return 0.0;
  return (curve_turn == CurveTurn::left ? 1.0 : -1.0) * target_speed_mps / curve_radius_m;
}

namespace {

// Every time the commanded acceleration changes, whether or not the run reaches it.
std::vector<double> changes(const ConveyorProfile& p) {
  const double ramp_up = p.target_speed_mps / std::max(p.accel_mps2, 1e-9);
  switch (p.shape) {
    case ProfileShape::accel_hold:
      return {ramp_up};
    case ProfileShape::constant:
      return {};
    case ProfileShape::ramp_decel:
      // A decel that starts before the ramp ends meets it halfway: the belt peaks there.
      return p.decel_start_s >= ramp_up
                 ? std::vector<double>{ramp_up, p.decel_start_s, p.decel_start_s + ramp_up}
                 : std::vector<double>{0.5 * (ramp_up + p.decel_start_s),
                                       p.decel_start_s + ramp_up};
    case ProfileShape::estop:
      return {p.decel_start_s, p.decel_start_s + p.target_speed_mps / std::max(p.decel_mps2, 1e-9)};
    case ProfileShape::curve:
      return {p.curve_start_s, p.curve_start_s + curve_duration(p)};
    case ProfileShape::eumos:
      return {kEumosRise, kEumosRise + p.eumos_hold_s};
  }
  return {};
}

}  // namespace

double ConveyorProfile::motion_end_s() const {
  const std::vector<double> all = changes(*this);
  return all.empty() ? 0.0 : std::max(0.0, *std::max_element(all.begin(), all.end()));
}

double default_duration_s(const ConveyorProfile& profile) {
  return std::min(kMaxProfileDurationS, std::max(5.0, profile.motion_end_s() + 1.0));
}

std::vector<double> ConveyorProfile::breakpoints() const {
  std::vector<double> out = changes(*this);
  std::erase_if(out, [&](double b) { return !(b > 0.0 && b < duration_s); });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

namespace {

void check_range(Diagnostics& out, const std::string& pointer, double value, double lo,
                 bool lo_open, double hi, const char* unit) {
  const bool bad = !std::isfinite(value) || (lo_open ? value <= lo : value < lo) || value > hi;
  if (!bad) return;
  const std::string allowed = std::string("a number in ") + (lo_open ? "(" : "[") +
                              short_number(lo) + ", " + short_number(hi) + "] " + unit;
  out.push_back(
      {pointer,
       wording::out_of_range(std::isfinite(value) ? short_number(value) : "not finite", allowed),
       Severity::error});
}

}  // namespace

Diagnostics validate_profile(const ConveyorProfile& p, const std::string& prefix) {
  Diagnostics out;
  check_range(out, prefix + "/target_speed_mps", p.target_speed_mps, 0.0, false, 5.0, "m/s");
  check_range(out, prefix + "/accel_mps2", p.accel_mps2, 0.0, true, 10.0, "m/s^2");
  check_range(out, prefix + "/duration_s", p.duration_s, 0.0, true, kMaxProfileDurationS, "s");
  check_range(out, prefix + "/decel_start_s", p.decel_start_s, 0.0, false, 30.0, "s");
  check_range(out, prefix + "/decel_mps2", p.decel_mps2, 0.0, true, 20.0, "m/s^2");
  check_range(out, prefix + "/curve_radius_m", p.curve_radius_m, 0.0, true, 1000.0, "m");
  check_range(out, prefix + "/curve_angle_deg", p.curve_angle_deg, 0.0, true, 360.0, "deg");
  check_range(out, prefix + "/curve_start_s", p.curve_start_s, 0.0, false, 30.0, "s");
  check_range(out, prefix + "/eumos_g", p.eumos_g, 0.0, true, 2.0, "g");
  check_range(out, prefix + "/eumos_hold_s", p.eumos_hold_s, 0.3, false, 10.0, "s");
  if (const double end = p.motion_end_s(); !has_errors(out) && end >= p.duration_s) {
    out.push_back(
        {prefix + "/duration_s",
         "the belt is still changing its motion when the run ends at " + fixed(p.duration_s, 2) +
             " s (its last change is at " + fixed(end, 2) +
             " s), so what follows is not simulated; " +
             (end < kMaxProfileDurationS ? std::string("make duration_s longer than that")
                                         : "a run is at most " + fixed(kMaxProfileDurationS, 0) +
                                               " s, so choose a motion that ends within it"),
         Severity::warning});
  }
  return out;
}

}  // namespace pb
