// SPDX-License-Identifier: MIT
// One reader of a pallet as a user hands it over: a PalletConfig or a scenario file, from a file,
// stdin or a curated scenario's slug; errors point into the document read.
#include "core/inputs/pallet_source.hpp"

#include <QTemporaryDir>
#include <QtTest>
#include <fstream>

#include "core/inputs/scenario.hpp"

using namespace pb;

class PalletSourceTest : public QObject {
  Q_OBJECT

 private slots:
  void aPalletOrAScenarioFile() {
    const Scenario tower = *load_scenario("tall-unwrapped-tower").value;
    auto plain = pallet_source_from_json(pallet_to_json(tower.pallet));
    QVERIFY(plain.ok());
    QVERIFY(plain->pointer_prefix.empty());
    QVERIFY(!plain->suggested_profile);
    QVERIFY(plain->pallet == tower.pallet);

    auto scenario = pallet_source_from_json(scenario_to_json(tower));
    QVERIFY(scenario.ok());
    QCOMPARE(scenario->pointer_prefix, std::string("/pallet"));
    QVERIFY(scenario->pallet == tower.pallet);
    QVERIFY(scenario->suggested_profile == tower.suggested_profile);
    QCOMPARE(scenario->scenario_name, tower.name);
  }

  void errorsPointIntoTheDocument() {
    Json j = scenario_to_json(*load_scenario("tall-unwrapped-tower").value);
    j["pallet"]["items"][0]["weight_kg"] = "heavy";
    j["suggested_profile"]["accel_mps2"] = "fast";
    auto read = pallet_source_from_json(j);
    QVERIFY(!read.ok());
    bool weight = false, accel = false;
    for (const Diagnostic& d : read.diagnostics) {
      weight = weight || d.pointer == "/pallet/items/0/weight_kg";
      accel = accel || d.pointer == "/suggested_profile/accel_mps2";
    }
    QVERIFY2(weight && accel, to_string(read.diagnostics[0]).c_str());
  }

  void aFileOrASlug() {
    QTemporaryDir dir;
    const std::string path = dir.filePath(QStringLiteral("tower.json")).toStdString();
    const Scenario tower = *load_scenario("tall-unwrapped-tower").value;
    std::ofstream(path) << pallet_to_json(tower.pallet).dump();
    auto file = read_pallet_source(path);
    QVERIFY(file.ok());
    QVERIFY(file->pallet == tower.pallet);

    auto slug = read_pallet_source("tall-unwrapped-tower");
    QVERIFY(slug.ok());
    QVERIFY(slug->suggested_profile == tower.suggested_profile);

    auto none = read_pallet_source(dir.filePath(QStringLiteral("nope.json")).toStdString());
    QVERIFY(!none.ok());
    QVERIFY(none.diagnostics[0].message.find("no such file and no curated scenario") !=
            std::string::npos);
    QVERIFY(none.diagnostics[0].message.find("stable-dairy-slab") != std::string::npos);

    auto folder = read_pallet_source(dir.path().toStdString());  // says what it is
    QVERIFY(!folder.ok());
    QVERIFY2(folder.diagnostics[0].message.find("is a directory") != std::string::npos,
             folder.diagnostics[0].message.c_str());
  }
};

QTEST_APPLESS_MAIN(PalletSourceTest)
#include "pallet_source_test.moc"
