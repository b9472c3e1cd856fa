// SPDX-License-Identifier: MIT
// End-to-end runs of palletballet-cli: every verb, its --help, and bad input.
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QTemporaryDir>
#include <QtTest>

#include "cli_runner.hpp"

namespace {

using pb::test::cli;
using pb::test::Run;
using pb::test::write_file;

}  // namespace

class CliTest : public QObject {
  Q_OBJECT

 private slots:
  void usageAndUnknownVerb() {
    Run none = cli({});
    QCOMPARE(none.exit_code, 2);
    QVERIFY(none.out.contains("verbs:"));
    Run help = cli({QStringLiteral("--help")});
    QCOMPARE(help.exit_code, 0);
    Run bad = cli({QStringLiteral("frobnicate")});
    QCOMPARE(bad.exit_code, 2);
    QVERIFY(bad.err.contains("unknown verb 'frobnicate'"));
  }

  void everyVerbHasHelp_data() {
    QTest::addColumn<QString>("verb");
    for (const char* v : {"scenarios", "catalog", "validate", "random", "friction", "mjcf", "solve",
                          "analyze", "bench"}) {
      QTest::newRow(v) << QString::fromLatin1(v);
    }
  }
  void everyVerbHasHelp() {
    QFETCH(QString, verb);
    Run r = cli({verb, QStringLiteral("--help")});
    QCOMPARE(r.exit_code, 0);
    QVERIFY2(r.out.startsWith("usage: palletballet-cli " + verb.toUtf8()), r.out.constData());
    QVERIFY(r.out.contains("--help"));
    Run unknown = cli({verb, QStringLiteral("--no-such-flag")});
    QCOMPARE(unknown.exit_code, 2);
    QVERIFY2(unknown.err.contains("unknown option --no-such-flag"), unknown.err.constData());
  }

  void scenariosListAndShow() {
    Run r = cli({QStringLiteral("scenarios")});
    QCOMPARE(r.exit_code, 0);
    const QJsonArray list = r.json().array();
    QCOMPARE(list.size(), 7);
    QCOMPARE(list.first().toObject().value(QStringLiteral("slug")).toString(),
             QStringLiteral("stable-dairy-slab"));
    QCOMPARE(list.last().toObject().value(QStringLiteral("slug")).toString(),
             QStringLiteral("random-scanner-feed"));

    Run one = cli({QStringLiteral("scenarios"), QStringLiteral("frozen-meat-sprint")});
    QCOMPARE(one.exit_code, 0);
    const QJsonObject s = one.json().object();
    QCOMPARE(s.value(QStringLiteral("pallet"))
                 .toObject()
                 .value(QStringLiteral("items"))
                 .toArray()
                 .size(),
             24);
    QCOMPARE(s.value(QStringLiteral("suggested_profile"))
                 .toObject()
                 .value(QStringLiteral("accel_mps2"))
                 .toDouble(),
             3.2);

    Run unknown = cli({QStringLiteral("scenarios"), QStringLiteral("no-such-scenario")});
    QCOMPARE(unknown.exit_code, 2);
    QVERIFY(unknown.err.contains("no curated scenario 'no-such-scenario'"));
    QVERIFY(unknown.err.contains("stable-dairy-slab"));
  }

  void scenariosCheck() {
    Run r = cli({QStringLiteral("scenarios"), QStringLiteral("--check")});
    QVERIFY2(r.exit_code == 0, r.err.constData());
    for (const QJsonValue& v : r.json().array()) {
      const QJsonObject o = v.toObject();
      QVERIFY(
          o.value(QStringLiteral("validation")).toObject().value(QStringLiteral("valid")).toBool());
      QVERIFY(o.value(QStringLiteral("recipe_matches")).toBool());
    }
    QCOMPARE(r.err.count("ok      "), 7);
  }

  void catalog() {
    Run all = cli({QStringLiteral("catalog")});
    QCOMPARE(all.exit_code, 0);
    QCOMPARE(all.json().array().size(), 30);
    Run frozen =
        cli({QStringLiteral("catalog"), QStringLiteral("--env"), QStringLiteral("frozen")});
    QCOMPARE(frozen.exit_code, 0);
    for (const QJsonValue& v : frozen.json().array()) {
      QCOMPARE(v.toObject().value(QStringLiteral("default_env")).toString(),
               QStringLiteral("frozen"));
    }
    QVERIFY(frozen.json().array().size() > 0 && frozen.json().array().size() < 30);
    Run bad = cli({QStringLiteral("catalog"), QStringLiteral("--env"), QStringLiteral("tropical")});
    QCOMPARE(bad.exit_code, 2);
    QVERIFY(bad.err.contains("frozen, refrigerated, thawed or transitioning"));
  }

