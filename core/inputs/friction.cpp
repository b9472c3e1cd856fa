// SPDX-License-Identifier: MIT
#include "core/inputs/friction.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <stdexcept>

#include "core/base/resources.hpp"
#include "core/base/text.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/json_reader.hpp"
#include "core/contract/pallet_type.hpp"

namespace pb {

namespace {

constexpr double kMuMax = 2.0;
constexpr std::string_view kBeltTable = "resources/friction_table.json";
constexpr std::string_view kItemTable = "resources/friction_items.json";
constexpr std::string_view kCarton = "carton";

void error(Diagnostics& out, std::string pointer, std::string message) {
  out.push_back({std::move(pointer), std::move(message), Severity::error});
}

bool mu_in_range(double mu) {
  return mu >= 0.0 && mu <= kMuMax;
}

std::optional<FrictionPoint> read_point(JsonReader& reader, const Json& json,
                                        const std::string& where) {
  if (!reader.object(json, where, "a control point",
                     "{\"temp_c\": ..., \"mu_s\": ..., \"mu_d\": ...}")) {
    return std::nullopt;
  }
  reader.unknown_keys(json, where, {"temp_c", "mu_s", "mu_d"}, Comments::underscore);
  FrictionPoint point;
  bool ok = reader.field(json, where, "temp_c", point.temp_c, Need::required);
  ok = reader.field(json, where, "mu_s", point.mu_s, Need::required) && ok;
  ok = reader.field(json, where, "mu_d", point.mu_d, Need::required) && ok;
  if (!ok) return std::nullopt;
  for (const auto& [name, mu] : {std::pair{"mu_s", point.mu_s}, std::pair{"mu_d", point.mu_d}}) {
    if (mu_in_range(mu)) continue;
    reader.error(member_pointer(where, name),
                 wording::out_of_range(short_number(mu), "a friction coefficient in [0, 2]"));
    ok = false;
  }
  if (ok && point.mu_d > point.mu_s) {
    reader.error(member_pointer(where, "mu_d"),
                 "mu_d (" + short_number(point.mu_d) + ") is above mu_s (" +
                     short_number(point.mu_s) +
                     "); dynamic friction cannot exceed static friction, lower mu_d or raise mu_s");
    ok = false;
  }
  if (!ok) return std::nullopt;
  return point;
}

// Reads "control_points": at least one, strictly increasing temp_c.
std::vector<FrictionPoint> read_points(JsonReader& reader, const Json& pair,
                                       const std::string& where) {
  const Json* list = reader.member(pair, where, "control_points", Need::required);
  const std::string pointer = member_pointer(where, "control_points");
  if (list == nullptr ||
      !reader.array(*list, pointer, "the control points",
                    "[{\"temp_c\": ..., \"mu_s\": ..., \"mu_d\": ...}, ...]", 1)) {
    return {};
  }
  std::vector<FrictionPoint> points;
  bool ok = true;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const std::string point_where = element_pointer(pointer, i);
    const auto point = read_point(reader, (*list)[i], point_where);
    if (!point) {
      ok = false;
      continue;
    }
    if (!points.empty() && point->temp_c <= points.back().temp_c) {
      reader.error(member_pointer(point_where, "temp_c"),
                   "temp_c " + short_number(point->temp_c) + " does not follow " +
                       short_number(points.back().temp_c) +
                       "; list control points in strictly increasing temperature");
      ok = false;
    }
    points.push_back(*point);
  }
  if (!ok) return {};
  return points;
}

std::optional<SurfacePair> read_pair(JsonReader& reader, const std::string& key, const Json& json) {
  const std::string where = member_pointer("/surface_pairs", key);
  const auto slash = key.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == key.size() ||
      key.find('/', slash + 1) != std::string::npos) {
    reader.error(where,
                 "surface pair key '" + key +
                     "' must name two surfaces as 'lower/upper' (e.g. 'wood_pallet/rubber_belt')");
    return std::nullopt;
  }
  if (!reader.object(json, where, "a surface pair",
                     "{\"description\": ..., \"source\": ..., \"control_points\": [...]}")) {
    return std::nullopt;
  }
  reader.unknown_keys(json, where, {"description", "source", "control_points"},
                      Comments::underscore);
  const std::size_t errors_before = reader.error_count();
  SurfacePair pair;
  pair.key = key;
  reader.field(json, where, "description", pair.description);
  reader.field(json, where, "source", pair.source);
  pair.points = read_points(reader, json, where);
  if (reader.error_count() != errors_before) return std::nullopt;
  return pair;
}

