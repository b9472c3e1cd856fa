// SPDX-License-Identifier: MIT
// The replay's timeline: a bar from the first to the last frame, the failure marked in red, the
// slow-motion band shaded, the cursor; click or drag to seek.
#pragma once

#include <QWidget>
#include <optional>

namespace pb::ui {

class Timeline : public QWidget {
  Q_OBJECT

 public:
  explicit Timeline(QWidget* parent = nullptr);

  void setRange(double start, double end);
  /// The failure's time, if the replay failed (drawn as a red marker).
  void setFailureTime(std::optional<double> t);
  /// The span played in slow motion (shaded), if any.
  void setSlowBand(std::optional<std::pair<double, double>> band);
  double start() const { return _start; }
  double end() const { return _end; }
  double time() const { return _time; }
  std::optional<double> failureTime() const { return _failure; }

  /// The x of time `t` on the bar (logical pixels), and the time at x (clamped to the range).
  double xForTime(double t) const;
  double timeForX(double x) const;

  static QColor failureColor() { return QColor(220, 30, 30); }
  static QColor cursorColor() { return QColor(20, 90, 200); }

  QSize sizeHint() const override { return {400, 34}; }
  QSize minimumSizeHint() const override { return {120, 28}; }

 public slots:
  void setTime(double t);

 signals:
  /// The user clicked or dragged to `t`.
  void seekRequested(double t);

 protected:
  void paintEvent(QPaintEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;

 private:
  static constexpr int kMargin = 8;
  double _start = 0.0, _end = 0.0, _time = 0.0;
  std::optional<double> _failure;
  std::optional<std::pair<double, double>> _slow;
};

}  // namespace pb::ui
