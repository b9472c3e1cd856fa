// SPDX-License-Identifier: MIT
// The core's folders are layers: base, contract, inputs, physics, analysis, then lab (palletlab).
// A file includes core headers of its own layer and the layers before it only, so each layer can be
// read, tested and reused without what is built on it. Every core source lives in a layer folder.
#include <QtTest>
#include <array>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 6> kLayers = {"base",    "contract", "inputs",
                                                "physics", "analysis", "lab"};

int rank_of(const std::string& layer) {
  for (std::size_t i = 0; i < kLayers.size(); ++i) {
    if (layer == kLayers[i]) return int(i);
  }
  return -1;
}

// The layer a `#include "core/<layer>/<name>.hpp"` line names, or "" for any other line.
std::string included_layer(const std::string& line) {
  static const std::regex pattern("^\\s*#\\s*include\\s*\"core/([^/\"]+)/");
  std::smatch m;
  return std::regex_search(line, m, pattern) ? m[1].str() : std::string();
}

struct Scan {
  int files = 0;
  QStringList offences;
};

Scan scan_core() {
  Scan scan;
  const fs::path root = fs::path(PB_SOURCE_DIR) / "core";
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const fs::path& path = entry.path();
    if (!entry.is_regular_file() || (path.extension() != ".hpp" && path.extension() != ".cpp")) {
      continue;
    }
    ++scan.files;
    const fs::path relative = fs::relative(path, root);
    const std::string layer = relative.has_parent_path() ? relative.begin()->string() : "";
    const int own = rank_of(layer);
    if (own < 0) {
      scan.offences << QString::fromStdString("core/" + relative.generic_string() +
                                              ": not in a layer folder");
      continue;
    }
    std::ifstream in(path);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      const std::string target = included_layer(line);
      if (target.empty()) continue;
      const int rank = rank_of(target);
      if (rank < 0 || rank > own) {
        scan.offences << QString::fromStdString(
            "core/" + relative.generic_string() + ":" + std::to_string(number) + ": " + line +
            " (" + layer + " may include " + std::string(kLayers[0]) + " to " + layer + ")");
      }
    }
  }
  return scan;
}

}  // namespace

class LayeringTest : public QObject {
  Q_OBJECT

 private slots:
  void includesAreRead() {
    QCOMPARE(included_layer("#include \"core/physics/scene.hpp\""), std::string("physics"));
    QCOMPARE(included_layer("  #  include \"core/base/text.hpp\"  // fixed()"),
             std::string("base"));
    QCOMPARE(included_layer("#include <vector>"), std::string());
    QCOMPARE(included_layer("// #include \"core/lab/study.hpp\" is not allowed"), std::string());
    QVERIFY(rank_of("analysis") > rank_of("physics"));
    QCOMPARE(rank_of("ui"), -1);
  }

  void everyLayerIncludesOnlyItselfAndLowerOnes() {
    const Scan scan = scan_core();
    QVERIFY2(scan.files > 80, "the scan found too few core files; is PB_SOURCE_DIR right?");
    QVERIFY2(scan.offences.isEmpty(), qPrintable(scan.offences.join(QLatin1Char('\n'))));
  }
};

QTEST_APPLESS_MAIN(LayeringTest)
#include "layering_test.moc"
