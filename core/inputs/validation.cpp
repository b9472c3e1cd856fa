// SPDX-License-Identifier: MIT
#include "core/inputs/validation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "core/base/text.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/contract/pallet_type.hpp"
#include "core/inputs/friction.hpp"
#include "core/inputs/static_stability.hpp"

namespace pb {

namespace {

// Base dimensions further than this from the type's nominal ones earn a warning.
constexpr double kNominalDimsTolerance = 0.05;
// Relative difference between an item and its catalog entry that earns a warning.
constexpr double kCatalogTolerance = 0.01;
// Footprint overlap (m^2) below which two items do not touch from above (1 mm^2).
constexpr double kMinContactArea = 1e-6;

std::string item_pointer(std::size_t i) {
  return "/items/" + std::to_string(i);
}

std::string item_name(const Item& item, std::size_t i) {
  return "item " + std::to_string(i) + " (" + (item.sku.empty() ? "no SKU" : item.sku) + ")";
}

// An inclusive or half-open interval a value must lie in, for one message format.
struct Range {
  double lo;
  double hi;
  bool lo_open;  ///< lo itself is not allowed
};

class Checker {
 public:
  explicit Checker(const ValidationLimits& limits) : limits_(limits) {}

  Diagnostics out;

  void error(std::string pointer, std::string message) {
    out.push_back({std::move(pointer), std::move(message), Severity::error});
  }
  void warning(std::string pointer, std::string message) {
    out.push_back({std::move(pointer), std::move(message), Severity::warning});
  }

  /// Records an error unless `value` is finite and in `range`; returns whether it is.
  bool in_range(const std::string& pointer, const std::string& what, double value, Range range,
                const char* unit) {
    const bool ok = std::isfinite(value) &&
                    (range.lo_open ? value > range.lo : value >= range.lo) && value <= range.hi;
    if (!ok) {
      const std::string shown = !std::isfinite(value)   ? "not finite"
                                : std::abs(value) < 1e6 ? fixed(value, 4)
                                                        : short_number(value);
      // An open-ended range reads as a bound ("a number >= 0 s"), not "[0.00, 1.79769e+308]".
      const std::string wanted =
          range.hi == std::numeric_limits<double>::max() ||
                  range.hi == std::numeric_limits<double>::infinity()
              ? std::string(range.lo_open ? "> " : ">= ") + short_number(range.lo)
              : std::string("in ") + (range.lo_open ? "(" : "[") + fixed(range.lo, 2) + ", " +
                    fixed(range.hi, 2) + "]";
      error(pointer,
            what + " is " + shown + " " + unit + "; set it to a number " + wanted + " " + unit);
    }
    return ok;
  }

  const ValidationLimits& limits() const { return limits_; }

