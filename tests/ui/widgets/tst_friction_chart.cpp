// SPDX-License-Identifier: MIT
// The friction chart: one steady and one penalised curve per surface pair the pallet uses, values
// from the friction model, the frost-melt band at the model's zone, and markers that follow the
// pallet's temperature onto the effective curve.
#include <QAreaSeries>
#include <QChart>
#include <QDir>
#include <QLineSeries>
#include <QScatterSeries>
#include <QtTest>

#include "core/inputs/scenario.hpp"
#include "ui/widgets/friction_chart.hpp"

using namespace pb;
using namespace pb::ui;

namespace {

PalletConfig frozen() {
  auto s = load_scenario("frozen-meat-sprint");
  if (!s) qFatal("curated scenario frozen-meat-sprint is missing");
  return s->pallet;
}

}  // namespace

class TestFrictionChart : public QObject {
  Q_OBJECT

 private slots:
  void curvesForEveryPairOfThePallet() {
    const PalletConfig config = frozen();
    const FrictionModel& model = FrictionModel::builtin();
    const auto cf = model.for_pallet(config);
    QVERIFY(cf.ok());
    FrictionChart chart;
    chart.setPallet(config);
    QVERIFY(chart.error().isEmpty());
    QCOMPARE(chart.pairs().size(), std::size_t{3});
    QCOMPARE(chart.pairs()[0].key, cf->belt_pallet_key);
    QCOMPARE(chart.pairs()[1].key, cf->item_pallet_key);
    QCOMPARE(chart.pairs()[2].key, cf->item_item_key);
    // The legend names each pair in words (no identifiers), and the band; the caption says when.
    QVERIFY2(chart.legendText().contains(QStringLiteral("carton on carton")),
             qPrintable(chart.legendText()));
    QVERIFY(chart.legendText().contains(QStringLiteral("frost-melt band")));
    QVERIFY(!chart.legendText().contains(QLatin1Char('_')));
    QVERIFY(chart.caption().startsWith(QStringLiteral("Static friction")));
    // Band + temperature line + three series per pair.
    QCOMPARE(chart.chart()->series().size(), 2 + 3 * 3);
    const int n = static_cast<int>((FrictionChart::kMaxTempC - FrictionChart::kMinTempC) /
                                   FrictionChart::kStepC) +
                  1;
    for (const auto& p : chart.pairs()) {
      QCOMPARE(p.steady->count(), n);
      QCOMPARE(p.effective->count(), n);
      // Spot values against the model: -25 C and +20 C.
      for (double t : {-25.0, 20.0}) {
        const int i = static_cast<int>((t - FrictionChart::kMinTempC) / FrictionChart::kStepC);
        QCOMPARE(p.steady->at(i).x(), t);
        QCOMPARE(p.steady->at(i).y(), model.steady(p.key, t)->mu_s);
      }
    }
  }

  void frostMeltBandIsTheModelsZone() {
    FrictionChart chart;
    chart.setPallet(frozen());
    const FrostMeltPenalty& pen = FrictionModel::builtin().penalty();
    const QLineSeries* upper = chart.frostBand()->upperSeries();
    QCOMPARE(upper->count(), 2);
    QCOMPARE(upper->at(0).x(), pen.zone_lo_c);
    QCOMPARE(upper->at(1).x(), pen.zone_hi_c);
  }

  void markerFollowsTemperatureOntoTheEffectiveCurve() {
    PalletConfig config = frozen();
    FrictionChart chart;
    chart.setPallet(config);
    const auto& belt = chart.pairs()[0];
    QCOMPARE(belt.marker->count(), 1);
    QCOMPARE(belt.marker->at(0).x(), config.body_temp_c);
    QCOMPARE(chart.temperatureLine()->at(0).x(), config.body_temp_c);

    // Out of the freezer onto a warm dock a minute ago: inside the frost-melt band, penalised.
    config.body_temp_c = 3.0;
    config.seconds_since_temp_change = 60.0;
    chart.setPallet(config);
    const FrictionModel& model = FrictionModel::builtin();
    const auto& belt2 = chart.pairs()[0];
    QCOMPARE(belt2.marker->at(0).x(), 3.0);
    const auto effective = model.effective(belt2.key, 3.0, 60.0);
    const auto steady = model.steady(belt2.key, 3.0);
    QCOMPARE(belt2.marker->at(0).y(), effective->mu_s);
    QVERIFY(effective->mu_s < 0.9 * steady->mu_s);  // the penalty is visible, not a rounding
    QCOMPARE(chart.temperatureLine()->at(0).x(), 3.0);
    // The dashed curve dips inside the band and equals the steady one outside it.
    const int inBand = static_cast<int>((3.0 - FrictionChart::kMinTempC) / FrictionChart::kStepC);
    const int outside =
        static_cast<int>((-20.0 - FrictionChart::kMinTempC) / FrictionChart::kStepC);
    QVERIFY(belt2.effective->at(inBand).y() < belt2.steady->at(inBand).y());
    QCOMPARE(belt2.effective->at(outside).y(), belt2.steady->at(outside).y());

    QVERIFY(QDir().mkpath(QStringLiteral(PB_TEST_ARTIFACTS_DIR)));
    chart.resize(640, 420);
    QVERIFY(chart.grab().save(QStringLiteral(PB_TEST_ARTIFACTS_DIR "/panel_friction_chart.png")));
  }

  void unknownPairSaysSoInsteadOfDrawing() {
    PalletConfig config = frozen();
    config.base_pallet_type = PalletType::chep;
    config.belt_surface = BeltSurface::steel_roller;
    if (FrictionModel::builtin().for_pallet(config).ok()) QSKIP("the table has plastic on steel");
    FrictionChart chart;
    chart.setPallet(frozen());
    chart.setPallet(config);
    QVERIFY(!chart.error().isEmpty());
    QVERIFY(chart.caption().startsWith(QStringLiteral("No friction curves: ")));
    QVERIFY(chart.pairs().empty());
    QCOMPARE(chart.chart()->series().size(), 2);  // the band and the (empty) temperature line
    chart.setPallet(frozen());                    // and it recovers
    QCOMPARE(chart.pairs().size(), std::size_t{3});
  }
};

QTEST_MAIN(TestFrictionChart)
#include "tst_friction_chart.moc"
