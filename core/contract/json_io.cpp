// SPDX-License-Identifier: MIT
#include "core/contract/json_io.hpp"
#include "core/base/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <initializer_list>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "core/contract/json_reader.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/contract/pallet_type.hpp"

namespace pb {

namespace {

// Disagreement above which a stored computed field earns a warning.
constexpr double kComputedTolerance = 1e-6;

Json vec3_to_json(const Vec3& v) {
  return Json::array({v[0], v[1], v[2]});
}

std::string disagreement(std::string_view key, const std::string& stored,
                         const std::string& expected) {
  return std::string(key) + " is " + stored + " but the pallet gives " + expected +
         "; the recomputed value is used, so correct or remove the stored one";
}

// Checks an optional stored computed number against its recomputed value.
void check_computed(JsonReader& reader, const Json& object, const std::string& pointer,
                    std::string_view key, double expected) {
  const auto it = object.find(key);
  if (it == object.end()) return;
  const std::string where = member_pointer(pointer, key);
  if (!it->is_number()) {
    reader.warning(
        where, std::string(key) + " is not a number and is ignored (it is recomputed); remove it");
  } else if (!(std::abs(it->get<double>() - expected) <= kComputedTolerance)) {
    reader.warning(where, disagreement(key, it->dump(), short_number(expected)));
  }
}

void check_computed(JsonReader& reader, const Json& object, const std::string& pointer,
                    std::string_view key, const Vec3& expected) {
  const auto it = object.find(key);
  if (it == object.end()) return;
  const std::string where = member_pointer(pointer, key);
  JsonReader scratch;
  Vec3 stored{};
  if (!scratch.read(*it, where, stored)) {
    reader.warning(where, std::string(key) + " is not an array of 3 numbers and is ignored (it " +
                              "is recomputed); remove it");
    return;
  }
  for (std::size_t k = 0; k < 3; ++k) {
    if (!(std::abs(stored[k] - expected[k]) <= kComputedTolerance)) {
      reader.warning(where, disagreement(key, it->dump(), vec3_to_json(expected).dump()));
      return;
    }
  }
}

Json to_json_value(double value) {
  return value;
}
Json to_json_value(const std::optional<double>& value) {
  return value ? Json(*value) : Json(nullptr);
}
Json to_json_value(int value) {
  return value;
}
Json to_json_value(bool value) {
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
    f("curve_turn", profile.curve_turn, false);
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
    f("accel_item_tipped", result.accel_item_tipped, false);
    f("decel_item_tipped", result.decel_item_tipped, false);
    f("lateral_item_tipped", result.lateral_item_tipped, false);
    f("speed_item_tipped", result.speed_item_tipped, false);
    f("accel_load_as_one", result.accel_load_as_one, false);
    f("decel_load_as_one", result.decel_load_as_one, false);
    f("lateral_load_as_one", result.lateral_load_as_one, false);
    f("speed_load_as_one", result.speed_load_as_one, false);
    f("dominant_slide", result.dominant_slide, false);
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
bool read_fields(JsonReader& reader, const Json& json, const std::string& pointer, T& value,
                 Fields fields, std::initializer_list<std::string_view> extra) {
  std::vector<std::string_view> known(extra);
  fields(value, [&known](std::string_view key, auto&, bool) { known.push_back(key); });
  reader.unknown_keys(json, pointer, known);
  bool ok = true;
  fields(value, [&](std::string_view key, auto& member, bool required) {
    ok = reader.field(json, pointer, key, member, required ? Need::required : Need::optional) && ok;
  });
  return ok;
}

// A versioned document of one field table: an object, a schema_version, the fields.
template <class T, class Fields>
Result<T> read_document(const Json& json, const std::string& pointer, const char* what,
                        Fields fields) {
  JsonReader reader;
  T value;
  if (reader.object(json, pointer, what)) {
    reader.schema_version(json, pointer);
    read_fields(reader, json, pointer, value, fields, {"schema_version"});
  }
  return reader.finish(std::move(value));
}

template <class T, class Fields>
Json write_document(const T& value, Fields fields) {
  Json json = write_fields(value, fields);
  json["schema_version"] = kSchemaVersion;
  return json;
}

bool read_item(JsonReader& reader, const Json& json, const std::string& pointer, Item& item) {
  if (!reader.object(json, pointer, "an item")) return false;
  return read_fields(reader, json, pointer, item, ItemFields{}, {"center_of_mass"});
}

void read_items(JsonReader& reader, const Json& json, const std::string& pointer,
                std::vector<Item>& items) {
  if (!reader.array(json, pointer, "the items", "[ {...}, ... ]")) return;
  items.resize(json.size());
  for (std::size_t i = 0; i < json.size(); ++i) {
    read_item(reader, json[i], element_pointer(pointer, i), items[i]);
  }
}

void read_notes(JsonReader& reader, const Json& object, const std::string& pointer,
                std::string& notes) {
  const Json* value = reader.member(object, pointer, "notes", Need::optional);
  if (value == nullptr || value->is_null()) return;
  reader.read(*value, member_pointer(pointer, "notes"), notes);
}

void check_computed(JsonReader& reader, const Json& json, const std::string& pointer,
                    const PalletConfig& config) {
  check_computed(reader, json, pointer, "total_mass_kg", total_mass_kg(config));
  check_computed(reader, json, pointer, "composite_com_m", composite_com_m(config));
  check_computed(reader, json, pointer, "stack_height_m", stack_height_m(config));
  check_computed(reader, json, pointer, "overhang_m", overhang_m(config));
  const Json& items = json["items"];
  for (std::size_t i = 0; i < config.items.size(); ++i) {
    check_computed(reader, items[i], element_pointer(member_pointer(pointer, "items"), i),
                   "center_of_mass", config.items[i].center_of_mass());
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
  JsonReader reader;
  const std::string& p = pointer_prefix;
  if (!reader.object(json, p, "a pallet")) return reader.finish(PalletConfig{});
  reader.schema_version(json, p);
  reader.unknown_keys(
      json, p,
      {"schema_version", "pallet_id", "base_pallet_type", "base_dims_m", "base_mass_kg", "items",
       "wrap", "env", "body_temp_c", "seconds_since_temp_change", "notes", "belt_surface",
       "total_mass_kg", "composite_com_m", "stack_height_m", "overhang_m"});
  PalletConfig config;
  reader.field(json, p, "pallet_id", config.pallet_id);
  reader.field(json, p, "base_pallet_type", config.base_pallet_type);
  // An absent base is the named type's nominal one (a GMA pallet is not 1.2 x 0.8 m).
  const PalletTypeSpec& base = pallet_type_spec(config.base_pallet_type);
  config.base_dims_m = base.dims_m;
  config.base_mass_kg = base.mass_kg;
  reader.field(json, p, "base_dims_m", config.base_dims_m);
  reader.field(json, p, "base_mass_kg", config.base_mass_kg);
  if (const Json* items = reader.member(json, p, "items", Need::required)) {
    read_items(reader, *items, member_pointer(p, "items"), config.items);
  }
  // Required although the reference's example payloads always carry it: a load read as wrapped
  // when it is not would be given a wrapped load's limits (a silent, unsafe answer).
  if (json.contains("wrap")) {
    reader.field(json, p, "wrap", config.wrap);
  } else {
    reader.error(member_pointer(p, "wrap"),
                 "the required key 'wrap' is missing; add it: " + enum_choices<WrapType>() +
                     " (an unwrapped load is never assumed wrapped)");
  }
  reader.field(json, p, "env", config.env, Need::required);
  reader.field(json, p, "body_temp_c", config.body_temp_c, Need::required);
  reader.field(json, p, "seconds_since_temp_change", config.seconds_since_temp_change);
  read_notes(reader, json, p, config.notes);
  reader.field(json, p, "belt_surface", config.belt_surface);
  if (!has_errors(reader.diagnostics)) check_computed(reader, json, p, config);
  return reader.finish(std::move(config));
}

Result<ConveyorProfile> profile_from_json(const Json& json, const std::string& pointer_prefix) {
  auto read =
      read_document<ConveyorProfile>(json, pointer_prefix, "a conveyor profile", ProfileFields{});
  if (read.value && json.is_object() && !json.contains("duration_s")) {
    read.value->duration_s = default_duration_s(*read.value);
  }
  return read;
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

// Finds the first key that appears twice in one object, as a JSON pointer to it: readers
// disagree on which of the two wins (nlohmann keeps the last), so a document that repeats one
// says two things and is refused rather than read one way.
class DuplicateKeys {
 public:
  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        frames_.push_back({event == E::object_start, {}, {}, 0});
        break;
      case E::key: {
        Frame& f = frames_.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second && !duplicate_) duplicate_ = pointer();
        break;
      }
      case E::object_end:
      case E::array_end:
        frames_.pop_back();
        element_done();
        break;
      case E::value:
        element_done();
        break;
    }
    return true;
  }
  const std::optional<std::string>& duplicate() const { return duplicate_; }
  /// A JSON pointer to the value being read (the whole document before any).
  std::string pointer() const {
    std::string out;
    for (const Frame& f : frames_) {
      out = f.object ? member_pointer(out, f.key) : element_pointer(out, f.index);
    }
    return out;
  }

 private:
  struct Frame {
    bool object = true;
    std::set<std::string> keys;
    std::string key;        // the member being read (objects)
    std::size_t index = 0;  // the element being read (arrays)
  };
  void element_done() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }
  std::vector<Frame> frames_;
  std::optional<std::string> duplicate_;
};

}  // namespace

