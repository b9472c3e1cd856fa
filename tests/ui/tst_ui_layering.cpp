// SPDX-License-Identifier: MIT
// The console's folders are layers: models, widgets, replay, window. A file includes ui headers of
// its own layer and the layers before it only, and the models are headless: they include no Qt
// Widgets header (a QtWidgets class, by the header Qt installs for it), so the document, the
// stack builder's model, the dial game, the replay player and the analysis service can be used and
// tested without a widget. Every ui source lives in a layer folder.
#include <QtTest>
#include <filesystem>
#include <regex>

#include "tests/layer_scan.hpp"

using pb::test::included_layer;
using pb::test::scan_layers;

namespace {

const std::vector<std::string> kLayers = {"models", "widgets", "replay", "window"};

// The Qt Widgets class a `#include <QName>` line names ("" when it is none of QtWidgets').
std::string included_widget(const std::string& line) {
  static const std::regex pattern("^\\s*#\\s*include\\s*<(Q[A-Za-z0-9]+)>");
  std::smatch m;
  if (!std::regex_search(line, m, pattern)) return {};
  namespace fs = std::filesystem;
  return fs::exists(fs::path(PB_QT_WIDGETS_DIR) / m[1].str()) ? m[1].str() : std::string();
}

}  // namespace

class TestUiLayering : public QObject {
  Q_OBJECT

 private slots:
  void includesAreRead() {
    QCOMPARE(included_layer("ui", "#include \"ui/models/dial_game.hpp\""), std::string("models"));
    QCOMPARE(included_layer("ui", "#include \"core/base/text.hpp\""), std::string());
    QCOMPARE(included_widget("#include <QPushButton>"), std::string("QPushButton"));
    QCOMPARE(included_widget("#include <QUndoStack>"), std::string());  // QtGui in Qt 6
    QCOMPARE(included_widget("#include <QObject>"), std::string());
  }

  void everyLayerIncludesOnlyItselfAndTheOnesBefore() {
    const auto scan =
        scan_layers("ui", kLayers, [](const std::string& layer, const std::string& line) {
          return layer == "models" && !included_widget(line).empty()
                     ? std::string("the models are headless: no Qt Widgets")
                     : std::string();
        });
    QVERIFY(scan.files > 40);
    QVERIFY2(scan.offences.isEmpty(), qPrintable(scan.offences.join(QLatin1Char('\n'))));
  }
};

QTEST_APPLESS_MAIN(TestUiLayering)
#include "tst_ui_layering.moc"
