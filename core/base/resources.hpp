// SPDX-License-Identifier: MIT
// The data files compiled into palletcore: resources/*.csv|json and scenarios/*.json.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

namespace pb {

namespace detail {
struct EmbeddedFile {
  std::string_view name;  ///< path relative to the source tree: "resources/sku_catalog.csv"
  std::string_view data;
};
}  // namespace detail

/// Contents of an embedded file by its path relative to the source tree, or nullopt.
std::optional<std::string_view> embedded_file(std::string_view name);

/// Names of the embedded files that start with `prefix` ("scenarios/"), sorted.
std::vector<std::string_view> embedded_files(std::string_view prefix);

}  // namespace pb
