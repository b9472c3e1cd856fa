// SPDX-License-Identifier: MIT
// Failure detectors on synthetic traces whose measures cross their thresholds at known frames.
#include "core/physics/detectors.hpp"

#include <QtTest>

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "core/contract/pallet_config.hpp"

using namespace pb;

namespace {

constexpr double kDt = 0.002;

Quat axis_angle(const Vec3& axis, double deg) {
  const double half = deg * std::numbers::pi / 360.0;
  return {std::cos(half), axis[0] * std::sin(half), axis[1] * std::sin(half),
          axis[2] * std::sin(half)};
}

Quat multiply(const Quat& a, const Quat& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

// The state of one frame, described in the pallet's own terms: the pallet's travel, yaw and tilt
// (about Y), the belt's travel, and where each item sits in the pallet frame.
struct Motion {
  double x = 0.0;
  double y = 0.0;
  double yaw_deg = 0.0;
  double tilt_deg = 0.0;
  double belt_x = 0.0;
  double belt_y = 0.0;
  // Items at rest: two on the bottom layer, one on top (pallet frame, m).
  std::vector<Vec3> items{{-0.3, 0.0, 0.2}, {0.3, 0.0, 0.2}, {0.0, 0.0, 0.5}};
};

constexpr double kPalletZ = 0.075;

Pose pallet_pose(const Motion& m) {
  return {{m.x, m.y, kPalletZ},
          multiply(axis_angle({0, 0, 1}, m.yaw_deg), axis_angle({0, 1, 0}, m.tilt_deg))};
}

std::vector<Pose> item_poses(const Motion& m) {
  const Pose pallet = pallet_pose(m);
  std::vector<Pose> out;
  for (const Vec3& local : m.items) {
    const Vec3 r = rotate(pallet.quat, local);
    out.push_back(
        {{pallet.pos[0] + r[0], pallet.pos[1] + r[1], pallet.pos[2] + r[2]}, pallet.quat});
  }
  return out;
}

// Frames 0..n-1 at t = f * kDt; frame 0 is the rest state motion(0).
Trace make_trace(int n, const std::function<Motion(int)>& motion) {
  Trace trace(3);
  for (int f = 0; f < n; ++f) {
    const Motion m = motion(f);
    trace.push(f * kDt, {m.belt_x, m.belt_y, 0.0, 0.0}, pallet_pose(m), item_poses(m));
  }
  return trace;
}

// One mode ramping by `step` per frame; every other measure stays well under its threshold.
Trace tip(double step_deg, int n = 20) {
  return make_trace(n, [=](int f) { return Motion{.tilt_deg = step_deg * f}; });
}
Trace slide(double step_m, int n = 20) {
  // The top item moves sideways: pair distances to the bottom items barely change.
  return make_trace(n, [=](int f) {
    Motion m;
    m.items[2][1] += step_m * f;
    return m;
  });
}
Trace shift(double step_m, int n = 20) {
  // The bottom items move apart along the line between them.
  return make_trace(n, [=](int f) {
    Motion m;
    m.items[1][0] += step_m * f;
    return m;
  });
}
Trace slip(double step_m, int n = 20) {
  // The belt travels diagonally (3-4-5), the pallet stays: the slip is step_m per frame.
  return make_trace(
      n, [=](int f) { return Motion{.belt_x = 0.6 * step_m * f, .belt_y = 0.8 * step_m * f}; });
}

bool near(double a, double b, double tol = 1e-9) {
  return std::abs(a - b) <= tol;
}

}  // namespace

class DetectorsTest : public QObject {
  Q_OBJECT

 private slots:
  void defaults() {
    const DetectorThresholds t;
    QCOMPARE(t.tip_deg, 8.0);
    QCOMPARE(t.item_slide_m, 0.05);
    QCOMPARE(t.load_shift_m, 0.02);
    QCOMPARE(t.pallet_slip_m, 0.30);
  }

