// SPDX-License-Identifier: MIT
#include "core/base/diagnostic.hpp"

#include <algorithm>

namespace pb {

bool has_errors(const Diagnostics& diagnostics) {
  return std::any_of(diagnostics.begin(), diagnostics.end(),
                     [](const Diagnostic& d) { return d.severity == Severity::error; });
}

static Diagnostics filter(const Diagnostics& diagnostics, Severity severity) {
  Diagnostics out;
  std::copy_if(diagnostics.begin(), diagnostics.end(), std::back_inserter(out),
               [severity](const Diagnostic& d) { return d.severity == severity; });
  return out;
}

Diagnostics errors_of(const Diagnostics& diagnostics) {
  return filter(diagnostics, Severity::error);
}
Diagnostics warnings_of(const Diagnostics& diagnostics) {
  return filter(diagnostics, Severity::warning);
}

std::string to_string(const Diagnostic& diagnostic) {
  std::string out = diagnostic.severity == Severity::warning ? "warning: " : "";
  out += diagnostic.pointer.empty() ? std::string("(document)") : diagnostic.pointer;
  out += ": ";
  out += diagnostic.message;
  return out;
}

std::string json_pointer_token(std::string_view token) {
  std::string out;
  out.reserve(token.size());
  for (char c : token) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace pb
