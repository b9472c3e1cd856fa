// SPDX-License-Identifier: MIT
#include "core/inputs/catalog.hpp"

#include <QtTest>

using namespace pb;

namespace {

const std::string kHeader =
    "sku,name,weight_kg,length_m,width_m,height_m,fragility,category,default_env\n";

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

QStringList pointers(const Diagnostics& diagnostics) {
  QStringList out;
  for (const auto& d : diagnostics) out << q(d.pointer);
  return out;
}

}  // namespace

class CatalogTest : public QObject {
  Q_OBJECT

 private slots:
  void builtinHasThirtySkus() {
    const Catalog& catalog = Catalog::builtin();
    QCOMPARE(catalog.all().size(), std::size_t{30});
    QCOMPARE(q(catalog.all().front().sku), QStringLiteral("SKU-FM-001"));
    QCOMPARE(q(catalog.all().back().sku), QStringLiteral("SKU-MS-003"));
  }

  void frozenBeefValues() {
    const SkuTemplate* t = Catalog::builtin().find("SKU-FM-001");
    QVERIFY(t != nullptr);
    QCOMPARE(q(t->name), QStringLiteral("Frozen Beef Cuts 10kg Box"));
    QCOMPARE(t->weight_kg, 10.5);
    QCOMPARE(t->dims_m[0], 0.40);
    QCOMPARE(t->dims_m[1], 0.30);
    QCOMPARE(t->dims_m[2], 0.20);
    QCOMPARE(t->fragility, Fragility::rigid);
    QCOMPARE(q(t->category), QStringLiteral("frozen_meat"));
    QCOMPARE(t->default_env, Environment::frozen);
  }

  void findUnknownIsNull() {
    QVERIFY(Catalog::builtin().find("SKU-XX-999") == nullptr);
    QVERIFY(Catalog::builtin().find("sku-fm-001") == nullptr);  // codes are case-sensitive
  }

  void forEnvCounts() {
    const Catalog& catalog = Catalog::builtin();
    QCOMPARE(catalog.for_env(Environment::frozen).size(), std::size_t{13});
    QCOMPARE(catalog.for_env(Environment::refrigerated).size(), std::size_t{10});
    QCOMPARE(catalog.for_env(Environment::thawed).size(), std::size_t{7});
    QCOMPARE(catalog.for_env(Environment::transitioning).size(), std::size_t{0});
    const auto thawed = catalog.for_env(Environment::thawed);
    QCOMPARE(q(thawed.front()->sku), QStringLiteral("SKU-DG-001"));  // catalog order
    QCOMPARE(q(thawed.back()->sku), QStringLiteral("SKU-BV-003"));
  }

  void readsQuotesCrlfAndBlankLines() {
    const std::string csv =
        "sku,name,weight_kg,length_m,width_m,height_m,fragility,category,default_env\r\n"
        "A-1,\"Beef, \"\"prime\"\"\",10.5,0.4,0.3,0.2,rigid,meat,frozen\r\n"
        "\r\n"
        "A-2,Milk,6,0.35,0.25,0.12,semi_rigid,dairy,refrigerated";
    const auto r = Catalog::from_csv(csv);
    QVERIFY(r.ok());
    QVERIFY(r.diagnostics.empty());
    QCOMPARE(r->all().size(), std::size_t{2});
    QCOMPARE(q(r->all()[0].name), QStringLiteral("Beef, \"prime\""));
    QCOMPARE(r->all()[1].weight_kg, 6.0);
    QCOMPARE(r->all()[1].fragility, Fragility::semi_rigid);
    QCOMPARE(q(r->all()[1].category), QStringLiteral("dairy"));
  }

  void headerOnlyIsAnEmptyCatalog() {
    const auto r = Catalog::from_csv(kHeader);
    QVERIFY(r.ok());
    QVERIFY(r->all().empty());
  }

