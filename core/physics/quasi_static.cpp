// SPDX-License-Identifier: MIT
#include "core/physics/quasi_static.hpp"
#include "core/base/text.hpp"

#include <algorithm>
#include <cmath>
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

// Half-extents of an item's yawed footprint along X and Y.
std::array<double, 2> half_extents(const Item& item) {
  const double yaw = item.orientation_deg * std::numbers::pi / 180.0;
  const double c = std::abs(std::cos(yaw)), s = std::abs(std::sin(yaw));
  return {0.5 * (c * item.dims_m[0] + s * item.dims_m[1]),
          0.5 * (s * item.dims_m[0] + c * item.dims_m[1])};
}

}  // namespace

QuasiStaticLimit QuasiStaticBounds::weakest_along() const {
  return weakest(along);
}
QuasiStaticLimit QuasiStaticBounds::weakest_across() const {
  return weakest(across);
}
bool QuasiStaticBounds::one_body() const {
  auto whole = [](const QuasiStaticLimit& m) {
    return m.mechanism == Mechanism::pallet_slip || m.mechanism == Mechanism::load_tip;
  };
  return std::all_of(along.begin(), along.end(), whole) &&
         std::all_of(across.begin(), across.end(), whole);
}

QuasiStaticBounds quasi_static_bounds(const PalletConfig& config, const ContactFriction& friction) {
  QuasiStaticBounds out;
  const double g = kGravity;
  const double mu_belt = friction.belt_pallet.mu_s;
  for (auto* list : {&out.along, &out.across}) {
    list->push_back({mu_belt * g, FailureMode::pallet_slip, Mechanism::pallet_slip,
                     "the pallet slips on the belt (mu " + fixed(mu_belt, 2) + ")", -1});
  }
  // The whole load over the pallet's edge (the pallet's bottom is the pivot).
  const Vec3 com = composite_com_m(config);
  if (com[2] > 0.0) {
    out.along.push_back({g * (config.base_dims_m[0] / 2 - std::abs(com[0])) / com[2],
                         FailureMode::tip_over, Mechanism::load_tip,
                         "the loaded pallet tips over its edge", -1});
    out.across.push_back({g * (config.base_dims_m[1] / 2 - std::abs(com[1])) / com[2],
                          FailureMode::tip_over, Mechanism::load_tip,
                          "the loaded pallet tips over its edge", -1});
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
    const std::string name = "item " + std::to_string(i);
    for (auto* list : {&out.along, &out.across}) {
      list->push_back({mu * g, FailureMode::top_item_slide,
                       on_deck ? Mechanism::item_slip_on_deck : Mechanism::item_slip_on_item,
                       name + " slips on " + (on_deck ? "the deck" : "the item below") + " (mu " +
                           fixed(mu, 2) + ")",
                       static_cast<int>(i)});
    }
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
    const auto half = half_extents(item);
    const double off_x = std::abs(moment_x / mass - item.position[0]);
    const double off_y = std::abs(moment_y / mass - item.position[1]);
    const std::string what = "the stack from " + name + " up tips over its edge";
    out.along.push_back({g * std::max(0.0, half[0] - off_x) / h, FailureMode::top_item_slide,
                         Mechanism::stack_tip, what, static_cast<int>(i)});
    out.across.push_back({g * std::max(0.0, half[1] - off_y) / h, FailureMode::top_item_slide,
                          Mechanism::stack_tip, what, static_cast<int>(i)});
  }
  return out;
}

}  // namespace pb
