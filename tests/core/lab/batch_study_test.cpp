// SPDX-License-Identifier: MIT
#include "core/lab/batch_study.hpp"

#include <QtTest>

#include "core/contract/json_io.hpp"

#include "tests/core/test_friction.hpp"
#include "tests/core/test_pallets.hpp"

using namespace pb;

class BatchStudyTest : public QObject {
  Q_OBJECT

 private slots:
  void distributionByHand() {
    const Distribution d = distribution_of({5, 1, 3, 2, 4});
    QCOMPARE(d.count, 5);
    QCOMPARE(d.min, 1.0);
    QCOMPARE(d.max, 5.0);
    QCOMPARE(d.median, 3.0);
    QCOMPARE(d.mean, 3.0);
    QVERIFY(std::abs(d.p10 - 1.4) < 1e-12);  // 0.1 * 4 = 0.4 of the way from 1 to 2
    QVERIFY(std::abs(d.p90 - 4.6) < 1e-12);
    QCOMPARE(distribution_of({}).count, 0);
  }

  void badOptionsNameTheField() {
    BatchStudyOptions o;
    o.n = 0;
    auto s = run_batch_study(o);
    QVERIFY(!s);
    QCOMPARE(s.diagnostics[0].pointer, std::string("/n"));
    o.n = 1;
    o.threads = -1;
    s = run_batch_study(o);
    QVERIFY(!s);
    QCOMPARE(s.diagnostics[0].pointer, std::string("/threads"));
  }

  // Two identical single-carton pallets and a different one: the shared cache answers the
  // repeat; results do not depend on the thread count; the summary counts every pallet.
  void sharedCacheAndThreads() {
    const FrictionModel friction = test::constant_friction({1.0, 0.3, 0.4});
    PalletConfig a = test::pallet({test::carton(0.0, 0.0, 0.15)});
    PalletConfig b = a;
    b.pallet_id = "same-load";
    PalletConfig c = test::pallet({test::carton(0.0, 0.0, 0.15, {0.3, 0.3, 0.6}, 20.0)});
    BatchStudyOptions o;
    o.pallets = {a, b, c};
    o.threads = 1;
    o.analyzer.fidelity = Fidelity::full;
    auto one = run_batch_study(o, Catalog::builtin(), friction);
    QVERIFY(one);
    QCOMPARE(one->analysed, 3);
    QCOMPARE(one->errors, 0);
    QCOMPARE(one->cache_hits, 1);
    QVERIFY(one->pallets[1].cached);
    QCOMPARE(one->pallets[1].result->pallet_id, std::string("same-load"));
    QCOMPARE(one->pallets[1].result->max_accel_mps2, one->pallets[0].result->max_accel_mps2);
    QCOMPARE(one->pallets[1].result->sims_run, 0);
    QCOMPARE(one->sims, one->pallets[0].result->sims_run + one->pallets[2].result->sims_run);
    int modes = 0;
    for (const auto& [mode, count] : one->dominant_modes) modes += count;
    QCOMPARE(modes, 3);
    QCOMPARE(one->max_accel_mps2.count + one->rejects, 3);

    // The same results, field for field, at 2 and 4 threads; but the work that produced them: the
    // timings, and the simulations (a repeat answered from the cache reports none, and which of
    // two identical loads is the repeat depends on which worker takes it first).
    auto comparable = [](const SafetyResult& r) {
      Json j = safety_result_to_json(r);
      j.erase("sim_runtime_ms");
      j.erase("sims_run");
      return j;
    };
    for (const int threads : {2, 4}) {
      o.threads = threads;
      auto other = run_batch_study(o, Catalog::builtin(), friction);
      QVERIFY(other);
      QCOMPARE(other->threads, std::min(threads, 3));  // no more workers than pallets
      for (std::size_t k = 0; k < 3; ++k) {
        const Json x = comparable(*other->pallets[k].result);
        const Json y = comparable(*one->pallets[k].result);
        QVERIFY2(x == y, (x.dump() + "\n" + y.dump()).c_str());
      }
    }
  }
};

QTEST_APPLESS_MAIN(BatchStudyTest)
#include "batch_study_test.moc"
