// SPDX-License-Identifier: MIT
// The speed x acceleration failure map as a heatmap: one cell per (speed, acceleration) probe,
// coloured by verdict and failure mode, non-monotone cells marked with a black corner dot, the
// dialled point marked with a ring, axes labelled, a legend below.
//
// Wiring (MainWindow, through ResultsPanel): the failure map of the pallet -> setMap(map);
// DialPanel::dialsChanged -> setDialledPoint(speed, accel).
#pragma once

#include <QColor>
#include <QRectF>
#include <QStringList>
#include <QWidget>
#include <optional>
#include <utility>
#include <vector>

#include "core/analysis/failure_map.hpp"
#include "core/base/enums.hpp"
#include "core/physics/simulate.hpp"

namespace pb::ui {

class FailureMapView : public QWidget {
  Q_OBJECT

 public:
  /// What the view draws (a copy of the core's failure map, without timings).
  struct Cell {
    pb::Outcome outcome = pb::Outcome::safe;
    pb::FailureMode mode = pb::FailureMode::no_failure;
    bool non_monotone = false;
  };
  struct Grid {
    std::vector<double> speeds_mps;   ///< x, increasing
    std::vector<double> accels_mps2;  ///< y, increasing
    std::vector<Cell> cells;          ///< cells[accel_index * speeds.size() + speed_index]
  };

  explicit FailureMapView(QWidget* parent = nullptr);

  /// The colour of a cell: safe green; failures by mode; unstable grey.
  static QColor cellColor(const Cell& cell);

  const Grid& grid() const { return _grid; }
  bool hasGrid() const { return !_grid.cells.empty(); }
  std::optional<QPointF> dialledPoint() const { return _dialled; }
  /// The widget rectangle of a cell in the current geometry (empty if out of range / no grid).
  QRectF cellRect(int speed_index, int accel_index) const;
  /// The widget point of a (speed, accel) value (the dialled marker's centre).
  QPointF valuePoint(double speed_mps, double accel_mps2) const;

  /// Text the last paint could not fit in its box (an axis label, a tick, a legend entry wider
  /// than the room it had): empty when everything was drawn whole. For the screenshot tests.
  QStringList cutTexts() const { return _cut; }

  QSize minimumSizeHint() const override { return {260, 200}; }
  QSize sizeHint() const override { return {420, 320}; }

 public slots:
  /// Shows a grid; an inconsistent one (cells != speeds x accels) shows a message instead.
  void setGrid(const pb::ui::FailureMapView::Grid& grid);
  /// Shows the core's failure map (its cells' verdicts, modes and non-monotone flags).
  void setMap(const pb::FailureMap& map);
  void clear();
  void setDialledPoint(double speed_mps, double accel_mps2);

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  QRectF plotRect() const;
  /// The legend's entries for _grid: one swatch per colour present (kept in _legend).
  std::vector<std::pair<QColor, QString>> legend() const;
  /// The legend laid out in rows within the plot's width: each entry's row and x offset.
  std::vector<QPointF> legendLayout(int* rows) const;

  Grid _grid;
  std::optional<QPointF> _dialled;  ///< (speed, accel)
  QString _message;
  QStringList _cut;                                 ///< set by paintEvent
  std::vector<std::pair<QColor, QString>> _legend;  ///< legend() of the grid shown
};

}  // namespace pb::ui
