// SPDX-License-Identifier: MIT
// The analysis service runs real core calls off the GUI thread: results arrive on the GUI thread,
// the event loop keeps turning meanwhile, bad input becomes a message, and cancel drops a result.
#include <QElapsedTimer>
#include <QSignalSpy>
#include <QTest>
#include <QThread>
#include <QTimer>
#include <algorithm>

#include "core/inputs/catalog.hpp"
#include "core/inputs/layer_layout.hpp"
#include "core/inputs/scenario.hpp"
#include "ui/models/analysis_service.hpp"

using pb::ui::AnalysisService;
using pb::ui::RequestId;

class TestAnalysisService : public QObject {
  Q_OBJECT

 private:
  static pb::Scenario tower() {
    auto scenario = pb::load_scenario("tall-unwrapped-tower");
    if (!scenario) qFatal("the curated scenario tall-unwrapped-tower is missing");
    return *scenario;
  }
  // An analysis long enough to watch the event loop through (the tower's took 0.19 s by session
  // 39, too short for a fair count): 48 unwrapped dairy cases in a brick, `bench scale`'s recipe,
  // about 1.5 s.
  static pb::PalletConfig brick48() {
    pb::ScannerInputs in;
    in.pallet_id = "brick-48";
    in.pattern = pb::LayerPattern::brick;
    in.layers = 4;
    in.items_per_layer = 12;
    in.skus = {"SKU-FD-003"};
    in.wrap = pb::WrapType::none;
    auto built = pb::build_from_scanner(in, pb::Catalog::builtin());
    if (!built) qFatal("the 48-carton brick could not be built");
    return *built;
  }

 private slots:
  void solveArrivesOnGuiThread() {
    const pb::Scenario s = tower();
    AnalysisService service;
    QThread* emittedOn = nullptr;
    connect(
        &service, &AnalysisService::solved, this, [&] { emittedOn = QThread::currentThread(); },
        Qt::DirectConnection);
    QStringList steps;
    connect(&service, &AnalysisService::progress, this,
            [&](RequestId, const QString& step) { steps << step; });
    QSignalSpy solved(&service, &AnalysisService::solved);
    QSignalSpy failed(&service, &AnalysisService::failed);

    const RequestId id = service.solve(s.pallet, s.suggested_profile);
    QCOMPARE(id, RequestId{1});
    QCOMPARE(service.pendingCount(), 1);
    QVERIFY(solved.wait(20000));

    QCOMPARE(failed.count(), 0);
    QCOMPARE(solved.count(), 1);
    QCOMPARE(solved.at(0).at(0).value<RequestId>(), id);
    QCOMPARE(emittedOn, QCoreApplication::instance()->thread());
    QCOMPARE(steps, (QStringList{QStringLiteral("Compiling and settling the pallet"),
                                 QStringLiteral("Simulating the profile")}));
    QCOMPARE(service.pendingCount(), 0);

    const auto solve = solved.at(0).at(1).value<pb::ui::SolvePtr>();
    QVERIFY(solve);
    QCOMPARE(solve->sim.outcome, pb::Outcome::failed);
    QVERIFY(solve->replay.failure.has_value());
    QCOMPARE(solve->replay.failure->mode, pb::FailureMode::top_item_slide);
    QCOMPARE(solve->replay.failure->items, std::vector<int>{7});
    QCOMPARE(solve->replay.outcome, std::string("failed"));
    QVERIFY(!solve->replay.frames.empty());
    // The replay follows the wreck past the failure, whose instant is a frame of its own.
    QVERIFY(solve->replay.frames.back().t > solve->replay.failure->time_s);
    QVERIFY(std::any_of(
        solve->replay.frames.begin(), solve->replay.frames.end(),
        [&](const pb::ReplayFrame& f) { return f.t == solve->replay.failure->time_s; }));
    QCOMPARE(solve->replay.pallet, s.pallet);
  }