 private:
  ValidationLimits limits_;
};

// The friction follows body_temp_c; `env` says what kind of load it is. A frozen load at +20 degC
// or a thawed one at -20 is a sign that one of them is wrong, and the answer rides on the
// temperature: say so (a warning: a load can be anything in transition).
void check_env_temperature(Checker& c, const PalletConfig& config) {
  const double t = config.body_temp_c;
  std::string expected;
  switch (config.env) {
    case Environment::frozen:
      if (t > -5.0) expected = "at or below -5 degC";
      break;
    case Environment::refrigerated:
      if (t < -5.0 || t > 10.0) expected = "between -5 and 10 degC";
      break;
    case Environment::thawed:
      if (t < 0.0) expected = "above 0 degC";
      break;
    case Environment::transitioning:
      break;
  }
  if (expected.empty()) return;
  c.warning("/body_temp_c",
            short_number(t) + " degC is unusual for env '" + std::string(to_string(config.env)) +
                "' (" + expected +
                "); friction follows body_temp_c: check it, or env (\"transitioning\" "
                "for a load warming or cooling)");
}

// Pallet-level fields. Returns whether the base is usable for the physical rules.
bool check_base(Checker& c, const PalletConfig& config) {
  if (config.pallet_id.empty()) {
    c.error("/pallet_id", "pallet_id is empty; give the pallet an identifier");
  }
  static constexpr const char* kAxis[3] = {"length", "width", "height"};
  bool base_ok = true;
  for (std::size_t k = 0; k < 3; ++k) {
    const Range range{0.0, k < 2 ? 3.0 : 0.5, true};
    base_ok = c.in_range("/base_dims_m/" + std::to_string(k), std::string("the base ") + kAxis[k],
                         config.base_dims_m[k], range, "m") &&
              base_ok;
  }
  const PalletTypeSpec& spec = pallet_type_spec(config.base_pallet_type);
  if (base_ok) {
    for (std::size_t k = 0; k < 3; ++k) {
      if (std::abs(config.base_dims_m[k] - spec.dims_m[k]) > kNominalDimsTolerance) {
        c.warning("/base_dims_m",
                  "base_dims_m differ from a nominal " + std::string(to_string(spec.type)) +
                      " pallet (" + fixed(spec.dims_m[0], 3) + " x " + fixed(spec.dims_m[1], 3) +
                      " x " + fixed(spec.dims_m[2], 3) +
                      " m) by more than 5 cm; check the dimensions or the base_pallet_type");
        break;
      }
    }
  }
  c.in_range("/base_mass_kg", "base_mass_kg", config.base_mass_kg, {0.0, 100.0, true}, "kg");
  if (c.in_range("/body_temp_c", "body_temp_c", config.body_temp_c, {kMinTempC, kMaxTempC, false},
                 "degC")) {
    check_env_temperature(c, config);
  }
  c.in_range("/seconds_since_temp_change", "seconds_since_temp_change",
             config.seconds_since_temp_change, {0.0, std::numeric_limits<double>::max(), false},
             "s");
  return base_ok;
}

// An item's size and position, each, within these (m).
constexpr double kMaxItemDim_m = 3.0;
constexpr double kMaxItemPosition_m = 10.0;

// Per-item syntax and range rules. Returns whether the item's numbers are usable for the
// physical rules.
bool check_item_fields(Checker& c, const Item& item, std::size_t i) {
  const std::string p = item_pointer(i);
  if (item.sku.empty()) c.error(p + "/sku", "the SKU is empty; give the item its SKU");
  bool ok = c.in_range(p + "/weight_kg", "weight_kg", item.weight_kg, {0.0, 500.0, true}, "kg");
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string k_str = std::to_string(k);
    ok = c.in_range(p + "/dims_m/" + k_str, "dims_m[" + k_str + "]", item.dims_m[k],
                    {0.0, kMaxItemDim_m, true}, "m") &&
         ok;
  }
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string k_str = std::to_string(k);
    // Any item beyond 10 m of the pallet's centre is off it; a larger number is a unit slip
    // (1e308 was reported as reaching "inf mm" beyond the edge).
    ok = c.in_range(p + "/position/" + k_str, "position[" + k_str + "]", item.position[k],
                    {-kMaxItemPosition_m, kMaxItemPosition_m, false}, "m") &&
         ok;
  }
  ok = c.in_range(p + "/orientation_deg", "orientation_deg", item.orientation_deg,
                  {-180.0, 180.0, false}, "deg") &&
       ok;
  if (ok) {
    const double volume = item.dims_m[0] * item.dims_m[1] * item.dims_m[2];
    const double density = item.weight_kg / volume;
    const ValidationLimits& l = c.limits();
    if (!(density >= l.min_density_kg_m3 && density <= l.max_density_kg_m3)) {
      c.error(p + "/weight_kg",
              short_number(item.weight_kg) + " kg in a " + short_number(item.dims_m[0]) + " x " +
                  short_number(item.dims_m[1]) + " x " + short_number(item.dims_m[2]) +
                  " m box is a density of " + short_number(density) + " kg/m^3, " +
                  (density > l.max_density_kg_m3 ? "denser than lead" : "lighter than air") +
                  "; check weight_kg (kilograms) and dims_m (metres)");
      ok = false;
    }
  }
  return ok;
}

bool close_to(double value, double reference) {
  return std::abs(value - reference) <= kCatalogTolerance * std::abs(reference);
}