  void badHeaderIsOneDocumentError() {
    for (const std::string& csv :
         {std::string(), std::string("sku,name,weight\nA-1,x,1\n"),
          std::string("name,sku,weight_kg,length_m,width_m,height_m,fragility,category,"
                      "default_env\n")}) {
      const auto r = Catalog::from_csv(csv);
      QVERIFY(!r.ok());
      QCOMPARE(pointers(r.diagnostics), QStringList{QString()});
      QVERIFY(r.diagnostics[0].message.find("header") != std::string::npos);
    }
  }

  void rowErrorsPointAtRowAndColumn() {
    const std::string csv = kHeader +
                            "A-1,ok,10,0.4,0.3,0.2,rigid,c,frozen\n"      // row 0
                            "A-2,too,few,fields\n"                        // row 1
                            "A-3,bad,heavy,0.4,0.3,0.2,rigid,c,frozen\n"  // row 2
                            "A-4,neg,10,0.4,-0.3,0,rigid,c,frozen\n"      // row 3
                            "A-5,frag,10,0.4,0.3,0.2,glass,c,frozen\n"    // row 4
                            "A-6,env,10,0.4,0.3,0.2,rigid,c,chilled\n"    // row 5
                            "A-1,dup,10,0.4,0.3,0.2,rigid,c,frozen\n"     // row 6
                            ",empty,10,0.4,0.3,0.2,rigid,c,frozen\n"      // row 7
                            "A-9,inf,inf,0.4,0.3,0.2,rigid,c,frozen\n";   // row 8
    const auto r = Catalog::from_csv(csv);
    QVERIFY(!r.ok());
    const QStringList expected = {"/1",          "/2/weight_kg", "/3/width_m",
                                  "/3/height_m", "/4/fragility", "/5/default_env",
                                  "/6/sku",      "/7/sku",       "/8/weight_kg"};
    QCOMPARE(pointers(r.diagnostics), expected);
    for (const auto& d : r.diagnostics) QCOMPARE(d.severity, Severity::error);
  }

  void duplicateSkuNamesTheCode() {
    const auto r = Catalog::from_csv(kHeader + "A-1,x,1,0.4,0.3,0.2,rigid,c,frozen\n" +
                                     "A-1,y,2,0.4,0.3,0.2,rigid,c,frozen\n");
    QVERIFY(!r.ok());
    QCOMPARE(r.diagnostics.size(), std::size_t{1});
    QCOMPARE(q(r.diagnostics[0].pointer), QStringLiteral("/1/sku"));
    QVERIFY(r.diagnostics[0].message.find("A-1") != std::string::npos);
  }

  void unknownEnumNamesTheChoices() {
    const auto r = Catalog::from_csv(kHeader + "A-1,x,1,0.4,0.3,0.2,Rigid,c,frozen\n");
    QVERIFY(!r.ok());
    QCOMPARE(q(r.diagnostics[0].message),
             QStringLiteral(
                 "'Rigid' is not a valid choice; use one of rigid, semi_rigid or deformable"));
  }

  void makeItemCopiesTheSku() {
    const SkuTemplate& t = *Catalog::builtin().find("SKU-FP-001");
    const Item item = make_item(t, {0.1, -0.2, 0.15}, 90.0);
    QCOMPARE(q(item.sku), QStringLiteral("SKU-FP-001"));
    QCOMPARE(item.weight_kg, 15.0);
    QCOMPARE(item.dims_m, (Vec3{0.50, 0.35, 0.25}));
    QCOMPARE(item.fragility, Fragility::deformable);
    QCOMPARE(item.position, (Vec3{0.1, -0.2, 0.15}));
    QCOMPARE(item.orientation_deg, 90.0);
    QCOMPARE(make_item(t, {0.0, 0.0, 0.15}).orientation_deg, 0.0);
  }
};

QTEST_APPLESS_MAIN(CatalogTest)
#include "catalog_test.moc"
