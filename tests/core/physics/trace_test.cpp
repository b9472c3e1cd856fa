// SPDX-License-Identifier: MIT
// Trace: frames appended in order and read back per frame, items included.
#include "core/physics/trace.hpp"

#include <QtTest>

#include <vector>

using namespace pb;

namespace {

Pose at(double x, double y, double z) {
  Pose pose;
  pose.pos = {x, y, z};
  return pose;
}

}  // namespace

class TraceTest : public QObject {
  Q_OBJECT

 private slots:
  void startsEmpty() {
    const Trace trace(3);
    QVERIFY(trace.empty());
    QCOMPARE(trace.size(), std::size_t{0});
    QCOMPARE(trace.n_items(), 3);
    QCOMPARE(Trace().n_items(), 0);
  }

  void reserveKeepsItEmpty() {
    Trace trace(2);
    trace.reserve(100);
    QVERIFY(trace.empty());
  }

  void framesReadBackInOrder() {
    Trace trace(2);
    const std::vector<Pose> items0{at(1, 2, 3), at(4, 5, 6)};
    const std::vector<Pose> items1{at(7, 8, 9), at(10, 11, 12)};
    trace.push(0.0, {}, at(0, 0, 0.075), items0);
    trace.push(0.002, {0.1, 0.2, 0.3, 0.4}, at(0.5, 0, 0.075), items1);

    QCOMPARE(trace.size(), std::size_t{2});
    QVERIFY(!trace.empty());
    QCOMPARE(trace.time(0), 0.0);
    QCOMPARE(trace.time(1), 0.002);
    QCOMPARE(trace.belt(0).x, 0.0);
    QCOMPARE(trace.belt(1).x, 0.1);
    QCOMPARE(trace.belt(1).y, 0.2);
    QCOMPARE(trace.belt(1).vx, 0.3);
    QCOMPARE(trace.belt(1).vy, 0.4);
    QVERIFY(trace.pallet(1) == at(0.5, 0, 0.075));
    QCOMPARE(trace.items(0).size(), std::size_t{2});
    QVERIFY(trace.items(0)[0] == items0[0]);
    QVERIFY(trace.items(0)[1] == items0[1]);
    QVERIFY(trace.items(1)[0] == items1[0]);
    QVERIFY(trace.items(1)[1] == items1[1]);
  }

  void noItems() {
    Trace trace(0);
    trace.push(0.0, {}, at(0, 0, 0), {});
    trace.push(1.0, {}, at(1, 0, 0), {});
    QCOMPARE(trace.size(), std::size_t{2});
    QVERIFY(trace.items(1).empty());
  }
};

QTEST_APPLESS_MAIN(TraceTest)
#include "trace_test.moc"