  void tipOver() {
    // 1.1 deg per frame: 7.7 deg at frame 7, 8.8 deg at frame 8.
    const auto event = first_failure(tip(1.1), {});
    QVERIFY(event);
    QCOMPARE(event->mode, FailureMode::tip_over);
    QCOMPARE(event->time_s, 8 * kDt);
    QVERIFY(near(event->value, 8.8));
    QVERIFY(event->items.empty());
  }

  void topItemSlide() {
    // 1.1 cm per frame: 4.4 cm at frame 4, 5.5 cm at frame 5.
    const auto event = first_failure(slide(0.011), {});
    QVERIFY(event);
    QCOMPARE(event->mode, FailureMode::top_item_slide);
    QCOMPARE(event->time_s, 5 * kDt);
    QVERIFY(near(event->value, 0.055));
    QCOMPARE(event->items, std::vector<int>{2});
  }

  // A top_item_slide says how the item turned out of level relative to the pallet, so a carton
  // that tipped over an edge is told from one that slid flat (item_tipped), on a pallet that is
  // itself yawed and tilted.
  void anItemThatTipsIsToldFromOneThatSlides() {
    const Pose pallet{{1.0, 2.0, kPalletZ},
                      multiply(axis_angle({0, 0, 1}, 30.0), axis_angle({0, 1, 0}, 2.0))};
    auto in_world = [&](const Vec3& local, const Quat& turn) {
      const Vec3 r = rotate(pallet.quat, local);
      return Pose{{pallet.pos[0] + r[0], pallet.pos[1] + r[1], pallet.pos[2] + r[2]},
                  multiply(pallet.quat, turn)};
    };
    // A 0.2 x 0.2 x 1 m carton standing on the deck, its centre 0.5 m up; it turns 6 deg about
    // its edge at y = +0.1: its centre moves 2 (0.51 m) sin 3 deg = 5.3 cm.
    const Vec3 rest{0.0, 0.0, 0.5};
    const Vec3 pivot{0.0, 0.1, 0.0};
    const Quat turn = axis_angle({1, 0, 0}, 6.0);
    const Vec3 arm = rotate(turn, Vec3{rest[0] - pivot[0], rest[1] - pivot[1], rest[2] - pivot[2]});
    const Vec3 tipped_at{pivot[0] + arm[0], pivot[1] + arm[1], pivot[2] + arm[2]};
    const std::vector<Pose> items0{in_world(rest, {1, 0, 0, 0})};
    const FailureDetector detector({}, pallet, items0);
    const std::vector<Pose> tipped{in_world(tipped_at, turn)};
    const auto event = detector.update(0.5, {0.0, 0.0, 0.0, 0.0}, pallet, tipped);
    QVERIFY(event);
    QCOMPARE(event->mode, FailureMode::top_item_slide);
    QVERIFY2(near(event->item_tilt_deg, 6.0, 1e-9), std::to_string(event->item_tilt_deg).c_str());
    QVERIFY(item_tipped(*event, {0.2, 0.2, 1.0}));
    QVERIFY2(describe(*event).find("turning 6.0 deg out of level") != std::string::npos,
             describe(*event).c_str());
    // The same carton slid 5.5 cm flat, turning 1 deg about its vertical and 0.5 about X.
    const std::vector<Pose> slid{in_world(
        {0.0, 0.055, 0.5}, multiply(axis_angle({0, 0, 1}, 1.0), axis_angle({1, 0, 0}, 0.5)))};
    const auto flat = detector.update(0.5, {0.0, 0.0, 0.0, 0.0}, pallet, slid);
    QVERIFY(flat);
    QCOMPARE(flat->mode, FailureMode::top_item_slide);
    QVERIFY2(near(flat->item_tilt_deg, 0.5, 1e-6), std::to_string(flat->item_tilt_deg).c_str());
    QVERIFY(!item_tipped(*flat, {0.2, 0.2, 1.0}));
    QVERIFY(describe(*flat).find("turning") == std::string::npos);
    // Only an item's event is told: the pallet's own tilt is tip_over.
    QVERIFY(!item_tipped(FailureEvent{FailureMode::tip_over, 0.5, 9.0, {}, 0.0}, {1, 1, 1}));
  }

