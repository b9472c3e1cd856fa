// SPDX-License-Identifier: MIT
// The analyzer's determinism and caching: the same pallet gives a bit-identical SafetyResult and
// replay from fresh analyzers, a second analysis is a cache hit, and the cache key is the physics
// (not the pallet's name) and nothing less.
#include "core/analysis/analyzer.hpp"

#include <QtTest>
#include <algorithm>
#include <map>
#include <mutex>

#include "core/contract/fingerprint.hpp"
#include "core/contract/json_io.hpp"
#include "core/inputs/scenario.hpp"
#include "tests/core/test_friction.hpp"

using namespace pb;

namespace {

std::string describe(const Diagnostics& diagnostics) {
  std::string out;
  for (const auto& d : diagnostics) out += (out.empty() ? "" : "; ") + to_string(d);
  return out;
}

// Constant friction: pallet on belt 1.0, carton on pallet 0.6, carton on carton 0.3.
const FrictionModel& friction() {
  static const FrictionModel model = test::constant_friction({1.0, 0.6, 0.3});
  return model;
}

// Two 10 kg cartons stacked, unwrapped, on an EUR pallet: the top one slides first (carton on
// carton, from 2.94 m/s^2), so the limits are set by a failure, not the top of a search range.
PalletConfig column() {
  PalletConfig config;
  config.pallet_id = "column";
  for (double z : {0.15, 0.35}) {
    Item item;
    item.sku = "TEST";
    item.weight_kg = 10.0;
    item.dims_m = {0.4, 0.3, 0.2};
    item.position = {0.0, 0.0, z};
    config.items.push_back(item);
  }
  config.wrap = WrapType::none;
  return config;
}

// Everything but the wall time, which is the only field allowed to differ between runs.
SafetyResult without_runtime(SafetyResult r) {
  r.sim_runtime_ms = 0.0;
  return r;
}

// A start-up ramp to `speed` at `accel`, `duration_s` long.
ConveyorProfile start_up(double speed, double accel, double duration_s) {
  ConveyorProfile p;
  p.shape = ProfileShape::accel_hold;
  p.accel_mps2 = accel;
  p.target_speed_mps = speed;
  p.duration_s = duration_s;
  return p;
}

// A start-up hard enough to make the top carton slide (a failure event in the replay).
ConveyorProfile hard_start() {
  return start_up(1.5, 5.0, 1.0);
}

bool same_trace(const Trace& a, const Trace& b) {
  if (a.size() != b.size() || a.n_items() != b.n_items()) return false;
  for (std::size_t f = 0; f < a.size(); ++f) {
    const auto ia = a.items(f), ib = b.items(f);
    if (a.time(f) != b.time(f) || a.pallet(f) != b.pallet(f) ||
        !std::equal(ia.begin(), ia.end(), ib.begin(), ib.end())) {
      return false;
    }
    const auto &ba = a.belt(f), &bb = b.belt(f);
    if (ba.x != bb.x || ba.y != bb.y || ba.vx != bb.vx || ba.vy != bb.vy) return false;
  }
  return true;
}

}  // namespace

class AnalyzerTest : public QObject {
  Q_OBJECT

 private slots:
  // Two fresh analyzers, same pallet: every field of the result is bit-identical.
  void sameInputGivesTheSameResult() {
    Analyzer first({}, friction()), second({}, friction());
    const auto a = first.analyze(column());
    QVERIFY2(a, describe(a.diagnostics).c_str());
    const auto b = second.analyze(column());
    QVERIFY2(b, describe(b.diagnostics).c_str());
    QVERIFY(a->sims_run > 0);
    QCOMPARE(a->pallet_id, std::string("column"));
    QCOMPARE(a->config_hash, config_fingerprint(column()));
    QVERIFY(a->max_accel_mps2 > 0.0);
    QCOMPARE(a->accel_mode, FailureMode::top_item_slide);
    QCOMPARE(safety_result_to_json(without_runtime(*b)).dump(),
             safety_result_to_json(without_runtime(*a)).dump());
    QVERIFY(without_runtime(*a) == without_runtime(*b));
    qInfo("%d sims: accel %.2f (%s), decel %.2f, lateral %.2f g, speed %.2f (%s), %.0f ms",
          a->sims_run, a->max_accel_mps2, std::string(to_string(a->accel_mode)).c_str(),
          a->max_decel_mps2, a->max_lateral_g, a->max_speed_mps,
          std::string(to_string(a->speed_governed_by)).c_str(), a->sim_runtime_ms);
  }

