// SPDX-License-Identifier: MIT
// Trace plots (Qt Charts) of one replay, linked to the replay cursor: pallet tilt, the largest item
// displacement on the pallet, the load shift (largest change of an item-to-item distance) and the
// pallet's slip on the belt, against time, each with its detector threshold as a dashed red line
// and a vertical cursor line at the replay time, and under them a readout of every quantity at the
// cursor. A plot reaches four times its threshold at most (a wreck leaves its top; the readout says
// how far it went). Measured with core/physics/detectors.hpp on the replay's frames, the first
// frame being the rest state (as the detectors' baselines). A click or a drag on a plot asks for
// its time.
//
// Wiring (MainWindow):
//   AnalysisService::solved(solve) / a replay file opened -> setReplay(replay)
//   ReplayControls / timeline time changed               -> setCursorTime(t)
//   timeRequested(t)                                     -> ReplayPlayer::setTime(t)
#pragma once

#include <QByteArray>
#include <QWidget>
#include <array>
#include <vector>

#include "core/analysis/replay.hpp"
#include "core/physics/detectors.hpp"

class QChart;
class QChartView;
class QLabel;
class QLineSeries;

namespace pb::ui {

class TracePlots : public QWidget {
  Q_OBJECT

 public:
  enum Quantity { Tilt = 0, ItemSlide = 1, LoadShift = 2, Slip = 3 };
  static constexpr int kQuantities = 4;

  explicit TracePlots(QWidget* parent = nullptr);

  /// Per-frame values of a quantity, in display units (deg or cm).
  struct Curve {
    std::vector<double> t;
    std::vector<double> value;
    double threshold = 0.0;  ///< same units
  };
  /// The curves of a replay (no widgets; testable alone).
  static std::array<Curve, kQuantities> measure(const pb::Replay& replay,
                                                const pb::DetectorThresholds& thresholds);
  /// The curves as CSV, one row per frame: t_s, the four quantities (pallet_tilt_deg,
  /// item_displacement_cm, load_shift_cm, pallet_slip_cm), then each one's threshold (`_limit`).
  static QByteArray csv(const pb::Replay& replay,
                        const pb::DetectorThresholds& thresholds = pb::DetectorThresholds{});
  /// A curve's value at `t_s`, linear between frames (the first or last value outside them).
  static double valueAt(const Curve& curve, double t_s);

  QChart* chart(Quantity q) const { return _charts[q]; }
  QLineSeries* series(Quantity q) const { return _series[q]; }
  QLineSeries* thresholdLine(Quantity q) const { return _thresholds[q]; }
  QLineSeries* cursorLine(Quantity q) const { return _cursors[q]; }
  QChartView* view(Quantity q) const { return _views[q]; }
  double cursorTime() const { return _cursorT; }
  /// The readout under the plots: every quantity at the cursor, with its threshold.
  QString readout() const;

 signals:
  /// A click or a drag on a plot, at this time (within the replay's range).
  void timeRequested(double t_s);

 public slots:
  void setReplay(const pb::Replay& replay,
                 const pb::DetectorThresholds& thresholds = pb::DetectorThresholds{});
  /// Moves the cursor line of every plot to `t_s` (clamped to the replay's time range).
  void setCursorTime(double t_s);
  void clear();

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  /// The axes' tick intervals for the plots' current size (no overlapping, elided labels).
  void fitTicks();

  std::array<QChart*, kQuantities> _charts{};
  std::array<QLineSeries*, kQuantities> _series{};
  std::array<QLineSeries*, kQuantities> _thresholds{};
  std::array<QLineSeries*, kQuantities> _cursors{};
  std::array<QChartView*, kQuantities> _views{};
  std::array<Curve, kQuantities> _curves{};
  QLabel* _readout = nullptr;
  std::array<double, kQuantities> _yNeed{};  ///< the height a curve and its threshold need
  std::array<double, kQuantities> _yMax{};   ///< the y axis's top: _yNeed up to a round tick
  std::array<double, kQuantities> _peak{};   ///< a curve's largest value (above _yMax: off scale)
  double _tStart = 0.0, _tEnd = 1.0;
  double _cursorT = 0.0;
};

}  // namespace pb::ui
