// SPDX-License-Identifier: MIT
#include "core/base/diagnostic.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <tuple>

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

namespace {

// Where an item's diagnostic points: the item's index and the pointer with a "*" for it
// ("/items/12/position/2" -> 12, "/items/*/position/2"). A pointer into no item has none.
struct ItemPlace {
  std::size_t index = 0;
  std::string place;
};

std::optional<ItemPlace> item_place(const std::string& pointer) {
  static constexpr std::string_view kItems = "/items/";
  const std::size_t at = pointer.find(kItems);
  if (at == std::string::npos) return std::nullopt;
  const std::size_t first = at + kItems.size();
  std::size_t end = first;
  while (end < pointer.size() && std::isdigit(static_cast<unsigned char>(pointer[end]))) ++end;
  if (end == first || end - first > 9 || (end < pointer.size() && pointer[end] != '/')) {
    return std::nullopt;
  }
  return ItemPlace{std::stoul(pointer.substr(first, end - first)),
                   pointer.substr(0, first) + "*" + pointer.substr(end)};
}

// The message with each number as "#": one problem, whatever the item's own values.
std::string shape_of(const std::string& message) {
  std::string out;
  for (std::size_t i = 0; i < message.size(); ++i) {
    const auto digit = [&](std::size_t k) {
      return k < message.size() && std::isdigit(static_cast<unsigned char>(message[k]));
    };
    if (!digit(i)) {
      out += message[i];
      continue;
    }
    while (digit(i + 1) || (message[i + 1] == '.' && digit(i + 2))) ++i;
    out += '#';
  }
  return out;
}

// "3, 7-12, 40" (at most `most` runs, then "...").
std::string runs_of(const std::vector<std::size_t>& sorted, std::size_t most = 6) {
  std::string out;
  std::size_t runs = 0;
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i;
    while (j + 1 < sorted.size() && sorted[j + 1] == sorted[j] + 1) ++j;
    if (runs == most) return out + ", ...";
    out += (runs++ == 0 ? "" : ", ") + std::to_string(sorted[i]);
    if (j > i) out += "-" + std::to_string(sorted[j]);
    i = j + 1;
  }
  return out;
}

}  // namespace

Diagnostics condensed(const Diagnostics& diagnostics, std::size_t shown) {
  using Key = std::tuple<Severity, std::string, std::string>;  // severity, place, shape
  std::vector<std::optional<Key>> keys(diagnostics.size());
  std::map<Key, std::vector<std::size_t>> items;  // each group's item indices, in order
  for (std::size_t i = 0; i < diagnostics.size(); ++i) {
    const Diagnostic& d = diagnostics[i];
    if (auto at = item_place(d.pointer)) {
      keys[i] = Key{d.severity, at->place, shape_of(d.message)};
      items[*keys[i]].push_back(at->index);
    }
  }
  Diagnostics out;
  std::map<Key, std::size_t> seen;
  for (std::size_t i = 0; i < diagnostics.size(); ++i) {
    if (!keys[i] || items[*keys[i]].size() <= shown + 1) {
      out.push_back(diagnostics[i]);
      continue;
    }
    const std::size_t k = seen[*keys[i]]++;
    if (k < shown) {
      out.push_back(diagnostics[i]);
    } else if (k == shown) {
      const std::vector<std::size_t>& all = items[*keys[i]];
      std::vector<std::size_t> rest(all.begin() + static_cast<std::ptrdiff_t>(shown), all.end());
      std::sort(rest.begin(), rest.end());
      out.push_back(
          {std::get<1>(*keys[i]),
           "the same for " + std::to_string(rest.size()) + " more items: " + runs_of(rest),
           diagnostics[i].severity});
    }
  }
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
