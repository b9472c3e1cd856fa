// SPDX-License-Identifier: MIT
#include "ui/models/recent_files.hpp"

#include <QFileInfo>

namespace pb::ui {

namespace {
const QString kKey = QStringLiteral("recentFiles");
}

RecentFiles::RecentFiles(QObject* parent)
    : QObject(parent),
      _settings(std::make_unique<QSettings>(QString::fromLatin1(kOrganization),
                                            QString::fromLatin1(kApplication))) {}

RecentFiles::RecentFiles(const QString& iniPath, QObject* parent)
    : QObject(parent), _settings(std::make_unique<QSettings>(iniPath, QSettings::IniFormat)) {}

QStringList RecentFiles::files() const {
  return _settings->value(kKey).toStringList();
}

void RecentFiles::add(const QString& path) {
  const QString absolute = QFileInfo(path).absoluteFilePath();
  QStringList list = files();
  list.removeAll(absolute);
  list.prepend(absolute);
  while (list.size() > maxCount()) list.removeLast();
  store(list);
}

void RecentFiles::remove(const QString& path) {
  QStringList list = files();
  if (list.removeAll(QFileInfo(path).absoluteFilePath()) > 0) store(list);
}

void RecentFiles::clear() {
  store({});
}

void RecentFiles::store(const QStringList& files) {
  _settings->setValue(kKey, files);
  _settings->sync();
  emit filesChanged(files);
}

}  // namespace pb::ui
