// SPDX-License-Identifier: MIT
// The console's folders are layers: models, widgets, replay, window. A file includes ui headers of
// its own layer and the layers before it only, and the models are headless: they include no Qt
// Widgets header (a QtWidgets class, by the header Qt installs for it), so the document, the
// stack builder's model, the dial game, the replay player and the analysis service can be used and
// tested without a widget. Every ui source lives in a layer folder.
#include <QtTest>
#include <array>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, 4> kLayers = {"models", "widgets", "replay", "window"};

int rank_of(const std::string& layer) {
  for (std::size_t i = 0; i < kLayers.size(); ++i) {
    if (layer == kLayers[i]) return int(i);
  }
  return -1;
}

// The layer a `#include "ui/<layer>/<name>.hpp"` line names, or "" for any other line.
std::string included_layer(const std::string& line) {
  static const std::regex pattern("^\\s*#\\s*include\\s*\"ui/([^/\"]+)/");
  std::smatch m;
  return std::regex_search(line, m, pattern) ? m[1].str() : std::string();
}

// The Qt Widgets class a `#include <QName>` line names ("" when it is none of QtWidgets').
std::string included_widget(const std::string& line) {
  static const std::regex pattern("^\\s*#\\s*include\\s*<(Q[A-Za-z0-9]+)>");
  std::smatch m;
  if (!std::regex_search(line, m, pattern)) return {};
  return fs::exists(fs::path(PB_QT_WIDGETS_DIR) / m[1].str()) ? m[1].str() : std::string();
}

struct Scan {
  int files = 0;
  QStringList offences;
};

Scan scan_ui() {
  Scan scan;
  const fs::path root = fs::path(PB_SOURCE_DIR) / "ui";
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const fs::path& path = entry.path();
    if (!entry.is_regular_file() || (path.extension() != ".hpp" && path.extension() != ".cpp")) {
      continue;
    }
    ++scan.files;
    const fs::path relative = fs::relative(path, root);
    const std::string where = "ui/" + relative.generic_string();
    const std::string layer = relative.has_parent_path() ? relative.begin()->string() : "";
    const int own = rank_of(layer);
    if (own < 0) {
      scan.offences << QString::fromStdString(where + ": not in a layer folder");
      continue;
    }
    std::ifstream in(path);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      const std::string at = where + ":" + std::to_string(number) + ": " + line;
      const std::string target = included_layer(line);
      if (!target.empty() && (rank_of(target) < 0 || rank_of(target) > own)) {
        scan.offences << QString::fromStdString(at + " (" + layer + " may include " + kLayers[0] +
                                                " to " + layer + ")");
      }
      if (layer == "models" && !included_widget(line).empty()) {
        scan.offences << QString::fromStdString(at + " (the models are headless: no Qt Widgets)");
      }
    }
  }
  return scan;
}

}  // namespace

class TestUiLayering : public QObject {
  Q_OBJECT

 private slots:
  void includesAreRead() {
    QCOMPARE(included_layer("#include \"ui/models/dial_game.hpp\""), std::string("models"));
    QCOMPARE(included_layer("#include \"core/base/text.hpp\""), std::string());
    QCOMPARE(included_widget("#include <QPushButton>"), std::string("QPushButton"));
    QCOMPARE(included_widget("#include <QUndoStack>"), std::string());  // QtGui in Qt 6
    QCOMPARE(included_widget("#include <QObject>"), std::string());
  }

  void everyLayerIncludesOnlyItselfAndTheOnesBefore() {
    const Scan scan = scan_ui();
    QVERIFY(scan.files > 40);
    QVERIFY2(scan.offences.isEmpty(), qPrintable(scan.offences.join(QLatin1Char('\n'))));
  }
};

QTEST_APPLESS_MAIN(TestUiLayering)
#include "tst_ui_layering.moc"
