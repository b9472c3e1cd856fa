// SPDX-License-Identifier: MIT
// The palletballet command without a display (a server, an SSH session, CI): --help prints the
// help, a plain start runs the CLI's analysis of the scenario and says why, a screenshot is refused
// with what to do.
#include <QtTest>

namespace {

struct Run {
  int exit_code = -1;
  QByteArray out, err;
};

Run console(const QStringList& args) {
  QProcess p;
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"}) {
    env.remove(QString::fromLatin1(name));
  }
  p.setProcessEnvironment(env);
  p.start(QStringLiteral(PB_BIN_DIR "/palletballet"), args);
  if (!p.waitForFinished(120000)) p.kill();
  p.waitForFinished();
  return {p.exitStatus() == QProcess::NormalExit ? p.exitCode() : -1, p.readAllStandardOutput(),
          p.readAllStandardError()};
}

}  // namespace

class TestConsoleCommand : public QObject {
  Q_OBJECT

 private slots:
  void helpNeedsNoDisplay() {
    for (const char* flag : {"--help", "-h"}) {
      const Run r = console({QString::fromLatin1(flag)});
      QCOMPARE(r.exit_code, 0);
      QVERIFY2(r.out.contains("--scenario") && r.out.contains("--screenshot"), r.out.constData());
    }
  }

  void withoutADisplayTheCliAnswers() {
    const Run r = console({QStringLiteral("--scenario"), QStringLiteral("stable-dairy-slab")});
    QCOMPARE(r.exit_code, 0);
    QVERIFY2(r.err.contains("no display"), r.err.constData());
    const QJsonDocument json = QJsonDocument::fromJson(r.out);
    QVERIFY2(json.isArray() && json.array().size() == 1, r.out.constData());
    QVERIFY(json.array().first().toObject().contains(QStringLiteral("verdict")));
  }

  void aScreenshotWithoutADisplayIsRefused() {
    QTemporaryDir dir;
    const QString png = dir.filePath(QStringLiteral("x.png"));
    const Run r = console({QStringLiteral("--screenshot"), png});
    QCOMPARE(r.exit_code, 1);
    QVERIFY2(r.err.contains("xvfb-run"), r.err.constData());
    QVERIFY(!QFile::exists(png));
  }
};

QTEST_GUILESS_MAIN(TestConsoleCommand)
#include "tst_console_command.moc"