  // Solving the same profile twice, in a fresh analyzer and again on its reused simulator, gives
  // the same trace bit for bit and the same replay document.
  void replayIsBitIdentical() {
    Analyzer first({}, friction()), second({}, friction());
    const auto a = first.solve(column(), hard_start());
    QVERIFY2(a, describe(a.diagnostics).c_str());
    const auto b = second.solve(column(), hard_start());
    QVERIFY2(b, describe(b.diagnostics).c_str());
    const auto again = first.solve(column(), hard_start());
    QVERIFY2(again, describe(again.diagnostics).c_str());
    QCOMPARE(a->sim.outcome, Outcome::failed);
    QCOMPARE(a->sim.failure->mode, FailureMode::top_item_slide);
    QVERIFY(a->replay.frames.size() > 2);
    for (const auto* other : {&*b, &*again}) {
      QVERIFY(other->sim.failure == a->sim.failure);
      QCOMPARE(other->sim.steps, a->sim.steps);
      QVERIFY(same_trace(other->sim.trace, a->sim.trace));
      QCOMPARE(replay_to_json(other->replay).dump(), replay_to_json(a->replay).dump());
    }
  }

  // A second analysis of the same pallet runs no simulation; a renamed pallet with the same
  // physics hits the cache too (and carries its own name); a heavier carton does not.
  void secondAnalysisIsACacheHit() {
    Analyzer analyzer({}, friction());
    const auto first = analyzer.analyze(column());
    QVERIFY2(first, describe(first.diagnostics).c_str());
    QVERIFY(first->sims_run > 0);
    const int hits = analyzer.cache_hits();

    const auto again = analyzer.analyze(column());
    QVERIFY2(again, describe(again.diagnostics).c_str());
    QCOMPARE(again->sims_run, 0);
    QCOMPARE(analyzer.cache_hits(), hits + 1);
    SafetyResult expected = without_runtime(*first);
    expected.sims_run = 0;
    QVERIFY(without_runtime(*again) == expected);

    PalletConfig renamed = column();
    renamed.pallet_id = "renamed";
    renamed.notes = "same physics";
    const auto named = analyzer.analyze(renamed);
    QVERIFY2(named, describe(named.diagnostics).c_str());
    QCOMPARE(named->sims_run, 0);
    QCOMPARE(analyzer.cache_hits(), hits + 2);
    QCOMPARE(named->pallet_id, std::string("renamed"));
    expected.pallet_id = "renamed";
    QVERIFY(without_runtime(*named) == expected);

    PalletConfig heavier = column();
    heavier.items[1].weight_kg = 11.0;
    const auto other = analyzer.analyze(heavier);
    QVERIFY2(other, describe(other.diagnostics).c_str());
    QVERIFY(other->sims_run > 0);
    QCOMPARE(analyzer.cache_hits(), hits + 2);
    QVERIFY(other->config_hash != first->config_hash);
  }