std::optional<FrostMeltPenalty> read_penalty(JsonReader& reader, const Json& json) {
  const std::string where = "/transition_penalty";
  if (!reader.object(json, where, "the transition penalty",
                     "{\"danger_zone_temp_c\": [low, high], \"min_multiplier\": ..., "
                     "\"recovery_seconds\": ...}")) {
    return std::nullopt;
  }
  reader.unknown_keys(json, where, {"danger_zone_temp_c", "min_multiplier", "recovery_seconds"},
                      Comments::underscore);
  const std::size_t errors_before = reader.error_count();
  FrostMeltPenalty penalty;
  const std::string zone_where = member_pointer(where, "danger_zone_temp_c");
  std::array<double, 2> zone{penalty.zone_lo_c, penalty.zone_hi_c};
  if (const Json* zone_json = reader.member(json, where, "danger_zone_temp_c", Need::required);
      zone_json && reader.numbers(*zone_json, zone_where, zone, "[low, high]")) {
    penalty.zone_lo_c = zone[0];
    penalty.zone_hi_c = zone[1];
    if (!(penalty.zone_lo_c < penalty.zone_hi_c)) {
      reader.error(zone_where, "the danger zone must have low < high; it is [" +
                                   short_number(penalty.zone_lo_c) + ", " +
                                   short_number(penalty.zone_hi_c) + "]");
    }
  }
  if (reader.field(json, where, "min_multiplier", penalty.min_multiplier, Need::required) &&
      !(penalty.min_multiplier > 0.0 && penalty.min_multiplier <= 1.0)) {
    reader.error(
        member_pointer(where, "min_multiplier"),
        wording::out_of_range(short_number(penalty.min_multiplier), "a multiplier in (0, 1]"));
  }
  if (reader.field(json, where, "recovery_seconds", penalty.recovery_s, Need::required) &&
      !(penalty.recovery_s > 0.0)) {
    reader.error(
        member_pointer(where, "recovery_seconds"),
        wording::out_of_range(short_number(penalty.recovery_s), "a number of seconds above 0"));
  }
  if (reader.error_count() != errors_before) return std::nullopt;
  return penalty;
}

// numpy.interp semantics: linear between control points, the end values outside their range.
double interpolate(const std::vector<FrictionPoint>& points, double temp_c,
                   double FrictionPoint::*mu) {
  if (std::isnan(temp_c)) return std::numeric_limits<double>::quiet_NaN();
  const auto upper =
      std::lower_bound(points.begin(), points.end(), temp_c,
                       [](const FrictionPoint& p, double t) { return p.temp_c < t; });
  if (upper == points.begin()) return points.front().*mu;
  if (upper == points.end()) return points.back().*mu;
  if (upper->temp_c == temp_c) return (*upper).*mu;
  const FrictionPoint& lower = *(upper - 1);
  const double f = (temp_c - lower.temp_c) / (upper->temp_c - lower.temp_c);
  return lower.*mu + ((*upper).*mu - lower.*mu) * f;
}

// " or "-joined names.
std::string join_or(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += (i + 1 == names.size()) ? " or " : ", ";
    out += names[i];
  }
  return out;
}

std::string pair_key(std::string_view lower, std::string_view upper) {
  return std::string(lower) + "/" + std::string(upper);
}

}  // namespace

