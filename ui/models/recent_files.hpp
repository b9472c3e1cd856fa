// SPDX-License-Identifier: MIT
// Recently opened or saved pallet files, kept in QSettings under "recentFiles" (most recent
// first, at most maxCount(), no duplicates).
#pragma once

#include <QObject>
#include <QSettings>
#include <QStringList>
#include <memory>

namespace pb::ui {

class RecentFiles : public QObject {
  Q_OBJECT

 public:
  /// Organisation and application names of the console's settings.
  static constexpr const char* kOrganization = "PalletBallet";
  static constexpr const char* kApplication = "PalletBallet Console";

  /// The console's settings (QSettings(kOrganization, kApplication)).
  explicit RecentFiles(QObject* parent = nullptr);
  /// An INI file of its own (tests use a temporary one).
  explicit RecentFiles(const QString& iniPath, QObject* parent = nullptr);

  static constexpr int maxCount() { return 8; }
  /// Absolute paths, most recent first.
  QStringList files() const;
  /// Moves (or adds) `path` to the front.
  void add(const QString& path);
  void remove(const QString& path);
  void clear();

 signals:
  void filesChanged(const QStringList& files);

 private:
  void store(const QStringList& files);
  std::unique_ptr<QSettings> _settings;
};

}  // namespace pb::ui
