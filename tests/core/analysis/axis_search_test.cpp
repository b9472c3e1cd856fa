// SPDX-License-Identifier: MIT
#include "core/analysis/axis_search.hpp"

#include <QtTest>
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

using namespace pb;

namespace {

// A made-up load: failed(x) decides the verdict, and a safe probe's peak ratio grows linearly
// from 0 at `calm` to 1 at `edge` (how near it came, as SimResult::peak_ratio reports it).
struct MadeUp {
  std::function<bool(double)> failed;
  double calm = 0.0, edge = 1.0;
  std::vector<double> probed;

  AxisSearch::ProbeFn fn() {
    return [this](double x) -> std::optional<ProbeVerdict> {
      probed.push_back(x);
      if (failed(x)) return ProbeVerdict{true, FailureMode::top_item_slide, 1.0};
      const double ratio = std::clamp((x - calm) / (edge - calm), 0.0, 0.999);
      return ProbeVerdict{false, FailureMode::no_failure, ratio};
    };
  }
};

constexpr double kLo = 0.05, kHi = 0.5, kStep = 0.01;

std::string describe(const std::vector<double>& probed) {
  std::string out;
  for (double x : probed) out += std::to_string(x) + " ";
  return out;
}

}  // namespace

class AxisSearchTest : public QObject {
  Q_OBJECT

 private slots:
  // Monotone failure at 0.3: the limit lies within one step below it, seeded below or above,
  // vouched or not, and by plain bisection over the range.
  void monotoneFailureIsBracketedWithinAStep() {
    for (double seed : {0.12, 0.29, 0.31, 0.45}) {
      for (bool vouch : {false, true}) {
        MadeUp load{[](double x) { return x >= 0.3; }, 0.2, 0.3, {}};
        auto limit = AxisSearch(kLo, kHi, kStep, load.fn(), true, vouch).run(seed);
        QVERIFY(limit.has_value());
        QVERIFY2(limit->limit < 0.3 && limit->limit >= 0.3 - kStep - 1e-12,
                 std::to_string(limit->limit).c_str());
        QCOMPARE(limit->mode, FailureMode::top_item_slide);
        QCOMPARE(limit->probes, int(load.probed.size()));
      }
    }
    MadeUp plain{[](double x) { return x >= 0.3; }, 0.0, 1.0, {}};
    auto limit = AxisSearch(kLo, kHi, kStep, plain.fn(), false).run(0.0);
    QVERIFY(limit && limit->limit < 0.3 && limit->limit >= 0.3 - kStep);
  }

  // A seed that came near failing vouches for nothing below it: where the load also fails a step
  // below its safe seed (failure not monotone there, as on u2048's curve), the vouched search
  // finds that failure and walks down from it; the unvouched one answers the seed, unsafe.
  void aSafeSeedNearFailingIsCheckedBelow() {
    auto island = [](double x) { return x >= 0.28 && !(x > 0.295 && x < 0.301); };
    MadeUp trusting{island, 0.2, 0.3, {}};
    auto unsafe = AxisSearch(kLo, kHi, kStep, trusting.fn(), true, false).run(0.298);
    QVERIFY(unsafe && std::abs(unsafe->limit - 0.298) < 1e-12);

    MadeUp checking{island, 0.2, 0.3, {}};
    auto limit = AxisSearch(kLo, kHi, kStep, checking.fn(), true, true).run(0.298);
    QVERIFY(limit.has_value());
    QVERIFY2(limit->limit < 0.28 && limit->limit >= 0.28 - kStep - 1e-12,
             std::to_string(limit->limit).c_str());
    QVERIFY(!limit->at_floor && !limit->at_ceiling);
    QCOMPARE(checking.probed[0], 0.298);
    QCOMPARE(checking.probed[1], 0.298 - kStep);  // the check below the seed
  }

  // A safe seed within 1 % of failing (kAtFailure) tries half a step above first: where that
  // fails the bracket is closed in two probes; where it holds the walk goes on from it, to the
  // limit a seed far from failing finds on the same grid.
  void aSeedAtThePointOfFailingTriesHalfAStepAbove() {
    MadeUp closing{[](double x) { return x >= 0.3; }, 0.2, 0.3, {}};
    auto closed = AxisSearch(kLo, kHi, kStep, closing.fn()).run(0.2995);
    QVERIFY(closed && std::abs(closed->limit - 0.2995) < 1e-12);
    QCOMPARE(closing.probed, (std::vector<double>{0.2995, 0.2995 + 0.5 * kStep}));

    MadeUp holding{[](double x) { return x >= 0.308; }, 0.2, 0.3, {}};
    auto held = AxisSearch(kLo, kHi, kStep, holding.fn()).run(0.2995);
    MadeUp calm{[](double x) { return x >= 0.308; }, 0.0, 10.0, {}};
    auto far = AxisSearch(kLo, kHi, kStep, calm.fn()).run(0.2995);
    QVERIFY(held && far);
    QCOMPARE(holding.probed[1], 0.2995 + 0.5 * kStep);
    QVERIFY(calm.probed[1] > 0.2995 + 0.9 * kStep);  // far from failing: a whole step or more
    QCOMPARE(held->limit, far->limit);
    QVERIFY2(held->limit < 0.308 && held->limit >= 0.308 - 0.5 * kStep - 1e-9,
             std::to_string(held->limit).c_str());

    MadeUp near{[](double x) { return x >= 0.3; }, 0.0, 0.3 / 0.95, {}};  // 0.95 at 0.2995
    (void)AxisSearch(kLo, kHi, kStep, near.fn()).run(0.2995);
    QCOMPARE(near.probed[1], 0.2995 + kStep);  // near failing (kNearFailure), not at it
  }

