// SPDX-License-Identifier: MIT
#include "core/base/diagnostic.hpp"

#include <QtTest>

using namespace pb;

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

const Diagnostic kError{"/items/3/dims_m/2", "height is 0; make it positive", Severity::error};
const Diagnostic kWarning{"/notes", "unknown key 'notez' is ignored", Severity::warning};
const Diagnostic kDocument{"", "the document is not valid JSON", Severity::error};

QStringList messages(const Diagnostics& diagnostics) {
  QStringList out;
  for (const auto& d : diagnostics) out << q(d.message);
  return out;
}

}  // namespace

class DiagnosticTest : public QObject {
  Q_OBJECT

 private slots:
  void toStringFormats() {
    QCOMPARE(q(to_string(kError)),
             QStringLiteral("/items/3/dims_m/2: height is 0; make it positive"));
    QCOMPARE(q(to_string(kWarning)),
             QStringLiteral("warning: /notes: unknown key 'notez' is ignored"));
    QCOMPARE(q(to_string(kDocument)), QStringLiteral("(document): the document is not valid JSON"));
    const Diagnostic document_warning{"", "old schema", Severity::warning};
    QCOMPARE(q(to_string(document_warning)), QStringLiteral("warning: (document): old schema"));
  }

  void defaultSeverityIsError() { QCOMPARE(Diagnostic{}.severity, Severity::error); }

  void pointerTokenEscaping() {
    QCOMPARE(q(json_pointer_token("carton/carton")), QStringLiteral("carton~1carton"));
    QCOMPARE(q(json_pointer_token("a~b")), QStringLiteral("a~0b"));
    // "~" first, so "~1" in a key does not read back as "/".
    QCOMPARE(q(json_pointer_token("~1/")), QStringLiteral("~01~1"));
    QCOMPARE(q(json_pointer_token("plain_key")), QStringLiteral("plain_key"));
    QCOMPARE(q(json_pointer_token("")), QString());
  }

  void hasErrorsIgnoresWarnings() {
    QVERIFY(!has_errors({}));
    QVERIFY(!has_errors({kWarning, kWarning}));
    QVERIFY(has_errors({kWarning, kError}));
    QVERIFY(has_errors({kDocument}));
  }

  void filtersKeepOrder() {
    const Diagnostics all{kWarning, kError, kDocument, kWarning};
    QCOMPARE(messages(errors_of(all)), QStringList({q(kError.message), q(kDocument.message)}));
    QCOMPARE(warnings_of(all).size(), std::size_t{2});
    QVERIFY(warnings_of(all)[0] == kWarning);
    QVERIFY(errors_of({kWarning}).empty());
    QVERIFY(warnings_of({kError}).empty());
  }

  void manyItemsWithOneProblemAreToldOnce() {
    // 399 items too high (a gap at 150), four of them with a second problem and a warning too.
    Diagnostics all{kDocument};
    QStringList expected{q(to_string(kDocument))};
    for (int i = 0; i < 400; ++i) {
      if (i == 150) continue;
      const std::string item = "/items/" + std::to_string(i);
      all.push_back({item + "/position/2",
                     "position[2] is " + std::to_string(10.05 + 0.15 * i) +
                         " m; set it to a "
                         "number in [-10, 10] m",
                     Severity::error});
      if (i < 3) expected << q(to_string(all.back()));
      if (i == 3) {
        expected << QStringLiteral(
            "/items/*/position/2: the same for 396 more items: 3-149, 151-399");
      }
      if (i % 100 == 0) {  // four of each: nothing is left out of so few
        all.push_back(
            {item + "/sku", "unknown SKU 'X'; use one of the catalog's", Severity::error});
        all.push_back({item + "/position/2", "position[2] is 0.5 m", Severity::warning});
        expected << q(to_string(all[all.size() - 2])) << q(to_string(all.back()));
      }
    }
    all.push_back({"/items/7/dims_m", "an item 12 m long; check the units", Severity::error});
    expected << q(to_string(all.back()));
    QStringList told;
    for (const auto& d : condensed(all)) told << q(to_string(d));
    QCOMPARE(told, expected);
    // Nothing to condense: the same list.
    const Diagnostics few{kError, kWarning, kDocument};
    QVERIFY(condensed(few) == few);
    // Scattered items are listed as runs, the first six of them.
    Diagnostics scattered;
    for (int i = 0; i < 40; i += 2) {
      scattered.push_back(
          {"/items/" + std::to_string(i) + "/sku", "unknown SKU 'X'", Severity::error});
    }
    QCOMPARE(q(to_string(condensed(scattered, 1).back())),
             QStringLiteral("/items/*/sku: the same for 19 more items: 2, 4, 6, 8, 10, 12, ..."));
  }

  void resultCarriesValueOrReasons() {
    const auto failed = Result<int>::failure("/x", "x is missing; add it");
    QVERIFY(!failed.ok());
    QVERIFY(!failed);
    QCOMPARE(failed.diagnostics.size(), std::size_t{1});
    QCOMPARE(q(failed.diagnostics[0].pointer), QStringLiteral("/x"));
    QCOMPARE(failed.diagnostics[0].severity, Severity::error);

    const Result<int> good{42, {kWarning}};
    QVERIFY(good.ok());
    QCOMPARE(*good, 42);
    QCOMPARE(good.diagnostics.size(), std::size_t{1});
  }
};

QTEST_APPLESS_MAIN(DiagnosticTest)
#include "diagnostic_test.moc"
