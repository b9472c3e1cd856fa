// SPDX-License-Identifier: MIT
// Recovery of unsaved work: while the document has unsaved changes, a copy of it is written to a
// recovery file a few seconds after each change (at most `delayMs` of edits are ever at risk), and
// removed once the document is saved, undone to its saved state, or the console closes. A recovery
// file left behind by a console that died (a crash, kill -9, a power cut) is an orphan: the next
// console offers to restore it (FileActions::offerRecovery).
//
// Each console holds a lock (QLockFile, by PID) beside its own recovery file, so two consoles never
// take each other's work for an orphan. Writes are atomic (QSaveFile): a kill mid-write leaves the
// previous copy.
//
// Wiring (MainWindow::enableAutosave): PalletDocument::changed / modifiedChanged -> Autosave.
#pragma once

#include <QDateTime>
#include <QList>
#include <QLockFile>
#include <QObject>
#include <QString>
#include <QTimer>
#include <memory>

#include "core/contract/pallet_config.hpp"

namespace pb::ui {

class PalletDocument;

/// What a console that died had not saved.
struct Recovery {
  QString recoveryPath;  ///< the recovery file
  QString filePath;      ///< the document's own file ("" if it had none yet)
  QString name;          ///< the document's display name
  QDateTime savedAt;     ///< when the copy was written
  pb::PalletConfig pallet;
};

class Autosave : public QObject {
  Q_OBJECT

 public:
  Autosave(PalletDocument* document, const QString& directory, int delayMs = 2000,
           QObject* parent = nullptr);
  /// A clean exit leaves nothing behind: the recovery file and the lock are removed.
  ~Autosave() override;

  /// $PALLETBALLET_RECOVERY_DIR, else the user's application data folder + "/recovery".
  static QString defaultDirectory();

  /// This console's recovery file (it exists only while there are unsaved changes).
  QString path() const { return _path; }
  /// Writes the copy now (the timer calls it). False, with a warning on stderr, when it cannot.
  bool saveNow();

  /// The recovery files in `directory` whose console is gone. A file that cannot be read is left
  /// where it is and named in `problems`.
  static QList<Recovery> orphans(const QString& directory, QStringList* problems = nullptr);
  /// Removes an orphan (restored or declined).
  static void discard(const Recovery& recovery);

 private:
  void documentChanged();
  void remove();

  PalletDocument* _document;
  QString _path;
  std::unique_ptr<QLockFile> _lock;
  QTimer _timer;
  bool _warned = false;
};

}  // namespace pb::ui