  // A top_item_slide says the least any item moved on the pallet, so a load that slid off its
  // pallet as one (every carton with it: load_slid_as_one) is told from an item that left it and
  // from a column leaning over as one, on a pallet that is itself yawed.
  void aLoadThatSlidesAsOneIsToldFromAnItemAndFromALean() {
    auto moved = [](const std::function<void(Motion&, int)>& move) {
      return first_failure(make_trace(20,
                                      [&](int f) {
                                        Motion m{.x = 0.4, .yaw_deg = 20.0};
                                        move(m, f);
                                        return m;
                                      }),
                           {});
    };
    // Every item 1.1 cm a frame along the pallet's x, the top one 2 % further.
    const auto as_one = moved([](Motion& m, int f) {
      for (Vec3& item : m.items) item[0] += 0.011 * f;
      m.items[2][0] += 0.00022 * f;
    });
    QVERIFY(as_one);
    QCOMPARE(as_one->mode, FailureMode::top_item_slide);
    QCOMPARE(as_one->items, std::vector<int>{2});
    QVERIFY2(near(as_one->least_item_move_m, 0.055, 1e-9),
             std::to_string(as_one->least_item_move_m).c_str());
    QVERIFY(load_slid_as_one(*as_one));
    QVERIFY2(describe(*as_one).find("the load moved 5.6 cm on the pallet as one (every item at "
                                    "least 5.5 cm)") != std::string::npos,
             describe(*as_one).c_str());
    // The top item alone.
    const auto top = first_failure(slide(0.011), {});
    QVERIFY(top);
    QVERIFY(near(top->least_item_move_m, 0.0, 1e-9));
    QVERIFY(!load_slid_as_one(*top));
    QVERIFY(describe(*top).find("item 2 moved") != std::string::npos);
    // The load leaning over as one about the deck's edge at x = 0.6: a rigid turn about Y keeps
    // every distance between items, but moves each by its distance from the edge (the nearest
    // 0.36 m, the farthest 0.92 m).
    const auto lean = moved([](Motion& m, int f) {
      const double a = 0.02 * f;  // rad
      for (Vec3& item : m.items) {
        const double dx = item[0] - 0.6;
        const double dz = item[2];
        item[0] = 0.6 + std::cos(a) * dx + std::sin(a) * dz;
        item[2] = -std::sin(a) * dx + std::cos(a) * dz;
      }
    });
    QVERIFY(lean);
    QCOMPARE(lean->mode, FailureMode::top_item_slide);
    QVERIFY2(lean->least_item_move_m < 0.7 * lean->value, describe(*lean).c_str());
    QVERIFY(!load_slid_as_one(*lean));
    // One item is never a load moving as one.
    const Pose pallet{{0.0, 0.0, kPalletZ}, {1, 0, 0, 0}};
    const FailureDetector one({}, pallet, std::vector<Pose>{{{0.0, 0.0, 0.3}, {1, 0, 0, 0}}});
    const auto alone = one.update(0.5, {0.0, 0.0, 0.0, 0.0}, pallet,
                                  std::vector<Pose>{{{0.06, 0.0, 0.3}, {1, 0, 0, 0}}});
    QVERIFY(alone);
    QCOMPARE(alone->least_item_move_m, 0.0);
    QVERIFY(!load_slid_as_one(*alone));
    // slide_kind tells the three apart for a pallet's cartons, and is item_slid for any other mode.
    PalletConfig config;
    config.items.assign(3, Item{});
    for (Item& item : config.items) item.dims_m = {0.4, 0.3, 0.2};
    QCOMPARE(slide_kind(*as_one, config), SlideKind::load_as_one);
    QCOMPARE(slide_kind(*top, config), SlideKind::item_slid);
    QCOMPARE(slide_kind(FailureEvent{FailureMode::tip_over, 0.5, 9.0, {}, 0.0}, config),
             SlideKind::item_slid);
    // Words for a person.
    QCOMPARE(mode_words(FailureMode::top_item_slide), std::string_view("an item slides off"));
    QCOMPARE(mode_words(FailureMode::top_item_slide, SlideKind::load_as_one),
             std::string_view("the load slides on its pallet"));
    QCOMPARE(mode_words(FailureMode::top_item_slide, SlideKind::item_tipped),
             std::string_view("an item tips over"));
  }

