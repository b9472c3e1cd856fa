// SPDX-License-Identifier: MIT
#include "ui/widgets/trace_plots.hpp"

#include <QChart>
#include <QChartView>
#include <QGridLayout>
#include <QLabel>
#include <QLineSeries>
#include <QMouseEvent>
#include <QValueAxis>
#include <algorithm>
#include <cmath>
#include <tuple>

namespace pb::ui {

namespace {

struct QuantityInfo {
  const char* title;
  const char* unit;
  const char* readout;  ///< its name in the readout
};
constexpr QuantityInfo kInfo[TracePlots::kQuantities] = {
    {"Pallet tilt", "deg", "tilt"},
    {"Item displacement on the pallet", "cm", "item moved"},
    {"Load shift (item-to-item)", "cm", "load shift"},
    {"Pallet slip on the belt", "cm", "slip"},
};

// A plot's y axis reaches this many times its threshold at most: a wreck (a carton that fell off
// travels metres) would otherwise squash the approach to the threshold, which is what a failure's
// replay is read for, into the bottom pixel. The readout gives the values beyond it.
constexpr double kOffScale = 4.0;

// The smallest round interval (1, 2 or 5 x 10^k) at least `raw`.
double round_step(double raw) {
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * decade >= raw) return m * decade;
  }
  return 10.0 * decade;
}

// A label format with as many decimals as `step` needs.
QString label_format(double step) {
  if (step >= 1.0) return QStringLiteral("%.0f");
  return step >= 0.1 ? QStringLiteral("%.1f") : QStringLiteral("%.2f");
}

}  // namespace

std::array<TracePlots::Curve, TracePlots::kQuantities> TracePlots::measure(
    const Replay& replay, const DetectorThresholds& th) {
  std::array<Curve, kQuantities> out;
  out[Tilt].threshold = th.tip_deg;
  out[ItemSlide].threshold = th.item_slide_m * 100.0;
  out[LoadShift].threshold = th.load_shift_m * 100.0;
  out[Slip].threshold = th.pallet_slip_m * 100.0;
  if (replay.frames.empty()) return out;
  const ReplayFrame& rest = replay.frames.front();
  for (const ReplayFrame& f : replay.frames) {
    const double v[kQuantities] = {
        measure_tilt(f.pallet).value,
        100.0 * measure_item_slide(rest.pallet, rest.items, f.pallet, f.items).value,
        100.0 * measure_load_shift(rest.items, f.items).value,
        100.0 * measure_pallet_slip(rest.pallet, f.pallet, f.belt_x, f.belt_y).value,
    };
    for (int q = 0; q < kQuantities; ++q) {
      out[q].t.push_back(f.t);
      out[q].value.push_back(v[q]);
    }
  }
  return out;
}

TracePlots::TracePlots(QWidget* parent) : QWidget(parent) {
  auto* layout = new QGridLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(2);
  for (int q = 0; q < kQuantities; ++q) {
    auto* chart = new QChart;
    chart->setTitle(tr(kInfo[q].title));
    chart->legend()->hide();
    chart->setMargins(QMargins(2, 2, 2, 2));
    auto* x = new QValueAxis;
    x->setTitleText(tr("time (s)"));
    x->setLabelFormat(QStringLiteral("%.1f"));
    auto* y = new QValueAxis;
    y->setTitleText(tr(kInfo[q].unit));
    y->setLabelFormat(QStringLiteral("%.1f"));
    chart->addAxis(x, Qt::AlignBottom);
    chart->addAxis(y, Qt::AlignLeft);
    _series[q] = new QLineSeries;
    _series[q]->setPen(QPen(QColor(31, 119, 180), 2.0));
    _thresholds[q] = new QLineSeries;
    _thresholds[q]->setPen(QPen(QColor(210, 40, 40), 1.5, Qt::DashLine));
    _cursors[q] = new QLineSeries;
    _cursors[q]->setPen(QPen(QColor(40, 40, 40), 1.5));
    for (QLineSeries* s : {_series[q], _thresholds[q], _cursors[q]}) {
      chart->addSeries(s);
      s->attachAxis(x);
      s->attachAxis(y);
    }
    _charts[q] = chart;
    auto* view = new QChartView(chart, this);
    view->setRenderHint(QPainter::Antialiasing);
    view->setMinimumSize(220, 150);
    view->setToolTip(tr("Click or drag to move the replay to that time"));
    view->viewport()->installEventFilter(this);
    _views[q] = view;
    layout->addWidget(view, q / 2, q % 2);
  }
  _readout = new QLabel(this);
  _readout->setWordWrap(true);
  _readout->setTextInteractionFlags(Qt::TextSelectableByMouse);
  _readout->setToolTip(tr("Every quantity at the replay's cursor, with its detector's threshold"));
  layout->addWidget(_readout, 2, 0, 1, 2);
  clear();
}

