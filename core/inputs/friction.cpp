// SPDX-License-Identifier: MIT
#include "core/inputs/friction.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "core/base/resources.hpp"
#include "core/contract/pallet_type.hpp"

namespace pb {

namespace {

using Json = nlohmann::json;

constexpr double kMuMax = 2.0;
constexpr std::string_view kBeltTable = "resources/friction_table.json";
constexpr std::string_view kItemTable = "resources/friction_items.json";
constexpr std::string_view kCarton = "carton";

void error(Diagnostics& out, std::string pointer, std::string message) {
  out.push_back({std::move(pointer), std::move(message), Severity::error});
}

// Warns about keys that are neither known nor comments ("_comment", "_units", ...).
void warn_unknown_keys(const Json& object, std::initializer_list<std::string_view> known,
                       const std::string& where, Diagnostics& out) {
  for (const auto& [key, value] : object.items()) {
    if (key.starts_with('_') || std::find(known.begin(), known.end(), key) != known.end()) continue;
    out.push_back({where + "/" + json_pointer_token(key),
                   "unknown key '" + key + "' is ignored; remove it or prefix it with '_'",
                   Severity::warning});
  }
}

// The finite number `object[name]`, or nullopt with an error.
std::optional<double> read_number(const Json& object, const char* name, const std::string& where,
                                  Diagnostics& out) {
  const std::string pointer = where + "/" + name;
  const auto it = object.find(name);
  if (it == object.end()) {
    error(out, pointer, std::string("'") + name + "' is missing; add it as a number");
    return std::nullopt;
  }
  if (!it->is_number() || !std::isfinite(it->get<double>())) {
    error(out, pointer, std::string("'") + name + "' must be a finite number");
    return std::nullopt;
  }
  return it->get<double>();
}

// An optional string member; an error if present and not a string.
std::string read_text(const Json& object, const char* name, const std::string& where,
                      Diagnostics& out) {
  const auto it = object.find(name);
  if (it == object.end()) return {};
  if (!it->is_string()) {
    error(out, where + "/" + name, std::string("'") + name + "' must be a string");
    return {};
  }
  return it->get<std::string>();
}

bool mu_in_range(double mu) {
  return mu >= 0.0 && mu <= kMuMax;
}

std::optional<FrictionPoint> read_point(const Json& json, const std::string& where,
                                        Diagnostics& out) {
  if (!json.is_object()) {
    error(out, where, "a control point must be an object {\"temp_c\", \"mu_s\", \"mu_d\"}");
    return std::nullopt;
  }
  warn_unknown_keys(json, {"temp_c", "mu_s", "mu_d"}, where, out);
  const auto temp = read_number(json, "temp_c", where, out);
  const auto mu_s = read_number(json, "mu_s", where, out);
  const auto mu_d = read_number(json, "mu_d", where, out);
  if (!temp || !mu_s || !mu_d) return std::nullopt;
  bool ok = true;
  for (const auto& [name, mu] : {std::pair{"mu_s", *mu_s}, std::pair{"mu_d", *mu_d}}) {
    if (mu_in_range(mu)) continue;
    error(out, where + "/" + name,
          std::string(name) + " is " + std::to_string(mu) + "; a friction coefficient must be in " +
              "[0, 2]");
    ok = false;
  }
  if (ok && *mu_d > *mu_s) {
    error(out, where + "/mu_d",
          "mu_d (" + std::to_string(*mu_d) + ") is above mu_s (" + std::to_string(*mu_s) +
              "); dynamic friction cannot exceed static friction, lower mu_d or raise mu_s");
    ok = false;
  }
  if (!ok) return std::nullopt;
  return FrictionPoint{*temp, *mu_s, *mu_d};
}

// Reads "control_points": at least one, strictly increasing temp_c.
std::vector<FrictionPoint> read_points(const Json& pair, const std::string& where,
                                       Diagnostics& out) {
  const std::string pointer = where + "/control_points";
  const auto it = pair.find("control_points");
  if (it == pair.end() || !it->is_array() || it->empty()) {
    error(out, pointer,
          "'control_points' must be a non-empty array of {\"temp_c\", \"mu_s\", \"mu_d\"}");
    return {};
  }
  std::vector<FrictionPoint> points;
  bool ok = true;
  for (std::size_t i = 0; i < it->size(); ++i) {
    const std::string point_where = pointer + "/" + std::to_string(i);
    const auto point = read_point((*it)[i], point_where, out);
    if (!point) {
      ok = false;
      continue;
    }
    if (!points.empty() && point->temp_c <= points.back().temp_c) {
      error(out, point_where + "/temp_c",
            "temp_c " + std::to_string(point->temp_c) + " does not follow " +
                std::to_string(points.back().temp_c) +
                "; list control points in strictly increasing temperature");
      ok = false;
    }
    points.push_back(*point);
  }
  if (!ok) return {};
  return points;
}

std::optional<SurfacePair> read_pair(const std::string& key, const Json& json, Diagnostics& out) {
  const std::string where = "/surface_pairs/" + json_pointer_token(key);
  const auto slash = key.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == key.size() ||
      key.find('/', slash + 1) != std::string::npos) {
    error(out, where,
          "surface pair key '" + key +
              "' must name two surfaces as 'lower/upper' (e.g. 'wood_pallet/rubber_belt')");
    return std::nullopt;
  }
  if (!json.is_object()) {
    error(out, where, "a surface pair must be an object with 'control_points'");
    return std::nullopt;
  }
  warn_unknown_keys(json, {"description", "source", "control_points"}, where, out);
  const std::size_t errors_before = errors_of(out).size();
  SurfacePair pair;
  pair.key = key;
  pair.description = read_text(json, "description", where, out);
  pair.source = read_text(json, "source", where, out);
  pair.points = read_points(json, where, out);
  if (errors_of(out).size() != errors_before) return std::nullopt;
  return pair;
}

std::optional<FrostMeltPenalty> read_penalty(const Json& json, Diagnostics& out) {
  const std::string where = "/transition_penalty";
  if (!json.is_object()) {
    error(out, where,
          "'transition_penalty' must be an object with danger_zone_temp_c, min_multiplier and "
          "recovery_seconds");
    return std::nullopt;
  }
  warn_unknown_keys(json, {"danger_zone_temp_c", "min_multiplier", "recovery_seconds"}, where, out);
  const std::size_t errors_before = errors_of(out).size();
  FrostMeltPenalty penalty;
  const std::string zone_where = where + "/danger_zone_temp_c";
  const auto zone = json.find("danger_zone_temp_c");
  if (zone == json.end() || !zone->is_array() || zone->size() != 2 || !(*zone)[0].is_number() ||
      !(*zone)[1].is_number()) {
    error(out, zone_where, "'danger_zone_temp_c' must be an array of two numbers [low, high]");
  } else {
    penalty.zone_lo_c = (*zone)[0].get<double>();
    penalty.zone_hi_c = (*zone)[1].get<double>();
    if (!std::isfinite(penalty.zone_lo_c) || !std::isfinite(penalty.zone_hi_c) ||
        !(penalty.zone_lo_c < penalty.zone_hi_c)) {
      error(out, zone_where,
            "the danger zone must be finite with low < high; it is [" +
                std::to_string(penalty.zone_lo_c) + ", " + std::to_string(penalty.zone_hi_c) + "]");
    }
  }
  if (const auto min = read_number(json, "min_multiplier", where, out)) {
    penalty.min_multiplier = *min;
    if (!(*min > 0.0 && *min <= 1.0)) {
      error(out, where + "/min_multiplier",
            "min_multiplier is " + std::to_string(*min) + "; it must be in (0, 1]");
    }
  }
  if (const auto recovery = read_number(json, "recovery_seconds", where, out)) {
    penalty.recovery_s = *recovery;
    if (!(*recovery > 0.0)) {
      error(out, where + "/recovery_seconds",
            "recovery_seconds is " + std::to_string(*recovery) + "; it must be above 0");
    }
  }
  if (errors_of(out).size() != errors_before) return std::nullopt;
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
  Diagnostics out;
  const Json json = Json::parse(text, nullptr, false);
  if (json.is_discarded()) {
    error(out, "", "the friction table is not valid JSON; fix its syntax");
    return out;
  }
  if (!json.is_object()) {
    error(out, "", "a friction table must be a JSON object with 'surface_pairs'");
    return out;
  }
  warn_unknown_keys(json, {"surface_pairs", "transition_penalty"}, "", out);
  const auto pairs = json.find("surface_pairs");
  if (pairs == json.end() || !pairs->is_object()) {
    error(out, "/surface_pairs",
          "'surface_pairs' must be an object mapping 'lower/upper' keys to surface pairs");
    return out;
  }
  std::vector<SurfacePair> read;
  for (const auto& [key, value] : pairs->items()) {
    if (find(key) != nullptr) {
      error(out, "/surface_pairs/" + json_pointer_token(key),
            "surface pair '" + key + "' is already defined by an earlier table; keep one of them");
      continue;
    }
    if (auto pair = read_pair(key, value, out)) read.push_back(std::move(*pair));
  }
  std::optional<FrostMeltPenalty> penalty;
  if (const auto it = json.find("transition_penalty"); it != json.end()) {
    penalty = read_penalty(*it, out);
    if (penalty && has_penalty_) {
      out.push_back({"/transition_penalty",
                     "the transition penalty of an earlier table applies and this one is "
                     "ignored; remove it or merge the tables",
                     Severity::warning});
    }
  }
  if (has_errors(out)) return out;
  std::move(read.begin(), read.end(), std::back_inserter(pairs_));
  if (penalty && !has_penalty_) {
    penalty_ = *penalty;
    has_penalty_ = true;
  }
  return out;
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
  const double tolerance = step * 1e-9;
  for (std::size_t i = 0;; ++i) {
    double t = t0 + static_cast<double>(i) * step;
    if (t > t1 + tolerance) break;
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
