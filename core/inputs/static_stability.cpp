// SPDX-License-Identifier: MIT
#include "core/inputs/static_stability.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/contract/pallet_metrics.hpp"

namespace pb {

namespace {

// Footprints sharing no more than this (m^2, 1 mm^2) touch along an edge: a neighbour, not a
// support (validate() and the layouts draw the same line).
constexpr double kMinContactArea = 1e-6;
constexpr std::size_t kDeck = std::numeric_limits<std::size_t>::max();
// The correction is searched in steps of this (m).
constexpr double kCorrectionStep = 0.001;
// Margins equal to within round-off meet the requirement (as ItemStanding::stands).
constexpr double kRoundOff = 1e-9;

struct Patch {
  std::vector<Vec2> polygon;  ///< counter-clockwise
  std::size_t support;        ///< the item under it, or kDeck
};

Vec2 operator-(const Vec2& a, const Vec2& b) {
  return {a[0] - b[0], a[1] - b[1]};
}
Vec2 operator+(const Vec2& a, const Vec2& b) {
  return {a[0] + b[0], a[1] + b[1]};
}
Vec2 operator*(double s, const Vec2& a) {
  return {s * a[0], s * a[1]};
}
double dot(const Vec2& a, const Vec2& b) {
  return a[0] * b[0] + a[1] * b[1];
}
double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}
double norm(const Vec2& a) {
  return std::hypot(a[0], a[1]);
}

std::vector<Vec2> translated(std::vector<Vec2> polygon, const Vec2& by) {
  for (Vec2& v : polygon) v = v + by;
  return polygon;
}

struct Box {
  double x0, y0, x1, y1;
};
Box bounds(const std::vector<Vec2>& polygon) {
  Box b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Vec2& v : polygon) {
    b = {std::min(b.x0, v[0]), std::min(b.y0, v[1]), std::max(b.x1, v[0]), std::max(b.y1, v[1])};
  }
  return b;
}

// What item `i`, shifted horizontally by `shift`, rests on: the deck, or the items whose top is at
// its bottom, among `candidates` (its footprint_neighbours when not shifted) or, without them, all.
std::vector<Patch> contacts(const PalletConfig& config, std::size_t i, const Vec2& shift,
                            double tolerance_m,
                            const std::vector<std::size_t>* candidates = nullptr) {
  const Item& item = config.items[i];
  const std::vector<Vec2> footprint = translated(footprint_polygon(item), shift);
  std::vector<Patch> out;
  if (std::abs(item.position[2] - config.base_dims_m[2]) <= tolerance_m) {
    auto patch = convex_intersection(footprint, deck_polygon(config.base_dims_m));
    if (!patch.empty() && polygon_area(patch) > kMinContactArea) {
      out.push_back({std::move(patch), kDeck});
    }
    return out;
  }
  const Box box = bounds(footprint);
  auto consider = [&](std::size_t j) {
    const Item& other = config.items[j];
    if (j == i || std::abs(other.top_z() - item.position[2]) > tolerance_m) return;
    const std::vector<Vec2> under = footprint_polygon(other);
    const Box b = bounds(under);
    if (b.x0 >= box.x1 || box.x0 >= b.x1 || b.y0 >= box.y1 || box.y0 >= b.y1) return;
    auto patch = convex_intersection(footprint, under);
    if (!patch.empty() && polygon_area(patch) > kMinContactArea) {
      out.push_back({std::move(patch), j});
    }
  };
  if (candidates != nullptr) {
    for (const std::size_t j : *candidates) consider(j);
  } else {
    for (std::size_t j = 0; j < config.items.size(); ++j) consider(j);
  }
  return out;
}

