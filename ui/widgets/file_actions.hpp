// SPDX-License-Identifier: MIT
// The File and Edit actions of a PalletDocument: New, Open..., Open Recent, Save, Save As...,
// Undo, Redo, with their standard shortcuts. Asks before discarding unsaved changes and shows
// errors (with their pointers) in a message box. Dialogs go through replaceable hooks so tests
// drive the actions without modal dialogs.
//
// Wiring (MainWindow): menuBar()->addMenu(actions->fileMenu()); menuBar()->addMenu(
// actions->editMenu()); toolbars may add newAction() etc. FileActions::opened(path) after a
// file was opened (e.g. to re-run the analysis).
#pragma once

#include <QObject>
#include <functional>

#include "ui/models/pallet_document.hpp"
#include "ui/models/recent_files.hpp"

class QAction;
class QMenu;
class QWidget;

namespace pb::ui {

class FileActions : public QObject {
  Q_OBJECT

 public:
  /// What the user answers when the document has unsaved changes.
  enum class Unsaved { save, discard, cancel };
  /// What the user answers to work a console lost (autosave.hpp).
  enum class Lost { restore, discard, later };
  struct Hooks {
    std::function<QString()> openPath;                ///< "" = cancelled
    std::function<QString(const QString&)> savePath;  ///< suggested name -> path, "" = cancelled
    std::function<Unsaved()> askUnsaved;
    std::function<void(const QString& title, const QString& text)> showError;
    std::function<Lost(const QString& text)> askRestore;
  };

  /// Dialogs parented to `dialogParent`; recent files in `recent` (not owned).
  FileActions(PalletDocument* document, RecentFiles* recent, QWidget* dialogParent,
              QObject* parent = nullptr);
  ~FileActions() override;

  /// Replaces the dialogs (tests).
  void setHooks(Hooks hooks) { _hooks = std::move(hooks); }

  QAction* newAction() const { return _new; }
  QAction* openAction() const { return _open; }
  QAction* saveAction() const { return _save; }
  QAction* saveAsAction() const { return _saveAs; }
  QAction* undoAction() const { return _undo; }
  QAction* redoAction() const { return _redo; }
  QMenu* fileMenu() const { return _fileMenu; }
  QMenu* recentMenu() const { return _recentMenu; }
  QMenu* editMenu() const { return _editMenu; }

 public slots:
  bool newDocument();
  bool open();
  bool openPath(const QString& path);
  bool save();
  bool saveAs();
  /// True when there are no unsaved changes left (saved, discarded); false when cancelled.
  bool maybeSave();
  /// Offers, newest first, each copy of unsaved work that a console which died left in
  /// `directory` (Autosave::orphans): Restore opens it (and ends the offers), Discard deletes it,
  /// Later keeps it for the next start. True when one was restored.
  bool offerRecovery(const QString& directory);

 signals:
  void opened(const QString& path);

 private:
  void rebuildRecentMenu();

  PalletDocument* _document;
  RecentFiles* _recent;
  QWidget* _dialogParent;
  Hooks _hooks;
  QAction* _new;
  QAction* _open;
  QAction* _save;
  QAction* _saveAs;
  QAction* _undo;
  QAction* _redo;
  QMenu* _fileMenu;
  QMenu* _recentMenu;
  QMenu* _editMenu;
};

}  // namespace pb::ui
