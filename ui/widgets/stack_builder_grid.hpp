// SPDX-License-Identifier: MIT
// The stack builder's deck seen from above: the grid of cells, every item's footprint (coloured
// by SKU, the top of each stack drawn last), the selected stack outlined, and the stack that a
// validation finding names in red. Click an empty cell to place a stack; click a stack to select
// it; drag it to another cell to move it; Delete (or the context menu) removes it.
#pragma once

#include <QWidget>
#include <vector>

#include "core/contract/pallet_config.hpp"
#include "ui/models/stack_builder_model.hpp"

namespace pb::ui {

class PalletDocument;

class StackBuilderGrid : public QWidget {
  Q_OBJECT

 public:
  explicit StackBuilderGrid(PalletDocument* document, QWidget* parent = nullptr);

  /// The SKU and height a click on an empty cell places.
  void setPlacement(const QString& sku, int height);
  QString placementSku() const { return _sku; }
  int placementHeight() const { return _height; }

  /// The selected stack (stacks_of() index) or -1.
  int selectedStack() const { return _selected; }
  void setSelectedStack(int stack);

  /// The grid shown (builder_grid() of the pallet and the placement SKU).
  pb::GridShape grid() const { return _grid; }
  /// Widget pixel at the centre of cell (row, col), and the deck point at a widget pixel.
  QPoint cellCentrePixel(int row, int col) const;
  pb::Vec2 deckPoint(QPointF pixel) const;
  /// Widget pixel of deck point (x, y): +X (belt travel) to the right, +Y up.
  QPointF deckPixel(pb::Vec2 point) const;

  /// Fill of the deck (an item is filled with its SKU's colour, ui/widgets/sku_color.hpp).
  static QColor deckColour(pb::PalletType type);

  QSize sizeHint() const override { return {480, 340}; }
  QSize minimumSizeHint() const override { return {240, 170}; }

 signals:
  void selectedStackChanged(int stack);

 public slots:
  /// Removes the selected stack, if any.
  void deleteSelected();

 protected:
  void paintEvent(QPaintEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;
  void contextMenuEvent(QContextMenuEvent* event) override;

 private:
  void refresh();
  /// Pixels per metre and the deck's top-left pixel for the current size.
  double scale() const;
  QPointF origin() const;

  PalletDocument* _document;
  std::vector<StackView> _stacks;
  pb::GridShape _grid;
  std::vector<int> _flagged;  ///< stacks named by validation errors
  QString _sku;
  int _height = 1;
  int _selected = -1;
  int _dragging = -1;  ///< stack being dragged (moved with Edit::drag)
  bool _dragMoved = false;
};

}  // namespace pb::ui
