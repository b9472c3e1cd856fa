// SPDX-License-Identifier: MIT
#include "core/contract/pallet_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pb {

namespace {

// cos and sin of a yaw in degrees; exact for multiples of 90 degrees so that an axis-aligned
// carton turned a quarter turn has exactly swapped extents.
Vec2 cos_sin_deg(double deg) {
  const double quarter = deg / 90.0;
  if (std::isfinite(quarter) && quarter == std::round(quarter)) {
    // fmod, not a cast: a yaw of 1e88 degrees (read from a hostile file) has no `long`.
    const int q = static_cast<int>(std::fmod(std::fmod(quarter, 4.0) + 4.0, 4.0));
    static constexpr Vec2 kExact[4] = {{1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, {0.0, -1.0}};
    return kExact[q];
  }
  const double rad = deg * std::numbers::pi / 180.0;
  return {std::cos(rad), std::sin(rad)};
}

// Twice the signed area of triangle (a, b, p): positive when p is left of a->b.
double cross(const Vec2& a, const Vec2& b, const Vec2& p) {
  return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
}

// Intersection of segment p->q with the infinite line a->b (p and q on opposite sides).
Vec2 intersect(const Vec2& p, const Vec2& q, const Vec2& a, const Vec2& b) {
  const double dp = cross(a, b, p);
  const double dq = cross(a, b, q);
  const double t = dp / (dp - dq);
  return {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])};
}

// Keeps the part of `poly` left of (or on) the directed line a->b (one Sutherland–Hodgman pass).
std::vector<Vec2> clip_by_edge(const std::vector<Vec2>& poly, const Vec2& a, const Vec2& b) {
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& cur = poly[i];
    const Vec2& prev = poly[(i + poly.size() - 1) % poly.size()];
    const bool cur_in = cross(a, b, cur) >= 0.0;
    const bool prev_in = cross(a, b, prev) >= 0.0;
    if (cur_in != prev_in) out.push_back(intersect(prev, cur, a, b));
    if (cur_in) out.push_back(cur);
  }
  return out;
}

}  // namespace

double total_mass_kg(const PalletConfig& config) {
  double mass = config.base_mass_kg;
  for (const Item& item : config.items) mass += item.weight_kg;
  return mass;
}

Vec3 composite_com_m(const PalletConfig& config) {
  double mass = config.base_mass_kg;
  Vec3 moment{0.0, 0.0, config.base_mass_kg * config.base_dims_m[2] / 2.0};
  for (const Item& item : config.items) {
    const Vec3 com = item.center_of_mass();
    for (std::size_t k = 0; k < 3; ++k) moment[k] += item.weight_kg * com[k];
    mass += item.weight_kg;
  }
  return {moment[0] / mass, moment[1] / mass, moment[2] / mass};
}

double stack_height_m(const PalletConfig& config) {
  if (config.items.empty()) return config.base_dims_m[2];
  double top = config.items.front().top_z();
  for (const Item& item : config.items) top = std::max(top, item.top_z());
  return top;
}

double item_overhang_m(const Item& item, const Vec3& base_dims_m) {
  const double hl = base_dims_m[0] / 2.0;
  const double hw = base_dims_m[1] / 2.0;
  double overhang = 0.0;
  for (const Vec2& c : item_footprint(item)) {
    overhang = std::max({overhang, std::abs(c[0]) - hl, std::abs(c[1]) - hw});
  }
  return overhang;
}

double overhang_m(const PalletConfig& config) {
  double overhang = 0.0;
  for (const Item& item : config.items) {
    overhang = std::max(overhang, item_overhang_m(item, config.base_dims_m));
  }
  return overhang;
}

std::array<Vec2, 4> item_footprint(const Item& item) {
  const auto [c, s] = cos_sin_deg(item.orientation_deg);
  const double hl = item.dims_m[0] / 2.0;
  const double hw = item.dims_m[1] / 2.0;
  static constexpr Vec2 kSigns[4] = {{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}};
  std::array<Vec2, 4> corners{};
  for (std::size_t i = 0; i < 4; ++i) {
    const double lx = kSigns[i][0] * hl;
    const double ly = kSigns[i][1] * hw;
    corners[i] = {item.position[0] + c * lx - s * ly, item.position[1] + s * lx + c * ly};
  }
  return corners;
}

double polygon_area(const std::vector<Vec2>& poly) {
  double twice = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    twice += p[0] * q[1] - q[0] * p[1];
  }
  return twice / 2.0;
}

std::vector<Vec2> convex_intersection(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  std::vector<Vec2> clipped = a;
  for (std::size_t i = 0; i < b.size() && !clipped.empty(); ++i) {
    clipped = clip_by_edge(clipped, b[i], b[(i + 1) % b.size()]);
  }
  if (clipped.size() < 3) clipped.clear();
  return clipped;
}

double convex_overlap_area(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  const std::vector<Vec2> clipped = convex_intersection(a, b);
  return clipped.empty() ? 0.0 : std::abs(polygon_area(clipped));
}

std::vector<Vec2> deck_polygon(const Vec3& base_dims_m) {
  const double hl = base_dims_m[0] / 2.0;
  const double hw = base_dims_m[1] / 2.0;
  return {{-hl, -hw}, {hl, -hw}, {hl, hw}, {-hl, hw}};
}

std::vector<Vec2> footprint_polygon(const Item& item) {
  const auto corners = item_footprint(item);
  return {corners.begin(), corners.end()};
}