  void validateGoodFileAndStdin() {
    QTemporaryDir dir;
    Run scenario = cli({QStringLiteral("scenarios"), QStringLiteral("stable-dairy-slab")});
    const QJsonObject pallet = scenario.json().object().value(QStringLiteral("pallet")).toObject();
    const QByteArray bytes = QJsonDocument(pallet).toJson();
    const QString path = write_file(dir, QStringLiteral("pallet.json"), bytes);
    Run file = cli({QStringLiteral("validate"), path});
    QVERIFY2(file.exit_code == 0, file.err.constData());
    QCOMPARE(file.json().object().value(QStringLiteral("valid")).toBool(), true);
    QCOMPARE(file.json().object().value(QStringLiteral("items")).toInt(), 8);
    Run stdin_run = cli({QStringLiteral("validate"), QStringLiteral("-")}, bytes);
    QCOMPARE(stdin_run.exit_code, 0);
    // A whole scenario file validates through its "pallet".
    Run whole =
        cli({QStringLiteral("validate"), write_file(dir, QStringLiteral("s.json"), scenario.out)});
    QCOMPARE(whole.exit_code, 0);
  }

  void validateReportsEveryErrorWithItsPointer() {
    QTemporaryDir dir;
    Run scenario = cli({QStringLiteral("scenarios"), QStringLiteral("stable-dairy-slab")});
    QJsonObject pallet = scenario.json().object().value(QStringLiteral("pallet")).toObject();
    QJsonArray items = pallet.value(QStringLiteral("items")).toArray();
    QJsonObject first = items[0].toObject();
    first[QStringLiteral("weight_kg")] = -3.0;
    items[0] = first;
    pallet[QStringLiteral("items")] = items;
    pallet[QStringLiteral("wrap")] = QStringLiteral("duct-tape");
    Run r = cli({QStringLiteral("validate"),
                 write_file(dir, QStringLiteral("bad.json"), QJsonDocument(pallet).toJson())});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("/wrap: "), r.err.constData());

    pallet[QStringLiteral("wrap")] = QStringLiteral("stretch");
    Run r2 = cli({QStringLiteral("validate"),
                  write_file(dir, QStringLiteral("bad2.json"), QJsonDocument(pallet).toJson())});
    QCOMPARE(r2.exit_code, 2);
    QVERIFY2(r2.err.contains("/items/0/weight_kg: "), r2.err.constData());

