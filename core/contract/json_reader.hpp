// SPDX-License-Identifier: MIT
// The one reader of JSON inputs: type checks, required and optional members, unknown members and
// JSON pointers, with one wording for each kind of mistake. The contract's values, replays,
// friction tables and scenarios all read through it; each keeps its own domain rules (ranges,
// physical validity) and words a value outside them with wording::out_of_range. Never throws.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/base/enums.hpp"

namespace pb {

using Json = nlohmann::json;

/// The sentence of each kind of mistake, "what is wrong; what to change". Readers of other formats
/// (the catalog's CSV) say the same things the same way.
namespace wording {
/// "expected <expected>, found <found>; <remedy>": a value of the wrong type or shape.
std::string wrong_type(std::string_view expected, std::string_view found, std::string_view remedy);
/// "the required key '<key>' is missing; add it"
std::string missing_key(std::string_view key);
/// "unknown key '<key>' is ignored; remove it or fix its spelling"
std::string unknown_key(std::string_view key);
/// "'<value>' is not a valid choice; use one of <choices>"
std::string not_a_choice(std::string_view value, std::string_view choices);
/// "<value> is out of range; write <allowed>" (allowed: "a number in [0, 2]", "a number above 0").
std::string out_of_range(std::string_view value, std::string_view allowed);
}  // namespace wording

/// "a, b or c": the choices of a message.
std::string join_choices(std::span<const std::string_view> names);

/// The pointer of a member ("/a" + "b/c" -> "/a/b~1c") and of an array element ("/a/3").
std::string member_pointer(const std::string& pointer, std::string_view key);
std::string element_pointer(const std::string& pointer, std::size_t index);

/// Whether a member must be there.
enum class Need { optional, required };
/// Whether members whose name starts with '_' are comments ("_comment", "_units"), never unknown.
enum class Comments { none, underscore };

/// Collects the diagnostics of one read. Each read_* or check records what is wrong at its pointer
/// and returns false, leaving its output as it was; reading goes on, so that one read reports every
/// mistake of a document.
class JsonReader {
 public:
  Diagnostics diagnostics;

  void error(std::string pointer, std::string message);
  void warning(std::string pointer, std::string message);
  /// Appends the diagnostics of a nested read (a pallet inside a replay).
  void merge(const Diagnostics& more);
  std::size_t error_count() const;

  // Values. A number is any finite JSON number; a whole number one without a fraction.
  bool read(const Json& json, const std::string& pointer, double& out);
  /// A number, or null for none.
  bool read(const Json& json, const std::string& pointer, std::optional<double>& out);
  bool read(const Json& json, const std::string& pointer, int& out);
  bool read(const Json& json, const std::string& pointer, std::uint64_t& out);
  bool read(const Json& json, const std::string& pointer, bool& out);
  bool read(const Json& json, const std::string& pointer, std::string& out);
  /// An array of exactly 3 numbers [x, y, z].
  bool read(const Json& json, const std::string& pointer, std::array<double, 3>& out);
  /// An array of exactly out.size() numbers; `layout` names them ("[x, y]").
  bool numbers(const Json& json, const std::string& pointer, std::span<double> out,
               std::string_view layout);

  /// One of `choices` (a string): its index into them.
  bool choice(const Json& json, const std::string& pointer,
              std::span<const std::string_view> choices, std::size_t& index);

  /// An enumeration by its JSON name (enums.hpp).
  template <class E>
  requires std::is_enum_v<E>
  bool read(const Json& json, const std::string& pointer, E& out) {
    const auto& table = EnumTable<E>::names;
    std::array<std::string_view, EnumTable<E>::names.size()> names{};
    for (std::size_t i = 0; i < table.size(); ++i) names[i] = table[i].name;
    std::size_t index = 0;
    if (!choice(json, pointer, names, index)) return false;
    out = table[index].value;
    return true;
  }

  // Shapes. "expected <what> as a JSON object, found <type>; write it as <layout>".
  bool object(const Json& json, const std::string& pointer, std::string_view what,
              std::string_view layout = "{\"key\": value, ...}");
  /// An array of at least `min_size` elements.
  bool array(const Json& json, const std::string& pointer, std::string_view what,
             std::string_view layout, std::size_t min_size = 0);

  // Members of an object.
  /// The member `key` of `object`, or nullptr; an absent required member is an error at the
  /// object's pointer.
  const Json* member(const Json& object, const std::string& pointer, std::string_view key,
                     Need need);
  /// Reads the member `key` into `out` if present. Returns whether the member is read, or absent
  /// and optional.
  template <class T>
  bool field(const Json& object, const std::string& pointer, std::string_view key, T& out,
             Need need = Need::optional) {
    const Json* value = member(object, pointer, key, need);
    if (value == nullptr) return need == Need::optional;
    return read(*value, member_pointer(pointer, key), out);
  }
  /// Warns about every member of `object` not in `known`.
  void unknown_keys(const Json& object, const std::string& pointer,
                    const std::vector<std::string_view>& known, Comments comments = Comments::none);
  /// An optional "schema_version" member: a whole number from 1 to kSchemaVersion.
  void schema_version(const Json& object, const std::string& pointer);

  /// The value with the diagnostics read, or only the diagnostics if any is an error.
  template <class T>
  Result<T> finish(T value) {
    if (has_errors(diagnostics)) return Result<T>::failure(std::move(diagnostics));
    return Result<T>{std::move(value), std::move(diagnostics)};
  }

  /// What a message says was found instead: the JSON type ("string", "null"), a number with its
  /// value ("number 1.5").
  static std::string found(const Json& json);
};

}  // namespace pb
