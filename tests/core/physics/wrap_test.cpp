// SPDX-License-Identifier: MIT
#include "core/physics/wrap.hpp"

#include <QtTest>
#include <array>
#include <cmath>

#include "core/physics/engine.hpp"
#include "core/physics/scene.hpp"
#include "tests/core/test_friction.hpp"

using namespace pb;

namespace {

bool near_rel(double actual, double expected, double rel) {
  return std::abs(actual - expected) <= rel * std::abs(expected);
}

// The physical stiffness and damping a weld realises (MUJOCO_2_2_NOTES.md section 1, direct
// solref with a constant impedance d): K_eff = K' / ((1 - d)(1/m1 + 1/m2)), C_eff likewise.
std::array<double, 2> physical(const WeldParams& w, double m1, double m2) {
  const double d = w.solimp[0];
  const double diag = 1.0 / m1 + 1.0 / m2;
  return {-w.solref[0] / ((1.0 - d) * diag), -w.solref[1] / ((1.0 - d) * diag)};
}

// Item-relative-to-pallet position in the pallet frame.
std::array<double, 3> relative(const mjData* d, int item, int pallet) {
  std::array<double, 3> out{};
  for (int k = 0; k < 3; ++k) {
    double v = 0.0;
    for (int j = 0; j < 3; ++j) {
      // xmat is row-major (world = R * local): local = R^T * world.
      v += d->xmat[9 * pallet + 3 * j + k] * (d->xpos[3 * item + j] - d->xpos[3 * pallet + j]);
    }
    out[static_cast<std::size_t>(k)] = v;
  }
  return out;
}

}  // namespace

class WrapTest : public QObject {
  Q_OBJECT

 private slots:
  void stiffnessPerWrapType() {
    QCOMPARE(wrap_stiffness(WrapType::none).stiffness_n_per_m, 0.0);
    QCOMPARE(wrap_stiffness(WrapType::none).damping_ratio, 0.0);
    QCOMPARE(wrap_stiffness(WrapType::shrink).stiffness_n_per_m, 3000.0);
    QCOMPARE(wrap_stiffness(WrapType::stretch).stiffness_n_per_m, 8000.0);
    QCOMPARE(wrap_stiffness(WrapType::banded).stiffness_n_per_m, 30000.0);
    for (const WrapType wrap : {WrapType::shrink, WrapType::stretch, WrapType::banded}) {
      QCOMPARE(wrap_stiffness(wrap).damping_ratio, 0.5);
    }
  }

  void weldRecoversThePhysicalSpringAndDamper_data() {
    QTest::addColumn<double>("stiffness");
    QTest::addColumn<double>("ratio");
    QTest::addColumn<double>("m1");
    QTest::addColumn<double>("m2");
    QTest::addColumn<double>("d");
    QTest::newRow("stretch 15 on 25, d 0.3") << 8000.0 << 0.5 << 15.0 << 25.0 << 0.3;
    QTest::newRow("shrink 2 on 25, d 0.1") << 3000.0 << 0.5 << 2.0 << 25.0 << 0.1;
    QTest::newRow("banded 400 on 17, d 0.5") << 30000.0 << 0.5 << 400.0 << 17.0 << 0.5;
    QTest::newRow("custom, d 0.9") << 1234.0 << 0.2 << 7.0 << 20.0 << 0.9;
  }
  void weldRecoversThePhysicalSpringAndDamper() {
    QFETCH(double, stiffness);
    QFETCH(double, ratio);
    QFETCH(double, m1);
    QFETCH(double, m2);
    QFETCH(double, d);
    const WrapStiffness wrap{stiffness, ratio};
    const WeldParams w = weld_params(wrap, m1, m2, d);
    const std::array<double, 5> solimp{d, d, 0.001, 0.5, 2.0};
    QCOMPARE(w.solimp, solimp);
    QVERIFY(w.solref[0] < 0.0 && w.solref[1] < 0.0);  // MuJoCo's direct (stiffness, damping) form
    const double m_red = 1.0 / (1.0 / m1 + 1.0 / m2);
    const auto [k_eff, c_eff] = physical(w, m1, m2);
    QVERIFY2(near_rel(k_eff, stiffness, 1e-12), QByteArray::number(k_eff));
    QVERIFY2(near_rel(c_eff, 2.0 * ratio * std::sqrt(stiffness * m_red), 1e-12),
             QByteArray::number(c_eff));
    // The bodies' order does not matter.
    const WeldParams swapped = weld_params(wrap, m2, m1, d);
    QVERIFY(near_rel(swapped.solref[0], w.solref[0], 1e-12));
    QVERIFY(near_rel(swapped.solref[1], w.solref[1], 1e-12));
  }