  // A failed solve follows the wreck on the aftermath model (whatever touches collides) and keeps
  // the verdict a search sees: the same first failure, and up to it the very same motion, frame
  // for frame, as the search's model (nothing differs until something touches that no pair
  // covers); after it the run goes on until the cartons move with the belt again.
  void solveFollowsTheWreck() {
    Analyzer analyzer({}, friction());
    auto prepared = analyzer.prepare(column());
    QVERIFY2(prepared, describe(prepared.diagnostics).c_str());
    PreparedPallet& p = **prepared.value;
    SimOptions o = analyzer.options().sim;
    o.record_trace = true;
    const SimResult verdict = p.simulator->run(p.rest, hard_start(), o);  // as a search sees it
    QCOMPARE(verdict.outcome, Outcome::failed);
    const auto solved = analyzer.solve(column(), hard_start());
    QVERIFY2(solved, describe(solved.diagnostics).c_str());
    const SimResult& wreck = solved->sim;
    QVERIFY2(wreck.aftermath_cut.empty(), wreck.aftermath_cut.c_str());
    QVERIFY(wreck.failure == verdict.failure);
    QVERIFY(wreck.sim_time_s >= verdict.sim_time_s + 0.25);
    QVERIFY(wreck.sim_time_s <= verdict.failure->time_s + kSolveAftermathS + 1e-9);
    QVERIFY(wreck.trace.size() > verdict.trace.size());
    for (std::size_t f = 0; f < verdict.trace.size(); ++f) {
      const auto a = verdict.trace.items(f), b = wreck.trace.items(f);
      QVERIFY(verdict.trace.time(f) == wreck.trace.time(f));
      QVERIFY(verdict.trace.pallet(f) == wreck.trace.pallet(f));
      QVERIFY(std::equal(a.begin(), a.end(), b.begin(), b.end()));
    }
    QVERIFY(p.aftermath_scene != nullptr);
    QVERIFY(p.aftermath_scene->mjcf.find("contype=\"1\"") != std::string::npos);
    QVERIFY(p.scene->mjcf.find("contype=\"1\"") == std::string::npos);  // searches: pairs only
  }

  // A safe run's replay shows the slide to its end. A search's probe of frozen-meat-sprint at 1.4
  // m/s and 3.2 m/s^2 stops on energy while the pallet still slips (what is left cannot carry it
  // to the 0.3 m threshold: SimOptions::energy_stop); solve runs on until the load rides with the
  // belt, with the same verdict (the CI screenshot's replay ended at 0.55 s, 19.5 cm in, rising).
  void aSafeSolveShowsTheSlideToItsEnd() {
    const auto meat = load_scenario("frozen-meat-sprint");
    QVERIFY(meat);
    const ConveyorProfile profile = start_up(1.4, 3.2, 3.0);
    Analyzer analyzer;
    auto prepared = analyzer.prepare(meat->pallet);
    QVERIFY2(prepared, describe(prepared.diagnostics).c_str());
    PreparedPallet& p = **prepared.value;
    SimOptions o = analyzer.options().sim;
    o.record_trace = true;
    const SimResult probe = p.simulator->run(p.rest, profile, o);
    const auto solved = analyzer.solve(meat->pallet, profile);
    QVERIFY2(solved, describe(solved.diagnostics).c_str());
    const SimResult& shown = solved->sim;
    QCOMPARE(probe.outcome, Outcome::safe);
    QCOMPARE(shown.outcome, Outcome::safe);
    // The pallet's slip behind the belt over the last 20 ms of each run.
    auto creeping = [](const SimResult& r) {
      const Trace& t = r.trace;
      const std::size_t last = t.size() - 1, before = last - 20;
      const double now = t.belt(last).x - t.pallet(last).pos[0];
      const double then = t.belt(before).x - t.pallet(before).pos[0];
      return std::abs(now - then);
    };
    qInfo(
        "probe ends at %.3f s (slip changing %.1f mm in its last 20 frames), solve at %.3f s "
        "(%.3f mm)",
        probe.sim_time_s, 1e3 * creeping(probe), shown.sim_time_s, 1e3 * creeping(shown));
    QVERIFY(probe.stopped_early && shown.stopped_early);
    QVERIFY(shown.sim_time_s > probe.sim_time_s);
    QVERIFY(creeping(probe) > 1e-3);
    QVERIFY(creeping(shown) < 1e-4);
  }