double FrostMeltPenalty::multiplier(double temp_c, double seconds_since_change) const {
  if (temp_c < zone_lo_c || temp_c > zone_hi_c) return 1.0;
  const double centre = (zone_lo_c + zone_hi_c) / 2.0;
  const double half_width = (zone_hi_c - zone_lo_c) / 2.0;
  const double zone_factor = 1.0 - std::abs(temp_c - centre) / half_width;
  // The reference clamps at 0 only; clamping at 1 too keeps a negative time from going below
  // min_multiplier.
  const double recovery_factor = std::clamp(1.0 - seconds_since_change / recovery_s, 0.0, 1.0);
  return 1.0 - zone_factor * recovery_factor * (1.0 - min_multiplier);
}

Result<FrictionModel> FrictionModel::from_json_text(std::string_view text) {
  FrictionModel model;
  Diagnostics diagnostics = model.add_json_text(text);
  if (has_errors(diagnostics)) return Result<FrictionModel>::failure(std::move(diagnostics));
  return Result<FrictionModel>{std::move(model), std::move(diagnostics)};
}

Diagnostics FrictionModel::add_json_text(std::string_view text) {
  auto parsed = parse_json(text);
  if (!parsed) return std::move(parsed.diagnostics);
  const Json& json = *parsed;
  JsonReader reader;
  if (!reader.object(json, "", "a friction table",
                     "{\"surface_pairs\": {...}, \"transition_penalty\": {...}}")) {
    return std::move(reader.diagnostics);
  }
  reader.unknown_keys(json, "", {"surface_pairs", "transition_penalty"}, Comments::underscore);
  const Json* pairs = reader.member(json, "", "surface_pairs", Need::required);
  if (pairs == nullptr || !reader.object(*pairs, "/surface_pairs", "the surface pairs",
                                         "{\"lower/upper\": {...}, ...}")) {
    return std::move(reader.diagnostics);
  }
  std::vector<SurfacePair> read;
  for (const auto& [key, value] : pairs->items()) {
    if (find(key) != nullptr) {
      reader.error(
          member_pointer("/surface_pairs", key),
          "surface pair '" + key + "' is already defined by an earlier table; keep one of them");
      continue;
    }
    if (auto pair = read_pair(reader, key, value)) read.push_back(std::move(*pair));
  }
  std::optional<FrostMeltPenalty> penalty;
  if (const Json* it = reader.member(json, "", "transition_penalty", Need::optional)) {
    penalty = read_penalty(reader, *it);
    if (penalty && has_penalty_) {
      reader.warning("/transition_penalty",
                     "the transition penalty of an earlier table applies and this one is "
                     "ignored; remove it or merge the tables");
    }
  }
  if (has_errors(reader.diagnostics)) return std::move(reader.diagnostics);
  std::move(read.begin(), read.end(), std::back_inserter(pairs_));
  if (penalty && !has_penalty_) {
    penalty_ = *penalty;
    has_penalty_ = true;
  }
  return std::move(reader.diagnostics);
}

const FrictionModel& FrictionModel::builtin() {
  static const FrictionModel model = [] {
    FrictionModel m;
    for (const std::string_view name : {kBeltTable, kItemTable}) {
      const auto text = embedded_file(name);
      if (!text) throw std::logic_error(std::string(name) + " is not embedded in palletcore");
      if (has_errors(m.add_json_text(*text))) {
        throw std::logic_error(std::string(name) + " does not parse");
      }
    }
    return m;
  }();
  return model;
}

std::vector<std::string> FrictionModel::pair_keys() const {
  std::vector<std::string> keys;
  keys.reserve(pairs_.size());
  for (const auto& pair : pairs_) keys.push_back(pair.key);
  return keys;
}

const SurfacePair* FrictionModel::find(std::string_view key) const {
  for (const auto& pair : pairs_) {
    if (pair.key == key) return &pair;
  }
  return nullptr;
}

std::optional<FrictionValue> FrictionModel::steady(std::string_view key, double temp_c) const {
  const SurfacePair* pair = find(key);
  if (pair == nullptr) return std::nullopt;
  return FrictionValue{interpolate(pair->points, temp_c, &FrictionPoint::mu_s),
                       interpolate(pair->points, temp_c, &FrictionPoint::mu_d), 1.0};
}

