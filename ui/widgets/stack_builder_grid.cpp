// SPDX-License-Identifier: MIT
#include "ui/widgets/stack_builder_grid.hpp"

#include <QContextMenuEvent>
#include <QKeyEvent>
#include <QMenu>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <algorithm>
#include <numeric>

#include "core/contract/pallet_metrics.hpp"
#include "ui/models/pallet_document.hpp"
#include "ui/widgets/sku_color.hpp"

namespace pb::ui {

namespace {

constexpr double kMargin = 12.0;  // pixels around the deck

}  // namespace

StackBuilderGrid::StackBuilderGrid(PalletDocument* document, QWidget* parent)
    : QWidget(parent), _document(document) {
  setFocusPolicy(Qt::StrongFocus);
  setMouseTracking(false);
  setAutoFillBackground(true);
  QPalette pal = palette();
  pal.setColor(QPalette::Window, QColor(0xf4, 0xf4, 0xf2));
  setPalette(pal);
  connect(_document, &PalletDocument::changed, this, [this] { refresh(); });
  refresh();
}

QColor StackBuilderGrid::deckColour(pb::PalletType type) {
  return type == pb::PalletType::chep ? QColor(0x6d, 0x8f, 0xb3) : QColor(0xc8, 0xa2, 0x6e);
}

void StackBuilderGrid::setPlacement(const QString& sku, int height) {
  _sku = sku;
  _height = std::max(1, height);
  refresh();
}

void StackBuilderGrid::setSelectedStack(int stack) {
  if (stack < -1 || stack >= static_cast<int>(_stacks.size())) stack = -1;
  if (stack == _selected) return;
  _selected = stack;
  update();
  emit selectedStackChanged(_selected);
}

void StackBuilderGrid::refresh() {
  const pb::PalletConfig& pallet = _document->pallet();
  _stacks = stacks_of(pallet);
  _grid = builder_grid(pallet, _sku.toStdString());
  _flagged.clear();
  for (const auto& d : pb::errors_of(_document->diagnostics())) {
    const int s = stack_of_finding(d, _stacks);
    if (s >= 0) _flagged.push_back(s);
  }
  if (_selected >= static_cast<int>(_stacks.size())) setSelectedStack(-1);
  update();
}

double StackBuilderGrid::scale() const {
  const auto& dims = _document->pallet().base_dims_m;
  const double sx = (width() - 2 * kMargin) / dims[0];
  const double sy = (height() - 2 * kMargin) / dims[1];
  return std::max(1.0, std::min(sx, sy));
}

QPointF StackBuilderGrid::origin() const {
  // Pixel of the deck's centre.
  return {width() / 2.0, height() / 2.0};
}

// +X (belt travel) to the right, +Y up, as seen from above.
QPointF StackBuilderGrid::deckPixel(pb::Vec2 point) const {
  const double s = scale();
  return origin() + QPointF(point[0] * s, -point[1] * s);
}

pb::Vec2 StackBuilderGrid::deckPoint(QPointF pixel) const {
  const double s = scale();
  const QPointF d = pixel - origin();
  return {d.x() / s, -d.y() / s};
}

QPoint StackBuilderGrid::cellCentrePixel(int row, int col) const {
  return deckPixel(cell_centre(_document->pallet(), _grid, row, col)).toPoint();
}

void StackBuilderGrid::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  const pb::PalletConfig& pallet = _document->pallet();
  const auto& dims = pallet.base_dims_m;
  const QRectF deck(deckPixel({-dims[0] / 2, dims[1] / 2}), deckPixel({dims[0] / 2, -dims[1] / 2}));
  // Deck (wood or plastic) and the cell grid.
  p.fillRect(deck, deckColour(pallet.base_pallet_type));
  p.setPen(QPen(QColor(0, 0, 0, 70), 1, Qt::DashLine));
  for (int c = 1; c < _grid.cols; ++c) {
    const double x = deck.left() + deck.width() * c / _grid.cols;
    p.drawLine(QPointF(x, deck.top()), QPointF(x, deck.bottom()));
  }
  for (int r = 1; r < _grid.rows; ++r) {
    const double y = deck.top() + deck.height() * r / _grid.rows;
    p.drawLine(QPointF(deck.left(), y), QPointF(deck.right(), y));
  }
  p.setPen(QPen(QColor(0x5a, 0x43, 0x26), 2));
  p.drawRect(deck);

