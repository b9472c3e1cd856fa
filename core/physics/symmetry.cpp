// SPDX-License-Identifier: MIT
#include "core/physics/symmetry.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

#include "core/contract/pallet_metrics.hpp"

namespace pb {

namespace {

// Surfaces within 1 mm touch (validation's tolerance, round-off included).
constexpr double kTouch = kSupportTolerance_m;
constexpr double kSame = 1e-6;  // positions that agree to a micrometre are the same

struct Extent {
  double x0, x1, y0, y1, z0, z1;
};

Extent extent(const Item& it) {
  const bool turned = std::lround(it.orientation_deg / 90.0) % 2 != 0;
  const double hx = 0.5 * (turned ? it.dims_m[1] : it.dims_m[0]);
  const double hy = 0.5 * (turned ? it.dims_m[0] : it.dims_m[1]);
  return {it.position[0] - hx, it.position[0] + hx, it.position[1] - hy,
          it.position[1] + hy, it.position[2],      it.position[2] + it.dims_m[2]};
}

bool stacked(const Extent& a, const Extent& b) {
  const bool touching = std::abs(a.z1 - b.z0) <= kTouch || std::abs(b.z1 - a.z0) <= kTouch;
  return touching && std::min(a.x1, b.x1) - std::max(a.x0, b.x0) > kTouch &&
         std::min(a.y1, b.y1) - std::max(a.y0, b.y0) > kTouch;
}

int find(std::vector<int>& parent, int i) {
  while (parent[std::size_t(i)] != i)
    i = parent[std::size_t(i)] = parent[std::size_t(parent[std::size_t(i)])];
  return i;
}

// Integer micrometres, so that equal positions compare equal as keys.
long long um(double v) {
  return std::llround(v / kSame);
}

struct Stack {
  std::vector<int> items;   // sorted by (z, x, y)
  double x = 0.0, y = 0.0;  // the first item's position: the stack's origin
};

}  // namespace

std::optional<LoadReduction> reduce_symmetric_stacks(const PalletConfig& config, ProbePlane plane) {
  const auto& items = config.items;
  const int n = int(items.size());
  if (config.wrap != WrapType::none || n < 2) return std::nullopt;
  for (const Item& it : items) {
    const double q = it.orientation_deg / 90.0;
    if (!std::isfinite(q) || std::abs(q - std::round(q)) > 1e-9) return std::nullopt;
  }
  std::vector<Extent> boxes;
  for (const Item& it : items) boxes.push_back(extent(it));
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (stacked(boxes[std::size_t(i)], boxes[std::size_t(j)])) {
        parent[std::size_t(find(parent, i))] = find(parent, j);
      }
    }
  }
  std::map<int, Stack> by_root;
  for (int i = 0; i < n; ++i) by_root[find(parent, i)].items.push_back(i);
  std::vector<Stack> stacks;
  for (auto& [root, s] : by_root) {
    std::sort(s.items.begin(), s.items.end(), [&](int a, int b) {
      const Item &p = items[std::size_t(a)], &q = items[std::size_t(b)];
      return std::make_tuple(um(p.position[2]), um(p.position[0]), um(p.position[1])) <
             std::make_tuple(um(q.position[2]), um(q.position[0]), um(q.position[1]));
    });
    s.x = items[std::size_t(s.items.front())].position[0];
    s.y = items[std::size_t(s.items.front())].position[1];
    stacks.push_back(std::move(s));
  }
  // Copies: the same items at the same offsets from the stack's origin, and the same position
  // along the plane (X for a probe along the belt, Y across it).
  const bool along = plane == ProbePlane::along;
  using ItemKey = std::tuple<std::string, double, long long, long long, long long, long long,
                             long long, long long, long long, int>;
  using Key = std::pair<long long, std::vector<ItemKey>>;  // position along the plane, items
  std::map<Key, std::vector<std::size_t>> groups;
  for (std::size_t s = 0; s < stacks.size(); ++s) {
    const Stack& st = stacks[s];
    Key key{um(along ? st.x : st.y), {}};
    for (int i : st.items) {
      const Item& it = items[std::size_t(i)];
      key.second.emplace_back(it.sku, it.weight_kg, um(it.dims_m[0]), um(it.dims_m[1]),
                              um(it.dims_m[2]), um(it.position[0] - st.x),
                              um(it.position[1] - st.y), um(it.position[2]),
                              std::llround(it.orientation_deg), int(it.fragility));
    }
    groups[key].push_back(s);
  }
  const std::size_t copies = groups.begin()->second.size();
  if (copies < 2) return std::nullopt;
  double across_mean = 0.0;
  bool first = true;
  for (const auto& [key, members] : groups) {
    if (members.size() != copies) return std::nullopt;
    double mean = 0.0;
    for (std::size_t s : members) mean += along ? stacks[s].y : stacks[s].x;
    mean /= double(members.size());
    if (first) {
      across_mean = mean;
      first = false;
    } else if (std::abs(mean - across_mean) > kTouch) {
      return std::nullopt;
    }
  }
  LoadReduction r;
  r.config = config;
  r.config.items.clear();
  r.config.base_mass_kg = config.base_mass_kg / double(copies);
  r.copies = int(copies);
  // The kept stack of each group is the one lowest across the plane (the first by item index
  // among equals), where it stands: on a grid the kept stacks are one row, neighbours as in the
  // load. Moved to the group's mean instead, a stack sat where no stack of the load stands, and
  // MuJoCo's box-box contacts there made its cartons slide less (four two-high columns: a start-up
  // limit 4.5 search steps above the whole load's; kept in place, 1.5 steps below it).
  std::vector<int> kept;
  for (const auto& [key, members] : groups) {
    const std::size_t s = *std::min_element(members.begin(), members.end(), [&](auto a, auto b) {
      const double ca = along ? stacks[a].y : stacks[a].x;
      const double cb = along ? stacks[b].y : stacks[b].x;
      return std::make_pair(um(ca), stacks[a].items.front()) <
             std::make_pair(um(cb), stacks[b].items.front());
    });
    kept.insert(kept.end(), stacks[s].items.begin(), stacks[s].items.end());
  }
  std::sort(kept.begin(), kept.end());
  for (int i : kept) {
    r.config.items.push_back(items[std::size_t(i)]);
    r.source_item.push_back(i);
  }
  return r;
}

}  // namespace pb
