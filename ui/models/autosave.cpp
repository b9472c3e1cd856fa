// SPDX-License-Identifier: MIT
#include "ui/models/autosave.hpp"

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QSaveFile>
#include <QStandardPaths>
#include <cstdio>

#include "core/contract/json_io.hpp"
#include "ui/models/pallet_document.hpp"

namespace pb::ui {

namespace {

constexpr const char* kKind = "palletballet-recovery";

QString lockPathOf(const QString& recoveryPath) {
  return recoveryPath.chopped(5) + QStringLiteral(".lock");  // "recovery-<pid>.json" -> ".lock"
}

}  // namespace

Autosave::Autosave(PalletDocument* document, const QString& directory, int delayMs, QObject* parent)
    : QObject(parent), _document(document) {
  QDir().mkpath(directory);
  const QString base = directory + QStringLiteral("/recovery-") +
                       QString::number(QCoreApplication::applicationPid());
  _path = base + QStringLiteral(".json");
  _lock = std::make_unique<QLockFile>(base + QStringLiteral(".lock"));
  _lock->setStaleLockTime(0);  // stale only when its process is gone, never by age
  if (!_lock->tryLock(0)) {
    std::fprintf(stderr,
                 "palletballet: cannot lock %s.lock: another console could take this one's "
                 "recovery copy for lost work\n",
                 qPrintable(base));
  }
  _timer.setSingleShot(true);
  _timer.setInterval(delayMs);
  connect(&_timer, &QTimer::timeout, this, &Autosave::saveNow);
  connect(document, &PalletDocument::changed, this, &Autosave::documentChanged);
  connect(document, &PalletDocument::modifiedChanged, this, &Autosave::documentChanged);
  documentChanged();
}

Autosave::~Autosave() {
  remove();
  _lock->unlock();
}

QString Autosave::defaultDirectory() {
  const QByteArray env = qgetenv("PALLETBALLET_RECOVERY_DIR");
  if (!env.isEmpty()) return QString::fromLocal8Bit(env);
  return QStandardPaths::writableLocation(QStandardPaths::AppLocalDataLocation) +
         QStringLiteral("/recovery");
}

void Autosave::documentChanged() {
  if (!_document->isModified()) {
    remove();
    return;
  }
  // Not restarted by later changes: a steady stream of edits is still saved every delayMs.
  if (!_timer.isActive()) _timer.start();
}

void Autosave::remove() {
  _timer.stop();
  QFile::remove(_path);
}

bool Autosave::saveNow() {
  _timer.stop();
  if (!_document->isModified()) return true;
  pb::Json json;
  json["kind"] = kKind;
  json["schema_version"] = pb::kSchemaVersion;
  json["saved_at"] = QDateTime::currentDateTimeUtc().toString(Qt::ISODateWithMs).toStdString();
  json["file"] = _document->filePath().toStdString();
  json["name"] = _document->displayName().toStdString();
  json["pallet"] = pb::pallet_to_json(_document->pallet());
  QSaveFile file(_path);
  const QByteArray bytes = QByteArray::fromStdString(json.dump(2) + "\n");
  if (file.open(QIODevice::WriteOnly) && file.write(bytes) == bytes.size() && file.commit()) {
    _warned = false;
    return true;
  }
  if (!_warned) {  // once, not on every edit
    std::fprintf(stderr, "palletballet: cannot write the recovery copy %s: %s\n", qPrintable(_path),
                 qPrintable(file.errorString()));
    _warned = true;
  }
  return false;
}

QList<Recovery> Autosave::orphans(const QString& directory, QStringList* problems) {
  QList<Recovery> out;
  const QDir dir(directory);
  const QStringList names =
      dir.entryList({QStringLiteral("recovery-*.json")}, QDir::Files, QDir::Name);
  for (const QString& name : names) {
    const QString path = dir.filePath(name);
    QLockFile owner(lockPathOf(path));
    owner.setStaleLockTime(0);
    if (!owner.tryLock(0)) continue;  // its console is running
    owner.unlock();
    QFile file(path);
    if (!file.open(QIODevice::ReadOnly)) {
      if (problems) *problems << path + QStringLiteral(": ") + file.errorString();
      continue;
    }
    const QByteArray bytes =
        file.read(qint64(pb::kMaxDocumentBytes) + 1);  // parse_json refuses more
    auto json = pb::parse_json(std::string_view(bytes.constData(), std::size_t(bytes.size())));
    const pb::Json* root = json ? &*json : nullptr;
    if (root == nullptr || !root->is_object() || root->value("kind", "") != kKind ||
        !root->contains("pallet")) {
      if (problems) *problems << path + QStringLiteral(": not a recovery copy");
      continue;
    }
    auto pallet = pb::pallet_from_json((*root)["pallet"], "/pallet");
    if (!pallet) {
      if (problems) {
        *problems << path + QStringLiteral(": ") +
                         QString::fromStdString(pb::to_string(pallet.diagnostics.front()));
      }
      continue;
    }
    Recovery r;
    r.recoveryPath = path;
    r.filePath = QString::fromStdString(root->value("file", ""));
    r.name = QString::fromStdString(root->value("name", ""));
    r.savedAt = QDateTime::fromString(QString::fromStdString(root->value("saved_at", "")),
                                      Qt::ISODateWithMs);
    r.pallet = std::move(*pallet.value);
    out << r;
  }
  return out;
}

void Autosave::discard(const Recovery& recovery) {
  QFile::remove(recovery.recoveryPath);
  QFile::remove(lockPathOf(recovery.recoveryPath));
}

}  // namespace pb::ui