// Unknown SKUs; and for an item whose numbers are usable, differences from its catalog entry.
void check_catalog(Checker& c, const Item& item, std::size_t i, const Catalog& catalog,
                   bool usable) {
  if (item.sku.empty()) return;
  const std::string p = item_pointer(i);
  const SkuTemplate* sku = catalog.find(item.sku);
  if (sku == nullptr) {
    const std::string message =
        "SKU '" + item.sku + "' is not in the catalog; check its spelling or add it to the catalog";
    if (c.limits().require_known_skus) {
      c.error(p + "/sku", message);
    } else {
      c.warning(p + "/sku", message);
    }
    return;
  }
  if (!usable) return;
  if (!close_to(item.weight_kg, sku->weight_kg)) {
    c.warning(p + "/weight_kg", "weight_kg " + fixed(item.weight_kg, 3) + " differs from the " +
                                    fixed(sku->weight_kg, 3) + " kg of catalog SKU '" + sku->sku +
                                    "' by more than 1 %; check the weight or the SKU");
  }
  // A carton described with length and width swapped is the same carton.
  const auto& d = item.dims_m;
  const auto& e = sku->dims_m;
  const bool same = close_to(d[2], e[2]) && ((close_to(d[0], e[0]) && close_to(d[1], e[1])) ||
                                             (close_to(d[0], e[1]) && close_to(d[1], e[0])));
  if (!same) {
    c.warning(p + "/dims_m", "dims_m differ from the " + fixed(e[0], 3) + " x " + fixed(e[1], 3) +
                                 " x " + fixed(e[2], 3) + " m of catalog SKU '" + sku->sku +
                                 "' by more than 1 %; check the dimensions or the SKU");
  }
}

// Separating-axis test on two convex footprints: the smallest overlap of their projections over
// every edge normal, i.e. the horizontal distance one must move to separate them (<= 0: apart).
double horizontal_penetration(const Item& a, const Item& b) {
  const auto fa = item_footprint(a);
  const auto fb = item_footprint(b);
  double depth = std::numeric_limits<double>::infinity();
  for (const auto* poly : {&fa, &fb}) {
    for (std::size_t e = 0; e < 2; ++e) {  // a rectangle has two distinct edge normals
      const Vec2& p = (*poly)[e];
      const Vec2& q = (*poly)[e + 1];
      const double len = std::hypot(q[0] - p[0], q[1] - p[1]);
      if (len <= 0.0) return 0.0;
      const Vec2 axis{-(q[1] - p[1]) / len, (q[0] - p[0]) / len};
      auto project = [&axis](const std::array<Vec2, 4>& corners) {
        double lo = std::numeric_limits<double>::infinity();
        double hi = -lo;
        for (const Vec2& v : corners) {
          const double s = v[0] * axis[0] + v[1] * axis[1];
          lo = std::min(lo, s);
          hi = std::max(hi, s);
        }
        return Vec2{lo, hi};
      };
      const Vec2 ia = project(fa);
      const Vec2 ib = project(fb);
      depth = std::min(depth, std::min(ia[1], ib[1]) - std::max(ia[0], ib[0]));
    }
  }
  return depth;
}

double vertical_overlap(const Item& a, const Item& b) {
  return std::min(a.top_z(), b.top_z()) - std::max(a.position[2], b.position[2]);
}

// The physical rules over the items whose numbers are usable (`usable[i]`). What carries an
// item cannot be judged while any item's numbers are unusable, so the support rules (floating,
// low support) then wait until those are fixed.
class PhysicalChecks {
 public:
  PhysicalChecks(Checker& c, const PalletConfig& config, const std::vector<bool>& usable)
      : c_(c),
        config_(config),
        usable_(usable),
        all_usable_(std::all_of(usable.begin(), usable.end(), [](bool u) { return u; })),
        deck_top_(config.base_dims_m[2]) {}

  // The tolerances as compared: an input given to the millimetre that meets one exactly (an item
  // at z = 0.441 m on a top at 0.440 m) computes a hair over it in doubles, and was refused.
  double support_tolerance() const { return c_.limits().support_tolerance_m + kLengthRoundOff_m; }
  double penetration_tolerance() const {
    return c_.limits().penetration_tolerance_m + kLengthRoundOff_m;
  }

  void run() {
    const double tolerance = support_tolerance();
    const std::vector<double> support = all_usable_
                                            ? support_fractions(config_, tolerance)
                                            : std::vector<double>(config_.items.size(), 1.0);
    if (all_usable_ && c_.limits().check_standing) standings_ = standing(config_, tolerance);
    neighbours_ = footprint_neighbours(config_);
    for (std::size_t i = 0; i < config_.items.size(); ++i) {
      if (!usable_[i]) continue;
      const bool interpenetrates = check_interpenetration(i);
      const bool placed =
          check_below_deck(i) && !interpenetrates && (!all_usable_ || check_floating(i));
      const bool stands = !placed || standings_.empty() || check_standing(i);
      if (placed && stands && support[i] < c_.limits().low_support_warning) {
        c_.warning(item_pointer(i), item_name(config_.items[i], i) + " rests on only " +
                                        fixed(100.0 * support[i], 0) +
                                        " % of its footprint; move it over what carries it");
      }
      check_overhang(i);
    }
  }

