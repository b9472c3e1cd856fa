// SPDX-License-Identifier: MIT
// Runs palletballet-cli (or palletballet-lab) as a user would and collects what it printed.
#pragma once

#include <QByteArray>
#include <QFile>
#include <QJsonDocument>
#include <QProcess>
#include <QString>
#include <QStringList>
#include <QTemporaryDir>

namespace pb::test {

struct Run {
  int exit_code = -1;
  QByteArray out;
  QByteArray err;
  QJsonDocument json() const { return QJsonDocument::fromJson(out); }
};

/// Runs `program` from the build's bin folder; a run still going after `timeout_ms` is killed
/// (exit_code -1).
inline Run run_tool(const QString& program, const QStringList& args,
                    const QByteArray& stdin_data = {}, int timeout_ms = 120000) {
  QProcess p;
  p.setProgram(QStringLiteral(PB_BIN_DIR "/") + program);
  p.setArguments(args);
  p.start();
  if (!stdin_data.isEmpty()) p.write(stdin_data);
  p.closeWriteChannel();
  if (!p.waitForFinished(timeout_ms)) {
    p.kill();
    p.waitForFinished();
  }
  Run r;
  r.exit_code = p.exitStatus() == QProcess::NormalExit ? p.exitCode() : -1;
  r.out = p.readAllStandardOutput();
  r.err = p.readAllStandardError();
  return r;
}

/// Runs palletballet-cli.
inline Run cli(const QStringList& args, const QByteArray& stdin_data = {},
               int timeout_ms = 120000) {
  return run_tool(QStringLiteral("palletballet-cli"), args, stdin_data, timeout_ms);
}

/// Runs palletballet-lab (the studies).
inline Run lab(const QStringList& args, const QByteArray& stdin_data = {},
               int timeout_ms = 120000) {
  return run_tool(QStringLiteral("palletballet-lab"), args, stdin_data, timeout_ms);
}

inline QString write_file(const QTemporaryDir& dir, const QString& name, const QByteArray& data) {
  const QString path = dir.filePath(name);
  QFile f(path);
  if (!f.open(QIODevice::WriteOnly)) return {};
  f.write(data);
  return path;
}

inline QByteArray read_file(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly)) return {};
  return f.readAll();
}

}  // namespace pb::test