bool TracePlots::eventFilter(QObject* watched, QEvent* event) {
  // A plot's viewport resized (after the layout, so its size is the new one): the labels refit.
  if (event->type() == QEvent::Resize) fitTicks();
  const bool press = event->type() == QEvent::MouseButtonPress;
  const bool drag = event->type() == QEvent::MouseMove;
  if (press || drag) {
    const auto* mouse = static_cast<QMouseEvent*>(event);
    if (mouse->buttons() & Qt::LeftButton) {
      for (int q = 0; q < kQuantities; ++q) {
        if (_views[q] == nullptr || watched != _views[q]->viewport() || _series[q]->count() == 0) {
          continue;
        }
        const QPointF scene = _views[q]->mapToScene(mouse->position().toPoint());
        const QPointF value = _charts[q]->mapToValue(_charts[q]->mapFromScene(scene), _series[q]);
        emit timeRequested(std::clamp(value.x(), _tStart, _tEnd));
        return true;
      }
    }
  }
  return QWidget::eventFilter(watched, event);
}

double TracePlots::valueAt(const Curve& c, double t_s) {
  if (c.t.empty()) return 0.0;
  const auto after = std::upper_bound(c.t.begin(), c.t.end(), t_s);
  if (after == c.t.begin()) return c.value.front();
  if (after == c.t.end()) return c.value.back();
  const std::size_t k = static_cast<std::size_t>(after - c.t.begin());
  const double t0 = c.t[k - 1], t1 = c.t[k];
  const double w = t1 > t0 ? (t_s - t0) / (t1 - t0) : 1.0;
  return c.value[k - 1] + w * (c.value[k] - c.value[k - 1]);
}

QString TracePlots::readout() const {
  return _readout->text();
}

void TracePlots::clear() {
  for (int q = 0; q < kQuantities; ++q) {
    _series[q]->clear();
    _thresholds[q]->clear();
    _cursors[q]->clear();
    _curves[q] = Curve{};
    _yNeed[q] = 1.0;
    _peak[q] = 0.0;
  }
  _tStart = 0.0;
  _tEnd = 1.0;
  _cursorT = 0.0;
  fitTicks();
  _readout->setText(tr("No replay: dispatch the pallet or open a replay to see its traces."));
}

void TracePlots::setReplay(const Replay& replay, const DetectorThresholds& thresholds) {
  clear();
  const auto curves = measure(replay, thresholds);
  _curves = curves;
  if (!replay.frames.empty()) {
    _tStart = replay.frames.front().t;
    _tEnd = std::max(_tStart + 1e-3, replay.frames.back().t);
  }
  for (int q = 0; q < kQuantities; ++q) {
    const Curve& c = curves[q];
    QList<QPointF> points;
    points.reserve(static_cast<qsizetype>(c.t.size()));
    double peak = 0.0;
    for (std::size_t i = 0; i < c.t.size(); ++i) {
      points.append(QPointF(c.t[i], c.value[i]));
      peak = std::max(peak, c.value[i]);
    }
    _series[q]->replace(points);
    _thresholds[q]->append(_tStart, c.threshold);
    _thresholds[q]->append(_tEnd, c.threshold);
    _yNeed[q] = std::max(1.25 * c.threshold, 1.05 * std::min(peak, kOffScale * c.threshold));
    _peak[q] = peak;
  }
  fitTicks();  // the axes' ranges and ticks
  setCursorTime(_tStart);
}