Result<Json> parse_json(std::string_view text) {
  if (text.size() > kMaxDocumentBytes) {
    return Result<Json>::failure(
        "", "the document is larger than " + std::to_string(kMaxDocumentBytes >> 20) +
                " MB, the most that is read; a pallet of 400 items is about 0.3 MB: check that "
                "this is the file you meant");
  }
  DuplicateKeys duplicates;
  try {
    Json json = Json::parse(text, std::ref(duplicates));
    if (const auto& at = duplicates.duplicate()) {
      return Result<Json>::failure(*at,
                                   "this member appears twice in its object; keep one (a "
                                   "reader may take either)");
    }
    return Result<Json>{std::move(json), {}};
  } catch (const Json::parse_error& e) {
    if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
      return Result<Json>::failure("",
                                   "the document is empty; send the pallet as a JSON object, "
                                   "{\"items\": [...], ...}");
    }
    // nlohmann stops at a NUL byte as at the end of the text ("unexpected end of input at byte
    // 1" for a file that is all there): name it, and what usually puts one there.
    if (const auto nul = text.find('\0'); nul != std::string_view::npos && nul + 1 <= e.byte) {
      return Result<Json>::failure(
          "", "the text has a NUL byte at byte " + std::to_string(nul + 1) +
                  ", which JSON never contains: the file is binary or not UTF-8 (UTF-16 puts one "
                  "beside every letter); save it as UTF-8 JSON");
    }
    // nlohmann's "[json.exception.parse_error.101] parse error at line 1, column 9: syntax error
    // while parsing value - ...": the position in words, then what it found.
    std::string detail = ascii(e.what());
    if (const auto at = detail.find("parse error at "); at != std::string::npos) {
      detail = detail.substr(at + 15);
    }
    return Result<Json>::failure("", "the text is not valid JSON at byte " +
                                         std::to_string(e.byte) + ", " + detail +
                                         "; fix the syntax there");
  } catch (const Json::exception& e) {
    // A number beyond a double's range (nlohmann's out_of_range 406) has no position in the
    // exception, but the callback has seen the value's key or index.
    if (e.id == 406) {
      // "[json.exception.out_of_range.406] number overflow parsing '1e999'": the number itself.
      std::string number = ascii(e.what());
      if (const auto at = number.find('\''); at != std::string::npos) {
        number = number.substr(at + 1, number.rfind('\'') - at - 1);
      }
      return Result<Json>::failure(duplicates.pointer(),
                                   "the number " + number +
                                       " is beyond what can be read (about 1.8e308); write the "
                                       "value the field means, in its range");
    }
    return Result<Json>::failure(
        "", "the text could not be read as JSON (" + ascii(e.what()) + "); fix the document");
  }
}

std::string to_canonical_text(const Json& json) {
  // Replacing invalid UTF-8 (instead of throwing) keeps this total; valid text is unchanged.
  return json.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace pb
