// SPDX-License-Identifier: MIT
// The core's folders are layers: base, contract, inputs, physics, analysis, then lab (palletlab).
// A file includes core headers of its own layer and the layers before it only, so each layer can be
// read, tested and reused without what is built on it. Every core source lives in a layer folder.
#include <QtTest>

#include "tests/layer_scan.hpp"

using pb::test::included_layer;
using pb::test::rank_of;
using pb::test::scan_layers;

namespace {

const std::vector<std::string> kLayers = {"base",    "contract", "inputs",
                                          "physics", "analysis", "lab"};

}  // namespace

class LayeringTest : public QObject {
  Q_OBJECT

 private slots:
  void includesAreRead() {
    QCOMPARE(included_layer("core", "#include \"core/physics/scene.hpp\""), std::string("physics"));
    QCOMPARE(included_layer("core", "  #  include \"core/base/text.hpp\"  // fixed()"),
             std::string("base"));
    QCOMPARE(included_layer("core", "#include <vector>"), std::string());
    QCOMPARE(included_layer("core", "// #include \"core/lab/study.hpp\" is not allowed"),
             std::string());
    QVERIFY(rank_of(kLayers, "analysis") > rank_of(kLayers, "physics"));
    QCOMPARE(rank_of(kLayers, "ui"), -1);
  }

  void everyLayerIncludesOnlyItselfAndLowerOnes() {
    const auto scan = scan_layers("core", kLayers);
    QVERIFY2(scan.files > 80, "the scan found too few core files; is PB_SOURCE_DIR right?");
    QVERIFY2(scan.offences.isEmpty(), qPrintable(scan.offences.join(QLatin1Char('\n'))));
  }
};

QTEST_APPLESS_MAIN(LayeringTest)
#include "layering_test.moc"