double footprint_overlap_area(const Item& a, const Item& b) {
  return convex_overlap_area(footprint_polygon(a), footprint_polygon(b));
}

std::vector<std::vector<std::size_t>> footprint_neighbours(const PalletConfig& config,
                                                           double margin_m) {
  struct Bounds {
    double x0, x1, y0, y1;
    std::size_t item;
  };
  std::vector<Bounds> boxes;
  boxes.reserve(config.items.size());
  for (std::size_t i = 0; i < config.items.size(); ++i) {
    const auto corners = item_footprint(config.items[i]);
    if (!std::all_of(corners.begin(), corners.end(),
                     [](const Vec2& v) { return std::isfinite(v[0]) && std::isfinite(v[1]); })) {
      continue;
    }
    Bounds b{corners[0][0], corners[0][0], corners[0][1], corners[0][1], i};
    for (const Vec2& v : corners) {
      b = {std::min(b.x0, v[0]), std::max(b.x1, v[0]), std::min(b.y0, v[1]), std::max(b.y1, v[1]),
           i};
    }
    boxes.push_back(b);
  }
  std::sort(boxes.begin(), boxes.end(), [](const Bounds& a, const Bounds& b) {
    return a.x0 < b.x0 || (a.x0 == b.x0 && a.item < b.item);
  });
  std::vector<std::vector<std::size_t>> out(config.items.size());
  for (std::size_t a = 0; a < boxes.size(); ++a) {
    for (std::size_t b = a + 1; b < boxes.size() && boxes[b].x0 <= boxes[a].x1 + margin_m; ++b) {
      if (boxes[b].y0 > boxes[a].y1 + margin_m || boxes[a].y0 > boxes[b].y1 + margin_m) continue;
      out[boxes[a].item].push_back(boxes[b].item);
      out[boxes[b].item].push_back(boxes[a].item);
    }
  }
  for (auto& list : out) std::sort(list.begin(), list.end());
  return out;
}

std::vector<double> support_fractions(const PalletConfig& config, double tolerance_m) {
  const double deck_top = config.base_dims_m[2];
  const std::vector<Vec2> deck = deck_polygon(config.base_dims_m);
  const auto neighbours = footprint_neighbours(config);
  std::vector<double> fractions;
  fractions.reserve(config.items.size());
  for (std::size_t i = 0; i < config.items.size(); ++i) {
    const Item& item = config.items[i];
    const double area = item.dims_m[0] * item.dims_m[1];
    const double bottom = item.position[2];
    double supported = 0.0;
    if (std::abs(bottom - deck_top) <= tolerance_m) {
      supported = convex_overlap_area(footprint_polygon(item), deck);
    } else {
      for (const std::size_t j : neighbours[i]) {
        const Item& other = config.items[j];
        if (std::abs(other.top_z() - bottom) <= tolerance_m) {
          supported += footprint_overlap_area(item, other);
        }
      }
    }
    fractions.push_back(area > 0.0 ? std::clamp(supported / area, 0.0, 1.0) : 0.0);
  }
  return fractions;
}

std::vector<std::vector<std::size_t>> resting_on(const PalletConfig& config) {
  constexpr double kMinSupportArea = 1e-4;  // m^2
  const auto& items = config.items;
  const auto neighbours = footprint_neighbours(config);
  std::vector<std::vector<std::size_t>> out(items.size());
  for (std::size_t i = 0; i < items.size(); ++i) {
    for (const std::size_t j : neighbours[i]) {
      if (std::abs(items[i].position[2] - items[j].top_z()) <= kSupportTolerance_m &&
          footprint_overlap_area(items[i], items[j]) > kMinSupportArea) {
        out[i].push_back(j);
      }
    }
  }
  return out;
}

namespace {

// Whether the load is its own mirror image across the plane `coordinate` = 0 (0: x, 1: y).
bool mirror_symmetric(const PalletConfig& config, int coordinate, double tolerance_m) {
  const int other = 1 - coordinate;
  const auto& items = config.items;
  auto near = [&](double a, double b) { return std::abs(a - b) <= tolerance_m; };
  auto footprint = [](const Item& it) {  // yaw a multiple of 90 degrees: the extents along X, Y
    const bool turned = std::lround(it.orientation_deg / 90.0) % 2 != 0;
    return std::array<double, 2>{turned ? it.dims_m[1] : it.dims_m[0],
                                 turned ? it.dims_m[0] : it.dims_m[1]};
  };
  std::vector<bool> used(items.size(), false);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Item& a = items[i];
    const double q = a.orientation_deg / 90.0;
    if (!std::isfinite(q) || std::abs(q - std::round(q)) > 1e-9) return false;
    if (used[i]) continue;
    bool found = false;
    for (std::size_t j = i; j < items.size() && !found; ++j) {
      const Item& b = items[j];
      if (used[j] || !near(b.position[coordinate], -a.position[coordinate]) ||
          !near(b.position[other], a.position[other]) || !near(b.position[2], a.position[2]) ||
          b.sku != a.sku || b.weight_kg != a.weight_kg || b.dims_m[2] != a.dims_m[2] ||
          footprint(a) != footprint(b)) {
        continue;
      }
      used[i] = used[j] = found = true;
    }
    if (!found) return false;
  }
  return true;
}

}  // namespace

bool mirror_symmetric_along(const PalletConfig& config, double tolerance_m) {
  return mirror_symmetric(config, 0, tolerance_m);
}

bool mirror_symmetric_across(const PalletConfig& config, double tolerance_m) {
  return mirror_symmetric(config, 1, tolerance_m);
}

}  // namespace pb