  void analyzeKeepsEventLoopTurning() {
    const pb::PalletConfig pallet = brick48();
    AnalysisService service;
    QThread* emittedOn = nullptr;
    connect(
        &service, &AnalysisService::analyzed, this, [&] { emittedOn = QThread::currentThread(); },
        Qt::DirectConnection);
    QSignalSpy analyzed(&service, &AnalysisService::analyzed);
    int ticks = 0;
    QTimer timer;
    timer.setInterval(10);
    connect(&timer, &QTimer::timeout, this, [&] { ++ticks; });
    timer.start();

    QElapsedTimer clock;
    clock.start();
    service.analyze(pallet);
    QVERIFY(analyzed.wait(60000));
    const qint64 elapsed = clock.elapsed();
    timer.stop();

    const auto result = analyzed.at(0).at(1).value<pb::SafetyResult>();
    QVERIFY(result.sims_run > 0);  // a real search, not a cache hit
    QCOMPARE(result.pallet_id, std::string("brick-48"));
    QCOMPARE(result.verdict, pb::Verdict::ok);
    QCOMPARE(emittedOn, QCoreApplication::instance()->thread());
    // The search takes seconds; a blocked GUI thread would count one or two ticks in that time.
    qInfo("analysis took %lld ms; the 10 ms timer ticked %d times", elapsed, ticks);
    QVERIFY2(elapsed > 200, "the analysis was too quick to show anything");
    QVERIFY(ticks >= elapsed / 10 / 3);
  }

  void envelopeCarriesProbes() {
    const pb::Scenario s = tower();
    AnalysisService service;
    QSignalSpy ready(&service, &AnalysisService::envelopeReady);
    QSignalSpy counted(&service, &AnalysisService::counted);
    const RequestId id = service.envelope(s.pallet);
    QVERIFY(ready.wait(25000));
    // Progress counted the search's simulations as they ended, for this request, an estimate
    // (not exact), up to every one of them before the result.
    QVERIFY(counted.size() >= 2);
    for (const auto& c : counted) {
      QCOMPARE(c.at(0).value<RequestId>(), id);
      QVERIFY(c.at(1).toInt() <= c.at(2).toInt());
      QCOMPARE(c.at(3).toBool(), false);
    }
    QCOMPARE(ready.at(0).at(0).value<RequestId>(), id);
    const auto envelope = ready.at(0).at(1).value<pb::ui::EnvelopePtr>();
    QVERIFY(envelope);
    QCOMPARE(static_cast<int>(envelope->probes.size()), envelope->result.sims_run);
    // The tower's start-up slips its pallet on the belt; in a curve its top carton slides off.
    QCOMPARE(envelope->accel.mode, pb::FailureMode::pallet_slip);
    QCOMPARE(envelope->lateral.mode, pb::FailureMode::top_item_slide);
    QCOMPARE(counted.last().at(1).toInt(), envelope->result.sims_run);
    QCOMPARE(counted.last().at(2).toInt(), envelope->result.sims_run);
  }

  // The status line's words for a count: exact for a map, "about" for a search; the time left
  // once two simulations have ended and half a second has passed.
  void progressWords() {
    const QString step = QStringLiteral("Mapping speed against acceleration");
    QCOMPARE(pb::ui::progressText(step, 1, 150, true, 0.4),
             QStringLiteral("Mapping speed against acceleration: 1 of 150 simulations"));
    QCOMPARE(pb::ui::progressText(step, 50, 150, true, 5.0),
             QStringLiteral("Mapping speed against acceleration: 50 of 150 simulations, about "
                            "10 s left"));
    QCOMPARE(pb::ui::progressText(QStringLiteral("Searching the safe envelope"), 6, 7, false, 1.2),
             QStringLiteral("Searching the safe envelope: 6 of about 7 simulations, less than a "
                            "second left"));
    QCOMPARE(pb::ui::progressText(QStringLiteral("Searching the safe envelope"), 7, 7, false, 1.2),
             QStringLiteral("Searching the safe envelope: 7 of about 7 simulations"));
  }

