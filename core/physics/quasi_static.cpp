// SPDX-License-Identifier: MIT
#include "core/physics/quasi_static.hpp"
#include "core/base/text.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/contract/pallet_metrics.hpp"

namespace pb {

namespace {

constexpr double kTouch = kSupportTolerance_m;

QuasiStaticLimit weakest(const std::vector<QuasiStaticLimit>& limits) {
  if (limits.empty()) return {};
  return *std::min_element(limits.begin(), limits.end(), [](const auto& a, const auto& b) {
    return a.accel_mps2 < b.accel_mps2;
  });
}

// How far a point (x, y) may move along the unit direction (ux, uy) before it leaves the item's
// yawed footprint (0 when it is already beyond an edge it moves towards). The line of action of
// gravity and the inertial force leaves the footprint there, so a stack standing on the item tips
// about that edge. A yawed footprint's bounding box overstates it: a 0.4 x 0.2 m carton at 60 deg
// reaches 0.187 m along X but its edge is 0.115 m from its centre that way.
double exit_distance(const Item& item, double x, double y, double ux, double uy) {
  const double yaw = item.orientation_deg * std::numbers::pi / 180.0;
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double qx = x - item.position[0], qy = y - item.position[1];
  double t = std::numeric_limits<double>::infinity();
  // The footprint's own axes: e1 = (c, s) with half-width dims[0] / 2, e2 = (-s, c) with dims[1]
  // / 2.
  for (const auto& [ex, ey, half] : {std::array<double, 3>{c, s, 0.5 * item.dims_m[0]},
                                     std::array<double, 3>{-s, c, 0.5 * item.dims_m[1]}}) {
    const double q = ex * qx + ey * qy, u = ex * ux + ey * uy;
    // An edge parallel to the direction is never crossed (per axis, as for an unyawed footprint).
    if (std::abs(u) > 1e-12) t = std::min(t, ((u > 0.0 ? half : -half) - q) / u);
  }
  return std::max(0.0, t);
}

}  // namespace

double belt_onset_mps2(const std::vector<QuasiStaticLimit>& mechanisms) {
  for (const QuasiStaticLimit& m : mechanisms) {
    if (m.mechanism == Mechanism::pallet_slip) return m.accel_mps2;
  }
  return 0.0;
}

QuasiStaticLimit QuasiStaticBounds::weakest_along() const {
  return weakest(along);
}
QuasiStaticLimit QuasiStaticBounds::weakest_across() const {
  return weakest(across);
}
bool QuasiStaticBounds::one_body() const {
  return std::all_of(along.begin(), along.end(), of_the_whole_load) &&
         std::all_of(across.begin(), across.end(), of_the_whole_load);
}

double curve_demand_factor(const QuasiStaticLimit& m, double radius_m) {
  if (!(radius_m > 0.0)) return 1.0;
  const double lateral = 1.0 + std::abs(m.offset_y_m) / radius_m;
  const bool tip = m.mechanism == Mechanism::load_tip || m.mechanism == Mechanism::stack_tip;
  return tip ? lateral : std::hypot(lateral, m.offset_x_m / radius_m);
}

QuasiStaticBounds quasi_static_bounds(const PalletConfig& config, const ContactFriction& friction) {
  QuasiStaticBounds out;
  const double g = kGravity;
  const double mu_belt = friction.belt_pallet.mu_s;
  const Vec3 com = composite_com_m(config);
  for (auto* list : {&out.along, &out.across}) {
    list->push_back({mu_belt * g, FailureMode::pallet_slip, Mechanism::pallet_slip,
                     "the pallet slips on the belt (mu " + fixed(mu_belt, 2) + ")", -1,
                     std::min(friction.belt_pallet.mu_d, mu_belt) * g, com[0], com[1]});
  }
  // The whole load over the pallet's edge (the pallet's bottom is the pivot).
  if (com[2] > 0.0) {
    out.along.push_back({g * (config.base_dims_m[0] / 2 - std::abs(com[0])) / com[2],
                         FailureMode::tip_over, Mechanism::load_tip,
                         "the loaded pallet tips over its edge", -1, 0.0, com[0], com[1]});
    out.across.push_back({g * (config.base_dims_m[1] / 2 - std::abs(com[1])) / com[2],
                          FailureMode::tip_over, Mechanism::load_tip,
                          "the loaded pallet tips over its edge", -1, 0.0, com[0], com[1]});
  }
  if (config.wrap != WrapType::none) return out;

  const auto& items = config.items;
  const std::size_t n = items.size();
  const double deck = config.base_dims_m[2];
  // carries[i]: items resting directly on item i.
  std::vector<std::vector<std::size_t>> carries(n);
  const auto below = resting_on(config);
  for (std::size_t j = 0; j < n; ++j) {
    for (std::size_t i : below[j]) carries[i].push_back(j);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Item& item = items[i];
    const bool on_deck = std::abs(item.position[2] - deck) <= kTouch;
    const double mu = on_deck ? friction.item_pallet.mu_s : friction.item_item.mu_s;
    const double mu_d = std::min(mu, on_deck ? friction.item_pallet.mu_d : friction.item_item.mu_d);
    const std::string name = "item " + std::to_string(i);
    // The sub-stack item i carries tips over item i's bottom edge: i and whatever rests on it
    // alone, directly or not. An item that also rests on something outside (a brick bridging two
    // cartons) is held there and does not go over with i: counted in, a bricked layer made the
    // whole slab above an end carton one body leaning on it (a 0.19 m/s^2 onset for 48 dairy
    // cases that stand to 3.1 m/s^2), and every search of such a load walked up from near zero.
    std::vector<bool> in(n, false);
    in[i] = true;
    std::vector<std::size_t> members{i};
    for (bool grew = true; grew;) {  // until no item rests on the sub-stack alone
      grew = false;
      for (std::size_t m = 0; m < members.size(); ++m) {
        for (std::size_t j : carries[members[m]]) {
          if (in[j] || !std::all_of(below[j].begin(), below[j].end(),
                                    [&](std::size_t b) { return in[b]; })) {
            continue;
          }
          in[j] = true;
          members.push_back(j);
          grew = true;
        }
      }
    }
    double mass = 0.0, moment_x = 0.0, moment_y = 0.0, moment_z = 0.0;
    for (std::size_t k : members) {
      const Vec3 c = items[k].center_of_mass();
      mass += items[k].weight_kg;
      moment_x += items[k].weight_kg * c[0];
      moment_y += items[k].weight_kg * c[1];
      moment_z += items[k].weight_kg * c[2];
    }
    const double h = moment_z / mass - item.position[2];
    const double cx = moment_x / mass, cy = moment_y / mass;
    // Item i's friction holds the sub-stack: its slip moves that mass too.
    for (auto* list : {&out.along, &out.across}) {
      list->push_back({mu * g, FailureMode::top_item_slide,
                       on_deck ? Mechanism::item_slip_on_deck : Mechanism::item_slip_on_item,
                       name + " slips on " + (on_deck ? "the deck" : "the item below") + " (mu " +
                           fixed(mu, 2) + ")",
                       static_cast<int>(i), mu_d * g, cx, cy});
    }
    // Either way along the plane (a start-up and a stop, a left and a right turn): the nearer edge.
    const double along =
        std::min(exit_distance(item, cx, cy, 1.0, 0.0), exit_distance(item, cx, cy, -1.0, 0.0));
    const double across =
        std::min(exit_distance(item, cx, cy, 0.0, 1.0), exit_distance(item, cx, cy, 0.0, -1.0));
    const std::string what = "the stack from " + name + " up tips over its edge";
    out.along.push_back({g * along / h, FailureMode::top_item_slide, Mechanism::stack_tip, what,
                         static_cast<int>(i), 0.0, cx, cy});
    out.across.push_back({g * across / h, FailureMode::top_item_slide, Mechanism::stack_tip, what,
                          static_cast<int>(i), 0.0, cx, cy});
  }
  return out;
}

double breakaway_slide_m(double onset, double sliding, double a, double duration_s,
                         double break_loose_m) {
  if (a <= onset) return 0.0;
  if (sliding <= 0.0) return 1e9;
  // On the static cone, lagging at a - onset, until it has slipped break_loose_m or the push ends.
  const double lag_static = a - onset;
  const double t_static = std::min(std::sqrt(2.0 * break_loose_m / lag_static), duration_s);
  double slip = 0.5 * lag_static * t_static * t_static, lag = lag_static * t_static;
  if (t_static < duration_s) {  // loose within the push: lags at a - sliding to its end
    const double t = duration_s - t_static, lag_kinetic = a - sliding;
    slip += lag * t + 0.5 * lag_kinetic * t * t;
    lag += lag_kinetic * t;
    return slip + lag * lag / (2.0 * sliding);
  }
  // Held through the push: catches up at the onset, and at `sliding` once it has slipped
  // break_loose_m.
  const double room = 2.0 * onset * (break_loose_m - slip);
  if (lag * lag <= room) return slip + lag * lag / (2.0 * onset);
  return break_loose_m + (lag * lag - room) / (2.0 * sliding);
}

double breakaway_slide_speed_mps(double onset, double sliding, double decel, double distance,
                                 double break_loose_m) {
  if (decel <= onset || sliding <= 0.0) return 1e9;
  auto slide = [&](double v) {
    return breakaway_slide_m(onset, sliding, decel, v / decel, break_loose_m);
  };
  double lo = 0.0, hi = 1.0;
  while (slide(hi) < distance && hi < 1e9) hi *= 2.0;
  if (slide(hi) < distance) return 1e9;
  for (int i = 0; i < 100 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (slide(mid) < distance ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace pb
