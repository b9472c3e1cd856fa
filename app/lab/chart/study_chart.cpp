// SPDX-License-Identifier: MIT
#include "app/lab/chart/study_chart.hpp"

#include <QApplication>
#include <QBrush>
#include <QChart>
#include <QChartView>
#include <QColor>
#include <QFont>
#include <QLineSeries>
#include <QLogValueAxis>
#include <QPainter>
#include <QPen>
#include <QPixmap>
#include <QScatterSeries>
#include <QValueAxis>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

namespace pb::cli {

namespace {

constexpr double kMinMs = 0.001;  // a log axis needs positive values (closed form takes µs)

QString label_of(const StudyChartPoint& p) {
  QString name = QString::fromStdString(p.name);
  if (p.is_default) name += QStringLiteral(" [shipped default]");
  if (p.is_reference_equivalent) name += QStringLiteral(" [reference-equivalent]");
  if (p.is_reference) name += QStringLiteral(" [reference]");
  if (p.pareto) name += QStringLiteral(" *");
  return name;
}

}  // namespace

std::string render_study_chart(const std::vector<StudyChartPoint>& points, const std::string& title,
                               const std::string& png_path, int width, int height) {
  if (points.empty()) return "no configuration to chart";
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  int argc = 1;
  char name[] = "palletballet-lab";
  char* argv[] = {name, nullptr};
  QApplication* app = qobject_cast<QApplication*>(QCoreApplication::instance());
  std::unique_ptr<QApplication> owned;
  if (!app) {
    owned = std::make_unique<QApplication>(argc, argv);
    app = owned.get();
  }

  auto* chart = new QChart();
  chart->setTitle(QString::fromStdString(title));
  chart->legend()->setAlignment(Qt::AlignRight);
  chart->setBackgroundBrush(Qt::white);

  auto* x_axis = new QLogValueAxis();
  x_axis->setTitleText(QStringLiteral("median wall time per envelope (ms, log scale)"));
  x_axis->setLabelFormat(QStringLiteral("%g"));
  x_axis->setBase(10.0);
  x_axis->setMinorTickCount(8);
  auto* y_axis = new QValueAxis();
  y_axis->setTitleText(QStringLiteral("share of pallets within one search step of the reference"));
  y_axis->setLabelFormat(QStringLiteral("%.2f"));
  chart->addAxis(x_axis, Qt::AlignBottom);
  chart->addAxis(y_axis, Qt::AlignLeft);

  double lo = 1e300, hi = 0.0, ymin = 1.0;
  for (const auto& p : points) {
    const double x = std::max(kMinMs, p.median_ms);
    lo = std::min(lo, x);
    hi = std::max(hi, x);
    ymin = std::min(ymin, p.within_one_step);
  }
  x_axis->setRange(std::pow(10.0, std::floor(std::log10(lo))),
                   std::pow(10.0, std::ceil(std::log10(hi * 1.0001))));
  y_axis->setRange(std::max(0.0, std::floor(ymin * 10.0) / 10.0 - 0.05), 1.05);
  y_axis->setTickType(QValueAxis::TicksDynamic);
  y_axis->setTickAnchor(0.0);
  y_axis->setTickInterval(ymin < 0.5 ? 0.1 : 0.05);

  // The Pareto front as a staircase line through its points, fastest first.
  std::vector<StudyChartPoint> front;
  for (const auto& p : points) {
    if (p.pareto) front.push_back(p);
  }
  std::sort(front.begin(), front.end(),
            [](const auto& a, const auto& b) { return a.median_ms < b.median_ms; });
  if (front.size() > 1) {
    auto* line = new QLineSeries();
    line->setName(QStringLiteral("Pareto front (*)"));
    QPen pen(QColor(120, 120, 120));
    pen.setStyle(Qt::DashLine);
    pen.setWidth(2);
    line->setPen(pen);
    for (const auto& p : front) line->append(std::max(kMinMs, p.median_ms), p.within_one_step);
    chart->addSeries(line);
    line->attachAxis(x_axis);
    line->attachAxis(y_axis);
  }

  for (const auto& p : points) {
    auto* s = new QScatterSeries();
    s->setName(label_of(p));
    s->append(std::max(kMinMs, p.median_ms), p.within_one_step);
    s->setMarkerSize(p.is_default ? 22.0 : (p.pareto ? 15.0 : 11.0));
    if (p.is_default) {
      s->setMarkerShape(QScatterSeries::MarkerShapeRectangle);
      s->setColor(QColor(220, 30, 30));
      s->setBorderColor(Qt::black);
    } else if (p.is_reference_equivalent) {
      s->setMarkerShape(QScatterSeries::MarkerShapeRectangle);
      s->setColor(QColor(40, 40, 40));
    } else if (p.is_reference) {
      s->setColor(QColor(30, 120, 30));
    }
    s->setPointLabelsVisible(true);
    s->setPointLabelsFormat(QString::fromStdString(p.name));
    s->setPointLabelsClipping(false);
    QFont f = s->pointLabelsFont();
    f.setPointSize(p.is_default ? 10 : 8);
    f.setBold(p.is_default);
    s->setPointLabelsFont(f);
    chart->addSeries(s);
    s->attachAxis(x_axis);
    s->attachAxis(y_axis);
  }

  QChartView view(chart);  // takes ownership of the chart
  view.setRenderHint(QPainter::Antialiasing);
  view.resize(width, height);
  view.show();
  QApplication::processEvents();
  const QPixmap pixmap = view.grab();
  view.hide();
  if (pixmap.isNull()) return "the chart could not be rendered";
  if (!pixmap.save(QString::fromStdString(png_path), "PNG")) {
    return "cannot write '" + png_path + "'; check that its folder exists";
  }
  return {};
}

}  // namespace pb::cli
