// SPDX-License-Identifier: MIT
// The layering rule of a folder of the tree (core/, ui/): every source sits in a layer folder and
// includes "<tree>/<layer>/..." headers of its own layer and the ones before it only. Shared by
// tests/core/layering_test.cpp and tests/ui/tst_ui_layering.cpp.
#pragma once

#include <QStringList>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <string>
#include <vector>

namespace pb::test {

struct LayerScan {
  int files = 0;
  QStringList offences;
};

/// The layer a `#include "<tree>/<layer>/<name>.hpp"` line names, or "" for any other line.
inline std::string included_layer(const std::string& tree, const std::string& line) {
  const std::regex pattern("^\\s*#\\s*include\\s*\"" + tree + "/([^/\"]+)/");
  std::smatch m;
  return std::regex_search(line, m, pattern) ? m[1].str() : std::string();
}

/// Where `layer` stands in `layers`, or -1.
inline int rank_of(const std::vector<std::string>& layers, const std::string& layer) {
  for (std::size_t i = 0; i < layers.size(); ++i) {
    if (layer == layers[i]) return int(i);
  }
  return -1;
}

/// Scans every .hpp and .cpp under PB_SOURCE_DIR/`tree`. `extra(layer, line)` may name one more
/// offence of a line (empty: none).
inline LayerScan scan_layers(
    const std::string& tree, const std::vector<std::string>& layers,
    const std::function<std::string(const std::string&, const std::string&)>& extra = {}) {
  namespace fs = std::filesystem;
  LayerScan scan;
  const fs::path root = fs::path(PB_SOURCE_DIR) / tree;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const fs::path& path = entry.path();
    if (!entry.is_regular_file() || (path.extension() != ".hpp" && path.extension() != ".cpp")) {
      continue;
    }
    ++scan.files;
    const fs::path relative = fs::relative(path, root);
    const std::string where = tree + "/" + relative.generic_string();
    const std::string layer = relative.has_parent_path() ? relative.begin()->string() : "";
    const int own = rank_of(layers, layer);
    if (own < 0) {
      scan.offences << QString::fromStdString(where + ": not in a layer folder");
      continue;
    }
    std::ifstream in(path);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      const std::string at = where + ":" + std::to_string(number) + ": " + line;
      const std::string target = included_layer(tree, line);
      const int rank = target.empty() ? 0 : rank_of(layers, target);
      if (rank < 0 || rank > own) {
        scan.offences << QString::fromStdString(at + " (" + layer + " may include " +
                                                layers.front() + " to " + layer + ")");
      }
      if (extra) {
        if (const std::string why = extra(layer, line); !why.empty()) {
          scan.offences << QString::fromStdString(at + " (" + why + ")");
        }
      }
    }
  }
  return scan;
}

}  // namespace pb::test
