// SPDX-License-Identifier: MIT
#include "core/analysis/fidelity.hpp"

#include <algorithm>

#include "core/base/text.hpp"
#include "core/physics/clustering.hpp"
#include "core/physics/quasi_static.hpp"
#include "core/physics/wrap.hpp"

namespace pb {

double load_reach_mps2(const PalletConfig& config, const ContactFriction& friction,
                       double ceiling_mps2, double curve_radius_m) {
  double curve = 1.0;  // the most a curve demands of an item over the centre line's v^2 / r
  for (const Item& item : config.items) {
    QuasiStaticLimit slip;  // a slip of the item where it stands
    slip.mechanism = Mechanism::item_slip_on_deck;
    slip.offset_x_m = item.position[0];
    slip.offset_y_m = item.position[1];
    curve = std::max(curve, curve_demand_factor(slip, curve_radius_m));
  }
  return std::min(ceiling_mps2, kBeltSlipOvershoot * friction.belt_pallet.mu_s * kGravity * curve);
}

FidelityChoice choose_fidelity(const PalletConfig& config, const ContactFriction& friction,
                               double max_accel_mps2, const DetectorThresholds& thresholds,
                               Fidelity requested) {
  const WrapStiffness wrap = wrap_stiffness(config.wrap);
  if (requested == Fidelity::closed_form) return {requested, "requested", {}};
  if (requested == Fidelity::full) return {requested, "requested", {}};
  if (config.items.empty()) return {Fidelity::full, "no items", {}};
  if (wrap.stiffness_n_per_m <= 0.0) {
    const Clustering c = cluster_items(config, friction, max_accel_mps2, kClusterMargin);
    const int n = static_cast<int>(config.items.size()), free = c.free_count();
    const std::string against = fixed(kClusterMargin, 2) + " x the " + fixed(c.reach_mps2, 2) +
                                " m/s^2 that can reach the load";
    // Automatically only as one rigid body: a load of free and merged items is not measured.
    if (free == n || (free > 0 && requested != Fidelity::clustered)) {
      return {Fidelity::full, "unwrapped: an item can slide or tip below " + against, {}};
    }
    if (free == 0) {
      return {Fidelity::clustered,
              "unwrapped, one rigid body: no item can slide or tip below " + against +
                  " (its pallet slips on the belt first)",
              c.carrier};
    }
    return {Fidelity::clustered,
            std::to_string(n - free) + " of " + std::to_string(n) +
                " items cannot slide or tip below " + against +
                ": merged into what carries them; " + std::to_string(free) + " free",
            c.carrier};
  }
  if (requested == Fidelity::clustered)
    return {Fidelity::full, "wrapped: its welds hold the items", {}};
  if (requested == Fidelity::reduced) return {requested, "requested", {}};
  double heaviest = 0.0;
  for (const auto& item : config.items) heaviest = std::max(heaviest, item.weight_kg);
  // The load cannot be pushed harder than the pallet's slip onset; friction on each item's
  // support carries mu g of that before the wrap has to.
  const double accel = std::min(max_accel_mps2, friction.belt_pallet.mu_s * kGravity);
  const double carried = std::min(friction.item_pallet.mu_s, friction.item_item.mu_s) * kGravity;
  const double deflection = heaviest * std::max(0.0, accel - carried) / wrap.stiffness_n_per_m;
  const double allowed = 0.25 * thresholds.load_shift_m;
  if (deflection < allowed) {
    return {Fidelity::reduced,
            "the " + std::string(to_string(config.wrap)) + " wrap holds every item within " +
                fixed(deflection * 1000.0, 1) + " mm (below " + fixed(allowed * 1000.0, 1) + " mm)",
            {}};
  }
  return {Fidelity::full,
          "the " + std::string(to_string(config.wrap)) + " wrap lets an item move " +
              fixed(deflection * 1000.0, 1) + " mm (above " + fixed(allowed * 1000.0, 1) +
              " mm): items are simulated",
          {}};
}

}  // namespace pb
