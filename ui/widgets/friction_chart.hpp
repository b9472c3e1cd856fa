// SPDX-License-Identifier: MIT
// The friction chart (Qt Charts): static friction against temperature for every surface pair the
// pallet uses (belt/pallet, item/pallet, item/item), steady (solid) and with the frost-melt
// penalty at the pallet's time since its temperature changed (dashed), the frost-melt band shaded,
// and a marker per pair at the pallet's body temperature on the effective curve.
//
// Wiring (MainWindow): PalletDocument changed -> setPallet(config). Nothing to listen to.
#pragma once

#include <QString>
#include <QWidget>
#include <string>
#include <vector>

#include "core/contract/pallet_config.hpp"
#include "core/inputs/friction.hpp"

class QChart;
class QLabel;
class QChartView;
class QLineSeries;
class QScatterSeries;
class QAreaSeries;
class QValueAxis;

namespace pb::ui {

class FrictionChart : public QWidget {
  Q_OBJECT

 public:
  /// Temperature range of the chart (the contract's body temperature range).
  static constexpr double kMinTempC = -40.0;
  static constexpr double kMaxTempC = 40.0;
  static constexpr double kStepC = 0.5;

  explicit FrictionChart(QWidget* parent = nullptr,
                         const pb::FrictionModel& model = pb::FrictionModel::builtin());

  /// For tests and the screenshot: one per pair shown, in belt/pallet, item/pallet, item/item
  /// order.
  struct PairSeries {
    std::string key;
    QLineSeries* steady = nullptr;
    QLineSeries* effective = nullptr;
    QScatterSeries* marker = nullptr;  ///< one point: (body temperature, effective mu_s)
  };
  const std::vector<PairSeries>& pairs() const { return _pairs; }
  QAreaSeries* frostBand() const { return _band; }
  QLineSeries* temperatureLine() const { return _tempLine; }
  QChart* chart() const { return _chart; }
  /// The words above the chart (what it shows, or why there is nothing) and the legend under it,
  /// both wrapped to the panel's width: the chart's own title and legend elided them ("wood_...").
  QString caption() const;
  QString legendText() const;
  /// The message shown instead of curves when the pallet's pairs are unknown (empty otherwise).
  QString error() const { return _error; }

 public slots:
  /// Rebuilds the curves for the pallet's pairs and moves the markers to its temperature.
  void setPallet(const pb::PalletConfig& config);

 private:
  void rebuild(const pb::ContactFriction& friction, double seconds_since_change);
  void moveMarkers(double temp_c, double seconds_since_change);

  const pb::FrictionModel* _model;
  QChart* _chart;
  QChartView* _view;
  QLabel* _caption;
  QLabel* _legend;
  QValueAxis* _axisX;
  QValueAxis* _axisY;
  QAreaSeries* _band = nullptr;
  QLineSeries* _tempLine = nullptr;
  std::vector<PairSeries> _pairs;
  std::vector<std::string> _keys;  ///< the pairs currently drawn
  double _seconds = -1.0;          ///< seconds since change the effective curves were drawn for
  QString _error;
};

}  // namespace pb::ui