// Andrew's monotone chain; counter-clockwise, no collinear points.
std::vector<Vec2> convex_hull(const std::vector<Patch>& patches) {
  std::vector<Vec2> points;
  for (const Patch& p : patches) points.insert(points.end(), p.polygon.begin(), p.polygon.end());
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<Vec2> hull(2 * points.size());
  std::size_t k = 0;
  for (const Vec2& p : points) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0.0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

Vec2 nearest_on_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

// The point of the polygon's boundary nearest to p, and whether p is inside (or on) it. A
// polygon of fewer than three points has no inside.
struct Nearest {
  Vec2 point{};
  bool inside = false;
  std::size_t edge = 0;  ///< the edge the point lies on
};
Nearest nearest_on_boundary(const std::vector<Vec2>& polygon, const Vec2& p) {
  Nearest out;
  double best = std::numeric_limits<double>::infinity();
  bool inside = polygon.size() >= 3;
  for (std::size_t e = 0; e < polygon.size(); ++e) {
    const Vec2& a = polygon[e];
    const Vec2& b = polygon[(e + 1) % polygon.size()];
    if (cross(a, b, p) < 0.0) inside = false;
    const Vec2 q = nearest_on_segment(p, a, b);
    if (const double d = norm(p - q); d < best) {
      best = d;
      out.point = q;
      out.edge = e;
    }
  }
  out.inside = inside;
  return out;
}

// Where a point outside a convex polygon is pulled to: its nearest point of the polygon.
Vec2 clamp_into(const std::vector<Vec2>& polygon, const Vec2& p) {
  const Nearest n = nearest_on_boundary(polygon, p);
  return n.inside ? p : n.point;
}

double signed_margin(const std::vector<Vec2>& hull, const Vec2& p) {
  if (hull.empty()) return -std::numeric_limits<double>::infinity();
  const Nearest n = nearest_on_boundary(hull, p);
  const double d = norm(p - n.point);
  return n.inside ? d : -d;
}

// Area, first and second moments of a polygon about the point `o`:
// [A, Sx, Sy, Ixx, Ixy, Iyy] = integrals of 1, x, y, x^2, xy, y^2 (x, y relative to o).
std::array<double, 6> moments(const std::vector<Vec2>& polygon, const Vec2& o) {
  std::array<double, 6> m{};
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2 p = polygon[i] - o;
    const Vec2 q = polygon[(i + 1) % polygon.size()] - o;
    const double c = p[0] * q[1] - q[0] * p[1];
    m[0] += c / 2.0;
    m[1] += (p[0] + q[0]) * c / 6.0;
    m[2] += (p[1] + q[1]) * c / 6.0;
    m[3] += (p[0] * p[0] + p[0] * q[0] + q[0] * q[0]) * c / 12.0;
    m[4] += (p[0] * q[1] + 2.0 * p[0] * p[1] + 2.0 * q[0] * q[1] + q[0] * p[1]) * c / 24.0;
    m[5] += (p[1] * p[1] + p[1] * q[1] + q[1] * q[1]) * c / 12.0;
  }
  return m;
}

struct Share {
  double mass = 0.0;
  Vec2 point{};
};

// The load `mass` acting at `p`, shared over the patches by a linear pressure a + b x + c y whose
// resultant is the load; a patch the pressure would pull on is lifted and the rest re-solved.
// On one support the load passes down whole, at its resultant. Over several, each share acts at
// its own resultant, inside its patch (a contact only pushes).
std::vector<Share> distribute(const std::vector<Patch>& patches, double mass, const Vec2& p) {
  std::vector<Share> out(patches.size());
  if (patches.size() == 1) {
    out[0] = {mass, p};
    return out;
  }
  std::vector<std::array<double, 6>> m;
  for (const Patch& patch : patches) m.push_back(moments(patch.polygon, p));
  std::vector<bool> active(patches.size(), true);
  for (;;) {
    Eigen::Matrix3d k = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (!active[i]) continue;
      const auto& [a, sx, sy, ixx, ixy, iyy] = m[i];
      k += (Eigen::Matrix3d() << a, sx, sy, sx, ixx, ixy, sy, ixy, iyy).finished();
    }
    const Eigen::Vector3d abc = k.ldlt().solve(Eigen::Vector3d(mass, 0.0, 0.0));
    std::size_t worst = m.size();
    double worst_force = 0.0;
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (!active[i]) continue;
      const auto& [a, sx, sy, ixx, ixy, iyy] = m[i];
      const double f = abc[0] * a + abc[1] * sx + abc[2] * sy;
      const double mx = abc[0] * sx + abc[1] * ixx + abc[2] * ixy;
      const double my = abc[0] * sy + abc[1] * ixy + abc[2] * iyy;
      out[i] = {f, f > 0.0 ? p + Vec2{mx / f, my / f} : p};
      if (f < worst_force) {
        worst = i;
        worst_force = f;
      }
    }
    const auto n_active = std::count(active.begin(), active.end(), true);
    if (worst == m.size() || n_active <= 1) break;
    active[worst] = false;
    out[worst] = {};
  }
  // A contact pushes only within its patch: a share whose resultant the linear pressure put
  // outside (negative pressure over part of the patch) acts at the patch's nearest point.
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!active[i] || out[i].mass <= 0.0) {
      out[i] = {};
      continue;
    }
    out[i].point = clamp_into(patches[i].polygon, out[i].point);
  }
  // The one patch left of several carries everything (a pull cannot remain).
  if (std::count(active.begin(), active.end(), true) == 1) {
    const auto i =
        static_cast<std::size_t>(std::find(active.begin(), active.end(), true) - active.begin());
    out[i] = {mass, clamp_into(patches[i].polygon, p)};
  }
  return out;
}

}  // namespace

