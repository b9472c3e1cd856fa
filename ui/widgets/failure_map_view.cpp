// SPDX-License-Identifier: MIT
#include "ui/widgets/failure_map_view.hpp"

#include <QPaintEvent>
#include <QPainter>
#include <algorithm>
#include <cmath>

namespace pb::ui {

namespace {

constexpr double kLeft = 52.0;  // room for the acceleration labels and title
constexpr double kTop = 8.0;
constexpr double kRight = 10.0;

/// The fractional index of x among increasing cell values (linear between cell centres,
/// extrapolated with the end spacing outside them).
double fractionalIndex(const std::vector<double>& v, double x) {
  if (v.size() == 1) return 0.0;
  if (x <= v.front()) return (x - v.front()) / (v[1] - v[0]);
  for (std::size_t i = 1; i < v.size(); ++i) {
    if (x <= v[i]) return static_cast<double>(i - 1) + (x - v[i - 1]) / (v[i] - v[i - 1]);
  }
  return static_cast<double>(v.size() - 1) + (x - v.back()) / (v.back() - v[v.size() - 2]);
}

QString modeLabel(FailureMode mode) {
  switch (mode) {
    case FailureMode::no_failure:
      return QObject::tr("safe");
    case FailureMode::tip_over:
      return QObject::tr("tips");
    case FailureMode::top_item_slide:
      return QObject::tr("item slides");
    case FailureMode::pallet_slip:
      return QObject::tr("pallet slips");
    case FailureMode::load_shift:
      return QObject::tr("load shifts");
    case FailureMode::cannot_stand:
      return QObject::tr("cannot stand");
  }
  return {};
}

}  // namespace

FailureMapView::FailureMapView(QWidget* parent) : QWidget(parent) {
  setAttribute(Qt::WA_OpaquePaintEvent);
  setAccessibleName(tr("Failure map: speed against start-up acceleration"));
}

QColor FailureMapView::cellColor(const Cell& cell) {
  if (cell.outcome == Outcome::unstable) return {150, 150, 150};
  if (cell.outcome == Outcome::safe) return {46, 160, 67};
  switch (cell.mode) {
    case FailureMode::tip_over:
      return {200, 30, 30};
    case FailureMode::top_item_slide:
      return {245, 140, 20};
    case FailureMode::pallet_slip:
      return {120, 70, 190};
    case FailureMode::load_shift:
      return {190, 50, 150};
    case FailureMode::cannot_stand:
    case FailureMode::no_failure:
      break;
  }
  return {200, 30, 30};  // failed without a mode: still a failure
}

void FailureMapView::setGrid(const Grid& grid) {
  const std::size_t n = grid.speeds_mps.size() * grid.accels_mps2.size();
  if (n == 0 || grid.cells.size() != n) {
    _grid = {};
    _message = tr("Failure map unavailable: %1 cells for %2 speeds x %3 accelerations")
                   .arg(grid.cells.size())
                   .arg(grid.speeds_mps.size())
                   .arg(grid.accels_mps2.size());
  } else {
    _grid = grid;
    _message.clear();
  }
  _legend = legend();  // once per grid: the layout that places the plot uses it on every cell
  update();
}

void FailureMapView::setMap(const FailureMap& map) {
  Grid g;
  g.speeds_mps = map.speeds_mps;
  g.accels_mps2 = map.accels_mps2;
  g.cells.reserve(map.cells.size());
  for (const MapCell& c : map.cells) g.cells.push_back({c.outcome, c.mode, c.non_monotone});
  setGrid(g);
}

void FailureMapView::clear() {
  _grid = {};
  _legend.clear();
  _message.clear();
  update();
}

void FailureMapView::setDialledPoint(double speed_mps, double accel_mps2) {
  _dialled = QPointF(speed_mps, accel_mps2);
  update();
}

QRectF FailureMapView::plotRect() const {
  // Below the plot: the speed labels, the axis title, then the legend's rows.
  const QFontMetrics fm(font());
  int rows = 1;
  legendLayout(&rows);
  const double bottom = 2.0 * fm.height() + 6.0 + rows * (fm.height() + 2.0) + 2.0;
  return QRectF(kLeft, kTop, std::max(10.0, width() - kLeft - kRight),
                std::max(10.0, height() - kTop - bottom));
}

std::vector<std::pair<QColor, QString>> FailureMapView::legend() const {
  std::vector<std::pair<QColor, QString>> out;
  out.emplace_back(cellColor({Outcome::safe, FailureMode::no_failure, false}),
                   modeLabel(FailureMode::no_failure));
  for (FailureMode m : {FailureMode::tip_over, FailureMode::top_item_slide,
                        FailureMode::pallet_slip, FailureMode::load_shift}) {
    const bool present = std::any_of(_grid.cells.begin(), _grid.cells.end(), [&](const Cell& c) {
      return c.outcome == Outcome::failed && c.mode == m;
    });
    if (present) out.emplace_back(cellColor({Outcome::failed, m, false}), modeLabel(m));
  }
  if (std::any_of(_grid.cells.begin(), _grid.cells.end(),
                  [](const Cell& c) { return c.outcome == Outcome::unstable; })) {
    out.emplace_back(cellColor({Outcome::unstable, FailureMode::no_failure, false}),
                     tr("unstable"));
  }
  if (std::any_of(_grid.cells.begin(), _grid.cells.end(),
                  [](const Cell& c) { return c.non_monotone; })) {
    out.emplace_back(Qt::black, tr("non-monotone"));
  }
  return out;
}

std::vector<QPointF> FailureMapView::legendLayout(int* rows) const {
  const QFontMetrics fm(font());
  const double left = kLeft, right = std::max(kLeft + 10.0, width() - kRight);
  std::vector<QPointF> at;  // (x, row)
  double x = left;
  int row = 0;
  for (const auto& [color, name] : _legend) {
    const double w = 13.0 + fm.horizontalAdvance(name);
    if (x > left && x + w > right) {  // wrap to the next row
      x = left;
      ++row;
    }
    at.emplace_back(x, row);
    x += w + 10.0;
  }
  *rows = row + 1;
  return at;
}

QPointF FailureMapView::valuePoint(double speed, double accel) const {
  if (!hasGrid()) return {};
  const QRectF r = plotRect();
  const double w = r.width() / static_cast<double>(_grid.speeds_mps.size());
  const double h = r.height() / static_cast<double>(_grid.accels_mps2.size());
  const QPointF c(r.left() + (fractionalIndex(_grid.speeds_mps, speed) + 0.5) * w,
                  r.bottom() - (fractionalIndex(_grid.accels_mps2, accel) + 0.5) * h);
  return {std::clamp(c.x(), r.left(), r.right()), std::clamp(c.y(), r.top(), r.bottom())};
}

QRectF FailureMapView::cellRect(int si, int ai) const {
  if (!hasGrid() || si < 0 || ai < 0 || si >= static_cast<int>(_grid.speeds_mps.size()) ||
      ai >= static_cast<int>(_grid.accels_mps2.size())) {
    return {};
  }
  // Cells are uniform in index space so that an uneven grid still reads as a grid; the value
  // axis is drawn at the cell centres.
  const QRectF r = plotRect();
  const double w = r.width() / static_cast<double>(_grid.speeds_mps.size());
  const double h = r.height() / static_cast<double>(_grid.accels_mps2.size());
  return {r.left() + si * w, r.bottom() - (ai + 1) * h, w, h};
}

void FailureMapView::paintEvent(QPaintEvent*) {
  _cut.clear();
  QPainter p(this);
  p.fillRect(rect(), palette().color(QPalette::Base));
  p.setRenderHint(QPainter::Antialiasing, false);
  const QRectF plot = plotRect();
  if (!hasGrid()) {
    p.setPen(palette().color(QPalette::Text));
    p.drawText(rect().adjusted(8, 8, -8, -8), Qt::AlignCenter | Qt::TextWordWrap,
               _message.isEmpty() ? tr("No failure map yet") : _message);
    return;
  }
  const int ns = static_cast<int>(_grid.speeds_mps.size());
  const int na = static_cast<int>(_grid.accels_mps2.size());
  for (int a = 0; a < na; ++a) {
    for (int s = 0; s < ns; ++s) {
      const Cell& c = _grid.cells[static_cast<std::size_t>(a * ns + s)];
      const QRectF cr = cellRect(s, a);
      p.fillRect(cr, cellColor(c));
      if (c.non_monotone) {
        // A black dot in the top-left corner: this cell disagrees with a neighbour's ordering.
        const double d = std::max(3.0, std::min(cr.width(), cr.height()) * 0.28);
        p.fillRect(QRectF(cr.left() + 1.0, cr.top() + 1.0, d, d), Qt::black);
      }
    }
  }
  // Grid lines and frame.
  p.setPen(QPen(QColor(255, 255, 255, 160), 1.0));
  for (int s = 1; s < ns; ++s) {
    const double x = cellRect(s, 0).left();
    p.drawLine(QPointF(x, plot.top()), QPointF(x, plot.bottom()));
  }
  for (int a = 1; a < na; ++a) {
    const double y = cellRect(0, a).bottom();
    p.drawLine(QPointF(plot.left(), y), QPointF(plot.right(), y));
  }
  const QColor text = palette().color(QPalette::Text);
  p.setPen(text);
  p.drawRect(plot);

  // Axis labels at (a subset of) the cell centres; text that does not fit its box is noted.
  const QFontMetrics fm(font());
  const auto fits = [&](const QString& s, double room) {
    if (fm.horizontalAdvance(s) > room + 0.5) _cut << s;
  };
  const int xStep =
      std::max(1, static_cast<int>(std::ceil(ns * fm.horizontalAdvance(QStringLiteral("0.00 ")) /
                                             plot.width())));
  for (int s = 0; s < ns; s += xStep) {
    const QRectF cr = cellRect(s, 0);
    const QString label = QString::number(_grid.speeds_mps[static_cast<std::size_t>(s)], 'f', 2);
    fits(label, 60.0);
    p.drawText(QRectF(cr.center().x() - 30, plot.bottom() + 2, 60, fm.height()), Qt::AlignHCenter,
               label);
  }
  const int yStep = std::max(1, static_cast<int>(std::ceil(na * fm.height() / plot.height())));
  for (int a = 0; a < na; a += yStep) {
    const QRectF cr = cellRect(0, a);
    const QString label = QString::number(_grid.accels_mps2[static_cast<std::size_t>(a)], 'f', 1);
    fits(label, kLeft - 18);
    p.drawText(QRectF(2, cr.center().y() - fm.height() / 2.0, kLeft - 18, fm.height()),
               Qt::AlignRight | Qt::AlignVCenter, label);
  }
  const QString xTitle = tr("belt speed (m/s)"), yTitle = tr("start-up (m/s²)");
  fits(xTitle, plot.width());
  fits(yTitle, plot.height());
  p.drawText(QRectF(plot.left(), plot.bottom() + fm.height() + 2, plot.width(), fm.height()),
             Qt::AlignHCenter, xTitle);
  p.save();
  p.translate(12, plot.center().y());
  p.rotate(-90);
  p.drawText(QRectF(-plot.height() / 2, -fm.height() / 2.0, plot.height(), fm.height()),
             Qt::AlignCenter, yTitle);
  p.restore();

  // Legend: one swatch per colour present, in rows within the plot's width.
  int rows = 1;
  const std::vector<QPointF> at = legendLayout(&rows);
  const std::vector<std::pair<QColor, QString>>& entries = _legend;
  const double top = plot.bottom() + 2 * fm.height() + 6;
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const double x = at[k].x(), y = top + at[k].y() * (fm.height() + 2.0);
    p.fillRect(QRectF(x, y + 2, 10, 10), entries[k].first);
    p.setPen(text);
    p.drawText(QPointF(x + 13, y + fm.ascent()), entries[k].second);
    fits(entries[k].second, width() - x - 13);
    if (y + fm.height() > height() + 0.5) _cut << entries[k].second;
  }

  // The dialled point: a ring with a white halo, clamped into the plot.
  if (_dialled) {
    const QPointF c = valuePoint(_dialled->x(), _dialled->y());
    p.setRenderHint(QPainter::Antialiasing, true);
    p.setBrush(Qt::NoBrush);
    p.setPen(QPen(Qt::white, 4.0));
    p.drawEllipse(c, 7.0, 7.0);
    p.setPen(QPen(Qt::black, 2.0));
    p.drawEllipse(c, 7.0, 7.0);
  }
}

}  // namespace pb::ui