 private:
  const Item& item(std::size_t i) const { return config_.items[i]; }

  bool check_below_deck(std::size_t i) {
    const double sink = deck_top_ - item(i).position[2];
    if (sink <= penetration_tolerance()) return true;
    c_.error(item_pointer(i) + "/position/2",
             item_name(item(i), i) + " reaches " + fixed(1000.0 * sink, 1) +
                 " mm into the pallet deck; raise it to z = " + fixed(deck_top_, 3) + " m");
    return false;
  }

  // Each pair is reported once, at the later item. Returns whether item j interpenetrates any
  // earlier item.
  bool check_interpenetration(std::size_t j) {
    const double tolerance = penetration_tolerance();
    bool found = false;
    for (const std::size_t i : neighbours_[j]) {
      if (i >= j) break;
      if (!usable_[i]) continue;
      const double horizontal = horizontal_penetration(item(i), item(j));
      const double vertical = vertical_overlap(item(i), item(j));
      if (horizontal > tolerance && vertical > tolerance) {
        c_.error(item_pointer(j), item_name(item(j), j) + " and " + item_name(item(i), i) +
                                      " interpenetrate by " +
                                      fixed(1000.0 * std::min(horizontal, vertical), 1) +
                                      " mm; move one of them so their volumes do not overlap");
        found = true;
      }
    }
    return found;
  }

  // An item rests on the highest deck or item top below its bottom under its footprint.
  bool check_floating(std::size_t i) {
    const double bottom = item(i).position[2];
    double rest = deck_top_;
    for (const std::size_t k : neighbours_[i]) {
      if (item(k).position[2] >= bottom) continue;
      if (footprint_overlap_area(item(i), item(k)) > kMinContactArea) {
        rest = std::max(rest, item(k).top_z());
      }
    }
    if (bottom - rest <= support_tolerance()) return true;
    c_.error(item_pointer(i) + "/position/2",
             item_name(item(i), i) + " floats " + fixed(1000.0 * (bottom - rest), 1) +
                 " mm above what is under it; lower it to z = " + fixed(rest, 3) + " m");
    return false;
  }

  // The item's load (its weight and what it carries) must act at least the stability margin inside
  // the region it rests on; otherwise it tips, and what is above it follows.
  bool check_standing(std::size_t i) {
    const ItemStanding& s = standings_[i];
    const double required = c_.limits().stability_margin_m;
    if (s.stands(required)) return true;
    const double tolerance = support_tolerance();
    const std::vector<std::size_t> carried = carried_items(config_, i, tolerance);
    const std::string load = carried.empty()
                                 ? ""
                                 : "the " + std::to_string(carried.size()) +
                                       (carried.size() == 1 ? " item" : " items") + " it carries";
    const std::string name = item_name(item(i), i);
    const std::string subject = carried.empty() ? name : name + " and " + load;
    std::string message =
        name + " cannot stand: " +
        (carried.empty() ? "its centre of mass" : "the centre of mass of it and " + load) + " is " +
        fixed(1000.0 * std::abs(s.margin_m), 0) + " mm " +
        (s.margin_m < 0.0 ? "outside" : "inside") + " the edge of what it rests on (" +
        supports_phrase(s) + ") and must be at least " + fixed(1000.0 * required, 0) +
        " mm inside; ";
    const Vec3& dims = item(i).dims_m;
    const double across = std::min(dims[0], dims[1]);
    if (across < 2.0 * required - 1e-9) {
      // Centred on its own footprint its load is half of that inside: no shift or re-stacking
      // stands it (an 18 mm board on its edge was told to re-stack centred, which it was).
      const std::string mm = fixed(1000.0 * across, 0) + " mm";
      message += "it is " + mm + " thick, so it cannot stand on that side wherever it is placed: " +
                 "lay it flat (its " + mm + " as its height, dims_m[2])";
    } else if (auto shift = standing_correction(config_, standings_, i, required, tolerance)) {
      message += "move " + subject + " " + shift_phrase(*shift) + " to stand it over its support";
    } else {
      message +=
          "no shift of it (with what it carries) by up to its own length stands it: re-stack "
          "it, and what is on it, centred over what carries it";
    }
    c_.error(item_pointer(i) + "/position", message);
    return false;
  }

