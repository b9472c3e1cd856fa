// SPDX-License-Identifier: MIT
#include "ui/widgets/timeline.hpp"

#include <QMouseEvent>
#include <QPainter>
#include <algorithm>

namespace pb::ui {

Timeline::Timeline(QWidget* parent) : QWidget(parent) {
  setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Fixed);
  setMinimumHeight(28);
  setCursor(Qt::PointingHandCursor);
  setToolTip(tr("Click or drag to move the replay; the red mark is the failure"));
}

void Timeline::setRange(double start, double end) {
  _start = start;
  _end = std::max(start, end);
  _time = std::clamp(_time, _start, _end);
  update();
}

void Timeline::setFailureTime(std::optional<double> t) {
  _failure = t;
  update();
}

void Timeline::setSlowBand(std::optional<std::pair<double, double>> band) {
  _slow = band;
  update();
}

void Timeline::setTime(double t) {
  _time = std::clamp(t, _start, _end);
  update();
}

double Timeline::xForTime(double t) const {
  const double w = std::max(1, width() - 2 * kMargin);
  if (_end <= _start) return kMargin;
  return kMargin + (std::clamp(t, _start, _end) - _start) / (_end - _start) * w;
}

double Timeline::timeForX(double x) const {
  const double w = std::max(1, width() - 2 * kMargin);
  return std::clamp(_start + (x - kMargin) / w * (_end - _start), _start, _end);
}

void Timeline::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  const double barTop = height() / 2.0 - 4.0, barH = 8.0;
  const QRectF bar(kMargin, barTop, width() - 2 * kMargin, barH);
  p.setPen(Qt::NoPen);
  p.setBrush(palette().mid());
  p.drawRoundedRect(bar, 3, 3);
  if (_slow && _end > _start) {
    const double x0 = xForTime(_slow->first), x1 = xForTime(_slow->second);
    p.setBrush(QColor(250, 190, 80));
    p.drawRect(QRectF(x0, barTop, std::max(1.0, x1 - x0), barH));
  }
  // Played part.
  p.setBrush(cursorColor().lighter(150));
  p.drawRect(QRectF(kMargin, barTop + 2, xForTime(_time) - kMargin, barH - 4));
  if (_failure) {
    const double x = xForTime(*_failure);
    p.setPen(QPen(failureColor(), 3));
    p.drawLine(QPointF(x, 2), QPointF(x, height() - 2));
  }
  const double x = xForTime(_time);
  p.setPen(QPen(Qt::white, 1));
  p.setBrush(cursorColor());
  p.drawEllipse(QPointF(x, height() / 2.0), 6, 6);
}

void Timeline::mousePressEvent(QMouseEvent* event) {
  if (event->button() == Qt::LeftButton) emit seekRequested(timeForX(event->position().x()));
}

void Timeline::mouseMoveEvent(QMouseEvent* event) {
  if (event->buttons() & Qt::LeftButton) emit seekRequested(timeForX(event->position().x()));
}

}  // namespace pb::ui
