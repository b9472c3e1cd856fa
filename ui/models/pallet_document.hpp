// SPDX-License-Identifier: MIT
// The pallet being edited in the console: the PalletConfig, the file it came from, whether it has
// changed since, and an undo stack holding every edit.
//
// Wiring (MainWindow):
//   PalletDocument::changed(const pb::PalletConfig&)   -> panels that show the pallet (replay,
//                                                         friction chart marker, analysis)
//   PalletDocument::validated(const pb::Diagnostics&)  -> inline messages (stack builder does it)
//   PalletDocument::titleChanged(const QString&)       -> QMainWindow::setWindowTitle
//   PalletDocument::modifiedChanged(bool)              -> QMainWindow::setWindowModified
//   PalletDocument::fileChanged(const QString& path)   -> recent files (FileActions does it)
//   undoStack()->createUndoAction/createRedoAction      -> Edit menu (FileActions does it)
#pragma once

#include <QObject>
#include <QString>
#include <QUndoStack>

#include "core/base/diagnostic.hpp"
#include "core/base/enums.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/scenario.hpp"

namespace pb::ui {

/// What a file operation found: ok, or why not (each message "pointer: sentence", the pointer
/// into the file). Warnings may accompany success.
struct FileOutcome {
  bool ok = false;
  QStringList messages;
};

/// Every edit goes through the undo stack as one command that stores the pallet before and after
/// it; undo and redo restore those values exactly. After every change (edit, undo, redo, open,
/// new) the document emits changed() and validated().
///
/// Continuous controls (a dial or a spin box being dragged, a stack being dragged) pass
/// Edit::drag: consecutive drag edits of the same kind (and the same stack) merge into one undo
/// step until endDrag() is called (on release / editingFinished).
class PalletDocument : public QObject {
  Q_OBJECT

 public:
  enum class Edit { step, drag };

  explicit PalletDocument(QObject* parent = nullptr);
  ~PalletDocument() override;

  const pb::PalletConfig& pallet() const { return _pallet; }
  /// validate() of the current pallet (errors and warnings, validate()'s pointers).
  const pb::Diagnostics& diagnostics() const { return _diagnostics; }
  bool isValid() const { return !pb::has_errors(_diagnostics); }
  QUndoStack* undoStack() { return &_undo; }

  /// The file the document is saved to; empty for a new document, a curated scenario or a
  /// scenario file (saving those asks for a new name, so a scenario is never overwritten).
  QString filePath() const { return _path; }
  /// "Untitled", the file's name, or "<scenario name> (scenario)".
  QString displayName() const { return _name; }
  bool isModified() const { return !_undo.isClean(); }
  /// "<name>[*] — PalletBallet" for QWidget::setWindowTitle (with setWindowModified, Qt shows
  /// the "*" when modified).
  QString windowTitle() const;

  // ---- Files. On failure the current document is left exactly as it was.
  /// An empty EUR pallet (refrigerated, 2 °C), no file, unmodified, empty undo history.
  void newDocument();
  /// Reads a pallet JSON file, or a scenario file (its "pallet"; pointers start "/pallet").
  /// Structural errors (bad JSON, wrong types, unknown values, missing keys) refuse the file;
  /// a pallet that reads but breaks a physical rule is opened and its findings returned as
  /// messages (they are also in diagnostics()).
  FileOutcome open(const QString& path);
  /// Writes pallet_to_json(pallet).dump(2) + "\n" atomically (QSaveFile): on any failure the old
  /// file is untouched. Fails with a message when the document has no file (use saveAs).
  FileOutcome save();
  FileOutcome saveAs(const QString& path);
  /// The bytes save() writes for `config` (pretty JSON with computed fields, trailing newline).
  static QByteArray serialize(const pb::PalletConfig& config);

  // ---- Edits (each one undo step; returns false, changing nothing, when the edit is not
  // possible: a stack index out of range, an unknown SKU, a height < 1).
  /// `height` cartons of `sku` (catalog) standing on the deck at centre (x, y).
  bool addStack(pb::Vec2 centre, const QString& sku, int height);
  /// Moves every item of stack `stack` (stacks_of() index) so its centre is at `centre`.
  bool moveStack(int stack, pb::Vec2 centre, Edit edit = Edit::step);
  bool deleteStack(int stack);
  /// Adds copies of the top carton, or removes cartons from the top, until `height` (>= 1).
  bool resizeStack(int stack, int height, Edit edit = Edit::step);
  /// Replaces the items by a layer pattern (column, brick or pinwheel) of `layers` layers of
  /// `sku`, as many per layer as fit the deck (pb::build_from_scanner); the pallet's other fields
  /// stay. On failure returns false and the reasons in `messages`.
  bool applyPreset(pb::LayerPattern pattern, const QString& sku, int layers,
                   QStringList* messages = nullptr);
  bool setWrap(pb::WrapType wrap);
  bool setEnvironment(pb::Environment env);
  bool setBodyTemperature(double celsius, Edit edit = Edit::step);
  bool setSecondsSinceTempChange(double seconds, Edit edit = Edit::step);
  /// The type's nominal deck and tare; items keep x, y and are lifted or lowered with the deck.
  bool setPalletType(pb::PalletType type);
  /// Replaces the whole pallet (one step), e.g. a curated scenario: `text` names the step.
  bool replacePallet(const pb::PalletConfig& config, const QString& text);
  /// Opens a curated scenario as a document of its own, as File > Open does a file: its pallet,
  /// named after the scenario, unmodified, no file yet (Save asks where), a fresh undo history.
  /// Ask to save unsaved work first (FileActions::maybeSave; the console's picker does).
  bool loadScenario(const pb::Scenario& scenario);
  /// Restores work a console lost (autosave.hpp): the document of `path` as saved (or, without a
  /// readable file, a new one named `name`) with `pallet` on top as one undoable step, so the
  /// restored work is unsaved again and Undo shows what the file held.
  void restoreUnsaved(const pb::PalletConfig& pallet, const QString& path, const QString& name);
  /// Ends the current drag: the next drag edit starts a new undo step.
  void endDrag();

 signals:
  void changed(const pb::PalletConfig& pallet);
  void validated(const pb::Diagnostics& diagnostics);
  void modifiedChanged(bool modified);
  void titleChanged(const QString& title);
  /// The document now belongs to this file (after open or save as); empty after new.
  void fileChanged(const QString& path);

 private:
  friend class PalletEditCommand;
  /// Pushes an edit from the current pallet to `after`. `mergeKey` != 0 lets consecutive drag
  /// edits with the same key merge.
  bool push(pb::PalletConfig after, const QString& text, int mergeKey = 0);
  /// Sets the pallet (undo/redo/new/open) and emits.
  void apply(const pb::PalletConfig& pallet);
  void setFile(const QString& path, const QString& name);
  /// Closes the command before the undo index for merging.
  void closeTop();

  pb::PalletConfig _pallet;
  pb::Diagnostics _diagnostics;
  QUndoStack _undo;
  QString _path;
  QString _name;
  bool _dragOpen = false;
  bool _pushing = false;
};

}  // namespace pb::ui