  std::string supports_phrase(const ItemStanding& s) const {
    if (s.on_deck) return "the deck";
    std::string out = s.supports.size() == 1 ? "item " : "items ";
    for (std::size_t k = 0; k < s.supports.size(); ++k) {
      if (k > 0) out += k + 1 == s.supports.size() ? " and " : ", ";
      out += std::to_string(s.supports[k]);
    }
    return out;
  }

  // "24 mm towards -x", or "17 mm towards -x and 9 mm towards +y" (to the millimetre).
  static std::string shift_phrase(const Vec2& shift) {
    std::string out;
    for (std::size_t k = 0; k < 2; ++k) {
      const long mm = std::lround(1000.0 * shift[k]);
      if (mm == 0) continue;
      if (!out.empty()) out += " and ";
      out += std::to_string(std::labs(mm)) + " mm towards " + (mm < 0 ? "-" : "+") +
             (k == 0 ? "x" : "y");
    }
    return out;
  }

  void check_overhang(std::size_t i) {
    const double overhang = item_overhang_m(item(i), config_.base_dims_m);
    if (overhang <= c_.limits().max_overhang_m + kLengthRoundOff_m) return;
    c_.error(item_pointer(i) + "/position", item_name(item(i), i) + " reaches " +
                                                fixed(1000.0 * overhang, 0) +
                                                " mm beyond the pallet edge, more than the " +
                                                fixed(1000.0 * c_.limits().max_overhang_m, 0) +
                                                " mm allowed; move it towards the centre");
  }

  Checker& c_;
  const PalletConfig& config_;
  const std::vector<bool>& usable_;
  bool all_usable_;
  double deck_top_;
  std::vector<ItemStanding> standings_;  ///< empty: not judged (unusable numbers, or not asked)
  std::vector<std::vector<std::size_t>> neighbours_;  ///< footprint_neighbours: the pairs to check
};

// The base against its type's tare and against the heaviest item it carries.
void check_base_mass(Checker& c, const PalletConfig& config) {
  const PalletTypeSpec& spec = pallet_type_spec(config.base_pallet_type);
  const std::string type(to_string(spec.type));
  const auto heaviest =
      std::max_element(config.items.begin(), config.items.end(),
                       [](const Item& a, const Item& b) { return a.weight_kg < b.weight_kg; });
  const double ratio =
      heaviest == config.items.end() ? 0.0 : heaviest->weight_kg / config.base_mass_kg;
  if (ratio > c.limits().max_item_to_base_mass) {
    const auto i = std::size_t(heaviest - config.items.begin());
    c.error("/base_mass_kg",
            "a base of " + short_number(config.base_mass_kg) + " kg under " +
                item_name(*heaviest, i) + " (" + short_number(heaviest->weight_kg) + " kg, " +
                short_number(ratio) + " times as heavy) is beyond what the simulation holds (" +
                short_number(c.limits().max_item_to_base_mass) + " times); check base_mass_kg (a " +
                type + " pallet weighs about " + short_number(spec.mass_kg) + " kg)");
  } else if (config.base_mass_kg < c.limits().light_base_warning * spec.mass_kg) {
    c.warning("/base_mass_kg", short_number(config.base_mass_kg) + " kg is light for a " + type +
                                   " pallet (about " + short_number(spec.mass_kg) +
                                   " kg); check base_mass_kg or base_pallet_type");
  }
}

// An item carrying one far heavier than itself is beyond what the contact solve holds
// (ValidationLimits::max_carried_to_carrier_mass): the heavy one creeps off it.
void check_carried_mass(Checker& c, const PalletConfig& config) {
  const std::vector<std::vector<std::size_t>> supports = resting_on(config);
  for (std::size_t j = 0; j < supports.size(); ++j) {
    for (const std::size_t i : supports[j]) {
      const Item& carrier = config.items[i];
      const double ratio = config.items[j].weight_kg / carrier.weight_kg;
      if (ratio <= c.limits().max_carried_to_carrier_mass) continue;
      c.error(item_pointer(i) + "/weight_kg",
              item_name(carrier, i) + ", " + short_number(carrier.weight_kg) + " kg, carries " +
                  item_name(config.items[j], j) + ", " + short_number(config.items[j].weight_kg) +
                  " kg (" + short_number(ratio) +
                  " times as heavy): beyond what the simulation holds (" +
                  short_number(c.limits().max_carried_to_carrier_mass) +
                  " times); check both weights, or stack the light item above the heavy one");
    }
  }
}