  // Progress: an envelope reports each probe as it ends, and each limit as it is found, from its
  // axis threads; it ends with done == planned == its simulations. A failure map plans its cells
  // exactly from the first report.
  void progressCountsTheSimulations() {
    Analyzer analyzer({}, friction());
    std::mutex m;
    std::vector<std::pair<int, int>> seen;
    std::map<Axis, AxisLimit> found;
    analyzer.set_axis_found([&](Axis axis, const AxisLimit& limit) {
      std::lock_guard lock(m);
      QVERIFY(found.emplace(axis, limit).second);  // each axis once
    });
    analyzer.set_progress([&](int done, int planned) {
      std::lock_guard lock(m);
      seen.emplace_back(done, planned);
    });
    const auto env = analyzer.envelope(column());
    QVERIFY(env);
    QVERIFY(!seen.empty());
    QCOMPARE(seen.front().first, 0);  // the plan comes first
    QVERIFY(seen.front().second >= 4);
    for (const auto& [done, planned] : seen) QVERIFY(done <= planned);
    QCOMPARE(seen.back(), std::make_pair(env->result.sims_run, env->result.sims_run));
    // Each of the start-up, stop and curve limits was told before the envelope ended, as found.
    QCOMPARE(found.size(), std::size_t(3));
    QCOMPARE(found.at(Axis::accel).limit, env->accel.limit);
    QCOMPARE(found.at(Axis::decel).limit, env->decel.limit);
    QCOMPARE(found.at(Axis::lateral).limit, env->lateral.limit);
    QCOMPARE(found.at(Axis::lateral).mode, env->lateral.mode);
    seen.clear();
    const auto map =
        analyzer.failure_map(column(), {.speeds_mps = {0.5, 1.0}, .accels_mps2 = {1.0, 2.0, 3.0}});
    QVERIFY(map);
    const int cells = 2 * 3 + 2 * 2;  // every start-up cell, a curve and an e-stop per speed
    QCOMPARE(seen.front(), std::make_pair(0, cells));
    QCOMPARE(seen.back(), std::make_pair(cells, cells));
    for (const auto& [done, planned] : seen) QCOMPARE(planned, cells);
  }

  // A cancelled call ends without a verdict and caches nothing: the settle at its next check, a
  // search or a map inside the probe it is stepping, a solve as an unstable run that says so.
  // Cleared, the same analyzer then gives the answer a fresh one gives.
  void aCancelledCallCachesNothing() {
    CancelFlag cancel{true};
    Analyzer analyzer({}, friction());
    analyzer.set_cancel(&cancel);
    const auto settled = analyzer.analyze(column());
    QVERIFY(!settled);
    QVERIFY2(describe(settled.diagnostics).find("cancelled") != std::string::npos,
             describe(settled.diagnostics).c_str());
    QCOMPARE(analyzer.cached_pallets(), std::size_t(0));

    cancel = false;
    QVERIFY(analyzer.prepare(column()));
    cancel = true;
    const auto searched = analyzer.analyze(column());
    QVERIFY(!searched);
    QVERIFY(describe(searched.diagnostics).find("cancelled") != std::string::npos);
    const auto mapped = analyzer.failure_map(column(), {.speeds_mps = {1.0}, .accels_mps2 = {1.0}});
    // No map of cells that were stopped part-way (they read as unstable cells before).
    QVERIFY(!mapped);
    QVERIFY(describe(mapped.diagnostics).find("cancelled") != std::string::npos);
    const auto solved = analyzer.solve(column(), hard_start());
    QVERIFY(solved);
    QCOMPARE(solved->sim.outcome, Outcome::unstable);
    QVERIFY(solved->sim.reason.starts_with(kCancelledReason));

    cancel = false;
    const auto answered = analyzer.analyze(column());
    QVERIFY2(answered, describe(answered.diagnostics).c_str());
    QVERIFY(answered->sims_run > 0);  // searched now: no result of the cancelled search was kept
    Analyzer fresh({}, friction());
    QVERIFY(without_runtime(*answered) == without_runtime(*fresh.analyze(column())));
  }

