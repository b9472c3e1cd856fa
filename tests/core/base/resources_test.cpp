// SPDX-License-Identifier: MIT
#include "core/base/resources.hpp"

#include <QtTest>
#include <fstream>
#include <sstream>

using namespace pb;

namespace {

QString q(std::string_view s) {
  return QString::fromUtf8(s.data(), static_cast<qsizetype>(s.size()));
}

std::string read_source_file(const std::string& relative) {
  std::ifstream in(std::string(PB_SOURCE_DIR) + "/" + relative, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

class ResourcesTest : public QObject {
  Q_OBJECT

 private slots:
  void catalogIsEmbedded() {
    const auto csv = embedded_file("resources/sku_catalog.csv");
    QVERIFY(csv.has_value());
    QVERIFY(!csv->empty());
    QVERIFY(csv->starts_with(
        "sku,name,weight_kg,length_m,width_m,height_m,fragility,category,default_env\n"));
  }

  void embeddedCopiesEqualTheSourceFiles() {
    for (const char* name : {"resources/sku_catalog.csv", "resources/friction_table.json",
                             "resources/friction_items.json"}) {
      const auto data = embedded_file(name);
      QVERIFY2(data.has_value(), name);
      QVERIFY2(std::string(*data) == read_source_file(name), name);
    }
  }

  void listsTheDataFilesSorted() {
    const auto names = embedded_files("resources/");
    QStringList listed;
    for (auto name : names) listed << q(name);
    QCOMPARE(listed, (QStringList{"resources/friction_items.json", "resources/friction_table.json",
                                  "resources/sku_catalog.csv"}));
    QVERIFY(embedded_files("no-such-folder/").empty());
  }

  void unknownNameIsNullopt() {
    QVERIFY(!embedded_file("resources/missing.csv").has_value());
    QVERIFY(!embedded_file("sku_catalog.csv").has_value());  // names are full relative paths
    QVERIFY(!embedded_file("").has_value());
  }
};

QTEST_APPLESS_MAIN(ResourcesTest)
#include "resources_test.moc"
