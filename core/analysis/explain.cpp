// SPDX-License-Identifier: MIT
#include "core/analysis/explain.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>

#include "core/base/text.hpp"
#include "core/physics/quasi_static.hpp"

namespace pb {

namespace {

constexpr double kTouch = 0.001;  // the same contact tolerance as the quasi-static bounds

/// "the start-up", "the stop", "the curve", "the pulse", "the step start".
std::string demand_name(const ConveyorProfile& p) {
  switch (p.shape) {
    case ProfileShape::accel_hold:
    case ProfileShape::ramp_decel:
      return "the start-up";
    case ProfileShape::constant:
      return "the step start";
    case ProfileShape::estop:
      return "the stop";
    case ProfileShape::curve:
      return "the curve";
    case ProfileShape::eumos:
      return "the pulse";
  }
  return "the motion";
}

bool lateral(const ConveyorProfile& p) {
  return p.shape == ProfileShape::curve;
}

/// "top item 8" when the item's top is the highest of the load, else "item 8": numbered from 1,
/// as the stack builder shows them (index 7 is item 8).
std::string item_name(const PalletConfig& config, int index) {
  if (index < 0 || index >= static_cast<int>(config.items.size())) {
    return "item " + std::to_string(index + 1);
  }
  double top = 0.0;
  for (const Item& it : config.items) top = std::max(top, it.top_z());
  const bool is_top = config.items[static_cast<std::size_t>(index)].top_z() >= top - kTouch;
  return (is_top ? "top item " : "item ") + std::to_string(index + 1);
}

/// The weakest quasi-static mechanism of `mode` (and `item`, if >= 0; `mechanism`, if given) in
/// the profile's direction.
std::optional<QuasiStaticLimit> weakest_of(const QuasiStaticBounds& bounds, bool across,
                                           FailureMode mode, int item,
                                           std::optional<Mechanism> mechanism = std::nullopt) {
  std::optional<QuasiStaticLimit> best;
  for (const auto& l : across ? bounds.across : bounds.along) {
    if (l.mode != mode || (item >= 0 && l.item != item)) continue;
    if (mechanism && l.mechanism != *mechanism) continue;
    if (!best || l.accel_mps2 < best->accel_mps2) best = l;
  }
  return best;
}

/// "the start-up's 0.41 g" or "the step start" when the demand is unknown.
std::string demand_phrase(const ConveyorProfile& p, double demand) {
  if (!(demand > 0.0)) return demand_name(p);
  return demand_name(p) + "'s " + fixed(demand / kGravity, 2) + " g";
}

}  // namespace

Grade grade(const SafetyResult& r) {
  if (r.dominant_failure_mode == FailureMode::cannot_stand) {
    return {'R', "Build defect: re-stack",
            "It cannot stand even on a still belt; re-stack it before anything else. No conveyor "
            "limit applies."};
  }
  if (r.verdict == Verdict::reject) {
    return {'R', "Reject and re-wrap",
            "No motion is safe: re-stack or re-wrap before it enters the conveyor."};
  }
  const double speed_ratio = r.max_speed_mps / kTableSpeedMps;
  const double accel_ratio = r.max_accel_mps2 / kTableAccelMps2;
  const double worst = std::min(speed_ratio, accel_ratio);
  if (worst >= 1.5) {
    return {'A', "Faster than the table",
            "Safe at " + fixed_floor(r.max_speed_mps, 2) +
                " m/s: it can run faster than the fixed " + fixed(kTableSpeedMps, 1) + " m/s."};
  }
  if (worst >= 1.0) {
    return {'B', "Table speed",
            "Runs at the standard " + fixed(kTableSpeedMps, 1) + " m/s and " +
                fixed(kTableAccelMps2, 1) + " m/s² start-up."};
  }
  return {'C', "Slow zone",
          "Keep it below " + fixed_floor(r.max_speed_mps, 2) + " m/s and " +
              fixed_floor(r.max_accel_mps2, 2) + " m/s² start-up: slower than the table."};
}

double peak_demand_mps2(const ConveyorProfile& p) {
  switch (p.shape) {
    case ProfileShape::accel_hold:
    case ProfileShape::ramp_decel:
      return p.accel_mps2;
    case ProfileShape::constant:
      return 0.0;
    case ProfileShape::estop:
      return p.decel_mps2;
    case ProfileShape::curve:
      return p.lateral_accel_mps2();
    case ProfileShape::eumos:
      return p.eumos_g * kGravity;
  }
  return 0.0;
}

std::string format_temperature(double t) {
  const std::string digits = fixed(std::abs(t), 0);
  const bool negative = t < 0.0 && digits != "0";
  return (negative ? "\u2212" : "") + digits + " \u00b0C";
}

std::string explain_failure(const PalletConfig& config, const ConveyorProfile& profile,
                            const FailureEvent& event, const FrictionModel& model) {
  const auto friction = model.for_pallet(config);
  if (!friction || event.mode == FailureMode::no_failure) return describe(event);
  const ContactFriction& cf = *friction;
  const QuasiStaticBounds bounds = quasi_static_bounds(config, cf);
  const double demand = peak_demand_mps2(profile);
  const bool across = lateral(profile);
  const std::string at = " at " + format_temperature(config.body_temp_c);
  const std::string when = " (" + fixed(event.time_s, 2) + " s)";
  const std::string penalty =
      cf.belt_pallet.penalty < 1.0
          ? ", frost-melt film: " + fixed(100.0 * (1.0 - cf.belt_pallet.penalty), 0) + " % off"
          : "";

  // A curve turns the load: a mass off the centre line rides at its own radius, where the demand
  // is curve_demand_factor times the centre line's (turning_frame.hpp).
  auto felt = [&](const std::optional<QuasiStaticLimit>& m) {
    return across && m ? demand * curve_demand_factor(*m, profile.curve_radius_m) : demand;
  };
  auto phrase = [&](double local) {
    std::string s = demand_phrase(profile, demand);
    if (demand > 0.0 && std::abs(local - demand) > 0.005 * demand) {
      s += " (" + fixed(local / kGravity, 2) + " g where it rides: the curve turns the load)";
    }
    return s;
  };

  switch (event.mode) {
    case FailureMode::pallet_slip: {
      const double local = felt(weakest_of(bounds, across, FailureMode::pallet_slip, -1));
      return "The pallet slipped on the belt" + when + ": " + phrase(local) + " needs μ " +
             fixed(local / kGravity, 2) + ", " + cf.belt_pallet_key + " has " +
             fixed(cf.belt_pallet.mu_s, 2) + at + penalty + ".";
    }
    case FailureMode::tip_over: {
      const auto tip = weakest_of(bounds, across, FailureMode::tip_over, -1);
      std::string s = "The load tipped over" + when + ": " + phrase(felt(tip));
      if (tip) {
        s += (demand > 0.0 ? " is more than the " : " beat the ") +
             fixed(tip->accel_mps2 / kGravity, 2) +
             " g its centre of mass allows (half the base over the height)";
      }
      return s + "; lower the load or run gentler.";
    }
    case FailureMode::top_item_slide: {
      const int item = event.items.empty() ? -1 : event.items.front();
      std::string name = item_name(config, item);
      name[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(name[0])));
      const std::string moved = " slid " + fixed(100.0 * event.value, 1) + " cm" + when;
      if (config.wrap != WrapType::none) {
        return name + moved + ": " + demand_phrase(profile, demand) + " is more than the " +
               std::string(to_string(config.wrap)) + " wrap holds; band it or run gentler.";
      }
      if (load_slid_as_one(event)) {  // every carton with it: they left a pallet that held
        const double local = felt(weakest_of(bounds, across, FailureMode::top_item_slide, -1,
                                             Mechanism::item_slip_on_deck));
        std::string s = "The whole load slid " + fixed(100.0 * event.value, 1) +
                        " cm on its pallet" + when + ": ";
        if (demand > 0.0) s += phrase(local) + " needs μ " + fixed(local / kGravity, 2) + ", ";
        const double deck = cf.item_pallet.mu_s, belt = cf.belt_pallet.mu_s;
        const int digits = fixed(deck, 2) == fixed(belt, 2) ? 3 : 2;  // h4022: 0.287 vs 0.289
        s += cf.item_pallet_key + " has " + fixed(deck, digits) + at;
        if (deck < belt) {
          s += ", less than the " + fixed(belt, digits) +
               " by which the pallet holds to its belt, so the load goes first";
        }
        return s + "; wrap the load to its pallet or lay an anti-slip sheet under it.";
      }
      bool on_deck = false;
      if (item >= 0 && item < static_cast<int>(config.items.size())) {
        on_deck = std::abs(config.items[static_cast<std::size_t>(item)].position[2] -
                           config.base_dims_m[2]) <= kTouch;
      }
      const std::string key = on_deck ? cf.item_pallet_key : cf.item_item_key;
      const double has = on_deck ? cf.item_pallet.mu_s : cf.item_item.mu_s;
      // How it went, as measured: tipped over an edge (item_tipped) or slid flat. A tip quotes
      // the quasi-static onset of its stack tipping (geometry), a slide its friction.
      const bool tipped = item >= 0 && item < static_cast<int>(config.items.size()) &&
                          item_tipped(event, config.items[static_cast<std::size_t>(item)].dims_m);
      if (tipped) {
        const auto tip =
            weakest_of(bounds, across, FailureMode::top_item_slide, item, Mechanism::stack_tip);
        std::string s = name + " tipped over" + when + ", turning " +
                        fixed(event.item_tilt_deg, 1) + " deg and moving " +
                        fixed(100.0 * event.value, 1) + " cm: " + phrase(felt(tip));
        s += tip ? " is more than the " + fixed(tip->accel_mps2 / kGravity, 2) +
                       " g its footprint holds"
                 : " rocked it over an edge";
        return s + "; restack it lower or wider.";
      }
      const double local =
          felt(weakest_of(bounds, across, FailureMode::top_item_slide, item,
                          on_deck ? Mechanism::item_slip_on_deck : Mechanism::item_slip_on_item));
      std::string s = name + moved + ": ";
      if (demand > 0.0) {
        s += phrase(local) + " needs μ " + fixed(local / kGravity, 2) + ", ";
      }
      s += key + " has " + fixed(has, 2) + at;
      if (demand > 0.0 && local / kGravity <= has) {
        s += " (friction alone would hold: the load's own jolt moved it)";
      }
      return s + ".";
    }
    case FailureMode::load_shift: {
      std::string who = "the load";
      if (event.items.size() == 2) {
        who = "items " + std::to_string(event.items[0] + 1) + " and " +
              std::to_string(event.items[1] + 1);
      }
      return "The load shifted inside" + when + ": " + who + " moved " +
             fixed(100.0 * event.value, 1) + " cm apart under " + demand_phrase(profile, demand) +
             "; re-stack interlocked (brick or pinwheel) or wrap it.";
    }
    case FailureMode::cannot_stand:
    case FailureMode::no_failure:
      break;
  }
  return describe(event);
}

}  // namespace pb
