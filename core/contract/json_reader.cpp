// SPDX-License-Identifier: MIT
#include "core/contract/json_reader.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "core/base/text.hpp"
#include "core/contract/pallet_config.hpp"

namespace pb {

namespace wording {

std::string wrong_type(std::string_view expected, std::string_view found, std::string_view remedy) {
  return "expected " + std::string(expected) + ", found " + std::string(found) + "; " +
         std::string(remedy);
}

std::string missing_key(std::string_view key) {
  return "the required key '" + std::string(key) + "' is missing; add it";
}

std::string unknown_key(std::string_view key) {
  return "unknown key '" + std::string(key) + "' is ignored; remove it or fix its spelling";
}

std::string not_a_choice(std::string_view value, std::string_view choices) {
  return "'" + std::string(value) + "' is not a valid choice; use one of " + std::string(choices);
}

std::string out_of_range(std::string_view value, std::string_view allowed) {
  return std::string(value) + " is out of range; write " + std::string(allowed);
}

}  // namespace wording

std::string join_choices(std::span<const std::string_view> names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += (i + 1 == names.size()) ? " or " : ", ";
    out += names[i];
  }
  return out;
}

std::string member_pointer(const std::string& pointer, std::string_view key) {
  return pointer + "/" + json_pointer_token(key);
}

std::string element_pointer(const std::string& pointer, std::size_t index) {
  return pointer + "/" + std::to_string(index);
}