  // The check goes down only while the safe probes stay near failing: one safe by a margin
  // (peak ratio below 0.5) ends it, and a seed that stayed far from failing is not checked.
  void theCheckStopsAtAProbeSafeByAMargin() {
    MadeUp load{[](double x) { return x >= 0.3; }, 0.27, 0.3, {}};  // ratio 0.5 at 0.285
    auto limit = AxisSearch(kLo, kHi, kStep, load.fn(), true, true).run(0.298);
    QVERIFY(limit.has_value());
    // 0.298 (ratio 0.93), 0.288 (0.6), 0.278 (0.27: a margin), then up from the seed.
    QVERIFY(load.probed.size() >= 4);
    QCOMPARE(load.probed[1], 0.298 - kStep);
    QCOMPARE(load.probed[2], 0.298 - 2 * kStep);
    for (std::size_t i = 3; i < load.probed.size(); ++i) QVERIFY(load.probed[i] > 0.298);
    QVERIFY(std::abs(limit->limit - 0.298) < 1e-12);

    MadeUp calm{[](double x) { return x >= 0.3; }, 0.29, 0.5, {}};
    auto far = AxisSearch(kLo, kHi, kStep, calm.fn(), true, true).run(0.2);
    QVERIFY(far.has_value());
    for (double x : calm.probed) QVERIFY2(x >= 0.2, std::to_string(x).c_str());
  }

  // With band checks, the answer of a load whose items can move is probed once more a step below:
  // where the load fails there (a band where it fails and holds by turns, as top-heavy-surprise's
  // stop did in session 14's physics), the search walks down from that failure; where it holds,
  // that is one probe more. Without them (the default since session 32) and unvouched, the search
  // answers inside the band.
  void theAnswerIsCheckedAStepBelow() {
    auto monotone = [](double x) { return x >= 0.3; };
    // A seed whose search never probed a step below its answer (else the check costs nothing and
    // finds nothing new), and a band there that none of its probes touched.
    double seed = 0.0, L = 0.0, lo = 0.0, hi = 0.0;
    int probes = 0;
    for (double s : {0.2, 0.22, 0.24, 0.26, 0.27, 0.28}) {
      MadeUp plain{monotone, 0.0, 1.0, {}};
      auto answer = AxisSearch(kLo, kHi, kStep, plain.fn(), true, false).run(s);
      QVERIFY(answer.has_value());
      const double a = answer->limit - 1.5 * kStep, b = answer->limit - 0.5 * kStep;
      if (std::none_of(plain.probed.begin(), plain.probed.end(),
                       [&](double x) { return x >= a && x < b; })) {
        seed = s, L = answer->limit, lo = a, hi = b, probes = answer->probes;
        break;
      }
    }
    QVERIFY(seed > 0.0);
    auto band = [&](double x) { return monotone(x) || (x >= lo && x < hi); };

    MadeUp trusting{band, 0.0, 1.0, {}};
    auto unsafe = AxisSearch(kLo, kHi, kStep, trusting.fn(), true, false).run(seed);
    QVERIFY(unsafe && unsafe->limit == L);

    MadeUp unchecked{band, 0.0, 1.0, {}};
    auto inside = AxisSearch(kLo, kHi, kStep, unchecked.fn(), true, true).run(seed);
    QVERIFY(inside && inside->limit == L);
    QCOMPARE(unchecked.probed, trusting.probed);

    constexpr int kChecks = 3;
    MadeUp checking{band, 0.0, 1.0, {}};
    auto limit = AxisSearch(kLo, kHi, kStep, checking.fn(), true, true, {}, 1, kChecks).run(seed);
    QVERIFY(limit.has_value());
    QVERIFY2(limit->limit < lo && limit->limit >= lo - kStep - 1e-12,
             std::to_string(limit->limit).c_str());
    QCOMPARE(limit->probes, int(checking.probed.size()));

    // Where the load holds a step below, the check is one probe more and changes nothing.
    MadeUp held{monotone, 0.0, 1.0, {}};
    auto same = AxisSearch(kLo, kHi, kStep, held.fn(), true, true, {}, 1, kChecks).run(seed);
    QVERIFY(same.has_value());
    QCOMPARE(same->limit, L);
    QCOMPARE(same->probes, probes + 1);
    QCOMPARE(held.probed.back(), L - kStep);
  }