void check_gross_mass(Checker& c, const PalletConfig& config) {
  const PalletTypeSpec& spec = pallet_type_spec(config.base_pallet_type);
  const double cap = std::min(c.limits().max_gross_mass_kg, spec.rated_load_kg + spec.mass_kg);
  const double mass = total_mass_kg(config);
  if (mass <= cap) return;
  c.error("/items", "the gross mass is " + fixed(mass, 1) + " kg, above the " + fixed(cap, 1) +
                        " kg this " + std::string(to_string(spec.type)) +
                        " pallet may carry; remove " + fixed(mass - cap, 1) + " kg of items");
}

// The top of the load over the usable items and those only too high to be (a 400-carton column
// was said to be 10.05 m high, the top of its last carton below 10 m, where it reached 60 m),
// reported at the highest one.
void check_stack_height(Checker& c, const PalletConfig& config, const std::vector<bool>& usable) {
  std::size_t highest = config.items.size();
  for (std::size_t i = 0; i < config.items.size(); ++i) {
    const Item& item = config.items[i];
    const bool too_high = std::isfinite(item.position[2]) &&
                          item.position[2] > kMaxItemPosition_m && item.dims_m[2] > 0.0 &&
                          item.dims_m[2] <= kMaxItemDim_m;
    if ((usable[i] || too_high) && (highest == config.items.size() ||
                                    config.items[i].top_z() > config.items[highest].top_z())) {
      highest = i;
    }
  }
  if (highest == config.items.size()) return;
  const double top = config.items[highest].top_z();
  if (top <= c.limits().max_stack_height_m) return;
  c.error(item_pointer(highest),
          "the load is " + (top < 1e6 ? fixed(top, 3) : short_number(top)) + " m high (top of " +
              item_name(config.items[highest], highest) + "), above the " +
              fixed(c.limits().max_stack_height_m, 3) + " m limit; remove or lower the top layer");
}

}  // namespace

Diagnostics validate(const PalletConfig& config, const ValidationLimits& limits,
                     const Catalog* catalog) {
  Checker c(limits);
  if (config.items.size() > limits.max_items) {
    c.error("/items", std::to_string(config.items.size()) + " items is more than the " +
                          std::to_string(limits.max_items) +
                          " a pallet may carry here; describe the load as fewer, larger units "
                          "(whole cases or layers) or split it over several pallets");
    return c.out;
  }
  if (config.items.empty()) {
    c.warning("/items",
              "the pallet carries no items: its limits are the empty base's; add the "
              "load if this was not meant");
  }
  const bool base_ok = check_base(c, config);
  const Catalog& skus = catalog != nullptr ? *catalog : Catalog::builtin();
  std::vector<bool> usable(config.items.size());
  for (std::size_t i = 0; i < config.items.size(); ++i) {
    usable[i] = check_item_fields(c, config.items[i], i);
    check_catalog(c, config.items[i], i, skus, usable[i]);
  }
  if (!base_ok) return c.out;
  PhysicalChecks(c, config, usable).run();
  const bool weights_ok = std::all_of(config.items.begin(), config.items.end(),
                                      [](const Item& it) { return std::isfinite(it.weight_kg); });
  if (weights_ok && std::isfinite(config.base_mass_kg) && config.base_mass_kg > 0.0) {
    check_base_mass(c, config);
    check_gross_mass(c, config);
    // Supports are read from positions and sizes that passed their own checks.
    if (!has_errors(c.out)) check_carried_mass(c, config);
  }
  check_stack_height(c, config, usable);
  return c.out;
}

Diagnostics validate_curve_radius(const PalletConfig& config, double radius_m,
                                  const std::string& pointer) {
  double half_width = config.base_dims_m[1] / 2;
  for (const Item& item : config.items) {
    for (const Vec2& corner : item_footprint(item)) {
      half_width = std::max(half_width, std::abs(corner[1]));
    }
  }
  if (radius_m > half_width) return {};
  const std::string reach = short_number(half_width) + " m";
  return {{pointer,
           "a curve of radius " + short_number(radius_m) +
               " m would turn this pallet about a point under it (it reaches " + reach +
               " from the belt's centre line); give the line's curves a radius of more than " +
               reach,
           Severity::error}};
}

}  // namespace pb