namespace {

// The value of a JSON integer that fits in 64 signed bits, or nullopt.
std::optional<std::int64_t> as_int64(const Json& json) {
  if (json.is_number_unsigned()) {
    const auto value = json.get<std::uint64_t>();
    if (value > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return {};
    return static_cast<std::int64_t>(value);
  }
  if (json.is_number_integer()) return json.get<std::int64_t>();
  return {};
}

constexpr std::string_view kWholeNumber = "a whole number";
constexpr std::string_view kWriteInteger = "write an integer such as 0";

}  // namespace

void JsonReader::error(std::string pointer, std::string message) {
  diagnostics.push_back({std::move(pointer), std::move(message), Severity::error});
}

void JsonReader::warning(std::string pointer, std::string message) {
  diagnostics.push_back({std::move(pointer), std::move(message), Severity::warning});
}

void JsonReader::merge(const Diagnostics& more) {
  diagnostics.insert(diagnostics.end(), more.begin(), more.end());
}

std::size_t JsonReader::error_count() const {
  return static_cast<std::size_t>(
      std::count_if(diagnostics.begin(), diagnostics.end(),
                    [](const Diagnostic& d) { return d.severity == Severity::error; }));
}

std::string JsonReader::found(const Json& json) {
  if (json.is_number()) return "number " + json.dump();
  return json.type_name();
}

bool JsonReader::read(const Json& json, const std::string& pointer, std::optional<double>& out) {
  if (json.is_null()) {
    out.reset();
    return true;
  }
  double value = 0.0;
  if (!read(json, pointer, value)) return false;
  out = value;
  return true;
}

bool JsonReader::read(const Json& json, const std::string& pointer, double& out) {
  if (!json.is_number()) {
    error(pointer, wording::wrong_type("a number", found(json), "write a plain number"));
    return false;
  }
  const double value = json.get<double>();
  if (!std::isfinite(value)) {  // only a Json built in code: parsing refuses 1e400
    error(pointer, wording::out_of_range(short_number(value), "a finite number"));
    return false;
  }
  out = value;
  return true;
}

bool JsonReader::read(const Json& json, const std::string& pointer, int& out) {
  if (!json.is_number_integer()) {
    error(pointer, wording::wrong_type(kWholeNumber, found(json), kWriteInteger));
    return false;
  }
  const auto value = as_int64(json);
  if (!value || *value < std::numeric_limits<int>::min() ||
      *value > std::numeric_limits<int>::max()) {
    error(pointer, wording::out_of_range(
                       json.dump(), "a whole number from " +
                                        std::to_string(std::numeric_limits<int>::min()) + " to " +
                                        std::to_string(std::numeric_limits<int>::max())));
    return false;
  }
  out = static_cast<int>(*value);
  return true;
}

bool JsonReader::read(const Json& json, const std::string& pointer, std::uint64_t& out) {
  if (!json.is_number_integer()) {
    error(pointer, wording::wrong_type(kWholeNumber, found(json), kWriteInteger));
    return false;
  }
  if (!json.is_number_unsigned()) {  // nlohmann keeps a negative integer signed
    error(pointer, wording::out_of_range(json.dump(), "a whole number >= 0"));
    return false;
  }
  out = json.get<std::uint64_t>();
  return true;
}

bool JsonReader::read(const Json& json, const std::string& pointer, bool& out) {
  if (!json.is_boolean()) {
    error(pointer, wording::wrong_type("true or false", found(json), "write true or false"));
    return false;
  }
  out = json.get<bool>();
  return true;
}

bool JsonReader::read(const Json& json, const std::string& pointer, std::string& out) {
  if (!json.is_string()) {
    error(pointer, wording::wrong_type("a string", found(json), "write it in quotes"));
    return false;
  }
  out = json.get<std::string>();
  return true;
}

bool JsonReader::read(const Json& json, const std::string& pointer, std::array<double, 3>& out) {
  return numbers(json, pointer, out, "[x, y, z]");
}

bool JsonReader::numbers(const Json& json, const std::string& pointer, std::span<double> out,
                         std::string_view layout) {
  const std::string n = std::to_string(out.size());
  if (!json.is_array() || json.size() != out.size()) {
    error(pointer, wording::wrong_type(
                       "an array of exactly " + n + " numbers " + std::string(layout),
                       json.is_array() ? "an array of " + std::to_string(json.size()) : found(json),
                       "write " + n + " numbers"));
    return false;
  }
  bool ok = true;
  for (std::size_t k = 0; k < out.size(); ++k) {
    ok = read(json[k], element_pointer(pointer, k), out[k]) && ok;
  }
  return ok;
}

bool JsonReader::choice(const Json& json, const std::string& pointer,
                        std::span<const std::string_view> choices, std::size_t& index) {
  if (!json.is_string()) {
    error(pointer,
          wording::wrong_type("a string", found(json), "use one of " + join_choices(choices)));
    return false;
  }
  const auto& text = json.get_ref<const std::string&>();
  const auto it = std::find(choices.begin(), choices.end(), text);
  if (it == choices.end()) {
    error(pointer, wording::not_a_choice(text, join_choices(choices)));
    return false;
  }
  index = static_cast<std::size_t>(it - choices.begin());
  return true;
}

bool JsonReader::object(const Json& json, const std::string& pointer, std::string_view what,
                        std::string_view layout) {
  if (json.is_object()) return true;
  error(pointer, wording::wrong_type(std::string(what) + " as a JSON object", found(json),
                                     "write it as " + std::string(layout)));
  return false;
}

bool JsonReader::array(const Json& json, const std::string& pointer, std::string_view what,
                       std::string_view layout, std::size_t min_size) {
  if (json.is_array() && json.size() >= min_size) return true;
  std::string expected = std::string(what) + " as a JSON array";
  if (min_size > 0) {
    expected +=
        " of at least " + std::to_string(min_size) + (min_size == 1 ? " element" : " elements");
  }
  error(pointer,
        wording::wrong_type(
            expected, json.is_array() ? "an array of " + std::to_string(json.size()) : found(json),
            "write it as " + std::string(layout)));
  return false;
}

const Json* JsonReader::member(const Json& object, const std::string& pointer, std::string_view key,
                               Need need) {
  if (object.is_object()) {
    const auto it = object.find(key);
    if (it != object.end()) return &*it;
  }
  // At the member's own pointer, so that a form can mark the field that is missing.
  if (need == Need::required) error(member_pointer(pointer, key), wording::missing_key(key));
  return nullptr;
}

void JsonReader::unknown_keys(const Json& object, const std::string& pointer,
                              const std::vector<std::string_view>& known, Comments comments) {
  if (!object.is_object()) return;
  for (const auto& [key, value] : object.items()) {
    if (comments == Comments::underscore && key.starts_with('_')) continue;
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    warning(member_pointer(pointer, key), wording::unknown_key(key));
  }
}

void JsonReader::schema_version(const Json& object, const std::string& pointer) {
  const Json* version = member(object, pointer, "schema_version", Need::optional);
  if (version == nullptr) return;
  const std::string where = member_pointer(pointer, "schema_version");
  const std::string supported = "a version from 1 to " + std::to_string(kSchemaVersion);
  if (!version->is_number_integer()) {
    error(where, wording::wrong_type(kWholeNumber, found(*version), "write " + supported));
    return;
  }
  const auto value = as_int64(*version);
  if (!value || *value < 1 || *value > kSchemaVersion) {
    error(where,
          wording::out_of_range(
              version->dump(), supported + (value && *value < 1 ? "" : ", or update the program")));
  }
}

}  // namespace pb