  // A seed at the bottom of the range has nothing below it to check.
  // A failure early in its demand says the limit is far below: the walk down doubles its steps
  // from it and steps singly after the next late failure. A made-up slide that fails at the
  // demand's end at 0.2 and earlier the higher the demand (failed_at = (0.2 / x)^4): from 0.35 the
  // hastened walk finds the same limit in fewer probes than the fixed one, every probe on the
  // fixed walk's grid (the seed minus whole steps). A load whose failures all come late walks as
  // before, probe for probe.
  void anEarlyFailureHastensTheWalkDown() {
    auto search = [](double failed_at_top, bool hasten, std::vector<double>& probed) {
      auto fn = [&, failed_at_top, hasten](double x) -> std::optional<ProbeVerdict> {
        probed.push_back(x);
        if (x < 0.2) return ProbeVerdict{false, FailureMode::no_failure, 0.1};
        const double at = failed_at_top >= 1.0 ? 1.0 : std::pow(0.2 / x, 4.0);
        return ProbeVerdict{true, FailureMode::load_shift, 1.0, hasten ? at : 1.0};
      };
      return AxisSearch(kLo, kHi, kStep, fn, true, true).run(0.35);
    };
    std::vector<double> fixed, hastened, late_fixed, late_hastened;
    const auto a = search(0.0, false, fixed);
    const auto b = search(0.0, true, hastened);
    QVERIFY(a && b);
    QCOMPARE(b->limit, a->limit);
    QVERIFY(a->limit < 0.2 && a->limit >= 0.2 - kStep - 1e-12);
    qInfo("fixed walk %zu probes, hastened %zu", fixed.size(), hastened.size());
    QVERIFY2(hastened.size() + 2 <= fixed.size(),
             qPrintable(QString("%1 probes against %2").arg(hastened.size()).arg(fixed.size())));
    for (double x : hastened) {
      const double steps = (0.35 - x) / (0.5 * kStep);  // bisection halves a single step
      QVERIFY2(std::abs(steps - std::round(steps)) < 1e-6, std::to_string(x).c_str());
    }
    const auto c = search(1.0, false, late_fixed);
    const auto d = search(1.0, true, late_hastened);
    QVERIFY(c && d);
    QCOMPARE(late_hastened, late_fixed);
  }

  // A walk down whose next step would pass the floor takes the longest step that stays above
  // it first: from a failure at 0.11 (steps of 0.04 by then) it probes 0.07, not the floor, and
  // a load that holds there is bisected on a bracket of a power of two of the precision. A load
  // that fails there too is probed at the floor next and answered there.
  void aWalkDownStopsShortOfTheFloorOnce() {
    auto at = [](const std::vector<double>& probed, double x) {
      return std::any_of(probed.begin(), probed.end(),
                         [x](double p) { return std::abs(p - x) < 1e-9; });
    };
    MadeUp holds{[](double x) { return x >= 0.075; }, 0.0, 10.0, {}};
    auto limit = AxisSearch(kLo, kHi, kStep, holds.fn()).run(0.2);
    QVERIFY(limit.has_value());
    QVERIFY2(limit->limit >= 0.07 - 1e-9 && limit->limit < 0.075, describe(holds.probed).c_str());
    QVERIFY2(at(holds.probed, 0.11) && at(holds.probed, 0.07) && !at(holds.probed, kLo),
             describe(holds.probed).c_str());
    QCOMPARE(int(holds.probed.size()), 10);  // with the floor first: 11

    MadeUp never{[](double) { return true; }, 0.0, 10.0, {}};
    auto floor = AxisSearch(kLo, kHi, kStep, never.fn()).run(0.2);
    QVERIFY(floor && floor->at_floor);
    QCOMPARE(never.probed.back(), kLo);
    QVERIFY2(std::abs(never.probed[never.probed.size() - 2] - 0.07) < 1e-9,
             describe(never.probed).c_str());
  }

  void aSeedAtTheFloorIsNotCheckedBelow() {
    MadeUp load{[](double x) { return x >= 0.06; }, 0.0, 0.06, {}};
    auto limit = AxisSearch(kLo, kHi, kStep, load.fn(), true, true).run(kLo);
    QVERIFY(limit.has_value());
    QCOMPARE(load.probed.front(), kLo);
    for (double x : load.probed) QVERIFY(x >= kLo);
    QVERIFY(limit->limit >= kLo && limit->limit < 0.06);
  }

  // An unstable probe ends the search without a verdict, in the check below the seed too.
  void anUnstableCheckGivesNoLimit() {
    int calls = 0;
    auto probe = [&](double) -> std::optional<ProbeVerdict> {
      if (++calls == 1) return ProbeVerdict{false, FailureMode::no_failure, 0.9};
      return std::nullopt;
    };
    QVERIFY(!AxisSearch(kLo, kHi, kStep, probe, true, true).run(0.3).has_value());
    QCOMPARE(calls, 2);
  }
};

QTEST_APPLESS_MAIN(AxisSearchTest)
#include "axis_search_test.moc"
