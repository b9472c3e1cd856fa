// SPDX-License-Identifier: MIT
#include "ui/widgets/file_actions.hpp"

#include <QAction>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QLocale>
#include <QMenu>
#include <QMessageBox>
#include <QPushButton>
#include <algorithm>
#include <cstdio>

#include "ui/models/autosave.hpp"

namespace pb::ui {

namespace {

const QString kFilter = QStringLiteral("Pallet or scenario JSON (*.json);;All files (*)");

}  // namespace

FileActions::FileActions(PalletDocument* document, RecentFiles* recent, QWidget* dialogParent,
                         QObject* parent)
    : QObject(parent), _document(document), _recent(recent), _dialogParent(dialogParent) {
  _hooks.openPath = [this] {
    return QFileDialog::getOpenFileName(_dialogParent, tr("Open pallet"), QString(), kFilter);
  };
  _hooks.savePath = [this](const QString& suggested) {
    return QFileDialog::getSaveFileName(_dialogParent, tr("Save pallet as"), suggested, kFilter);
  };
  _hooks.askUnsaved = [this] {
    const auto answer = QMessageBox::question(
        _dialogParent, tr("Unsaved changes"),
        tr("%1 has changes that are not saved. Save them first?").arg(_document->displayName()),
        QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
    return answer == QMessageBox::Save      ? Unsaved::save
           : answer == QMessageBox::Discard ? Unsaved::discard
                                            : Unsaved::cancel;
  };
  _hooks.showError = [this](const QString& title, const QString& text) {
    QMessageBox::warning(_dialogParent, title, text);
  };
  _hooks.askRestore = [this](const QString& text) {
    QMessageBox box(QMessageBox::Question, tr("Restore unsaved work?"), text, QMessageBox::NoButton,
                    _dialogParent);
    QPushButton* restore = box.addButton(tr("Restore"), QMessageBox::AcceptRole);
    QPushButton* discard = box.addButton(tr("Discard"), QMessageBox::DestructiveRole);
    box.addButton(tr("Later"), QMessageBox::RejectRole);
    box.setDefaultButton(restore);
    box.exec();
    return box.clickedButton() == restore   ? Lost::restore
           : box.clickedButton() == discard ? Lost::discard
                                            : Lost::later;
  };

  _new = new QAction(tr("&New pallet"), this);
  _new->setShortcut(QKeySequence::New);
  _open = new QAction(tr("&Open..."), this);
  _open->setShortcut(QKeySequence::Open);
  _save = new QAction(tr("&Save"), this);
  _save->setShortcut(QKeySequence::Save);
  _saveAs = new QAction(tr("Save &As..."), this);
  _saveAs->setShortcut(QKeySequence::SaveAs);
  _undo = _document->undoStack()->createUndoAction(this, tr("&Undo"));
  _undo->setShortcut(QKeySequence::Undo);
  _redo = _document->undoStack()->createRedoAction(this, tr("&Redo"));
  _redo->setShortcut(QKeySequence::Redo);
  connect(_new, &QAction::triggered, this, &FileActions::newDocument);
  connect(_open, &QAction::triggered, this, qOverload<>(&FileActions::open));
  connect(_save, &QAction::triggered, this, &FileActions::save);
  connect(_saveAs, &QAction::triggered, this, &FileActions::saveAs);

  _fileMenu = new QMenu(tr("&File"), _dialogParent);
  _recentMenu = new QMenu(tr("Open &Recent"), _fileMenu);
  _editMenu = new QMenu(tr("&Edit"), _dialogParent);
  _fileMenu->addAction(_new);
  _fileMenu->addAction(_open);
  _fileMenu->addMenu(_recentMenu);
  _fileMenu->addSeparator();
  _fileMenu->addAction(_save);
  _fileMenu->addAction(_saveAs);
  _editMenu->addAction(_undo);
  _editMenu->addAction(_redo);
  if (_recent) connect(_recent, &RecentFiles::filesChanged, this, &FileActions::rebuildRecentMenu);
  connect(_document, &PalletDocument::fileChanged, this, [this](const QString& path) {
    if (_recent && !path.isEmpty()) _recent->add(path);
  });
  rebuildRecentMenu();
}

FileActions::~FileActions() {
  if (!_dialogParent) {
    delete _fileMenu;
    delete _editMenu;
  }
}

void FileActions::rebuildRecentMenu() {
  _recentMenu->clear();
  const QStringList files = _recent ? _recent->files() : QStringList();
  for (const QString& path : files) {
    QAction* action = _recentMenu->addAction(QFileInfo(path).fileName());
    action->setToolTip(path);
    action->setData(path);
    connect(action, &QAction::triggered, this, [this, path] { openPath(path); });
  }
  _recentMenu->setEnabled(!files.isEmpty());
}

bool FileActions::maybeSave() {
  if (!_document->isModified()) return true;
  switch (_hooks.askUnsaved()) {
    case Unsaved::save:
      return save();
    case Unsaved::discard:
      return true;
    case Unsaved::cancel:
      return false;
  }
  return false;
}

bool FileActions::newDocument() {
  if (!maybeSave()) return false;
  _document->newDocument();
  return true;
}

bool FileActions::open() {
  const QString path = _hooks.openPath();
  if (path.isEmpty()) return false;
  return openPath(path);
}

bool FileActions::openPath(const QString& path) {
  if (!maybeSave()) return false;
  const FileOutcome outcome = _document->open(path);
  if (!outcome.ok) {
    if (_recent && !QFileInfo::exists(path)) _recent->remove(path);
    _hooks.showError(tr("Cannot open %1").arg(QFileInfo(path).fileName()),
                     tr("The pallet was not opened; the current one is unchanged.\n\n") +
                         outcome.messages.join(QLatin1Char('\n')));
    return false;
  }
  if (_recent) _recent->add(path);  // scenario files too: they are opened, not saved to
  emit opened(path);
  return true;
}

bool FileActions::save() {
  if (_document->filePath().isEmpty()) return saveAs();
  const FileOutcome outcome = _document->save();
  if (!outcome.ok) {
    _hooks.showError(tr("Cannot save"), outcome.messages.join(QLatin1Char('\n')));
  }
  return outcome.ok;
}

bool FileActions::saveAs() {
  QString suggested = _document->filePath();
  if (suggested.isEmpty())
    suggested = QString::fromStdString(_document->pallet().pallet_id) + QStringLiteral(".json");
  const QString path = _hooks.savePath(suggested);
  if (path.isEmpty()) return false;
  const FileOutcome outcome = _document->saveAs(path);
  if (!outcome.ok) {
    _hooks.showError(tr("Cannot save"), outcome.messages.join(QLatin1Char('\n')));
  }
  return outcome.ok;
}

bool FileActions::offerRecovery(const QString& directory) {
  QStringList problems;
  QList<Recovery> lost = Autosave::orphans(directory, &problems);
  for (const QString& p : problems) std::fprintf(stderr, "palletballet: %s\n", qPrintable(p));
  std::sort(lost.begin(), lost.end(),
            [](const Recovery& a, const Recovery& b) { return a.savedAt > b.savedAt; });
  for (const Recovery& r : lost) {
    const QString what = r.filePath.isEmpty() ? r.name : QDir::toNativeSeparators(r.filePath);
    const QString text =
        tr("PalletBallet closed without saving changes to %1 (last copied %2). Restore them?")
            .arg(what, QLocale().toString(r.savedAt.toLocalTime(), QLocale::ShortFormat));
    switch (_hooks.askRestore ? _hooks.askRestore(text) : Lost::later) {
      case Lost::restore:
        _document->restoreUnsaved(r.pallet, r.filePath, r.name);
        Autosave::discard(r);  // the document holds it now, and the autosave copies it again
        return true;
      case Lost::discard:
        Autosave::discard(r);
        break;
      case Lost::later:
        break;
    }
  }
  return false;
}

}  // namespace pb::ui
