// SPDX-License-Identifier: MIT
// The stack builder panel: the deck grid (StackBuilderGrid), the searchable catalog, the height
// of the stack to place (or of the selected stack), layer-pattern presets, the pallet's wrap,
// environment, body temperature, time since the temperature changed and pallet type, a live
// summary (mass, centre of mass, stack height, overhang, support) and the validation findings
// inline, each naming the stack that is wrong (selecting a finding selects its stack).
//
// Wiring (MainWindow): the panel edits the PalletDocument it is given and listens to it; it has
// no signals of its own to wire. Put it in a dock or a splitter; give it the same document as
// ScenarioPicker and FileActions.
#pragma once

#include <QWidget>

#include "core/contract/pallet_config.hpp"

class QBoxLayout;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QListWidget;
class QPushButton;
class QSpinBox;

namespace pb::ui {

class CatalogList;
class PalletDocument;
class StackBuilderGrid;

class StackBuilderPanel : public QWidget {
  Q_OBJECT

 public:
  explicit StackBuilderPanel(PalletDocument* document, QWidget* parent = nullptr);

  StackBuilderGrid* grid() const { return _grid; }
  CatalogList* catalog() const { return _catalog; }
  QSpinBox* heightSpin() const { return _height; }
  QComboBox* patternCombo() const { return _pattern; }
  QSpinBox* layersSpin() const { return _layers; }
  QPushButton* presetButton() const { return _applyPreset; }
  QComboBox* wrapCombo() const { return _wrap; }
  QComboBox* environmentCombo() const { return _env; }
  QComboBox* palletTypeCombo() const { return _type; }
  QDoubleSpinBox* temperatureSpin() const { return _temp; }
  QDoubleSpinBox* minutesSinceChangeSpin() const { return _since; }
  /// The summary line (summary_line()) and the findings as listed.
  QString summaryText() const;
  QStringList findingTexts() const;

  /// Narrower than this, the controls go under the deck instead of beside it.
  static constexpr int kSideBySideWidth = 700;

 public slots:
  /// Applies the preset chosen in the panel (pattern, catalog SKU, layers).
  void applyPreset();

 protected:
  void resizeEvent(QResizeEvent* event) override;

 private:
  void showPallet(const pb::PalletConfig& pallet);
  void showSelection(int stack);

  PalletDocument* _document;
  QBoxLayout* _layout = nullptr;
  StackBuilderGrid* _grid;
  CatalogList* _catalog;
  QSpinBox* _height;
  QComboBox* _pattern;
  QSpinBox* _layers;
  QPushButton* _applyPreset;
  QComboBox* _wrap;
  QComboBox* _env;
  QComboBox* _type;
  QDoubleSpinBox* _temp;
  QDoubleSpinBox* _since;
  QLabel* _summary;
  QLabel* _presetMessage;
  QListWidget* _findings;
  bool _updating = false;  ///< true while the panel shows the document (no edits back)
};

}  // namespace pb::ui
