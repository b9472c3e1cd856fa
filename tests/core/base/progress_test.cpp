// SPDX-License-Identifier: MIT
// ProgressCounter: counts from many threads at once, never reports more done than planned, and
// ends with the plan equal to what was done.
#include "core/base/progress.hpp"

#include <QtTest>
#include <mutex>
#include <thread>
#include <vector>

using namespace pb;

class ProgressTest : public QObject {
  Q_OBJECT

 private slots:
  void countsFromManyThreads() {
    std::mutex m;
    std::vector<std::pair<int, int>> seen;
    ProgressCounter counter([&](int done, int planned) {
      std::lock_guard lock(m);
      seen.emplace_back(done, planned);
    });
    counter.plan(100);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t) {
      threads.emplace_back([&] {
        for (int k = 0; k < 1000; ++k) counter.finished();
      });
    }
    for (auto& t : threads) t.join();
    QCOMPARE(counter.done(), 4000);
    QCOMPARE(counter.planned(), 4000);  // past the plan, the plan follows
    QCOMPARE(seen.size(), std::size_t(4001));
    for (const auto& [done, planned] : seen) QVERIFY(done <= planned);
  }

  void settlingEndsThePlanAtWhatWasDone() {
    std::pair<int, int> last{-1, -1};
    ProgressCounter counter([&](int done, int planned) { last = {done, planned}; });
    counter.plan(12);
    QCOMPARE(last, std::make_pair(0, 12));
    counter.finished(3);
    QCOMPARE(last, std::make_pair(3, 12));
    counter.settle();  // the search needed fewer than it planned
    QCOMPARE(last, std::make_pair(3, 3));
    ProgressCounter silent({});  // no callback: counts all the same
    silent.finished();
    QCOMPARE(silent.done(), 1);
  }
};

QTEST_APPLESS_MAIN(ProgressTest)
#include "progress_test.moc"