  void loadShift() {
    // 0.7 cm per frame: 1.4 cm at frame 2, 2.1 cm at frame 3 between items 0 and 1.
    const auto event = first_failure(shift(0.007), {});
    QVERIFY(event);
    QCOMPARE(event->mode, FailureMode::load_shift);
    QCOMPARE(event->time_s, 3 * kDt);
    QVERIFY(near(event->value, 0.021));
    QCOMPARE(event->items, (std::vector<int>{0, 1}));
  }

  void palletSlip() {
    // 7 cm per frame: 28 cm at frame 4, 35 cm at frame 5.
    const auto event = first_failure(slip(0.07), {});
    QVERIFY(event);
    QCOMPARE(event->mode, FailureMode::pallet_slip);
    QCOMPARE(event->time_s, 5 * kDt);
    QVERIFY(near(event->value, 0.35));
    QVERIFY(event->items.empty());
  }

  void justUnderEveryThreshold() {
    // Each ramp ends at 98 % of its threshold at frame 19.
    const DetectorThresholds t;
    QVERIFY(!first_failure(tip(0.98 * t.tip_deg / 19), t));
    QVERIFY(!first_failure(slide(0.98 * t.item_slide_m / 19), t));
    QVERIFY(!first_failure(shift(0.98 * t.load_shift_m / 19), t));
    QVERIFY(!first_failure(slip(0.98 * t.pallet_slip_m / 19), t));
  }

  void thresholdsAreConfigurable() {
    DetectorThresholds t;
    t.tip_deg = 3.0;  // 1.1 deg per frame crosses 3 at frame 3
    const auto event = first_failure(tip(1.1), t);
    QVERIFY(event);
    QCOMPARE(event->time_s, 3 * kDt);
  }

  void earliestModeWins() {
    // The slip crosses at frame 3 (33 cm); the slide would cross later at frame 5, further past.
    const Trace trace = make_trace(20, [](int f) {
      Motion m;
      m.items[2][1] += 0.011 * f;
      m.belt_x = 0.11 * f;
      return m;
    });
    const auto event = first_failure(trace, {});
    QVERIFY(event);
    QCOMPARE(event->mode, FailureMode::pallet_slip);
    QCOMPARE(event->time_s, 3 * kDt);
  }

  void tieGoesToLargestRatio() {
    const Motion rest;
    const FailureDetector detector({}, pallet_pose(rest), item_poses(rest));
    // Tilt 8.8 deg (1.10 x 8) and slip 0.36 m (1.20 x 0.30): slip, though 0.36 < 8.8.
    Motion m{.tilt_deg = 8.8, .belt_x = 0.36};
    auto event = detector.update(0.5, {m.belt_x, m.belt_y, 0, 0}, pallet_pose(m), item_poses(m));
    QVERIFY(event);
    QCOMPARE(event->mode, FailureMode::pallet_slip);
    QCOMPARE(event->time_s, 0.5);
    QVERIFY(near(event->value, 0.36));
    // Tilt 10 deg (1.25 x 8) beats the same slip.
    m.tilt_deg = 10.0;
    event = detector.update(0.5, {m.belt_x, m.belt_y, 0, 0}, pallet_pose(m), item_poses(m));
    QVERIFY(event);
    QCOMPARE(event->mode, FailureMode::tip_over);
    QVERIFY(near(event->value, 10.0));
  }

  void rigidMotionOfPalletAndLoadIsNoFailure() {
    // The pallet travels 1.2 m in x and 0.4 m in y, yawing 57 deg, with the belt and its load.
    const Trace trace = make_trace(20, [](int f) {
      return Motion{
          .x = 0.06 * f, .y = 0.02 * f, .yaw_deg = 3.0 * f, .belt_x = 0.06 * f, .belt_y = 0.02 * f};
    });
    QVERIFY(!first_failure(trace, {}));
    const std::size_t last = trace.size() - 1;
    QVERIFY(
        measure_item_slide(trace.pallet(0), trace.items(0), trace.pallet(last), trace.items(last))
            .value < 1e-12);
    QVERIFY(measure_load_shift(trace.items(0), trace.items(last)).value < 1e-12);
    QVERIFY(measure_pallet_slip(trace.pallet(0), trace.pallet(last), trace.belt(last).x,
                                trace.belt(last).y)
                .value < 1e-12);
  }