  // A load that cannot stand is a build defect, not a conveyor limit: refused by validation; and
  // where the standing rule is off (to reach the simulation), found at rest on a still belt,
  // reported as a reject of its own mode with no limit, and never probed, mapped or solved.
  void aLoadThatCannotStandIsABuildDefect() {
    PalletConfig config = column();
    config.items[1].position[0] = 0.3;  // its centre of mass 10 cm beyond the lower carton's end
    Analyzer strict(AnalyzerOptions{}, friction());
    const auto refused = strict.analyze(config);
    QVERIFY(!refused);
    const Diagnostic why = errors_of(refused.diagnostics).front();
    QCOMPARE(why.pointer, std::string("/items/1/position"));
    QVERIFY(why.message.find("cannot stand") != std::string::npos);

    AnalyzerOptions options;
    options.scene.require_standing = false;
    Analyzer analyzer(options, friction());
    const auto r = analyzer.analyze(config);
    QVERIFY2(r, describe(r.diagnostics).c_str());
    QCOMPARE(r->verdict, Verdict::reject);
    QCOMPARE(r->dominant_failure_mode, FailureMode::cannot_stand);
    QCOMPARE(r->accel_mode, FailureMode::cannot_stand);
    QCOMPARE(r->speed_governed_by, SpeedGovernor::build_defect);
    QCOMPARE(r->sims_run, 1);
    QVERIFY2(r->reason.find("Item 1 (TEST) cannot stand: with the belt standing still") == 0 ||
                 r->reason.find("Reject, build defect: Item 1 (TEST) cannot stand") == 0,
             r->reason.c_str());
    // No number that reads like a limit in the JSON, and it reads back.
    const Json json = safety_result_to_json(*r);
    QVERIFY(json["max_speed_mps"].is_null());
    QVERIFY(json["max_accel_mps2"].is_null());
    QCOMPARE(json["dominant_failure_mode"], Json("cannot_stand"));
    const auto back = safety_result_from_json(json);
    QVERIFY2(back, describe(back.diagnostics).c_str());
    QVERIFY(without_runtime(*back) == without_runtime(*r));

    // Nothing runs from a collapsed rest: a solve and a map say why, at the item.
    const auto solve = analyzer.solve(config, hard_start());
    QVERIFY(!solve);
    const Diagnostic defect = errors_of(solve.diagnostics).front();
    QCOMPARE(defect.pointer, std::string("/items/1"));
    QVERIFY(defect.message.find("cannot stand") != std::string::npos);
    QVERIFY(!analyzer.failure_map(config));
  }

  // A pallet the validation refuses is refused before anything else looks at it: 20,000 cartons
  // in one column (every pair in one footprint, so finding what rests on what is quadratic) took
  // 80 s in the model level's choice before the scene refused their count, in each of analyze,
  // solve and map. Here each call gets the one error naming the limit (and under QtTest's
  // per-function timeout).
  void anInvalidPalletIsRefusedBeforeItsModelIsChosen() {
    PalletConfig config = column();
    const Item carton = config.items[0];
    config.items.clear();
    for (int i = 0; i < 20000; ++i) {
      config.items.push_back(carton);
      config.items.back().position[2] = config.base_dims_m[2] + i * carton.dims_m[2];
    }
    Analyzer analyzer(AnalyzerOptions{}, friction());
    auto only_the_count = [](const Diagnostics& d) {
      const Diagnostics errors = errors_of(d);
      return errors.size() == 1 && errors[0].pointer == "/items" &&
             errors[0].message.find("400") != std::string::npos;
    };
    const auto analysed = analyzer.analyze(config);
    QVERIFY(!analysed);
    QVERIFY2(only_the_count(analysed.diagnostics), describe(analysed.diagnostics).c_str());
    const auto solved = analyzer.solve(config, hard_start());
    QVERIFY(!solved);
    QVERIFY2(only_the_count(solved.diagnostics), describe(solved.diagnostics).c_str());
    const auto map = analyzer.failure_map(config);
    QVERIFY(!map);
    QVERIFY2(only_the_count(map.diagnostics), describe(map.diagnostics).c_str());
  }

