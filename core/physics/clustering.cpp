// SPDX-License-Identifier: MIT
#include "core/physics/clustering.hpp"

#include <algorithm>
#include <numeric>

#include "core/contract/pallet_metrics.hpp"
#include "core/physics/quasi_static.hpp"

namespace pb {

int Clustering::root(int i) const {
  while (i >= 0 && carrier[static_cast<std::size_t>(i)] != kFreeItem) {
    i = carrier[static_cast<std::size_t>(i)];
  }
  return i;
}

int Clustering::free_count() const {
  return static_cast<int>(std::count(carrier.begin(), carrier.end(), kFreeItem));
}

Clustering cluster_items(const PalletConfig& config, const ContactFriction& friction,
                         double max_demand_mps2, double margin) {
  const std::size_t n = config.items.size();
  Clustering out;
  out.carrier.assign(n, kFreeItem);
  out.reach_mps2 = max_demand_mps2;
  if (config.wrap != WrapType::none || n == 0) return out;

  const QuasiStaticBounds bounds = quasi_static_bounds(config, friction);
  // The weakest onset of each item's own mechanisms (its slip, its sub-stack's tip), both ways.
  std::vector<double> onset(n, 1e9);
  for (const auto* list : {&bounds.along, &bounds.across}) {
    for (const QuasiStaticLimit& m : *list) {
      if (m.item >= 0) {
        auto& o = onset[static_cast<std::size_t>(m.item)];
        o = std::min(o, m.accel_mps2);
      }
    }
  }
  const auto carriers = resting_on(config);
  // Bottom-up, so an item's supports are decided before it.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return config.items[a].position[2] < config.items[b].position[2];
  });
  const double deck = config.base_dims_m[2];
  for (std::size_t i : order) {
    if (onset[i] < margin * out.reach_mps2) continue;
    const Item& item = config.items[i];
    int body = kFreeItem;  // the rigid body every support belongs to
    if (std::abs(item.position[2] - deck) <= kSupportTolerance_m) {
      body = kOnPallet;
      if (!carriers[i].empty()) continue;  // on the deck and on items at once: leave it free
    } else {
      if (carriers[i].empty()) continue;
      bool one = true;
      const int first = out.root(static_cast<int>(carriers[i].front()));
      for (std::size_t c : carriers[i]) one = one && out.root(static_cast<int>(c)) == first;
      if (!one) continue;
      body = static_cast<int>(carriers[i].front());
    }
    out.carrier[i] = body;
  }
  return out;
}

}  // namespace pb
