// SPDX-License-Identifier: MIT
// Errors and warnings of reading and validation: where (a JSON pointer) and what to change.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pb {

enum class Severity { error, warning };

/// One finding about an input. `pointer` is an RFC 6901 JSON pointer into the document that was
/// read or validated ("/items/3/dims_m/2"; "" for the whole document). `message` is one sentence
/// that says what is wrong and what to change.
struct Diagnostic {
  std::string pointer;
  std::string message;
  Severity severity = Severity::error;

  bool operator==(const Diagnostic&) const = default;
};

using Diagnostics = std::vector<Diagnostic>;

/// True if any diagnostic is an error (warnings do not count).
bool has_errors(const Diagnostics& diagnostics);

/// Only the errors, or only the warnings, in their original order.
Diagnostics errors_of(const Diagnostics& diagnostics);
Diagnostics warnings_of(const Diagnostics& diagnostics);

/// "pointer: message" for an error, "warning: pointer: message" for a warning.
std::string to_string(const Diagnostic& diagnostic);

/// The diagnostics as a person reads them (the CLI's messages, the service's `detail`, the
/// console's): where more than `shown` + 1 items have one problem (the same message but for its
/// numbers, at the same place in each item: /items/12/position/2, /items/13/position/2, ...),
/// the first `shown` are kept and the rest are told in one more diagnostic at that place with a
/// "*" for the item ("/items/*/position/2": "the same for 331 more items: 69-399"), where the
/// group's first left-out member stood. Everything else is kept, in order. The lists a program
/// reads (JSON "errors", "warnings") keep every diagnostic.
Diagnostics condensed(const Diagnostics& diagnostics, std::size_t shown = 3);

/// Escapes one reference token of a JSON pointer ("~" -> "~0", "/" -> "~1").
std::string json_pointer_token(std::string_view token);

/// A value or the reasons there is none. Warnings may accompany a value; an error never does.
template <class T>
struct Result {
  std::optional<T> value;
  Diagnostics diagnostics;

  bool ok() const { return value.has_value(); }
  explicit operator bool() const { return ok(); }
  const T& operator*() const { return *value; }
  T& operator*() { return *value; }
  const T* operator->() const { return &*value; }
  T* operator->() { return &*value; }

  static Result failure(Diagnostics d) { return Result{std::nullopt, std::move(d)}; }
  static Result failure(std::string pointer, std::string message) {
    return failure(Diagnostics{{std::move(pointer), std::move(message), Severity::error}});
  }
};

}  // namespace pb