  // Items bottom to top, so each stack shows its top carton.
  std::vector<int> order(pallet.items.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return pallet.items[a].position[2] < pallet.items[b].position[2];
  });
  for (int k : order) {
    const auto corners = pb::item_footprint(pallet.items[k]);
    QPolygonF poly;
    for (const auto& c : corners) poly << deckPixel(c);
    p.setPen(QPen(QColor(0x30, 0x30, 0x30), 1));
    p.setBrush(skuColor(pallet.items[k].sku));
    p.drawPolygon(poly);
  }
  // Stack heights, selection and stacks named by validation errors.
  QFont font = p.font();
  font.setBold(true);
  p.setFont(font);
  for (int s = 0; s < static_cast<int>(_stacks.size()); ++s) {
    const pb::Item& top = pallet.items[_stacks[s].items.back()];
    QPolygonF poly;
    for (const auto& c : pb::item_footprint(top)) poly << deckPixel(c);
    const bool flagged = std::find(_flagged.begin(), _flagged.end(), s) != _flagged.end();
    if (flagged) {
      p.setPen(QPen(QColor(0xd0, 0x10, 0x10), 3));
      p.setBrush(Qt::NoBrush);
      p.drawPolygon(poly);
    }
    if (s == _selected) {
      p.setPen(QPen(QColor(0x10, 0x50, 0xe0), 3, Qt::SolidLine));
      p.setBrush(QColor(0x10, 0x50, 0xe0, 50));
      p.drawPolygon(poly);
    }
    p.setPen(Qt::black);
    p.drawText(poly.boundingRect(), Qt::AlignCenter,
               QStringLiteral("%1\n×%2").arg(s + 1).arg(_stacks[s].height()));
  }
  // Belt travel arrow.
  p.setPen(QPen(QColor(0x40, 0x40, 0x40), 2));
  const QPointF a(deck.right() - 40, deck.bottom() + kMargin / 2);
  p.drawLine(a, a + QPointF(30, 0));
  p.drawLine(a + QPointF(30, 0), a + QPointF(24, -4));
  p.drawLine(a + QPointF(30, 0), a + QPointF(24, 4));
}

void StackBuilderGrid::mousePressEvent(QMouseEvent* event) {
  if (event->button() != Qt::LeftButton) return QWidget::mousePressEvent(event);
  setFocus(Qt::MouseFocusReason);
  const pb::Vec2 point = deckPoint(event->position());
  const int hit = stack_at(_document->pallet(), _stacks, point);
  if (hit >= 0) {
    setSelectedStack(hit);
    _dragging = hit;
    _dragMoved = false;
    return;
  }
  const auto cell = cell_at(_document->pallet(), _grid, point);
  if (!cell || _sku.isEmpty()) {
    setSelectedStack(-1);
    return;
  }
  const pb::Vec2 centre = cell_centre(_document->pallet(), _grid, cell->row, cell->col);
  // A stack already centred in this cell (covered only partly by the click) is selected instead.
  const int there = stack_at(_document->pallet(), _stacks, centre);
  if (there >= 0) {
    setSelectedStack(there);
    return;
  }
  if (_document->addStack(centre, _sku, _height)) {
    setSelectedStack(static_cast<int>(_stacks.size()) - 1);
  }
}

void StackBuilderGrid::mouseMoveEvent(QMouseEvent* event) {
  if (_dragging < 0 || !(event->buttons() & Qt::LeftButton)) return;
  const auto cell = cell_at(_document->pallet(), _grid, deckPoint(event->position()));
  if (!cell) return;
  const pb::Vec2 centre = cell_centre(_document->pallet(), _grid, cell->row, cell->col);
  const pb::Vec2 now = _stacks[_dragging].centre;
  if (std::hypot(centre[0] - now[0], centre[1] - now[1]) <= kStackCentreTolerance) return;
  // Never onto another stack.
  const int there = stack_at(_document->pallet(), _stacks, centre);
  if (there >= 0 && there != _dragging) return;
  _dragMoved = _document->moveStack(_dragging, centre, PalletDocument::Edit::drag) || _dragMoved;
}

void StackBuilderGrid::mouseReleaseEvent(QMouseEvent* event) {
  if (event->button() == Qt::LeftButton && _dragging >= 0) {
    _document->endDrag();
    _dragging = -1;
  }
  QWidget::mouseReleaseEvent(event);
}

void StackBuilderGrid::keyPressEvent(QKeyEvent* event) {
  if ((event->key() == Qt::Key_Delete || event->key() == Qt::Key_Backspace) && _selected >= 0) {
    deleteSelected();
    return;
  }
  QWidget::keyPressEvent(event);
}

void StackBuilderGrid::contextMenuEvent(QContextMenuEvent* event) {
  const int hit = stack_at(_document->pallet(), _stacks, deckPoint(event->pos()));
  if (hit < 0) return;
  setSelectedStack(hit);
  QMenu menu(this);
  QAction* remove = menu.addAction(tr("Delete %1").arg(stack_label(_stacks, hit)));
  if (menu.exec(event->globalPos()) == remove) deleteSelected();
}

void StackBuilderGrid::deleteSelected() {
  if (_selected < 0) return;
  const int stack = _selected;
  setSelectedStack(-1);
  _document->deleteStack(stack);
}

}  // namespace pb::ui
