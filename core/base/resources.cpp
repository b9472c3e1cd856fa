// SPDX-License-Identifier: MIT
#include "core/base/resources.hpp"

#include <algorithm>

namespace pb {

namespace detail {
extern const EmbeddedFile kEmbedded[];
extern const std::size_t kEmbeddedCount;
}  // namespace detail

std::optional<std::string_view> embedded_file(std::string_view name) {
  for (std::size_t i = 0; i < detail::kEmbeddedCount; ++i) {
    if (detail::kEmbedded[i].name == name) return detail::kEmbedded[i].data;
  }
  return std::nullopt;
}

std::vector<std::string_view> embedded_files(std::string_view prefix) {
  std::vector<std::string_view> names;
  for (std::size_t i = 0; i < detail::kEmbeddedCount; ++i) {
    if (detail::kEmbedded[i].name.starts_with(prefix)) names.push_back(detail::kEmbedded[i].name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace pb
