// SPDX-License-Identifier: MIT
// core/lab/study.hpp: the shipped default against the reference configuration on a small fixed
// corpus, limit by limit, in search steps: every limit within one step, the same verdict and the
// same governing mode wherever the reference fails inside the range. The corpus covers each level
// the automatic choice picks, each failing inside the search range: an unwrapped one-layer load and
// a two-layer column stack (the full model), and the same stack wrapped on a slippery belt (the
// reduced model). Labelled long: the reference runs at
// 0.5 ms with plain bisection at half steps (about a minute in all on 2 cores).
#include <QtTest>

#include "core/analysis/analyzer.hpp"
#include "core/lab/study.hpp"
#include "tests/core/test_friction.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

namespace {

using test::carton;
using test::pallet;

// Cartons grip each other and the deck (0.45, 0.4); the belt holds the pallet at 0.5 g, or at
// 0.3 g where the whole load is meant to slip inside the search range.
const FrictionModel& friction_model(bool slippery_belt) {
  static const FrictionModel grippy = test::constant_friction({0.5, 0.45, 0.4});
  static const FrictionModel slippery = test::constant_friction({0.3, 0.45, 0.4});
  return slippery_belt ? slippery : grippy;
}

// Four 10 kg cartons side by side, two layers.
PalletConfig column_stack(WrapType wrap) {
  std::vector<Item> items;
  for (double z : {0.15, 0.35}) {
    for (double x : {-0.25, 0.25}) items.push_back(carton(x, 0.0, z));
  }
  return pallet(items, wrap);
}

// Two 20 kg cartons, one layer: what slides is the whole load on the pallet or the pallet on the
// belt.
PalletConfig one_layer() {
  return pallet({carton(-0.25, 0.0, 0.15, {0.4, 0.3, 0.2}, 20.0),
                 carton(0.25, 0.0, 0.15, {0.4, 0.3, 0.2}, 20.0)});
}

}  // namespace

Q_DECLARE_METATYPE(pb::PalletConfig)

class StudyAgreementTest : public QObject {
  Q_OBJECT

 private slots:
  void defaultAgreesWithTheReference_data() {
    QTest::addColumn<PalletConfig>("config");
    QTest::addColumn<bool>("slippery_belt");
    QTest::addColumn<QString>("level");
    QTest::newRow("one layer, unwrapped") << one_layer() << false << "full";
    QTest::newRow("column stack, unwrapped") << column_stack(WrapType::none) << false << "full";
    QTest::newRow("column stack, stretch wrap, slippery belt")
        << column_stack(WrapType::stretch) << true << "reduced";
  }

  void defaultAgreesWithTheReference() {
    QFETCH(PalletConfig, config);
    QFETCH(bool, slippery_belt);
    QFETCH(QString, level);
    Analyzer reference(reference_options(), friction_model(slippery_belt));
    Analyzer shipped(AnalyzerOptions{}, friction_model(slippery_belt));
    auto ref = reference.analyze(config);
    auto def = shipped.analyze(config);
    QVERIFY(ref.ok());
    QVERIFY(def.ok());
    QCOMPARE(QString::fromUtf8(to_string(def->fidelity)), level);
    const EnvelopeComparison c = compare_envelopes(*ref.value, *def.value);
    qInfo(
        "reference a %.3f d %.3f lat %.3f v %.2f | default a %.3f d %.3f lat %.3f v %.2f | "
        "error in steps %.2f %.2f %.2f %.2f, modes %d/%d",
        ref->max_accel_mps2, ref->max_decel_mps2, ref->max_lateral_g, ref->max_speed_mps,
        def->max_accel_mps2, def->max_decel_mps2, def->max_lateral_g, def->max_speed_mps,
        c.error_steps[0], c.error_steps[1], c.error_steps[2], c.error_steps[3], c.modes_agreeing,
        c.modes_compared);
    QVERIFY(c.verdict_agrees);
    QVERIFY2(c.within_one_step, "a limit of the default is more than one search step away");
    QVERIFY2(c.modes_agree(), "the governing mode differs where the reference fails in range");
  }
};

QTEST_APPLESS_MAIN(StudyAgreementTest)
#include "study_agreement_test.moc"