std::optional<FrictionValue> FrictionModel::effective(std::string_view key, double temp_c,
                                                      double seconds_since_change) const {
  auto value = steady(key, temp_c);
  if (!value) return std::nullopt;
  value->penalty = penalty_.multiplier(temp_c, seconds_since_change);
  value->mu_s *= value->penalty;
  value->mu_d *= value->penalty;
  return value;
}

std::vector<FrictionSample> FrictionModel::curve(std::string_view key, double t0, double t1,
                                                 double step, double seconds_since_change) const {
  std::vector<FrictionSample> samples;
  if (find(key) == nullptr || !(step > 0.0) || !std::isfinite(t0) || !std::isfinite(t1)) {
    return samples;
  }
  // By count, not by adding steps: where a step is below the temperatures' resolution (t0 = 1e300,
  // step 1) adding it never reaches t1.
  const double intervals = (t1 - t0) / step;
  if (!(intervals >= 0.0 && intervals <= 1e6)) return samples;
  const auto count = static_cast<std::size_t>(std::floor(intervals + 1e-9)) + 1;
  const double tolerance = step * 1e-9;
  for (std::size_t i = 0; i < count; ++i) {
    double t = t0 + static_cast<double>(i) * step;
    if (std::abs(t - t1) <= tolerance) t = t1;
    samples.push_back({t, *steady(key, t), *effective(key, t, seconds_since_change)});
  }
  return samples;
}

Result<ContactFriction> FrictionModel::for_pallet(const PalletConfig& config) const {
  const PalletTypeSpec& spec = pallet_type_spec(config.base_pallet_type);
  const std::string belt(to_string(config.belt_surface));
  ContactFriction out;
  out.belt_pallet_key = pair_key(spec.surface, belt);
  out.item_pallet_key = pair_key(kCarton, spec.surface);
  out.item_item_key = pair_key(kCarton, kCarton);

  Diagnostics diagnostics;
  if (find(out.belt_pallet_key) == nullptr) {
    std::vector<std::string> belts;
    for (const auto& entry : EnumTable<BeltSurface>::names) {
      if (find(pair_key(spec.surface, entry.name)) != nullptr) belts.emplace_back(entry.name);
    }
    error(diagnostics, "/belt_surface",
          std::string(spec.surface) + " on " + belt + " has no friction data; " +
              (belts.empty() ? "" : "use belt_surface " + join_or(belts) + ", or ") +
              "add the pair " + out.belt_pallet_key + " to " + std::string(kBeltTable));
  }
  if (find(out.item_pallet_key) == nullptr) {
    std::vector<std::string> types;
    for (const auto& entry : EnumTable<PalletType>::names) {
      if (find(pair_key(kCarton, pallet_type_spec(entry.value).surface)) != nullptr) {
        types.emplace_back(entry.name);
      }
    }
    error(diagnostics, "/base_pallet_type",
          "cartons on " + std::string(spec.surface) + " have no friction data; " +
              (types.empty() ? "" : "use base_pallet_type " + join_or(types) + ", or ") +
              "add the pair " + out.item_pallet_key + " to " + std::string(kItemTable));
  }
  if (find(out.item_item_key) == nullptr) {
    error(diagnostics, "",
          "cartons on cartons have no friction data; add the pair " + out.item_item_key + " to " +
              std::string(kItemTable));
  }
  if (!std::isfinite(config.body_temp_c)) {
    error(diagnostics, "/body_temp_c", "body_temp_c must be a finite temperature in Celsius");
  }
  if (!(config.seconds_since_temp_change >= 0.0)) {
    error(diagnostics, "/seconds_since_temp_change",
          "seconds_since_temp_change must be a number of seconds >= 0");
  }
  if (has_errors(diagnostics)) return Result<ContactFriction>::failure(std::move(diagnostics));

  const double t = config.body_temp_c;
  const double s = config.seconds_since_temp_change;
  out.belt_pallet = *effective(out.belt_pallet_key, t, s);
  out.item_pallet = *effective(out.item_pallet_key, t, s);
  out.item_item = *effective(out.item_item_key, t, s);
  return Result<ContactFriction>{std::move(out), {}};
}

}  // namespace pb