  void invalidPalletIsAMessage() {
    pb::PalletConfig pallet = tower().pallet;
    pallet.items[2].weight_kg = -1.0;
    AnalysisService service;
    QSignalSpy failed(&service, &AnalysisService::failed);
    QSignalSpy analyzed(&service, &AnalysisService::analyzed);
    const RequestId id = service.analyze(pallet);
    QVERIFY(failed.wait(10000));
    QCOMPARE(analyzed.count(), 0);
    QCOMPARE(failed.at(0).at(0).value<RequestId>(), id);
    const QString message = failed.at(0).at(1).toString();
    QVERIFY2(
        message.startsWith(QStringLiteral("The pallet cannot be simulated: /items/2/weight_kg: ")),
        qPrintable(message));
    QCOMPARE(service.pendingCount(), 0);
  }

  void invalidProfileIsAMessage() {
    pb::Scenario s = tower();
    s.suggested_profile.duration_s = -1.0;
    AnalysisService service;
    QSignalSpy failed(&service, &AnalysisService::failed);
    service.solve(s.pallet, s.suggested_profile);
    QVERIFY(failed.wait(10000));
    const QString message = failed.at(0).at(1).toString();
    QVERIFY2(message.startsWith(
                 QStringLiteral("The profile cannot be simulated: /profile/duration_s: ")),
             qPrintable(message));
  }

  void cancelDropsResults() {
    const pb::Scenario s = tower();
    AnalysisService service;
    QSignalSpy analyzed(&service, &AnalysisService::analyzed);
    QSignalSpy solved(&service, &AnalysisService::solved);
    QSignalSpy cancelled(&service, &AnalysisService::cancelled);

    const RequestId running = service.analyze(s.pallet);                    // starts at once
    const RequestId queued = service.solve(s.pallet, s.suggested_profile);  // waits behind it
    service.cancel(running);
    service.cancel(queued);
    service.cancel(queued);  // twice: ignored
    QCOMPARE(cancelled.count(), 2);
    QCOMPARE(cancelled.at(0).at(0).value<RequestId>(), running);
    QCOMPARE(cancelled.at(1).at(0).value<RequestId>(), queued);
    QCOMPARE(service.pendingCount(), 0);

    // Requests run in order, so once a later one is answered the cancelled ones are done with.
    const RequestId last = service.solve(s.pallet, s.suggested_profile);
    QVERIFY(solved.wait(25000));
    QCOMPARE(solved.count(), 1);
    QCOMPARE(solved.at(0).at(0).value<RequestId>(), last);
    QCoreApplication::processEvents();
    QCOMPARE(analyzed.count(), 0);
    QCOMPARE(solved.count(), 1);
  }

  // Cancel stops the core call that is running, inside the probe it is stepping: the unwrapped
  // tower's failure map (240 probes, 5-10 s of both cores on a 2-core machine) gives way to the
  // next request at once, and says nothing more.
  void cancelStopsTheRunningCall() {
    const pb::Scenario tower = TestAnalysisService::tower();
    AnalysisService service;
    QSignalSpy mapped(&service, &AnalysisService::failureMapReady);
    QSignalSpy failed(&service, &AnalysisService::failed);
    QSignalSpy solved(&service, &AnalysisService::solved);
    QSignalSpy progress(&service, &AnalysisService::progress);
    const RequestId map = service.failureMap(tower.pallet);
    QVERIFY(progress.wait(10000));  // the worker has started on it
    QTest::qWait(300);              // and is stepping probes
    service.cancel(map);
    const RequestId next = service.solve(tower.pallet, tower.suggested_profile);
    QVERIFY2(solved.wait(8000), "the cancelled map kept the worker busy");
    QCOMPARE(solved.at(0).at(0).value<RequestId>(), next);
    QCoreApplication::processEvents();
    QCOMPARE(mapped.count(), 0);
    QCOMPARE(failed.count(), 0);
  }
};

QTEST_GUILESS_MAIN(TestAnalysisService)
#include "tst_analysis_service.moc"