void TracePlots::fitTicks() {
  // As many labels as the plot holds without one overlapping the next (Qt Charts elides
  // overlapping labels to "..."), at a round interval (1, 2 or 5 x 10^k) from zero: y labels a
  // line apart, time labels about six characters apart. The plot's size is reckoned from its
  // view's, which the layout has set by now, less the title, the axes' labels and titles (the
  // chart's own plotArea() is laid out later, and lags a resize).
  const QFontMetrics font = fontMetrics();
  const double label_height = 1.8 * font.height();
  const double label_width = 6.0 * font.averageCharWidth();
  for (int q = 0; q < kQuantities; ++q) {
    if (_views[q] == nullptr) continue;  // still being built
    const QSize view = _views[q]->viewport()->size();
    const double height = view.height() - 4.5 * font.height();
    const double width = view.width() - 6.0 * font.averageCharWidth() - 2.0 * font.height();
    const int rows = std::max(2, static_cast<int>(height / label_height) + 1);
    const int columns = std::max(2, static_cast<int>(width / label_width) + 1);
    const double y_step = round_step(_yNeed[q] / (rows - 1));
    const double t_step = round_step((_tEnd - _tStart) / (columns - 1));
    _yMax[q] = y_step * std::ceil(_yNeed[q] / y_step - 1e-9);  // the top tick
    // The interval first, then the range: Qt Charts lays out an axis's labels again when its range
    // changes, but a new interval alone was drawn with the labels of the old one until the next
    // layout (the elided labels of the console's screenshot).
    for (auto [orientation, step, lo, hi] : {std::tuple{Qt::Vertical, y_step, 0.0, _yMax[q]},
                                             std::tuple{Qt::Horizontal, t_step, _tStart, _tEnd}}) {
      for (QAbstractAxis* axis : _charts[q]->axes(orientation)) {
        auto* a = static_cast<QValueAxis*>(axis);
        a->setTickType(QValueAxis::TicksDynamic);
        a->setTickAnchor(0.0);
        a->setTickInterval(step);
        a->setLabelFormat(label_format(step));
        a->setRange(lo, hi);
      }
    }
    if (!_curves[q].t.empty()) {
      _cursors[q]->replace(QList<QPointF>{{_cursorT, 0.0}, {_cursorT, _yMax[q]}});
    }
  }
}

void TracePlots::setCursorTime(double t_s) {
  _cursorT = std::clamp(t_s, _tStart, _tEnd);
  for (int q = 0; q < kQuantities; ++q) {
    _cursors[q]->replace(QList<QPointF>{{_cursorT, 0.0}, {_cursorT, _yMax[q]}});
  }
  if (_curves[Tilt].t.empty()) return;
  QStringList parts;
  for (int q = 0; q < kQuantities; ++q) {
    parts << tr("%1 %2 %3 (limit %4)")
                 .arg(tr(kInfo[q].readout))
                 .arg(valueAt(_curves[q], _cursorT), 0, 'f', q == Tilt ? 2 : 1)
                 .arg(tr(kInfo[q].unit))
                 .arg(_curves[q].threshold, 0, 'g', 3);
  }
  QStringList off;
  for (int q = 0; q < kQuantities; ++q) {
    if (_peak[q] > _yMax[q]) {
      off << tr("%1 up to %2 %3")
                 .arg(tr(kInfo[q].readout))
                 .arg(_peak[q], 0, 'f', 0)
                 .arg(tr(kInfo[q].unit));
    }
  }
  _readout->setText(
      tr("At %1 s: %2.").arg(_cursorT, 0, 'f', 3).arg(parts.join(QStringLiteral("; "))) +
      (off.isEmpty() ? QString() : tr(" Off scale: %1.").arg(off.join(QStringLiteral(", ")))));
}

QByteArray TracePlots::csv(const pb::Replay& replay, const pb::DetectorThresholds& thresholds) {
  const auto curves = measure(replay, thresholds);
  QByteArray out =
      "t_s,pallet_tilt_deg,item_displacement_cm,load_shift_cm,pallet_slip_cm,"
      "pallet_tilt_deg_limit,item_displacement_cm_limit,load_shift_cm_limit,pallet_slip_cm_limit\n";
  const auto number = [](double v) { return QByteArray::number(v, 'g', 10); };
  for (std::size_t k = 0; k < curves[0].t.size(); ++k) {
    out += number(curves[0].t[k]);
    for (const Curve& c : curves) out += ',' + number(k < c.value.size() ? c.value[k] : 0.0);
    for (const Curve& c : curves) out += ',' + number(c.threshold);
    out += '\n';
  }
  return out;
}

}  // namespace pb::ui