  void defaultImpedanceIsPointThree() {
    const WeldParams w = weld_params(wrap_stiffness(WrapType::stretch), 10.0, 25.0);
    QCOMPARE(w.solimp[0], 0.3);
    QCOMPARE(w.solimp[1], 0.3);
    QVERIFY(near_rel(physical(w, 10.0, 25.0)[0], 8000.0, 1e-12));
  }

  // The documented N/m in MuJoCo: a 15 kg frictionless carton welded to a 25 kg pallet that the
  // belt accelerates at 2 m/s^2 lags by m a / K once the transient has rung out (10, 3.75 and
  // 1 mm for shrink, stretch, banded).
  void weldDeflectsByMassTimesAccelOverStiffness_data() {
    QTest::addColumn<WrapType>("wrap");
    QTest::newRow("shrink") << WrapType::shrink;
    QTest::newRow("stretch") << WrapType::stretch;
    QTest::newRow("banded") << WrapType::banded;
  }
  void weldDeflectsByMassTimesAccelOverStiffness() {
    QFETCH(WrapType, wrap);
    constexpr double kMass = 15.0, kAccel = 2.0;
    PalletConfig config;
    config.wrap = wrap;
    Item carton;
    carton.sku = "test";
    carton.weight_kg = kMass;
    carton.dims_m = {0.4, 0.3, 0.25};
    carton.position = {0.0, 0.0, 0.15};
    config.items = {carton};
    // The carton slides freely on the deck (mu 0): only the weld moves it. The pallet holds on
    // the belt (mu 1: 9.8 m/s^2 > 2).
    auto scene = build_scene(config, {}, test::constant_friction({1.0, 0.0, 0.4}));
    QVERIFY2(scene.ok(), scene.ok() ? "" : to_string(scene.diagnostics[0]).c_str());
    const mjModel* m = scene->model.get();
    const SceneLayout& l = scene->layout;
    const int item = l.item_bodies[0], pallet = l.pallet_body;
    // The mapping's premise: MuJoCo's diagonal for a free item and a free pallet is 1/m1 + 1/m2.
    QVERIFY(near_rel(m->body_invweight0[2 * item], 1.0 / kMass, 1e-9));
    QVERIFY(near_rel(m->body_invweight0[2 * pallet], 1.0 / config.base_mass_kg, 1e-9));

    auto data = make_data(m);
    QVERIFY(data.ok());
    mjData* d = data->get();
    const double dt = m->opt.timestep;
    for (int k = 0; k < static_cast<int>(0.3 / dt); ++k) mj_step(m, d);  // settle
    const double rest_x = relative(d, item, pallet)[0];
    // Ramp the belt for 1.5 s; average the lag over the last 0.5 s (the oscillator's decay time
    // 1 / (zeta omega) is below 0.1 s for every wrap).
    const int steps = static_cast<int>(1.5 / dt), from = static_cast<int>(1.0 / dt);
    double lag_sum = 0.0;
    int samples = 0;
    for (int k = 1; k <= steps; ++k) {
      d->ctrl[l.belt_x_act] = kAccel * k * dt;
      mj_step(m, d);
      if (k > from) {
        lag_sum += rest_x - relative(d, item, pallet)[0];
        ++samples;
      }
    }
    QCOMPARE(instability_reason(m, d), std::optional<std::string>());
    QVERIFY(std::abs(d->qvel[l.pallet_dof] - kAccel * 1.5) < 0.01);  // the pallet kept up
    const double lag = lag_sum / samples;
    const double expected = kMass * kAccel / wrap_stiffness(wrap).stiffness_n_per_m;
    QVERIFY2(near_rel(lag, expected, 0.05), QByteArray("lag ") + QByteArray::number(lag * 1000.0) +
                                                " mm, expected " +
                                                QByteArray::number(expected * 1000.0) + " mm");
  }
};

QTEST_APPLESS_MAIN(WrapTest)
#include "wrap_test.moc"