std::vector<ItemStanding> standing(const PalletConfig& config, double tolerance_m) {
  const auto& items = config.items;
  std::vector<ItemStanding> out(items.size());
  const auto neighbours = footprint_neighbours(config);
  std::vector<double> mass(items.size());
  std::vector<Vec2> moment(items.size());
  for (std::size_t i = 0; i < items.size(); ++i) {
    mass[i] = items[i].weight_kg;
    moment[i] = {items[i].weight_kg * items[i].position[0],
                 items[i].weight_kg * items[i].position[1]};
  }
  // What an item carries starts higher than it does: top to bottom, every load is complete when
  // its item is reached.
  std::vector<std::size_t> order(items.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return items[a].position[2] > items[b].position[2];
  });
  for (const std::size_t i : order) {
    ItemStanding& s = out[i];
    s.load_kg = mass[i];
    s.load_point = (1.0 / mass[i]) * moment[i];
    const std::vector<Patch> patches = contacts(config, i, {0.0, 0.0}, tolerance_m, &neighbours[i]);
    for (const Patch& p : patches) {
      if (p.support == kDeck) {
        s.on_deck = true;
      } else {
        s.supports.push_back(p.support);
      }
    }
    const std::vector<Vec2> hull = convex_hull(patches);
    s.margin_m = signed_margin(hull, s.load_point);
    if (s.supports.empty()) continue;
    // A load outside its region tips the item over the region's edge: what is under it then
    // bears it there, not where it would act on a rigid stack.
    const Vec2 acts = s.margin_m >= 0.0 || hull.size() < 3
                          ? s.load_point
                          : nearest_on_boundary(hull, s.load_point).point;
    const std::vector<Share> shares = distribute(patches, s.load_kg, acts);
    for (std::size_t k = 0; k < patches.size(); ++k) {
      const std::size_t j = patches[k].support;
      mass[j] += shares[k].mass;
      moment[j] = moment[j] + shares[k].mass * shares[k].point;
    }
  }
  return out;
}

bool stands(const PalletConfig& config, double margin_m, double tolerance_m) {
  const auto all = standing(config, tolerance_m);
  return std::all_of(all.begin(), all.end(),
                     [&](const ItemStanding& s) { return s.stands(margin_m); });
}

std::vector<std::size_t> carried_items(const PalletConfig& config, std::size_t item,
                                       double tolerance_m) {
  const auto neighbours = footprint_neighbours(config);
  std::vector<bool> seen(config.items.size(), false);
  std::vector<std::size_t> stack{item};
  while (!stack.empty()) {
    const std::size_t below = stack.back();
    stack.pop_back();
    const Item& b = config.items[below];
    for (const std::size_t j : neighbours[below]) {
      const Item& a = config.items[j];
      if (seen[j] || j == item || std::abs(a.position[2] - b.top_z()) > tolerance_m ||
          footprint_overlap_area(a, b) <= kMinContactArea) {
        continue;
      }
      seen[j] = true;
      stack.push_back(j);
    }
  }
  std::vector<std::size_t> out;
  for (std::size_t j = 0; j < seen.size(); ++j) {
    if (seen[j]) out.push_back(j);
  }
  return out;
}

std::optional<Vec2> standing_correction(const PalletConfig& config,
                                        const std::vector<ItemStanding>& standings,
                                        std::size_t item, double margin_m, double tolerance_m) {
  const Vec2 p = standings[item].load_point;
  const std::vector<Vec2> hull = convex_hull(contacts(config, item, {0.0, 0.0}, tolerance_m));
  if (hull.empty()) return std::nullopt;
  // Towards the inside: to the nearest point of the region from outside, away from the nearest
  // edge from inside, along the edge's inward normal from on it.
  const Nearest n = nearest_on_boundary(hull, p);
  Vec2 towards = n.inside ? p - n.point : n.point - p;
  if (norm(towards) < 1e-9) {
    if (hull.size() < 2) return std::nullopt;
    const Vec2 edge = hull[(n.edge + 1) % hull.size()] - hull[n.edge];
    towards = {-edge[1], edge[0]};  // left of a counter-clockwise edge is inside
  }
  towards = (1.0 / norm(towards)) * towards;
  const Item& it = config.items[item];
  const int steps =
      static_cast<int>(std::ceil(std::max(it.dims_m[0], it.dims_m[1]) / kCorrectionStep));
  for (int k = 1; k <= steps; ++k) {
    const Vec2 shift = (k * kCorrectionStep) * towards;
    const std::vector<Vec2> moved = convex_hull(contacts(config, item, shift, tolerance_m));
    if (moved.size() >= 3 && signed_margin(moved, p + shift) >= margin_m - kRoundOff) {
      return shift;
    }
  }
  return std::nullopt;
}

}  // namespace pb
