// SPDX-License-Identifier: MIT
// The verbs' argument parser (app/cli/args.hpp, over CLI11), in process: what it accepts, and the
// one message of each bad invocation.
#include "app/cli/args.hpp"

#include <QtTest>

using namespace pb::cli;

namespace {

VerbSpec spec() {
  VerbSpec s;
  s.name = "solve";
  s.usage = "solve FILE [--speed V] [--offset X] [--json]";
  s.summary = "Simulate.";
  s.options = {{"speed", "V", "belt speed"},
               {"offset", "X", "offset, m"},
               {"threads", "LIST", "thread counts"},
               {"seed", "N", "seed"},
               {"json", "", "print JSON"}};
  s.min_positionals = 1;
  s.max_positionals = 2;
  return s;
}

Args parse(const VerbSpec& s, std::vector<std::string> argv) {
  return Args(s, argv);
}

// The UsageError message of parsing `argv`, or "" if it parses.
QString error_of(const VerbSpec& s, std::vector<std::string> argv) {
  try {
    (void)Args(s, argv);
  } catch (const UsageError& e) {
    return QString::fromStdString(e.message);
  }
  return {};
}

}  // namespace

class ArgsTest : public QObject {
  Q_OBJECT

 private slots:
  void valuesBothWays() {
    const VerbSpec s = spec();
    const Args args = parse(s, {"p.json", "--speed", "1.5", "--offset=-0.5", "--json"});
    QVERIFY(!args.help());
    QCOMPARE(*args.number("speed"), 1.5);
    QCOMPARE(*args.number("offset"), -0.5);
    QVERIFY(args.flag("json"));
    QVERIFY(!args.flag("seed"));
    QVERIFY(!args.text("seed"));
    QCOMPARE(args.positionals(), std::vector<std::string>{"p.json"});
  }

  void theWordAfterAnOptionIsItsValue() {
    const VerbSpec s = spec();
    const Args args = parse(s, {"--offset", "-0.5", "--speed", "-3", "f", "--seed", "--json"});
    QCOMPARE(*args.number("offset"), -0.5);
    QCOMPARE(*args.number("speed"), -3.0);
    QCOMPARE(*args.text("seed"), std::string("--json"));
    QVERIFY(!args.flag("json"));
  }

  void positionalsKeepTheirOrder() {
    const VerbSpec s = spec();
    QCOMPARE(parse(s, {"-", "-.5"}).positionals(), (std::vector<std::string>{"-", "-.5"}));
    QCOMPARE(parse(s, {"-5", "--json", "a"}).positionals(), (std::vector<std::string>{"-5", "a"}));
    QCOMPARE(parse(s, {"a", "--", "--json"}).positionals(),
             (std::vector<std::string>{"a", "--json"}));
  }

  void theLastOfARepeatedOptionCounts() {
    const VerbSpec s = spec();
    const Args args = parse(s, {"f", "--speed", "1", "--speed=2", "--json", "--json"});
    QCOMPARE(*args.number("speed"), 2.0);
    QVERIFY(args.flag("json"));
  }

  void emptyValue() {
    const VerbSpec s = spec();
    QCOMPARE(*parse(s, {"f", "--seed", ""}).text("seed"), std::string());
  }

  void helpWins() {
    const VerbSpec s = spec();
    QVERIFY(parse(s, {"--help"}).help());
    QVERIFY(parse(s, {"-h"}).help());
    QVERIFY(parse(s, {"--speed", "1", "--help", "--no-such", "a", "b", "c"}).help());
    QVERIFY(parse(s, {"--help", "--speed"}).help());
  }

  void badInvocations_data() {
    QTest::addColumn<QStringList>("argv");
    QTest::addColumn<QString>("message");
    const QString see = QStringLiteral(" (see 'palletballet-cli solve --help')");
    QTest::newRow("unknown long") << QStringList{"f", "--no-such"}
                                  << "solve: unknown option --no-such" + see;
    QTest::newRow("unknown with value")
        << QStringList{"f", "--no-such=3"} << "solve: unknown option --no-such" + see;
    QTest::newRow("unknown short") << QStringList{"f", "-x"} << "solve: unknown option -x" + see;
    QTest::newRow("no value") << QStringList{"f", "--speed"}
                              << "solve: --speed needs a value V" + see;
    QTest::newRow("empty = value, last")
        << QStringList{"f", "--seed="} << "solve: --seed needs a value N" + see;
    QTest::newRow("flag with value")
        << QStringList{"f", "--json=yes"} << "solve: --json takes no value" + see;
    QTest::newRow("no positional")
        << QStringList{"--json"}
        << "solve: missing argument; usage: " + QString::fromStdString(spec().usage) + see;
    QTest::newRow("too many") << QStringList{"a", "b", "c"}
                              << "solve: unexpected argument 'c'" + see;
  }
  void badInvocations() {
    QFETCH(QStringList, argv);
    QFETCH(QString, message);
    std::vector<std::string> args;
    for (const QString& a : argv) args.push_back(a.toStdString());
    QCOMPARE(error_of(spec(), args), message);
  }

  void typedValuesKeepTheirWording() {
    const VerbSpec s = spec();
    const Args args = parse(s, {"f", "--speed", "fast", "--seed", "1.5", "--threads", "1,x"});
    const auto message = [](auto&& read) {
      try {
        read();
      } catch (const UsageError& e) {
        return QString::fromStdString(e.message);
      }
      return QString();
    };
    const QString see = QStringLiteral(" (see 'palletballet-cli solve --help')");
    QCOMPARE(message([&] { (void)args.number("speed"); }),
             "solve: --speed expects a number, got 'fast'" + see);
    QCOMPARE(message([&] { (void)args.integer("seed"); }),
             "solve: --seed expects a whole number, got '1.5'" + see);
    QCOMPARE(message([&] { (void)args.numbers("threads"); }),
             "solve: --threads expects comma-separated numbers, got '1,x'" + see);
    QCOMPARE(*parse(s, {"f", "--threads", "1,2,4"}).numbers("threads"),
             (std::vector<double>{1.0, 2.0, 4.0}));
  }

  void programNamesTheTool() {
    VerbSpec s = spec();
    s.program = "palletballet-lab";
    QCOMPARE(
        error_of(s, {"f", "--no-such"}),
        QStringLiteral("solve: unknown option --no-such (see 'palletballet-lab solve --help')"));
  }

  void helpTextIsUnchanged() {
    QCOMPARE(QString::fromStdString(help_text(spec())),
             QStringLiteral("usage: palletballet-cli solve FILE [--speed V] [--offset X] [--json]\n"
                            "\n"
                            "Simulate.\n"
                            "\n"
                            "options:\n"
                            "  --speed V                belt speed\n"
                            "  --offset X               offset, m\n"
                            "  --threads LIST           thread counts\n"
                            "  --seed N                 seed\n"
                            "  --json                   print JSON\n"
                            "  --help                   this text\n"));
  }
};

QTEST_APPLESS_MAIN(ArgsTest)
#include "args_test.moc"
