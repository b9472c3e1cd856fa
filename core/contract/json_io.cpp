// SPDX-License-Identifier: MIT
#include "core/contract/json_io.hpp"
#include "core/base/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "core/contract/pallet_metrics.hpp"

namespace pb {

namespace {

// Disagreement above which a stored computed field earns a warning.
constexpr double kComputedTolerance = 1e-6;

Json vec3_to_json(const Vec3& v) {
  return Json::array({v[0], v[1], v[2]});
}

std::string key_pointer(const std::string& pointer, std::string_view key) {
  return pointer + "/" + json_pointer_token(key);
}

std::string type_name(const Json& json) {
  return json.type_name();
}

// The value of a JSON integer that fits in 64 signed bits, or nullopt.
std::optional<std::int64_t> as_integer(const Json& json) {
  if (json.is_number_unsigned()) {
    const auto value = json.get<std::uint64_t>();
    if (value > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return {};
    return static_cast<std::int64_t>(value);
  }
  if (json.is_number_integer()) return json.get<std::int64_t>();
  return {};
}

// Collects the diagnostics of one read; every read_* records what is wrong and returns false.
class Reader {
 public:
  Diagnostics diagnostics;

  void error(std::string pointer, std::string message) {
    diagnostics.push_back({std::move(pointer), std::move(message), Severity::error});
  }
  void warning(std::string pointer, std::string message) {
    diagnostics.push_back({std::move(pointer), std::move(message), Severity::warning});
  }

  bool read(const Json& json, const std::string& pointer, double& out) {
    if (!json.is_number()) {
      error(pointer, "expected a number, found " + type_name(json) + "; write a plain number");
      return false;
    }
    out = json.get<double>();
    return true;
  }

  bool read(const Json& json, const std::string& pointer, int& out) {
    const auto value = as_integer(json);
    if (!value || *value < std::numeric_limits<int>::min() ||
        *value > std::numeric_limits<int>::max()) {
      error(pointer, "expected a whole number, found " +
                         (value ? "one out of range" : type_name(json)) +
                         "; write an integer such as 0");
      return false;
    }
    out = static_cast<int>(*value);
    return true;
  }

  bool read(const Json& json, const std::string& pointer, std::string& out) {
    if (!json.is_string()) {
      error(pointer, "expected a string, found " + type_name(json) + "; write it in quotes");
      return false;
    }
    out = json.get<std::string>();
    return true;
  }

  bool read(const Json& json, const std::string& pointer, Vec3& out) {
    if (!json.is_array() || json.size() != 3) {
      error(pointer,
            "expected an array of exactly 3 numbers [x, y, z], found " +
                (json.is_array() ? "an array of " + std::to_string(json.size()) : type_name(json)) +
                "; write three numbers");
      return false;
    }
    bool ok = true;
    for (std::size_t k = 0; k < 3; ++k) {
      ok = read(json[k], pointer + "/" + std::to_string(k), out[k]) && ok;
    }
    return ok;
  }

  template <class E>
  requires std::is_enum_v<E>
  bool read(const Json& json, const std::string& pointer, E& out) {
    const auto value =
        json.is_string() ? enum_from_string<E>(json.get<std::string>()) : std::optional<E>{};
    if (!value) {
      error(pointer, (json.is_string() ? "'" + json.get<std::string>() + "' is not a valid choice"
                                       : "expected a string, found " + type_name(json)) +
                         "; use one of " + enum_choices<E>());
      return false;
    }
    out = *value;
    return true;
  }

  /// Reads `key` of `object` into `out` if present; an absent required key is an error.
  template <class T>
  bool field(const Json& object, const std::string& pointer, std::string_view key, T& out,
             bool required = false) {
    const auto it = object.find(key);
    if (it == object.end()) {
      if (required) {
        error(pointer, "the required key '" + std::string(key) + "' is missing; add it");
      }
      return !required;
    }
    return read(*it, key_pointer(pointer, key), out);
  }

  /// Reads an optional "schema_version": an integer no newer than kSchemaVersion.
  void schema_version(const Json& object, const std::string& pointer) {
    const auto it = object.find("schema_version");
    if (it == object.end()) return;
    const std::string where = key_pointer(pointer, "schema_version");
    const std::string supported = "use a version from 1 to " + std::to_string(kSchemaVersion);
    const auto version = as_integer(*it);
    if (!version) {
      error(where, "schema_version must be an integer, found " + type_name(*it) + "; " + supported);
    } else if (*version < 1 || *version > kSchemaVersion) {
      error(where, "schema_version " + std::to_string(*version) +
                       " is not one this program reads; " + supported +
                       (*version > kSchemaVersion ? ", or update the program" : ""));
    }
  }

  /// Warns about every key of `object` not in `known`.
  void unknown_keys(const Json& object, const std::string& pointer,
                    const std::vector<std::string_view>& known) {
    for (const auto& [key, value] : object.items()) {
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        warning(key_pointer(pointer, key),
                "unknown key '" + key + "' is ignored; check its spelling");
      }
    }
  }

  /// Checks an optional stored computed number against its recomputed value.
  void computed(const Json& object, const std::string& pointer, std::string_view key,
                double expected) {
    const auto it = object.find(key);
    if (it == object.end()) return;
    const std::string where = key_pointer(pointer, key);
    if (!it->is_number()) {
      warning(where, std::string(key) + " is not a number and is ignored (it is recomputed); " +
                         "remove it");
    } else if (!(std::abs(it->get<double>() - expected) <= kComputedTolerance)) {
      warning(where, disagreement(key, it->dump(), short_number(expected)));
    }
  }

  void computed(const Json& object, const std::string& pointer, std::string_view key,
                const Vec3& expected) {
    const auto it = object.find(key);
    if (it == object.end()) return;
    const std::string where = key_pointer(pointer, key);
    Reader scratch;
    Vec3 stored{};
    if (!scratch.read(*it, where, stored)) {
      warning(where, std::string(key) + " is not an array of 3 numbers and is ignored (it is " +
                         "recomputed); remove it");
      return;
    }
    for (std::size_t k = 0; k < 3; ++k) {
      if (!(std::abs(stored[k] - expected[k]) <= kComputedTolerance)) {
        warning(where, disagreement(key, it->dump(), vec3_to_json(expected).dump()));
        return;
      }
    }
  }

 private:
  static std::string disagreement(std::string_view key, const std::string& stored,
                                  const std::string& expected) {
    return std::string(key) + " is " + stored + " but the pallet gives " + expected +
           "; the recomputed value is used, so correct or remove the stored one";
  }
};

bool require_object(Reader& reader, const Json& json, const std::string& pointer,
                    const char* what) {
  if (json.is_object()) return true;
  reader.error(pointer, std::string("expected ") + what + " as a JSON object, found " +
                            type_name(json) + "; write it as {\"key\": value, ...}");
  return false;
}

template <class T>
Result<T> finish(Reader& reader, T value) {
  if (has_errors(reader.diagnostics)) return Result<T>::failure(std::move(reader.diagnostics));
  return Result<T>{std::move(value), std::move(reader.diagnostics)};
}

Json to_json_value(double value) {
  return value;
}
Json to_json_value(int value) {
  return value;
}
Json to_json_value(const std::string& value) {
  return value;
}
Json to_json_value(const Vec3& value) {
  return vec3_to_json(value);
}
template <class E>
requires std::is_enum_v<E> Json to_json_value(E value) {
  return to_string(value);
}

// Field tables: each calls f(key, member, required) for every stored field, in document order,
// so that writing, reading and the list of known keys cannot drift apart. `T` is const for
// writing.
struct ItemFields {
  template <class T, class F>
  void operator()(T& item, F&& f) const {
    f("sku", item.sku, true);
    f("weight_kg", item.weight_kg, true);
    f("dims_m", item.dims_m, true);
    f("fragility", item.fragility, false);
    f("position", item.position, true);
    f("orientation_deg", item.orientation_deg, false);
  }
};

struct ProfileFields {
  template <class T, class F>
  void operator()(T& profile, F&& f) const {
    f("target_speed_mps", profile.target_speed_mps, false);
    f("accel_mps2", profile.accel_mps2, false);
    f("duration_s", profile.duration_s, false);
    f("shape", profile.shape, false);
    f("decel_start_s", profile.decel_start_s, false);
    f("decel_mps2", profile.decel_mps2, false);
    f("curve_radius_m", profile.curve_radius_m, false);
    f("curve_angle_deg", profile.curve_angle_deg, false);
    f("curve_start_s", profile.curve_start_s, false);
    f("eumos_g", profile.eumos_g, false);
    f("eumos_hold_s", profile.eumos_hold_s, false);
  }
};

// The reference's fields are required (its model has no defaults); ours are optional.
struct SafetyResultFields {
  template <class T, class F>
  void operator()(T& result, F&& f) const {
    f("pallet_id", result.pallet_id, true);
    f("max_speed_mps", result.max_speed_mps, true);
    f("max_accel_mps2", result.max_accel_mps2, true);
    f("max_decel_mps2", result.max_decel_mps2, true);
    f("max_lateral_g", result.max_lateral_g, true);
    f("dominant_failure_mode", result.dominant_failure_mode, true);
    f("margin_pct", result.margin_pct, true);
    f("confidence", result.confidence, true);
    f("sim_runtime_ms", result.sim_runtime_ms, true);
    f("config_hash", result.config_hash, true);
    f("sims_run", result.sims_run, false);
    f("accel_mode", result.accel_mode, false);
    f("decel_mode", result.decel_mode, false);
    f("lateral_mode", result.lateral_mode, false);
    f("speed_mode", result.speed_mode, false);
    f("speed_governed_by", result.speed_governed_by, false);
    f("verdict", result.verdict, false);
    f("reason", result.reason, false);
    f("line_estop_decel_mps2", result.line_estop_decel_mps2, false);
    f("line_curve_radius_m", result.line_curve_radius_m, false);
    f("fidelity", result.fidelity, false);
  }
};

template <class T, class Fields>
Json write_fields(const T& value, Fields fields) {
  Json json = Json::object();
  fields(value, [&json](std::string_view key, const auto& member, bool) {
    json[std::string(key)] = to_json_value(member);
  });
  return json;
}

// Reads every field of the table into `value`, warning about keys outside the table and `extra`.
// Returns whether every field was read.
template <class T, class Fields>
bool read_fields(Reader& reader, const Json& json, const std::string& pointer, T& value,
                 Fields fields, std::initializer_list<std::string_view> extra) {
  std::vector<std::string_view> known(extra);
  fields(value, [&known](std::string_view key, auto&, bool) { known.push_back(key); });
  reader.unknown_keys(json, pointer, known);
  bool ok = true;
  fields(value, [&](std::string_view key, auto& member, bool required) {
    ok = reader.field(json, pointer, key, member, required) && ok;
  });
  return ok;
}

// A versioned document of one field table: an object, a schema_version, the fields.
template <class T, class Fields>
Result<T> read_document(const Json& json, const std::string& pointer, const char* what,
                        Fields fields) {
  Reader reader;
  T value;
  if (require_object(reader, json, pointer, what)) {
    reader.schema_version(json, pointer);
    read_fields(reader, json, pointer, value, fields, {"schema_version"});
  }
  return finish(reader, std::move(value));
}

template <class T, class Fields>
Json write_document(const T& value, Fields fields) {
  Json json = write_fields(value, fields);
  json["schema_version"] = kSchemaVersion;
  return json;
}

bool read_item(Reader& reader, const Json& json, const std::string& pointer, Item& item) {
  if (!require_object(reader, json, pointer, "an item")) return false;
  return read_fields(reader, json, pointer, item, ItemFields{}, {"center_of_mass"});
}

void read_items(Reader& reader, const Json& json, const std::string& pointer,
                std::vector<Item>& items) {
  if (!json.is_array()) {
    reader.error(pointer, "expected an array of items, found " + type_name(json) +
                              "; write \"items\": [ {...}, ... ]");
    return;
  }
  items.resize(json.size());
  for (std::size_t i = 0; i < json.size(); ++i) {
    read_item(reader, json[i], pointer + "/" + std::to_string(i), items[i]);
  }
}

void read_notes(Reader& reader, const Json& object, const std::string& pointer,
                std::string& notes) {
  const auto it = object.find("notes");
  if (it == object.end() || it->is_null()) return;
  reader.read(*it, key_pointer(pointer, "notes"), notes);
}

void check_computed(Reader& reader, const Json& json, const std::string& pointer,
                    const PalletConfig& config) {
  reader.computed(json, pointer, "total_mass_kg", total_mass_kg(config));
  reader.computed(json, pointer, "composite_com_m", composite_com_m(config));
  reader.computed(json, pointer, "stack_height_m", stack_height_m(config));
  reader.computed(json, pointer, "overhang_m", overhang_m(config));
  const Json& items = json["items"];
  for (std::size_t i = 0; i < config.items.size(); ++i) {
    reader.computed(items[i], pointer + "/items/" + std::to_string(i), "center_of_mass",
                    config.items[i].center_of_mass());
  }
}

}  // namespace

Json item_to_json(const Item& item, bool computed) {
  Json json = write_fields(item, ItemFields{});
  if (computed) json["center_of_mass"] = vec3_to_json(item.center_of_mass());
  return json;
}

Json pallet_to_json(const PalletConfig& config, bool computed) {
  Json items = Json::array();
  for (const Item& item : config.items) items.push_back(item_to_json(item, computed));
  Json json = {{"schema_version", kSchemaVersion},
               {"pallet_id", config.pallet_id},
               {"base_pallet_type", to_string(config.base_pallet_type)},
               {"base_dims_m", vec3_to_json(config.base_dims_m)},
               {"base_mass_kg", config.base_mass_kg},
               {"items", std::move(items)},
               {"wrap", to_string(config.wrap)},
               {"env", to_string(config.env)},
               {"body_temp_c", config.body_temp_c},
               {"seconds_since_temp_change", config.seconds_since_temp_change},
               {"notes", config.notes.empty() ? Json(nullptr) : Json(config.notes)},
               {"belt_surface", to_string(config.belt_surface)}};
  if (computed) {
    json["total_mass_kg"] = total_mass_kg(config);
    json["composite_com_m"] = vec3_to_json(composite_com_m(config));
    json["stack_height_m"] = stack_height_m(config);
    json["overhang_m"] = overhang_m(config);
  }
  return json;
}

Json profile_to_json(const ConveyorProfile& profile) {
  return write_document(profile, ProfileFields{});
}

namespace {
// A load that cannot stand has no conveyor limit: these are null in its JSON, never a 0 that
// reads like a speed.
constexpr const char* kLimitKeys[] = {"max_speed_mps", "max_accel_mps2", "max_decel_mps2",
                                      "max_lateral_g", "margin_pct"};
}  // namespace

Json safety_result_to_json(const SafetyResult& result) {
  Json json = write_document(result, SafetyResultFields{});
  if (result.dominant_failure_mode == FailureMode::cannot_stand) {
    for (const char* key : kLimitKeys) json[key] = nullptr;
  }
  return json;
}

Result<PalletConfig> pallet_from_json(const Json& json, const std::string& pointer_prefix) {
  Reader reader;
  const std::string& p = pointer_prefix;
  if (!require_object(reader, json, p, "a pallet")) return finish(reader, PalletConfig{});
  reader.schema_version(json, p);
  reader.unknown_keys(
      json, p,
      {"schema_version", "pallet_id", "base_pallet_type", "base_dims_m", "base_mass_kg", "items",
       "wrap", "env", "body_temp_c", "seconds_since_temp_change", "notes", "belt_surface",
       "total_mass_kg", "composite_com_m", "stack_height_m", "overhang_m"});
  PalletConfig config;
  reader.field(json, p, "pallet_id", config.pallet_id);
  reader.field(json, p, "base_pallet_type", config.base_pallet_type);
  reader.field(json, p, "base_dims_m", config.base_dims_m);
  reader.field(json, p, "base_mass_kg", config.base_mass_kg);
  if (const auto it = json.find("items"); it != json.end()) {
    read_items(reader, *it, key_pointer(p, "items"), config.items);
  } else {
    reader.error(p, "the required key 'items' is missing; add \"items\": [] or a list of items");
  }
  reader.field(json, p, "wrap", config.wrap);
  reader.field(json, p, "env", config.env, true);
  reader.field(json, p, "body_temp_c", config.body_temp_c, true);
  reader.field(json, p, "seconds_since_temp_change", config.seconds_since_temp_change);
  read_notes(reader, json, p, config.notes);
  reader.field(json, p, "belt_surface", config.belt_surface);
  if (!has_errors(reader.diagnostics)) check_computed(reader, json, p, config);
  return finish(reader, std::move(config));
}

Result<ConveyorProfile> profile_from_json(const Json& json, const std::string& pointer_prefix) {
  return read_document<ConveyorProfile>(json, pointer_prefix, "a conveyor profile",
                                        ProfileFields{});
}

Result<SafetyResult> safety_result_from_json(const Json& json, const std::string& pointer_prefix) {
  const auto mode = json.is_object() ? json.find("dominant_failure_mode") : json.end();
  if (mode != json.end() && *mode == "cannot_stand") {
    Json limits_zero = json;
    for (const char* key : kLimitKeys) {
      if (auto it = limits_zero.find(key); it != limits_zero.end() && it->is_null()) *it = 0.0;
    }
    return read_document<SafetyResult>(limits_zero, pointer_prefix, "a safety result",
                                       SafetyResultFields{});
  }
  return read_document<SafetyResult>(json, pointer_prefix, "a safety result", SafetyResultFields{});
}

namespace {

// nlohmann's messages quote what they last read, invalid UTF-8 included: a message must stay text
// that can itself be written as JSON, so bytes outside ASCII are shown as '?'.
std::string ascii(std::string_view message) {
  std::string out(message);
  for (char& c : out) {
    if (static_cast<unsigned char>(c) >= 0x80) c = '?';
  }
  return out;
}

}  // namespace

Result<Json> parse_json(std::string_view text) {
  if (text.size() > kMaxDocumentBytes) {
    return Result<Json>::failure(
        "", "the document is larger than " + std::to_string(kMaxDocumentBytes >> 20) +
                " MB, the most that is read; a pallet of 400 items is about 0.3 MB: check that "
                "this is the file you meant");
  }
  try {
    return Result<Json>{Json::parse(text), {}};
  } catch (const Json::parse_error& e) {
    return Result<Json>::failure("", "the text is not valid JSON at byte " +
                                         std::to_string(e.byte) + " (" + ascii(e.what()) +
                                         "); fix the syntax there");
  } catch (const Json::exception& e) {
    return Result<Json>::failure(
        "", "the text could not be read as JSON (" + ascii(e.what()) + "); fix the document");
  }
}

std::string to_canonical_text(const Json& json) {
  // Replacing invalid UTF-8 (instead of throwing) keeps this total; valid text is unchanged.
  return json.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace pb