  void slideIsMeasuredInThePalletFrame() {
    // Yawed 90 deg, the top item's move along the pallet's own +X is world +Y.
    const Motion rest;
    Motion m{.yaw_deg = 90.0};
    m.items[2][0] += 0.04;
    const Measure slide_measure =
        measure_item_slide(pallet_pose(rest), item_poses(rest), pallet_pose(m), item_poses(m));
    QVERIFY(near(slide_measure.value, 0.04));
    QCOMPARE(slide_measure.a, 2);
    QCOMPARE(slide_measure.b, -1);
  }

  void measures() {
    Pose pallet0{{1.0, 2.0, kPalletZ}, {1, 0, 0, 0}};
    Pose pallet{{1.4, 2.1, kPalletZ}, {1, 0, 0, 0}};
    // Belt (0.5, 0.4) against pallet (0.4, 0.1): (0.1, 0.3) apart.
    QVERIFY(near(measure_pallet_slip(pallet0, pallet, 0.5, 0.4).value, std::hypot(0.1, 0.3)));
    QVERIFY(near(measure_tilt({{0, 0, 0}, axis_angle({1, 0, 0}, 12)}).value, 12.0));

    const std::vector<Pose> items0{
        {{0, 0, 0}, {1, 0, 0, 0}}, {{1, 0, 0}, {1, 0, 0, 0}}, {{0, 2, 0}, {1, 0, 0, 0}}};
    std::vector<Pose> items = items0;
    items[2].pos[1] = 2.5;  // d02 changes by 0.5; d12 by sqrt(1 + 6.25) - sqrt(5)
    const Measure shift_measure = measure_load_shift(items0, items);
    QVERIFY(near(shift_measure.value, 0.5));
    QCOMPARE(shift_measure.a, 0);
    QCOMPARE(shift_measure.b, 2);
    const Measure none = measure_load_shift(items0, items0);
    QCOMPARE(none.value, 0.0);
    QCOMPARE(none.a, -1);
    QCOMPARE(measure_load_shift({}, {}).value, 0.0);
  }

  void noFailureOnEmptyOrRestOnlyTraces() {
    QVERIFY(!first_failure(Trace(3), {}));
    QVERIFY(!first_failure(tip(100.0, 1), {}));
  }

  void describeEachMode() {
    QCOMPARE(QString::fromStdString(describe({FailureMode::tip_over, 0.412, 8.3, {}})),
             QStringLiteral("tip_over at 0.412 s: the pallet tilted 8.3 deg"));
    QCOMPARE(QString::fromStdString(describe({FailureMode::top_item_slide, 0.242, 0.051, {7}})),
             QStringLiteral("top_item_slide at 0.242 s: item 7 moved 5.1 cm on the pallet"));
    QCOMPARE(
        QString::fromStdString(describe({FailureMode::load_shift, 0.3, 0.023, {3, 7}})),
        QStringLiteral("load_shift at 0.300 s: items 3 and 7 moved 2.3 cm relative to each other"));
    QCOMPARE(
        QString::fromStdString(describe({FailureMode::pallet_slip, 1.25, 0.31, {}})),
        QStringLiteral("pallet_slip at 1.250 s: the pallet slipped 31 cm relative to the belt"));
    QCOMPARE(QString::fromStdString(describe({})),
             QStringLiteral("no_failure: the load stayed within every threshold"));
    // An event without its items still reads as a sentence.
    QCOMPARE(QString::fromStdString(describe({FailureMode::load_shift, 0.3, 0.023, {}})),
             QStringLiteral("load_shift at 0.300 s: measured 0.023"));
  }
};

QTEST_APPLESS_MAIN(DetectorsTest)
#include "detectors_test.moc"
