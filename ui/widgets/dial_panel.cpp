// SPDX-License-Identifier: MIT
#include "ui/widgets/dial_panel.hpp"

#include <QDoubleSpinBox>
#include <QGridLayout>
#include <QLabel>
#include <QPainter>
#include <QPushButton>
#include <QSignalBlocker>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/base/text.hpp"

namespace pb::ui {

namespace {

// QDial (not wrapping) maps its range onto 300 degrees: the minimum at 240 degrees (counter-
// clockwise from 3 o'clock), the maximum at -60 degrees, clockwise (QStyle's calcRadialPos).
constexpr double kStartDeg = 240.0;
constexpr double kSweepDeg = 300.0;
constexpr double kArcWidth = 7.0;

double angleDeg(double fraction) {
  return kStartDeg - kSweepDeg * std::clamp(fraction, 0.0, 1.0);
}

QRectF arcRect(const QWidget* w) {
  const double side = std::min(w->width(), w->height()) - kArcWidth;
  return {(w->width() - side) / 2.0, (w->height() - side) / 2.0, side, side};
}

QString fmt(double v, int decimals) {
  return QString::number(v, 'f', decimals);
}

}  // namespace

EnvelopeDial::EnvelopeDial(double min_value, double max_value, int steps_per_unit, QWidget* parent)
    : QDial(parent), _min(min_value), _max(max_value), _steps(steps_per_unit) {
  setRange(static_cast<int>(std::lround(min_value * steps_per_unit)),
           static_cast<int>(std::lround(max_value * steps_per_unit)));
  setNotchesVisible(true);
  setNotchTarget(10.0);
  setWrapping(false);
  setMinimumSize(120, 120);
}

double EnvelopeDial::physicalValue() const {
  return static_cast<double>(value()) / _steps;
}

void EnvelopeDial::setPhysicalValue(double v) {
  setValue(static_cast<int>(std::lround(std::clamp(v, _min, _max) * _steps)));
}

double EnvelopeDial::fraction(double v) const {
  return _max > _min ? (v - _min) / (_max - _min) : 0.0;
}

void EnvelopeDial::setLimit(std::optional<double> limit) {
  _limit = limit;
  update();
}

QColor EnvelopeDial::zoneColor(DialZone zone) {
  switch (zone) {
    case DialZone::safe:
      return {46, 160, 67};
    case DialZone::marginal:
      return {240, 170, 0};
    case DialZone::failing:
      return {210, 40, 40};
  }
  return Qt::gray;
}

QPointF EnvelopeDial::arcPoint(double v) const {
  const QRectF r = arcRect(this);
  const double a = angleDeg(fraction(v)) * std::numbers::pi / 180.0;
  return {r.center().x() + r.width() / 2.0 * std::cos(a),
          r.center().y() - r.height() / 2.0 * std::sin(a)};
}

void EnvelopeDial::paintEvent(QPaintEvent* event) {
  QDial::paintEvent(event);
  if (!_limit) return;
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  const QRectF r = arcRect(this);
  const double limit = *_limit;
  // Zone boundaries as fractions of the dial's range.
  const double marginal_from = std::clamp(fraction(kDialedInFraction * limit), 0.0, 1.0);
  const double failing_from = std::clamp(fraction(limit), 0.0, 1.0);
  auto arc = [&](double f0, double f1, DialZone zone) {
    if (f1 <= f0) return;
    p.setPen(QPen(zoneColor(zone), kArcWidth, Qt::SolidLine, Qt::FlatCap));
    const double a0 = angleDeg(f0);
    const double span = angleDeg(f1) - a0;  // negative: clockwise
    p.drawArc(r, static_cast<int>(std::lround(a0 * 16)), static_cast<int>(std::lround(span * 16)));
  };
  arc(0.0, marginal_from, DialZone::safe);
  arc(marginal_from, failing_from, DialZone::marginal);
  arc(failing_from, 1.0, DialZone::failing);
}

DialPanel::DialPanel(const pb::SearchConfig& range, QWidget* parent) : QWidget(parent) {
  // In 0.01 m/s and 0.01 m/s^2.
  _speedDial = new EnvelopeDial(range.speed_min_mps, range.speed_max_mps, 100, this);
  _accelDial = new EnvelopeDial(range.accel_min_mps2, range.accel_max_mps2, 100, this);
  _speedDial->setAccessibleName(tr("Belt speed dial"));
  _accelDial->setAccessibleName(tr("Start-up acceleration dial"));
  _speedDial->setToolTip(
      tr("The belt speed to dispatch at (the coloured arc shows the analysed "
         "envelope once the replay ends)"));
  _accelDial->setToolTip(
      tr("The start-up acceleration to dispatch with (the coloured arc shows "
         "the analysed envelope once the replay ends)"));

  auto spin = [this](const EnvelopeDial* dial, const QString& suffix, const QString& name) {
    auto* s = new QDoubleSpinBox(this);
    s->setRange(dial->minPhysical(), dial->maxPhysical());
    s->setDecimals(2);
    s->setSingleStep(0.05);
    s->setSuffix(suffix);
    s->setAccessibleName(name);
    s->setKeyboardTracking(false);
    return s;
  };
  _speedSpin = spin(_speedDial, QStringLiteral(" m/s"), tr("Belt speed"));
  _accelSpin = spin(_accelDial, QStringLiteral(" m/s²"), tr("Start-up acceleration"));
  // The range is the analysed one: the limits say nothing outside it.
  _speedSpin->setToolTip(tr("The belt speed to dispatch at, typed exactly (%1 to %2 m/s, the "
                            "analysed range)")
                             .arg(fmt(range.speed_min_mps, 1), fmt(range.speed_max_mps, 1)));
  _accelSpin->setToolTip(tr("The start-up acceleration to dispatch with, typed exactly (%1 to "
                            "%2 m/s², the analysed range)")
                             .arg(fmt(range.accel_min_mps2, 1), fmt(range.accel_max_mps2, 1)));

  _dispatch = new QPushButton(tr("Dispatch"), this);
  _dispatch->setToolTip(
      tr("Run this start-up once; the solver's envelope is revealed after the "
         "replay ends"));
  _status = new QLabel(this);
  _status->setWordWrap(true);
  _limits = new QLabel(this);
  _limits->setWordWrap(true);

  auto* grid = new QGridLayout;
  grid->addWidget(new QLabel(tr("Speed"), this), 0, 0, Qt::AlignHCenter);
  grid->addWidget(new QLabel(tr("Start-up acceleration"), this), 0, 1, Qt::AlignHCenter);
  grid->addWidget(_speedDial, 1, 0);
  grid->addWidget(_accelDial, 1, 1);
  grid->addWidget(_speedSpin, 2, 0);
  grid->addWidget(_accelSpin, 2, 1);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(grid);
  layout->addWidget(_dispatch);
  layout->addWidget(_status);
  layout->addWidget(_limits);
  layout->addStretch(1);

  // Dial and spin box stay in sync; the dial's resolution is the spin box's (0.01).
  connect(_speedDial, &QDial::valueChanged, this,
          [this] { setSpeed(_speedDial->physicalValue()); });
  connect(_accelDial, &QDial::valueChanged, this,
          [this] { setAccel(_accelDial->physicalValue()); });
  connect(_speedSpin, &QDoubleSpinBox::valueChanged, this, &DialPanel::setSpeed);
  connect(_accelSpin, &QDoubleSpinBox::valueChanged, this, &DialPanel::setAccel);
  connect(_dispatch, &QPushButton::clicked, this, &DialPanel::dispatch);

  setSpeed(1.0);  // the fixed-table speed a warehouse runs today
  setAccel(1.0);
  refresh();
}

double DialPanel::speed() const {
  return _speedSpin->value();
}
double DialPanel::accel() const {
  return _accelSpin->value();
}

void DialPanel::setSpeed(double v) {
  v = std::clamp(v, _speedSpin->minimum(), _speedSpin->maximum());
  const bool changed = std::abs(v - _speed) > 1e-9;
  _speed = v;
  {
    const QSignalBlocker b1(_speedSpin), b2(_speedDial);
    _speedSpin->setValue(v);
    _speedDial->setPhysicalValue(v);
  }
  if (changed) emit dialsChanged(speed(), accel());
}

void DialPanel::setAccel(double v) {
  v = std::clamp(v, _accelSpin->minimum(), _accelSpin->maximum());
  const bool changed = std::abs(v - _accel) > 1e-9;
  _accel = v;
  {
    const QSignalBlocker b1(_accelSpin), b2(_accelDial);
    _accelSpin->setValue(v);
    _accelDial->setPhysicalValue(v);
  }
  if (changed) emit dialsChanged(speed(), accel());
}

ConveyorProfile DialPanel::profile() const {
  ConveyorProfile p;
  p.shape = ProfileShape::accel_hold;
  p.target_speed_mps = speed();
  p.accel_mps2 = accel();
  p.duration_s = std::min(30.0, speed() / accel() + 2.0);
  return p;
}

void DialPanel::dispatch() {
  const ConveyorProfile p = profile();
  _game.dispatch(p);
  _announced = false;
  _refused.clear();
  refresh();
  emit dispatchRequested(p);
}

void DialPanel::setEnvelope(const SafetyResult& envelope) {
  _game.setEnvelope(envelope);
  refresh();
}

void DialPanel::setOutcome(bool survived, FailureMode mode, SlideKind how) {
  _game.setOutcome(survived, mode, how);
  refresh();
}

void DialPanel::replayFinished() {
  _game.replayFinished();
  refresh();
}

void DialPanel::resetRound() {
  _game = DialGame{};
  _announced = false;
  _refused.clear();
  refresh();
}

void DialPanel::refuseDispatch(const QString& why) {
  _game = DialGame{};
  _announced = false;
  _refused = why;
  refresh();
}

QString DialPanel::statusText() const {
  return _status->text();
}

QString DialPanel::limitsText() const {
  return _limits->text();
}

void DialPanel::refresh() {
  const auto envelope = _game.envelope();
  if (!envelope) {
    _speedDial->setLimit(std::nullopt);
    _accelDial->setLimit(std::nullopt);
    _limits->clear();
    _status->setText(_game.dispatched()
                         ? tr("Dispatched. The solver's envelope is revealed when the replay ends.")
                     : !_refused.isEmpty() ? _refused
                                           : tr("Dial a speed and a start-up, then Dispatch."));
    return;
  }
  _speedDial->setLimit(envelope->max_speed_mps);
  _accelDial->setLimit(envelope->max_accel_mps2);
  const QString limits =
      tr("Solver's limits: %1 m/s, %2 m/s² start-up")
          .arg(QString::fromStdString(pb::fixed_floor(envelope->max_speed_mps, 2)),
               QString::fromStdString(pb::fixed_floor(envelope->max_accel_mps2, 2)));
  _limits->setText(limits);
  const DialScore score = *_game.score();
  // The dispatch's score, not the pallet's grade (the results panel grades the pallet against the
  // fixed table): how close the dialled motion came to the limits without crashing.
  _status->setText(tr("%1 — your dispatch scores %2 (%3 points)")
                       .arg(QString::fromStdString(score.headline), QChar::fromLatin1(score.grade))
                       .arg(score.points));
  if (!_announced) {
    _announced = true;
    emit scoreRevealed(score);
  }
}

}  // namespace pb::ui