    // Valid is what an analysis will not refuse: a plastic pallet on steel rollers has no friction
    // data, so validate says so, as analyze does.
    first[QStringLiteral("weight_kg")] = 10.0;
    items[0] = first;
    pallet[QStringLiteral("items")] = items;
    pallet[QStringLiteral("base_pallet_type")] = QStringLiteral("CHEP");
    pallet[QStringLiteral("belt_surface")] = QStringLiteral("steel_roller");
    const QString unmodelled =
        write_file(dir, QStringLiteral("steel.json"), QJsonDocument(pallet).toJson());
    for (const char* verb : {"validate", "analyze"}) {
      Run r3 = cli({QString::fromLatin1(verb), unmodelled});
      QCOMPARE(r3.exit_code, 2);
      QVERIFY2(r3.err.contains("/belt_surface: ") && r3.err.contains("no friction data"),
               r3.err.constData());
    }
  }

  // Many items with one problem: the messages tell it once after the first three (and analyze's
  // the same), the JSON report keeps every error with its pointer.
  void manyItemsWithOneProblemAreToldOnce() {
    QTemporaryDir dir;
    Run scenario = cli({QStringLiteral("scenarios"), QStringLiteral("stable-dairy-slab")});
    QJsonObject pallet = scenario.json().object().value(QStringLiteral("pallet")).toObject();
    QJsonArray items = pallet.value(QStringLiteral("items")).toArray();
    for (int i = 0; i < items.size(); ++i) {
      QJsonObject item = items[i].toObject();
      item[QStringLiteral("weight_kg")] = -1.0 - i;
      items[i] = item;
    }
    pallet[QStringLiteral("items")] = items;
    const QString path =
        write_file(dir, QStringLiteral("bad.json"), QJsonDocument(pallet).toJson());
    const int n = int(items.size());
    QVERIFY(n >= 6);
    Run r = cli({QStringLiteral("validate"), path});
    QCOMPARE(r.exit_code, 2);
    const QByteArray told = "/items/*/weight_kg: the same for " + QByteArray::number(n - 3) +
                            " more items: 3-" + QByteArray::number(n - 1);
    QVERIFY2(r.err.contains("/items/2/weight_kg: ") && !r.err.contains("/items/3/weight_kg: ") &&
                 r.err.contains(told),
             r.err.constData());
    const QJsonArray errors = r.json().object().value(QStringLiteral("errors")).toArray();
    QCOMPARE(int(errors.size()), n);
    QCOMPARE(errors[n - 1].toObject().value(QStringLiteral("pointer")).toString(),
             QStringLiteral("/items/%1/weight_kg").arg(n - 1));
    Run a = cli({QStringLiteral("analyze"), path});
    QCOMPARE(a.exit_code, 2);
    QVERIFY2(a.err.contains(told) && !a.err.contains("/items/3/weight_kg: "), a.err.constData());
  }

  // A document over the size limit is refused by its size (read no further than the limit), from
  // a file and from stdin alike.
  void anOversizedDocumentIsRefusedBySize() {
    QTemporaryDir dir;
    QByteArray huge = "{\"items\": [], \"notes\": \"";
    huge += QByteArray(65 << 20, 'x');
    huge += "\"}";
    const QString path = write_file(dir, QStringLiteral("huge.json"), huge);
    for (const Run& r : {cli({QStringLiteral("validate"), path}),
                         cli({QStringLiteral("validate"), QStringLiteral("-")}, huge)}) {
      QCOMPARE(r.exit_code, 2);
      QVERIFY2(r.err.contains("larger than 64 MB"), r.err.constData());
    }
  }

  void validateBadInput() {
    QTemporaryDir dir;
    Run syntax = cli({QStringLiteral("validate"), write_file(dir, QStringLiteral("x.json"),
                                                             QByteArrayLiteral("{\"items\": [}"))});
    QCOMPARE(syntax.exit_code, 2);
    QVERIFY(!syntax.err.isEmpty());
    Run missing = cli({QStringLiteral("validate"), dir.filePath(QStringLiteral("nope.json"))});
    QCOMPARE(missing.exit_code, 2);
    QVERIFY(missing.err.contains("cannot open"));
    Run no_arg = cli({QStringLiteral("validate")});
    QCOMPARE(no_arg.exit_code, 2);
    QVERIFY(no_arg.err.contains("missing argument"));
    Run bad_limit = cli({QStringLiteral("validate"), QStringLiteral("-"),
                         QStringLiteral("--max-height"), QStringLiteral("tall")});
    QCOMPARE(bad_limit.exit_code, 2);
    QVERIFY(bad_limit.err.contains("--max-height expects a number"));
    // A limit out of range is the flag's mistake, not the pallet's ("remove 226 kg of items" for
    // --max-mass -1 blamed a pallet of 200 kg).
    for (const char* flag : {"--max-mass", "--max-height", "--max-overhang"}) {
      Run negative = cli({QStringLiteral("validate"), QStringLiteral("stable-dairy-slab"),
                          QString::fromLatin1(flag), QStringLiteral("-1")});
      QCOMPARE(negative.exit_code, 2);
      QVERIFY2(negative.err.contains(QByteArray(flag) + " must be"), negative.err.constData());
    }
    // No overhang at all: items flush with the deck's edge pass.
    QCOMPARE(cli({QStringLiteral("validate"), QStringLiteral("stable-dairy-slab"),
                  QStringLiteral("--max-overhang"), QStringLiteral("0")})
                 .exit_code,
             0);
  }

  void randomIsDeterministicAndValid() {
    const QStringList args = {QStringLiteral("random"), QStringLiteral("--seed"),
                              QStringLiteral("42")};
    Run a = cli(args);
    Run b = cli(args);
    QCOMPARE(a.exit_code, 0);
    QCOMPARE(a.out, b.out);
    QVERIFY(a.json().object().value(QStringLiteral("items")).toArray().size() > 0);
    Run c = cli({QStringLiteral("random"), QStringLiteral("--seed"), QStringLiteral("43")});
    QVERIFY(a.out != c.out);
    Run v = cli({QStringLiteral("validate"), QStringLiteral("-")}, a.out);
    QVERIFY2(v.exit_code == 0, v.err.constData());
    Run small = cli({QStringLiteral("random"), QStringLiteral("--seed"), QStringLiteral("7"),
                     QStringLiteral("--min-layers"), QStringLiteral("2"),
                     QStringLiteral("--max-layers"), QStringLiteral("2")});
    QCOMPARE(small.exit_code, 0);
  }

  void randomBadInput() {
    Run seed = cli({QStringLiteral("random"), QStringLiteral("--seed"), QStringLiteral("abc")});
    QCOMPARE(seed.exit_code, 2);
    QVERIFY(seed.err.contains("--seed expects a whole number"));
    Run rate =
        cli({QStringLiteral("random"), QStringLiteral("--anomaly-rate"), QStringLiteral("2")});
    QCOMPARE(rate.exit_code, 2);
    QVERIFY2(rate.err.contains("--anomaly-rate"), rate.err.constData());
    Run layers = cli({QStringLiteral("random"), QStringLiteral("--min-layers"), QStringLiteral("5"),
                      QStringLiteral("--max-layers"), QStringLiteral("2")});
    QCOMPARE(layers.exit_code, 2);
    Run missing = cli({QStringLiteral("random"), QStringLiteral("--seed")});
    QCOMPARE(missing.exit_code, 2);
    QVERIFY(missing.err.contains("--seed needs a value"));
  }

  void friction() {
    Run all = cli({QStringLiteral("friction")});
    QCOMPARE(all.exit_code, 0);
    QCOMPARE(all.json().object().value(QStringLiteral("pairs")).toArray().size(), 6);
    Run one = cli({QStringLiteral("friction"), QStringLiteral("--pair"),
                   QStringLiteral("wood_pallet/rubber_belt"), QStringLiteral("--from"),
                   QStringLiteral("-25"), QStringLiteral("--to"), QStringLiteral("-25")});
    QCOMPARE(one.exit_code, 0);
    const QJsonArray samples = one.json()
                                   .object()
                                   .value(QStringLiteral("pairs"))
                                   .toArray()
                                   .first()
                                   .toObject()
                                   .value(QStringLiteral("samples"))
                                   .toArray();
    QCOMPARE(samples.size(), 1);
    QCOMPARE(samples[0].toObject().value(QStringLiteral("mu_s")).toDouble(), 0.22);
    // Frost-melt: centre of the danger zone right after the change.
    Run melt = cli({QStringLiteral("friction"), QStringLiteral("--pair"),
                    QStringLiteral("wood_pallet/rubber_belt"), QStringLiteral("--from"),
                    QStringLiteral("3"), QStringLiteral("--to"), QStringLiteral("3"),
                    QStringLiteral("--since"), QStringLiteral("0")});
    const QJsonObject s = melt.json()
                              .object()
                              .value(QStringLiteral("pairs"))
                              .toArray()
                              .first()
                              .toObject()
                              .value(QStringLiteral("samples"))
                              .toArray()
                              .first()
                              .toObject();
    QCOMPARE(s.value(QStringLiteral("penalty")).toDouble(), 0.65);
    QVERIFY(qAbs(s.value(QStringLiteral("mu_s_effective")).toDouble() -
                 0.65 * s.value(QStringLiteral("mu_s")).toDouble()) < 1e-12);
  }

  void frictionBadInput() {
    Run pair =
        cli({QStringLiteral("friction"), QStringLiteral("--pair"), QStringLiteral("ice/ice")});
    QCOMPARE(pair.exit_code, 2);
    QVERIFY(pair.err.contains("wood_pallet/rubber_belt"));
    Run step = cli({QStringLiteral("friction"), QStringLiteral("--step"), QStringLiteral("0")});
    QCOMPARE(step.exit_code, 2);
    Run range = cli({QStringLiteral("friction"), QStringLiteral("--from"), QStringLiteral("10"),
                     QStringLiteral("--to"), QStringLiteral("0")});
    QCOMPARE(range.exit_code, 2);
    Run since = cli({QStringLiteral("friction"), QStringLiteral("--since"), QStringLiteral("-1")});
    QCOMPARE(since.exit_code, 2);
    // Below absolute zero, or so large a step cannot move it (that looped until memory ran out).
    for (const char* t : {"-300", "1e300"}) {
      Run cold = cli({QStringLiteral("friction"), QStringLiteral("--from"), QString::fromLatin1(t),
                      QStringLiteral("--to"), QString::fromLatin1(t)});
      QCOMPARE(cold.exit_code, 2);
      QVERIFY2(cold.err.contains("the friction tables cover -40 to 40 C"), cold.err.constData());
    }
  }
};

QTEST_GUILESS_MAIN(CliTest)
#include "cli_test.moc"
