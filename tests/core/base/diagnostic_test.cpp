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
