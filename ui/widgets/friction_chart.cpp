// SPDX-License-Identifier: MIT
#include "ui/widgets/friction_chart.hpp"

#include <QAreaSeries>
#include <QChart>
#include <QChartView>
#include <QLabel>
#include <QLegendMarker>
#include <QLineSeries>
#include <QScatterSeries>
#include <QTextDocument>
#include <QVBoxLayout>
#include <QValueAxis>
#include <algorithm>
#include <array>

#include "core/analysis/explain.hpp"

namespace pb::ui {

namespace {

constexpr double kMuAxisMax = 1.0;

/// One colour per contact: belt/pallet, item/pallet, item/item.
const std::array<QColor, 3> kPairColors{QColor(31, 119, 180), QColor(214, 39, 40),
                                        QColor(44, 160, 44)};

// A pair in words: "carton/wood_pallet" is "carton on wood pallet".
QString label(const std::string& key) {
  QString words = QString::fromStdString(key);
  words.replace(QLatin1Char('_'), QLatin1Char(' '));
  words.replace(QLatin1Char('/'), QStringLiteral(" on "));
  return words;
}

}  // namespace

FrictionChart::FrictionChart(QWidget* parent, const FrictionModel& model)
    : QWidget(parent), _model(&model), _chart(new QChart) {
  // Title and legend are labels that wrap (the chart's own elided them at a dock's width).
  _caption = new QLabel(
      tr("Static friction μ against temperature (dashed: with the frost-melt penalty; dots: the "
         "pallet now)"),
      this);
  _caption->setWordWrap(true);
  _legend = new QLabel(this);
  _legend->setWordWrap(true);
  _legend->setTextFormat(Qt::RichText);
  _chart->legend()->hide();
  _chart->setMargins(QMargins(4, 4, 4, 4));
  _axisX = new QValueAxis;
  _axisX->setRange(kMinTempC, kMaxTempC);
  _axisX->setTitleText(tr("temperature (°C)"));
  _axisX->setTickCount(9);
  _axisX->setLabelFormat(QStringLiteral("%.0f"));
  _axisY = new QValueAxis;
  _axisY->setRange(0.0, kMuAxisMax);
  _axisY->setTitleText(tr("μ static"));
  _axisY->setLabelFormat(QStringLiteral("%.1f"));
  _axisY->setTickCount(6);
  _chart->addAxis(_axisX, Qt::AlignBottom);
  _chart->addAxis(_axisY, Qt::AlignLeft);

  // The frost-melt band: shaded over the whole μ range between the zone's edges.
  const FrostMeltPenalty& pen = _model->penalty();
  auto* lower = new QLineSeries(this);
  auto* upper = new QLineSeries(this);
  lower->append(pen.zone_lo_c, 0.0);
  lower->append(pen.zone_hi_c, 0.0);
  upper->append(pen.zone_lo_c, kMuAxisMax);
  upper->append(pen.zone_hi_c, kMuAxisMax);
  _band = new QAreaSeries(upper, lower);
  _band->setName(tr("frost-melt band"));
  _band->setColor(QColor(120, 180, 255, 70));
  _band->setBorderColor(QColor(120, 180, 255, 140));
  _chart->addSeries(_band);
  _band->attachAxis(_axisX);
  _band->attachAxis(_axisY);

  _tempLine = new QLineSeries;
  _tempLine->setName(tr("pallet temperature"));
  _tempLine->setPen(QPen(QColor(60, 60, 60), 1.5, Qt::DotLine));
  _chart->addSeries(_tempLine);
  _tempLine->attachAxis(_axisX);
  _tempLine->attachAxis(_axisY);
  for (QLegendMarker* m : _chart->legend()->markers(_tempLine)) m->setVisible(false);

  _view = new QChartView(_chart, this);
  _view->setRenderHint(QPainter::Antialiasing);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(2);
  layout->addWidget(_caption);
  layout->addWidget(_view, 1);
  layout->addWidget(_legend);
  setMinimumSize(360, 260);
}

void FrictionChart::setPallet(const PalletConfig& config) {
  const auto friction = _model->for_pallet(config);
  if (!friction) {
    // Unknown pair (e.g. a plastic pallet on steel rollers): say so instead of drawing curves.
    _error = QString::fromStdString(friction.diagnostics.empty()
                                        ? std::string("no friction data for this pallet")
                                        : friction.diagnostics.front().message);
    for (auto& p : _pairs) {
      _chart->removeSeries(p.steady);
      _chart->removeSeries(p.effective);
      _chart->removeSeries(p.marker);
      delete p.steady;
      delete p.effective;
      delete p.marker;
    }
    _pairs.clear();
    _keys.clear();
    _tempLine->clear();
    _caption->setText(tr("No friction curves: %1").arg(_error));
    _legend->clear();
    return;
  }
  _error.clear();
  const ContactFriction& cf = *friction.value;
  const std::vector<std::string> keys{cf.belt_pallet_key, cf.item_pallet_key, cf.item_item_key};
  if (keys != _keys || config.seconds_since_temp_change != _seconds) {
    rebuild(cf, config.seconds_since_temp_change);
  }
  moveMarkers(config.body_temp_c, config.seconds_since_temp_change);
  _caption->setText(tr("Static friction μ against temperature · dashed: with the frost-melt "
                       "penalty, %1 s after the change · dots: now, %2")
                        .arg(config.seconds_since_temp_change, 0, 'f', 0)
                        .arg(QString::fromStdString(format_temperature(config.body_temp_c))));
  QStringList entries;
  for (std::size_t i = 0; i < _pairs.size(); ++i) {
    entries << QStringLiteral("<span style=\"color:%1\">&#9632;</span>&nbsp;%2")
                   .arg(_pairs[i].steady->pen().color().name(),
                        label(_pairs[i].key).toHtmlEscaped());
  }
  entries << tr("<span style=\"color:#78b4ff\">&#9632;</span>&nbsp;frost-melt band");
  _legend->setText(entries.join(QStringLiteral(" &nbsp; ")));
}

QString FrictionChart::caption() const {
  return _caption->text();
}

QString FrictionChart::legendText() const {
  QTextDocument doc;
  doc.setHtml(_legend->text());
  return doc.toPlainText();
}

void FrictionChart::rebuild(const ContactFriction& cf, double seconds) {
  for (auto& p : _pairs) {
    _chart->removeSeries(p.steady);
    _chart->removeSeries(p.effective);
    _chart->removeSeries(p.marker);
    delete p.steady;
    delete p.effective;
    delete p.marker;
  }
  _pairs.clear();
  _keys = {cf.belt_pallet_key, cf.item_pallet_key, cf.item_item_key};
  _seconds = seconds;
  for (std::size_t i = 0; i < _keys.size(); ++i) {
    const std::string& key = _keys[i];
    // The same pair can serve two contacts (never today, but cheap to guard): draw it once.
    if (std::find(_keys.begin(), _keys.begin() + static_cast<long>(i), key) !=
        _keys.begin() + static_cast<long>(i)) {
      continue;
    }
    PairSeries ps;
    ps.key = key;
    ps.steady = new QLineSeries;
    ps.effective = new QLineSeries;
    ps.marker = new QScatterSeries;
    ps.steady->setName(label(key));
    ps.effective->setName(tr("%1, frost-melt penalty").arg(label(key)));
    ps.marker->setName(tr("%1 now").arg(label(key)));
    const QColor c = kPairColors[i];
    ps.steady->setPen(QPen(c, 2.0));
    ps.effective->setPen(QPen(c, 2.0, Qt::DashLine));
    ps.marker->setColor(c);
    ps.marker->setBorderColor(Qt::black);
    ps.marker->setMarkerSize(11.0);
    for (const FrictionSample& s : _model->curve(key, kMinTempC, kMaxTempC, kStepC, seconds)) {
      ps.steady->append(s.temp_c, s.steady.mu_s);
      ps.effective->append(s.temp_c, s.effective.mu_s);
    }
    for (QAbstractSeries* series :
         {static_cast<QAbstractSeries*>(ps.steady), static_cast<QAbstractSeries*>(ps.effective),
          static_cast<QAbstractSeries*>(ps.marker)}) {
      _chart->addSeries(series);
      series->attachAxis(_axisX);
      series->attachAxis(_axisY);
    }
    // The legend names the pairs; the dashed curve and the marker share their pair's colour.
    for (QAbstractSeries* series :
         {static_cast<QAbstractSeries*>(ps.effective), static_cast<QAbstractSeries*>(ps.marker)}) {
      for (QLegendMarker* m : _chart->legend()->markers(series)) m->setVisible(false);
    }
    _pairs.push_back(ps);
  }
}

void FrictionChart::moveMarkers(double temp_c, double seconds) {
  const double t = std::clamp(temp_c, kMinTempC, kMaxTempC);
  for (auto& p : _pairs) {
    const auto v = _model->effective(p.key, temp_c, seconds);
    p.marker->clear();
    if (v) p.marker->append(t, v->mu_s);
  }
  _tempLine->clear();
  _tempLine->append(t, 0.0);
  _tempLine->append(t, kMuAxisMax);
}

}  // namespace pb::ui