  // SearchConfig::confirm_limits: every limit a search reports (not derived, not at the floor)
  // was run along the second numerical path too and held there; a value that failed along it is
  // above the limit; confirmation only lowers limits; and without it only a limit that came near
  // failing is confirmed.
  // Which limits hang on round-off moves with any change to the physics, so the three small
  // unwrapped scenarios are searched and at least one confirmation must fail among them. They are
  // searched in MuJoCo's pyramidal cone, whose loads chatter near their onsets (core/README.md
  // "The friction cone"): there top-heavy-surprise's start-up at 3.16 m/s^2 and asymmetric-load's
  // curve at 0.291 g did not hold along the second path when this was written (before curves
  // turned the load, the tall tower's curve at 0.250 g); in the shipped elliptic cone every one
  // of their limits holds.
  void confirmedLimitsHoldAlongASecondPath() {
    AnalyzerOptions plain_options, confirmed_options;
    plain_options.scene = confirmed_options.scene = with_mujoco_solver({});
    confirmed_options.search.confirm_limits = true;
    Analyzer plain(plain_options, FrictionModel::builtin());
    Analyzer confirmed(confirmed_options, FrictionModel::builtin());
    int failed_confirmations = 0;
    for (const char* slug : {"tall-unwrapped-tower", "top-heavy-surprise", "asymmetric-load"}) {
      const auto scenario = load_scenario(slug);
      QVERIFY2(scenario, slug);
      const auto a = plain.envelope(scenario->pallet);
      const auto b = confirmed.envelope(scenario->pallet);
      QVERIFY2(a && b, describe(a ? b.diagnostics : a.diagnostics).c_str());
      // Without it, only a limit whose own probe came near failing is confirmed
      // (SearchConfig::confirm_from_peak).
      for (const Probe& p : a->probes) {
        if (!p.confirmation) continue;
        const bool near = std::any_of(a->probes.begin(), a->probes.end(), [&](const Probe& q) {
          return !q.confirmation && q.axis == p.axis && q.value == p.value &&
                 q.peak_ratio >= plain_options.search.confirm_from_peak;
        });
        QVERIFY2(near, to_string(p.axis).data());
      }
      const std::pair<Axis, const AxisLimit*> axes[] = {
          {Axis::accel, &b->accel}, {Axis::decel, &b->decel}, {Axis::lateral, &b->lateral}};
      for (const auto& [axis, limit] : axes) {
        if (limit->derived || limit->at_floor) continue;
        bool held = false;
        for (const Probe& p : b->probes) {
          if (p.axis != axis || !p.confirmation) continue;
          if (p.outcome == Outcome::failed) {
            ++failed_confirmations;
            QVERIFY2(p.value > limit->limit, to_string(axis).data());
          } else if (p.value == limit->limit) {
            held = true;
          }
        }
        QVERIFY2(held, to_string(axis).data());
      }
      QVERIFY2(b->accel.limit <= a->accel.limit, slug);
      QVERIFY2(b->decel.limit <= a->decel.limit, slug);
      QVERIFY2(b->lateral.limit <= a->lateral.limit, slug);
    }
    QVERIFY(failed_confirmations > 0);
  }

  // A load that stands settles, is held still, and is probed as before: not a defect.
  void aStandingLoadIsNotADefect() {
    Analyzer analyzer(AnalyzerOptions{}, friction());
    auto prepared = analyzer.prepare(column());
    QVERIFY2(prepared, describe(prepared.diagnostics).c_str());
    QVERIFY(!(*prepared.value)->rest.cannot_stand);
    QVERIFY((*prepared.value)->rest.settle_time_s >= SettleOptions{}.min_time_s);
  }
};

QTEST_APPLESS_MAIN(AnalyzerTest)
#include "analyzer_test.moc"
